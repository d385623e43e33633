//! The TT-Multi-RF text protocols on one port: CSV (6.4), JSON (6.6), NMEA (9.2.1) and AT lines
//! (4.2, 5), decoded by one [`TextDecoder`].
//!
//! With [`TextMode::Auto`] the protocol is chosen per line by its first byte, which is
//! unambiguous between these protocols: `#` CSV, `{` JSON, `$` NMEA, `AT+` AT. A line starting
//! with `*` is a raw Mode S frame (HEX/HEXd, manual 7.2.2): it is not decoded here (the raw
//! Mode S decoder owns it) and is counted as an unknown type. Anything else (binary protocols,
//! noise, the free-text lines of `AT+HELP`) is skipped as bytes up to the next candidate start.
//! The other modes decode one protocol only, exactly as its own decoder does.
//!
//! ```
//! use vigil_drivers::decode_slice;
//! use vigil_drivers::ttmrf::text::{TextDecoder, TextMode};
//!
//! let port = b"AT+RUN_START\r\n\
//! #A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE\r\n\
//! $GPZDA,201530.00,04,07,2002,00,00*60\r\n";
//! let mut decoder = TextDecoder::new(TextMode::Auto);
//! let messages = decode_slice(&mut decoder, port);
//! assert_eq!(messages.len(), 3);
//! let traffic = messages[1].traffic_reports();
//! assert_eq!(traffic[0].address_hex(), "4D240E");
//! assert_eq!(traffic[0].alt_pressure_m, Some(28550.0 * 0.3048));
//! ```

pub mod line;

use bytes::BytesMut;
use serde::Serialize;

use crate::traffic::TrafficReport;
use crate::ttmrf::at;
use crate::ttmrf::at::{AtDecoder, AtResponse};
use crate::ttmrf::csv::{self, CsvDecoder, CsvMessage};
use crate::ttmrf::json::framing::ObjectFramer;
use crate::ttmrf::json::{self, JsonDecoder, JsonMessage, Step};
use crate::ttmrf::nmea::{self, NmeaDecoder, NmeaSentence};
use crate::{DecodeStats, DeviceDecoder};
use line::{LineFramer, LineStep};

/// Which protocols the port carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TextMode {
    /// Detect per line.
    Auto,
    /// CSV only.
    Csv,
    /// JSON only.
    Json,
    /// NMEA only.
    Nmea,
    /// AT responses only (CONFIGURATION / BOOTLOADER sessions, including free text).
    At,
}

/// One decoded text message.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "protocol", rename_all = "snake_case")]
pub enum TextMessage {
    /// A CSV line.
    Csv(CsvMessage),
    /// A JSON message.
    Json(Box<JsonMessage>),
    /// An NMEA sentence.
    Nmea(NmeaSentence),
    /// An AT line.
    At(AtResponse),
}

impl TextMessage {
    /// The traffic reports this message carries (none, one, or one per JSON target).
    pub fn traffic_reports(&self) -> Vec<TrafficReport> {
        match self {
            TextMessage::Csv(m) => m.to_traffic().into_iter().collect(),
            TextMessage::Json(m) => m.traffic_reports(),
            _ => Vec::new(),
        }
    }
}

/// Messages decoded per protocol (auto mode diagnostics).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct ProtocolCounts {
    /// CSV lines.
    pub csv: u64,
    /// JSON messages.
    pub json: u64,
    /// NMEA sentences.
    pub nmea: u64,
    /// AT lines.
    pub at: u64,
    /// Raw Mode S lines: passed over by [`TextDecoder`], decoded by
    /// [`crate::ttmrf::mixed::MixedDecoder`].
    pub raw_mode_s: u64,
}

#[derive(Debug, Clone)]
enum Inner {
    Auto(Box<Auto>),
    Csv(CsvDecoder),
    Json(JsonDecoder),
    Nmea(NmeaDecoder),
    At(AtDecoder),
}

