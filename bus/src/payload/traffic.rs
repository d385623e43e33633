//! `vigil/traffic`: up to [`MAX_TARGETS`] targets with their reported state and DO-365 geometry,
//! sorted by priority (most urgent first: alert level, then time to loss of well-clear, then
//! range).
//!
//! On the wire (schema 3, issue 26) a picture is a variable-length iceoryx2 slice of [`Target`]
//! sized by the number of targets, with a [`TrafficHeader`] as the iceoryx2 user header: a
//! 10-target picture is 10 targets long, not the 1024 of schema 2. [`TrafficPayload`] is the
//! same picture owned in the process (what the service builds and a subscriber may copy out).
//!
//! Relative quantities are intruder minus ownship, in the ownship's local north-east-down frame
//! (the frame a DAA's bands expect): `rel_down_m` is positive when the intruder is below.

use iceoryx2::prelude::ZeroCopySend;
use serde::ser::SerializeStruct;
use serde::{Serialize, Serializer};

use super::{Header, impl_payload, ser_text};
use crate::names::Topic;

/// Most targets in one picture (the documented maximum of the slice). More targets than this are
/// not published (the lowest priority ones are dropped and counted in
/// [`TrafficPayload::dropped`]).
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

/// Plausibility flag: positions drift away from where the reported velocity takes them (issue
/// 24: a slow spoof).
pub const PLAUSIBILITY_POSITION_DRIFT: u8 = 1 << 5;

// --- issue 24: fail-safe flags of `Target::flags` ---
/// Fail-safe flag: the ownship's velocity is unknown; the geometry is from the present relative
/// position alone (`rel_vel_*`, `range_rate_mps`, `tcpa_s`, `hmd_m`, `tau_mod_s`,
/// `time_to_lowc_s` are NaN; the alert level is from the present separation).
pub const FLAG_OWNSHIP_VELOCITY_UNKNOWN: u64 = 1 << 0;
/// Fail-safe flag: the intruder's altitude is unknown; it is taken as co-altitude and its alert
/// level is at most corrective (2); `rel_down_m` and `rel_vel_down_mps` are NaN.
pub const FLAG_ALTITUDE_UNKNOWN: u64 = 1 << 1;
/// Fail-safe flag: the intruder's velocity is unknown; position-only geometry as for
/// [`FLAG_OWNSHIP_VELOCITY_UNKNOWN`], with the distance it may have flown taken off the range.
pub const FLAG_VELOCITY_UNKNOWN: u64 = 1 << 2;
/// Fail-safe flag: the intruder's vertical rate is unknown; the vertical test covers the rates
/// its category allows; `rel_vel_down_mps` is NaN.
pub const FLAG_VERTICAL_RATE_UNKNOWN: u64 = 1 << 3;
/// Fail-safe flag: the newest position is older than the link's limit; no geometry (the
/// geometric quantities are NaN, alert level 0).
pub const FLAG_STALE: u64 = 1 << 4;
/// Fail-safe flag: some `plausibility_flags` bit is set (the target is suspect).
pub const FLAG_PLAUSIBILITY: u64 = 1 << 5;
/// Fail-safe flag: the ownship's vertical rate is unknown; the vertical test covers its
/// possible rates.
pub const FLAG_OWNSHIP_VERTICAL_RATE_UNKNOWN: u64 = 1 << 6;
/// Fail-safe flag: a pressure altitude was compared with a geometric one with no measured
/// difference; the vertical test holds for any separation within the band of that difference.
pub const FLAG_ALTITUDE_REFERENCE_MIXED: u64 = 1 << 7;
/// Fail-safe flag: the report's time is its arrival (the protocol carries no time of
/// applicability); the position is less certain.
pub const FLAG_TIME_FROM_RECEIPT: u64 = 1 << 8;

/// Source bit of [`Target::sources`]: ADS-B heard on 1090 MHz from the aircraft itself.
pub const SOURCE_ADSB: u8 = 1 << 0;
/// Source bit: UAT (978 MHz) heard from the aircraft itself.
pub const SOURCE_UAT: u8 = 1 << 1;
/// Source bit: FLARM.
pub const SOURCE_FLARM: u8 = 1 << 2;
/// Source bit: relayed by a ground station (TIS-B or ADS-R) rather than heard from the aircraft.
pub const SOURCE_TISB: u8 = 1 << 3;

/// Value of a `u8` category field ([`Target::nic`], [`Target::nac_p`], [`Target::nac_v`],
/// [`Target::emitter_category`]) that no source reported (distinct from a reported 0).
pub const NOT_REPORTED: u8 = 0xFF;

