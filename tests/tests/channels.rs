//! Issue 25 points 5 and 6 through the service (no bus): the simulator's BAHRS faults reach
//! `vertical_miscompare` and `inertial_miscompare` on the attitude payloads' comparisons, and the
//! alerts clear when the faults end. The nominal flight raising neither is asserted (with every
//! other rule) by `coverage_tests::nominal_flight_is_covered_and_raises_no_alert_of_any_rule`.

use vigil_bus::payload::alerts::{AlertPayload, STATE_CLEARED, STATE_RAISED};
use vigil_bus::payload::attitude as att;
use vigil_monitor::Rule;
use vigil_sim::scenario::{BodyAxis, Fault, builtin};

use vigil_service::Collected;
use vigil_tests::sim_drive::run_service as run;

const S: i64 = 1_000_000_000;

/// The first GPS time of the run and the transitions of `rule`'s alerts, with seconds from
/// the start.
fn transitions(out: &Collected, rule: Rule) -> (i64, Vec<(f64, &AlertPayload)>) {
    let t0 = out.attitude[0].header.gps_time_ns;
    let xs = out
        .alerts
        .iter()
        .filter(|a| Rule::of_alert(a.alert_id) == Some(rule))
        .map(|a| ((a.header.gps_time_ns - t0) as f64 / 1e9, a))
        .collect();
    (t0, xs)
}

/// Pressure port blocked from 10 s to 25 s of the nominal flight, which climbs at 2 m/s for its
/// first 60 s (the scenario file): the BAHRS holds its height and reads 0 m/s down while the
/// VN-200 climbs. Both vertical comparisons fail, the alert says the BAHRS is the suspect, no
/// attitude or inertial alert is raised, and every vertical alert clears after the port opens.
#[test]
fn blocked_pressure_port_raises_vertical_miscompare_on_the_bahrs_and_clears() {
    let mut sc = builtin("nominal").unwrap();
    sc.faults.push(Fault::PressurePortBlocked {
        from_s: 10.0,
        to_s: Some(25.0),
    });
    let out = run(&sc, 45);
    let (t0, xs) = transitions(&out, Rule::VerticalMiscompare);
    for (t, a) in &xs {
        eprintln!(
            "vertical_miscompare {t:.2} s: state {} {}",
            a.state,
            a.reason()
        );
    }
    let raised: Vec<_> = xs.iter().filter(|(_, a)| a.state == STATE_RAISED).collect();
    assert!(!raised.is_empty(), "no vertical alert");
    // Truth: the fault starts at 10 s; the BAHRS velocity is 2 m/s off (4 sigma of 0.5 m/s) and
    // its height rate 2 m/s (2.6 sigma of 0.76 m/s): the CUSUM declares within a few seconds.
    let vel = Rule::VerticalMiscompare.alert_id(att::VERTICAL_VELOCITY_DOWN as u32);
    let first_vel = raised.iter().find(|(_, a)| a.alert_id == vel);
    let (t_vel, a) = first_vel.expect("down velocity alert");
    assert!(*t_vel > 10.0 && *t_vel < 14.0, "{t_vel}");
    assert!(
        a.reason()
            .starts_with("vertical down velocity miscompare, BAHRS suspected"),
        "{}",
        a.reason()
    );
    assert!(a.reason().contains("BAHRS 0.00"), "{}", a.reason());
    for (t, _) in &raised {
        assert!(*t > 10.0, "raised before the fault: {t}");
    }
    // Cleared after the fault ends (25 s), each alert raised is cleared by the end.
    for (_, r) in &raised {
        let cleared = xs
            .iter()
            .find(|(t, a)| a.alert_id == r.alert_id && a.state == STATE_CLEARED && *t > 25.0);
        assert!(cleared.is_some(), "{} not cleared", r.reason());
    }
    // Isolated to the BAHRS's vertical channel: no attitude or inertial alert.
    for rule in [
        Rule::AttitudeMiscompare,
        Rule::UnitIsolated,
        Rule::InertialMiscompare,
    ] {
        let (_, others) = transitions(&out, rule);
        assert!(others.is_empty(), "{rule:?}: {:?}", others[0].1.reason());
    }
    // The payloads say what was compared: during the fault the BAHRS down velocity is 0 and
    // its pressure-height health "safe" (the unit does not notice).
    let mid: Vec<_> = out
        .attitude
        .iter()
        .filter(|p| (p.header.gps_time_ns - t0) / S == 20)
        .collect();
    assert!(!mid.is_empty());
    for p in mid {
        let v = &p.vertical[att::VERTICAL_VELOCITY_DOWN];
        assert_eq!(p.bahrs_vertical_health, [att::HEALTH_SAFE; 2]);
        if v.coverage == att::COVERAGE_COMPARED {
            assert_eq!(v.bahrs, 0.0);
            assert!((v.vn200 + 2.0).abs() < 0.3, "{}", v.vn200);
        }
    }
}

