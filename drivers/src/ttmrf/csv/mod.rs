//! TT-Multi-RF CSV protocol "AERO" (manual 6.4, 6.7.1, 7.2.1, 7.2.3, 8.2.1, 8.2.2, 10.2.1).
//!
//! Every message is one line `#TAG:field,field,...,CRC\r\n`. The CRC (see [`crc`]) covers the
//! bytes from `#` to the last comma, excluded. The manual promises that later firmware may add
//! fields just before the CRC, "guaranteed to be at the end of message": the CRC is therefore
//! always taken from the last field, and fields beyond the documented ones are kept verbatim.
//!
//! | tag | message | CRC |
//! |---|---|---|
//! | `#A` | ADS-B aircraft ([`AdsbAircraft`]) | yes |
//! | `#U` | UAT aircraft ([`UatAircraft`]) | yes |
//! | `#ALRM` | FLARM aircraft ([`FlarmAircraft`]) | not documented: parsed without |
//! | `#S` | system statistics ([`SystemStats`]) | yes |
//! | `#AS` | ADS-B statistics ([`AdsbStats`]) | yes |
//! | `#FS` | FLARM statistics ([`FlarmStats`]) | not documented: parsed without |
//!
//! Empty fields mean "unknown" and decode to `None`, never zero. A line whose CRC verifies but
//! whose fields do not parse (or are out of range) is dropped and counted as malformed; a line of
//! another tag (RID, sensors: listed in 6.4 but not specified) is counted as an unknown type.
//! Bytes before a `#` (other protocols, noise) are skipped and counted as skipped bytes.

pub mod aircraft;
pub mod crc;
pub mod fields;
pub mod flarm;
pub mod stats;

#[cfg(test)]
mod tests;

use serde::Serialize;

pub use aircraft::{AdsbAircraft, AircraftFlags, AircraftState, NicNac, UatAircraft, UatFlags};
pub use flarm::FlarmAircraft;
pub use stats::{AdsbStats, FlarmStats, SystemStats};

use crate::DecodeStats;
use crate::traffic::TrafficReport;
use crate::ttmrf::text::line::{LineDecoder, LineProtocol};
use fields::Fields;

/// Longest CSV line accepted, bytes without terminator. A full `#A` line is about 110 bytes;
/// the margin leaves room for the future fields the manual announces.
pub const MAX_LINE: usize = 512;

/// Most fields accepted in one line (documented lines have up to 20, plus future ones).
pub const MAX_FIELDS: usize = 64;

/// Why a CSV line was rejected (the decoder counts these; [`parse_line`] returns them).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CsvError {
    /// The line does not start with `#TAG:`.
    #[error("csv line does not start with '#TAG:'")]
    NoTag,
    /// A tag this decoder does not know.
    #[error("unknown csv message tag '{0}'")]
    UnknownType(String),
    /// The CRC field is missing or is not hexadecimal.
    #[error("csv #{tag}: missing or malformed crc field")]
    BadCrcField {
        /// Message tag.
        tag: &'static str,
    },
    /// The CRC does not match the line.
    #[error("csv #{tag}: crc {got:04X} does not match computed {computed:04X}")]
    Checksum {
        /// Message tag.
        tag: &'static str,
        /// CRC in the line.
        got: u16,
        /// CRC computed over the line.
        computed: u16,
    },
    /// Fewer fields than the message documents (or more than [`MAX_FIELDS`]).
    #[error("csv #{tag}: {got} fields, expected at least {expected}")]
    FieldCount {
        /// Message tag.
        tag: &'static str,
        /// Documented number of data fields.
        expected: usize,
        /// Number present.
        got: usize,
    },
    /// A field that does not parse or is out of range.
    #[error("csv field {name}: bad value '{value}'")]
    Field {
        /// Field name as in the manual.
        name: &'static str,
        /// The offending text.
        value: String,
    },
    /// Not ASCII/UTF-8 text.
    #[error("csv line is not text")]
    NotText,
    /// An aircraft record with an impossible value (issue 24): dropped alone, counted in
    /// `invalid_values`.
    #[error("csv aircraft record: {0}")]
    InvalidValue(crate::traffic::InvalidValue),
}

impl CsvError {
    /// A field error.
    pub fn field(name: &'static str, value: &str) -> Self {
        CsvError::Field {
            name,
            value: value.chars().take(32).collect(),
        }
    }
}

/// One decoded CSV message.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum CsvMessage {
    /// `#A`.
    Adsb(AdsbAircraft),
    /// `#U`.
    Uat(UatAircraft),
    /// `#ALRM`.
    Flarm(FlarmAircraft),
    /// `#S`.
    SystemStats(SystemStats),
    /// `#AS`.
    AdsbStats(AdsbStats),
    /// `#FS`.
    FlarmStats(FlarmStats),
}

/// Known tags: (tag, carries a CRC).
const TAGS: [(&str, bool); 6] = [
    ("A", true),
    ("U", true),
    ("ALRM", false),
    ("S", true),
    ("AS", true),
    ("FS", false),
];

