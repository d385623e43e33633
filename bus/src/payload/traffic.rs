//! `vigil/traffic` (schema 2): the traffic picture, targets sorted by priority (most urgent first:
//! alert level, then time to loss of well-clear, then range).
//!
//! # On the wire
//!
//! One iceoryx2 sample per picture: a [`TrafficHeader`] as the sample's *user header* and a slice
//! of [`Target`]s as its payload, as long as the picture (`count` targets, at most
//! [`MAX_TARGETS`]). A 10-target picture is a 40-byte header and 10 x 216 bytes, not the fixed
//! 131 KB of schema 1. A C, C++ or Python consumer opens the service with the payload type
//! "slice of `Target`" and the user header `TrafficHeader` (see `bus/include/vigil_bus.h` and
//! `bus/python/`).
//!
//! # Frames and units
//!
//! - Absolute state: WGS-84 latitude and longitude in degrees; pressure altitude (referenced to
//!   1013.25 hPa) and geometric altitude (as reported: above the ellipsoid unless the source says
//!   MSL) in metres; track over ground in degrees true; ground speed m/s; vertical rate m/s, up
//!   positive.
//! - Relative geometry: intruder minus ownship in the local north-east-down (NED) frame of the
//!   ownship: origin at the ownship position the service held at `header.gps_time_ns`, x north and
//!   y east in the plane tangent to the WGS-84 ellipsoid there, z down along its normal. Velocities
//!   are over ground (intruder velocity minus ownship velocity) in the same axes. The down axis
//!   compares the altitudes named by `altitude_kind`.
//!
//! # Unknowns
//!
//! An unknown float is NaN (documented per field); an unknown code is the field's `*_UNKNOWN`
//! constant. Inside vigil these are `Option`s; NaN and 0xFF exist only here, at the wire edge.

use iceoryx2::prelude::ZeroCopySend;
use serde::ser::SerializeStruct;
use serde::{Serialize, Serializer};

use super::{Header, impl_header, ser_text};
use crate::names::Topic;

/// Largest number of targets one picture carries (the slice's maximum length; the service's
/// shared memory is sized for it). More targets than this are not published: the lowest
/// priority ones are dropped and counted in [`TrafficHeader::dropped`].
pub const MAX_TARGETS: usize = 1024;
/// Length of the callsign field, bytes (ADS-B carries 8 characters).
pub const CALLSIGN_LEN: usize = 8;

/// Address type: 24-bit ICAO.
pub const ADDRESS_ICAO: u8 = 0;
/// Address type: non-ICAO ADS-B/UAT address (self-assigned, anonymous).
pub const ADDRESS_NON_ICAO: u8 = 1;
/// Address type: TIS-B track number or other TIS-B address.
pub const ADDRESS_TISB_OTHER: u8 = 2;
/// Address type: FLARM random id.
pub const ADDRESS_FLARM_RANDOM: u8 = 3;
/// Address type: FLARM fixed id.
pub const ADDRESS_FLARM_FIXED: u8 = 4;
/// Address type: surface vehicle or beacon.
pub const ADDRESS_SURFACE: u8 = 5;
/// Address type: not given.
pub const ADDRESS_UNKNOWN: u8 = 0xFF;

/// Alert level: none.
pub const ALERT_NONE: u8 = 0;
/// Alert level: preventive.
pub const ALERT_PREVENTIVE: u8 = 1;
/// Alert level: corrective.
pub const ALERT_CORRECTIVE: u8 = 2;
/// Alert level: warning.
pub const ALERT_WARNING: u8 = 3;

/// Altitude kind of the vertical separation: pressure altitudes compared.
pub const ALTITUDE_PRESSURE: u8 = 0;
/// Altitude kind: geometric altitudes compared.
pub const ALTITUDE_GEOMETRIC: u8 = 1;
/// Altitude kind: intruder altitude unknown (vertical quantities NaN).
pub const ALTITUDE_UNKNOWN: u8 = 2;

/// Plausibility flag: reported ground speed beyond what any aircraft flies.
pub const PLAUSIBILITY_IMPOSSIBLE_SPEED: u8 = 1 << 0;
/// Plausibility flag: a position jump implying an impossible speed.
pub const PLAUSIBILITY_POSITION_JUMP: u8 = 1 << 1;
/// Plausibility flag: an altitude change beyond the vertical-rate limit.
pub const PLAUSIBILITY_ALTITUDE_JUMP: u8 = 1 << 2;
/// Plausibility flag: signal far stronger than the reported range allows.
pub const PLAUSIBILITY_RANGE_VS_SIGNAL: u8 = 1 << 3;
/// Plausibility flag: sources disagree on the position beyond their uncertainty.
pub const PLAUSIBILITY_INCONSISTENT_SOURCES: u8 = 1 << 4;

