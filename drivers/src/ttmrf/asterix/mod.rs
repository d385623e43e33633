//! TT-Multi-RF ASTERIX output (manual 7.2.1 "ADS-B ASTERIX protocol", 8.2.1 "FLARM ASTERIX
//! protocol"): CAT021 ed 2.1 target reports and CAT023 ed 1.2 ground station status, as a raw
//! stream of ASTERIX data blocks (EUROCONTROL ASTERIX Part 1, 4: `CAT | LEN (2 octets, counting
//! the whole block) | records...`).
//!
//! Modules: [`item`] (FSPEC and the length rules: fixed, extended, repetitive, explicit,
//! compound), [`common`] (items both categories share), [`cat021`] and [`cat023`] (UAP tables,
//! records, item groups, encoders).
//!
//! The stream has no synchronisation pattern, so [`AsterixDecoder`] accepts a data block only when
//! its header is plausible and *every* record in it walks exactly to the block's end:
//! - the category is 21 or 23 (the only ones the module sends);
//! - LEN is at least 6 (header, one FSPEC octet, the mandatory 2-octet I0xx/010) and at most
//!   [`AsterixDecoder::max_block_len`] (default [`DEFAULT_MAX_BLOCK_LEN`]);
//! - the first FSPEC octet has FRN 1 (the mandatory data source item) set;
//! - every record parses under the category's UAP and carries its data source item.
//!
//! Otherwise one byte is skipped and the search goes on. While synchronised (as the decoder
//! starts, and after every good block), a block that fails
//! counts once as `malformed` (or as `unknown_types` when its category is not 21/23); the bytes
//! skipped while resynchronising are counted only as skipped bytes. Each record is one message:
//! the first of a block takes the block's bytes, the others are counted as reassembled messages
//! starting at the block's offset.

pub mod cat021;
pub mod cat023;
pub mod common;
pub mod item;

#[cfg(test)]
mod tests;

use std::collections::VecDeque;

use bytes::BytesMut;
use serde::Serialize;

use crate::traffic::TrafficReport;
use crate::{DecodeStats, DeviceDecoder};
use cat021::Cat021Record;
use cat023::Cat023Record;
use item::ItemError;

/// Default largest data block accepted, octets. ASTERIX allows 65535; a TT-Multi-RF block holds
/// a few records of about 50 octets each, and a smaller bound limits how long a false block
/// header found after corruption can hold up the stream.
pub const DEFAULT_MAX_BLOCK_LEN: usize = 4096;
/// Smallest possible data block: CAT, LEN, one FSPEC octet and a 2-octet data source item.
pub const MIN_BLOCK_LEN: usize = 6;

/// One decoded ASTERIX record.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "cat", rename_all = "snake_case")]
pub enum AsterixMessage {
    /// A CAT021 ADS-B (or FLARM) target report.
    Cat021(Box<Cat021Record>),
    /// A CAT023 ground station / service status report.
    Cat023(Box<Cat023Record>),
}

impl AsterixMessage {
    /// The common traffic report of a CAT021 record (CAT023 gives `None`).
    pub fn to_traffic(&self) -> Option<TrafficReport> {
        match self {
            Self::Cat021(r) => Some(cat021::traffic::to_traffic(r)),
            Self::Cat023(_) => None,
        }
    }

    /// Appends this record as a data block of its own.
    pub fn encode_block(&self, out: &mut Vec<u8>) {
        let mut rec = Vec::new();
        let cat = match self {
            Self::Cat021(r) => {
                r.encode(&mut rec);
                cat021::CAT
            }
            Self::Cat023(r) => {
                r.encode(&mut rec);
                cat023::CAT
            }
        };
        encode_block(cat, &rec, out);
    }
}

/// `tokio_util` encoder writing each record as a data block of its own (for the simulated module
/// and `FramedWrite`).
#[derive(Debug, Clone, Copy, Default)]
pub struct AsterixEncoder;

impl tokio_util::codec::Encoder<AsterixMessage> for AsterixEncoder {
    type Error = std::io::Error;

    fn encode(&mut self, msg: AsterixMessage, dst: &mut BytesMut) -> Result<(), Self::Error> {
        let mut out = Vec::with_capacity(64);
        msg.encode_block(&mut out);
        dst.extend_from_slice(&out);
        Ok(())
    }
}

/// Appends a data block of category `cat` holding the already-encoded `records` (concatenated).
/// Records longer than a block can hold are cut at 65532 octets.
pub fn encode_block(cat: u8, records: &[u8], out: &mut Vec<u8>) {
    let body = &records[..records.len().min(usize::from(u16::MAX) - 3)];
    out.push(cat);
    out.extend_from_slice(&((body.len() + 3) as u16).to_be_bytes());
    out.extend_from_slice(body);
}

