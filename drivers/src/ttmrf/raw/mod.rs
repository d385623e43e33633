//! TT-Multi-RF raw outputs (manual 7.2.2 "ADS-B raw protocols", 10.2.2 "UAT raw protocols"):
//! the framing of HEX / HEXd (dump1090 AVR) lines and of the Beast binary protocol, as frames
//! with their receive metadata. Decoding the Mode S content is [`crate::modes`]' job.
//!
//! - [`hex::HexDecoder`]: `*<hex>;` lines, optionally followed by `(SIGS,SIGQ,TS1s,TS24h)`, and
//!   AVR-with-timestamp lines `@<12 hex MLAT ticks><hex>;`. Mode S (7/14 bytes), Mode A/C (four
//!   octal digits) and UAT (uplink and downlink) payloads.
//! - [`beast::BeastDecoder`]: 0x1A-escaped binary frames, types 0x31/0x32/0x33.
//! - Encoders for both ([`hex::encode_hex`], [`beast::encode_beast`]).

pub mod beast;
pub mod hex;

use serde::Serialize;

use crate::modes::squawk::Squawk;

pub use beast::BeastDecoder;
pub use hex::HexDecoder;

/// Receive metadata the receiver attached to a frame. Every field is optional: HEXd carries
/// none, HEX carries signal and (with a PPS) times, Beast carries the MLAT counter and RSSI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct RxMeta {
    /// Signal strength, dBm (HEX SIGS).
    pub signal_dbm: Option<i16>,
    /// Signal quality, dB for Mode S (HEX SIGQ); errors corrected for UAT.
    pub signal_quality: Option<i16>,
    /// Time since the last PPS, ns (HEX TS1s).
    pub ts_pps_ns: Option<u64>,
    /// Time since UTC midnight, ns (HEX TS24h).
    pub ts_utc_ns: Option<u64>,
    /// 12 MHz multilateration counter (Beast, AVR `@`); `None` when the sender gave 0.
    pub mlat_ticks: Option<u64>,
    /// Beast RSSI byte (0..254; 255 means "none" and gives `None`).
    pub rssi: Option<u8>,
}

impl RxMeta {
    /// Beast RSSI as dBFS, 20 log10(rssi / 255) (dump1090's convention).
    pub fn signal_dbfs(&self) -> Option<f64> {
        self.rssi
            .map(|r| 20.0 * (f64::from(r.max(1)) / 255.0).log10())
    }

    /// Receive time in seconds on the best time scale the frame carries: UTC of day (TS24h),
    /// else the MLAT counter / 12 MHz. `None` when the frame has no usable time (TS1s alone
    /// repeats every second, so it cannot order frames).
    pub fn time_s(&self) -> Option<f64> {
        if let Some(ns) = self.ts_utc_ns {
            return Some(ns as f64 * 1e-9);
        }
        self.mlat_ticks.map(|t| t as f64 / 12e6)
    }
}

/// A raw Mode S frame (7 or 14 bytes).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModeSFrame {
    /// The bytes; only the first `len` are meaningful.
    pub bytes: [u8; 14],
    /// 7 or 14.
    pub len: u8,
    /// Receive metadata.
    pub meta: RxMeta,
}

impl ModeSFrame {
    /// The frame's bytes.
    pub fn data(&self) -> &[u8] {
        &self.bytes[..usize::from(self.len).min(14)]
    }
}

/// A Mode A/C reply: four octal digits. Mode A and Mode C cannot be told apart on 1090 MHz
/// (manual, "Mode-AC raw frames"), so the code is given as received.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModeAcFrame {
    /// The code, one octal digit per nibble (0xABCD).
    pub code: Squawk,
    /// Receive metadata.
    pub meta: RxMeta,
}

/// A UAT (978 MHz) frame, passed on undecoded with its fields.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UatFrame {
    /// Uplink (ground station, >= 432 bytes) rather than downlink (aircraft) frame.
    pub uplink: bool,
    /// The payload bytes as sent by the receiver.
    pub bytes: Vec<u8>,
    /// Receive metadata.
    pub meta: RxMeta,
}

/// One frame of a raw stream.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RawFrame {
    /// Mode S short or long frame.
    ModeS(ModeSFrame),
    /// Mode A/C reply.
    ModeAc(ModeAcFrame),
    /// UAT frame (HEX only).
    Uat(UatFrame),
}

/// A Mode A/C code from its 16-bit nibble form, `None` if a nibble is not an octal digit.
pub(crate) fn mode_ac_code(v: u16) -> Option<Squawk> {
    (v & 0x8888 == 0).then_some(Squawk(v))
}

/// Bytes as upper-case hex (for output and logs; allocates).
pub fn encode_hex_string(bytes: &[u8]) -> String {
    use std::fmt::Write;
    let mut s = String::with_capacity(bytes.len() * 2);
    for b in bytes {
        let _ = write!(s, "{b:02X}");
    }
    s
}

/// [`tokio_util::codec::Encoder`] writing HEX lines (with extended fields) or HEXd lines, for
/// the simulator and loopback tests.
#[derive(Debug, Clone, Copy, Default)]
pub struct HexEncoder {
    /// Append `(SIGS,SIGQ,TS1s,TS24h)` (HEX) rather than nothing (HEXd).
    pub extended: bool,
}

impl tokio_util::codec::Encoder<&RawFrame> for HexEncoder {
    type Error = std::io::Error;

    fn encode(&mut self, item: &RawFrame, dst: &mut bytes::BytesMut) -> Result<(), Self::Error> {
        hex::encode_hex(item, self.extended, dst);
        Ok(())
    }
}

/// [`tokio_util::codec::Encoder`] writing Beast frames. UAT frames have no Beast form and are
/// refused with an `InvalidInput` error.
#[derive(Debug, Clone, Copy, Default)]
pub struct BeastEncoder;

impl tokio_util::codec::Encoder<&RawFrame> for BeastEncoder {
    type Error = std::io::Error;

    fn encode(&mut self, item: &RawFrame, dst: &mut bytes::BytesMut) -> Result<(), Self::Error> {
        if beast::encode_beast(item, dst) {
            Ok(())
        } else {
            Err(std::io::Error::new(
                std::io::ErrorKind::InvalidInput,
                "uat frames have no beast encoding",
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tokio_util::codec::Encoder;

    #[test]
    fn encoders_frame_as_the_free_functions() {
        let f = RawFrame::ModeAc(ModeAcFrame {
            code: Squawk(0x7700),
            meta: RxMeta::default(),
        });
        let mut out = bytes::BytesMut::new();
        HexEncoder { extended: false }.encode(&f, &mut out).unwrap();
        assert_eq!(&out[..], b"*7700;\r\n");
        out.clear();
        BeastEncoder.encode(&f, &mut out).unwrap();
        assert_eq!(&out[..], &[0x1A, 0x31, 0, 0, 0, 0, 0, 0, 0xFF, 0x77, 0x00]);
        let u = RawFrame::Uat(UatFrame {
            uplink: false,
            bytes: vec![0; 18],
            meta: RxMeta::default(),
        });
        assert!(BeastEncoder.encode(&u, &mut out).is_err());
        assert_eq!(encode_hex_string(&[0x8D, 0x0A]), "8D0A");
    }
}