/// A BAHRS gyro bias ramp on body y (pitch rate) growing 0.05 deg/s each second from 10 s to
/// 30 s, with the BAHRS health still "safe": `inertial_miscompare` raises on angular rate y only
/// (subject 4) and clears after the bias is removed. The detection time from the fault start
/// is printed.
#[test]
fn gyro_bias_ramp_raises_inertial_miscompare_on_its_axis_and_clears() {
    let mut sc = builtin("nominal").unwrap();
    sc.faults.push(Fault::BahrsGyroBias {
        from_s: 10.0,
        to_s: Some(30.0),
        axis: BodyAxis::Y,
        bias_dps: 0.0,
        rate_dps_per_s: 0.05,
    });
    let out = run(&sc, 45);
    let (_, xs) = transitions(&out, Rule::InertialMiscompare);
    for (t, a) in &xs {
        eprintln!(
            "inertial_miscompare {t:.2} s: state {} {}",
            a.state,
            a.reason()
        );
    }
    let y = Rule::InertialMiscompare.alert_id((att::INERTIAL_ANGULAR_RATE_X + 1) as u32);
    assert!(
        xs.iter().all(|(_, a)| a.alert_id == y),
        "another axis alerted"
    );
    let (t_raise, a) = xs
        .iter()
        .find(|(_, a)| a.state == STATE_RAISED)
        .expect("raised");
    let detection_s = t_raise - 10.0;
    let bias_dps = 0.05 * detection_s;
    eprintln!(
        "gyro bias ramp 0.05 deg/s per s: detected {detection_s:.2} s after the fault start \
         (bias {bias_dps:.3} deg/s)"
    );
    // The statistical limit: sigma = 0.067 deg/s (params), k = 4.42 -> 0.30 deg/s per sample;
    // the CUSUM (slack 2 sigma) declares a growing bias earlier. Truth: the bias passes
    // 2 sigma (0.13 deg/s) at 2.7 s and the threshold at 6 s.
    assert!(detection_s > 2.0 && detection_s < 8.0, "{detection_s}");
    assert!(
        a.reason()
            .starts_with("inertial angular rate y miscompare (BAHRS health safe)"),
        "{}",
        a.reason()
    );
    let cleared = xs
        .iter()
        .find(|(t, a)| a.state == STATE_CLEARED && *t > 30.0);
    assert!(cleared.is_some(), "not cleared after the bias ends");
    assert_eq!(xs.len(), 2, "raised once, cleared once");
}

