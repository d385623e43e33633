//! One decoder for everything a VN-200 serial port carries: binary output messages (0xFA),
//! split packets (0xFB) and ASCII sentences (`$VN...`), interleaved (ICD 1.1). Bytes that start
//! none of these (NMEA from another receiver, logger markers, line noise) are skipped and
//! counted.
//!
//! Resynchronisation: a candidate 0xFA that selects no group, an unknown group or type, implies
//! a length beyond the largest unsplit message (600 bytes), or fails its CRC, is a false sync:
//! one byte is dropped and the search resumes at the next candidate, so a stray 0xFA inside
//! other data never stalls the decoder. At the end of the stream a candidate still waiting for
//! bytes is treated the same way (counted as truncated), so what follows it still decodes.

use bytes::{Buf, BytesMut};
use serde::Serialize;

use super::ascii::{self, AsciiError, AsciiMessage, ChecksumKind, Scan};
use super::binary::{self, BinaryOutput, MAX_MESSAGE_LEN, Probe};
use super::crc::crc16;
use super::split::{self, Push, Reassembler, SplitCounters};
use crate::{DecodeStats, DeviceDecoder};

/// A message from a VN-200 port.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// Binary messages are the hot path: kept inline (no allocation per message) although larger
// than the ASCII variant.
#[allow(clippy::large_enum_variant)]
pub enum Vn200Message {
    /// A binary output message (unsplit or reassembled from split packets).
    Binary(BinaryOutput),
    /// An ASCII sentence.
    Ascii(AsciiMessage),
}

/// VN-200 specific counters, beside [`DecodeStats`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct Vn200Counters {
    /// Binary messages decoded (including reassembled ones).
    pub binary_messages: u64,
    /// ASCII sentences decoded.
    pub ascii_messages: u64,
    /// 0xFA / 0xFB candidates rejected by their structure or length (false syncs).
    pub false_syncs: u64,
    /// Candidates cut off by the end of the stream.
    pub truncated: u64,
    /// Printable lines starting with `$` that are not VectorNav sentences (e.g. `$GPRMC`).
    pub foreign_sentences: u64,
    /// `$` candidates that are not sentences (non-printable bytes, no checksum, too long).
    pub invalid_sentences: u64,
    /// Sentences with a bypassed checksum (`XX`, `XXXX`).
    pub checksum_bypassed: u64,
    /// Sentences with a 16-bit CRC checksum (Register 30 AsciiChecksum = 3).
    pub crc16_sentences: u64,
    /// Split packet reassembly.
    pub split: SplitCounters,
}

/// Outcome of checking a 0xFA candidate.
enum BinaryStep {
    /// A complete frame with a valid CRC, `total` bytes long.
    Frame {
        header: binary::Header,
        total: usize,
    },
    /// The candidate was dropped (counted): look for the next one.
    Next,
    /// More bytes are needed.
    Wait,
}

/// The VN-200 stream decoder.
#[derive(Debug, Clone, Default)]
pub struct Vn200Decoder {
    stats: DecodeStats,
    counters: Vn200Counters,
    split: Reassembler,
    eof: bool,
}

impl Vn200Decoder {
    /// A new decoder.
    pub fn new() -> Self {
        Self::default()
    }

    /// The VN-200 specific counters (split-packet counters included).
    pub fn counters(&self) -> Vn200Counters {
        let mut c = self.counters;
        c.split = self.split.counters;
        c
    }

    fn skip(&mut self, buf: &mut BytesMut, n: usize) {
        self.stats.skip(buf, n);
    }

    /// Consumes bytes held by the reassembler (neither a frame nor skipped yet).
    fn hold(&mut self, buf: &mut BytesMut, n: usize) {
        let n = n.min(buf.len());
        buf.advance(n);
        self.stats.bytes_consumed += n as u64;
    }

    fn count_abandoned(&mut self, held: u64) {
        self.stats.bytes_skipped += held;
    }

    /// A candidate is cut off: wait for more, or at the end of the stream drop one byte.
    fn incomplete(&mut self, buf: &mut BytesMut) -> bool {
        if self.eof {
            self.counters.truncated += 1;
            self.skip(buf, 1);
            true
        } else {
            false
        }
    }

