//! VectorNav VN-200 GNSS/INS (Interface Control Document, Industrial Series, firmware 2.1.0.0,
//! 24-20006-R1): binary output messages, split packets, the ASCII command protocol and the
//! registers vigil uses.
//!
//! - [`binary`]: 0xFA messages, every type of every group (chapter 2), with encoders.
//! - [`split`]: 0xFB split packets and their reassembly (Appendix B.1.2).
//! - [`ascii`]: sentences, commands, registers, async outputs and `$VNERR` (chapters 1, 3, 4).
//! - [`status`]: the status words (InsStatus, ImuStatus, TimeStatus, GnssStatus, SensSat).
//! - [`decoder`]: [`Vn200Decoder`], one [`crate::DeviceDecoder`] for the interleaved stream.
//! - [`client`]: the sans-IO configuration client (Registers 75-77).
//! - [`crc`]: the 8-bit XOR and 16-bit CRC checksums.
//!
//! Units: SI where the device sends SI; otherwise the unit is in the field name (`yaw_deg`,
//! `mag_gauss`, `pressure_kpa`, `time_gps_ns`). Values are kept at the wire's precision (f32
//! stays f32) so that encoders reproduce the bytes exactly.

pub mod ascii;
pub mod binary;
pub mod client;
pub mod crc;
pub mod decoder;
pub mod split;
pub mod status;

pub use decoder::{Vn200Counters, Vn200Decoder, Vn200Message};
