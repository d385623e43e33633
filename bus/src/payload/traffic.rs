//! `vigil/traffic`: up to [`MAX_TARGETS`] targets with their DO-365 geometry, sorted by priority
//! (most urgent first: alert level, then time to loss of well-clear, then range).
//!
//! Relative quantities are intruder minus ownship, in a local level frame (north, east, up).

use iceoryx2::prelude::ZeroCopySend;
use serde::ser::SerializeStruct;
use serde::{Serialize, Serializer};

use super::{Header, impl_payload, ser_text};
use crate::names::Topic;

/// Capacity of [`TrafficPayload::targets`]. More targets than this are not published (the lowest
/// priority ones are dropped and counted in [`TrafficPayload::dropped`]).
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
/// level is at most corrective (2); `vertical_separation_m` and `rel_vel_up_mps` are NaN.
pub const FLAG_ALTITUDE_UNKNOWN: u64 = 1 << 1;
/// Fail-safe flag: the intruder's velocity is unknown; position-only geometry as for
/// [`FLAG_OWNSHIP_VELOCITY_UNKNOWN`], with the distance it may have flown taken off the range.
pub const FLAG_VELOCITY_UNKNOWN: u64 = 1 << 2;
/// Fail-safe flag: the intruder's vertical rate is unknown; the vertical test covers the rates
/// its category allows; `rel_vel_up_mps` is NaN.
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

/// One target and its geometry relative to the ownship.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Target.v2")]
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
    /// Relative position north, m.
    pub rel_north_m: f64,
    /// Relative position east, m.
    pub rel_east_m: f64,
    /// Relative velocity north, m/s.
    pub rel_vel_north_mps: f64,
    /// Relative velocity east, m/s.
    pub rel_vel_east_mps: f64,
    /// Rate of the vertical separation, m/s; NaN when the altitude is unknown.
    pub rel_vel_up_mps: f64,
    /// Horizontal distance, m.
    pub horizontal_distance_m: f64,
    /// Vertical separation (intruder above ownship positive), m; NaN when unknown.
    pub vertical_separation_m: f64,
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
    // --- issue 24 ---
    /// `FLAG_*` bits: which quantities were unknown and how the geometry treated them. A NaN in
    /// this record is always "unknown", and a set bit says why.
    pub flags: u64,
}

impl Target {
    /// An empty slot: zeros, undefined quantities NaN.
    pub const EMPTY: Target = Target {
        address: 0,
        address_type: ADDRESS_UNKNOWN,
        alert_level: ALERT_NONE,
        altitude_kind: ALTITUDE_UNKNOWN,
        plausibility_flags: 0,
        callsign: [0; CALLSIGN_LEN],
        rel_north_m: 0.0,
        rel_east_m: 0.0,
        rel_vel_north_mps: 0.0,
        rel_vel_east_mps: 0.0,
        rel_vel_up_mps: f64::NAN,
        horizontal_distance_m: 0.0,
        vertical_separation_m: f64::NAN,
        bearing_deg: 0.0,
        range_rate_mps: 0.0,
        tcpa_s: 0.0,
        hmd_m: 0.0,
        tau_mod_s: f64::NAN,
        time_to_lowc_s: f64::NAN,
        age_s: 0.0,
        flags: 0,
    };
}

impl Default for Target {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// The traffic picture: `targets[..count]` are valid, sorted by priority.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend)]
#[type_name("vigil.Traffic.v2")]
pub struct TrafficPayload {
    /// Common header; `gps_time_ns` is the time the geometry was computed for.
    pub header: Header,
    /// Number of valid entries in `targets` (at most [`MAX_TARGETS`]).
    pub count: u32,
    /// Targets tracked but not published because the array was full.
    pub dropped: u32,
    /// The targets, most urgent first; entries from `count` on are unspecified.
    pub targets: [Target; MAX_TARGETS],
}

impl Default for TrafficPayload {
    fn default() -> Self {
        Self {
            header: Header::default(),
            count: 0,
            dropped: 0,
            targets: [Target::EMPTY; MAX_TARGETS],
        }
    }
}

impl TrafficPayload {
    /// The valid targets (`count` clamped to the capacity, so a bad count never panics).
    pub fn targets(&self) -> &[Target] {
        let n = (self.count as usize).min(MAX_TARGETS);
        &self.targets[..n]
    }

    /// Replaces the targets with `targets` (already sorted by priority): the first
    /// [`MAX_TARGETS`] are kept, the rest counted in `dropped`.
    pub fn set_targets(&mut self, targets: &[Target]) {
        let n = targets.len().min(MAX_TARGETS);
        self.targets[..n].copy_from_slice(&targets[..n]);
        self.count = n as u32;
        self.dropped = u32::try_from(targets.len() - n).unwrap_or(u32::MAX);
    }
}

impl Serialize for TrafficPayload {
    /// Header, count, dropped and only the valid targets.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("TrafficPayload", 4)?;
        st.serialize_field("header", &self.header)?;
        st.serialize_field("count", &self.count)?;
        st.serialize_field("dropped", &self.dropped)?;
        st.serialize_field("targets", self.targets())?;
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
        assert_eq!(p.count as usize, MAX_TARGETS);
        assert_eq!(p.dropped, 5);
        p.set_targets(&[t; 3]);
        assert_eq!(p.targets().len(), 3);
        assert_eq!(p.dropped, 0);
        // A corrupt count from a foreign writer is clamped, not trusted.
        p.count = u32::MAX;
        assert_eq!(p.targets().len(), MAX_TARGETS);
    }
}
