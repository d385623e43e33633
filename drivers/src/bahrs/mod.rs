//! BAHRS baro-inertial AHRS, serial protocol 2.0 (protocol id 0x0003).
//!
//! - [`frame`]: the frame layout, padding and CRC-32/MPEG-2 (sections 2.1-2.3), with the decisions
//!   taken where the document's frame table contradicts itself;
//! - [`health`]: 2-bit signal health (section 2.4);
//! - [`Message`] and its payloads (sections 3 and 5), raw integers with SI accessors;
//! - [`Decoder`]: the sans-IO stream decoder; [`Encoder`]: frames for `FramedWrite`.
//!
//! ```
//! use vigil_drivers::bahrs::{Decoder, Message, SyncPulseTime};
//! use vigil_drivers::decode_slice;
//!
//! let frame = Message::SyncPulseTime(SyncPulseTime { seq: 7, mcu_time_us: 1_000_000 }).to_frame();
//! let mut decoder = Decoder::new();
//! let messages = decode_slice(&mut decoder, &frame);
//! assert_eq!(messages, vec![Message::SyncPulseTime(SyncPulseTime { seq: 7, mcu_time_us: 1_000_000 })]);
//! assert_eq!(decoder.stats().frames_decoded, 1);
//! ```

mod decoder;
pub mod frame;
pub mod health;
mod messages;
#[cfg(test)]
mod tests;

pub use decoder::{Decoder, Encoder, Error};
pub use health::{Health, InertialHealth, NavigationHealth};
pub use messages::*;
