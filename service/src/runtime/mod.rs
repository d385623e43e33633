//! The live runtime of `vigil run`: serial ports opened and set up with tokio-serial, read on
//! arrival or paced, each read chunk handed to the sans-IO [`crate::Service`] with its host
//! monotonic time. Everything that needs tokio, the operating system or the wall clock lives
//! here; the rest of the crate takes time as an argument.

pub mod live;
pub mod reader;
pub mod realtime;
pub mod record;
pub mod serial;
pub mod setup;
