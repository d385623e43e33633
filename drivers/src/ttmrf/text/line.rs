//! Line framing shared by the TT-Multi-RF text protocols (CSV, NMEA, AT responses).
//!
//! The module ends every text line with `\r\n` (manual 6.4); a lone `\n` is accepted too and a
//! trailing `\r` is stripped. The framer remembers how far it has searched, so feeding a long line
//! one byte at a time stays linear, and it bounds the line length: a candidate longer than `max`
//! bytes is discarded up to its end of line and counted once as malformed.

use bytes::BytesMut;

use crate::DecodeStats;

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
