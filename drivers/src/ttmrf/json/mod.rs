//! TT-Multi-RF JSON protocol (manual 6.6, tables 10, 11, 19, 23, 29, 32, 40, 41).
//!
//! Every message is one JSON object with the common fields `src` (serial number), `ts`
//! (milliseconds since UTC midnight, omitted if unknown) and `ver` (protocol version, 1 in this
//! manual), plus one or more sections: `status`, `adsb`, `uat`, `flarm`, `gnss`, `raw`
//! ([`sections`]). Field order is free, omitted fields are unknown (`None`), unknown fields are
//! ignored (the manual: "Future ICD versions may introduce additional fields without changing the
//! version number").
//!
//! Version rule: "If a breaking change occurs [...] the version number is guaranteed to be
//! incremented." A message with `ver` other than 1 is therefore not interpreted: the decoder
//! counts it in `unsupported_version` and drops it. A message without `ver` is malformed.
//!
//! Framing ([`framing`]): brace matching; a line feed inside an open object cuts it (compact
//! JSON never contains one), so the decoder resynchronises at the next line.

pub mod encode;
pub mod framing;
pub mod sections;

#[cfg(test)]
mod tests;

use bytes::BytesMut;
use serde::{Deserialize, Serialize};

pub use sections::{
    AdsbTarget, FlarmTarget, Gnss, GnssAccuracy, NavModes, RawFrame, Status, TargetFlags,
    UatNicNac, UatStatusFlags, UatTarget,
};

use crate::traffic::limits::{ALT_MAX_M, ALT_MIN_M, SPEED_MAX_MPS, VERTICAL_RATE_MAX_MPS};
use crate::traffic::{AddressType, Link, Protocol, SourceTime, TrafficFlags, TrafficReport};
use crate::ttmrf::csv::aircraft::{FPM_TO_MPS, FT_TO_M, KT_TO_MPS};
use crate::ttmrf::{csv, flarm_category};
use crate::{DecodeStats, DeviceDecoder};
use framing::{ObjectFramer, ObjectStep};

/// The JSON protocol version this module implements.
pub const SUPPORTED_VERSION: u32 = 1;

/// Milliseconds in a day plus one leap second: the largest `ts` accepted.
const MAX_TS_MS: u32 = 86_401_000;

/// Why a JSON message was rejected.
#[derive(Debug, thiserror::Error)]
pub enum JsonError {
    /// Not valid JSON or a field of the wrong type.
    #[error("json message: {0}")]
    Syntax(#[from] serde_json::Error),
    /// `ver` missing.
    #[error("json message without 'ver'")]
    NoVersion,
    /// `ver` other than 1.
    #[error("json protocol version {0} is not supported (expected 1)")]
    Version(u32),
    /// A value outside its documented range.
    #[error("json field {0} out of range")]
    Range(&'static str),
}

/// One JSON message with all its sections.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct JsonMessage {
    /// Serial number of the module.
    #[serde(default)]
    pub src: Option<String>,
    /// Milliseconds since UTC midnight (omitted if unknown).
    #[serde(default, rename(deserialize = "ts"))]
    pub ts_ms: Option<u32>,
    /// Protocol version.
    #[serde(default)]
    pub ver: Option<u32>,
    /// `status` section.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub status: Option<Status>,
    /// `adsb` targets.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub adsb: Vec<AdsbTarget>,
    /// `uat` targets.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub uat: Vec<UatTarget>,
    /// `flarm` targets.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub flarm: Vec<FlarmTarget>,
    /// `gnss` section.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gnss: Option<Gnss>,
    /// `raw` Mode S frames.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub raw: Vec<RawFrame>,
    // --- issue 24 ---
    /// Records (targets, the `gnss` section) dropped from this message for an impossible value;
    /// the decoder adds them to `invalid_values`. Not on the wire.
    #[serde(skip)]
    pub invalid_records: u32,
}

/// Parses one JSON message and applies the version and range rules.
pub fn parse_message(bytes: &[u8]) -> Result<JsonMessage, JsonError> {
    let m: JsonMessage = serde_json::from_slice(bytes)?;
    match m.ver {
        None => return Err(JsonError::NoVersion),
        Some(SUPPORTED_VERSION) => {}
        Some(v) => return Err(JsonError::Version(v)),
    }
    if m.ts_ms.is_some_and(|t| t >= MAX_TS_MS) {
        return Err(JsonError::Range("ts"));
    }
    Ok(drop_invalid_records(m))
}

/// Issue 24: a target (or the `gnss` section) with an impossible value is dropped alone and
/// counted in [`JsonMessage::invalid_records`]; the message's other records are kept.
fn drop_invalid_records(mut m: JsonMessage) -> JsonMessage {
    let n = m.adsb.len() + m.uat.len() + m.flarm.len();
    m.adsb.retain(|a| a.to_traffic(None).check_values().is_ok());
    m.uat.retain(|u| u.to_traffic(None).check_values().is_ok());
    m.flarm
        .retain(|f| f.to_traffic(None).check_values().is_ok());
    let mut dropped = n - (m.adsb.len() + m.uat.len() + m.flarm.len());
    let gnss_ok = |g: &Gnss| {
        let ok = |v: Option<f64>, lo: f64, hi: f64| v.is_none_or(|x| (lo..=hi).contains(&x));
        ok(g.lat_deg, -90.0, 90.0)
            && ok(g.lon_deg, -180.0, 180.0)
            && ok(g.alt_wgs84_m, ALT_MIN_M, ALT_MAX_M)
            && ok(g.velh_kt, 0.0, SPEED_MAX_MPS / KT_TO_MPS)
            && ok(g.track_deg, 0.0, 360.0)
            && ok(g.velv_mps, -VERTICAL_RATE_MAX_MPS, VERTICAL_RATE_MAX_MPS)
    };
    if m.gnss.as_ref().is_some_and(|g| !gnss_ok(g)) {
        m.gnss = None;
        dropped += 1;
    }
    m.invalid_records = u32::try_from(dropped).unwrap_or(u32::MAX);
    m
}

/// Counts a rejected message.
pub(crate) fn count_error(stats: &mut DecodeStats, e: &JsonError) {
    match e {
        JsonError::Version(_) => stats.unsupported_version += 1,
        _ => stats.malformed += 1,
    }
}

impl JsonMessage {
    fn source_time(&self) -> Option<SourceTime> {
        self.ts_ms.map(SourceTime::MsSinceUtcMidnight)
    }

