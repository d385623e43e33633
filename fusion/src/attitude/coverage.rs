//! Coverage (issue 25, point 1): for each unit (BAHRS, VN-200, Watson) and each check (roll,
//! pitch, heading, vertical channel), when it was last compared and, when it is not compared now,
//! why. Silence from the cross-check must mean "checked and fine", never "not checked": every
//! attitude record (check and prompt) carries a [`CoverageRecord`], and the monitor's
//! `cross_check_unavailable` alert reads it from the attitude payload.
//!
//! A unit is compared on a check record when at least one pair it belongs to was compared on at
//! least one axis; a check (axis) when at least one pair was compared on it; the vertical channel
//! when either of its two comparisons ran. On a prompt record (between check records) a unit or a
//! check counts as compared while its last comparison is at most
//! [`super::params::CheckParams::verdict_max_age_s`] old; older, the prompt's verdicts are
//! `unknown` (not compared), never repeated.
//!
//! Decisions (where the issue names reasons but not their precedence):
//! - A unit whose samples arrive but cannot be put on GPS time is `not_aligned` when some of its
//!   samples were aligned before (PPS lost for longer than the holdover), `not_wired` when none
//!   ever was (the synchronisation input is not wired, or the first pulses have not come yet:
//!   the two cannot be told apart from the data, so the reason names the likelier one and the
//!   README says so). This takes precedence over `stale`/`absent`, which it explains.
//! - `invalid` covers every reason a unit gives itself or the gates find (health, INS mode, error
//!   bits, over-range, frozen, non-finite). A heading that is only not comparable here (no
//!   declination, a magnetic pole zone) is `not_comparable`, on the heading check only.
//! - `no_partner`: the unit is usable but no other unit was, on any axis. `no_check`: no check
//!   ran at all; the checks run at BAHRS sample times, so without a usable BAHRS sample the
//!   VN-200 and the Watson are not compared either (not even with each other: a known gap,
//!   reported rather than hidden).

use serde::Serialize;

use super::gates::{Gate, GateReason};

/// Why a unit or a check was not compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NotComparedReason {
    /// Samples arrive, but none can be put on GPS time now, although some were before (clock
    /// model unlocked: e.g. the BAHRS lost its PPS for longer than the holdover).
    NotAligned,
    /// Samples arrive, but none has ever been put on GPS time (e.g. the BAHRS synchronisation
    /// input is not wired, or its first pulses have not arrived).
    NotWired,
    /// The unit's newest sample is older than its freshness limit.
    Stale,
    /// No sample of the unit at all.
    Absent,
    /// The unit's samples are there but not usable (its own health or mode, error bits,
    /// over-range, frozen, non-finite values).
    Invalid,
    /// The heading cannot be compared here (no declination, near a magnetic pole).
    NotComparable,
    /// The unit is usable, but no other unit was to compare it with.
    NoPartner,
    /// No cross-check ran (checks run at BAHRS sample times: no usable BAHRS sample).
    NoCheck,
}

/// Coverage of one unit or one check.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Coverage {
    /// Compared on this record (a prompt: within the verdict age limit).
    pub compared: bool,
    /// Why not, when not compared.
    pub reason: Option<NotComparedReason>,
    /// Time since the last comparison, s (null when never compared).
    pub age_s: Option<f64>,
}

/// Coverage of every unit and check on one attitude record.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoverageRecord {
    /// BAHRS.
    pub bahrs: Coverage,
    /// VN-200.
    pub vn200: Coverage,
    /// Watson.
    pub watson: Coverage,
    /// Roll check.
    pub roll: Coverage,
    /// Pitch check.
    pub pitch: Coverage,
    /// Heading check.
    pub heading: Coverage,
    /// Vertical channel.
    pub vertical: Coverage,
}

/// Number of coverage slots: three units, then roll, pitch, heading, vertical.
pub const SLOTS: usize = 7;
/// Slot of the roll check (units are 0, 1, 2 in `Unit` order).
pub const SLOT_ROLL: usize = 3;
/// Slot of the vertical channel.
pub const SLOT_VERTICAL: usize = 6;

/// The reason a closed gate gives, for a unit (`heading_only` false) or the heading check.
pub fn reason_of_gate(g: GateReason) -> NotComparedReason {
    match g {
        GateReason::NoData => NotComparedReason::Absent,
        GateReason::Stale => NotComparedReason::Stale,
        GateReason::MagneticPole | GateReason::NoDeclination => NotComparedReason::NotComparable,
        _ => NotComparedReason::Invalid,
    }
}

/// How a unit's samples reach the checker (the pipeline reports the unaligned ones).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Arrival {
    /// The unit's newest sample could not be aligned (or its clock model was unlocked).
    pub unaligned_now: bool,
    /// At least one of its samples was aligned since the start.
    pub ever_aligned: bool,
}

