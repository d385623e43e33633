//! Line framing shared by the TT-Multi-RF text protocols (CSV, NMEA, AT responses).
//!
//! The module ends every text line with `\r\n` (manual 6.4); a lone `\n` is accepted too and a
//! trailing `\r` is stripped. The framer remembers how far it has searched, so feeding a long line
//! one byte at a time stays linear, and it bounds the line length: a candidate longer than `max`
//! bytes is discarded up to its end of line and counted once as malformed.

use std::marker::PhantomData;

use bytes::BytesMut;

use crate::{DecodeStats, DeviceDecoder};

/// One line-oriented protocol: where its lines start and how one parses. [`LineDecoder`] does the
/// framing, resynchronisation and byte accounting for all of them.
pub trait LineProtocol {
    /// The message a line gives.
    type Message;
    /// The byte every line starts with, if the protocol has one: input before it is skipped.
    const START: Option<u8>;
    /// Longest line content, bytes.
    const MAX_LINE: usize;
    /// Parses one line's content (terminator removed). `None` rejects the line; the parser counts
    /// why in `stats` (a line that is simply ignored, such as a blank one, counts nothing).
    fn parse(content: &[u8], stats: &mut DecodeStats) -> Option<Self::Message>;
}

/// The sans-IO decoder of a [`LineProtocol`]: lines ending in `\r\n` or `\n`, bounded length,
/// a last line without terminator still decoded at the end of the stream.
#[derive(Debug, Clone)]
pub struct LineDecoder<P> {
    framer: LineFramer,
    stats: DecodeStats,
    protocol: PhantomData<P>,
}

impl<P> Default for LineDecoder<P> {
    fn default() -> Self {
        Self {
            framer: LineFramer::default(),
            stats: DecodeStats::default(),
            protocol: PhantomData,
        }
    }
}

impl<P: LineProtocol> LineDecoder<P> {
    /// A fresh decoder.
    pub fn new() -> Self {
        Self::default()
    }

    /// The counters (also through [`DeviceDecoder::stats`]).
    pub fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    /// Drops buffered framing state (after a baud change the old bytes are garbage).
    pub fn reset_framing(&mut self) {
        self.framer = LineFramer::default();
    }

    fn finish(
        &mut self,
        buf: &mut BytesMut,
        frame_len: usize,
        content_len: usize,
    ) -> Option<P::Message> {
        match P::parse(&buf[..content_len], &mut self.stats) {
            Some(m) => {
                self.stats.take_frame(buf, frame_len);
                Some(m)
            }
            None => {
                self.stats.skip(buf, frame_len);
                None
            }
        }
    }
}

