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

// --- issue 25 points 5 and 6: the vertical and inertial channels ---
/// Number of vertical comparisons in [`AttitudePayload::vertical`].
pub const VERTICAL_COUNT: usize = 2;
/// Vertical comparison: BAHRS downward velocity against the VN-200 NED down velocity, m/s.
pub const VERTICAL_VELOCITY_DOWN: usize = 0;
/// Vertical comparison: BAHRS pressure-height rate against the VN-200 altitude rate (both
/// differenced over the same window), m/s, up positive.
pub const VERTICAL_HEIGHT_RATE: usize = 1;
/// Number of third-opinion comparisons in [`AttitudePayload::vertical_tt`].
pub const VERTICAL_TT_COUNT: usize = 2;
/// Third opinion: BAHRS pressure-height rate against the TT-Multi-RF GNSS altitude rate, m/s.
pub const VERTICAL_TT_BAHRS: usize = 0;
/// Third opinion: VN-200 altitude rate against the TT-Multi-RF GNSS altitude rate, m/s.
pub const VERTICAL_TT_VN200: usize = 1;
/// Number of inertial comparisons in [`AttitudePayload::inertial`].
pub const INERTIAL_COUNT: usize = 6;
/// Inertial comparison: specific force along body x, m/s^2 (`+ 1`, `+ 2`: y, z).
pub const INERTIAL_SPECIFIC_FORCE_X: usize = 0;
/// Inertial comparison: angular rate about body x, rad/s (`+ 1`, `+ 2`: y, z).
pub const INERTIAL_ANGULAR_RATE_X: usize = 3;

/// BAHRS 2-bit signal health (protocol 2.0, 2.4): 00 signal unavailable.
pub const HEALTH_UNAVAILABLE: u8 = 0;
/// BAHRS signal health 01: available and safe.
pub const HEALTH_SAFE: u8 = 1;
/// BAHRS signal health 10: integrity risk (available, possibly misleading).
pub const HEALTH_INTEGRITY_RISK: u8 = 2;
/// BAHRS signal health 11: not defined by the document.
pub const HEALTH_UNDEFINED: u8 = 3;
/// No BAHRS message carrying the signal has been received (not a wire value).
pub const HEALTH_NONE: u8 = 0xFF;

/// One comparison of a BAHRS signal with the VN-200's, in the signal's unit (m/s for the
/// vertical channel; m/s^2 or rad/s for the inertial one, in the aircraft body frame). Unknown
/// values are NaN.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.ChannelComparison.v1")]
pub struct ChannelComparison {
    /// BAHRS value; NaN when unknown.
    pub bahrs: f64,
    /// VN-200 value at the same time; NaN when unknown.
    pub vn200: f64,
    /// Difference BAHRS minus VN-200; NaN when not compared.
    pub diff: f64,
    /// Combined 1-sigma of the difference; NaN when not compared.
    pub sigma: f64,
    /// Statistical test ratio `|diff| / (k sigma)` (1 at the threshold); NaN when not compared.
    pub stat_ratio: f64,
    /// `VERDICT_*` code (`VERDICT_FAIL` after the fusion's persistence).
    pub verdict: u8,
    /// `COVERAGE_*` code: `COVERAGE_COMPARED`, or why not (`COVERAGE_INVALID`: a BAHRS health
    /// other than safe or an invalid VN-200 solution; `COVERAGE_ABSENT`: no value; ...).
    pub coverage: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 6],
}

impl Default for ChannelComparison {
    /// Not compared, nothing known.
    fn default() -> Self {
        Self {
            bahrs: f64::NAN,
            vn200: f64::NAN,
            diff: f64::NAN,
            sigma: f64::NAN,
            stat_ratio: f64::NAN,
            verdict: VERDICT_NOT_COMPARED,
            coverage: COVERAGE_NO_CHECK,
            reserved: [0; 6],
        }
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
#[type_name("vigil.Attitude.v4")]
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
    // --- issue 25 points 5 and 6 (layout v3): the vertical and inertial channels ---
    /// Vertical comparisons (`VERTICAL_*`) of the newest cross-check.
    pub vertical: [ChannelComparison; VERTICAL_COUNT],
    /// Inertial comparisons (`INERTIAL_*`) of the newest cross-check.
    pub inertial: [ChannelComparison; INERTIAL_COUNT],
    /// BAHRS health (`HEALTH_*`) of its pressure height and downward velocity (0x02), in that
    /// order; `HEALTH_NONE` before the first message.
    pub bahrs_vertical_health: [u8; 2],
    /// BAHRS health (`HEALTH_*`) of its specific force x/y/z and angular rate x/y/z (0x01), in
    /// `INERTIAL_*` order; `HEALTH_NONE` before the first message.
    pub bahrs_inertial_health: [u8; INERTIAL_COUNT],
    // --- issue 25 point 6 (layout v4): the TT-Multi-RF GNSS altitude as a third opinion ---
    /// TT-Multi-RF GNSS altitude rate over the third opinion's window (about 20 s), m/s up; NaN
    /// when not compared.
    pub vertical_tt_rate_mps: f64,
    /// BAHRS pressure-height rate and VN-200 altitude rate over the same window, each against
    /// the TT rate (`VERTICAL_TT_*`): `bahrs` is the unit's rate, `vn200` the TT rate.
    pub vertical_tt: [ChannelComparison; VERTICAL_TT_COUNT],
    /// `COVERAGE_*` code of the third opinion: `COVERAGE_COMPARED`, or why not
    /// (`COVERAGE_ABSENT` no TT GNSS, `COVERAGE_INVALID` no fix, `COVERAGE_STALE`,
    /// `COVERAGE_NO_CHECK` window still filling, `COVERAGE_NO_PARTNER` neither unit's height
    /// usable at both ends).
    pub vertical_tt_coverage: u8,
    /// Unit (`UNIT_BAHRS`, `UNIT_VN200`) a vertical miscompare is isolated to by the third
    /// opinion (the one disagreeing with both others), or [`UNIT_NONE`]: no miscompare, no third
    /// opinion (the attribution to the BAHRS then rests on the premise that the VN-200 vertical
    /// is GNSS-observed), or no single unit disagreeing with both.
    pub vertical_isolated_unit: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved_vertical_tt: [u8; 6],
}

impl_payload!(AttitudePayload, Topic::Attitude);