    /// Checks a 0xFA candidate: its header, length and CRC. On success the frame is left in
    /// the buffer for [`Vn200Decoder::decode_into`] to decode in place.
    #[inline(always)]
    fn probe_binary(&mut self, buf: &mut BytesMut) -> BinaryStep {
        match binary::body_len(&buf[1..], MAX_MESSAGE_LEN - 3) {
            Ok((header, body_len)) => {
                let total = 1 + body_len + 2;
                if buf.len() < total {
                    return if self.incomplete(buf) {
                        BinaryStep::Next
                    } else {
                        BinaryStep::Wait
                    };
                }
                if crc16(&buf[1..total]) != 0 {
                    self.stats.checksum_failures += 1;
                    self.skip(buf, 1);
                    return BinaryStep::Next;
                }
                BinaryStep::Frame { header, total }
            }
            Err(Probe::NeedMore) => {
                if self.incomplete(buf) {
                    BinaryStep::Next
                } else {
                    BinaryStep::Wait
                }
            }
            Err(Probe::Unknown) => {
                self.stats.unknown_types += 1;
                self.skip(buf, 1);
                BinaryStep::Next
            }
            Err(Probe::Invalid | Probe::TooLong) => {
                self.counters.false_syncs += 1;
                self.skip(buf, 1);
                BinaryStep::Next
            }
        }
    }

    fn try_split(&mut self, buf: &mut BytesMut) -> Result<Option<Vn200Message>, ()> {
        let h = match split::parse_header(buf) {
            Ok(h) => h,
            Err(true) => {
                return if self.incomplete(buf) {
                    Ok(None)
                } else {
                    Err(())
                };
            }
            Err(false) => {
                self.counters.false_syncs += 1;
                self.skip(buf, 1);
                return Ok(None);
            }
        };
        let total = 1 + split::HEADER_LEN + h.payload_len + 2;
        if buf.len() < total {
            return if self.incomplete(buf) {
                Ok(None)
            } else {
                Err(())
            };
        }
        if crc16(&buf[1..total]) != 0 {
            self.stats.checksum_failures += 1;
            self.skip(buf, 1);
            return Ok(None);
        }
        let offset = self.stats.bytes_consumed;
        let payload = &buf[1 + split::HEADER_LEN..total - 2];
        let (push, abandoned) = self.split.push(h, payload, offset, total as u64);
        self.count_abandoned(abandoned);
        match push {
            Push::Pending => {
                self.hold(buf, total);
                Ok(None)
            }
            Push::Dropped => {
                self.skip(buf, total);
                Ok(None)
            }
            Push::Complete(body) => {
                let start = self.split.start_offset;
                // Every packet of the sequence, this one included: consumed when held.
                let held = std::mem::take(&mut self.split.held_bytes);
                self.hold(buf, total);
                let ok = binary::body_len(&body, usize::MAX)
                    .ok()
                    .filter(|(_, n)| *n == body.len())
                    .and_then(|_| BinaryOutput::decode_body(&body));
                match ok {
                    Some(m) => {
                        self.split.counters.reassembled += 1;
                        self.counters.binary_messages += 1;
                        self.stats.count_reassembled(start);
                        Ok(Some(Vn200Message::Binary(m)))
                    }
                    None => {
                        self.split.counters.malformed += 1;
                        self.stats.malformed += 1;
                        self.count_abandoned(held);
                        Ok(None)
                    }
                }
            }
        }
    }

    fn try_ascii(&mut self, buf: &mut BytesMut) -> Result<Option<Vn200Message>, ()> {
        match ascii::scan(buf) {
            Scan::NeedMore => {
                if self.incomplete(buf) {
                    Ok(None)
                } else {
                    Err(())
                }
            }
            Scan::Invalid => {
                self.counters.invalid_sentences += 1;
                self.skip(buf, 1);
                Ok(None)
            }
            Scan::BadChecksum => {
                self.stats.checksum_failures += 1;
                self.skip(buf, 1);
                Ok(None)
            }
            Scan::Foreign { len } => {
                self.counters.foreign_sentences += 1;
                self.skip(buf, len);
                Ok(None)
            }
            Scan::Sentence { body, kind, len } => {
                let parsed = AsciiMessage::parse(body);
                match parsed {
                    Ok(m) => {
                        match kind {
                            ChecksumKind::BypassXor8 | ChecksumKind::BypassCrc16 => {
                                self.counters.checksum_bypassed += 1
                            }
                            ChecksumKind::Crc16 => self.counters.crc16_sentences += 1,
                            ChecksumKind::Xor8 => {}
                        }
                        self.stats.take_frame(buf, len);
                        self.counters.ascii_messages += 1;
                        Ok(Some(Vn200Message::Ascii(m)))
                    }
                    Err(AsciiError::UnknownHeader(_)) => {
                        self.stats.unknown_types += 1;
                        self.skip(buf, len);
                        Ok(None)
                    }
                    Err(AsciiError::Malformed { .. }) => {
                        self.stats.malformed += 1;
                        self.skip(buf, len);
                        Ok(None)
                    }
                }
            }
        }
    }
}

