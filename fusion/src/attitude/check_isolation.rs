//! The isolation of one check (steps 4 and 5 of [`AttitudeChecker::compare_at`]): which unit the
//! pair verdicts point at, per axis and for the joint test, then the transitions from the
//! previous outcome (settling at an onset, holding during a recovery), then the record's fault
//! flags.

use super::*;

/// A pair record's verdict on one axis, and whether that axis exceeds its threshold or limit on
/// this sample (what the transitions look at).
type AxisOf<'a> = &'a dyn Fn(&PairRecord) -> (PairVerdict, bool);

/// The isolation per axis from this sample's pair verdicts alone, before the transitions.
///
/// The heading uses the magnetic-disturbance rule. The joint test includes the heading, so when
/// the heading alone is a magnetic disturbance the same rule keeps the joint test from isolating
/// a healthy VN-200, and a joint failure of a pair with the VN-200 that the heading explains is
/// the disturbance too (roll and pitch keep their own per-axis tests, so a tilt fault is still
/// caught there).
pub(super) fn raw_isolation(pairs: &PairsRecord, vn_healthy: bool) -> IsolationRecord {
    let verdicts = |f: &dyn Fn(&PairRecord) -> PairVerdict| Pairs {
        bahrs_vn200: f(&pairs.bahrs_vn200),
        bahrs_watson: f(&pairs.bahrs_watson),
        vn200_watson: f(&pairs.vn200_watson),
    };
    let heading = isolate(&verdicts(&|r| r.heading.verdict), true, vn_healthy);
    let magnetic = heading == Isolation::MagneticDisturbance;
    let joint = match isolate(&verdicts(&|r| r.joint.verdict), magnetic, vn_healthy) {
        Isolation::DetectedNotIsolated | Isolation::Isolated(Unit::Vn200)
            if magnetic
                && pairs.bahrs_watson.joint.verdict != PairVerdict::Fail
                && (pairs.bahrs_vn200.joint.verdict == PairVerdict::Fail
                    || pairs.vn200_watson.joint.verdict == PairVerdict::Fail) =>
        {
            Isolation::MagneticDisturbance
        }
        other => other,
    };
    IsolationRecord {
        roll: isolate(&verdicts(&|r| r.roll.verdict), false, vn_healthy),
        pitch: isolate(&verdicts(&|r| r.pitch.verdict), false, vn_healthy),
        heading,
        joint,
    }
}

impl AttitudeChecker {
    /// The isolation after the transitions from the previous outcome of each axis and of the
    /// joint test (see [`Self::transition`]), at time `t`, GPS ns.
    pub(super) fn settle_isolation(
        &mut self,
        t: i64,
        raw: IsolationRecord,
        pairs: &PairsRecord,
    ) -> IsolationRecord {
        let axis = |ai: usize| {
            move |r: &PairRecord| {
                let a = [&r.roll, &r.pitch, &r.heading][ai];
                (a.verdict, a.stat_exceeded || a.fixed_exceeded)
            }
        };
        let joint_of = |r: &PairRecord| (r.joint.verdict, r.joint.ratio.is_some_and(|x| x > 1.0));
        IsolationRecord {
            roll: self.transition(t, 0, raw.roll, pairs, &axis(0)),
            pitch: self.transition(t, 1, raw.pitch, pairs, &axis(1)),
            heading: self.transition(t, 2, raw.heading, pairs, &axis(2)),
            joint: self.transition(t, 3, raw.joint, pairs, &joint_of),
        }
    }

