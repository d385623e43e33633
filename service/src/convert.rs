//! Fusion outputs -> bus payloads (issue 10, "bus/"): the one place where the fusion's
//! serde-friendly records (degrees, `Option`s, enums) become the fixed-size `#[repr(C)]` payloads
//! (radians where the payload says so, NaN for unknown, `u8` codes).
//!
//! Decisions:
//! - Voted attitude sigma: the record does not carry one. The selected (median) unit's sigma is
//!   used; when two units are averaged (no median unit), the larger of the two sigmas (the
//!   conservative choice); NaN when none is known.
//! - A unit's `valid`: its values are present and its three gates are open.
//! - A unit's `t_gps_ns`: the comparison time minus the unit's sample age (interpolated units),
//!   the comparison time itself for the BAHRS (the reference), 0 without values.
//! - Isolation: one unit isolated (the record's `isolated`) -> ISOLATED; otherwise a declared
//!   fault -> DETECTED_NOT_ISOLATED; no axis compared -> NOT_COMPARED; else NO_FAULT.
//! - Traffic relative velocities (`rel_vel_north_mps`, `rel_vel_east_mps`, `rel_vel_up_mps`):
//!   the intruder's velocity ([`Target::velocity_ne_mps`], [`Target::vertical_rate_mps`]) minus
//!   the ownship's (track, ground speed, vertical rate); NaN when either is unknown, with the
//!   target's fail-safe `FLAG_*` bit saying which (issue 24).
//! - A target without geometry (no comparable altitude): horizontal distance from the positions,
//!   the other geometric quantities NaN.

use vigil_bus::payload::attitude::{
    self as att, AttitudePayload, UNIT_COUNT, UNIT_NONE, UnitAttitude,
};
use vigil_bus::payload::integrity::{
    self as integ, DeviceIntegrity, IntegrityPayload, MAX_DEVICES,
};
use vigil_bus::payload::ownship::{self as own, OwnshipPayload};
use vigil_bus::payload::traffic::{self as tr, TrafficPayload};
use vigil_bus::payload::write_text;
use vigil_drivers::DecodeStats;
use vigil_fusion::attitude::coverage::{Coverage, CoverageRecord, NotComparedReason};
use vigil_fusion::attitude::gates::{Gate, GateReason};
use vigil_fusion::attitude::health::{HealthCheck, HealthVerdict, NotCompared};
use vigil_fusion::attitude::isolation::{Isolation, PairVerdict, Unit};
use vigil_fusion::attitude::record::{AttitudeRecord, AxisPair, PairRecord, UnitValues, VotedAxis};
use vigil_fusion::ownship::{Ownship, OwnshipSolution, PositionSource};
use vigil_fusion::pipeline::TrafficPicture;
use vigil_fusion::time::ClockStatus;
use vigil_fusion::time::aligner::{ClockReport, Device};
use vigil_fusion::traffic::track::AddressSpace;
use vigil_fusion::traffic::{AltitudeKind, Origins, Target};

use super::config::Protocol;

const NS_PER_S: f64 = 1e9;