/// Parses every record of a block body (after CAT and LEN).
pub fn parse_block(cat: u8, body: &[u8]) -> Result<Vec<AsterixMessage>, ItemError> {
    let mut out = Vec::new();
    let mut pos = 0;
    while pos < body.len() {
        let rest = &body[pos..];
        let (msg, len) = match cat {
            cat021::CAT => {
                let (r, len) = cat021::decode_record(rest)?;
                (AsterixMessage::Cat021(Box::new(r)), len)
            }
            cat023::CAT => {
                let (r, len) = cat023::decode_record(rest)?;
                (AsterixMessage::Cat023(Box::new(r)), len)
            }
            _ => return Err(ItemError::Malformed("category")),
        };
        out.push(msg);
        pos += len;
    }
    if out.is_empty() {
        return Err(ItemError::Truncated("block without records"));
    }
    Ok(out)
}

/// Sans-IO decoder of a TT-Multi-RF ASTERIX byte stream (CAT021 and CAT023 data blocks).
#[derive(Debug, Clone)]
pub struct AsterixDecoder {
    stats: DecodeStats,
    /// Records of the last block not yet handed out.
    pending: VecDeque<AsterixMessage>,
    /// Stream offset of the block the pending records came from.
    pending_start: u64,
    /// The last thing consumed was a valid block (so a failure now is counted).
    in_sync: bool,
    max_block_len: usize,
}

impl Default for AsterixDecoder {
    fn default() -> Self {
        Self::new(DEFAULT_MAX_BLOCK_LEN)
    }
}

impl AsterixDecoder {
    /// A decoder accepting data blocks of up to `max_block_len` octets (clamped to
    /// [`MIN_BLOCK_LEN`]..=65535).
    pub fn new(max_block_len: usize) -> Self {
        Self {
            stats: DecodeStats::default(),
            pending: VecDeque::new(),
            pending_start: 0,
            in_sync: true,
            max_block_len: max_block_len.clamp(MIN_BLOCK_LEN, usize::from(u16::MAX)),
        }
    }

    /// The largest data block this decoder accepts, octets.
    pub fn max_block_len(&self) -> usize {
        self.max_block_len
    }

    fn reject(&mut self, buf: &mut BytesMut, unknown_category: bool) {
        if self.in_sync {
            if unknown_category {
                self.stats.unknown_types += 1;
            } else {
                self.stats.malformed += 1;
            }
            self.in_sync = false;
        }
        self.stats.skip(buf, 1);
    }
}

impl DeviceDecoder for AsterixDecoder {
    type Message = AsterixMessage;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<AsterixMessage> {
        if let Some(m) = self.pending.pop_front() {
            self.stats.count_reassembled(self.pending_start);
            return Some(m);
        }
        loop {
            let &cat = buf.first()?;
            if cat != cat021::CAT && cat != cat023::CAT {
                self.reject(buf, true);
                continue;
            }
            if buf.len() < 4 {
                return None;
            }
            let len = usize::from(u16::from_be_bytes([buf[1], buf[2]]));
            if !(MIN_BLOCK_LEN..=self.max_block_len).contains(&len) || buf[3] & 0x80 == 0 {
                self.reject(buf, false);
                continue;
            }
            if buf.len() < len {
                return None;
            }
            match parse_block(cat, &buf[3..len]) {
                Ok(mut msgs) => {
                    self.in_sync = true;
                    // Issue 24: a CAT021 record with an impossible value is dropped alone and
                    // counted; the block's other records are kept.
                    let n = msgs.len();
                    msgs.retain(|m| match m {
                        AsterixMessage::Cat021(r) => {
                            cat021::traffic::to_traffic(r).check_values().is_ok()
                        }
                        _ => true,
                    });
                    self.stats.invalid_values += (n - msgs.len()) as u64;
                    if msgs.is_empty() {
                        self.stats.skip(buf, len);
                        continue;
                    }
                    self.stats.take_frame(buf, len);
                    self.pending_start = self.stats.last_frame_start;
                    let mut it = msgs.into_iter();
                    let first = it.next();
                    self.pending.extend(it);
                    if first.is_some() {
                        return first;
                    }
                }
                Err(_) => self.reject(buf, false),
            }
        }
    }

    /// At the end of the stream a block that still lacks bytes can never complete: its first
    /// byte is rejected (a truncated block counts once as malformed) and the rest is searched
    /// again, so a false block header near the end does not hide the real blocks after it.
    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<AsterixMessage> {
        loop {
            if let Some(m) = self.decode(buf) {
                return Some(m);
            }
            if buf.is_empty() {
                return None;
            }
            self.reject(buf, false);
        }
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}