impl CsvMessage {
    /// The line tag without `#`.
    pub fn tag(&self) -> &'static str {
        match self {
            CsvMessage::Adsb(_) => "A",
            CsvMessage::Uat(_) => "U",
            CsvMessage::Flarm(_) => "ALRM",
            CsvMessage::SystemStats(_) => "S",
            CsvMessage::AdsbStats(_) => "AS",
            CsvMessage::FlarmStats(_) => "FS",
        }
    }

    /// The common traffic report, for the aircraft messages.
    pub fn to_traffic(&self) -> Option<TrafficReport> {
        match self {
            CsvMessage::Adsb(m) => Some(m.to_traffic()),
            CsvMessage::Uat(m) => Some(m.to_traffic()),
            CsvMessage::Flarm(m) => Some(m.to_traffic()),
            _ => None,
        }
    }

    /// Encodes the message as the module sends it: `#TAG:fields[,CRC]\r\n` (the CRC only for the
    /// tags that have one). Used by the simulator and the round-trip tests.
    pub fn to_line(&self) -> String {
        let mut line = String::with_capacity(128);
        line.push('#');
        line.push_str(self.tag());
        line.push(':');
        match self {
            CsvMessage::Adsb(m) => m.write_fields(&mut line),
            CsvMessage::Uat(m) => m.write_fields(&mut line),
            CsvMessage::Flarm(m) => m.write_fields(&mut line),
            CsvMessage::SystemStats(m) => m.write_fields(&mut line),
            CsvMessage::AdsbStats(m) => m.write_fields(&mut line),
            CsvMessage::FlarmStats(m) => m.write_fields(&mut line),
        }
        if has_crc(self.tag()) {
            let crc = crc::csv_crc(line.as_bytes());
            line.push_str(&format!(",{crc:04X}"));
        }
        line.push_str("\r\n");
        line
    }
}

fn has_crc(tag: &str) -> bool {
    TAGS.iter().any(|(t, c)| *t == tag && *c)
}

/// Parses one CSV line (without its `\r\n`), verifying the CRC where the message has one.
pub fn parse_line(line: &[u8]) -> Result<CsvMessage, CsvError> {
    parse_line_inner(line, true)
}

/// Parses one CSV line without verifying its CRC (for diagnosing captures whose CRC is known to
/// be damaged, such as OCR'd manual examples). The CRC field must still be present.
pub fn parse_line_unchecked(line: &[u8]) -> Result<CsvMessage, CsvError> {
    parse_line_inner(line, false)
}

fn parse_line_inner(line: &[u8], verify: bool) -> Result<CsvMessage, CsvError> {
    let rest = line.strip_prefix(b"#").ok_or(CsvError::NoTag)?;
    let colon = rest
        .iter()
        .take(9)
        .position(|&b| b == b':')
        .ok_or(CsvError::NoTag)?;
    let tag_bytes = &rest[..colon];
    let Some(&(tag, crc_present)) = TAGS.iter().find(|(t, _)| t.as_bytes() == tag_bytes) else {
        return Err(CsvError::UnknownType(
            String::from_utf8_lossy(tag_bytes).into_owned(),
        ));
    };
    let data_start = 1 + colon + 1;
    let data: &[u8] = if crc_present {
        let comma = line
            .iter()
            .rposition(|&b| b == b',')
            .filter(|&c| c >= data_start)
            .ok_or(CsvError::BadCrcField { tag })?;
        let crc_text = std::str::from_utf8(&line[comma + 1..])
            .map_err(|_| CsvError::BadCrcField { tag })?
            .trim_matches([' ', '\t']);
        let got = fields::parse_hex(crc_text, 4).ok_or(CsvError::BadCrcField { tag })? as u16;
        let computed = crc::csv_crc(&line[..comma]);
        if verify && got != computed {
            return Err(CsvError::Checksum { tag, got, computed });
        }
        &line[data_start..comma]
    } else {
        &line[data_start..]
    };
    let text = std::str::from_utf8(data).map_err(|_| CsvError::NotText)?;
    // Fields go into a stack array: no allocation per line. No documented line has more than
    // 20 fields; more than MAX_FIELDS is malformed.
    let mut split = [""; MAX_FIELDS];
    let mut n = 0;
    for part in text.split(',') {
        let slot = split.get_mut(n).ok_or(CsvError::FieldCount {
            tag,
            expected: MAX_FIELDS,
            got: n + 1,
        })?;
        *slot = part;
        n += 1;
    }
    let f = Fields::new(&split[..n]);
    let m = match tag {
        "A" => CsvMessage::Adsb(AdsbAircraft::parse(&f)?),
        "U" => CsvMessage::Uat(UatAircraft::parse(&f)?),
        "ALRM" => CsvMessage::Flarm(FlarmAircraft::parse(&f)?),
        "S" => CsvMessage::SystemStats(SystemStats::parse(&f)?),
        "AS" => CsvMessage::AdsbStats(AdsbStats::parse(&f)?),
        _ => CsvMessage::FlarmStats(FlarmStats::parse(&f)?),
    };
    // Issue 24: an aircraft line whose values are impossible is one record, dropped alone.
    if let Some(r) = m.to_traffic() {
        r.check_values().map_err(CsvError::InvalidValue)?;
    }
    Ok(m)
}

/// Counts a rejected line in the decoder counters.
pub(crate) fn count_error(stats: &mut DecodeStats, e: &CsvError) {
    match e {
        CsvError::Checksum { .. } | CsvError::BadCrcField { .. } => stats.checksum_failures += 1,
        CsvError::UnknownType(_) => stats.unknown_types += 1,
        CsvError::InvalidValue(_) => stats.invalid_values += 1,
        _ => stats.malformed += 1,
    }
}

/// Sans-IO decoder of a CSV ("AERO") line stream: lines start with `#`.
pub type CsvDecoder = LineDecoder<CsvLines>;

/// The CsvLines line protocol for [`LineDecoder`].
#[derive(Debug, Clone, Copy, Default)]
pub struct CsvLines;

impl LineProtocol for CsvLines {
    type Message = CsvMessage;
    const START: Option<u8> = Some(b'#');
    const MAX_LINE: usize = MAX_LINE;

    fn parse(content: &[u8], stats: &mut DecodeStats) -> Option<CsvMessage> {
        parse_line(content).map_err(|e| count_error(stats, &e)).ok()
    }
}