fn opt(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

fn heading_rad(deg: Option<f64>) -> f64 {
    deg.map_or(f64::NAN, |d| {
        d.to_radians().rem_euclid(std::f64::consts::TAU)
    })
}

fn unit_index(u: Unit) -> usize {
    match u {
        Unit::Bahrs => usize::from(att::UNIT_BAHRS),
        Unit::Vn200 => usize::from(att::UNIT_VN200),
        Unit::Watson => usize::from(att::UNIT_WATSON),
    }
}

fn gate_flags(g: Gate) -> u8 {
    match g {
        None => 0,
        Some(r) => match r {
            GateReason::HealthIntegrityRisk => att::FAULT_HEALTH,
            GateReason::InsErrorBits | GateReason::ImuFailed => {
                att::FAULT_HEALTH | att::FAULT_INVALID
            }
            GateReason::HealthUnavailable
            | GateReason::HealthUndefined
            | GateReason::AccuracyInvalid
            | GateReason::InsModeNoAttitude
            | GateReason::OverRange
            | GateReason::NotFinite => att::FAULT_INVALID,
            GateReason::NoData | GateReason::Stale => att::FAULT_STALE,
            GateReason::Frozen => att::FAULT_FROZEN,
            // Not a fault of the unit: the heading is not comparable here.
            GateReason::MagneticPole | GateReason::NoDeclination => 0,
        },
    }
}

fn unit(v: &UnitValues, t_gps_ns: i64, isolated: bool) -> UnitAttitude {
    let has = v.roll_deg.is_some() || v.pitch_deg.is_some() || v.heading_deg.is_some();
    let gates = [v.gates.roll, v.gates.pitch, v.gates.heading];
    let sigma = v.sigma_deg.map(|s| s.map(f64::to_radians));
    let mut flags = gates.iter().fold(0u8, |f, g| f | gate_flags(*g));
    if isolated {
        flags |= att::FAULT_ISOLATED;
    }
    UnitAttitude {
        t_gps_ns: if has {
            t_gps_ns - v.age_s.map_or(0, |a| (a * NS_PER_S).round() as i64)
        } else {
            0
        },
        roll_rad: v.roll_deg.map_or(f64::NAN, f64::to_radians),
        pitch_rad: v.pitch_deg.map_or(f64::NAN, f64::to_radians),
        heading_rad: heading_rad(v.heading_deg),
        sigma_roll_rad: sigma.map_or(f64::NAN, |s| s[0]),
        sigma_pitch_rad: sigma.map_or(f64::NAN, |s| s[1]),
        sigma_heading_rad: sigma.map_or(f64::NAN, |s| s[2]),
        valid: u8::from(
            v.roll_deg.is_some()
                && v.pitch_deg.is_some()
                && v.heading_deg.is_some()
                && gates.iter().all(Option::is_none),
        ),
        fault_flags: flags,
        reserved: [0; 6],
    }
}

fn verdict(v: PairVerdict) -> u8 {
    match v {
        PairVerdict::Pass => att::VERDICT_PASS,
        PairVerdict::Fail => att::VERDICT_FAIL,
        PairVerdict::NotCompared => att::VERDICT_NOT_COMPARED,
    }
}

fn verdicts(p: &PairRecord) -> [u8; 3] {
    let v = |a: &AxisPair| verdict(a.verdict);
    [v(&p.roll), v(&p.pitch), v(&p.heading)]
}

/// Sigma of a voted axis, rad (see the module decisions); `axis` 0 roll, 1 pitch, 2 heading.
fn voted_sigma(v: Option<&VotedAxis>, units: &[UnitAttitude; UNIT_COUNT], axis: usize) -> f64 {
    let Some(v) = v else { return f64::NAN };
    let sigma = |u: Unit| {
        let u = &units[unit_index(u)];
        [u.sigma_roll_rad, u.sigma_pitch_rad, u.sigma_heading_rad][axis]
    };
    match v.selected {
        Some(u) => sigma(u),
        None => v
            .used
            .iter()
            .map(|&u| sigma(u))
            .fold(f64::NAN, |m, s| if s.is_nan() { m } else { s.max(m) }),
    }
}

/// The attitude payload of one cross-check record.
pub fn attitude(r: &AttitudeRecord) -> AttitudePayload {
    let isolated = |u: Unit| r.isolated == Some(u);
    let mut units = [UnitAttitude::default(); UNIT_COUNT];
    units[unit_index(Unit::Bahrs)] = unit(&r.bahrs, r.t_gps_ns, isolated(Unit::Bahrs));
    units[unit_index(Unit::Vn200)] = unit(&r.vn200, r.t_gps_ns, isolated(Unit::Vn200));
    units[unit_index(Unit::Watson)] = unit(&r.watson, r.t_gps_ns, isolated(Unit::Watson));
    let i = &r.isolation;
    let all_not_compared = [i.roll, i.pitch, i.heading, i.joint]
        .iter()
        .all(|x| *x == Isolation::NotCompared);
    let (isolation, isolated_unit) = match r.isolated {
        Some(u) => (att::ISOLATION_ISOLATED, unit_index(u) as u8),
        None if r.fault || r.multiple_fault => (att::ISOLATION_DETECTED_NOT_ISOLATED, UNIT_NONE),
        None if all_not_compared => (att::ISOLATION_NOT_COMPARED, UNIT_NONE),
        None => (att::ISOLATION_NO_FAULT, UNIT_NONE),
    };
    let mut pair_verdicts = [[0u8; 3]; 3];
    pair_verdicts[att::PAIR_BAHRS_VN200] = verdicts(&r.pairs.bahrs_vn200);
    pair_verdicts[att::PAIR_BAHRS_WATSON] = verdicts(&r.pairs.bahrs_watson);
    pair_verdicts[att::PAIR_VN200_WATSON] = verdicts(&r.pairs.vn200_watson);
    let v = &r.voted;
    let mut p = AttitudePayload {
        roll_rad: v
            .roll
            .as_ref()
            .map_or(f64::NAN, |a| a.value_deg.to_radians()),
        pitch_rad: v
            .pitch
            .as_ref()
            .map_or(f64::NAN, |a| a.value_deg.to_radians()),
        heading_rad: heading_rad(v.heading.as_ref().map(|a| a.value_deg)),
        sigma_roll_rad: voted_sigma(v.roll.as_ref(), &units, 0),
        sigma_pitch_rad: voted_sigma(v.pitch.as_ref(), &units, 1),
        sigma_heading_rad: voted_sigma(v.heading.as_ref(), &units, 2),
        units,
        pair_verdicts,
        isolation,
        isolated_unit,
        valid: u8::from(v.roll.is_some() && v.pitch.is_some() && v.heading.is_some()),
        ..AttitudePayload::default()
    };
    p.header.gps_time_ns = r.t_gps_ns;
    set_coverage(&mut p, &r.coverage);
    set_channels(&mut p, r);
    p
}

// --- issue 25 points 5 and 6: the vertical and inertial channels ---
/// The payload's `COVERAGE_*` code of a comparison's gate (`None`: compared).
fn gate_coverage(g: Gate) -> u8 {
    match g.map(vigil_fusion::attitude::coverage::reason_of_gate) {
        None => att::COVERAGE_COMPARED,
        Some(NotComparedReason::Absent) => att::COVERAGE_ABSENT,
        Some(NotComparedReason::Stale) => att::COVERAGE_STALE,
        Some(NotComparedReason::NotComparable) => att::COVERAGE_NOT_COMPARABLE,
        Some(_) => att::COVERAGE_INVALID,
    }
}

fn health_code(h: vigil_drivers::bahrs::Health) -> u8 {
    use vigil_drivers::bahrs::Health as H;
    match h {
        H::Unavailable => att::HEALTH_UNAVAILABLE,
        H::Safe => att::HEALTH_SAFE,
        H::IntegrityRisk => att::HEALTH_INTEGRITY_RISK,
        H::Undefined => att::HEALTH_UNDEFINED,
    }
}

/// Fills the vertical and inertial comparisons and the BAHRS health of their signals (unknown
/// values NaN, health `HEALTH_NONE` before the first message).
fn set_channels(p: &mut AttitudePayload, r: &AttitudeRecord) {
    use vigil_fusion::attitude::inertial::SignalComparison;
    use vigil_fusion::attitude::vertical::VerticalComparison;
    let vert = |c: &VerticalComparison| att::ChannelComparison {
        bahrs: opt(c.bahrs_mps),
        vn200: opt(c.vn200_mps),
        diff: opt(c.diff_mps),
        sigma: opt(c.sigma_mps),
        stat_ratio: opt(c.stat_ratio),
        verdict: verdict(c.verdict),
        coverage: gate_coverage(c.gate),
        ..att::ChannelComparison::default()
    };
    p.vertical[att::VERTICAL_VELOCITY_DOWN] = vert(&r.vertical.velocity_down);
    p.vertical[att::VERTICAL_HEIGHT_RATE] = vert(&r.vertical.height_rate);
    p.bahrs_vertical_health = r
        .vertical
        .bahrs_health
        .map_or([att::HEALTH_NONE; 2], |h| h.map(health_code));
    set_third_opinion(p, &r.vertical.third);
    let inert = |c: &SignalComparison| att::ChannelComparison {
        bahrs: opt(c.bahrs),
        vn200: opt(c.vn200),
        diff: opt(c.diff),
        sigma: opt(c.sigma),
        stat_ratio: opt(c.stat_ratio),
        verdict: verdict(c.verdict),
        coverage: gate_coverage(c.gate),
        ..att::ChannelComparison::default()
    };
    p.inertial = r.inertial.axes.map(|c| inert(&c));
    p.bahrs_inertial_health = r
        .inertial
        .bahrs_health
        .map_or([att::HEALTH_NONE; att::INERTIAL_COUNT], |h| {
            h.map(health_code)
        });
}

/// Issue 25 point 6: the TT-Multi-RF GNSS third opinion on the height rate (unknown values
/// NaN, `UNIT_NONE` when nothing is isolated).
fn set_third_opinion(p: &mut AttitudePayload, t: &vigil_fusion::attitude::vertical::ThirdOpinion) {
    use vigil_fusion::attitude::vertical::{TtNotCompared as W, VerticalComparison};
    let cmp = |c: &VerticalComparison| att::ChannelComparison {
        bahrs: opt(c.bahrs_mps),
        vn200: opt(c.vn200_mps),
        diff: opt(c.diff_mps),
        sigma: opt(c.sigma_mps),
        stat_ratio: opt(c.stat_ratio),
        verdict: verdict(c.verdict),
        coverage: if t.not_compared.is_some() {
            att::COVERAGE_NO_CHECK
        } else {
            gate_coverage(c.gate)
        },
        ..att::ChannelComparison::default()
    };
    p.vertical_tt_rate_mps = opt(t.tt_rate_mps);
    p.vertical_tt[att::VERTICAL_TT_BAHRS] = cmp(&t.bahrs_vs_tt);
    p.vertical_tt[att::VERTICAL_TT_VN200] = cmp(&t.vn200_vs_tt);
    p.vertical_tt_coverage = match t.not_compared {
        None => att::COVERAGE_COMPARED,
        Some(W::Absent) => att::COVERAGE_ABSENT,
        Some(W::NoFix) => att::COVERAGE_INVALID,
        Some(W::Stale) => att::COVERAGE_STALE,
        Some(W::WindowFilling) => att::COVERAGE_NO_CHECK,
        Some(W::NoPartner) => att::COVERAGE_NO_PARTNER,
    };
    p.vertical_isolated_unit = t.isolated.map_or(UNIT_NONE, |u| unit_index(u) as u8);
}

// --- issue 25: coverage ---
fn coverage_code(c: &Coverage) -> u8 {
    use NotComparedReason as R;
    match (c.compared, c.reason) {
        (true, _) => att::COVERAGE_COMPARED,
        (false, Some(R::NotAligned)) => att::COVERAGE_NOT_ALIGNED,
        (false, Some(R::NotWired)) => att::COVERAGE_NOT_WIRED,
        (false, Some(R::Stale)) => att::COVERAGE_STALE,
        (false, Some(R::Absent)) => att::COVERAGE_ABSENT,
        (false, Some(R::Invalid)) => att::COVERAGE_INVALID,
        (false, Some(R::NotComparable)) => att::COVERAGE_NOT_COMPARABLE,
        (false, Some(R::NoPartner)) => att::COVERAGE_NO_PARTNER,
        // Not compared without a reason cannot come from the checker; "no check" is the honest
        // reading of it.
        (false, Some(R::NoCheck) | None) => att::COVERAGE_NO_CHECK,
    }
}

/// Fills the payload's coverage block from the record's (ages NaN when never compared).
fn set_coverage(p: &mut AttitudePayload, c: &CoverageRecord) {
    let units = [
        (unit_index(Unit::Bahrs), &c.bahrs),
        (unit_index(Unit::Vn200), &c.vn200),
        (unit_index(Unit::Watson), &c.watson),
    ];
    for (i, u) in units {
        p.unit_coverage[i] = coverage_code(u);
        p.unit_compared_age_s[i] = opt(u.age_s);
    }
    let checks = [
        (att::CHECK_ROLL, &c.roll),
        (att::CHECK_PITCH, &c.pitch),
        (att::CHECK_HEADING, &c.heading),
        (att::CHECK_VERTICAL, &c.vertical),
    ];
    for (i, k) in checks {
        p.check_coverage[i] = coverage_code(k);
        p.check_compared_age_s[i] = opt(k.age_s);
    }
}

/// The ownship payload of one ownship solution: unknown quantities NaN, with their `FLAG_*` bit.
pub fn ownship(s: &OwnshipSolution) -> OwnshipPayload {
    let o = &s.ownship;
    let nan = f64::NAN;
    let v = o.velocity_en_mps();
    let mut flags = 0;
    if v.is_none() {
        flags |= own::FLAG_VELOCITY_UNKNOWN;
    }
    if o.vertical_rate_mps.is_none() {
        flags |= own::FLAG_VERTICAL_RATE_UNKNOWN;
    }
    if o.alt_geometric_band_m > 0.0 {
        flags |= own::FLAG_GEOID_UNKNOWN;
    }
    let mut p = OwnshipPayload {
        lat_deg: o.lat_deg,
        lon_deg: o.lon_deg,
        alt_pressure_m: opt(o.alt_pressure_m),
        alt_geometric_m: opt(o.alt_geometric_m),
        vel_north_mps: v.map_or(nan, |v| v[1]),
        vel_east_mps: v.map_or(nan, |v| v[0]),
        vel_up_mps: opt(o.vertical_rate_mps),
        ground_speed_mps: v.and(o.ground_speed_mps).unwrap_or(nan),
        track_deg: v.and(o.track_deg).unwrap_or(nan),
        sigma_horizontal_m: opt(o.position_sigma_m),
        // The builder gives no vertical uncertainty, except the geoid's range when the geoid
        // separation is unknown (uniform over +-band: band / sqrt 3).
        sigma_vertical_m: if o.alt_geometric_band_m > 0.0 {
            o.alt_geometric_band_m / 3f64.sqrt()
        } else {
            nan
        },
        sigma_velocity_mps: opt(s.velocity_sigma_mps),
        source: match o.source {
            PositionSource::Vn200Ins => own::SOURCE_VN200_INS,
            PositionSource::TtMultiRfGnss => own::SOURCE_TTMRF_GNSS,
            PositionSource::External => own::SOURCE_EXTERNAL,
        },
        // The builder returns a state only when it is usable; a non-finite position is not.
        valid: u8::from(o.lat_deg.is_finite() && o.lon_deg.is_finite()),
        flags,
        ..OwnshipPayload::default()
    };
    p.header.gps_time_ns = o.t_gps_ns;
    p
}

fn address_type(s: AddressSpace) -> u8 {
    match s {
        AddressSpace::Icao => tr::ADDRESS_ICAO,
        AddressSpace::NonIcao => tr::ADDRESS_NON_ICAO,
        AddressSpace::TisbOther => tr::ADDRESS_TISB_OTHER,
        AddressSpace::FlarmRandom => tr::ADDRESS_FLARM_RANDOM,
        AddressSpace::FlarmFixed => tr::ADDRESS_FLARM_FIXED,
        AddressSpace::Surface => tr::ADDRESS_SURFACE,
        AddressSpace::Unknown => tr::ADDRESS_UNKNOWN,
    }
}

/// The `PLAUSIBILITY_*` bits of a target.
fn plausibility_bits(f: &vigil_fusion::traffic::track::PlausibilityFlags) -> u8 {
    [
        (f.impossible_speed, tr::PLAUSIBILITY_IMPOSSIBLE_SPEED),
        (f.position_jump, tr::PLAUSIBILITY_POSITION_JUMP),
        (f.altitude_jump, tr::PLAUSIBILITY_ALTITUDE_JUMP),
        (f.range_vs_signal, tr::PLAUSIBILITY_RANGE_VS_SIGNAL),
        (
            f.inconsistent_sources,
            tr::PLAUSIBILITY_INCONSISTENT_SOURCES,
        ),
        (f.position_drift, tr::PLAUSIBILITY_POSITION_DRIFT),
    ]
    .iter()
    .fold(0u8, |acc, &(on, bit)| if on { acc | bit } else { acc })
}

/// The fail-safe `FLAG_*` bits of a target (issue 24).
fn fail_safe_bits(t: &Target) -> u64 {
    let f = &t.fail_safe;
    [
        (
            f.ownship_velocity_unknown,
            tr::FLAG_OWNSHIP_VELOCITY_UNKNOWN,
        ),
        (f.altitude_unknown, tr::FLAG_ALTITUDE_UNKNOWN),
        (f.velocity_unknown, tr::FLAG_VELOCITY_UNKNOWN),
        (f.vertical_rate_unknown, tr::FLAG_VERTICAL_RATE_UNKNOWN),
        (f.stale, tr::FLAG_STALE),
        (t.flags.any(), tr::FLAG_PLAUSIBILITY),
        (
            f.ownship_vertical_rate_unknown,
            tr::FLAG_OWNSHIP_VERTICAL_RATE_UNKNOWN,
        ),
        (
            f.altitude_reference_mixed,
            tr::FLAG_ALTITUDE_REFERENCE_MIXED,
        ),
        (f.time_from_receipt, tr::FLAG_TIME_FROM_RECEIPT),
    ]
    .iter()
    .fold(0u64, |acc, &(on, bit)| if on { acc | bit } else { acc })
}

/// The `SOURCE_*` bits of a target's origins.
fn source_bits(o: &Origins) -> u8 {
    [
        (o.adsb, tr::SOURCE_ADSB),
        (o.uat, tr::SOURCE_UAT),
        (o.flarm, tr::SOURCE_FLARM),
        (o.relayed, tr::SOURCE_TISB),
    ]
    .iter()
    .fold(0u8, |acc, &(on, bit)| if on { acc | bit } else { acc })
}

/// One target of the traffic payload; `own` (the ownship of the same step) gives the distance of
/// a target without geometry (a stale one). Every unknown is NaN with its `FLAG_*` bit.
pub fn target(t: &Target, own: Option<&Ownship>) -> tr::Target {
    let mut callsign = [0u8; tr::CALLSIGN_LEN];
    if let Some(c) = &t.callsign {
        write_text(&mut callsign, c);
    }
    let nan = f64::NAN;
    let distance = match (&t.geometry, own) {
        (Some(g), _) => g.horizontal_distance_m,
        (None, Some(o)) => vigil_fusion::traffic::plausibility::horizontal_distance_m(
            o.lat_deg, o.lon_deg, t.lat_deg, t.lon_deg,
        ),
        (None, None) => nan,
    };
    let (sin, cos) = t.bearing_true_deg.to_radians().sin_cos();
    let g = t.geometry.as_ref();
    let own_v = own.and_then(Ownship::velocity_en_mps);
    // Relative velocity, north / east / up: NaN where either side's is unknown.
    let rel_h = match (t.velocity_ne_mps, own_v) {
        (Some(v), Some(o)) => [v[0] - o[1], v[1] - o[0]],
        _ => [nan; 2],
    };
    // Down is the negated up rate of the separation (intruder minus ownship).
    let rel_down_rate = match (t.vertical_rate_mps, own.and_then(|o| o.vertical_rate_mps)) {
        (Some(v), Some(o)) if g.is_some_and(|g| g.vertical_separation_m.is_some()) => o - v,
        _ => nan,
    };
    let r = &t.reported;
    let u8_or = |v: Option<u8>| v.unwrap_or(tr::NOT_REPORTED);
    tr::Target {
        address: t.key.address & 0x00FF_FFFF,
        address_type: address_type(t.key.space),
        alert_level: t.alert_level.min(tr::ALERT_WARNING),
        altitude_kind: match t.altitude_kind {
            AltitudeKind::Pressure => tr::ALTITUDE_PRESSURE,
            AltitudeKind::Geometric | AltitudeKind::Mixed => tr::ALTITUDE_GEOMETRIC,
            AltitudeKind::None => tr::ALTITUDE_UNKNOWN,
        },
        plausibility_flags: plausibility_bits(&t.flags),
        callsign,
        lat_deg: t.lat_deg,
        lon_deg: t.lon_deg,
        alt_pressure_m: r.alt_pressure_m.unwrap_or(nan),
        alt_geometric_m: r.alt_geometric_m.unwrap_or(nan),
        track_deg: r.track_deg.unwrap_or(nan),
        ground_speed_mps: r.ground_speed_mps.unwrap_or(nan),
        vertical_rate_mps: t.vertical_rate_mps.unwrap_or(nan),
        position_sigma_m: t.position_sigma_m,
        nic: u8_or(r.nic),
        nac_p: u8_or(r.nac_p),
        nac_v: u8_or(r.nac_v),
        emitter_category: u8_or(r.emitter_category),
        sources: source_bits(&r.origins),
        reserved: [0; 3],
        rel_north_m: distance * cos,
        rel_east_m: distance * sin,
        rel_down_m: g
            .and_then(|g| g.vertical_separation_m)
            .map_or(nan, |dz| -dz),
        rel_vel_north_mps: rel_h[0],
        rel_vel_east_mps: rel_h[1],
        rel_vel_down_mps: rel_down_rate,
        horizontal_distance_m: distance,
        bearing_deg: t.bearing_true_deg.rem_euclid(360.0),
        range_rate_mps: g.and_then(|g| g.range_rate_mps).unwrap_or(nan),
        tcpa_s: g.and_then(|g| g.tcpa_s).unwrap_or(nan),
        hmd_m: g.and_then(|g| g.hmd_m).unwrap_or(nan),
        tau_mod_s: g.and_then(|g| g.tau_mod_s).unwrap_or(nan),
        time_to_lowc_s: g.map_or(nan, |g| {
            if g.well_clear_violated_now {
                0.0
            } else {
                g.loss_of_well_clear_interval_s.map_or(nan, |iv| iv.0)
            }
        }),
        age_s: t.age_s,
        flags: fail_safe_bits(t),
    }
}

/// Fills `out` (reused, so its target vector keeps its allocation) with the picture, targets in
/// the picture's priority order; targets beyond [`tr::MAX_TARGETS`] are dropped and counted.
pub fn traffic(p: &TrafficPicture, own: Option<&Ownship>, out: &mut TrafficPayload) {
    out.header = Default::default();
    out.header.gps_time_ns = p.t_gps_ns;
    let n = p.targets.len().min(tr::MAX_TARGETS);
    out.targets.clear();
    out.targets
        .extend(p.targets[..n].iter().map(|t| target(t, own)));
    out.dropped = u32::try_from(p.targets.len() - n).unwrap_or(u32::MAX);
}

/// What the service knows of one port, for its integrity entry.
#[derive(Debug, Clone, PartialEq)]
pub struct PortReport<'a> {
    /// Port name.
    pub name: &'a str,
    /// Wire protocol (gives the device kind).
    pub protocol: Protocol,
    /// `LINK_*` code.
    pub link_state: u8,
    /// Time since the last decoded message, s; `None` when none was ever decoded.
    pub last_message_age_s: Option<f64>,
    /// Bytes read from the port.
    pub bytes_received: u64,
    /// The decoder's counters (`None`: nothing decoded yet).
    pub stats: Option<DecodeStats>,
    /// Times the port was reopened.
    pub reconnects: u64,
}

