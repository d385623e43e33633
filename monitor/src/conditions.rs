//! The rules' conditions over the latest payloads: pure functions that push `(alert_id,
//! Condition)` for every alert whose condition holds now. Timing (raise delay, hysteresis, latch)
//! is applied afterwards by [`crate::lifecycle`].

use core::fmt::Write as _;

use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION, SEVERITY_WARNING};
use vigil_bus::payload::attitude::{
    AXIS_HEADING, AXIS_PITCH, AXIS_ROLL, AttitudePayload, FAULT_HEALTH, FAULT_INVALID,
    ISOLATION_DETECTED_NOT_ISOLATED, ISOLATION_ISOLATED, UNIT_BAHRS, UNIT_COUNT, UNIT_VN200,
    UnitAttitude, VERDICT_FAIL, VERDICT_PASS, VERTICAL_TT_BAHRS, VERTICAL_TT_VN200,
};
use vigil_bus::payload::attitude::{COVERAGE_COMPARED, coverage_name};
use vigil_bus::payload::attitude::{
    ChannelComparison, HEALTH_INTEGRITY_RISK, HEALTH_NONE, HEALTH_SAFE, HEALTH_UNAVAILABLE,
    INERTIAL_ANGULAR_RATE_X,
};
use vigil_bus::payload::integrity::{
    CLOCK_GPS_TIME, CLOCK_HOLDOVER, CLOCK_NOT_LOCKED, CLOCK_PPS_LOCKED, DEVICE_BAHRS, DEVICE_TTMRF,
    DEVICE_VN200, IntegrityPayload,
};
use vigil_bus::payload::integrity::{
    HEALTH_DISAGREE, HEALTH_FIX_WITHOUT_PPS, HEALTH_GNSS_LOST_WITH_FIX, HEALTH_PPS_WITHOUT_FIX,
    HEALTH_TRACKING_WITHOUT_FIX, VN200_STATUS_NONE,
};
use vigil_bus::payload::ownship::{
    OwnshipPayload, SOURCE_EXTERNAL, SOURCE_NONE, SOURCE_TTMRF_GNSS, SOURCE_VN200_INS,
};
use vigil_bus::payload::read_text;
use vigil_bus::payload::traffic::{
    ALERT_CORRECTIVE, ALERT_NONE, ALERT_PREVENTIVE, CALLSIGN_LEN, PLAUSIBILITY_ALTITUDE_JUMP,
    PLAUSIBILITY_IMPOSSIBLE_SPEED, PLAUSIBILITY_INCONSISTENT_SOURCES, PLAUSIBILITY_POSITION_DRIFT,
    PLAUSIBILITY_POSITION_JUMP, PLAUSIBILITY_RANGE_VS_SIGNAL, Target,
};

use crate::lifecycle::Condition;
use crate::params::MonitorParams;
use crate::rules::{Rule, target_alert_id};

/// Conditions holding at one evaluation, `(alert_id, condition)`.
pub(crate) type Active = Vec<(u32, Condition)>;

fn push(
    out: &mut Active,
    params: &MonitorParams,
    rule: Rule,
    id: u32,
    severity: u8,
    reason: String,
) {
    if params.timing(rule).enabled {
        out.push((id, Condition { severity, reason }));
    }
}

/// Display name of a `UNIT_*` index.
pub fn unit_name(unit: usize) -> &'static str {
    match unit {
        0 => "BAHRS",
        1 => "VN-200",
        2 => "Watson",
        _ => "unknown unit",
    }
}

const PAIR_NAMES: [&str; 3] = ["BAHRS/VN-200", "BAHRS/Watson", "VN-200/Watson"];
const AXIS_NAMES: [&str; 3] = ["roll", "pitch", "heading"];

fn axis_deg(u: &UnitAttitude, axis: usize) -> f64 {
    match axis {
        AXIS_ROLL => u.roll_rad,
        AXIS_PITCH => u.pitch_rad,
        _ => u.heading_rad,
    }
    .to_degrees()
}

/// "BAHRS 12.3, VN-200 3.1, Watson - deg" (a unit without a valid sample shows "-").
fn unit_values(p: &AttitudePayload, axis: usize) -> String {
    let mut s = String::new();
    for (i, u) in p.units.iter().enumerate() {
        if i > 0 {
            s.push_str(", ");
        }
        if u.valid != 0 {
            let _ = write!(s, "{} {:.1}", unit_name(i), axis_deg(u, axis));
        } else {
            let _ = write!(s, "{} -", unit_name(i));
        }
    }
    s.push_str(" deg");
    s
}