/// The same gyro bias while the BAHRS marks its angular rates "integrity risk": the signals are
/// excluded (not compared, reason `COVERAGE_INVALID`), the payload reports their health, and
/// `inertial_miscompare` stays silent; the specific force is still compared.
#[test]
fn angular_rates_the_bahrs_marks_at_risk_are_excluded_and_reported() {
    use vigil_sim::scenario::{HealthSignal, HealthWord};
    let mut sc = builtin("nominal").unwrap();
    sc.faults.push(Fault::BahrsGyroBias {
        from_s: 10.0,
        to_s: Some(30.0),
        axis: BodyAxis::Y,
        bias_dps: 0.0,
        rate_dps_per_s: 0.05,
    });
    sc.faults.push(Fault::BahrsHealth {
        from_s: 8.0,
        to_s: None,
        signal: HealthSignal::AngularRate,
        health: HealthWord::IntegrityRisk,
    });
    let out = run(&sc, 35);
    let (t0, xs) = transitions(&out, Rule::InertialMiscompare);
    assert!(xs.is_empty(), "{:?}", xs[0].1.reason());
    let late: Vec<_> = out
        .attitude
        .iter()
        .filter(|p| p.header.gps_time_ns - t0 > 9 * S)
        .collect();
    assert!(late.len() > 1000, "{}", late.len());
    let r = att::INERTIAL_ANGULAR_RATE_X;
    let mut compared_force = 0;
    for p in &late {
        if p.inertial[r].coverage == att::COVERAGE_NO_CHECK {
            continue; // a prompt payload without a fresh check
        }
        assert_eq!(
            p.bahrs_inertial_health[r..],
            [att::HEALTH_INTEGRITY_RISK; 3],
            "{p:?}"
        );
        for c in &p.inertial[r..] {
            assert_eq!(
                (c.verdict, c.coverage),
                (att::VERDICT_NOT_COMPARED, att::COVERAGE_INVALID)
            );
        }
        assert_eq!(p.bahrs_inertial_health[..r], [att::HEALTH_SAFE; 3]);
        if p.inertial[..r]
            .iter()
            .all(|c| c.coverage == att::COVERAGE_COMPARED)
        {
            compared_force += 1;
        }
    }
    assert!(compared_force * 10 > late.len() * 9, "{compared_force}");
}

/// The two built-in scenarios (`vigil sim --scenario bahrs-pressure-port | bahrs-gyro-bias`)
/// raise the alert their comments promise, after their faults start at 20 s (printed).
#[test]
fn builtin_bahrs_channel_scenarios_raise_their_alerts() {
    for (name, rule, subject, secs) in [
        (
            "bahrs-pressure-port",
            Rule::VerticalMiscompare,
            att::VERTICAL_VELOCITY_DOWN,
            40,
        ),
        (
            "bahrs-gyro-bias",
            Rule::InertialMiscompare,
            att::INERTIAL_ANGULAR_RATE_X + 1,
            40,
        ),
    ] {
        let out = run(&builtin(name).unwrap(), secs);
        let (_, xs) = transitions(&out, rule);
        let id = rule.alert_id(subject as u32);
        let first = xs
            .iter()
            .find(|(_, a)| a.state == STATE_RAISED)
            .unwrap_or_else(|| panic!("{name}: nothing raised"));
        eprintln!(
            "{name}: {} raised {:.2} s after the fault",
            rule.name(),
            first.0 - 20.0
        );
        assert_eq!(first.1.alert_id, id, "{name}: {}", first.1.reason());
        assert!(first.0 > 20.0 && first.0 < 28.0, "{name}: {}", first.0);
    }
}

/// The reasons of the active `vertical_miscompare` alerts in every integrity payload (the
/// active set, whose reason follows the condition while the alert is raised).
fn active_vertical_reasons(out: &Collected) -> Vec<String> {
    out.integrity
        .iter()
        .flat_map(|p| p.active_alerts[..p.active_alert_count as usize].iter())
        .filter(|a| Rule::of_alert(a.alert_id) == Some(Rule::VerticalMiscompare))
        .map(|a| vigil_bus::payload::read_text(&a.reason).to_string())
        .collect()
}

