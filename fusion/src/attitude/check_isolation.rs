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