/// Attitude rules: miscompare per axis, unit isolated, unit health, voted attitude invalid, INS
/// not tracking (one function per rule; each pushes its alerts to `out`).
pub(crate) fn attitude(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    attitude_miscompare(p, params, out);
    unit_isolated(p, params, out);
    unit_health(p, params, out);
    attitude_invalid(p, params, out);
    ins_not_tracking(p, params, out);
}

/// One alert per axis with a failed pair, naming the failed pairs and each unit's value; "not
/// isolated" when the cross-check could not say which unit is wrong.
fn attitude_miscompare(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    for axis in [AXIS_ROLL, AXIS_PITCH, AXIS_HEADING] {
        let failed: Vec<&str> = (0..3)
            .filter(|&pair| p.pair_verdicts[pair][axis] == VERDICT_FAIL)
            .map(|pair| PAIR_NAMES[pair])
            .collect();
        if failed.is_empty() {
            continue;
        }
        let not_isolated = if p.isolation == ISOLATION_DETECTED_NOT_ISOLATED {
            ", not isolated"
        } else {
            ""
        };
        let reason = format!(
            "{} miscompare ({} fail{not_isolated}): {}",
            AXIS_NAMES[axis],
            failed.join(", "),
            unit_values(p, axis)
        );
        let id = Rule::AttitudeMiscompare.alert_id(axis as u32);
        push(
            out,
            params,
            Rule::AttitudeMiscompare,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

/// The unit the cross-check isolated, with its values against the voted attitude; an unknown
/// unit code is named as such rather than dropped.
fn unit_isolated(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    if p.isolation == ISOLATION_ISOLATED {
        let u = usize::from(p.isolated_unit);
        let values = p
            .units
            .get(u)
            .map(|v| {
                format!(
                    " (roll {:.1}, pitch {:.1}, heading {:.1} deg; voted {:.1}, {:.1}, {:.1} deg)",
                    v.roll_rad.to_degrees(),
                    v.pitch_rad.to_degrees(),
                    v.heading_rad.to_degrees(),
                    p.roll_rad.to_degrees(),
                    p.pitch_rad.to_degrees(),
                    p.heading_rad.to_degrees()
                )
            })
            .unwrap_or_default();
        let reason = if u < UNIT_COUNT {
            format!("{} isolated by the cross-check{values}", unit_name(u))
        } else {
            format!("unit code {u} isolated by the cross-check")
        };
        let id = Rule::UnitIsolated.alert_id(u as u32);
        push(
            out,
            params,
            Rule::UnitIsolated,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

/// One alert per unit whose health flag is set: for the BAHRS its own integrity-risk
/// declaration (with its values), for the others the fault flags.
fn unit_health(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    for (i, u) in p.units.iter().enumerate() {
        if u.fault_flags & FAULT_HEALTH == 0 {
            continue;
        }
        let reason = if i == usize::from(UNIT_BAHRS) {
            format!(
                "BAHRS health integrity risk: the unit declares its output possibly misleading \
                 (roll {:.1}, pitch {:.1}, heading {:.1} deg)",
                u.roll_rad.to_degrees(),
                u.pitch_rad.to_degrees(),
                u.heading_rad.to_degrees()
            )
        } else {
            format!(
                "{} reports a health problem (fault flags 0x{:02X})",
                unit_name(i),
                u.fault_flags
            )
        };
        let id = Rule::UnitHealth.alert_id(i as u32);
        push(out, params, Rule::UnitHealth, id, SEVERITY_CAUTION, reason);
    }
}

/// The voted attitude is unusable (severity warning), with every unit's fault flags.
fn attitude_invalid(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    if p.valid == 0 {
        let mut reason = String::from("voted attitude unusable; unit fault flags");
        for (i, u) in p.units.iter().enumerate() {
            let _ = write!(reason, " {} 0x{:02X}", unit_name(i), u.fault_flags);
        }
        let id = Rule::AttitudeInvalid.alert_id(0);
        push(
            out,
            params,
            Rule::AttitudeInvalid,
            id,
            SEVERITY_WARNING,
            reason,
        );
    }
}

/// The VN-200 INS reports its attitude invalid (INS mode or error bits).
fn ins_not_tracking(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    let vn = &p.units[usize::from(UNIT_VN200)];
    if vn.fault_flags & FAULT_INVALID != 0 {
        let reason = format!(
            "VN-200 INS not tracking: attitude invalid (INS mode or error bits; fault flags \
             0x{:02X})",
            vn.fault_flags
        );
        let id = Rule::InsNotTracking.alert_id(0);
        push(
            out,
            params,
            Rule::InsNotTracking,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

// --- issue 25 ---
/// Cross-check coverage rule: one alert per unit whose `unit_coverage` is not
/// `COVERAGE_COMPARED` (the raise delay is the "longer than a configured time"). The reason names
/// the unit, why it is not compared and since when.
pub(crate) fn coverage(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    for (i, &code) in p.unit_coverage.iter().enumerate() {
        if code == COVERAGE_COMPARED {
            continue;
        }
        let age = p.unit_compared_age_s[i];
        let since = if age.is_finite() {
            format!("last compared {age:.1} s ago")
        } else {
            "never compared".to_string()
        };
        let reason = format!(
            "{} not cross-checked: {} ({since})",
            unit_name(i),
            coverage_name(code)
        );
        let id = Rule::CrossCheckUnavailable.alert_id(i as u32);
        push(
            out,
            params,
            Rule::CrossCheckUnavailable,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

// --- issue 25 points 5 and 6 ---
const VERTICAL_NAMES: [&str; 2] = ["down velocity", "height rate"];
const INERTIAL_NAMES: [&str; 6] = [
    "specific force x",
    "specific force y",
    "specific force z",
    "angular rate x",
    "angular rate y",
    "angular rate z",
];

/// "BAHRS 1.23, VN-200 0.45, difference 0.78 (sigma 0.12)" with `scale` applied and `unit`.
fn channel_values(c: &ChannelComparison, scale: f64, unit: &str, digits: usize) -> String {
    let f = |x: f64| known(x, |x| format!("{:.digits$}", x * scale));
    format!(
        "BAHRS {}, VN-200 {} {unit}, difference {} (sigma {})",
        f(c.bahrs),
        f(c.vn200),
        f(c.diff),
        f(c.sigma)
    )
}

/// Vertical channel rule: one alert per comparison (`VERTICAL_*`) whose verdict is FAIL.
///
/// Issue 25 point 6: where the TT-Multi-RF GNSS altitude rate (the third opinion) singles out
/// the unit that disagrees with both others, the reason names it ("BAHRS isolated" / "VN-200
/// isolated"). Otherwise the reason keeps the premise-based attribution, "BAHRS suspected": the
/// VN-200's vertical is compared only while its INS tracks with a GNSS fix (GNSS-observed
/// velocity and height). It then says why the third opinion did not decide: "TT GNSS" followed
/// by its coverage name when not compared (`absent`, `invalid` no fix, `stale`, `no_check`
/// window filling, `no_partner`), or "undecided" when compared without singling out a unit.
/// (Kept short: the reason field holds 160 bytes.) The third opinion needs about 20 s of
/// window, so an alert raised by the down velocity within seconds usually starts as "suspected"
/// and its reason in the active set becomes "isolated" once the third opinion has declared.
pub(crate) fn vertical(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    let suspect = if p.vertical_tt_coverage != COVERAGE_COMPARED {
        format!(
            "BAHRS suspected (VN-200 GNSS-aided; TT GNSS {})",
            coverage_name(p.vertical_tt_coverage)
        )
    } else {
        // The isolated unit is taken only when the two third-opinion verdicts carry it out (a
        // payload left at its derived default has unit 0, the BAHRS, with no comparison).
        let tt = |i: usize| p.vertical_tt[i].verdict;
        match (
            p.vertical_isolated_unit,
            tt(VERTICAL_TT_BAHRS),
            tt(VERTICAL_TT_VN200),
        ) {
            (UNIT_BAHRS, VERDICT_FAIL, VERDICT_PASS) => {
                "BAHRS isolated (TT GNSS agrees with VN-200)".to_string()
            }
            (UNIT_VN200, VERDICT_PASS, VERDICT_FAIL) => {
                "VN-200 isolated (TT GNSS agrees with BAHRS)".to_string()
            }
            _ => "BAHRS suspected (VN-200 GNSS-aided; TT GNSS undecided)".to_string(),
        }
    };
    for (i, c) in p.vertical.iter().enumerate() {
        if c.verdict != VERDICT_FAIL {
            continue;
        }
        let name = VERTICAL_NAMES
            .get(i)
            .copied()
            .unwrap_or("unknown comparison");
        let reason = format!(
            "vertical {name} miscompare, {suspect}: {}",
            channel_values(c, 1.0, "m/s", 2)
        );
        let id = Rule::VerticalMiscompare.alert_id(i as u32);
        push(
            out,
            params,
            Rule::VerticalMiscompare,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

/// Inertial channel rule: one alert per signal (`INERTIAL_*`) whose verdict is FAIL (both
/// units usable: a signal the BAHRS marks unavailable or at integrity risk is not compared).
/// The reason names the axis and gives the BAHRS health of the signal.
pub(crate) fn inertial(p: &AttitudePayload, params: &MonitorParams, out: &mut Active) {
    for (i, c) in p.inertial.iter().enumerate() {
        if c.verdict != VERDICT_FAIL {
            continue;
        }
        let name = INERTIAL_NAMES.get(i).copied().unwrap_or("unknown signal");
        let values = if i >= INERTIAL_ANGULAR_RATE_X {
            channel_values(c, 1f64.to_degrees(), "deg/s", 3)
        } else {
            channel_values(c, 1.0, "m/s^2", 3)
        };
        let health = match p.bahrs_inertial_health.get(i).copied() {
            Some(HEALTH_SAFE) => "safe",
            Some(HEALTH_UNAVAILABLE) => "unavailable",
            Some(HEALTH_INTEGRITY_RISK) => "integrity risk",
            Some(HEALTH_NONE) => "unknown",
            _ => "undefined",
        };
        let reason = format!("inertial {name} miscompare (BAHRS health {health}): {values}");
        let id = Rule::InertialMiscompare.alert_id(i as u32);
        push(
            out,
            params,
            Rule::InertialMiscompare,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

/// Ownship rule: GNSS lost (position not from the VN-200 INS).
pub(crate) fn ownship(p: &OwnshipPayload, params: &MonitorParams, out: &mut Active) {
    let id = Rule::GnssLost.alert_id(0);
    let (severity, reason) = if p.valid == 0 || p.source == SOURCE_NONE {
        (
            SEVERITY_CAUTION,
            format!(
                "no valid ownship position (source code {}, valid {})",
                p.source, p.valid
            ),
        )
    } else if p.source == SOURCE_TTMRF_GNSS {
        (
            SEVERITY_ADVISORY,
            format!(
                "INS GNSS lost: ownship position from the TT-Multi-RF GNSS fallback \
                 (sigma_h {:.1} m)",
                p.sigma_horizontal_m
            ),
        )
    } else if p.source == SOURCE_VN200_INS || p.source == SOURCE_EXTERNAL {
        return;
    } else {
        (
            SEVERITY_ADVISORY,
            format!("ownship position from unknown source code {}", p.source),
        )
    };
    push(out, params, Rule::GnssLost, id, severity, reason);
}

/// Clock rule from the integrity payload.
pub(crate) fn clock(p: &IntegrityPayload, params: &MonitorParams, out: &mut Active) {
    let values = format!(
        "offset {:.6} s, sigma {:.6} s",
        p.clock_offset_s, p.clock_sigma_s
    );
    let (severity, reason) = match p.clock_status {
        CLOCK_PPS_LOCKED => return,
        CLOCK_GPS_TIME if !params.clock_require_pps => return,
        CLOCK_GPS_TIME => (
            SEVERITY_ADVISORY,
            format!("clock has GPS time but no PPS lock ({values})"),
        ),
        CLOCK_HOLDOVER => (
            SEVERITY_ADVISORY,
            format!("clock holding over after losing lock ({values})"),
        ),
        CLOCK_NOT_LOCKED => (
            SEVERITY_CAUTION,
            format!("clock not locked: host clock only ({values})"),
        ),
        code => (
            SEVERITY_CAUTION,
            format!("clock status unknown (code {code}): taken as not locked"),
        ),
    };
    let id = Rule::ClockNotLocked.alert_id(0);
    push(out, params, Rule::ClockNotLocked, id, severity, reason);
}

// --- issue 25 point 4 ---
/// Health cross-check rule: one alert per combination (`HEALTH_*`) whose state is
/// `HEALTH_DISAGREE` (the raise delay is the "longer than a configured time"). The reason names
/// the combination, its likely cause and the VN-200 status and pulse age behind it (kept within
/// the 160-byte reason).
pub(crate) fn health(p: &IntegrityPayload, params: &MonitorParams, out: &mut Active) {
    let mode = match p.vn200_ins_mode {
        0 => "NotTracking",
        1 => "Aligning",
        2 => "Tracking",
        3 => "GnssLost",
        VN200_STATUS_NONE => "unknown",
        _ => "undefined",
    };
    let pulse = known(p.bahrs_pulse_age_s, |a| format!("{a:.1} s ago"));
    for (i, c) in p.health_checks.iter().enumerate() {
        if c.state != HEALTH_DISAGREE {
            continue;
        }
        let what = match i {
            HEALTH_PPS_WITHOUT_FIX => {
                "BAHRS sync pulses without a VN-200 GNSS fix (miswired sync?)"
            }
            HEALTH_FIX_WITHOUT_PPS => "VN-200 GNSS fix without BAHRS sync pulses (sync wire lost?)",
            HEALTH_TRACKING_WITHOUT_FIX => "VN-200 INS Tracking without a GNSS fix",
            HEALTH_GNSS_LOST_WITH_FIX => "VN-200 INS GnssLost with a GNSS fix",
            _ => "unknown health combination",
        };
        let reason = format!(
            "health disagreement: {what} for {}; INS {mode}, status 0x{:04X}, last pulse {pulse}",
            known(c.disagree_s, |s| format!("{s:.1} s")),
            p.vn200_ins_status
        );
        let id = Rule::HealthDisagreement.alert_id(i as u32);
        push(
            out,
            params,
            Rule::HealthDisagreement,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

/// Clock disagreement rule (issue 18 point 4): one alert per `DEVICE_*` code whose bit is set
/// in the integrity payload's `clock_disagreement`. The payload carries only the bits, so the
/// reason says what each device's check compares and what the aligner does meanwhile.
pub(crate) fn clock_disagreement(p: &IntegrityPayload, params: &MonitorParams, out: &mut Active) {
    for code in 0..8u8 {
        if p.clock_disagreement & (1 << code) == 0 {
            continue;
        }
        let reason = match code {
            DEVICE_BAHRS => "BAHRS PPS-named time disagrees with the host clock (wrong pulse \
                             edge or second?): PPS model dropped, BAHRS timed through the host \
                             clock"
                .to_string(),
            DEVICE_VN200 => "VN-200 GPS time disagrees with the host clock (leap second or \
                             week wrong?): not used, VN-200 timed by its start-up clock or the \
                             host clock"
                .to_string(),
            // Within the 160-byte reason; the line's own alert (`line_full`) tells the two
            // causes apart when the line is full.
            DEVICE_TTMRF => "TT-Multi-RF ts / TS24h disagrees with the host clock (a second \
                             off, or queued over 0.5 s on a full line?): not used; timed by the \
                             host clock or not aligned"
                .to_string(),
            other => format!("device code {other}: clock disagrees with the host clock"),
        };
        let id = Rule::ClockDisagreement.alert_id(u32::from(code));
        push(
            out,
            params,
            Rule::ClockDisagreement,
            id,
            SEVERITY_CAUTION,
            reason,
        );
    }
}

/// Full line rule: one alert per `DEVICE_*` code whose bit is set in the integrity payload's
/// `line_full`. The payload carries only the bits, so the reason says what a full line does to
/// the device's data and what the user can change.
pub(crate) fn line_full(p: &IntegrityPayload, params: &MonitorParams, out: &mut Active) {
    for code in 0..8u8 {
        if p.line_full & (1 << code) == 0 {
            continue;
        }
        let reason = match code {
            // Within the alert's 160-byte reason.
            DEVICE_TTMRF => "TT-Multi-RF output fills its serial line: reports wait in the \
                             module (times widened or not aligned) and may be lost there; send \
                             fewer formats or raise the baud"
                .to_string(),
            other => format!("device code {other}: output fills its serial line"),
        };
        let id = Rule::LineFull.alert_id(u32::from(code));
        push(out, params, Rule::LineFull, id, SEVERITY_CAUTION, reason);
    }
}

/// What the monitor keeps of a traffic target that has an alert level or a plausibility flag.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct TargetSummary {
    pub address: u32,
    pub address_type: u8,
    pub alert_level: u8,
    pub plausibility_flags: u8,
    pub callsign: [u8; CALLSIGN_LEN],
    pub horizontal_distance_m: f64,
    pub vertical_separation_m: f64,
    pub time_to_lowc_s: f64,
}

impl TargetSummary {
    /// The summary of `t` when it matters to a rule, else `None`.
    pub fn of(t: &Target, params: &MonitorParams) -> Option<Self> {
        (t.alert_level != ALERT_NONE || t.plausibility_flags & params.spoofing_flags != 0)
            .then_some(Self {
                address: t.address & 0x00FF_FFFF,
                address_type: t.address_type,
                alert_level: t.alert_level,
                plausibility_flags: t.plausibility_flags,
                callsign: t.callsign,
                horizontal_distance_m: t.horizontal_distance_m,
                vertical_separation_m: t.vertical_separation_m(),
                time_to_lowc_s: t.time_to_lowc_s,
            })
    }

    /// "ABCDEF (N123AB)".
    fn name(&self) -> String {
        let cs = read_text(&self.callsign).trim();
        if cs.is_empty() {
            format!("{:06X}", self.address)
        } else {
            format!("{:06X} ({cs})", self.address)
        }
    }
}

/// Names of the plausibility flags set in `flags`.
pub fn plausibility_names(flags: u8) -> Vec<&'static str> {
    [
        (PLAUSIBILITY_IMPOSSIBLE_SPEED, "impossible speed"),
        (PLAUSIBILITY_POSITION_JUMP, "position jump"),
        (PLAUSIBILITY_ALTITUDE_JUMP, "altitude jump"),
        (PLAUSIBILITY_RANGE_VS_SIGNAL, "signal too strong for range"),
        (PLAUSIBILITY_INCONSISTENT_SOURCES, "inconsistent sources"),
        (PLAUSIBILITY_POSITION_DRIFT, "position drift"),
    ]
    .into_iter()
    .filter(|(bit, _)| flags & bit != 0)
    .map(|(_, name)| name)
    .collect()
}

/// `x` formatted by `f` when it is finite, else "unknown" (the bus's NaN sentinel).
fn known(x: f64, f: impl Fn(f64) -> String) -> String {
    if x.is_finite() {
        f(x)
    } else {
        "unknown".to_string()
    }
}

/// Traffic rules: per-target alert level and suspected spoofing.
pub(crate) fn traffic(targets: &[TargetSummary], params: &MonitorParams, out: &mut Active) {
    for t in targets {
        if t.alert_level != ALERT_NONE {
            // A level code above the known ones (a newer publisher) is taken as a warning.
            let (severity, level) = match t.alert_level {
                ALERT_PREVENTIVE => (SEVERITY_ADVISORY, "preventive"),
                ALERT_CORRECTIVE => (SEVERITY_CAUTION, "corrective"),
                _ => (SEVERITY_WARNING, "warning"),
            };
            // The payload encodes an unknown quantity as NaN (issue 24): say "unknown" instead.
            let reason = format!(
                "traffic {} {level}: range {}, vertical {}, time to LoWC {}",
                t.name(),
                known(t.horizontal_distance_m, |x| format!("{x:.0} m")),
                known(t.vertical_separation_m, |x| format!("{x:+.0} m")),
                known(t.time_to_lowc_s, |x| format!("{x:.1} s"))
            );
            let id = target_alert_id(Rule::TrafficAlert, t.address, t.address_type);
            push(out, params, Rule::TrafficAlert, id, severity, reason);
        }
        let flags = t.plausibility_flags & params.spoofing_flags;
        if flags != 0 {
            let reason = format!(
                "traffic {} suspected spoofing: {} (flags 0x{flags:02X}), range {:.0} m",
                t.name(),
                plausibility_names(flags).join(", "),
                t.horizontal_distance_m
            );
            let id = target_alert_id(Rule::SuspectedSpoofing, t.address, t.address_type);
            push(
                out,
                params,
                Rule::SuspectedSpoofing,
                id,
                SEVERITY_CAUTION,
                reason,
            );
        }
    }
}