/// One target: its reported state, and its geometry relative to the ownship.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Target.v3")]
pub struct Target {
    /// 24-bit address (upper byte 0).
    pub address: u32,
    /// `ADDRESS_*` code.
    pub address_type: u8,
    /// `ALERT_*` code.
    pub alert_level: u8,
    /// `ALTITUDE_*` code: which altitudes the vertical quantities compare.
    pub altitude_kind: u8,
    /// `PLAUSIBILITY_*` bits; any set bit marks the target suspect.
    pub plausibility_flags: u8,
    /// Callsign, ASCII, NUL-padded (all NUL when unknown).
    #[serde(serialize_with = "ser_text")]
    pub callsign: [u8; CALLSIGN_LEN],
    // --- reported state (schema 3) ---
    /// Latitude at the picture's time (extrapolated from the newest fix), deg WGS-84.
    pub lat_deg: f64,
    /// Longitude at the picture's time, deg WGS-84.
    pub lon_deg: f64,
    /// Pressure altitude (1013.25 hPa datum), m; NaN when not reported.
    pub alt_pressure_m: f64,
    /// Geometric altitude (above the WGS-84 ellipsoid unless the source gave MSL), m; NaN when not
    /// reported.
    pub alt_geometric_m: f64,
    /// Track over ground, deg true, [0, 360); NaN when not reported.
    pub track_deg: f64,
    /// Ground speed, m/s; NaN when not reported.
    pub ground_speed_mps: f64,
    /// Vertical rate, m/s, positive up; NaN when not reported.
    pub vertical_rate_mps: f64,
    /// 1-sigma horizontal position uncertainty at the picture's time (from the source's accuracy,
    /// grown with the fix's age), m.
    pub position_sigma_m: f64,
    /// Navigation integrity category 0..11, or [`NOT_REPORTED`].
    pub nic: u8,
    /// Navigation accuracy category for position 0..11, or [`NOT_REPORTED`].
    pub nac_p: u8,
    /// Navigation accuracy category for velocity 0..4, or [`NOT_REPORTED`].
    pub nac_v: u8,
    /// Emitter category (DO-260B / GDL90 set, 0 = "no information" as reported), or
    /// [`NOT_REPORTED`].
    pub emitter_category: u8,
    /// `SOURCE_*` bits: the links and relays that reported the target.
    pub sources: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 3],
    // --- relative geometry, north-east-down about the ownship ---
    /// Relative position north, m.
    pub rel_north_m: f64,
    /// Relative position east, m.
    pub rel_east_m: f64,
    /// Relative position down (positive: intruder below the ownship), m, between the altitudes
    /// `altitude_kind` names; NaN when unknown.
    pub rel_down_m: f64,
    /// Relative velocity north, m/s.
    pub rel_vel_north_mps: f64,
    /// Relative velocity east, m/s.
    pub rel_vel_east_mps: f64,
    /// Relative velocity down (rate of `rel_down_m`), m/s; NaN when either vertical rate or the
    /// altitude is unknown.
    pub rel_vel_down_mps: f64,
    /// Horizontal distance, m.
    pub horizontal_distance_m: f64,
    /// Bearing of the intruder from the ownship, deg true, in [0, 360).
    pub bearing_deg: f64,
    /// Horizontal range rate, m/s; negative when closing.
    pub range_rate_mps: f64,
    /// Time to horizontal closest point of approach, s (0 when diverging).
    pub tcpa_s: f64,
    /// Horizontal miss distance at the closest point of approach, m.
    pub hmd_m: f64,
    /// DO-365 modified tau, s. NaN when undefined: the aircraft are diverging, or already inside
    /// the distance modifier DMOD (then the horizontal test holds by distance alone).
    pub tau_mod_s: f64,
    /// Time to loss of well-clear, s: 0 when well-clear is violated now, NaN when no loss is
    /// predicted within the look-ahead.
    pub time_to_lowc_s: f64,
    /// Age of the freshest report's data (from its time of applicability), s.
    pub age_s: f64,
    /// `FLAG_*` bits: which quantities were unknown and how the geometry treated them. A NaN in
    /// this record is always "unknown", and a set bit says why.
    pub flags: u64,
}

