//! Behaviour of the whole cross-check on synthetic streams (issue 8, "Done when").

use super::checker::AttitudeChecker;
use super::isolation::{Isolation, PairVerdict, Unit};
use super::params::CheckParams;
use super::record::AttitudeRecord;
use super::synthetic::{Event, Scenario, Stream};
use crate::magnetic::{Declination, FixedDeclination, MagneticZone, Wmm};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// A fixed declination of `decl_deg`, 0.3 deg 1-sigma, in a normal compass zone.
pub(super) fn fixed(decl_deg: f64) -> Box<FixedDeclination> {
    Box::new(FixedDeclination(Declination {
        declination_rad: decl_deg * DEG,
        sigma_rad: 0.3 * DEG,
        horizontal_nt: 20_000.0,
        zone: MagneticZone::Normal,
    }))
}

/// Runs a scenario through a checker; returns (time from start s, record).
fn run(sc: Scenario, checker: &mut AttitudeChecker) -> Vec<(f64, AttitudeRecord)> {
    let mut out = Vec::new();
    let t0 = sc.t0_gps_ns;
    let take = |c: &mut AttitudeChecker, out: &mut Vec<(f64, AttitudeRecord)>| {
        while let Some(r) = c.next_record() {
            out.push(((r.t_gps_ns - t0) as f64 * 1e-9, r));
        }
    };
    for e in Stream::new(sc) {
        e.push_into(checker);
        take(checker, &mut out);
    }
    checker.finish();
    take(checker, &mut out);
    out
}

/// A checker with the default parameters and `model`.
pub(super) fn checker_with(
    model: Box<dyn crate::magnetic::DeclinationModel + Send>,
) -> AttitudeChecker {
    AttitudeChecker::new(CheckParams::default(), model).unwrap()
}

fn first(recs: &[(f64, AttitudeRecord)], f: impl Fn(&AttitudeRecord) -> bool) -> Option<f64> {
    recs.iter().find(|(_, r)| f(r)).map(|(t, _)| *t)
}