/// The `DEVICE_*` code of a port's protocol.
pub fn device_code(p: Protocol) -> u8 {
    match p {
        Protocol::Bahrs => integ::DEVICE_BAHRS,
        Protocol::Watson => integ::DEVICE_WATSON,
        Protocol::Vn200 => integ::DEVICE_VN200,
        Protocol::TtmrfText
        | Protocol::TtmrfHex
        | Protocol::TtmrfMavlink
        | Protocol::TtmrfGdl90
        | Protocol::TtmrfAsterix => integ::DEVICE_TTMRF,
    }
}

/// The integrity entry of one port.
pub fn device(r: &PortReport<'_>) -> DeviceIntegrity {
    let s = r.stats.unwrap_or_default();
    let mut name = [0u8; integ::DEVICE_NAME_LEN];
    write_text(&mut name, r.name);
    DeviceIntegrity {
        name,
        device: device_code(r.protocol),
        link_state: r.link_state,
        reserved: [0; 6],
        last_message_age_s: opt(r.last_message_age_s),
        bytes_received: r.bytes_received,
        bytes_consumed: s.bytes_consumed,
        bytes_skipped: s.bytes_skipped,
        messages: s.frames_decoded,
        checksum_failures: s.checksum_failures,
        unknown_types: s.unknown_types,
        // Unsupported protocol versions are malformed frames for a consumer.
        malformed: s.malformed + s.unsupported_version,
        reconnects: r.reconnects,
        invalid_values: s.invalid_values,
    }
}

