//! Beast binary raw protocol (TT-Multi-RF manual 7.2.2 "ADS-B Beast protocol").
//!
//! ```text
//! 0x1A  type  MLAT[6] (12 MHz counter, big-endian)  RSSI  data[2 | 7 | 14]
//!       0x31 Mode A/C, 0x32 Mode S short, 0x33 Mode S long
//! ```
//!
//! Every 0x1A after the start byte is doubled on the wire (0x1A 0x1A), so a frame is 2 + 9..21
//! logical bytes and at most 2 + 2 x 21 bytes on the wire.
//!
//! Resynchronisation, as the manual describes: after garbage, a frame start is only accepted
//! where a byte other than 0x1A is followed by 0x1A and a type byte (a 0x1A 0x31 preceded by 0x1A
//! may be the second half of an escaped pair followed by data). Right after a complete frame,
//! 0x1A + type is accepted directly. A 0x1A inside a frame that is not doubled ends the frame
//! early: the frame is counted malformed and decoding resumes at that 0x1A. Type 0x34 (receiver
//! status in some dump1090 forks) and other types are counted as unknown and skipped.
//! An MLAT counter of 0 means "no time"; RSSI 0xFF means "no signal level" (dump1090-fa).

use bytes::BytesMut;

use super::{ModeAcFrame, ModeSFrame, RawFrame, RxMeta, mode_ac_code};
use crate::{DecodeStats, DeviceDecoder};

/// The escape / start byte.
pub const ESC: u8 = 0x1A;
/// Longest frame on the wire: start, type and 21 logical bytes all escaped.
pub const MAX_WIRE_LEN: usize = 2 + 2 * 21;

/// Decoder of a Beast byte stream.
#[derive(Debug, Clone)]
pub struct BeastDecoder {
    stats: DecodeStats,
    /// The previous frame ended cleanly, so 0x1A + type at the head starts a frame.
    synced: bool,
    /// The last byte consumed (for the resynchronisation rule).
    prev: Option<u8>,
}

impl Default for BeastDecoder {
    fn default() -> Self {
        // The start of a stream counts as synchronised.
        Self {
            stats: DecodeStats::default(),
            synced: true,
            prev: None,
        }
    }
}

impl BeastDecoder {
    /// A new decoder.
    pub fn new() -> Self {
        Self::default()
    }

    fn skip(&mut self, buf: &mut BytesMut, n: usize) {
        if n == 0 {
            return;
        }
        self.prev = buf.get(n.min(buf.len()).saturating_sub(1)).copied();
        self.stats.skip(buf, n);
        self.synced = false;
    }
}

/// Logical data length of a frame type.
#[inline]
fn data_len(t: u8) -> Option<usize> {
    match t {
        0x31 => Some(2),
        0x32 => Some(7),
        0x33 => Some(14),
        _ => None,
    }
}

impl DeviceDecoder for BeastDecoder {
    type Message = RawFrame;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<RawFrame> {
        loop {
            let n = buf.len();
            if n == 0 {
                return None;
            }
            if buf[0] != ESC {
                let p = buf.iter().position(|&b| b == ESC).unwrap_or(n);
                self.skip(buf, p);
                continue;
            }
            if n < 2 {
                return None;
            }
            let t = buf[1];
            let may_start = self.synced || self.prev != Some(ESC);
            if t == ESC || !may_start {
                self.skip(buf, 1);
                continue;
            }
            let Some(dlen) = data_len(t) else {
                if (0x31..=0x39).contains(&t) {
                    self.stats.unknown_types += 1;
                } else {
                    self.stats.malformed += 1;
                }
                self.skip(buf, 2);
                continue;
            };
            let want = 7 + dlen;
            let mut logical = [0u8; 21];
            let mut k = 0;
            let mut i = 2;
            let mut broken = false;
            while k < want {
                if i >= n {
                    return None;
                }
                let b = buf[i];
                if b == ESC {
                    if i + 1 >= n {
                        return None;
                    }
                    if buf[i + 1] != ESC {
                        broken = true;
                        break;
                    }
                    i += 2;
                } else {
                    i += 1;
                }
                logical[k] = b;
                k += 1;
            }
            if broken {
                // Truncated frame: resume at the unescaped 0x1A, which may start the next one.
                self.stats.malformed += 1;
                self.stats.skip(buf, i);
                self.prev = None;
                self.synced = true;
                continue;
            }
            let ticks = logical[..6]
                .iter()
                .fold(0u64, |a, &b| (a << 8) | u64::from(b));
            let meta = RxMeta {
                mlat_ticks: (ticks != 0).then_some(ticks),
                rssi: (logical[6] != 0xFF).then_some(logical[6]),
                ..RxMeta::default()
            };
            let data = &logical[7..want];
            let frame = if t == 0x31 {
                match mode_ac_code(u16::from_be_bytes([data[0], data[1]])) {
                    Some(code) => RawFrame::ModeAc(ModeAcFrame { code, meta }),
                    None => {
                        self.stats.malformed += 1;
                        self.skip(buf, i);
                        self.synced = true;
                        continue;
                    }
                }
            } else {
                let mut bytes = [0u8; 14];
                bytes[..dlen].copy_from_slice(data);
                RawFrame::ModeS(ModeSFrame {
                    bytes,
                    len: dlen as u8,
                    meta,
                })
            };
            self.prev = Some(buf[i - 1]);
            self.synced = true;
            self.stats.take_frame(buf, i);
            return Some(frame);
        }
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

#[inline]
fn push_escaped(out: &mut BytesMut, bytes: &[u8]) {
    for &b in bytes {
        if b == ESC {
            out.extend_from_slice(&[ESC, ESC]);
        } else {
            out.extend_from_slice(&[b]);
        }
    }
}

/// Writes a frame in Beast framing (UAT frames have no Beast form and are not written; the
/// function returns false for them). A missing MLAT time is sent as 0, a missing RSSI as 0xFF.
pub fn encode_beast(frame: &RawFrame, out: &mut BytesMut) -> bool {
    let (t, meta, data): (u8, RxMeta, &[u8]) = match frame {
        RawFrame::ModeS(f) => (if f.len == 7 { 0x32 } else { 0x33 }, f.meta, f.data()),
        RawFrame::ModeAc(f) => (0x31, f.meta, &[]),
        RawFrame::Uat(_) => return false,
    };
    out.extend_from_slice(&[ESC, t]);
    let ticks = meta.mlat_ticks.unwrap_or(0) & 0xFFFF_FFFF_FFFF;
    push_escaped(out, &ticks.to_be_bytes()[2..]);
    push_escaped(out, &[meta.rssi.unwrap_or(0xFF)]);
    if let RawFrame::ModeAc(f) = frame {
        push_escaped(out, &f.code.0.to_be_bytes());
    } else {
        push_escaped(out, data);
    }
    true
}

#[cfg(test)]
#[path = "beast_tests.rs"]
mod tests;