    /// The outcome of one axis (`slot`: roll, pitch, heading, joint) given its raw isolation
    /// `iso` and its previous outcome.
    ///
    /// Onset: a single failed pair waits (bounded by `isolation_settle_s`) for another exceeding
    /// pair of the axis to settle, so a fault is not declared "not isolated" a few samples before
    /// the second pair would have isolated it. Settling applies only at an onset: a fault already
    /// declared is not withdrawn by it. End of a magnetic disturbance or of an isolated unit's
    /// fault: its failed pairs clear one by one (each after its own hysteresis); while every
    /// failed pair is only clearing (no longer exceeding), the axis keeps its classification
    /// instead of becoming "detected, not isolated" for the last pair's hysteresis.
    fn transition(
        &mut self,
        t: i64,
        slot: usize,
        iso: Isolation,
        pairs: &PairsRecord,
        f: AxisOf,
    ) -> Isolation {
        let exceeding = |verdict: PairVerdict| {
            [&pairs.bahrs_vn200, &pairs.bahrs_watson, &pairs.vn200_watson]
                .into_iter()
                .any(|r| f(r) == (verdict, true))
        };
        let settle_ns = (self.params.isolation_settle_s * 1e9) as i64;
        let prev = self.prev_isolation[slot];
        let out = if iso == Isolation::DetectedNotIsolated
            && prev != Isolation::DetectedNotIsolated
            && exceeding(PairVerdict::Pass)
        {
            let since = *self.settle_since[slot].get_or_insert(t);
            if t.saturating_sub(since) < settle_ns {
                Isolation::Settling
            } else {
                iso
            }
        } else if matches!(iso, Isolation::DetectedNotIsolated | Isolation::Isolated(_))
            && matches!(
                prev,
                Isolation::MagneticDisturbance | Isolation::Isolated(_)
            )
            && iso != prev
            && !exceeding(PairVerdict::Fail)
        {
            // Recovery: the failed pairs clear one by one; while none of them is
            // exceeding any more, the classification they led to stands.
            prev
        } else {
            iso
        };
        if iso != Isolation::DetectedNotIsolated {
            self.settle_since[slot] = None;
        }
        self.prev_isolation[slot] = out;
        out
    }
}

/// The record's fault flags, from the isolation after the transitions.
pub(super) struct FaultSummary {
    /// Some axis or the joint test detected a fault (isolated or not).
    pub(super) fault: bool,
    /// The one unit isolated; `None` when none is, or when the outcomes point at more than one
    /// unit (then `multiple`).
    pub(super) isolated: Option<Unit>,
    /// More than one unit is at fault: some outcome is a multiple fault, or two outcomes isolate
    /// different units.
    pub(super) multiple: bool,
}