    /// One common traffic report per `adsb`, `uat` and `flarm` target, in that order.
    pub fn traffic_reports(&self) -> Vec<TrafficReport> {
        let t = self.source_time();
        let mut out = Vec::with_capacity(self.adsb.len() + self.uat.len() + self.flarm.len());
        out.extend(self.adsb.iter().map(|a| a.to_traffic(t)));
        out.extend(self.uat.iter().map(|u| u.to_traffic(t)));
        out.extend(self.flarm.iter().map(|f| f.to_traffic(t)));
        out
    }
}

/// A callsign trimmed of padding; empty means unknown.
fn callsign(c: Option<&str>) -> Option<String> {
    c.map(str::trim)
        .filter(|c| !c.is_empty())
        .map(str::to_owned)
}

impl AdsbTarget {
    /// The common traffic report; `time` is the message's `ts`.
    pub fn to_traffic(&self, time: Option<SourceTime>) -> TrafficReport {
        TrafficReport {
            callsign: callsign(self.callsign.as_deref()),
            squawk: self.squawk,
            emitter_category: self.ecat,
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_pressure_m: self.alt_baro_ft.map(|v| v * FT_TO_M),
            alt_geometric_m: self.alt_geo_ft.map(|v| v * FT_TO_M),
            track_deg: self.track_deg,
            heading_deg: self.true_heading_deg,
            ground_speed_mps: self.velh_kt.map(|v| v * KT_TO_MPS),
            vertical_rate_mps: self.velv_fpm.map(|v| v * FPM_TO_MPS),
            nic: self.nic,
            nac_p: self.nac_p,
            nac_v: self.nac_v,
            signal_dbm: self.sig_dbm,
            flags: TrafficFlags {
                on_ground: self.flags.and_then(|f| f.on_ground).unwrap_or(false),
                ..Default::default()
            },
            source_time: time,
            ..TrafficReport::new(Link::Adsb1090, Protocol::Json, self.icao, AddressType::Icao)
        }
    }
}

impl UatTarget {
    /// The common traffic report; `time` is the message's `ts`.
    pub fn to_traffic(&self, time: Option<SourceTime>) -> TrafficReport {
        let nn = self.nicnac.unwrap_or_default();
        let uf = self.uat_flags.unwrap_or_default();
        TrafficReport {
            callsign: callsign(self.callsign.as_deref()),
            squawk: self.squawk,
            emitter_category: self.ecat,
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_pressure_m: self.alt_baro_ft.map(|v| v * FT_TO_M),
            alt_geometric_m: self.alt_geo_ft.map(|v| v * FT_TO_M),
            // A magnetic direction is not passed off as true (as for CSV `#U`).
            track_deg: self.track_deg.filter(|_| uf.heading_magnetic != Some(true)),
            ground_speed_mps: self.velh_kt.map(|v| v * KT_TO_MPS),
            vertical_rate_mps: self.velv_fpm.map(|v| v * FPM_TO_MPS),
            nic: nn.nic,
            nac_p: nn.nac_p,
            nac_v: nn.nac_v,
            signal_dbm: self.sig_dbm,
            emergency_code: self.emergency,
            flags: TrafficFlags {
                on_ground: self.flags.and_then(|f| f.on_ground).unwrap_or(false),
                ident: uf.ident_active.unwrap_or(false),
                emergency: self.emergency.is_some_and(|e| e != 0),
                ..Default::default()
            },
            source_time: time,
            ..TrafficReport::new(Link::Uat978, Protocol::Json, self.icao, AddressType::Icao)
        }
    }
}

impl FlarmTarget {
    /// The common traffic report; `time` is the message's `ts`. Altitude goes to the geometric
    /// altitude, as for CSV `#ALRM` (see [`crate::ttmrf::csv::flarm`]).
    pub fn to_traffic(&self, time: Option<SourceTime>) -> TrafficReport {
        TrafficReport {
            emitter_category: self.aircraft_type.map(flarm_category::emitter_category),
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_geometric_m: self.alt_m,
            track_deg: self.track_deg,
            ground_speed_mps: self.velh_mps,
            vertical_rate_mps: self.velv_mps,
            flarm_alarm_level: self.alarm_level,
            source_time: time,
            ..TrafficReport::new(
                Link::Flarm,
                Protocol::Json,
                self.id & 0xFF_FFFF,
                csv::flarm::address_type(self.id_type),
            )
        }
    }
}

/// Sans-IO decoder of a JSON-only byte stream.
#[derive(Debug, Clone, Default)]
pub struct JsonDecoder {
    framer: ObjectFramer,
    discarding: bool,
    stats: DecodeStats,
}

impl JsonDecoder {
    /// A fresh decoder for the module's compact JSON (a line feed cuts an open object).
    pub fn new() -> Self {
        Self::default()
    }

