//! `vigil/attitude`: the voted attitude with the three-unit cross-check verdicts.
//!
//! Units are indexed [`UNIT_BAHRS`], [`UNIT_VN200`], [`UNIT_WATSON`]; the three compared pairs are
//! indexed [`PAIR_BAHRS_VN200`], [`PAIR_BAHRS_WATSON`], [`PAIR_VN200_WATSON`]; axes [`AXIS_ROLL`],
//! [`AXIS_PITCH`], [`AXIS_HEADING`].

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use super::{Header, impl_payload};
use crate::names::Topic;

/// Number of attitude units cross-checked.
pub const UNIT_COUNT: usize = 3;
/// Index of the BAHRS baro-inertial AHRS in [`AttitudePayload::units`].
pub const UNIT_BAHRS: u8 = 0;
/// Index of the VN-200 GNSS/INS.
pub const UNIT_VN200: u8 = 1;
/// Index of the Watson AHRS-E304.
pub const UNIT_WATSON: u8 = 2;
/// [`AttitudePayload::isolated_unit`] when no unit is isolated.
pub const UNIT_NONE: u8 = 0xFF;

/// Index of the BAHRS/VN-200 pair in [`AttitudePayload::pair_verdicts`].
pub const PAIR_BAHRS_VN200: usize = 0;
/// Index of the BAHRS/Watson pair.
pub const PAIR_BAHRS_WATSON: usize = 1;
/// Index of the VN-200/Watson pair.
pub const PAIR_VN200_WATSON: usize = 2;
/// Axis index of roll in a pair's verdicts.
pub const AXIS_ROLL: usize = 0;
/// Axis index of pitch.
pub const AXIS_PITCH: usize = 1;
/// Axis index of heading.
pub const AXIS_HEADING: usize = 2;

/// Pair verdict: compared and consistent.
pub const VERDICT_PASS: u8 = 0;
/// Pair verdict: compared and inconsistent (after persistence).
pub const VERDICT_FAIL: u8 = 1;
/// Pair verdict: not compared (a gate closed: invalid, stale or frozen input).
pub const VERDICT_NOT_COMPARED: u8 = 2;

/// Isolation: no pair failed.
pub const ISOLATION_NO_FAULT: u8 = 0;
/// Isolation: fewer than one pair could be compared.
pub const ISOLATION_NOT_COMPARED: u8 = 1;
/// Isolation: a disagreement was detected but cannot be pinned on one unit.
pub const ISOLATION_DETECTED_NOT_ISOLATED: u8 = 2;
/// Isolation: one unit ([`AttitudePayload::isolated_unit`]) is isolated as faulty.
pub const ISOLATION_ISOLATED: u8 = 3;

/// Unit fault flag: the unit reports its own solution invalid.
pub const FAULT_INVALID: u8 = 1 << 0;
/// Unit fault flag: no fresh sample within the staleness limit.
pub const FAULT_STALE: u8 = 1 << 1;
/// Unit fault flag: the output is frozen (identical values for too long).
pub const FAULT_FROZEN: u8 = 1 << 2;
/// Unit fault flag: the unit is isolated by the cross-check.
pub const FAULT_ISOLATED: u8 = 1 << 3;
/// Unit fault flag: the unit reports an internal health problem.
pub const FAULT_HEALTH: u8 = 1 << 4;

// --- issue 25: coverage codes ---
/// Number of checks in [`AttitudePayload::check_coverage`].
pub const CHECK_COUNT: usize = 4;
/// Check index of roll in [`AttitudePayload::check_coverage`].
pub const CHECK_ROLL: usize = 0;
/// Check index of pitch.
pub const CHECK_PITCH: usize = 1;
/// Check index of heading.
pub const CHECK_HEADING: usize = 2;
/// Check index of the vertical channel (BAHRS down velocity and pressure-height rate against the
/// VN-200).
pub const CHECK_VERTICAL: usize = 3;
/// Coverage: compared (within the verdict age limit).
pub const COVERAGE_COMPARED: u8 = 0;
/// Not compared: samples arrive but cannot be put on GPS time now (e.g. BAHRS PPS lost).
pub const COVERAGE_NOT_ALIGNED: u8 = 1;
/// Not compared: samples arrive but none was ever put on GPS time (e.g. the BAHRS
/// synchronisation input not wired, or no pulse yet).
pub const COVERAGE_NOT_WIRED: u8 = 2;
/// Not compared: the newest sample is older than the freshness limit.
pub const COVERAGE_STALE: u8 = 3;
/// Not compared: no sample at all.
pub const COVERAGE_ABSENT: u8 = 4;
/// Not compared: the samples are not usable (own health or mode, error bits, frozen, ...).
pub const COVERAGE_INVALID: u8 = 5;
/// Not compared: the heading is not comparable here (no declination, magnetic pole zone).
pub const COVERAGE_NOT_COMPARABLE: u8 = 6;
/// Not compared: usable, but no other unit was.
pub const COVERAGE_NO_PARTNER: u8 = 7;
/// Not compared: no cross-check ran (checks run at BAHRS sample times).
pub const COVERAGE_NO_CHECK: u8 = 8;