impl Target {
    /// An empty slot: zeros, undefined quantities NaN, categories not reported.
    pub const EMPTY: Target = Target {
        address: 0,
        address_type: ADDRESS_UNKNOWN,
        alert_level: ALERT_NONE,
        altitude_kind: ALTITUDE_UNKNOWN,
        plausibility_flags: 0,
        callsign: [0; CALLSIGN_LEN],
        lat_deg: f64::NAN,
        lon_deg: f64::NAN,
        alt_pressure_m: f64::NAN,
        alt_geometric_m: f64::NAN,
        track_deg: f64::NAN,
        ground_speed_mps: f64::NAN,
        vertical_rate_mps: f64::NAN,
        position_sigma_m: f64::NAN,
        nic: NOT_REPORTED,
        nac_p: NOT_REPORTED,
        nac_v: NOT_REPORTED,
        emitter_category: NOT_REPORTED,
        sources: 0,
        reserved: [0; 3],
        rel_north_m: 0.0,
        rel_east_m: 0.0,
        rel_down_m: f64::NAN,
        rel_vel_north_mps: 0.0,
        rel_vel_east_mps: 0.0,
        rel_vel_down_mps: f64::NAN,
        horizontal_distance_m: 0.0,
        bearing_deg: 0.0,
        range_rate_mps: 0.0,
        tcpa_s: 0.0,
        hmd_m: 0.0,
        tau_mod_s: f64::NAN,
        time_to_lowc_s: f64::NAN,
        age_s: 0.0,
        flags: 0,
    };

    /// Vertical separation (intruder above the ownship positive), m: `-rel_down_m`, the sign
    /// DO-365's vertical tests use.
    pub fn vertical_separation_m(&self) -> f64 {
        -self.rel_down_m
    }
}

impl Default for Target {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// The iceoryx2 user header of a traffic sample: the common header and the counts. The targets
/// follow as the sample's slice payload, `count` of them.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, ZeroCopySend, Serialize)]
#[type_name("vigil.TrafficHeader.v1")]
pub struct TrafficHeader {
    /// Common header; `gps_time_ns` is the time the geometry was computed for.
    pub header: Header,
    /// Number of targets in the sample's slice (equal to the slice's length; a reader takes the
    /// smaller of the two, so a bad count never reads past the slice).
    pub count: u32,
    /// Targets tracked but not published because the picture was beyond [`MAX_TARGETS`].
    pub dropped: u32,
}

/// A traffic picture owned in the process: what the service fills and publishes, and what a
/// subscriber gets when it copies a sample out.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrafficPayload {
    /// Common header; `gps_time_ns` is the time the geometry was computed for.
    pub header: Header,
    /// Targets tracked but not published because the picture was beyond [`MAX_TARGETS`].
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
    pub fn count(&self) -> usize {
        self.targets.len()
    }

    /// Replaces the targets with `targets` (already sorted by priority): the first
    /// [`MAX_TARGETS`] are kept, the rest counted in `dropped`. Reuses the allocation.
    pub fn set_targets(&mut self, targets: &[Target]) {
        let n = targets.len().min(MAX_TARGETS);
        self.targets.clear();
        self.targets.extend_from_slice(&targets[..n]);
        self.dropped = u32::try_from(targets.len() - n).unwrap_or(u32::MAX);
    }

    /// The user header of this picture on the wire.
    pub fn wire_header(&self) -> TrafficHeader {
        TrafficHeader {
            header: self.header,
            count: self.targets.len() as u32,
            dropped: self.dropped,
        }
    }

    /// A picture from a received header and slice (`count` clamped to the slice).
    pub fn from_wire(h: &TrafficHeader, targets: &[Target]) -> Self {
        let n = (h.count as usize).min(targets.len());
        Self {
            header: h.header,
            dropped: h.dropped,
            targets: targets[..n].to_vec(),
        }
    }
}

impl Serialize for TrafficPayload {
    /// Header, count, dropped and the targets.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("TrafficPayload", 4)?;
        st.serialize_field("header", &self.header)?;
        st.serialize_field("count", &self.targets.len())?;
        st.serialize_field("dropped", &self.dropped)?;
        st.serialize_field("targets", &self.targets)?;
        st.end()
    }
}

impl_payload!(TrafficPayload, Topic::Traffic);

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
        assert_eq!(p.count(), MAX_TARGETS);
        assert_eq!(p.dropped, 5);
        p.set_targets(&[t; 3]);
        assert_eq!(p.targets().len(), 3);
        assert_eq!(p.dropped, 0);
        assert_eq!(p.wire_header().count, 3);
    }

    #[test]
    fn a_bad_count_from_a_foreign_writer_is_clamped_to_the_slice() {
        let t = [Target::EMPTY; 4];
        let h = TrafficHeader {
            count: u32::MAX,
            ..TrafficHeader::default()
        };
        assert_eq!(TrafficPayload::from_wire(&h, &t).count(), 4);
        let h = TrafficHeader {
            count: 2,
            ..TrafficHeader::default()
        };
        assert_eq!(TrafficPayload::from_wire(&h, &t).count(), 2);
    }

    #[test]
    fn vertical_separation_is_the_negated_down_component() {
        let t = Target {
            rel_down_m: 150.0,
            ..Target::EMPTY
        };
        // 150 m down = intruder 150 m below the ownship.
        assert_eq!(t.vertical_separation_m(), -150.0);
    }
}
