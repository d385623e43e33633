//! The record emitted for every comparison (issue 8: "Every comparison emits one record"): what
//! the integrity monitor and the replay tests read, one JSON line with `"kind":
//! "attitude_check"`. Angles in degrees (named `_deg`), headings true unless named `_mag`.

use serde::Serialize;

use super::compare::AxisComparison;
use super::coverage::CoverageRecord;
use super::gates::Gate;
use super::inertial::InertialRecord;
use super::isolation::{Isolation, PairVerdict, Unit, UnitSet};
use super::vertical::VerticalRecord;
use crate::magnetic::MagneticZone;

/// The record's `kind`.
pub const KIND: &str = "attitude_check";
/// The `kind` of a prompt output (the voted attitude at a unit's sample time, with the verdicts
/// of the newest check; see [`super::checker::AttitudeChecker::prompt`]).
pub const PROMPT_KIND: &str = "attitude_prompt";

/// Per-axis gates of one unit.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AxisGates {
    /// Roll gate (null when open).
    pub roll: Gate,
    /// Pitch gate.
    pub pitch: Gate,
    /// Heading gate.
    pub heading: Gate,
}

/// One unit's values at the comparison time (after mounting correction and declination).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct UnitValues {
    /// Roll, deg.
    pub roll_deg: Option<f64>,
    /// Pitch, deg.
    pub pitch_deg: Option<f64>,
    /// True heading, deg, 0 .. 360 (magnetic units: magnetic + declination).
    pub heading_deg: Option<f64>,
    /// Magnetic heading as reported, deg (BAHRS and Watson only).
    pub heading_mag_deg: Option<f64>,
    /// 1-sigma roll, pitch, heading used, deg.
    pub sigma_deg: Option<[f64; 3]>,
    /// Age of the unit's latest sample at the comparison time, s (interpolated units).
    pub age_s: Option<f64>,
    /// Gates.
    pub gates: AxisGates,
}

/// One pair on one axis.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AxisPair {
    /// Verdict after persistence.
    pub verdict: PairVerdict,
    /// The comparison (null when not compared).
    pub comparison: Option<AxisComparison>,
    /// Statistical detector over its threshold on this sample.
    pub stat_exceeded: bool,
    /// Fixed comparator over its limit on this sample.
    pub fixed_exceeded: bool,
    /// Statistical detector fault after persistence (or CUSUM).
    pub stat_fault: bool,
    /// Fixed comparator fault after persistence.
    pub fixed_fault: bool,
    /// CUSUM of the statistical detector, sigma-samples.
    pub cusum: f64,
}

/// The joint chi-square test of one pair.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct JointTest {
    /// Sum of the three squared normalised differences (null unless all three compared).
    pub chi2: Option<f64>,
    /// `chi2 / threshold`.
    pub ratio: Option<f64>,
    /// Verdict after persistence.
    pub verdict: PairVerdict,
}

/// One pair: three axes and the joint test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PairRecord {
    /// Roll.
    pub roll: AxisPair,
    /// Pitch.
    pub pitch: AxisPair,
    /// Heading (true).
    pub heading: AxisPair,
    /// Joint chi-square with 3 degrees of freedom.
    pub joint: JointTest,
}

/// The three pairs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PairsRecord {
    /// BAHRS minus VN-200.
    pub bahrs_vn200: PairRecord,
    /// BAHRS minus Watson.
    pub bahrs_watson: PairRecord,
    /// VN-200 minus Watson.
    pub vn200_watson: PairRecord,
}

/// Isolation outcome per axis and for the joint test.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IsolationRecord {
    /// Roll.
    pub roll: Isolation,
    /// Pitch.
    pub pitch: Isolation,
    /// Heading (with the magnetic-disturbance rule).
    pub heading: Isolation,
    /// Joint test.
    pub joint: Isolation,
}

/// One voted axis: the median of the valid, non-isolated units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct VotedAxis {
    /// Voted value, deg (heading true, 0 .. 360).
    pub value_deg: f64,
    /// Units that took part.
    pub used: UnitSet,
    /// The unit whose value is the median (null when two units are averaged).
    pub selected: Option<Unit>,
}

/// The voted attitude with provenance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Voted {
    /// Roll.
    pub roll: Option<VotedAxis>,
    /// Pitch.
    pub pitch: Option<VotedAxis>,
    /// True heading.
    pub heading: Option<VotedAxis>,
}

/// The declination used.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DeclinationRecord {
    /// Declination, deg, east positive.
    pub declination_deg: f64,
    /// 1-sigma, deg.
    pub sigma_deg: f64,
    /// Horizontal field, nT.
    pub horizontal_nt: f64,
    /// Compass zone.
    pub zone: MagneticZone,
}

/// One attitude-check record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttitudeRecord {
    /// Always [`KIND`].
    pub kind: &'static str,
    /// GPS time of the BAHRS sample, ns.
    pub t_gps_ns: i64,
    /// A fault is declared after persistence (any axis or joint isolation other than "no fault",
    /// "not compared" and "magnetic disturbance").
    pub fault: bool,
    /// The isolated unit, when exactly one unit is isolated.
    pub isolated: Option<Unit>,
    /// No consistent pair, or different units isolated on different axes.
    pub multiple_fault: bool,
    /// The heading disagreement is a magnetic disturbance.
    pub magnetic_disturbance: bool,
    /// The BAHRS declares one of its signals an integrity risk (health 10) on this sample: raised
    /// at once, no persistence.
    pub bahrs_integrity_risk: bool,
    /// The VN-200 is Tracking without error bits.
    pub vn200_healthy: bool,
    /// BAHRS values.
    pub bahrs: UnitValues,
    /// VN-200 values (interpolated by slerp).
    pub vn200: UnitValues,
    /// Watson values (interpolated by slerp).
    pub watson: UnitValues,
    /// Declination used (null when unknown).
    pub declination: Option<DeclinationRecord>,
    /// Pairwise comparisons.
    pub pairs: PairsRecord,
    /// Isolation per axis.
    pub isolation: IsolationRecord,
    /// Voted attitude.
    pub voted: Voted,
    /// Vertical channel.
    pub vertical: VerticalRecord,
    /// The inertial channel (issue 25 point 5): the newest 0x01 against the VN-200, per axis.
    pub inertial: InertialRecord,
    // --- issue 25: coverage ---
    /// What was compared on this record and why the rest was not (a prompt: compared within
    /// `verdict_max_age_s`; see [`super::coverage`]).
    pub coverage: CoverageRecord,
}