impl<P: LineProtocol> DeviceDecoder for LineDecoder<P> {
    type Message = P::Message;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<P::Message> {
        loop {
            if let Some(start) = P::START
                && !self.framer.is_discarding()
                && buf.first().is_some_and(|&b| b != start)
            {
                let n = memchr::memchr(start, buf).unwrap_or(buf.len());
                self.stats.skip(buf, n);
                self.framer.reset();
            }
            if buf.is_empty() {
                return None;
            }
            match self.framer.next_line(buf, &mut self.stats, P::MAX_LINE) {
                LineStep::NeedMore => return None,
                LineStep::Skipped => {}
                LineStep::Line {
                    frame_len,
                    content_len,
                } => {
                    if let Some(m) = self.finish(buf, frame_len, content_len) {
                        return Some(m);
                    }
                }
            }
        }
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<P::Message> {
        if let Some(m) = self.decode(buf) {
            return Some(m);
        }
        // A last line without its terminator is still a line.
        if !buf.is_empty() && !self.framer.is_discarding() && buf.len() <= P::MAX_LINE {
            let len = buf.len();
            let content_len = if buf.ends_with(b"\r") { len - 1 } else { len };
            self.framer.reset();
            return self.finish(buf, len, content_len);
        }
        let n = buf.len();
        self.stats.skip(buf, n);
        None
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

/// Result of looking for the next complete line at the front of the buffer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LineStep {
    /// A complete line: `frame_len` bytes including the terminator, `content_len` bytes without
    /// the `\r\n` / `\n` terminator.
    Line {
        /// Bytes to consume, terminator included.
        frame_len: usize,
        /// Bytes of content, terminator excluded.
        content_len: usize,
    },
    /// No complete line yet: wait for more bytes.
    NeedMore,
    /// Bytes of an over-long line were skipped: resynchronise, then ask again.
    Skipped,
}

/// Incremental line finder with a length bound.
#[derive(Debug, Clone, Default)]
pub struct LineFramer {
    /// Bytes at the front of the buffer already searched for `\n`.
    scanned: usize,
    /// Set while discarding the rest of an over-long line.
    discarding: bool,
}

impl LineFramer {
    /// Looks for the next line in `buf`. Over-long input is skipped (and counted) here, so the
    /// caller only sees lines of at most `max` content bytes. After skipping, the framer returns
    /// [`LineStep::Skipped`] so the caller can resynchronise before the next line.
    pub fn next_line(
        &mut self,
        buf: &mut BytesMut,
        stats: &mut DecodeStats,
        max: usize,
    ) -> LineStep {
        if self.discarding {
            self.scanned = 0;
            return match buf.iter().position(|&b| b == b'\n') {
                Some(i) => {
                    stats.skip(buf, i + 1);
                    self.discarding = false;
                    LineStep::Skipped
                }
                None => {
                    let n = buf.len();
                    stats.skip(buf, n);
                    LineStep::NeedMore
                }
            };
        }
        // Only the first `max + 2` bytes matter (content plus "\r\n").
        let limit = buf.len().min(max.saturating_add(2));
        let start = self.scanned.min(limit);
        match buf[start..limit].iter().position(|&b| b == b'\n') {
            Some(i) => {
                let nl = start + i;
                self.scanned = 0;
                let content_len = if nl > 0 && buf[nl - 1] == b'\r' {
                    nl - 1
                } else {
                    nl
                };
                if content_len > max {
                    stats.malformed += 1;
                    stats.skip(buf, nl + 1);
                    return LineStep::Skipped;
                }
                LineStep::Line {
                    frame_len: nl + 1,
                    content_len,
                }
            }
            None if limit >= max.saturating_add(2) => {
                // Over-long: drop it, up to and including its line end.
                stats.malformed += 1;
                self.discarding = true;
                self.scanned = 0;
                LineStep::Skipped
            }
            None => {
                self.scanned = limit;
                LineStep::NeedMore
            }
        }
    }

    /// Forgets the search position (call after the caller removed bytes from the buffer).
    pub fn reset(&mut self) {
        self.scanned = 0;
    }

    /// Whether the framer is discarding the rest of an over-long line.
    pub fn is_discarding(&self) -> bool {
        self.discarding
    }
}

/// Removes ASCII spaces and tabs around a field.
pub fn trim(field: &[u8]) -> &[u8] {
    let start = field
        .iter()
        .position(|b| !matches!(b, b' ' | b'\t'))
        .unwrap_or(field.len());
    let end = field
        .iter()
        .rposition(|b| !matches!(b, b' ' | b'\t'))
        .map_or(start, |i| i + 1);
    field.get(start..end).unwrap_or(&[])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_lines_and_strips_cr() {
        let mut f = LineFramer::default();
        let mut s = DecodeStats::default();
        let mut buf = BytesMut::from(&b"abc\r\nde\nf"[..]);
        assert_eq!(
            f.next_line(&mut buf, &mut s, 10),
            LineStep::Line {
                frame_len: 5,
                content_len: 3
            }
        );
        s.take_frame(&mut buf, 5);
        assert_eq!(
            f.next_line(&mut buf, &mut s, 10),
            LineStep::Line {
                frame_len: 3,
                content_len: 2
            }
        );
        s.take_frame(&mut buf, 3);
        assert_eq!(f.next_line(&mut buf, &mut s, 10), LineStep::NeedMore);
    }

    #[test]
    fn over_long_line_is_dropped_once() {
        let mut f = LineFramer::default();
        let mut s = DecodeStats::default();
        let mut buf = BytesMut::from(&b"0123456789abcdef"[..]);
        assert_eq!(f.next_line(&mut buf, &mut s, 4), LineStep::Skipped);
        assert_eq!(f.next_line(&mut buf, &mut s, 4), LineStep::NeedMore);
        assert!(buf.is_empty());
        buf.extend_from_slice(b"xyz\nok\n");
        assert_eq!(f.next_line(&mut buf, &mut s, 4), LineStep::Skipped);
        assert_eq!(
            f.next_line(&mut buf, &mut s, 4),
            LineStep::Line {
                frame_len: 3,
                content_len: 2
            }
        );
        assert_eq!(s.malformed, 1);
        assert_eq!(s.bytes_skipped, 20);
    }

    #[test]
    fn trims_spaces() {
        assert_eq!(trim(b"  a b \t"), b"a b");
        assert_eq!(trim(b"   "), b"");
        assert_eq!(trim(b""), b"");
    }
}
