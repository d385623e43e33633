//! Where a service's payloads go besides the iceoryx2 bus (`crate::runtime::live::BusOutputs`):
//! GDL90 and MAVLink over UDP for ground stations and autopilots, and the optional Foxglove live
//! view. Each is an [`crate::Outputs`]; a failure to send is counted, never fatal.

#[cfg(feature = "foxglove")]
pub mod foxglove_view;
pub mod gdl90_out;
pub mod live_view;
pub mod mavlink_out;
pub mod udp_out;