/// The auto-mode state machine; also driven by [`crate::ttmrf::mixed::MixedDecoder`], which hands
/// it the text lines of a port that carries raw HEX lines too.
#[derive(Debug, Clone, Default)]
pub(crate) struct Auto {
    lines: LineFramer,
    object: ObjectFramer,
    object_discarding: bool,
    pub(crate) stats: DecodeStats,
    pub(crate) counts: ProtocolCounts,
}

/// Longest line in auto mode (the longest of the line protocols).
const MAX_LINE: usize = at::response::MAX_LINE;

#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    Csv,
    Nmea,
    At,
    Raw,
}

/// Bytes that may start a message in auto mode.
fn is_start(b: u8) -> bool {
    matches!(b, b'#' | b'$' | b'{' | b'A' | b'*')
}

impl Auto {
    /// Whether a message (JSON object) or an over-long line is in progress: the next bytes belong
    /// to it whatever they look like.
    pub(crate) fn busy(&self) -> bool {
        self.object.in_progress() || self.object_discarding || self.lines.is_discarding()
    }

    /// One step: `None` = need more bytes, `Some(None)` = bytes consumed (skipped) without a
    /// message, `Some(Some(m))` = a message.
    pub(crate) fn step(&mut self, buf: &mut BytesMut, eof: bool) -> Option<Option<TextMessage>> {
        if self.object.in_progress() || self.object_discarding {
            return self.json(buf, eof);
        }
        if !self.lines.is_discarding() {
            let first = *buf.first()?;
            match first {
                b'{' => return self.json(buf, eof),
                b'#' | b'$' | b'*' => {}
                b'A' => {
                    let n = buf.len().min(3);
                    if buf[..n] != b"AT+"[..n] {
                        self.stats.skip(buf, 1);
                        return Some(None);
                    }
                    if n < 3 {
                        if eof {
                            self.stats.skip(buf, n);
                            return Some(None);
                        }
                        return None;
                    }
                }
                _ => {
                    let n = buf.iter().position(|&b| is_start(b)).unwrap_or(buf.len());
                    self.stats.skip(buf, n.max(1));
                    return Some(None);
                }
            }
        }
        let kind = match buf.first() {
            Some(b'#') => Kind::Csv,
            Some(b'$') => Kind::Nmea,
            Some(b'*') => Kind::Raw,
            _ => Kind::At,
        };
        let (frame_len, content_len) = match self.lines.next_line(buf, &mut self.stats, MAX_LINE) {
            LineStep::Skipped => return Some(None),
            LineStep::Line {
                frame_len,
                content_len,
            } => (frame_len, content_len),
            LineStep::NeedMore => {
                if !eof || buf.is_empty() {
                    return None;
                }
                if self.lines.is_discarding() || buf.len() > MAX_LINE {
                    let n = buf.len();
                    self.stats.skip(buf, n);
                    return None;
                }
                // The last line of the stream, without its terminator.
                self.lines.reset();
                let len = buf.len();
                (len, if buf.ends_with(b"\r") { len - 1 } else { len })
            }
        };
        let content = &buf[..content_len];
        let result = match kind {
            Kind::Csv => csv::parse_line(content)
                .map(TextMessage::Csv)
                .map_err(|e| csv::count_error(&mut self.stats, &e)),
            Kind::Nmea => nmea::parse_sentence(content)
                .map(TextMessage::Nmea)
                .map_err(|e| nmea::count_error(&mut self.stats, &e)),
            Kind::At => at::parse_response(content)
                .map(TextMessage::At)
                .ok_or_else(|| self.stats.malformed += 1),
            Kind::Raw => {
                self.counts.raw_mode_s += 1;
                self.stats.unknown_types += 1;
                Err(())
            }
        };
        match result {
            Ok(m) => {
                self.stats.take_frame(buf, frame_len);
                match &m {
                    TextMessage::Csv(_) => self.counts.csv += 1,
                    TextMessage::Nmea(_) => self.counts.nmea += 1,
                    TextMessage::At(_) => self.counts.at += 1,
                    TextMessage::Json(_) => self.counts.json += 1,
                }
                Some(Some(m))
            }
            Err(()) => {
                self.stats.skip(buf, frame_len);
                Some(None)
            }
        }
    }