/// Lower-case name of a `COVERAGE_*` code (as in the fusion records and the alert reasons).
pub fn coverage_name(code: u8) -> &'static str {
    match code {
        COVERAGE_COMPARED => "compared",
        COVERAGE_NOT_ALIGNED => "not_aligned",
        COVERAGE_NOT_WIRED => "not_wired",
        COVERAGE_STALE => "stale",
        COVERAGE_ABSENT => "absent",
        COVERAGE_INVALID => "invalid",
        COVERAGE_NOT_COMPARABLE => "not_comparable",
        COVERAGE_NO_PARTNER => "no_partner",
        COVERAGE_NO_CHECK => "no_check",
        _ => "unknown",
    }
}

/// One unit's attitude as used by the cross-check.
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.UnitAttitude.v1")]
pub struct UnitAttitude {
    /// GPS time of the unit's sample, ns; 0 when it has none.
    pub t_gps_ns: i64,
    /// Roll, rad (right wing down positive).
    pub roll_rad: f64,
    /// Pitch, rad (nose up positive).
    pub pitch_rad: f64,
    /// Heading, rad from true north, in [0, 2*pi).
    pub heading_rad: f64,
    /// 1-sigma roll uncertainty, rad.
    pub sigma_roll_rad: f64,
    /// 1-sigma pitch uncertainty, rad.
    pub sigma_pitch_rad: f64,
    /// 1-sigma heading uncertainty, rad.
    pub sigma_heading_rad: f64,
    /// 1 when the sample is valid and fresh, 0 otherwise.
    pub valid: u8,
    /// `FAULT_*` bits.
    pub fault_flags: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 6],
}

/// The voted attitude and the cross-check state.
///
/// `vigil run` publishes one at every attitude sample by default (the VN-200's rate, as soon as
/// the sample's last byte is read: the reporting unit at its own time, the others propagated
/// to it; verdicts of the newest cross-check), or one per cross-check (per BAHRS navigation
/// sample) with `[pipeline] attitude_output = "checks"`. Times increase in either mode (a
/// prompt time more than 1 s behind the newest is a clock reset, and followed).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Attitude.v2")]
pub struct AttitudePayload {
    /// Common header; `gps_time_ns` is the time of the voted solution.
    pub header: Header,
    /// Voted roll, rad.
    pub roll_rad: f64,
    /// Voted pitch, rad.
    pub pitch_rad: f64,
    /// Voted heading, rad from true north, in [0, 2*pi).
    pub heading_rad: f64,
    /// 1-sigma uncertainty of the voted roll, rad.
    pub sigma_roll_rad: f64,
    /// 1-sigma uncertainty of the voted pitch, rad.
    pub sigma_pitch_rad: f64,
    /// 1-sigma uncertainty of the voted heading, rad.
    pub sigma_heading_rad: f64,
    /// Per-unit inputs, indexed by `UNIT_*`.
    pub units: [UnitAttitude; UNIT_COUNT],
    /// Cross-check verdicts `[pair][axis]` (`PAIR_*`, `AXIS_*`), `VERDICT_*` codes.
    pub pair_verdicts: [[u8; 3]; 3],
    /// `ISOLATION_*` code.
    pub isolation: u8,
    /// Isolated unit (`UNIT_*`), or [`UNIT_NONE`].
    pub isolated_unit: u8,
    /// 1 when the voted attitude is usable, 0 otherwise.
    pub valid: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 4],
    // --- issue 25: coverage (what the cross-check compared on this sample, and why not) ---
    /// Per unit (`UNIT_*`): `COVERAGE_*` code (`COVERAGE_COMPARED` when it took part in a
    /// comparison no older than the verdict age limit).
    pub unit_coverage: [u8; UNIT_COUNT],
    /// Per check (`CHECK_*`): `COVERAGE_*` code.
    pub check_coverage: [u8; CHECK_COUNT],
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved_coverage: [u8; 1],
    /// Per unit: time since it was last compared, s; NaN when never compared.
    pub unit_compared_age_s: [f64; UNIT_COUNT],
    /// Per check: time since it last ran, s; NaN when never.
    pub check_compared_age_s: [f64; CHECK_COUNT],
}

impl_payload!(AttitudePayload, Topic::Attitude);