/// Issue 25 point 6, the TT-Multi-RF GNSS altitude as the third opinion. Pressure port blocked
/// from 10 s to 40 s of the nominal flight (climbing 2 m/s): the third opinion (20 s window,
/// TT altitude 1-sigma 4 m in the simulator) isolates the BAHRS once the BAHRS-TT rate
/// difference, growing 0.1 m/s each second, passes 4.42 x 0.29 = 1.26 m/s (about 13 s, then two
/// epochs): the payloads say BAHRS, never the VN-200, and the active alert's reason says
/// "BAHRS isolated". Before the fault nothing is isolated.
#[test]
fn blocked_pressure_port_is_isolated_to_the_bahrs_by_the_tt_gnss_altitude() {
    let mut sc = builtin("nominal").unwrap();
    sc.faults.push(Fault::PressurePortBlocked {
        from_s: 10.0,
        to_s: Some(40.0),
    });
    let out = run(&sc, 50);
    let t0 = out.attitude[0].header.gps_time_ns;
    let secs = |p: &att::AttitudePayload| (p.header.gps_time_ns - t0) as f64 / 1e9;
    let first = out
        .attitude
        .iter()
        .find(|p| p.vertical_isolated_unit != att::UNIT_NONE)
        .expect("isolated");
    eprintln!(
        "third opinion isolates unit {} at {:.2} s",
        first.vertical_isolated_unit,
        secs(first)
    );
    assert_eq!(first.vertical_isolated_unit, att::UNIT_BAHRS);
    assert!(secs(first) > 20.0 && secs(first) < 30.0, "{}", secs(first));
    for p in &out.attitude {
        assert_ne!(p.vertical_isolated_unit, att::UNIT_VN200, "{}", secs(p));
        if secs(p) < 10.0 {
            assert_eq!(p.vertical_isolated_unit, att::UNIT_NONE);
        }
        // Compared with the TT GNSS after the first window (the TT stream is present).
        if secs(p) > 25.0 {
            assert_eq!(
                p.vertical_tt_coverage,
                att::COVERAGE_COMPARED,
                "{}",
                secs(p)
            );
            assert!(
                (p.vertical_tt_rate_mps - 2.0).abs() < 1.5,
                "{}",
                p.vertical_tt_rate_mps
            );
        }
    }
    let reasons = active_vertical_reasons(&out);
    assert!(
        reasons
            .iter()
            .any(|r| r.contains("BAHRS isolated (TT GNSS agrees with VN-200)")),
        "{reasons:?}"
    );
    assert!(reasons.iter().all(|r| !r.contains("VN-200 isolated")));
}

/// Without the TT-Multi-RF's GNSS section the third opinion is "not compared, absent" on every
/// payload, nothing is isolated by it, and the alert keeps the premise-based attribution with
/// the reason stated.
#[test]
fn without_tt_gnss_the_vertical_alert_keeps_the_premise_and_says_why() {
    let mut sc = builtin("nominal").unwrap();
    sc.devices.ttmrf.as_mut().unwrap().gnss = false;
    sc.faults.push(Fault::PressurePortBlocked {
        from_s: 10.0,
        to_s: Some(25.0),
    });
    let out = run(&sc, 30);
    // Before the first cross-check the prompt output says "no check"; from then on "absent".
    let first = out
        .attitude
        .iter()
        .position(|p| p.vertical_tt_coverage == att::COVERAGE_ABSENT)
        .expect("absent");
    assert!(
        out.attitude[..first]
            .iter()
            .all(|p| p.vertical_tt_coverage == att::COVERAGE_NO_CHECK)
    );
    for p in &out.attitude {
        if p.header.gps_time_ns >= out.attitude[first].header.gps_time_ns {
            assert_eq!(p.vertical_tt_coverage, att::COVERAGE_ABSENT);
        }
        assert_eq!(p.vertical_isolated_unit, att::UNIT_NONE);
        assert!(p.vertical_tt_rate_mps.is_nan());
    }
    let (_, xs) = transitions(&out, Rule::VerticalMiscompare);
    let raised: Vec<_> = xs.iter().filter(|(_, a)| a.state == STATE_RAISED).collect();
    assert!(!raised.is_empty());
    for (_, a) in raised {
        assert!(
            a.reason()
                .contains("BAHRS suspected (VN-200 GNSS-aided; TT GNSS absent)"),
            "{}",
            a.reason()
        );
    }
}