    fn json(&mut self, buf: &mut BytesMut, eof: bool) -> Option<Option<TextMessage>> {
        match json::step_object(
            &mut self.object,
            &mut self.object_discarding,
            &mut self.stats,
            buf,
            eof,
        ) {
            Step::Message(m) => {
                self.counts.json += 1;
                Some(Some(TextMessage::Json(m)))
            }
            Step::Continue => Some(None),
            Step::NeedMore => None,
        }
    }
}

/// Sans-IO decoder of the text protocols of one port.
#[derive(Debug, Clone)]
pub struct TextDecoder {
    inner: Inner,
}

impl TextDecoder {
    /// A decoder for `mode`.
    pub fn new(mode: TextMode) -> Self {
        let inner = match mode {
            TextMode::Auto => Inner::Auto(Box::default()),
            TextMode::Csv => Inner::Csv(CsvDecoder::new()),
            TextMode::Json => Inner::Json(JsonDecoder::new()),
            TextMode::Nmea => Inner::Nmea(NmeaDecoder::new()),
            TextMode::At => Inner::At(AtDecoder::new()),
        };
        Self { inner }
    }

    /// Messages per protocol (auto mode; the single-protocol modes count frames in the stats).
    pub fn counts(&self) -> ProtocolCounts {
        match &self.inner {
            Inner::Auto(a) => a.counts,
            _ => ProtocolCounts::default(),
        }
    }

    fn step_auto(a: &mut Auto, buf: &mut BytesMut, eof: bool) -> Option<TextMessage> {
        while let Some(r) = a.step(buf, eof) {
            if r.is_some() {
                return r;
            }
        }
        None
    }
}

impl DeviceDecoder for TextDecoder {
    type Message = TextMessage;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<TextMessage> {
        match &mut self.inner {
            Inner::Auto(a) => Self::step_auto(a, buf, false),
            Inner::Csv(d) => d.decode(buf).map(TextMessage::Csv),
            Inner::Json(d) => d.decode(buf).map(|m| TextMessage::Json(Box::new(m))),
            Inner::Nmea(d) => d.decode(buf).map(TextMessage::Nmea),
            Inner::At(d) => d.decode(buf).map(TextMessage::At),
        }
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<TextMessage> {
        match &mut self.inner {
            Inner::Auto(a) => {
                let m = Self::step_auto(a, buf, true);
                if m.is_none() {
                    let n = buf.len();
                    a.stats.skip(buf, n);
                }
                m
            }
            Inner::Csv(d) => d.decode_eof(buf).map(TextMessage::Csv),
            Inner::Json(d) => d.decode_eof(buf).map(|m| TextMessage::Json(Box::new(m))),
            Inner::Nmea(d) => d.decode_eof(buf).map(TextMessage::Nmea),
            Inner::At(d) => d.decode_eof(buf).map(TextMessage::At),
        }
    }

    fn stats(&self) -> &DecodeStats {
        match &self.inner {
            Inner::Auto(a) => &a.stats,
            Inner::Csv(d) => d.stats(),
            Inner::Json(d) => d.stats(),
            Inner::Nmea(d) => d.stats(),
            Inner::At(d) => d.stats(),
        }
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        match &mut self.inner {
            Inner::Auto(a) => &mut a.stats,
            Inner::Csv(d) => d.stats_mut(),
            Inner::Json(d) => d.stats_mut(),
            Inner::Nmea(d) => d.stats_mut(),
            Inner::At(d) => d.stats_mut(),
        }
    }
}

#[cfg(test)]
mod tests;