/// The clock status code from the aligner's per-device reports.
///
/// Decision: the installation's time is PPS-locked when the BAHRS clock (disciplined by the
/// VN-200 PPS) is locked; else it has GPS time when the VN-200 clock or the host-clock model is
/// locked; holdover when one of them coasts; not locked otherwise.
pub fn clock_status(reports: &[ClockReport]) -> u8 {
    let status = |d: Device| reports.iter().find(|r| r.device == d).map(|r| r.status);
    let host = status(Device::Watson).or(status(Device::Ttmrf));
    let gps = [status(Device::Vn200), host];
    if status(Device::Bahrs) == Some(ClockStatus::Locked) {
        integ::CLOCK_PPS_LOCKED
    } else if gps.contains(&Some(ClockStatus::Locked)) {
        integ::CLOCK_GPS_TIME
    } else if gps.contains(&Some(ClockStatus::Coasting))
        || status(Device::Bahrs) == Some(ClockStatus::Coasting)
    {
        integ::CLOCK_HOLDOVER
    } else {
        integ::CLOCK_NOT_LOCKED
    }
}

/// The `DEVICE_*` code of an aligner device (issue 18: the `clock_disagreement` bits).
pub fn device_code_of(d: Device) -> u8 {
    match d {
        Device::Bahrs => integ::DEVICE_BAHRS,
        Device::Watson => integ::DEVICE_WATSON,
        Device::Vn200 => integ::DEVICE_VN200,
        Device::Ttmrf => integ::DEVICE_TTMRF,
    }
}

