//! The ASCII protocol (ICD 1.1.2, 1.3, 1.4, 1.5): sentences `$VN<HDR>,<fields>*<CS>\r\n`.
//!
//! - Checksum (1.4): two hex digits = 8-bit XOR, four = 16-bit CRC (CRC16-CCITT, as the binary
//!   messages), over the bytes between `$` and `*`. `XX` / `XXXX` bypass the checksum (1.4.1);
//!   only a host sends them, and they are accepted (and counted) so that a host-side capture or
//!   the simulator's view of a port decodes too.
//! - [`Command`]: what the host sends (1.3), and the device's echo of it.
//! - [`RegisterValue`]: register contents, in `$VNRRG` responses and `$VNWRG` commands.
//! - [`Measurement`]: the measurement registers, also sent as async outputs (Register 6).
//! - [`ErrorCode`]: `$VNERR` (1.5); its code is hexadecimal on the wire.
//!
//! Floats are written with Rust's shortest round-trip representation (`73.2`, `-0.3574`), as in
//! the ICD's command examples; it makes decode(encode(x)) exact. The sensor's own fixed-width
//! output (`+010.071`, `2.00E-09`) parses the same way.

mod command;
mod error;
mod fields;
mod measurement;
mod register;

pub use command::{Command, CommandEncoder, InitialHeading};
pub use error::ErrorCode;
pub use measurement::{
    AsyncOutput, GnssSolutionEcef, GnssSolutionLla, ImuMeasurements, InsSolutionEcef,
    InsSolutionLla, InsStateEcef, InsStateLla, MagAccelGyro, Measurement, QuatMagAccelGyro,
    YprLinAccelGyro, YprMagAccelGyro,
};
pub use register::{
    BinaryOutputConfig, CommProtocolControl, GnssBasicConfig, GnssSystemConfig, InsBasicConfig,
    NmeaOutputConfig, RegisterValue, SyncControl, SyncStatus,
};

use serde::Serialize;

use crate::vn200::crc::{crc16, xor8};
pub(crate) use fields::Fields;

/// Start of every sentence.
pub const START: u8 = b'$';

/// Longest sentence accepted, `$` to `\n` (the longest documented response is about 180
/// characters; the sensor's input buffer is 256).
pub const MAX_SENTENCE_LEN: usize = 512;

/// Checksum style of a sentence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ChecksumKind {
    /// Two hex digits, 8-bit XOR (the default, Register 30 AsciiChecksum = 1).
    Xor8,
    /// Four hex digits, 16-bit CRC (Register 30 AsciiChecksum = 3).
    Crc16,
    /// `XX`: checksum bypassed (host to sensor only).
    BypassXor8,
    /// `XXXX`: checksum bypassed (host to sensor only).
    BypassCrc16,
}

/// Why a sentence was not decoded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum AsciiError {
    /// The header after `$VN` is not one this crate knows.
    #[error("unknown vn200 sentence header {0:?}")]
    UnknownHeader(String),
    /// A field is missing, extra or does not parse.
    #[error("malformed vn200 sentence {header}: {reason}")]
    Malformed {
        /// The sentence header (e.g. `VNRRG`).
        header: String,
        /// What was wrong.
        reason: String,
    },
}

/// A decoded ASCII sentence.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "sentence", rename_all = "snake_case")]
pub enum AsciiMessage {
    /// An asynchronous output (Register 6 selects which).
    Async(AsyncOutput),
    /// A `$VNRRG` response carrying a register's contents.
    ReadResponse {
        /// The register contents.
        value: RegisterValue,
    },
    /// A command, as sent by the host or echoed by the sensor (including `$VNRRG,<id>` and
    /// `$VNWRG`, whose echo is the register's new contents).
    Command {
        /// The command.
        command: Command,
    },
    /// `$VNERR`: the sensor rejected a command or reports a system error.
    Error {
        /// The error code.
        code: ErrorCode,
    },
}

impl AsciiMessage {
    /// Parses a sentence body (between `$` and `*`, checksum already verified).
    pub fn parse(body: &str) -> Result<Self, AsciiError> {
        let (header, rest) = match body.split_once(',') {
            Some((h, r)) => (h, Some(r)),
            None => (body, None),
        };
        let mut f = Fields::new(header, rest);
        let msg = match header {
            "VNERR" => AsciiMessage::Error {
                code: ErrorCode::from_hex(f.next_str()?).ok_or_else(|| f.bad("error code"))?,
            },
            "VNRRG" => {
                let id = f.u8()?;
                if f.is_empty() {
                    AsciiMessage::Command {
                        command: Command::ReadRegister(id),
                    }
                } else {
                    AsciiMessage::ReadResponse {
                        value: RegisterValue::parse(id, &mut f)?,
                    }
                }
            }
            _ => {
                if let Some(m) = Measurement::parse_async(header, &mut f)? {
                    let (status, count) = f.appended()?;
                    AsciiMessage::Async(AsyncOutput {
                        data: m,
                        appended_status: status,
                        appended_count: count,
                    })
                } else {
                    AsciiMessage::Command {
                        command: Command::parse(header, &mut f)?,
                    }
                }
            }
        };
        f.finish()?;
        Ok(msg)
    }