impl Arrival {
    /// The reason for a unit that has no fresh aligned sample (`gate` NoData or Stale): its
    /// samples are arriving unaligned, or the gate's own reason.
    pub fn explain(&self, gate: GateReason) -> NotComparedReason {
        match (gate, self.unaligned_now) {
            (GateReason::NoData | GateReason::Stale, true) if self.ever_aligned => {
                NotComparedReason::NotAligned
            }
            (GateReason::NoData | GateReason::Stale, true) => NotComparedReason::NotWired,
            (g, _) => reason_of_gate(g),
        }
    }
}

/// The coverage state the checker keeps between records.
#[derive(Debug, Clone, Copy, Default)]
pub struct CoverageState {
    /// GPS time of the last comparison per slot, ns.
    pub last_ns: [Option<i64>; SLOTS],
    /// Reason per slot on the newest check record (None where compared).
    pub reason: [Option<NotComparedReason>; SLOTS],
    /// Per unit (BAHRS, VN-200, Watson).
    pub arrival: [Arrival; 3],
}

impl CoverageState {
    /// Records a check at `t_ns`: `compared` and `reason` per slot.
    pub fn record(
        &mut self,
        t_ns: i64,
        compared: [bool; SLOTS],
        reason: [Option<NotComparedReason>; SLOTS],
    ) -> CoverageRecord {
        for (last, &c) in self.last_ns.iter_mut().zip(&compared) {
            if c {
                *last = Some(t_ns);
            }
        }
        self.reason = reason;
        self.at(t_ns, 0.0, |i| reason[i])
    }

    /// The coverage at `t_ns`: a slot is compared when its last comparison is at most `max_age_s`
    /// old; otherwise `why(slot)` (or, when that has nothing, `no_check`).
    pub fn at(
        &self,
        t_ns: i64,
        max_age_s: f64,
        why: impl Fn(usize) -> Option<NotComparedReason>,
    ) -> CoverageRecord {
        let c = |i: usize| {
            let age_s = self.last_ns[i].map(|l| t_ns.saturating_sub(l).max(0) as f64 * 1e-9);
            let compared = age_s.is_some_and(|a| a <= max_age_s);
            Coverage {
                compared,
                reason: if compared {
                    None
                } else {
                    Some(why(i).unwrap_or(NotComparedReason::NoCheck))
                },
                age_s,
            }
        };
        CoverageRecord {
            bahrs: c(0),
            vn200: c(1),
            watson: c(2),
            roll: c(3),
            pitch: c(4),
            heading: c(5),
            vertical: c(6),
        }
    }
}

/// The reason a unit with gates `gates` (roll, pitch, heading) was not compared: its first
/// closed gate explained by its arrival, or `no_partner` when all three are open.
pub fn unit_reason(gates: &[Gate; 3], arrival: &Arrival) -> NotComparedReason {
    // Roll and pitch first: a heading closed only for the declination says nothing of the unit.
    match gates[0].or(gates[1]).or(gates[2]) {
        Some(g) => arrival.explain(g),
        None => NotComparedReason::NoPartner,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unaligned_arrival_explains_a_missing_or_stale_unit() {
        let never = Arrival {
            unaligned_now: true,
            ever_aligned: false,
        };
        let lost = Arrival {
            unaligned_now: true,
            ever_aligned: true,
        };
        let fine = Arrival::default();
        use NotComparedReason as R;
        assert_eq!(never.explain(GateReason::NoData), R::NotWired);
        assert_eq!(lost.explain(GateReason::Stale), R::NotAligned);
        assert_eq!(fine.explain(GateReason::Stale), R::Stale);
        assert_eq!(fine.explain(GateReason::NoData), R::Absent);
        // A unit's own invalidity is reported as such even while its samples are unaligned.
        assert_eq!(lost.explain(GateReason::Frozen), R::Invalid);
        assert_eq!(
            unit_reason(&[None, None, Some(GateReason::NoDeclination)], &fine),
            R::NotComparable
        );
        assert_eq!(unit_reason(&[None; 3], &fine), R::NoPartner);
    }

    #[test]
    fn an_old_comparison_is_not_coverage() {
        let mut s = CoverageState::default();
        let t = 1_000_000_000_000;
        let mut compared = [false; SLOTS];
        compared[0] = true;
        let r = s.record(t, compared, [None; SLOTS]);
        assert!(r.bahrs.compared && r.bahrs.age_s == Some(0.0));
        assert!(!r.vn200.compared && r.vn200.age_s.is_none());
        assert_eq!(r.vn200.reason, Some(NotComparedReason::NoCheck));
        // 0.4 s later within a 0.5 s limit: still covered; 0.6 s later: not, and says why.
        let r = s.at(t + 400_000_000, 0.5, |_| None);
        assert!(r.bahrs.compared);
        let r = s.at(t + 600_000_000, 0.5, |_| {
            Some(NotComparedReason::NotAligned)
        });
        assert!(!r.bahrs.compared);
        assert_eq!(r.bahrs.reason, Some(NotComparedReason::NotAligned));
        assert!((r.bahrs.age_s.unwrap() - 0.6).abs() < 1e-12);
    }
}