#[test]
fn one_record_per_bahrs_sample_in_order_with_the_json_contract() {
    let sc = Scenario {
        duration_s: 10.0,
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    // 10 s at 50 Hz.
    assert_eq!(recs.len(), 500);
    assert!(recs.windows(2).all(|w| w[0].1.t_gps_ns < w[1].1.t_gps_ns));
    let v = serde_json::to_value(&recs[300].1).unwrap();
    assert_eq!(v["kind"], "attitude_check");
    assert_eq!(v["fault"], false);
    assert!(v["isolated"].is_null());
    assert!(v["t_gps_ns"].is_i64());
    assert!(v["pairs"]["bahrs_vn200"]["roll"]["comparison"]["stat_ratio"].is_f64());
    assert_eq!(v["pairs"]["bahrs_vn200"]["roll"]["verdict"], "pass");
    assert!(v["bahrs"]["gates"]["roll"].is_null());
}

#[test]
fn declination_is_applied_to_the_magnetic_units() {
    // The magnetic units see true - 3 deg; with the declination applied their true headings
    // agree with the VN-200 to within the noise, and the magnetic ones read 3 deg less.
    let sc = Scenario {
        duration_s: 5.0,
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    let (_, r) = &recs[200];
    let dh = r.pairs.bahrs_vn200.heading.comparison.unwrap().diff_deg;
    assert!(dh.abs() < 3.0, "{dh}");
    let b = r.bahrs.heading_deg.unwrap();
    let bm = r.bahrs.heading_mag_deg.unwrap();
    assert!((super::angles::angle_diff(b * DEG, bm * DEG) / DEG - 3.0).abs() < 1e-6);
    // Mean heading difference over 4 s is near 0 (not 3): the offset is removed.
    let mean: f64 = recs[50..]
        .iter()
        .map(|(_, r)| r.pairs.bahrs_vn200.heading.comparison.unwrap().diff_deg)
        .sum::<f64>()
        / (recs.len() - 50) as f64;
    assert!(mean.abs() < 0.3, "{mean}");
    // Without declination (the wrong model), the same stream shows the -3 deg offset.
    let recs = run(sc, &mut checker_with(fixed(0.0)));
    let mean: f64 = recs[50..]
        .iter()
        .map(|(_, r)| r.pairs.bahrs_vn200.heading.comparison.unwrap().diff_deg)
        .sum::<f64>()
        / (recs.len() - 50) as f64;
    assert!((mean + 3.0).abs() < 0.3, "{mean}");
}

/// Issue 25, acceptance "the roll-fault scenario still isolates the BAHRS within 1.5 s of
/// crossing the limit, on the host-clock fallback as well as on PPS": the same 0.5 deg/s roll
/// ramp from 60 s (crossing 6 deg at 72 s) with the BAHRS stamped as by a host-clock fallback
/// (2 ms 1-sigma errors, stated as such: twice the README's "about 1 ms worse"), and on PPS.
#[test]
fn the_roll_fault_is_isolated_in_time_on_pps_and_on_a_host_clock_fallback() {
    let mut figures = Vec::new();
    for sigma in [None, Some(2e6)] {
        let sc = Scenario {
            duration_s: 80.0,
            roll_ramp: Some((60.0, 0.5)),
            bahrs_time_sigma_ns: sigma,
            ..Default::default()
        };
        let recs = run(sc, &mut checker_with(fixed(3.0)));
        assert!(recs.len() > 79 * 50, "{}", recs.len());
        assert!(
            recs.iter()
                .filter(|(t, _)| *t < 60.0)
                .all(|(_, r)| !r.fault)
        );
        let iso = first(&recs, |r| r.isolated == Some(Unit::Bahrs)).unwrap();
        assert!(iso <= 72.0 + 1.5 && iso > 60.0, "{sigma:?}: {iso}");
        figures.push((sigma, iso - 72.0));
    }
    eprintln!("BAHRS isolated (s after the 6 deg crossing; negative: before): {figures:?}");
}

#[test]
fn bahrs_attitude_fault_is_isolated_in_time_and_the_statistical_test_fires_first() {
    // Roll bias ramping at 0.5 deg/s from t = 60 s: the error crosses 6 deg at t = 72 s.
    // Integrity risk on roll from t = 90 s.
    let sc = Scenario {
        duration_s: 100.0,
        roll_ramp: Some((60.0, 0.5)),
        integrity_risk_from_s: Some(90.0),
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    // Nothing before the fault.
    assert!(
        recs.iter()
            .filter(|(t, _)| *t < 60.0)
            .all(|(_, r)| !r.fault)
    );
    let bv = |r: &AttitudeRecord| r.pairs.bahrs_vn200.roll;
    let stat_first = first(&recs, |r| bv(r).stat_exceeded).unwrap();
    let fixed_first = first(&recs, |r| bv(r).fixed_exceeded).unwrap();
    // The fixed comparator trips when the error (bias + noise of ~0.16 deg) crosses 6 deg:
    // t = 72 s +- a few noise sigmas / 0.5 deg/s.
    assert!((71.0..73.0).contains(&fixed_first), "{fixed_first}");
    // The statistical test, with sigma = sqrt(0.3^2 + 0.1^2 + 2 x 0.1^2) = 0.346 deg, trips near
    // 4.42 x 0.346 = 1.53 deg, i.e. about t = 63 s: earlier.
    assert!(stat_first < fixed_first - 5.0, "{stat_first} {fixed_first}");
    assert!((61.5..65.0).contains(&stat_first), "{stat_first}");
    // BAHRS isolated within 1.5 s of the 6 deg crossing (here well before it), never another.
    let iso = first(&recs, |r| r.isolated == Some(Unit::Bahrs)).unwrap();
    assert!(iso <= 72.0 + 1.5 && iso > 60.0, "{iso}");
    assert!(
        recs.iter()
            .all(|(_, r)| r.isolated != Some(Unit::Vn200) && r.isolated != Some(Unit::Watson))
    );
    // The fixed comparator alone declares about 1.5 s after its own first exceedance: the
    // low-passed ratio lags a ramp by the filter's time constant (0.5 s), then the counter needs
    // 1 s; noise moves it by a tenth or two. (So the 1.5 s requirement rests on the statistical
    // detector, which has declared long before.)
    let fixed_fault = first(&recs, |r| bv(r).fixed_fault).unwrap();
    assert!(
        (fixed_first + 1.2..fixed_first + 1.9).contains(&fixed_fault),
        "{fixed_first} {fixed_fault}"
    );
    eprintln!(
        "stat {stat_first:.2} s, fixed {fixed_first:.2} s, isolated {iso:.2} s, fixed fault {fixed_fault:.2} s"
    );
    // From isolation until t = 90 s, the roll isolation stays on the BAHRS and the vote uses
    // the VN-200 and Watson only.
    let (_, r) = recs.iter().find(|(t, _)| *t >= 80.0).unwrap();
    assert_eq!(r.isolation.roll, Isolation::Isolated(Unit::Bahrs));
    let vr = r.voted.roll.as_ref().unwrap();
    assert_eq!(vr.used, vec![Unit::Vn200, Unit::Watson]);
    // Integrity risk: raised at the first sample with health 10 (t = 90.00 s), not before.
    let ir = first(&recs, |r| r.bahrs_integrity_risk).unwrap();
    assert!((ir - 90.0).abs() < 1e-6, "{ir}");
    let (_, r) = recs.iter().find(|(t, _)| *t >= 90.0).unwrap();
    assert_eq!(
        r.bahrs.gates.roll,
        Some(super::gates::GateReason::HealthIntegrityRisk)
    );
    assert_eq!(r.pairs.bahrs_vn200.roll.verdict, PairVerdict::NotCompared);
}

#[test]
fn nominal_hour_declares_no_fault() {
    // One simulated hour, WMM declination at the scenario's place and date.
    let sc = Scenario {
        duration_s: 3600.0,
        seed: 7,
        ..Default::default()
    };
    let d = crate::magnetic::DeclinationModel::declination(
        &Wmm,
        sc.lla[0],
        sc.lla[1],
        sc.lla[2],
        sc.t0_gps_ns,
    )
    .unwrap();
    let sc = Scenario {
        declination_deg: d.declination_rad / DEG,
        ..sc
    };
    let recs = run(sc, &mut checker_with(Box::new(Wmm)));
    assert_eq!(recs.len(), 180_000);
    let faults = recs.iter().filter(|(_, r)| r.fault).count();
    let magnetic = recs.iter().filter(|(_, r)| r.magnetic_disturbance).count();
    let vertical = recs
        .iter()
        .filter(|(_, r)| {
            r.vertical.velocity_down.verdict == PairVerdict::Fail
                || r.vertical.height_rate.verdict == PairVerdict::Fail
        })
        .count();
    assert_eq!((faults, magnetic, vertical), (0, 0, 0));
    // Everything was compared (no gate closed in a nominal run after the first second).
    let not_compared = recs[50..]
        .iter()
        .filter(|(_, r)| r.pairs.bahrs_watson.heading.verdict == PairVerdict::NotCompared)
        .count();
    assert_eq!(not_compared, 0);
    assert!(recs[100].1.declination.is_some());
}

#[test]
fn magnetic_disturbance_is_classified_not_a_vn200_fault() {
    let sc = Scenario {
        duration_s: 90.0,
        magnetic_disturbance: Some((60.0, 15.0)),
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    let md = first(&recs, |r| r.magnetic_disturbance).unwrap();
    assert!((60.0..62.0).contains(&md), "{md}");
    let (_, r) = recs.iter().find(|(t, _)| *t >= 70.0).unwrap();
    assert_eq!(r.isolation.heading, Isolation::MagneticDisturbance);
    assert_eq!(r.isolation.roll, Isolation::NoFault);
    assert!(r.isolated.is_none());
    assert!(recs.iter().all(|(_, r)| r.isolated.is_none()));
}

#[test]
fn gnss_lost_keeps_the_attitude_comparison_going() {
    let sc = Scenario {
        duration_s: 90.0,
        gnss_lost_from_s: Some(60.0),
        ..Default::default()
    };
    let mut c = checker_with(Box::new(Wmm));
    // The ownship's fallback GNSS position keeps the declination available.
    c.set_fallback_position(Some(sc.lla));
    let recs = run(sc, &mut c);
    let after: Vec<_> = recs.iter().filter(|(t, _)| *t > 61.0).collect();
    assert!(!after.is_empty());
    for (_, r) in &after {
        assert!(!r.vn200_healthy);
        assert_eq!(r.pairs.bahrs_vn200.roll.verdict, PairVerdict::Pass);
        assert_eq!(r.pairs.bahrs_vn200.heading.verdict, PairVerdict::Pass);
        assert!(r.vn200.gates.roll.is_none());
        assert!(r.declination.is_some());
        // No VN-200 velocity in GnssLost: the vertical channel is not compared.
        assert_eq!(r.vertical.velocity_down.verdict, PairVerdict::NotCompared);
        assert!(!r.fault);
    }
}

#[test]
fn a_silent_watson_goes_stale_and_records_keep_coming() {
    let sc = Scenario {
        duration_s: 40.0,
        watson_stops_s: Some(30.0),
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    assert_eq!(recs.len(), 2000);
    let (_, r) = recs.iter().find(|(t, _)| *t >= 31.0).unwrap();
    assert_eq!(r.watson.gates.roll, Some(super::gates::GateReason::Stale));
    assert_eq!(r.pairs.bahrs_watson.roll.verdict, PairVerdict::NotCompared);
    assert_eq!(r.pairs.bahrs_vn200.roll.verdict, PairVerdict::Pass);
    assert_eq!(r.isolation.roll, Isolation::NoFault);
    // Just before the silence (0.25 s horizon): still fresh.
    let (_, r) = recs.iter().find(|(t, _)| *t >= 30.1).unwrap();
    assert!(r.watson.gates.roll.is_none());
}

#[test]
fn a_frozen_vn200_is_not_compared() {
    let mut c = checker_with(fixed(3.0));
    let sc = Scenario {
        duration_s: 20.0,
        ..Default::default()
    };
    let t0 = sc.t0_gps_ns;
    let mut held = None;
    let mut recs = Vec::new();
    for e in Stream::new(sc) {
        match e {
            Event::Bahrs(b) => c.push_bahrs(b),
            Event::Vn200(mut v) => {
                // From t = 10 s the VN-200 repeats the same attitude.
                if v.t_gps_ns - t0 >= 10_000_000_000 {
                    let h = *held.get_or_insert(v.attitude);
                    v.attitude = h;
                }
                c.push_vn200(v)
            }
            Event::Watson(w) => c.push_watson(w),
        }
        while let Some(r) = c.next_record() {
            recs.push(((r.t_gps_ns - t0) as f64 * 1e-9, r));
        }
    }
    let frozen = first(&recs, |r| {
        r.vn200.gates.roll == Some(super::gates::GateReason::Frozen)
    })
    .unwrap();
    // Identical for more than 1 s: from just after t = 11 s.
    assert!((11.0..11.1).contains(&frozen), "{frozen}");
}

#[test]
fn a_vn200_roll_fault_and_a_watson_pitch_fault_are_isolated() {
    let sc = Scenario {
        duration_s: 40.0,
        vn200_roll_step: Some((20.0, 8.0)),
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    let iso = first(&recs, |r| r.isolated == Some(Unit::Vn200)).unwrap();
    // A step of 8 deg: every detector exceeds at once. The CUSUM (z clamped to 4.42, slack 2:
    // +2.42 per sample, limit 60) declares after 25 samples = 0.5 s, before the 1 s counter.
    assert!((20.45..20.6).contains(&iso), "{iso}");
    let (_, r) = recs.last().unwrap();
    assert_eq!(r.isolation.roll, Isolation::Isolated(Unit::Vn200));
    assert_eq!(r.isolation.pitch, Isolation::NoFault);
    // The vote leaves the VN-200 out on roll and keeps it on pitch and heading.
    assert_eq!(
        r.voted.roll.as_ref().unwrap().used,
        vec![Unit::Bahrs, Unit::Watson]
    );
    assert_eq!(r.voted.pitch.as_ref().unwrap().used.len(), 3);
    assert!(recs.iter().all(|(_, r)| r.isolated != Some(Unit::Bahrs)));

    let sc = Scenario {
        duration_s: 40.0,
        watson_pitch_step: Some((20.0, 6.0)),
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    let (_, r) = recs.last().unwrap();
    assert_eq!(r.isolated, Some(Unit::Watson));
    assert_eq!(r.isolation.pitch, Isolation::Isolated(Unit::Watson));
    assert!(r.fault);
}

#[test]
fn two_faulty_units_are_a_multiple_fault() {
    // VN-200 roll +8 deg and Watson roll -8 deg: no pair agrees on roll.
    let sc = Scenario {
        duration_s: 30.0,
        vn200_roll_step: Some((10.0, 8.0)),
        roll_ramp: Some((10.0, 100.0)), // BAHRS roll off by far more, at once
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    let (_, r) = recs.last().unwrap();
    assert_eq!(r.isolation.roll, Isolation::MultipleFault);
    assert!(r.fault && r.multiple_fault && r.isolated.is_none());
}

#[test]
fn mounting_offsets_are_configured_away() {
    // The BAHRS is mounted 3 deg rolled and 2 deg pitched: without the offsets it fails against
    // the others on roll; with them, nothing.
    let sc = Scenario {
        duration_s: 30.0,
        bahrs_mounting_deg: [0.0, 2.0, 3.0],
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    assert_eq!(recs.last().unwrap().1.isolated, Some(Unit::Bahrs));
    let mut p = CheckParams::default();
    p.mounting_bahrs.pitch_deg = 2.0;
    p.mounting_bahrs.roll_deg = 3.0;
    let mut c = AttitudeChecker::new(p, fixed(3.0)).unwrap();
    let recs = run(sc, &mut c);
    assert!(recs.iter().all(|(_, r)| !r.fault));
    let d = recs[1000]
        .1
        .pairs
        .bahrs_vn200
        .roll
        .comparison
        .unwrap()
        .diff_deg;
    assert!(d.abs() < 1.0, "{d}");
}

#[test]
fn heading_checks_are_suppressed_near_the_magnetic_poles() {
    for (zone, h) in [
        (MagneticZone::Caution, 4000.0),
        (MagneticZone::Blackout, 1000.0),
    ] {
        let model = FixedDeclination(Declination {
            declination_rad: 3.0 * DEG,
            sigma_rad: 5.0 * DEG,
            horizontal_nt: h,
            zone,
        });
        let sc = Scenario {
            duration_s: 5.0,
            // Even a large heading disturbance raises nothing there.
            magnetic_disturbance: Some((1.0, 30.0)),
            ..Default::default()
        };
        let recs = run(sc, &mut checker_with(Box::new(model)));
        for (_, r) in &recs[100..] {
            assert_eq!(
                r.bahrs.gates.heading,
                Some(super::gates::GateReason::MagneticPole)
            );
            assert_eq!(
                r.watson.gates.heading,
                Some(super::gates::GateReason::MagneticPole)
            );
            assert!(r.vn200.gates.heading.is_none());
            assert_eq!(
                r.pairs.bahrs_vn200.heading.verdict,
                PairVerdict::NotCompared
            );
            assert_eq!(
                r.pairs.bahrs_watson.heading.verdict,
                PairVerdict::NotCompared
            );
            assert_eq!(r.pairs.bahrs_vn200.roll.verdict, PairVerdict::Pass);
            assert!(!r.fault && !r.magnetic_disturbance);
            // The voted heading is the VN-200's alone.
            assert_eq!(r.voted.heading.as_ref().unwrap().used, vec![Unit::Vn200]);
        }
    }
}

#[test]
fn arbitrary_samples_never_panic_and_non_finite_values_are_gated() {
    use super::samples::{Vn200Sample, WatsonSample};
    use super::synthetic::Noise;
    use vigil_drivers::vn200::status::InsStatus;
    let mut n = Noise::new(99);
    let mut c = checker_with(Box::new(Wmm));
    let base = Scenario::default().t0_gps_ns;
    let wild = |n: &mut Noise| match (n.gauss() * 10.0) as i64 {
        0 => f64::NAN,
        1 => f64::INFINITY,
        2 => -1e300,
        _ => n.gauss() * 4.0,
    };
    let mut bahrs = Stream::new(Scenario {
        duration_s: 200.0,
        ..Default::default()
    })
    .filter_map(|e| match e {
        Event::Bahrs(b) => Some(b),
        _ => None,
    });
    let mut count = 0;
    for i in 0..20_000i64 {
        // Times jitter backwards and forwards, sometimes wildly.
        let jitter = (n.gauss() * 3e7) as i64;
        let t = if i % 997 == 0 {
            i64::MAX - 5
        } else {
            base + i * 7_000_000 + jitter
        };
        match i % 3 {
            0 => {
                let mut b = bahrs.next().unwrap();
                b.t_gps_ns = t;
                b.accuracy_rad = Some([Some(wild(&mut n).abs()), None, Some(0.01)]);
                b.rates_radps = Some([wild(&mut n), wild(&mut n), wild(&mut n)]);
                c.push_bahrs(b);
            }
            1 => c.push_vn200(Vn200Sample {
                t_gps_ns: t,
                sigma_ns: wild(&mut n),
                attitude: super::angles::from_ypr(wild(&mut n), wild(&mut n), wild(&mut n)),
                ypr_sigma_rad: Some([wild(&mut n), 0.0, -1.0]),
                ins_status: InsStatus((n.gauss() * 1000.0) as i64 as u16),
                imu_status: None,
                rates_radps: Some([wild(&mut n), 0.0, 0.0]),
                accel_mps2: None,
                lla: Some([wild(&mut n) * 30.0, wild(&mut n) * 50.0, wild(&mut n)]),
                vel_ned_mps: Some([wild(&mut n), 0.0, wild(&mut n)]),
                pos_u_m: None,
                vel_u_mps: Some(wild(&mut n)),
            }),
            _ => c.push_watson(WatsonSample {
                t_gps_ns: t,
                sigma_ns: 1e6,
                roll_rad: wild(&mut n),
                pitch_rad: wild(&mut n),
                heading_mag_rad: wild(&mut n),
                over_range: n.gauss() > 1.0,
                rates_radps: [wild(&mut n); 3],
            }),
        }
        while let Some(r) = c.next_record() {
            count += 1;
            // A compared pair always carries finite numbers.
            for pr in [
                r.pairs.bahrs_vn200,
                r.pairs.bahrs_watson,
                r.pairs.vn200_watson,
            ] {
                for ax in [pr.roll, pr.pitch, pr.heading] {
                    if let Some(cmp) = ax.comparison {
                        assert!(cmp.diff_deg.is_finite(), "{cmp:?}");
                    }
                }
            }
            serde_json::to_string(&r).unwrap();
        }
    }
    c.finish();
    while c.next_record().is_some() {
        count += 1;
    }
    assert_eq!(count, 6667);
}

#[test]
fn with_two_units_a_disagreement_is_detected_but_not_isolated() {
    // No Watson at all: the BAHRS roll ramp is detected on the one pair left, and nobody is
    // blamed (nothing says which of the two is right).
    let sc = Scenario {
        duration_s: 80.0,
        roll_ramp: Some((60.0, 0.5)),
        watson_stops_s: Some(0.0),
        ..Default::default()
    };
    let recs = run(sc, &mut checker_with(fixed(3.0)));
    assert_eq!(recs.len(), 4000);
    assert!(
        recs.iter()
            .filter(|(t, _)| *t < 60.0)
            .all(|(_, r)| !r.fault)
    );
    let (_, r) = recs.last().unwrap();
    assert_eq!(r.watson.gates.roll, Some(super::gates::GateReason::NoData));
    assert_eq!(r.isolation.roll, Isolation::DetectedNotIsolated);
    assert!(r.fault && r.isolated.is_none() && !r.multiple_fault);
}

/// The first BAHRS, VN-200 and Watson samples of the default synthetic stream, as templates for
/// hand-placed samples.
pub(super) fn templates() -> (
    super::samples::BahrsSample,
    super::samples::Vn200Sample,
    super::samples::WatsonSample,
) {
    let (mut b, mut v, mut w) = (None, None, None);
    for e in Stream::new(Scenario::default()) {
        match e {
            Event::Bahrs(s) => b = b.or(Some(s)),
            Event::Vn200(s) => v = v.or(Some(s)),
            Event::Watson(s) => w = w.or(Some(s)),
        }
        if let (Some(b), Some(v), Some(w)) = (b, v, w) {
            return (b, v, w);
        }
    }
    unreachable!("the default stream has all three units")
}

/// A declination model that counts its queries and answers with a value that names the position
/// asked about: declination (deg) = 10 x latitude + longitude.
struct Counting(std::sync::Arc<std::sync::atomic::AtomicUsize>);

impl crate::magnetic::DeclinationModel for Counting {
    fn declination(
        &self,
        lat_deg: f64,
        lon_deg: f64,
        _height_m: f64,
        _t_gps_ns: i64,
    ) -> Result<Declination, crate::magnetic::MagneticError> {
        self.0.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        Ok(Declination {
            declination_rad: (10.0 * lat_deg + lon_deg) * DEG,
            sigma_rad: 0.3 * DEG,
            horizontal_nt: 20_000.0,
            zone: MagneticZone::Normal,
        })
    }
}

/// The declination is queried again only after `declination_refresh_s` (strictly), or once the
/// position has moved more than 0.1 deg of latitude or 0.1 deg of longitude scaled by cos(lat)
/// (strictly); in between the cached value is used.
#[test]
fn the_declination_is_refreshed_after_its_period_or_a_move_beyond_a_tenth_of_a_degree() {
    let calls = std::sync::Arc::new(std::sync::atomic::AtomicUsize::new(0));
    let params = CheckParams::default();
    assert_eq!(params.declination_refresh_s, 60.0);
    let mut c = AttitudeChecker::new(params, Box::new(Counting(calls.clone()))).unwrap();
    let (b0, v0, _) = templates();
    let t0 = b0.t_gps_ns;
    // (time from the first check s, latitude deg, longitude deg, queries so far, the declination
    // in use deg = 10 lat + lon of the position last queried).
    let steps: [(f64, f64, f64, usize, f64); 10] = [
        (0.0, 0.0, 0.0, 1, 0.0),
        // Same place, 2 s later: cached.
        (2.0, 0.0, 0.0, 1, 0.0),
        // Exactly 0.1 deg north, then exactly 0.1 deg east (cos 0 = 1): not beyond, cached.
        (3.0, 0.1, 0.0, 1, 0.0),
        (4.0, 0.0, 0.1, 1, 0.0),
        // 0.2 deg north: queried there.
        (5.0, 0.2, 0.0, 2, 2.0),
        // Exactly the refresh period after that query: cached; 1 ns later: queried.
        (65.0, 0.2, 0.0, 2, 2.0),
        (65.000_000_001, 0.2, 0.0, 3, 2.0),
        // 0.2 deg east: queried.
        (66.0, 0.2, 0.2, 4, 2.2),
        // At 60 deg north (a new query), 0.15 deg of longitude is 0.075 deg scaled by
        // cos 60 deg = 0.5: cached.
        (67.0, 60.0, 0.2, 5, 600.2),
        (68.0, 60.0, 0.35, 5, 600.2),
    ];
    for (t_s, lat, lon, queries, decl_deg) in steps {
        let t = t0 + (t_s * 1e9).round() as i64;
        let mut v = v0;
        v.t_gps_ns = t;
        v.lla = Some([lat, lon, 100.0]);
        assert!(v.ins_status.position_valid());
        c.push_vn200(v);
        let mut b = b0;
        b.t_gps_ns = t;
        let rec = c.compare_at(&b, false);
        let what = format!("at {t_s} s, ({lat}, {lon})");
        assert_eq!(
            calls.load(std::sync::atomic::Ordering::Relaxed),
            queries,
            "{what}"
        );
        let used = rec.declination.expect("a declination");
        assert!(
            (used.declination_deg - decl_deg).abs() < 1e-9,
            "{what}: {used:?}"
        );
        assert!((used.sigma_deg - 0.3).abs() < 1e-12, "{what}: {used:?}");
    }
}

/// Pushes samples at `t` ns (BAHRS always; VN-200 and Watson when asked) and says whether the
/// BAHRS sample at the front is compared now.
fn ready_after(c: &mut AttitudeChecker, b_ns: &[i64], vn_ns: &[i64], watson_ns: &[i64]) -> bool {
    let (b0, v0, w0) = templates();
    for &t in b_ns {
        c.push_bahrs(super::samples::BahrsSample { t_gps_ns: t, ..b0 });
    }
    for &t in vn_ns {
        c.push_vn200(super::samples::Vn200Sample { t_gps_ns: t, ..v0 });
    }
    for &t in watson_ns {
        c.push_watson(super::samples::WatsonSample { t_gps_ns: t, ..w0 });
    }
    c.next_record().is_some()
}

/// A BAHRS sample is compared once the VN-200 and the Watson have each reached its time (at it
/// counts), or once the newest sample of any unit is more than `max_age_periods` of that unit's
/// period past it (the unit is then compared as missing); not before.
#[test]
fn a_bahrs_sample_waits_for_both_partners_or_their_horizon() {
    // Horizons of exactly representable length: 2 x 0.125 s = 250 ms for the Watson and
    // 2 x 0.0625 s = 125 ms for the VN-200.
    let params = CheckParams {
        max_age_periods: 2.0,
        vn200_period_s: 0.0625,
        watson_period_s: 0.125,
        ..CheckParams::default()
    };
    let new = || AttitudeChecker::new(params, fixed(3.0)).unwrap();
    let t = templates().0.t_gps_ns;
    assert_eq!(new().params(), &params);
    // Both partners exactly at the BAHRS time: compared.
    assert!(ready_after(&mut new(), &[t], &[t], &[t]));
    // Only the VN-200 there, the Watson silent: waits...
    assert!(!ready_after(&mut new(), &[t], &[t], &[]));
    // ...until a newer sample is more than the Watson's 250 ms past it, not at 250 ms.
    let mut c = new();
    assert!(!ready_after(&mut c, &[t], &[t + 250_000_000], &[]));
    assert!(ready_after(&mut c, &[], &[t + 250_000_001], &[]));
    // The Watson there, the VN-200 silent: compared once the 125 ms VN-200 horizon has passed.
    let mut c = new();
    assert!(!ready_after(&mut c, &[t], &[], &[t + 125_000_000]));
    assert!(ready_after(&mut c, &[], &[], &[t + 125_000_001]));
}

/// With neither partner and no time passing, at most 256 BAHRS samples wait; the 257th forces the
/// oldest out (a bound on memory when both partners are silent and the BAHRS clock stands still).
#[test]
fn at_most_256_bahrs_samples_wait() {
    let mut c = checker_with(fixed(3.0));
    let t = templates().0.t_gps_ns;
    // 256 samples 1 ns apart: far inside every horizon.
    let first: Vec<i64> = (0..256).map(|k| t + k).collect();
    assert!(!ready_after(&mut c, &first, &[], &[]));
    assert!(ready_after(&mut c, &[t + 256], &[], &[]));
}

/// A TT-Multi-RF GNSS epoch reaches the vertical third opinion: one without a fix is reported as
/// such, not as an absent receiver.
#[test]
fn a_tt_gnss_epoch_reaches_the_vertical_third_opinion() {
    use super::vertical::TtNotCompared;
    let third = |epoch: bool| {
        let mut c = checker_with(fixed(3.0));
        let (b, v, _) = templates();
        if epoch {
            c.push_tt_gnss(b.t_gps_ns, None);
        }
        c.push_vn200(v);
        c.compare_at(&b, false).vertical.third.not_compared
    };
    assert_eq!(third(false), Some(TtNotCompared::Absent));
    assert_eq!(third(true), Some(TtNotCompared::NoFix));
}

fn assert_sigmas(got: Option<[f64; 3]>, want: [f64; 3], what: &str) {
    let got = got.unwrap_or_else(|| panic!("{what}: no sigmas"));
    for (g, w) in got.iter().zip(want) {
        assert!((g - w).abs() < 1e-9, "{what}: {got:?}, want {want:?}");
    }
}

/// Each unit's 1-sigma per axis (roll, pitch, heading; deg) as the record states it: from the
/// unit's own report where it has one, else from the configured defaults; and the heading pair
/// BAHRS-VN-200 adds the declination's variance to both units' and both mountings'.
#[test]
fn each_units_sigmas_come_from_its_report_or_the_defaults_and_add_up_in_a_pair() {
    use super::samples::{BahrsSample, Vn200Sample, WatsonSample};
    let (b0, v0, w0) = templates();
    let t = b0.t_gps_ns;
    // No timing term: every sample perfectly aligned.
    let b0 = BahrsSample {
        sigma_ns: 0.0,
        heading_mag_rad: 30.0 * DEG,
        ..b0
    };
    let v0 = Vn200Sample {
        t_gps_ns: t,
        sigma_ns: 0.0,
        ..v0
    };
    let w0 = WatsonSample {
        t_gps_ns: t,
        sigma_ns: 0.0,
        ..w0
    };
    let check = |b: BahrsSample, v: Vn200Sample| {
        let mut c = checker_with(fixed(30.0));
        c.push_vn200(v);
        c.push_watson(w0);
        c.compare_at(&b, false)
    };

    // Nothing reported: the defaults of the parameter table (BAHRS tilt 0.5, heading 2; VN-200
    // tilt 0.3, heading 1; Watson tilt 0.75, heading 2).
    let r = check(
        BahrsSample {
            accuracy_rad: None,
            ..b0
        },
        Vn200Sample {
            ypr_sigma_rad: None,
            ..v0
        },
    );
    assert_sigmas(r.bahrs.sigma_deg, [0.5, 0.5, 2.0], "BAHRS defaults");
    assert_sigmas(r.vn200.sigma_deg, [0.3, 0.3, 1.0], "VN-200 defaults");
    assert_sigmas(r.watson.sigma_deg, [0.75, 0.75, 2.0], "Watson");

    // Reported: the BAHRS north 1, east 2, heading 3 deg; at magnetic heading 30 deg plus the
    // 30 deg declination (true heading psi = 60 deg, cos^2 = 1/4, sin^2 = 3/4) roll takes
    // 1/4 x 1 + 3/4 x 4 = 3.25 deg^2 and pitch 3/4 x 1 + 1/4 x 4 = 1.75 deg^2. The VN-200's
    // yaw, pitch, roll 0.5, 0.2, 0.1 deg.
    let r = check(
        BahrsSample {
            accuracy_rad: Some([Some(DEG), Some(2.0 * DEG), Some(3.0 * DEG)]),
            ..b0
        },
        Vn200Sample {
            ypr_sigma_rad: Some([0.5 * DEG, 0.2 * DEG, 0.1 * DEG]),
            ..v0
        },
    );
    assert_sigmas(
        r.bahrs.sigma_deg,
        [3.25f64.sqrt(), 1.75f64.sqrt(), 3.0],
        "BAHRS reported",
    );
    assert_sigmas(r.vn200.sigma_deg, [0.1, 0.2, 0.5], "VN-200 reported");
    // Heading, BAHRS (magnetic made true) against the VN-200 (true): 3^2 + 0.5^2 + the two
    // default mountings 0.1^2 each + the declination's 0.3^2 = 9.36 deg^2.
    let var = r.pairs.bahrs_vn200.heading.comparison.unwrap().var_deg2;
    assert!((var - 9.36).abs() < 1e-9, "{var}");
    // Roll: 3.25 + 0.1^2 + 0.1^2 + 0.1^2, no declination.
    let var = r.pairs.bahrs_vn200.roll.comparison.unwrap().var_deg2;
    assert!((var - 3.28).abs() < 1e-9, "{var}");

    // A VN-200 sigma that is zero or not finite is no report: the defaults.
    for bad in [0.0, f64::INFINITY, -0.1 * DEG] {
        let r = check(
            b0,
            Vn200Sample {
                ypr_sigma_rad: Some([0.5 * DEG, bad, 0.1 * DEG]),
                ..v0
            },
        );
        assert_sigmas(r.vn200.sigma_deg, [0.3, 0.3, 1.0], &format!("VN-200 {bad}"));
    }
}

/// A partner sample is stale once it is more than `max_age_periods` of its unit's period older
/// than the comparison (not at exactly that age); a stale VN-200 also closes the vertical
/// channel; and the age is stated in seconds.
#[test]
fn a_partner_is_stale_only_beyond_its_horizon() {
    use super::gates::GateReason;
    use super::samples::{Vn200Sample, WatsonSample};
    // Horizons of exactly representable length: 2 x 1/64 s = 31.25 ms (VN-200) and
    // 2 x 1/16 s = 125 ms (Watson).
    let params = CheckParams {
        max_age_periods: 2.0,
        vn200_period_s: 0.015_625,
        watson_period_s: 0.0625,
        ..CheckParams::default()
    };
    let (b, v0, w0) = templates();
    let t = b.t_gps_ns;
    for (vn_age_ns, watson_age_ns, stale) in [
        (31_250_000, 125_000_000, false),
        (31_250_001, 125_000_001, true),
    ] {
        let mut c = AttitudeChecker::new(params, fixed(3.0)).unwrap();
        c.push_vn200(Vn200Sample {
            t_gps_ns: t - vn_age_ns,
            ..v0
        });
        c.push_watson(WatsonSample {
            t_gps_ns: t - watson_age_ns,
            ..w0
        });
        let r = c.compare_at(&b, false);
        let want = stale.then_some(GateReason::Stale);
        assert_eq!(r.vn200.gates.roll, want, "VN-200 {vn_age_ns} ns old");
        assert_eq!(r.watson.gates.roll, want, "Watson {watson_age_ns} ns old");
        assert_eq!(r.vertical.velocity_down.gate, want, "vertical");
        let age = r.vn200.age_s.unwrap();
        assert!((age - vn_age_ns as f64 * 1e-9).abs() < 1e-12, "{age}");
    }
}

/// A partner interpolated between a frozen sample and a fresh one is still frozen at the
/// comparison (either end frozen closes its gates).
#[test]
fn a_partner_between_a_frozen_and_a_fresh_sample_is_frozen() {
    use super::gates::GateReason;
    use super::samples::{Vn200Sample, WatsonSample};
    let (b, v0, w0) = templates();
    let t = b.t_gps_ns;
    let mut c = checker_with(fixed(3.0));
    // Bit-identical outputs every 20 ms for 1.2 s (frozen after the 1 s window), then one
    // changed output 20 ms later; the comparison is halfway between the last two.
    for k in 0..=60 {
        let tk = t - 1_210_000_000 + k * 20_000_000;
        c.push_vn200(Vn200Sample { t_gps_ns: tk, ..v0 });
        c.push_watson(WatsonSample { t_gps_ns: tk, ..w0 });
    }
    let q = v0.attitude * nalgebra::UnitQuaternion::from_euler_angles(0.01, 0.0, 0.0);
    c.push_vn200(Vn200Sample {
        t_gps_ns: t + 10_000_000,
        attitude: q,
        ..v0
    });
    c.push_watson(WatsonSample {
        t_gps_ns: t + 10_000_000,
        roll_rad: w0.roll_rad + 0.01,
        ..w0
    });
    let r = c.compare_at(&b, false);
    assert_eq!(r.vn200.gates.roll, Some(GateReason::Frozen));
    assert_eq!(r.watson.gates.roll, Some(GateReason::Frozen));
}

/// A Watson attitude between two samples is slerped by the fraction of their interval elapsed.
#[test]
fn the_watson_is_interpolated_between_its_samples() {
    use super::samples::WatsonSample;
    let (b, v0, w0) = templates();
    let t = b.t_gps_ns;
    let mut c = checker_with(fixed(0.0));
    c.push_vn200(super::samples::Vn200Sample { t_gps_ns: t, ..v0 });
    let at = |dt_ns: i64, roll_deg: f64| WatsonSample {
        t_gps_ns: t + dt_ns,
        roll_rad: roll_deg * DEG,
        pitch_rad: 4.0 * DEG,
        heading_mag_rad: 0.0,
        ..w0
    };
    // Roll 0 at -20 ms and 10 deg at +60 ms: a quarter of the way, 2.5 deg.
    c.push_watson(at(-20_000_000, 0.0));
    c.push_watson(at(60_000_000, 10.0));
    // (The pitch, 4 deg at both ends, stays 4 deg: the slerp is about the body x axis.)
    let w = c.compare_at(&b, false).watson;
    let (roll, pitch) = (w.roll_deg.unwrap(), w.pitch_deg.unwrap());
    assert!((roll - 2.5).abs() < 1e-9, "{roll}");
    assert!((pitch - 4.0).abs() < 1e-9, "{pitch}");
}

/// A declination model that cannot answer.
struct NoDeclination;

impl crate::magnetic::DeclinationModel for NoDeclination {
    fn declination(
        &self,
        _: f64,
        _: f64,
        _: f64,
        t_gps_ns: i64,
    ) -> Result<Declination, crate::magnetic::MagneticError> {
        Err(crate::magnetic::MagneticError::BadTime(t_gps_ns))
    }
}

/// The coverage names, for each unit, axis and the vertical channel not compared, the reason of
/// the first closed gate (not "no check"), and says compared for the rest.
#[test]
fn coverage_gives_each_uncompared_slot_its_own_reason() {
    use super::coverage::NotComparedReason as R;
    let (b, v0, _) = templates();
    // The Watson silent, no declination (the magnetic headings cannot be made true).
    let mut c = AttitudeChecker::new(CheckParams::default(), Box::new(NoDeclination)).unwrap();
    c.push_vn200(super::samples::Vn200Sample {
        t_gps_ns: b.t_gps_ns,
        ..v0
    });
    let cov = c.compare_at(&b, false).coverage;
    assert!(cov.bahrs.compared && cov.vn200.compared);
    assert!(cov.roll.compared && cov.pitch.compared && cov.vertical.compared);
    assert_eq!(cov.watson.reason, Some(R::Absent));
    assert_eq!(cov.heading.reason, Some(R::NotComparable));
    // The VN-200 silent too: nothing compared; the vertical channel has no partner sample.
    let mut c = AttitudeChecker::new(CheckParams::default(), Box::new(NoDeclination)).unwrap();
    let cov = c.compare_at(&b, false).coverage;
    assert_eq!(cov.vn200.reason, Some(R::Absent));
    assert_eq!(cov.roll.reason, Some(R::Absent));
    assert_eq!(cov.vertical.reason, Some(R::Absent));
}

/// The timing term of a pair (issue 25): the axis's Euler rate times the relative time sigma of
/// the two samples, from the body rates of the first unit that reports them.
#[test]
fn the_timing_term_is_the_rate_times_the_relative_time_sigma() {
    use super::samples::{BahrsSample, Vn200Sample};
    let (b0, v0, _) = templates();
    let t = b0.t_gps_ns;
    // Level, yawing at 10 deg/s: Euler rates (0, 0, 10) deg/s. Time sigmas 3 and 4 ms: 5 ms
    // relative. Heading term 10 x 0.005 = 0.05 deg; roll and pitch 0.
    let b = BahrsSample {
        roll_rad: 0.0,
        pitch_rad: 0.0,
        sigma_ns: 3e6,
        rates_radps: Some([0.0, 0.0, 10.0 * DEG]),
        ..b0
    };
    let mut c = checker_with(fixed(3.0));
    c.push_vn200(Vn200Sample {
        t_gps_ns: t,
        sigma_ns: 4e6,
        rates_radps: None,
        ..v0
    });
    let pair = c.compare_at(&b, false).pairs.bahrs_vn200;
    let heading = pair.heading.comparison.unwrap().timing_deg;
    assert!((heading - 0.05).abs() < 1e-12, "{heading}");
    let roll = pair.roll.comparison.unwrap().timing_deg;
    assert!(roll.abs() < 1e-12, "{roll}");
}

/// The VN-200's down velocity at the comparison is interpolated between the samples around it,
/// and held from the last one when none follows.
#[test]
fn the_vn200_down_velocity_is_interpolated_or_held() {
    use super::samples::{BahrsSample, Vn200Sample};
    let (b0, v0, _) = templates();
    let t = b0.t_gps_ns;
    let b = BahrsSample {
        velocity_down_mps: 0.0,
        ..b0
    };
    let vn = |dt_ns: i64, down: f64| Vn200Sample {
        t_gps_ns: t + dt_ns,
        vel_ned_mps: Some([0.0, 0.0, down]),
        ..v0
    };
    // 1 m/s at -10 ms, 3 m/s at +30 ms: a quarter of the way, 1.5 m/s.
    let mut c = checker_with(fixed(3.0));
    c.push_vn200(vn(-10_000_000, 1.0));
    c.push_vn200(vn(30_000_000, 3.0));
    let got = c.compare_at(&b, false).vertical.velocity_down.vn200_mps;
    assert!((got.unwrap() - 1.5).abs() < 1e-9, "{got:?}");
    // Only the earlier one: held, 1 m/s.
    let mut c = checker_with(fixed(3.0));
    c.push_vn200(vn(-10_000_000, 1.0));
    let got = c.compare_at(&b, false).vertical.velocity_down.vn200_mps;
    assert!((got.unwrap() - 1.0).abs() < 1e-9, "{got:?}");
}

/// The persistence counters integrate the time between checks: a fixed-comparator fault
/// (`declare_after_s` = 1 s) takes the same 1 s whether the BAHRS comes at 50 Hz or, as here,
/// 10 Hz; a check whose time does not advance counts as one nominal BAHRS period (20 ms).
#[test]
fn persistence_counts_the_time_between_checks() {
    use super::samples::{BahrsSample, Vn200Sample};
    let (b0, v0, _) = templates();
    let t0 = b0.t_gps_ns;
    // The BAHRS rolled 20 deg from the VN-200: 3.3 times the 6 deg fixed limit, at once.
    let b_at = |t: i64| BahrsSample {
        t_gps_ns: t,
        roll_rad: b0.roll_rad + 20.0 * DEG,
        ..b0
    };
    // The VN-200 moves a little each sample, so that it is never frozen.
    let v_at = |t: i64, k: i32| Vn200Sample {
        t_gps_ns: t,
        attitude: v0.attitude
            * nalgebra::UnitQuaternion::from_euler_angles(0.0, 0.0, f64::from(k) * 1e-6),
        ..v0
    };
    // 10 Hz: the counter is 20 ms after the first check (the nominal period) and 100 ms more at
    // each; 0.02 + 9 x 0.1 = 0.92 s at the 10th check, 1 s (declared) at the 11th.
    let mut c = checker_with(fixed(3.0));
    for k in 0..11 {
        let t = t0 + i64::from(k) * 100_000_000;
        c.push_vn200(v_at(t, k));
        let fixed_fault = c
            .compare_at(&b_at(t), false)
            .pairs
            .bahrs_vn200
            .roll
            .fixed_fault;
        assert_eq!(fixed_fault, k == 10, "check {}", k + 1);
    }
    // The same time over and over: 20 ms a check, declared at the 50th (not before the 49th).
    let mut c = checker_with(fixed(3.0));
    let mut declared_at = None;
    for k in 0..60 {
        c.push_vn200(v_at(t0, k));
        let r = c.compare_at(&b_at(t0), false);
        if r.pairs.bahrs_vn200.roll.fixed_fault && declared_at.is_none() {
            declared_at = Some(k + 1);
        }
    }
    let n = declared_at.expect("declared");
    assert!((49..=51).contains(&n), "{n}");
}