impl Vn200Decoder {
    /// Decodes the next message from the front of `buf` into `out`, the caller's message, and
    /// returns `true`; `false` when `buf` holds no complete message yet (same contract and
    /// counters as [`DeviceDecoder::decode`], which is built on it).
    ///
    /// Issue 21: a binary message is written in place, group by group, into `out` (which is
    /// switched to [`Vn200Message::Binary`] first if needed): the 928-byte message is not built
    /// on the stack and moved out. Reusing the same `out` for a stream (e.g. a recycled box) is
    /// the point. When it returns `false`, `out` may hold a partial decode: do not use it.
    pub fn decode_into(&mut self, buf: &mut BytesMut, out: &mut Vn200Message) -> bool {
        loop {
            // Skip to the next possible start: 0xFA, 0xFB or '$'.
            let start = buf
                .iter()
                .position(|&b| b == binary::SYNC || b == split::SYNC || b == ascii::START);
            match start {
                None => {
                    let n = buf.len();
                    self.skip(buf, n);
                    if self.eof && self.split.in_progress() {
                        let held = self.split.abandon();
                        self.count_abandoned(held);
                    }
                    return false;
                }
                Some(0) => {}
                Some(n) => self.skip(buf, n),
            }
            let r = match buf[0] {
                binary::SYNC => match self.probe_binary(buf) {
                    BinaryStep::Frame { header, total } => {
                        // Decoded straight into the caller's message (the hot path).
                        let payload = buf.get(1 + header.len..total - 2).unwrap_or(&[]);
                        if binary_slot(out).decode_payload_into(&header, payload) {
                            self.stats.take_frame(buf, total);
                            self.counters.binary_messages += 1;
                            return true;
                        }
                        self.stats.malformed += 1;
                        self.skip(buf, 1);
                        continue;
                    }
                    BinaryStep::Next => continue,
                    BinaryStep::Wait => return false,
                },
                split::SYNC => self.try_split(buf),
                _ => self.try_ascii(buf),
            };
            match r {
                Ok(Some(m)) => {
                    *out = m;
                    return true;
                }
                Ok(None) => continue,
                Err(()) => return false,
            }
        }
    }

    /// [`Vn200Decoder::decode_into`] at the end of the stream (see
    /// [`DeviceDecoder::decode_eof`], which is built on it).
    pub fn decode_eof_into(&mut self, buf: &mut BytesMut, out: &mut Vn200Message) -> bool {
        self.eof = true;
        let got = self.decode_into(buf, out);
        if !got {
            self.eof = false;
        }
        got
    }
}

/// The binary message in `out`, which is made one (empty) if it holds an ASCII sentence.
#[inline(always)]
fn binary_slot(out: &mut Vn200Message) -> &mut BinaryOutput {
    if let Vn200Message::Ascii(_) = out {
        *out = Vn200Message::Binary(BinaryOutput::default());
    }
    match out {
        Vn200Message::Binary(b) => b,
        Vn200Message::Ascii(_) => unreachable!("replaced by a binary message just above"),
    }
}

impl DeviceDecoder for Vn200Decoder {
    type Message = Vn200Message;

    /// [`Vn200Decoder::decode_into`] a new message, returned by value.
    fn decode(&mut self, buf: &mut BytesMut) -> Option<Vn200Message> {
        let mut m = Vn200Message::Binary(BinaryOutput::default());
        self.decode_into(buf, &mut m).then_some(m)
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<Vn200Message> {
        let mut m = Vn200Message::Binary(BinaryOutput::default());
        self.decode_eof_into(buf, &mut m).then_some(m)
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

#[cfg(test)]
mod tests;
