//! The prompt output (issue 10: a fused attitude for every VN-200 message, published as soon as
//! the message arrives): the voted attitude at the time of each new attitude sample.
//!
//! A cross-check record waits until the other units have passed the BAHRS sample time (up to a
//! Watson period, 84 ms): right for the comparison, too late for a consumer flying on the
//! attitude. [`AttitudeChecker::prompt`] votes at the newest sample's time over the three units as
//! they are at that moment: the unit that just reported at its own time, and each other unit's
//! newest sample propagated to that time with its own body rates (Euler-angle rates times the
//! time since the sample: milliseconds for the BAHRS and the VN-200, at most the staleness limit
//! for the Watson). A unit past its staleness limit is gated exactly as in the check.
//!
//! The verdicts, the isolation and the health flags are those of the newest check record, so a
//! unit isolated there is left out of this vote too. Nothing here touches the statistics of the
//! check (the persistence counters, the CUSUMs): a prompt output only reads them.
//!
//! Issue 25: a check record older than `verdict_max_age_s` gives no verdicts: the prompt then
//! says "not compared" on every pair and axis (never a repeated old verdict), and its coverage
//! says why, from the units as they are now (e.g. the BAHRS samples arriving unaligned).
//!
//! Decision: the propagation uses each unit's body rates as aircraft body rates. The mounting
//! rotations are a few degrees at most, and over the few milliseconds propagated the difference
//! is far below the units' noise.

use super::*;
use crate::attitude::angles::wrap_2pi;
use crate::attitude::compare::euler_rates;
use crate::attitude::inertial::InertialRecord;
use crate::attitude::vertical::{ThirdOpinion, TtNotCompared, VerticalComparison, VerticalRecord};

/// A prompt time this far (or further) behind the newest one starts a new timeline, ns.
const NEW_TIMELINE_NS: i64 = 1_000_000_000;

/// The parts of a check record that a prompt output repeats (all `Copy`: stored per record).
#[derive(Debug, Clone, Copy)]
pub(super) struct Verdicts {
    fault: bool,
    isolated: Option<Unit>,
    multiple_fault: bool,
    magnetic_disturbance: bool,
    bahrs_integrity_risk: bool,
    vn200_healthy: bool,
    declination: Option<DeclinationRecord>,
    pairs: PairsRecord,
    isolation: IsolationRecord,
    vertical: VerticalRecord,
    inertial: InertialRecord,
}

impl Verdicts {
    /// The verdicts of `r`.
    pub(super) fn of(r: &AttitudeRecord) -> Self {
        Self {
            fault: r.fault,
            isolated: r.isolated,
            multiple_fault: r.multiple_fault,
            magnetic_disturbance: r.magnetic_disturbance,
            bahrs_integrity_risk: r.bahrs_integrity_risk,
            vn200_healthy: r.vn200_healthy,
            declination: r.declination,
            pairs: r.pairs,
            isolation: r.isolation,
            vertical: r.vertical,
            inertial: r.inertial,
        }
    }

    /// Before the first check: nothing compared, nothing declared.
    fn none() -> Self {
        let pair = PairRecord {
            roll: not_compared_pair(),
            pitch: not_compared_pair(),
            heading: not_compared_pair(),
            joint: JointTest {
                chi2: None,
                ratio: None,
                verdict: PairVerdict::NotCompared,
            },
        };
        let vertical = VerticalComparison {
            bahrs_mps: None,
            vn200_mps: None,
            diff_mps: None,
            sigma_mps: None,
            stat_ratio: None,
            verdict: PairVerdict::NotCompared,
            gate: Some(GateReason::NoData),
        };
        Self {
            fault: false,
            isolated: None,
            multiple_fault: false,
            magnetic_disturbance: false,
            bahrs_integrity_risk: false,
            vn200_healthy: false,
            declination: None,
            pairs: PairsRecord {
                bahrs_vn200: pair,
                bahrs_watson: pair,
                vn200_watson: pair,
            },
            isolation: IsolationRecord {
                roll: Isolation::NotCompared,
                pitch: Isolation::NotCompared,
                heading: Isolation::NotCompared,
                joint: Isolation::NotCompared,
            },
            vertical: VerticalRecord {
                velocity_down: vertical,
                height_rate: vertical,
                bahrs_health: None,
                // Before the first check the window has not begun to fill.
                third: ThirdOpinion::absent(TtNotCompared::WindowFilling),
            },
            inertial: InertialRecord::none(Some(GateReason::NoData)),
        }
    }
}

