//! The TT-Multi-RF main UART as the host sees it with a text protocol and raw HEX output both on:
//! text lines (CSV 6.4, JSON 6.6, NMEA 9.2.1, AT 4.2 / 5) interleaved with raw HEX / HEXd / AVR
//! lines (7.2.2, 10.2.2). The manual gives the module one UART (2.2.4, "Main UART"), so every
//! enabled output shares it: one [`MixedDecoder`] reads the whole port in stream order.
//!
//! Dispatch is by the first byte of each message, which is unambiguous between the protocols:
//! `#` CSV, `$` NMEA, `{` JSON, `AT+` AT (the text decoder's auto mode, [`TextMode::Auto`]) and
//! `*` / `@` raw lines ([`hex::parse_line`]). Bytes that start none of them are skipped up to the
//! next candidate start. Every byte is counted once in one [`DecodeStats`], so
//! `bytes_consumed` equals the input length at the end of the stream and
//! [`DecodeStats::last_frame_start`] is the offset of each message's first byte in the port's
//! stream (consumers compute a message's wire length as the distance to the next start).
//!
//! Decisions:
//! - A raw line ends at its `\n`. One of `# $ { * @` before that `\n` cannot belong to a raw line
//!   (the HEX alphabet, `;`, `(`, `)`, `,`, `-`, spaces): the raw line was cut (a lost line end),
//!   its bytes up to that start are dropped as malformed and decoding resumes there, so a text or
//!   raw message that follows a damaged raw line is not lost with it. (`A` can be a hex digit, so
//!   an `AT+` line glued to a damaged raw line is lost with it.)
//! - While a JSON object is open (or an over-long text line is being dropped) the bytes belong to
//!   it, whatever they look like, as in the text decoder alone.
//! - A raw line longer than [`hex::MAX_LINE`] without its end is dropped (malformed), so the buffer
//!   stays bounded.
//!
//! [`TextMode::Auto`]: crate::ttmrf::text::TextMode::Auto

use bytes::BytesMut;

use crate::ttmrf::raw::{RawFrame, hex};
use crate::ttmrf::text::{ProtocolCounts, TextMessage};
use crate::{DecodeStats, DeviceDecoder};

use super::text::Auto;

/// One message of the port.
#[derive(Debug, Clone, PartialEq)]
pub enum MixedMessage {
    /// A text message (CSV, JSON, NMEA, AT).
    Text(TextMessage),
    /// A raw HEX / HEXd / AVR frame.
    Raw(RawFrame),
}

/// Sans-IO decoder of a TT-Multi-RF port carrying text protocols and raw HEX lines.
#[derive(Debug, Clone, Default)]
pub struct MixedDecoder {
    text: Box<Auto>,
    /// Bytes of the raw line at the front already searched for its end.
    raw_scanned: usize,
}

// Moved straight out to the caller; boxing it would allocate per message.
#[allow(clippy::large_enum_variant)]
enum Step {
    Message(MixedMessage),
    Continue,
    NeedMore,
}

fn is_text_start(b: u8) -> bool {
    matches!(b, b'#' | b'$' | b'{' | b'A')
}

fn is_raw_start(b: u8) -> bool {
    matches!(b, b'*' | b'@')
}

/// Bytes that never occur inside a raw line but start another message.
fn cuts_raw_line(b: u8) -> bool {
    matches!(b, b'#' | b'$' | b'{' | b'*' | b'@')
}

impl MixedDecoder {
    /// A fresh decoder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Messages decoded per protocol (`raw_mode_s` counts the raw frames decoded).
    pub fn counts(&self) -> ProtocolCounts {
        self.text.counts
    }

    fn step(&mut self, buf: &mut BytesMut, eof: bool) -> Step {
        if self.text.busy() {
            return self.text_step(buf, eof);
        }
        let Some(&first) = buf.first() else {
            return Step::NeedMore;
        };
        if is_raw_start(first) {
            return self.raw_step(buf, eof);
        }
        if is_text_start(first) {
            return self.text_step(buf, eof);
        }
        let n = buf
            .iter()
            .position(|&b| is_text_start(b) || is_raw_start(b))
            .unwrap_or(buf.len());
        self.text.stats.skip(buf, n);
        Step::Continue
    }

    fn text_step(&mut self, buf: &mut BytesMut, eof: bool) -> Step {
        match self.text.step(buf, eof) {
            None => Step::NeedMore,
            Some(None) => Step::Continue,
            Some(Some(m)) => Step::Message(MixedMessage::Text(m)),
        }
    }

    /// The raw line at the front of `buf` (which starts with `*` or `@`).
    fn raw_step(&mut self, buf: &mut BytesMut, eof: bool) -> Step {
        let limit = buf.len().min(hex::MAX_LINE);
        let from = self.raw_scanned.clamp(1, limit.max(1));
        let found = buf
            .get(from..limit)
            .and_then(|w| w.iter().position(|&b| b == b'\n' || cuts_raw_line(b)));
        let stats = &mut self.text.stats;
        match found {
            Some(i) => {
                self.raw_scanned = 0;
                let at = from + i;
                if buf[at] != b'\n' {
                    stats.malformed += 1;
                    stats.skip(buf, at);
                    return Step::Continue;
                }
                match hex::parse_line(&buf[..at]) {
                    Some(f) => {
                        stats.take_frame(buf, at + 1);
                        self.text.counts.raw_mode_s += 1;
                        Step::Message(MixedMessage::Raw(f))
                    }
                    None => {
                        stats.malformed += 1;
                        stats.skip(buf, at + 1);
                        Step::Continue
                    }
                }
            }
            None if limit >= hex::MAX_LINE => {
                self.raw_scanned = 0;
                stats.malformed += 1;
                stats.skip(buf, limit);
                Step::Continue
            }
            None if eof => {
                // The last line of the stream, without its line end.
                self.raw_scanned = 0;
                let n = buf.len();
                match hex::parse_line(&buf[..]) {
                    Some(f) => {
                        stats.take_frame(buf, n);
                        self.text.counts.raw_mode_s += 1;
                        Step::Message(MixedMessage::Raw(f))
                    }
                    None => {
                        stats.malformed += 1;
                        stats.skip(buf, n);
                        Step::Continue
                    }
                }
            }
            None => {
                self.raw_scanned = limit;
                Step::NeedMore
            }
        }
    }
}

impl DeviceDecoder for MixedDecoder {
    type Message = MixedMessage;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<MixedMessage> {
        loop {
            match self.step(buf, false) {
                Step::Message(m) => return Some(m),
                Step::Continue => {}
                Step::NeedMore => return None,
            }
        }
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<MixedMessage> {
        loop {
            match self.step(buf, true) {
                Step::Message(m) => return Some(m),
                Step::Continue => {}
                Step::NeedMore => {
                    // Nothing more can complete: whatever is left is counted as skipped.
                    let n = buf.len();
                    self.text.stats.skip(buf, n);
                    return None;
                }
            }
        }
    }

    fn stats(&self) -> &DecodeStats {
        &self.text.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.text.stats
    }
}

#[cfg(test)]
#[path = "mixed_tests.rs"]
mod tests;
