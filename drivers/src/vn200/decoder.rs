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
    /// the buffer for [`DeviceDecoder::decode`] to decode in place.
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

impl DeviceDecoder for Vn200Decoder {
    type Message = Vn200Message;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<Vn200Message> {
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
                    return None;
                }
                Some(0) => {}
                Some(n) => self.skip(buf, n),
            }
            let r = match buf[0] {
                binary::SYNC => match self.probe_binary(buf) {
                    BinaryStep::Frame { header, total } => {
                        // Decoded straight into the return value (the hot path).
                        let payload = buf.get(1 + header.len..total - 2).unwrap_or(&[]);
                        if let Some(m) = BinaryOutput::decode_payload(&header, payload) {
                            self.stats.take_frame(buf, total);
                            self.counters.binary_messages += 1;
                            return Some(Vn200Message::Binary(m));
                        }
                        self.stats.malformed += 1;
                        self.skip(buf, 1);
                        continue;
                    }
                    BinaryStep::Next => continue,
                    BinaryStep::Wait => return None,
                },
                split::SYNC => self.try_split(buf),
                _ => self.try_ascii(buf),
            };
            match r {
                Ok(Some(m)) => return Some(m),
                Ok(None) => continue,
                Err(()) => return None,
            }
        }
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<Vn200Message> {
        self.eof = true;
        let m = self.decode(buf);
        if m.is_none() {
            self.eof = false;
        }
        m
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
