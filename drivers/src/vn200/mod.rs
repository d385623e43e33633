//! VectorNav VN-200 GNSS/INS (Interface Control Document, Industrial Series, firmware 2.1.0.0,
//! 24-20006-R1): binary output messages, split packets, the ASCII command protocol and the
//! registers vigil uses.
//!
//! - [`binary`]: 0xFA messages, every type of every group (chapter 2), with encoders.
//! - [`split`]: 0xFB split packets and their reassembly (Appendix B.1.2).
//! - [`ascii`]: sentences, commands, registers, async outputs and `$VNERR` (chapters 1, 3, 4).
//! - [`status`]: the status words (InsStatus, ImuStatus, TimeStatus, GnssStatus, SensSat).
//! - [`decoder`]: [`Vn200Decoder`], one [`crate::DeviceDecoder`] for the interleaved stream.
//! - [`boxed`]: [`boxed::BoxedDecoder`], the same decoding each message into a recycled box.
//! - [`client`]: the sans-IO configuration client (Registers 75-77).
//! - [`crc`]: the 8-bit XOR and 16-bit CRC checksums.
//!
//! Decisions where the ICD is ambiguous or wrong (each tested where it is implemented):
//! - Type offsets past 14 follow the type tables (offset 16 = bit 0 of the second type word),
//!   not Appendix B.1.1's example, which counts data bits only (as VectorNav's current SDK).
//! - A 0xFA candidate longer than 600 bytes is a false sync (B.1.2: longer messages are split).
//! - Split packets: the packet number may start at 0 or 1 (the ICD does not say); encoded from 1.
//! - TimeUtc FracSec: uint16 in the Time group, int16 in the GNSS groups; read as i16 (both
//!   agree on 0..999).
//! - Appended ASCII status/count (Register 30): the text puts status first, the example count
//!   first; both orders are read, the example's is written.
//! - GnssStatus DataSource: bits 8-10 (the next documented field is at 11).
//! - Reserved status bits are kept, never rejected (InsStatus 0x8085 is normal).
//! - ICD misprints found by checksums: `$VNWRG,5,921600` is `*63` (printed `*46`/`*6D`);
//!   Register 32's example needs `100000000` for its `*6B`.
//! - The sensor's own NMEA output (Registers 101/102) is not decoded here: counted as foreign.
//!
//! Units: SI where the device sends SI; otherwise the unit is in the field name (`yaw_deg`,
//! `mag_gauss`, `pressure_kpa`, `time_gps_ns`). Values are kept at the wire's precision (f32
//! stays f32) so that encoders reproduce the bytes exactly.

pub mod ascii;
pub mod binary;
pub mod boxed;
pub mod client;
pub mod crc;
pub mod decoder;
pub mod split;
pub mod status;

pub use decoder::{Vn200Counters, Vn200Decoder, Vn200Message};