/// One bit per device (`1 << DEVICE_*` code): the integrity payload's `clock_disagreement` and
/// `line_full`.
pub fn device_bits(devices: impl IntoIterator<Item = Device>) -> u8 {
    devices
        .into_iter()
        .fold(0, |bits, d| bits | 1 << device_code_of(d))
}

/// The integrity payload: one entry per port (at most [`MAX_DEVICES`]), the clock status, and
/// the host clock's offset from GPS time with its sigma (from the host-clock model, the report of
/// the host-timed devices), at GPS time `t_gps_ns` (0 when unknown).
pub fn integrity(
    ports: &[PortReport<'_>],
    clocks: &[ClockReport],
    leap_seconds_known: bool,
    t_gps_ns: i64,
) -> IntegrityPayload {
    let mut p = IntegrityPayload {
        clock_status: clock_status(clocks),
        leap_seconds_known: u8::from(leap_seconds_known),
        clock_offset_s: f64::NAN,
        clock_sigma_s: f64::NAN,
        ..IntegrityPayload::default()
    };
    p.header.gps_time_ns = t_gps_ns;
    if let Some(host) = clocks.iter().find(|r| r.device == Device::Watson) {
        p.clock_offset_s = host.offset_ns.map_or(f64::NAN, |o| o / NS_PER_S);
        p.clock_sigma_s = host.residual_ns.map_or(f64::NAN, |s| s / NS_PER_S);
    }
    let n = ports.len().min(MAX_DEVICES);
    for (slot, r) in p.devices.iter_mut().zip(ports) {
        *slot = device(r);
    }
    p.device_count = n as u32;
    p
}

// --- issue 25 point 4: the health cross-check ---
/// Fills the integrity payload's health fields from the fusion's health cross-check at GPS time
/// `now_ns` (`None`: no clock yet, so every combination is "not compared: no clock"): every BAHRS
/// signal's health, the VN-200 status and the verdict per combination.
pub fn health(p: &mut IntegrityPayload, check: &HealthCheck, now_ns: Option<i64>) {
    if let Some(h) = check.navigation_health() {
        p.bahrs_navigation_health = [
            h.pressure_height(),
            h.velocity_down(),
            h.roll(),
            h.pitch(),
            h.heading(),
        ]
        .map(health_code);
    }
    if let Some(h) = check.inertial_health() {
        // The attitude payload's `INERTIAL_*` order: specific force x/y/z, angular rate x/y/z.
        p.bahrs_inertial_health = [0, 1, 2, 3, 4, 5].map(|i| {
            health_code(if i < 3 {
                h.specific_force(i)
            } else {
                h.angular_rate(i - 3)
            })
        });
    }
    let Some(now) = now_ns else {
        return;
    };
    if let Some((status, age_s)) = check.vn200(now) {
        p.vn200_ins_status = status.0;
        p.vn200_ins_mode = (status.0 & 3) as u8;
        p.vn200_gnss_fix = u8::from(status.gnss_fix());
        p.vn200_status_age_s = age_s;
    }
    p.bahrs_pulse_age_s = check.pulse_age_s(now).unwrap_or(f64::NAN);
    for (slot, v) in p.health_checks.iter_mut().zip(check.verdicts(now)) {
        *slot = health_comparison(v, now);
    }
}

fn health_comparison(v: HealthVerdict, now_ns: i64) -> integ::HealthComparison {
    let (state, reason, disagree_s) = match v {
        HealthVerdict::Agree => (integ::HEALTH_AGREE, integ::HEALTH_WHY_NONE, f64::NAN),
        HealthVerdict::Disagree { since_ns } => (
            integ::HEALTH_DISAGREE,
            integ::HEALTH_WHY_NONE,
            (now_ns - since_ns).max(0) as f64 / NS_PER_S,
        ),
        HealthVerdict::NotCompared(why) => (
            integ::HEALTH_NOT_COMPARED,
            match why {
                NotCompared::NoVn200Status => integ::HEALTH_WHY_NO_VN200_STATUS,
                NotCompared::Vn200Stale => integ::HEALTH_WHY_VN200_STALE,
                NotCompared::BahrsSilent => integ::HEALTH_WHY_BAHRS_SILENT,
                NotCompared::NeverPulsed => integ::HEALTH_WHY_NEVER_PULSED,
            },
            f64::NAN,
        ),
    };
    integ::HealthComparison {
        state,
        reason,
        disagree_s,
        ..integ::HealthComparison::default()
    }
}

#[cfg(test)]
#[path = "convert_tests.rs"]
mod tests;