impl AttitudeChecker {
    /// The voted attitude at GPS time `t` (ns), the time of the attitude sample just pushed (by
    /// unit `from`), with
    /// the verdicts of the newest check record (see the module documentation). `None` when `t`
    /// is not later than the previous prompt output's time, so the outputs' times increase.
    /// The record's `kind` is [`PROMPT_KIND`]; each unit's `age_s` is the time since the sample
    /// its values were propagated from.
    pub fn prompt(&mut self, t: i64, from: Unit) -> Option<AttitudeRecord> {
        // A sample up to a second older than the newest output is late: skipped, so the times
        // increase. A VN-200 sample further back is a new timeline (a device or clock reset):
        // followed, or the outputs would stop until the clock caught up with the old one. Only
        // the VN-200, the GPS time reference, starts one: an older BAHRS or Watson sample is one
        // that waited (for its clock model, for a paced read) and is skipped, however old, or
        // the topic would jump back and replay a burst of stale outputs.
        if self.last_prompt_ns.is_some_and(|p| {
            t <= p && (from != Unit::Vn200 || p.saturating_sub(t) <= NEW_TIMELINE_NS)
        }) {
            return None;
        }
        self.last_prompt_ns = Some(t);
        let decl = self.declination(t);
        let (mag_gate, rz, d_rad) = magnetic_frame(decl);
        let bahrs_horizon = self.horizon_ns(self.params.bahrs_period_s);
        let newest_bahrs = self.pending.back().copied().or(self.last_bahrs);
        let bahrs = match newest_bahrs {
            Some((b, frozen)) => {
                let mut u = self.prepare_bahrs(&b, frozen, &rz, mag_gate, d_rad);
                let age_ns = t.saturating_sub(b.t_gps_ns);
                u.age_s = Some(age_ns as f64 * 1e-9);
                u.held_s = age_ns as f64 * 1e-9;
                if age_ns > bahrs_horizon {
                    u.gates = u.gates.map(|g| g.or(Some(GateReason::Stale)));
                }
                u
            }
            None => Prepared::missing(GateReason::NoData),
        };
        let (vn, _, _) = self.prepare_vn200(t);
        let watson = self.prepare_watson(t, &rz, mag_gate);
        let max_age_s = self.params.verdict_max_age_s;
        let fresh = self
            .last_t_ns
            .is_some_and(|c| t.saturating_sub(c) as f64 * 1e-9 <= max_age_s);
        let coverage = self.prompt_coverage(t, fresh, [&bahrs, &vn, &watson]);
        let [bahrs, vn, watson] = [bahrs, vn, watson].map(propagate);
        let v = match self.last_verdicts {
            Some(v) if fresh => v,
            _ => Verdicts::none(),
        };
        let i = &v.isolation;
        Some(AttitudeRecord {
            kind: PROMPT_KIND,
            t_gps_ns: t,
            fault: v.fault,
            isolated: v.isolated,
            multiple_fault: v.multiple_fault,
            magnetic_disturbance: v.magnetic_disturbance,
            bahrs_integrity_risk: v.bahrs_integrity_risk,
            vn200_healthy: v.vn200_healthy,
            bahrs: unit_values(&bahrs),
            vn200: unit_values(&vn),
            watson: unit_values(&watson),
            declination: v.declination,
            pairs: v.pairs,
            isolation: v.isolation,
            voted: vote_units([&bahrs, &vn, &watson], [i.roll, i.pitch, i.heading]),
            vertical: v.vertical,
            inertial: v.inertial,
            coverage,
        })
    }

