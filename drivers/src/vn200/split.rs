//! Split packets (ICD Appendix B.1.2): a binary message over 600 bytes is sent as packets
//!
//! ```text
//! 0xFB | MsgType (0x00) | MessageID | PacketCount | PayloadLength (u16 LE) | payload | CRC (BE)
//! ```
//!
//! whose payloads, concatenated in order, form the header and payload (the *body*) of one 0xFA
//! message. The CRC of each packet covers its header and payload, as for 0xFA messages.
//!
//! PacketCount holds the total number of packets in its high nibble and "the current packet
//! count" in its low nibble. The ICD does not say whether that count starts at 0 or 1: the
//! reassembler accepts a sequence that starts at either (and then counts up by one), and the
//! encoder numbers packets from 1 (a count of packets sent so far). A packet that does not
//! continue the sequence in progress abandons it (counted as incomplete); a packet in the middle
//! of a sequence that never started is counted as out of order. Incomplete or out-of-order
//! bytes are counted as skipped.

use serde::Serialize;

use crate::vn200::crc::crc16;

/// Sync byte of a split packet.
pub const SYNC: u8 = 0xFB;

/// Header bytes after the sync byte.
pub const HEADER_LEN: usize = 5;

/// Largest packet payload: a packet is at most as long as an unsplit message (600 bytes) less
/// sync, header and CRC.
pub const MAX_PACKET_PAYLOAD: usize = 600 - 1 - HEADER_LEN - 2;

/// Counters of split-packet reassembly.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct SplitCounters {
    /// Packets with a valid CRC.
    pub packets: u64,
    /// Messages reassembled and decoded.
    pub reassembled: u64,
    /// Sequences abandoned before their last packet (a new sequence or the end of the stream).
    pub incomplete: u64,
    /// Packets that did not fit any sequence (not its start, not the next one expected).
    pub out_of_order: u64,
    /// Reassembled bodies that did not form a valid message.
    pub malformed: u64,
}

/// A validated split packet's header fields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PacketHeader {
    /// Message id shared by the packets of one message.
    pub message_id: u8,
    /// Total packets of the message (high nibble).
    pub total: u8,
    /// This packet's number (low nibble).
    pub index: u8,
    /// Payload bytes.
    pub payload_len: usize,
}

/// Reads the header at the start of `buf` (`buf[0]` = 0xFB). `Err(true)` = need more bytes,
/// `Err(false)` = not a split packet.
pub fn parse_header(buf: &[u8]) -> Result<PacketHeader, bool> {
    let h = buf.get(..1 + HEADER_LEN).ok_or(true)?;
    let payload_len = usize::from(u16::from_le_bytes([h[4], h[5]]));
    let total = h[3] >> 4;
    let index = h[3] & 0x0F;
    if h[1] != 0
        || total == 0
        || index > total
        || payload_len == 0
        || payload_len > MAX_PACKET_PAYLOAD
    {
        return Err(false);
    }
    Ok(PacketHeader {
        message_id: h[2],
        total,
        index,
        payload_len,
    })
}

/// What a packet did to the sequence in progress.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Push {
    /// Held; more packets are expected.
    Pending,
    /// The packet completed a message: the concatenated body.
    Complete(Vec<u8>),
    /// The packet fits no sequence and was dropped.
    Dropped,
}

/// Reassembles split packets into message bodies. Bounded: at most 15 packets of
/// [`MAX_PACKET_PAYLOAD`] bytes are held.
#[derive(Debug, Clone, Default)]
pub struct Reassembler {
    /// (message id, total, next expected index, last index) of the sequence in progress.
    current: Option<(u8, u8, u8, u8)>,
    body: Vec<u8>,
    /// Stream offset of the first packet of the sequence in progress.
    pub start_offset: u64,
    /// Wire bytes of the packets held (to count them as skipped if abandoned).
    pub held_bytes: u64,
    /// Counters.
    pub counters: SplitCounters,
}

impl Reassembler {
    /// Abandons the sequence in progress; returns the wire bytes it held.
    pub fn abandon(&mut self) -> u64 {
        let held = self.held_bytes;
        if self.current.take().is_some() {
            self.counters.incomplete += 1;
        }
        self.body.clear();
        self.held_bytes = 0;
        held
    }

    /// Whether a sequence is in progress.
    pub fn in_progress(&self) -> bool {
        self.current.is_some()
    }

    /// Adds a CRC-valid packet that started at stream offset `offset` and took `wire_len` bytes.
    /// Returns what happened and the wire bytes of any abandoned sequence (to count as skipped).
    pub fn push(
        &mut self,
        h: PacketHeader,
        payload: &[u8],
        offset: u64,
        wire_len: u64,
    ) -> (Push, u64) {
        self.counters.packets += 1;
        let mut abandoned = 0;
        if let Some((id, total, next, _)) = self.current {
            if id == h.message_id && total == h.total && next == h.index {
                self.body.extend_from_slice(payload);
                self.held_bytes += wire_len;
                return (self.advance(), 0);
            }
            abandoned = self.abandon();
        }
        if h.index <= 1 && h.index + h.total - 1 <= 15 {
            self.current = Some((h.message_id, h.total, h.index, h.index + h.total - 1));
            self.body.clear();
            self.body.extend_from_slice(payload);
            self.start_offset = offset;
            self.held_bytes = wire_len;
            (self.advance(), abandoned)
        } else {
            self.counters.out_of_order += 1;
            (Push::Dropped, abandoned)
        }
    }

    fn advance(&mut self) -> Push {
        let Some((id, total, next, last)) = self.current else {
            return Push::Dropped;
        };
        if next == last {
            // `held_bytes` is left for the caller to account (all packets of the message).
            self.current = None;
            Push::Complete(std::mem::take(&mut self.body))
        } else {
            self.current = Some((id, total, next + 1, last));
            Push::Pending
        }
    }
}

/// Splits a message body into packets of at most `max_payload` bytes (clamped to 1 ..=
/// [`MAX_PACKET_PAYLOAD`]), numbered from 1. Returns `None` if more than 15 packets would be
/// needed.
pub fn encode_split(body: &[u8], message_id: u8, max_payload: usize) -> Option<Vec<u8>> {
    let max = max_payload.clamp(1, MAX_PACKET_PAYLOAD);
    let chunks: Vec<&[u8]> = body.chunks(max).collect();
    let total = u8::try_from(chunks.len())
        .ok()
        .filter(|&t| (1..=15).contains(&t))?;
    let mut out = Vec::with_capacity(body.len() + chunks.len() * 8);
    for (i, c) in chunks.iter().enumerate() {
        out.push(SYNC);
        let start = out.len();
        out.push(0);
        out.push(message_id);
        out.push(total << 4 | (i as u8 + 1));
        out.extend_from_slice(&(c.len() as u16).to_le_bytes());
        out.extend_from_slice(c);
        let crc = crc16(&out[start..]);
        out.extend_from_slice(&crc.to_be_bytes());
    }
    Some(out)
}