/// Source bit: 1090 MHz ADS-B (extended squitter, including ADS-R relays).
pub const SOURCE_ADSB: u8 = 1 << 0;
/// Source bit: 978 MHz UAT.
pub const SOURCE_UAT: u8 = 1 << 1;
/// Source bit: FLARM.
pub const SOURCE_FLARM: u8 = 1 << 2;
/// Source bit: TIS-B (ground-radar traffic rebroadcast on 1090 MHz or UAT).
pub const SOURCE_TISB: u8 = 1 << 3;

/// Emitter category: never reported (0 is the standard's "no information", a reported value).
pub const EMITTER_UNKNOWN: u8 = 0xFF;
/// NIC / NACp / NACv / SIL: not reported.
pub const ACCURACY_UNKNOWN: u8 = 0xFF;

/// One target: its absolute state with accuracy, and its geometry relative to the ownship.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Target.v2")]
pub struct Target {
    /// 24-bit address (upper byte 0). JSON: six upper-case hex digits.
    #[serde(serialize_with = "ser_address")]
    pub address: u32,
    /// `ADDRESS_*` code.
    pub address_type: u8,
    /// `ALERT_*` code. JSON: `none`, `preventive`, `corrective` or `warning`.
    #[serde(serialize_with = "ser_alert_level")]
    pub alert_level: u8,
    /// `ALTITUDE_*` code: which altitudes the vertical quantities compare.
    pub altitude_kind: u8,
    /// `PLAUSIBILITY_*` bits; any set bit marks the target suspect.
    pub plausibility_flags: u8,
    /// Callsign, ASCII, NUL-padded (all NUL when unknown).
    #[serde(serialize_with = "ser_text")]
    pub callsign: [u8; CALLSIGN_LEN],
    /// Emitter category, DO-260B / GDL90 numbering (0 no information, 1 light ... 39);
    /// [`EMITTER_UNKNOWN`] when no source reported one.
    pub emitter_category: u8,
    /// `SOURCE_*` bits: the links that reported the target (0: none known).
    pub sources: u8,
    /// Navigation integrity category 0..11 of the newest report that carried one;
    /// [`ACCURACY_UNKNOWN`] when none did.
    pub nic: u8,
    /// Navigation accuracy category for position 0..11 (as `nic`).
    pub nac_p: u8,
    /// Navigation accuracy category for velocity 0..4 (as `nic`).
    pub nac_v: u8,
    /// Source integrity level 0..3 (as `nic`).
    pub sil: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 2],
    /// Fail-safe flags of the target (bits defined by issue 24's traffic unknowns; 0 here).
    pub flags: u32,
    /// Explicit padding (keeps the floats 8-byte aligned); always 0.
    #[serde(skip)]
    pub reserved2: u32,
    /// Latitude extrapolated to `header.gps_time_ns`, deg (WGS-84).
    pub lat_deg: f64,
    /// Longitude extrapolated to `header.gps_time_ns`, deg (WGS-84).
    pub lon_deg: f64,
    /// Pressure altitude (1013.25 hPa), m, extrapolated with the vertical rate; NaN when unknown.
    pub alt_pressure_m: f64,
    /// Geometric altitude, m, extrapolated with the vertical rate; NaN when unknown.
    pub alt_geometric_m: f64,
    /// Track over ground, deg true in [0, 360); NaN without a reported velocity.
    pub track_deg: f64,
    /// Ground speed, m/s; NaN without a reported velocity.
    pub ground_speed_mps: f64,
    /// Vertical rate, m/s, up positive; NaN without a reported velocity.
    pub vertical_rate_mps: f64,
    /// 1-sigma horizontal position uncertainty at `header.gps_time_ns` (grows with age), m.
    pub position_sigma_m: f64,
    /// Age of the freshest position report at `header.gps_time_ns`, s.
    pub age_s: f64,
    /// Relative position, north, m (NED frame of the ownship, see the module documentation).
    pub rel_north_m: f64,
    /// Relative position, east, m.
    pub rel_east_m: f64,
    /// Relative position, down, m (= -`vertical_separation_m`); NaN when the altitude is unknown.
    pub rel_down_m: f64,
    /// Relative velocity, north, m/s; NaN without the intruder's velocity or the ownship.
    pub rel_vel_north_mps: f64,
    /// Relative velocity, east, m/s (as north).
    pub rel_vel_east_mps: f64,
    /// Relative velocity, down, m/s (as north).
    pub rel_vel_down_mps: f64,
    /// Horizontal distance, m.
    pub horizontal_distance_m: f64,
    /// Vertical separation (intruder above ownship positive), m; NaN when unknown.
    pub vertical_separation_m: f64,
    /// Bearing of the intruder from the ownship, deg true, in [0, 360).
    pub bearing_deg: f64,
    /// Horizontal range rate, m/s; negative when closing; NaN without geometry.
    pub range_rate_mps: f64,
    /// Time to horizontal closest point of approach, s (0 when diverging); NaN without geometry.
    pub tcpa_s: f64,
    /// Horizontal miss distance at the closest point of approach, m; NaN without geometry.
    pub hmd_m: f64,
    /// DO-365 modified tau, s. NaN when undefined: the aircraft are diverging, or already inside
    /// the distance modifier DMOD (then the horizontal test holds by distance alone).
    pub tau_mod_s: f64,
    /// Time to loss of well-clear, s: 0 when well-clear is violated now, NaN when no loss is
    /// predicted within the look-ahead.
    pub time_to_lowc_s: f64,
}