    /// A decoder that also accepts pretty-printed messages (line feeds inside objects), such as
    /// the manual's examples or hand-edited files. Not for the module's port: see
    /// [`ObjectFramer::multiline`].
    pub fn allowing_newlines() -> Self {
        Self {
            framer: ObjectFramer::multiline(),
            ..Self::default()
        }
    }

    fn step(&mut self, buf: &mut BytesMut, eof: bool) -> Option<Option<JsonMessage>> {
        let out = step_object(
            &mut self.framer,
            &mut self.discarding,
            &mut self.stats,
            buf,
            eof,
        );
        match out {
            Step::Message(m) => Some(Some(*m)),
            Step::Continue => Some(None),
            Step::NeedMore => None,
        }
    }
}

/// Outcome of one framing step (shared with the auto-detecting text decoder).
pub(crate) enum Step {
    Message(Box<JsonMessage>),
    Continue,
    NeedMore,
}

/// One step of JSON framing at the front of `buf`: skips bytes before a `{`, frames the object,
/// parses it and does the accounting.
pub(crate) fn step_object(
    framer: &mut ObjectFramer,
    discarding: &mut bool,
    stats: &mut DecodeStats,
    buf: &mut BytesMut,
    eof: bool,
) -> Step {
    if *discarding {
        match buf.iter().position(|&b| b == b'\n') {
            Some(i) => {
                stats.skip(buf, i + 1);
                *discarding = false;
                // Hand back here: on a port that carries other protocols too (text auto mode,
                // `ttmrf::mixed`), the next line is the caller's to dispatch, not bytes to skip
                // up to the next `{`.
                return Step::Continue;
            }
            None => {
                let n = buf.len();
                stats.skip(buf, n);
                return Step::NeedMore;
            }
        }
    }
    if !framer.in_progress() && buf.first().is_some_and(|&b| b != b'{') {
        let n = buf.iter().position(|&b| b == b'{').unwrap_or(buf.len());
        stats.skip(buf, n);
    }
    if buf.is_empty() {
        return Step::NeedMore;
    }
    match framer.step(buf, eof) {
        ObjectStep::NeedMore => {
            if eof {
                framer.reset();
                stats.malformed += 1;
                let n = buf.len();
                stats.skip(buf, n);
            }
            Step::NeedMore
        }
        ObjectStep::Cut { skip_len } => {
            stats.malformed += 1;
            stats.skip(buf, skip_len);
            Step::Continue
        }
        ObjectStep::TooLong { skip_len } => {
            stats.malformed += 1;
            stats.skip(buf, skip_len);
            *discarding = true;
            Step::Continue
        }
        ObjectStep::Complete {
            object_len,
            frame_len,
        } => match parse_message(&buf[..object_len]) {
            Ok(m) => {
                stats.take_frame(buf, frame_len);
                stats.invalid_values += u64::from(m.invalid_records);
                Step::Message(Box::new(m))
            }
            Err(e) => {
                count_error(stats, &e);
                stats.skip(buf, frame_len);
                Step::Continue
            }
        },
    }
}

impl DeviceDecoder for JsonDecoder {
    type Message = JsonMessage;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<JsonMessage> {
        while let Some(r) = self.step(buf, false) {
            if r.is_some() {
                return r;
            }
        }
        None
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<JsonMessage> {
        while let Some(r) = self.step(buf, true) {
            if r.is_some() {
                return r;
            }
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