impl FaultSummary {
    /// The flags of `isolation`. A magnetic disturbance, a settling axis and "not compared" are
    /// no fault of a unit.
    pub(super) fn of(isolation: &IsolationRecord) -> Self {
        let all = [
            isolation.roll,
            isolation.pitch,
            isolation.heading,
            isolation.joint,
        ];
        let mut isolated: Option<Unit> = None;
        let mut multiple = false;
        let mut fault = false;
        for i in all {
            match i {
                Isolation::NoFault
                | Isolation::NotCompared
                | Isolation::MagneticDisturbance
                | Isolation::Settling => {}
                Isolation::DetectedNotIsolated => fault = true,
                Isolation::MultipleFault => {
                    fault = true;
                    multiple = true;
                }
                Isolation::Isolated(u) => {
                    fault = true;
                    match isolated {
                        Some(v) if v != u => multiple = true,
                        _ => isolated = Some(u),
                    }
                }
            }
        }
        if multiple {
            isolated = None;
        }
        Self {
            fault,
            isolated,
            multiple,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use PairVerdict::{Fail, Pass};

    fn checker() -> AttitudeChecker {
        // Zero declination: magnetic and true headings are the same number.
        use crate::attitude::checker_tests::{checker_with, fixed};
        checker_with(fixed(0.0))
    }

    /// One axis of a pair: its verdict, and which detector exceeds on this sample.
    fn axis(verdict: PairVerdict, stat: bool, fixed: bool) -> AxisPair {
        AxisPair {
            verdict,
            comparison: None,
            stat_exceeded: stat,
            fixed_exceeded: fixed,
            stat_fault: false,
            fixed_fault: false,
            cusum: 0.0,
        }
    }

    fn joint(verdict: PairVerdict, ratio: Option<f64>) -> JointTest {
        JointTest {
            chi2: ratio.map(|r| r * 25.9),
            ratio,
            verdict,
        }
    }

    /// A pair passing on every axis and the joint test, nothing exceeding.
    fn passing() -> PairRecord {
        let a = axis(Pass, false, false);
        PairRecord {
            roll: a,
            pitch: a,
            heading: a,
            joint: joint(Pass, Some(0.1)),
        }
    }

    fn pairs(bv: PairRecord, bw: PairRecord, vw: PairRecord) -> PairsRecord {
        PairsRecord {
            bahrs_vn200: bv,
            bahrs_watson: bw,
            vn200_watson: vw,
        }
    }

    /// Pairs with the given heading and joint verdicts (roll and pitch passing).
    fn heading_joint(heading: [PairVerdict; 3], joints: [PairVerdict; 3]) -> PairsRecord {
        let [bv, bw, vw] = [0, 1, 2].map(|i| PairRecord {
            heading: axis(heading[i], false, false),
            joint: joint(joints[i], Some(0.1)),
            ..passing()
        });
        pairs(bv, bw, vw)
    }

    #[test]
    fn a_joint_failure_with_the_vn200_that_the_heading_explains_is_the_magnetic_disturbance() {
        // The heading of the magnetic units agrees against the (healthy) VN-200: a magnetic
        // disturbance. A joint failure of BAHRS-VN200 or of VN200-Watson alone is that
        // disturbance showing through the heading, not a fault of its own.
        let md = [Fail, Pass, Fail];
        for joints in [[Fail, Pass, Pass], [Pass, Pass, Fail]] {
            let r = raw_isolation(&heading_joint(md, joints), true);
            assert_eq!(r.heading, Isolation::MagneticDisturbance, "{joints:?}");
            assert_eq!(r.joint, Isolation::MagneticDisturbance, "{joints:?}");
        }
        // A joint failure of BAHRS-Watson, the two magnetic units, is not explained by it.
        let r = raw_isolation(&heading_joint(md, [Pass, Fail, Pass]), true);
        assert_eq!(r.joint, Isolation::DetectedNotIsolated);
        // Without the disturbance on the heading a single joint failure is only detected.
        for joints in [[Fail, Pass, Pass], [Pass, Pass, Fail]] {
            let r = raw_isolation(&heading_joint([Pass; 3], joints), true);
            assert_eq!(r.heading, Isolation::NoFault);
            assert_eq!(r.joint, Isolation::DetectedNotIsolated, "{joints:?}");
        }
        // With an unhealthy VN-200 there is no magnetic excuse: the heading isolates it.
        let r = raw_isolation(&heading_joint(md, [Fail, Pass, Pass]), false);
        assert_eq!(r.heading, Isolation::Isolated(Unit::Vn200));
        assert_eq!(r.joint, Isolation::DetectedNotIsolated);
    }

    /// Roll-axis pairs: BAHRS-VN200 failed and exceeding; BAHRS-Watson passing, exceeding by the
    /// statistical detector only when `second_exceeding`; VN200-Watson passing quietly.
    fn onset(second_exceeding: bool) -> PairsRecord {
        let bv = PairRecord {
            roll: axis(Fail, true, true),
            ..passing()
        };
        let bw = PairRecord {
            roll: axis(Pass, second_exceeding, false),
            ..passing()
        };
        pairs(bv, bw, passing())
    }

    fn roll_at(c: &mut AttitudeChecker, t: i64, p: &PairsRecord) -> Isolation {
        c.settle_isolation(t, raw_isolation(p, true), p).roll
    }

    #[test]
    fn an_onset_settles_for_isolation_settle_s_while_another_pair_exceeds() {
        // isolation_settle_s = 1 s: from the first sample of the onset at t0, "settling" up to
        // t0 + 1 s - 1 ns, then declared "detected, not isolated" at t0 + 1 s.
        assert_eq!(CheckParams::default().isolation_settle_s, 1.0);
        let t0 = 1_000_000_000_000;
        let p = onset(true);
        let mut c = checker();
        assert_eq!(roll_at(&mut c, t0, &p), Isolation::Settling);
        assert_eq!(roll_at(&mut c, t0 + 999_999_999, &p), Isolation::Settling);
        assert_eq!(
            roll_at(&mut c, t0 + 1_000_000_000, &p),
            Isolation::DetectedNotIsolated
        );
        // Once declared it is not withdrawn into settling.
        assert_eq!(
            roll_at(&mut c, t0 + 1_000_000_001, &p),
            Isolation::DetectedNotIsolated
        );
        // A no-fault sample ends the onset: the next one settles its own full second again.
        let quiet = pairs(passing(), passing(), passing());
        assert_eq!(
            roll_at(&mut c, t0 + 2_000_000_000, &quiet),
            Isolation::NoFault
        );
        let t1 = t0 + 3_000_000_000;
        assert_eq!(roll_at(&mut c, t1, &p), Isolation::Settling);
        assert_eq!(roll_at(&mut c, t1 + 999_999_999, &p), Isolation::Settling);
        assert_eq!(
            roll_at(&mut c, t1 + 1_000_000_000, &p),
            Isolation::DetectedNotIsolated
        );
        // Without another exceeding pair nothing is awaited: declared at once.
        let mut c = checker();
        assert_eq!(
            roll_at(&mut c, t0, &onset(false)),
            Isolation::DetectedNotIsolated
        );
    }

    #[test]
    fn either_detector_over_its_limit_makes_a_pair_exceeding() {
        let t0 = 1_000_000_000_000;
        for (stat, fixed) in [(true, false), (false, true)] {
            let mut p = onset(false);
            p.bahrs_watson.roll = axis(Pass, stat, fixed);
            assert_eq!(roll_at(&mut checker(), t0, &p), Isolation::Settling);
        }
    }

    #[test]
    fn the_joint_test_settles_while_another_pairs_ratio_is_over_one() {
        // The joint test's "exceeding" is its ratio over 1 (chi2 over the bound): at exactly 1 it
        // is not, and the failure is declared at once.
        let t0 = 1_000_000_000_000;
        let joint_at = |bw_ratio: f64| {
            let bv = PairRecord {
                joint: joint(Fail, Some(1.5)),
                ..passing()
            };
            let bw = PairRecord {
                joint: joint(Pass, Some(bw_ratio)),
                ..passing()
            };
            let p = pairs(bv, bw, passing());
            checker()
                .settle_isolation(t0, raw_isolation(&p, true), &p)
                .joint
        };
        assert_eq!(joint_at(1.5), Isolation::Settling);
        assert_eq!(joint_at(1.0f64.next_up()), Isolation::Settling);
        assert_eq!(joint_at(1.0), Isolation::DetectedNotIsolated);
        assert_eq!(joint_at(0.5), Isolation::DetectedNotIsolated);
    }

    #[test]
    fn an_isolation_is_held_while_its_failed_pairs_only_clear() {
        // BAHRS isolated on roll (BAHRS-VN200 and BAHRS-Watson failed). Then BAHRS-Watson has
        // cleared and BAHRS-VN200 is still in its hysteresis, no longer exceeding: the BAHRS stays
        // isolated rather than "detected, not isolated".
        let t0 = 1_000_000_000_000;
        let failed = |exceeding: bool| PairRecord {
            roll: axis(Fail, exceeding, false),
            ..passing()
        };
        let mut c = checker();
        let both = pairs(failed(true), failed(true), passing());
        assert_eq!(roll_at(&mut c, t0, &both), Isolation::Isolated(Unit::Bahrs));
        let clearing = pairs(failed(false), passing(), passing());
        assert_eq!(
            roll_at(&mut c, t0 + 20_000_000, &clearing),
            Isolation::Isolated(Unit::Bahrs)
        );
        // A failed pair exceeding again is a new disagreement: the hold ends.
        let again = pairs(failed(true), passing(), passing());
        assert_eq!(
            roll_at(&mut c, t0 + 40_000_000, &again),
            Isolation::DetectedNotIsolated
        );
    }

    #[test]
    fn two_outcomes_isolating_different_units_are_a_multiple_fault() {
        let rec = |roll, pitch| IsolationRecord {
            roll,
            pitch,
            heading: Isolation::NoFault,
            joint: Isolation::NoFault,
        };
        let s = FaultSummary::of(&rec(
            Isolation::Isolated(Unit::Bahrs),
            Isolation::Isolated(Unit::Watson),
        ));
        assert!(s.fault && s.multiple && s.isolated.is_none());
        let s = FaultSummary::of(&rec(
            Isolation::Isolated(Unit::Bahrs),
            Isolation::Isolated(Unit::Bahrs),
        ));
        assert!(s.fault && !s.multiple);
        assert_eq!(s.isolated, Some(Unit::Bahrs));
    }
}