impl Target {
    /// An empty slot: zeros, codes unknown, undefined quantities NaN.
    pub const EMPTY: Target = Target {
        address: 0,
        address_type: ADDRESS_UNKNOWN,
        alert_level: ALERT_NONE,
        altitude_kind: ALTITUDE_UNKNOWN,
        plausibility_flags: 0,
        callsign: [0; CALLSIGN_LEN],
        emitter_category: EMITTER_UNKNOWN,
        sources: 0,
        nic: ACCURACY_UNKNOWN,
        nac_p: ACCURACY_UNKNOWN,
        nac_v: ACCURACY_UNKNOWN,
        sil: ACCURACY_UNKNOWN,
        reserved: [0; 2],
        flags: 0,
        reserved2: 0,
        lat_deg: f64::NAN,
        lon_deg: f64::NAN,
        alt_pressure_m: f64::NAN,
        alt_geometric_m: f64::NAN,
        track_deg: f64::NAN,
        ground_speed_mps: f64::NAN,
        vertical_rate_mps: f64::NAN,
        position_sigma_m: f64::NAN,
        age_s: 0.0,
        rel_north_m: 0.0,
        rel_east_m: 0.0,
        rel_down_m: f64::NAN,
        rel_vel_north_mps: f64::NAN,
        rel_vel_east_mps: f64::NAN,
        rel_vel_down_mps: f64::NAN,
        horizontal_distance_m: 0.0,
        vertical_separation_m: f64::NAN,
        bearing_deg: 0.0,
        range_rate_mps: f64::NAN,
        tcpa_s: f64::NAN,
        hmd_m: f64::NAN,
        tau_mod_s: f64::NAN,
        time_to_lowc_s: f64::NAN,
    };
}

impl Default for Target {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// The word for an `ALERT_*` code (JSON); an unknown code is `"unknown"`.
pub fn alert_level_name(level: u8) -> &'static str {
    match level {
        ALERT_NONE => "none",
        ALERT_PREVENTIVE => "preventive",
        ALERT_CORRECTIVE => "corrective",
        ALERT_WARNING => "warning",
        _ => "unknown",
    }
}

fn ser_address<S: Serializer>(a: &u32, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{:06X}", a & 0x00FF_FFFF))
}

fn ser_alert_level<S: Serializer>(l: &u8, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(alert_level_name(*l))
}

/// The user header of a traffic sample: what the picture is about; the targets follow as the
/// sample's slice payload.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, ZeroCopySend, Serialize)]
#[type_name("vigil.TrafficHeader.v2")]
pub struct TrafficHeader {
    /// Common header; `gps_time_ns` is the time the geometry was computed for.
    pub header: Header,
    /// Number of targets in the slice (equal to the slice's length; a reader takes the smaller
    /// of the two, so a corrupt count never reads past the slice).
    pub count: u32,
    /// Targets tracked but not published because the picture was full ([`MAX_TARGETS`]).
    pub dropped: u32,
}