    /// The sentence body (between `$` and `*`) of this message.
    pub fn body(&self) -> String {
        match self {
            AsciiMessage::Async(a) => a.body(),
            AsciiMessage::ReadResponse { value } => format!("VNRRG,{}", value.body()),
            AsciiMessage::Command { command } => command.body(),
            AsciiMessage::Error { code } => format!("VNERR,{:02X}", code.code()),
        }
    }

    /// The complete sentence with the given checksum style.
    pub fn encode(&self, kind: ChecksumKind) -> Vec<u8> {
        frame_sentence(&self.body(), kind)
    }
}

/// Frames a body as `$body*CS\r\n`.
pub fn frame_sentence(body: &str, kind: ChecksumKind) -> Vec<u8> {
    let cs = match kind {
        ChecksumKind::Xor8 => format!("{:02X}", xor8(body.as_bytes())),
        ChecksumKind::Crc16 => format!("{:04X}", crc16(body.as_bytes())),
        ChecksumKind::BypassXor8 => "XX".to_string(),
        ChecksumKind::BypassCrc16 => "XXXX".to_string(),
    };
    let mut out = Vec::with_capacity(body.len() + 8);
    out.push(START);
    out.extend_from_slice(body.as_bytes());
    out.push(b'*');
    out.extend_from_slice(cs.as_bytes());
    out.extend_from_slice(b"\r\n");
    out
}

/// Result of looking for a sentence at the start of a buffer that begins with `$`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Scan<'a> {
    /// No line end yet, and the line is still short enough to be a sentence.
    NeedMore,
    /// Not a sentence: a non-printable byte before the line end, no `*`, a malformed checksum
    /// field, or too long.
    Invalid,
    /// A printable line starting with `$` but not `$VN` (e.g. NMEA `$GPRMC`), `len` bytes up to
    /// and including `\n`.
    Foreign {
        /// Bytes of the line including its terminator.
        len: usize,
    },
    /// A `$VN` line whose checksum does not verify.
    BadChecksum,
    /// A `$VN` sentence with a verified (or bypassed) checksum.
    Sentence {
        /// The body between `$` and `*`.
        body: &'a str,
        /// The checksum style used.
        kind: ChecksumKind,
        /// Bytes of the line including its terminator.
        len: usize,
    },
}

/// Looks for one sentence at the start of `buf` (`buf[0]` is `$`).
pub fn scan(buf: &[u8]) -> Scan<'_> {
    let limit = buf.len().min(MAX_SENTENCE_LEN);
    let mut nl = None;
    for (i, &b) in buf.iter().enumerate().take(limit).skip(1) {
        match b {
            b'\n' => {
                nl = Some(i);
                break;
            }
            b'\r' => {
                if buf.get(i + 1).is_some_and(|&n| n != b'\n') {
                    return Scan::Invalid;
                }
            }
            0x20..=0x7E => {}
            _ => return Scan::Invalid,
        }
    }
    let Some(nl) = nl else {
        return if buf.len() >= MAX_SENTENCE_LEN {
            Scan::Invalid
        } else {
            Scan::NeedMore
        };
    };
    let len = nl + 1;
    let line = &buf[1..nl];
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    // The bytes are printable ASCII here, so this cannot fail.
    let Ok(line) = std::str::from_utf8(line) else {
        return Scan::Invalid;
    };
    if !line.starts_with("VN") {
        return Scan::Foreign { len };
    }
    let Some((body, cs)) = line.rsplit_once('*') else {
        return Scan::Invalid;
    };
    let kind = match cs {
        "XX" => ChecksumKind::BypassXor8,
        "XXXX" => ChecksumKind::BypassCrc16,
        _ if cs.len() == 2 => match u8::from_str_radix(cs, 16) {
            Ok(v) if is_hex(cs) => {
                if v != xor8(body.as_bytes()) {
                    return Scan::BadChecksum;
                }
                ChecksumKind::Xor8
            }
            _ => return Scan::Invalid,
        },
        _ if cs.len() == 4 => match u16::from_str_radix(cs, 16) {
            Ok(v) if is_hex(cs) => {
                if v != crc16(body.as_bytes()) {
                    return Scan::BadChecksum;
                }
                ChecksumKind::Crc16
            }
            _ => return Scan::Invalid,
        },
        _ => return Scan::Invalid,
    };
    Scan::Sentence { body, kind, len }
}

fn is_hex(s: &str) -> bool {
    s.bytes().all(|b| b.is_ascii_hexdigit())
}

#[cfg(test)]
mod tests;