    /// The coverage at prompt time `t`: the newest check's reasons while it is `fresh`;
    /// without a recent check, each unit's state now (a closed roll or pitch gate, explained by
    /// how its samples arrive), the checks following the BAHRS's, else "no check".
    fn prompt_coverage(&self, t: i64, fresh: bool, units: [&Prepared; 3]) -> CoverageRecord {
        let arrival = self.coverage.arrival;
        let last = self.coverage.reason;
        let now = |i: usize| {
            let g = &units[i].gates;
            g[0].or(g[1])
                .map(|_| crate::attitude::coverage::unit_reason(g, &arrival[i]))
        };
        let bahrs_now = now(0);
        self.coverage
            .at(t, self.params.verdict_max_age_s, |slot| match slot {
                _ if fresh => last[slot],
                0..=2 => now(slot),
                _ => bahrs_now,
            })
    }
}

/// A held unit's values carried forward (or back) by `held_s` with its body rates; a unit
/// without rates keeps its values.
fn propagate(mut u: Prepared) -> Prepared {
    if let (Some(v), Some(r)) = (u.values, u.rates)
        && u.held_s != 0.0
    {
        let e = euler_rates(r, v[0], v[1]);
        let dt = u.held_s;
        u.values = Some([
            v[0] + e[0] * dt,
            v[1] + e[1] * dt,
            wrap_2pi(v[2] + e[2] * dt),
        ]);
        u.heading_mag = u.heading_mag.map(|h| wrap_2pi(h + e[2] * dt));
    }
    u
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::synthetic::{Event, Scenario, Stream, truth};
    use crate::magnetic::FixedDeclination;

    fn checker() -> AttitudeChecker {
        // Zero declination: magnetic and true headings are the same number.
        use crate::attitude::checker_tests::{checker_with, fixed};
        checker_with(fixed(0.0))
    }

    /// One sample of each unit from the synthetic stream, to edit.
    fn samples() -> (BahrsSample, Vn200Sample, WatsonSample) {
        crate::attitude::checker_tests::templates()
    }

    #[test]
    fn held_units_are_carried_to_the_prompt_time_with_their_rates_and_the_median_is_voted() {
        // Level, heading 90 deg, rolling right at 20 deg/s (body p; q = r = 0, so the Euler roll
        // rate is p and heading and pitch stay). At t = T:
        // - BAHRS sampled 5 ms before at 10.0 deg: 10.0 + 20 x 0.005 = 10.1 deg;
        // - Watson sampled 45 ms before at 9.0 deg: 9.0 + 20 x 0.045 = 9.9 deg;
        // - VN-200 sampled at T: 10.3 deg.
        // Median of 9.9, 10.1, 10.3: the BAHRS's 10.1 deg.
        let (mut b, mut v, mut w) = samples();
        let t = v.t_gps_ns + 1_000_000_000;
        let p = [20.0 * DEG, 0.0, 0.0];
        b.t_gps_ns = t - 5_000_000;
        (b.roll_rad, b.pitch_rad, b.heading_mag_rad) = (10.0 * DEG, 0.0, 90.0 * DEG);
        b.rates_radps = Some(p);
        w.t_gps_ns = t - 45_000_000;
        (w.roll_rad, w.pitch_rad, w.heading_mag_rad) = (9.0 * DEG, 0.0, 90.0 * DEG);
        w.rates_radps = p;
        v.t_gps_ns = t;
        v.attitude = from_ypr(90.0 * DEG, 0.0, 10.3 * DEG);
        v.rates_radps = Some(p);
        let mut c = checker();
        c.push_watson(w);
        c.push_bahrs(b);
        c.push_vn200(v);
        let r = c.prompt(t, Unit::Bahrs).unwrap();
        assert_eq!((r.kind, r.t_gps_ns), (PROMPT_KIND, t));
        let close = |x: Option<f64>, want: f64| (x.unwrap() - want).abs() < 1e-6;
        assert!(close(r.bahrs.roll_deg, 10.1), "{:?}", r.bahrs.roll_deg);
        assert!(close(r.watson.roll_deg, 9.9), "{:?}", r.watson.roll_deg);
        assert!(close(r.vn200.roll_deg, 10.3), "{:?}", r.vn200.roll_deg);
        assert!(close(r.bahrs.age_s, 0.005) && close(r.watson.age_s, 0.045));
        assert!(close(r.vn200.age_s, 0.0));
        for u in [&r.bahrs, &r.vn200, &r.watson] {
            assert!(close(u.heading_deg, 90.0) && close(u.pitch_deg, 0.0));
        }
        let roll = r.voted.roll.unwrap();
        assert!((roll.value_deg - 10.1).abs() < 1e-6);
        assert_eq!(roll.selected, Some(Unit::Bahrs));
        // No check yet: nothing compared, nothing declared.
        assert_eq!(r.isolation.roll, Isolation::NotCompared);
        assert_eq!(r.pairs.bahrs_vn200.roll.verdict, PairVerdict::NotCompared);
        // Times only increase: the same time again, or a little older, gives nothing; a jump
        // back by more than a second is followed (a new timeline) when the VN-200 makes it.
        assert!(c.prompt(t, Unit::Vn200).is_none() && c.prompt(t - 1, Unit::Vn200).is_none());
        assert!(c.prompt(t - 1_000_000_000, Unit::Vn200).is_none());
        // 0.3 s later nothing new arrived: every unit is past its staleness limit (3 periods)
        // and gated; no vote.
        let r = c.prompt(t + 300_000_000, Unit::Watson).unwrap();
        assert_eq!(r.bahrs.gates.roll, Some(GateReason::Stale));
        assert_eq!(r.watson.gates.roll, Some(GateReason::Stale));
        assert_eq!(r.vn200.gates.roll, Some(GateReason::Stale));
        assert!(r.voted.roll.is_none());
        let back = t + 300_000_000 - 5_000_000_000;
        // A BAHRS or Watson sample that old waited somewhere: skipped, not a new timeline.
        assert!(c.prompt(back, Unit::Bahrs).is_none());
        assert!(c.prompt(back, Unit::Watson).is_none());
        assert_eq!(c.prompt(back, Unit::Vn200).map(|r| r.t_gps_ns), Some(back));
    }

    #[test]
    fn prompts_follow_the_truth_and_carry_the_checks_isolation() {
        // BAHRS roll bias ramping at 0.5 deg/s from 60 s (isolated by the check about 65 s).
        let sc = Scenario {
            duration_s: 80.0,
            roll_ramp: Some((60.0, 0.5)),
            ..Default::default()
        };
        let t0 = sc.t0_gps_ns;
        let mut c = checker_with_wmm_off(sc.declination_deg);
        let mut prompts = Vec::new();
        let mut last_check = None;
        for e in Stream::new(sc) {
            let (t, from) = e.push_into(&mut c);
            while let Some(r) = c.next_record() {
                last_check = Some(r);
            }
            if let Some(p) = c.prompt(t, from) {
                prompts.push((p, last_check.clone()));
            }
        }
        assert!(
            prompts
                .windows(2)
                .all(|w| w[0].0.t_gps_ns < w[1].0.t_gps_ns)
        );
        // Every VN-200 sample (50 Hz) gives one at least: 80 s x 50.
        assert!(prompts.len() >= 4000, "{}", prompts.len());
        let mut worst = [0.0f64; 3];
        let mut isolated_seen = 0;
        for (p, check) in &prompts {
            let s = (p.t_gps_ns - t0) as f64 * 1e-9;
            // The verdicts are the newest check's.
            let check = check.as_ref();
            assert_eq!(p.isolated, check.and_then(|c| c.isolated));
            assert_eq!(
                p.isolation.roll,
                check.map_or(Isolation::NotCompared, |c| c.isolation.roll)
            );
            let (Some(r), Some(pi), Some(h)) = (&p.voted.roll, &p.voted.pitch, &p.voted.heading)
            else {
                continue;
            };
            if p.isolated == Some(Unit::Bahrs) {
                isolated_seen += 1;
                assert!(!r.used.contains(&Unit::Bahrs), "at {s} s");
            }
            // Against the truth, before the BAHRS fault or once the BAHRS is out of the vote.
            if s < 60.0 || p.isolated == Some(Unit::Bahrs) {
                let ([yaw, pitch, roll], _, _, _) = truth(s);
                let err = [
                    r.value_deg - roll / DEG,
                    pi.value_deg - pitch / DEG,
                    crate::attitude::angles::angle_diff(h.value_deg * DEG, yaw) / DEG,
                ];
                for (w, e) in worst.iter_mut().zip(err) {
                    *w = w.max(e.abs());
                }
            }
        }
        assert!(isolated_seen > 500, "{isolated_seen}");
        // Noise (1 sigma): VN-200 0.05 deg tilt and 0.2 deg heading, BAHRS 0.15 / 0.5, Watson
        // 0.3 / 0.8 (0.1 deg steps): the median stays within a few of the middle unit's sigmas.
        assert!(
            worst[0] < 0.6 && worst[1] < 0.6 && worst[2] < 2.0,
            "{worst:?}"
        );
    }

    /// Issue 25: the BAHRS is aligned for the first 30 s, then its samples keep arriving but
    /// cannot be aligned (PPS lost past the holdover). While it was aligned every prompt covers
    /// all three units; from 30 s + `verdict_max_age_s` on no prompt repeats a verdict, and each
    /// says the BAHRS is `not_aligned` and the others `no_check`. A second checker whose BAHRS
    /// is never aligned says `not_wired` from the first prompt on.
    #[test]
    fn prompts_never_repeat_old_verdicts_and_say_why_nothing_is_compared() {
        use crate::attitude::coverage::NotComparedReason as R;
        let sc = Scenario {
            duration_s: 40.0,
            ..Default::default()
        };
        let t0 = sc.t0_gps_ns;
        let max_age = CheckParams::default().verdict_max_age_s;
        let (mut lost, mut never) = (checker_with_wmm_off(3.0), checker_with_wmm_off(3.0));
        let (mut before, mut after, mut never_count) = (0, 0, 0);
        for e in Stream::new(sc) {
            let aligned = match e {
                Event::Bahrs(b) => (b.t_gps_ns - t0) < 30_000_000_000,
                _ => true,
            };
            let (t, from) = if aligned {
                e.push_into(&mut lost)
            } else {
                lost.note_unaligned(Unit::Bahrs);
                continue;
            };
            while lost.next_record().is_some() {}
            let secs = (t - t0) as f64 * 1e-9;
            if let Some(p) = lost.prompt(t, from) {
                let c = &p.coverage;
                if (2.0..30.0).contains(&secs) {
                    before += 1;
                    assert!(
                        c.bahrs.compared && c.vn200.compared && c.watson.compared,
                        "{secs}"
                    );
                    assert!(c.roll.compared && c.pitch.compared && c.heading.compared);
                    assert_eq!(p.isolation.roll, Isolation::NoFault, "{secs}");
                } else if secs > 30.0 + max_age + 0.02 {
                    after += 1;
                    assert_eq!(c.bahrs.reason, Some(R::NotAligned), "{secs}");
                    assert!(c.bahrs.age_s.unwrap() > max_age);
                    assert_eq!(c.vn200.reason, Some(R::NoCheck));
                    assert_eq!(c.roll.reason, Some(R::NotAligned));
                    assert_eq!(p.isolation.roll, Isolation::NotCompared, "{secs}");
                    assert_eq!(p.pairs.vn200_watson.roll.verdict, PairVerdict::NotCompared);
                    // The vote goes on without the BAHRS.
                    let roll = p.voted.roll.as_ref().unwrap();
                    assert!(!roll.used.contains(&Unit::Bahrs));
                }
            }
            // The same stream with the BAHRS never aligned.
            if from != Unit::Bahrs {
                never.note_unaligned(Unit::Bahrs);
                e.push_into(&mut never);
                while never.next_record().is_some() {}
                if let Some(p) = never.prompt(t, from) {
                    never_count += 1;
                    assert_eq!(p.coverage.bahrs.reason, Some(R::NotWired));
                    assert_eq!(p.coverage.bahrs.age_s, None);
                    assert_eq!(p.isolation.joint, Isolation::NotCompared);
                }
            }
        }
        // 28 s and 9.5 s of VN-200 prompts at 50 Hz at least; 40 s in the second checker.
        assert!(before > 1400 && after > 450 && never_count > 2000);
    }

    fn checker_with_wmm_off(decl_deg: f64) -> AttitudeChecker {
        let model = Box::new(FixedDeclination(Declination {
            declination_rad: decl_deg * DEG,
            sigma_rad: 0.3 * DEG,
            horizontal_nt: 20_000.0,
            zone: MagneticZone::Normal,
        }));
        AttitudeChecker::new(CheckParams::default(), model).unwrap()
    }

    #[test]
    fn a_held_unit_is_carried_on_every_axis_and_its_magnetic_heading_too() {
        // Level (roll = pitch = 0): the Euler rates are the body rates 0.1, 0.2, 0.3 rad/s. Held
        // 0.5 s: roll 0 + 0.05, pitch 0 + 0.1, heading (2 pi - 0.05) + 0.15 = 0.1 rad after the
        // wrap, magnetic heading 6.0 + 0.15 = 6.15 rad.
        let held = Prepared {
            values: Some([0.0, 0.0, std::f64::consts::TAU - 0.05]),
            heading_mag: Some(6.0),
            var: [0.0; 3],
            gates: [None; 3],
            sigma_ns: 0.0,
            age_s: Some(0.5),
            rates: Some([0.1, 0.2, 0.3]),
            held_s: 0.5,
        };
        let u = propagate(held);
        let [roll, pitch, heading] = u.values.unwrap();
        let close = |x: f64, want: f64| (x - want).abs() < 1e-12;
        assert!(close(roll, 0.05) && close(pitch, 0.1), "{u:?}");
        assert!(close(heading, 0.1), "{u:?}");
        assert!(close(u.heading_mag.unwrap(), 6.15), "{u:?}");
        // Interpolated (held 0): as it was.
        let u = propagate(Prepared {
            held_s: 0.0,
            ..held
        });
        assert_eq!((u.values, u.heading_mag), (held.values, held.heading_mag));
    }

    #[test]
    fn the_prompts_bahrs_is_fresh_up_to_three_periods_old() {
        // max_age_periods 3 x bahrs_period_s 20 ms: 60 ms old is fresh, 60 ms + 1 ns stale.
        let (b, _, _) = samples();
        let mut c = checker();
        c.push_bahrs(b);
        let horizon = 60_000_000;
        let r = c.prompt(b.t_gps_ns + horizon, Unit::Vn200).unwrap();
        assert_eq!(r.bahrs.gates.roll, None);
        let r = c.prompt(b.t_gps_ns + horizon + 1, Unit::Vn200).unwrap();
        assert_eq!(r.bahrs.gates.roll, Some(GateReason::Stale));
    }

    #[test]
    fn a_fresh_checks_coverage_reasons_are_the_prompts_then_the_units_as_they_are_now() {
        use crate::attitude::coverage::NotComparedReason as R;
        // The BAHRS alone: its sample at t0 is checked once 0.3 s of BAHRS samples have gone by
        // (the others' staleness horizons). Its only closed gate is its heading's (no position
        // for the declination: the VN-200 never sent one), so the check says "not comparable"
        // for it; the roll check's first closed gate is the VN-200's, which sent nothing.
        let (b, _, _) = samples();
        let t0 = b.t_gps_ns;
        let mut later = b;
        later.t_gps_ns = t0 + 300_000_000;
        later.roll_rad += 0.001;
        let mut c = checker();
        c.push_bahrs(b);
        c.push_bahrs(later);
        assert_eq!(c.next_record().map(|r| r.t_gps_ns), Some(t0));
        // 0.3 s after the check (within verdict_max_age_s, 0.5 s): its reasons, although the
        // BAHRS sample now is open.
        let r = c.prompt(later.t_gps_ns, Unit::Bahrs).unwrap();
        assert_eq!(r.bahrs.gates.roll, None);
        assert_eq!(r.coverage.bahrs.reason, Some(R::NotComparable));
        assert_eq!(r.coverage.roll.reason, Some(R::Absent));
        // 0.5 s after the newest BAHRS sample and 0.8 s after the check: the check is too old,
        // and the units as they are say why: the BAHRS is stale, and the roll check with it.
        let r = c.prompt(later.t_gps_ns + 500_000_000, Unit::Vn200).unwrap();
        assert_eq!(r.coverage.bahrs.reason, Some(R::Stale));
        assert_eq!(r.coverage.roll.reason, Some(R::Stale));
    }
}