/// The nominal flight (climb, turns; TT GNSS altitude with 4 m noise every second): the third
/// opinion is compared once its 20 s window has filled, neither of its comparisons fails, and
/// it isolates nothing. (No vertical alert of any kind on the 10-minute nominal flight is
/// asserted by `coverage_tests::nominal_flight_is_covered_and_raises_no_alert_of_any_rule`.)
#[test]
fn nominal_flight_third_opinion_compares_and_isolates_nothing() {
    let sc = builtin("nominal").unwrap();
    let out = run(&sc, 180);
    let t0 = out.attitude[0].header.gps_time_ns;
    let late: Vec<_> = out
        .attitude
        .iter()
        .filter(|p| p.header.gps_time_ns - t0 > 25 * S)
        .collect();
    let compared = late
        .iter()
        .filter(|p| p.vertical_tt_coverage == att::COVERAGE_COMPARED)
        .count();
    let max_ratio = late
        .iter()
        .flat_map(|p| p.vertical_tt.iter().map(|c| c.stat_ratio))
        .filter(|r| r.is_finite())
        .fold(0.0, f64::max);
    eprintln!(
        "nominal third opinion: compared on {compared} of {} payloads after 25 s, max ratio {max_ratio:.2}",
        late.len()
    );
    assert!(
        compared * 10 >= late.len() * 9,
        "{compared} of {}",
        late.len()
    );
    for p in &out.attitude {
        assert_eq!(p.vertical_isolated_unit, att::UNIT_NONE);
        for c in &p.vertical_tt {
            assert_ne!(c.verdict, att::VERDICT_FAIL);
        }
    }
}

/// Issue 25 point 6: the simulator's VN-200 vertical drifts from 10 s to 45 s (its altitude and
/// down velocity say a climb 3 m/s faster than the truth, INS still Tracking with a fix): the
/// down-velocity comparison fails (3 m/s, about 6 sigma), and the third opinion (the TT GNSS
/// agrees with the BAHRS) isolates the VN-200 once the VN-200-TT rate difference, growing
/// 3 / 20 = 0.15 m/s each second, passes 4.42 x 0.28 = 1.25 m/s (8.3 s, then two epochs);
/// never the BAHRS; the active alert's reason says "VN-200 isolated".
#[test]
fn drifting_vn200_vertical_is_isolated_to_the_vn200_by_the_tt_gnss_altitude() {
    let mut sc = builtin("nominal").unwrap();
    sc.faults.push(Fault::Vn200VerticalDrift {
        from_s: 10.0,
        to_s: Some(45.0),
        rate_mps: 3.0,
    });
    let out = run(&sc, 50);
    let t0 = out.attitude[0].header.gps_time_ns;
    let secs = |p: &att::AttitudePayload| (p.header.gps_time_ns - t0) as f64 / 1e9;
    let first = out
        .attitude
        .iter()
        .find(|p| p.vertical_isolated_unit != att::UNIT_NONE)
        .expect("isolated");
    eprintln!(
        "third opinion isolates unit {} at {:.2} s",
        first.vertical_isolated_unit,
        secs(first)
    );
    assert_eq!(first.vertical_isolated_unit, att::UNIT_VN200);
    assert!(secs(first) > 18.0 && secs(first) < 25.0, "{}", secs(first));
    for p in &out.attitude {
        assert_ne!(p.vertical_isolated_unit, att::UNIT_BAHRS, "{}", secs(p));
    }
    let reasons = active_vertical_reasons(&out);
    assert!(
        reasons
            .iter()
            .any(|r| r.contains("VN-200 isolated (TT GNSS agrees with BAHRS)")),
        "{reasons:?}"
    );
}
