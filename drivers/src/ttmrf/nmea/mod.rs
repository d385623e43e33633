//! NMEA 0183 sentences from the module's GNSS receiver (manual 9.1 table 31:
//! `GNSS_RX_PROTOCOL_RAW=5`; 9.2.1 refers to the receiver's documentation), for the ownship
//! fallback and the UTC date: GGA, RMC, VTG, GSA, ZDA of any talker (GP, GN, GL, GA, BD ...).
//!
//! A sentence is `$TTSSS,f1,f2,...*HH\r\n` where `HH` is the XOR of every byte between `$` and `*`
//! in hexadecimal. The checksum is required and verified (checksum_failures). A verified sentence
//! of another type is counted as an unknown type; one whose fields do not parse as malformed.
//! A small parser of our own is used rather than the `nmea` crate: five sentences, the house
//! accounting rules, and no dependency.

pub mod encode;
pub mod sentences;

#[cfg(test)]
mod tests;

use serde::Serialize;

pub use sentences::{Date, Gga, Gsa, Rmc, Vtg, Zda};

use crate::DecodeStats;
use crate::ttmrf::text::line::{LineDecoder, LineProtocol};

/// Longest sentence accepted (NMEA allows 82 bytes; receivers exceed it, e.g. NMEA 4.1 GSA).
pub const MAX_LINE: usize = 256;

/// Why a sentence was rejected.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NmeaError {
    /// No `$`, no `*HH`, or not text.
    #[error("nmea: not a sentence")]
    Framing,
    /// The checksum does not match.
    #[error("nmea: checksum {got:02X} does not match computed {computed:02X}")]
    Checksum {
        /// Checksum in the sentence.
        got: u8,
        /// Computed checksum.
        computed: u8,
    },
    /// A sentence type this module does not decode.
    #[error("nmea: sentence type {0} not decoded")]
    UnknownType(String),
    /// A field that does not parse or is out of range.
    #[error("nmea: bad {0} field")]
    Field(&'static str),
    /// A fix whose value is impossible for physics (issue 24): the sentence (one record) is
    /// dropped alone and counted in `invalid_values`.
    #[error("nmea: impossible {0}")]
    InvalidValue(&'static str),
}

/// The decoded body of a sentence.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "sentence", rename_all = "UPPERCASE")]
pub enum NmeaBody {
    /// GGA fix data.
    Gga(Gga),
    /// RMC recommended minimum.
    Rmc(Rmc),
    /// VTG course and speed.
    Vtg(Vtg),
    /// GSA DOP and satellites.
    Gsa(Gsa),
    /// ZDA date and time.
    Zda(Zda),
}

/// One decoded sentence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct NmeaSentence {
    /// Talker id (GP, GN, GL, GA, BD ...).
    pub talker: String,
    /// The sentence.
    #[serde(flatten)]
    pub body: NmeaBody,
}

/// XOR checksum of the bytes between `$` and `*`.
pub fn checksum(body: &[u8]) -> u8 {
    body.iter().fold(0, |a, b| a ^ b)
}

/// Parses one sentence (without line end), verifying the checksum.
pub fn parse_sentence(line: &[u8]) -> Result<NmeaSentence, NmeaError> {
    let rest = line.strip_prefix(b"$").ok_or(NmeaError::Framing)?;
    let star = rest
        .iter()
        .rposition(|&b| b == b'*')
        .ok_or(NmeaError::Framing)?;
    let (body, cs) = (&rest[..star], &rest[star + 1..]);
    let cs = std::str::from_utf8(cs).map_err(|_| NmeaError::Framing)?;
    if cs.len() != 2 {
        return Err(NmeaError::Framing);
    }
    let got = u8::from_str_radix(cs, 16).map_err(|_| NmeaError::Framing)?;
    let computed = checksum(body);
    if got != computed {
        return Err(NmeaError::Checksum { got, computed });
    }
    let text = std::str::from_utf8(body).map_err(|_| NmeaError::Framing)?;
    let fields: Vec<&str> = text.split(',').collect();
    let address = fields.first().copied().unwrap_or("");
    if address.len() != 5 || !address.is_ascii() {
        return Err(NmeaError::UnknownType(address.chars().take(8).collect()));
    }
    let (talker, kind) = address.split_at(2);
    let f = sentences::F(fields.get(1..).unwrap_or(&[]));
    let body = match kind {
        "GGA" => NmeaBody::Gga(Gga::parse(&f)?),
        "RMC" => NmeaBody::Rmc(Rmc::parse(&f)?),
        "VTG" => NmeaBody::Vtg(Vtg::parse(&f)?),
        "GSA" => NmeaBody::Gsa(Gsa::parse(&f)?),
        "ZDA" => NmeaBody::Zda(Zda::parse(&f)?),
        _ => return Err(NmeaError::UnknownType(address.to_owned())),
    };
    check_values(&body)?;
    Ok(NmeaSentence {
        talker: talker.to_owned(),
        body,
    })
}

/// Issue 24: physics ranges of a fix (the parser already bounds latitude and longitude):
/// altitude and geoid separation, speed not negative and within the traffic limits, course
/// within 0..360, HDOP not negative.
fn check_values(body: &NmeaBody) -> Result<(), NmeaError> {
    use crate::traffic::limits::{ALT_MAX_M, ALT_MIN_M, SPEED_MAX_MPS};
    let ok = |v: Option<f64>, lo: f64, hi: f64, name| match v {
        Some(x) if !(lo..=hi).contains(&x) => Err(NmeaError::InvalidValue(name)),
        _ => Ok(()),
    };
    let max_kt = SPEED_MAX_MPS * 3600.0 / 1852.0;
    match body {
        NmeaBody::Gga(g) => {
            ok(g.alt_msl_m, ALT_MIN_M, ALT_MAX_M, "altitude")?;
            ok(g.geoid_sep_m, -200.0, 200.0, "geoid separation")?;
            ok(g.hdop, 0.0, 100.0, "hdop")
        }
        NmeaBody::Rmc(r) => {
            ok(r.speed_kt, 0.0, max_kt, "speed")?;
            ok(r.course_deg, 0.0, 360.0, "course")
        }
        NmeaBody::Vtg(v) => {
            ok(v.speed_kt, 0.0, max_kt, "speed")?;
            ok(v.course_true_deg, 0.0, 360.0, "course")
        }
        _ => Ok(()),
    }
}

/// Counts a rejected sentence.
pub(crate) fn count_error(stats: &mut DecodeStats, e: &NmeaError) {
    match e {
        NmeaError::Checksum { .. } => stats.checksum_failures += 1,
        NmeaError::UnknownType(_) => stats.unknown_types += 1,
        NmeaError::InvalidValue(_) => stats.invalid_values += 1,
        _ => stats.malformed += 1,
    }
}

/// Sans-IO decoder of an NMEA sentence stream: sentences start with `$`.
pub type NmeaDecoder = LineDecoder<NmeaLines>;

/// The NmeaLines line protocol for [`LineDecoder`].
#[derive(Debug, Clone, Copy, Default)]
pub struct NmeaLines;

impl LineProtocol for NmeaLines {
    type Message = NmeaSentence;
    const START: Option<u8> = Some(b'$');
    const MAX_LINE: usize = MAX_LINE;

    fn parse(content: &[u8], stats: &mut DecodeStats) -> Option<NmeaSentence> {
        parse_sentence(content)
            .map_err(|e| count_error(stats, &e))
            .ok()
    }
}