/// The traffic picture as a program holds it: the header fields and the targets in priority
/// order. On the bus it travels as a [`TrafficHeader`] and a slice (see the module documentation).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrafficPayload {
    /// Common header; `gps_time_ns` is the time the geometry was computed for.
    pub header: Header,
    /// Targets tracked but not published because the picture was full.
    pub dropped: u32,
    /// The targets, most urgent first, at most [`MAX_TARGETS`].
    pub targets: Vec<Target>,
}

impl TrafficPayload {
    /// The targets.
    pub fn targets(&self) -> &[Target] {
        &self.targets
    }

    /// Number of targets.
    pub fn count(&self) -> u32 {
        self.targets.len() as u32
    }

    /// Replaces the targets with `targets` (already sorted by priority): the first
    /// [`MAX_TARGETS`] are kept, the rest counted in `dropped`.
    pub fn set_targets(&mut self, targets: &[Target]) {
        let n = targets.len().min(MAX_TARGETS);
        self.targets.clear();
        self.targets.extend_from_slice(&targets[..n]);
        self.dropped = u32::try_from(targets.len() - n).unwrap_or(u32::MAX);
    }

    /// The wire header of this picture (count from the targets, at most [`MAX_TARGETS`]).
    pub fn wire_header(&self) -> TrafficHeader {
        TrafficHeader {
            header: self.header,
            count: self.targets.len().min(MAX_TARGETS) as u32,
            dropped: self.dropped,
        }
    }

    /// The picture from a received header and slice: `count` is trusted only up to the slice's
    /// length and [`MAX_TARGETS`].
    pub fn from_wire(h: &TrafficHeader, targets: &[Target]) -> Self {
        let n = (h.count as usize).min(targets.len()).min(MAX_TARGETS);
        Self {
            header: h.header,
            dropped: h.dropped,
            targets: targets[..n].to_vec(),
        }
    }
}

/// serde form shared by the owned and the received picture: header, count, dropped, targets.
pub(crate) fn serialize_picture<S: Serializer>(
    s: S,
    header: &Header,
    dropped: u32,
    targets: &[Target],
) -> Result<S::Ok, S::Error> {
    let mut st = s.serialize_struct("TrafficPayload", 4)?;
    st.serialize_field("header", header)?;
    st.serialize_field("count", &(targets.len() as u32))?;
    st.serialize_field("dropped", &dropped)?;
    st.serialize_field("targets", targets)?;
    st.end()
}

impl Serialize for TrafficPayload {
    /// Header, count, dropped and the targets.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_picture(s, &self.header, self.dropped, &self.targets)
    }
}

impl_header!(TrafficPayload, Topic::Traffic);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_targets_clamps_and_counts_the_rest() {
        let mut p = TrafficPayload::default();
        let t = Target {
            address: 0xABCDEF,
            ..Target::EMPTY
        };
        p.set_targets(&vec![t; MAX_TARGETS + 5]);
        assert_eq!(p.count() as usize, MAX_TARGETS);
        assert_eq!(p.dropped, 5);
        assert_eq!(p.wire_header().count as usize, MAX_TARGETS);
        p.set_targets(&[t; 3]);
        assert_eq!(p.targets().len(), 3);
        assert_eq!(p.dropped, 0);
    }

    #[test]
    fn from_wire_trusts_the_count_only_up_to_the_slice() {
        let t = Target::EMPTY;
        let mut h = TrafficHeader {
            count: u32::MAX,
            ..TrafficHeader::default()
        };
        assert_eq!(TrafficPayload::from_wire(&h, &[t; 4]).targets.len(), 4);
        h.count = 2;
        assert_eq!(TrafficPayload::from_wire(&h, &[t; 4]).targets.len(), 2);
    }

    #[test]
    fn json_names_the_address_in_hex_and_the_alert_level_in_words() {
        let t = Target {
            address: 0x00AB_C0DE,
            alert_level: ALERT_CORRECTIVE,
            ..Target::EMPTY
        };
        let v = serde_json::to_value(t).unwrap();
        assert_eq!(v["address"], "ABC0DE");
        assert_eq!(v["alert_level"], "corrective");
        assert!(v.get("reserved").is_none() && v.get("reserved2").is_none());
        // A small address keeps its six digits.
        let v = serde_json::to_value(Target {
            address: 0x42,
            alert_level: 9,
            ..Target::EMPTY
        })
        .unwrap();
        assert_eq!(v["address"], "000042");
        assert_eq!(v["alert_level"], "unknown");
    }
}
