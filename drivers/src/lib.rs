//! Sans-IO codecs for the serial devices vigil reads.
//!
//! Every device module turns raw bytes into typed messages and, for what a host or the simulator
//! sends, typed messages back into bytes. Nothing here touches a port or a clock: the transport
//! (`tokio_util::codec::FramedRead` over a serial port, a recording, or a test slice) feeds bytes
//! in and takes messages out.
//!
//! The shared framework:
//! - [`DeviceDecoder`]: the one trait every device decoder implements. It never fails: bad input is
//!   skipped and counted in [`DecodeStats`], so a stream of garbage yields no messages and no panic.
//! - [`Codec`]: adapts any [`DeviceDecoder`] to [`tokio_util::codec::Decoder`], yielding each
//!   message with the stream offset of its first byte ([`Located`]) so the transport can stamp it
//!   with the host receive time of that byte.
//! - [`decode_slice`]: decode a byte slice without tokio.
//! - [`protocol`]: the one table of wire protocols (names, default bauds, device families) and
//!   [`protocol::PortDecoder`], which dispatches a port's bytes to its protocol's codec.
//!
#![deny(missing_docs)]

mod codec;
mod stats;
pub mod testkit;
pub mod traffic;

pub mod bahrs;
pub mod modes;
pub mod protocol;
pub mod replay;
pub mod ttmrf;
pub mod vn200;
pub mod watson;

pub use codec::{Codec, DeviceDecoder, Located, decode_slice};
pub use stats::DecodeStats;
