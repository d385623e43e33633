//! `vigil bridge` (issue 22): vigil's topics on Zenoh, for other boards of the vehicle and the
//! ground. A separate process, so the safety path never waits on a network: it subscribes to a
//! running vigil's iceoryx2 services and publishes each on Zenoh under `vigil/<vehicle>/<topic>`.
//!
//! It only carries vigil's outputs outward: it declares Zenoh publishers and one queryable,
//! never a Zenoh subscriber, so nothing received from the network reaches vigil's services.
//!
//! The configuration (`vigil_service::config::bridge`) is always compiled (so `vigil config
//! --check` validates `[bridge]` in every build); the runtime needs the cargo feature `bridge`
//! (Zenoh's dependencies stay out of the default build).

#[cfg(feature = "bridge")]
mod run;

#[cfg(feature = "bridge")]
pub use run::{BridgeArgs, listen_remote, run};
