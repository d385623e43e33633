//! Decoder counters: what was decoded and what was skipped, and why.

use bytes::{Buf, BytesMut};
use serde::Serialize;

/// Counters every device decoder keeps. Nothing a decoder discards goes uncounted.
///
/// Byte accounting holds at every point: `bytes_consumed` = bytes of decoded frames + `bytes_skipped`,
/// and `bytes_consumed` never exceeds the bytes fed in (the rest waits in the buffer for more input).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct DecodeStats {
    /// Bytes removed from the input buffer so far (decoded frames and skipped bytes).
    pub bytes_consumed: u64,
    /// Bytes discarded while searching for a frame (garbage, bad frames, unknown types).
    pub bytes_skipped: u64,
    /// Messages decoded and handed out.
    pub frames_decoded: u64,
    /// Candidate frames whose checksum did not verify.
    pub checksum_failures: u64,
    /// Frames with a valid structure (and checksum where the type's length is known) but a message
    /// type the decoder does not know.
    pub unknown_types: u64,
    /// Frames whose checksum verified (or that have none) but whose fields are out of range or
    /// badly formed.
    pub malformed: u64,
    /// Frames of a protocol version the decoder does not support.
    pub unsupported_version: u64,
    /// Stream offset (in `bytes_consumed` units) of the first byte of the last decoded message.
    #[serde(skip)]
    pub last_frame_start: u64,
    // --- issue 24 ---
    /// Records dropped alone because a value was impossible for the protocol or for physics
    /// (e.g. latitude 95 deg, negative ground speed); their message's other records are kept.
    pub invalid_values: u64,
}

impl DecodeStats {
    /// Discards `n` bytes from the front of `buf` as skipped input.
    ///
    /// `n` is clamped to the buffer length, so a caller's arithmetic slip cannot panic here.
    #[inline]
    pub fn skip(&mut self, buf: &mut BytesMut, n: usize) {
        let n = n.min(buf.len());
        buf.advance(n);
        self.bytes_skipped += n as u64;
        self.bytes_consumed += n as u64;
    }

    /// Removes a frame of `len` bytes from the front of `buf` that produced a message, and records
    /// its start offset in [`DecodeStats::last_frame_start`].
    #[inline]
    pub fn take_frame(&mut self, buf: &mut BytesMut, len: usize) {
        let len = len.min(buf.len());
        self.last_frame_start = self.bytes_consumed;
        buf.advance(len);
        self.bytes_consumed += len as u64;
        self.frames_decoded += 1;
    }

    /// Records a decoded message that was built from bytes already consumed (for example the last
    /// part of a split packet), whose first byte was at stream offset `start`.
    #[inline]
    pub fn count_reassembled(&mut self, start: u64) {
        self.last_frame_start = start;
        self.frames_decoded += 1;
    }

    /// Adds another decoder's counters to these (used where one port carries several protocols).
    pub fn absorb(&mut self, other: &DecodeStats) {
        self.bytes_consumed += other.bytes_consumed;
        self.bytes_skipped += other.bytes_skipped;
        self.frames_decoded += other.frames_decoded;
        self.checksum_failures += other.checksum_failures;
        self.unknown_types += other.unknown_types;
        self.malformed += other.malformed;
        self.unsupported_version += other.unsupported_version;
        self.invalid_values += other.invalid_values;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accounting_adds_up() {
        let mut s = DecodeStats::default();
        let mut buf = BytesMut::from(&b"xxFRAMEyy"[..]);
        s.skip(&mut buf, 2);
        s.take_frame(&mut buf, 5);
        assert_eq!(&buf[..], b"yy");
        assert_eq!(s.last_frame_start, 2);
        assert_eq!(s.bytes_consumed, 7);
        assert_eq!(s.bytes_skipped, 2);
        assert_eq!(s.frames_decoded, 1);
        // Over-long requests are clamped, not a panic.
        s.skip(&mut buf, 100);
        assert!(buf.is_empty());
        assert_eq!(s.bytes_consumed, 9);
    }
}
