//! The life cycle of one alert: raise delay, clear hysteresis, latch and acknowledgement.
//!
//! A [`Lifecycle`] is stepped at every evaluation with the time and whether the rule's condition
//! holds (with the severity and reason it would carry). It returns a [`Change`] when the alert's
//! published state changes:
//!
//! ```text
//!             cond held >= raise delay                cond absent >= hysteresis
//! Inactive ------------------------------> Raised ---------------------------------> Inactive
//!     ^   (cond held, < delay: Pending;    |   ^   (latch: -> Latched instead,        (CLEARED)
//!     |    a shorter blip raises nothing)  |   |    LATCHED published)
//!     |                                    v   |
//!     +------ acknowledge (CLEARED) ---- Latched --- cond held >= raise delay (RAISED again)
//! ```
//!
//! Timing is judged at the evaluations only: an alert raises at the first evaluation at which the
//! condition has held for at least the raise delay since the evaluation that first saw it, and
//! clears at the first evaluation at which it has been absent for at least the hysteresis. While
//! raised, a change of severity (a traffic target escalating) is published at once as another
//! RAISED with the new severity; `raised_gps_ns` keeps the first raise.

use vigil_bus::payload::alerts::{STATE_CLEARED, STATE_LATCHED, STATE_RAISED};

use crate::params::RuleTiming;

/// The condition of a rule at one evaluation: it holds, with this severity and reason.
#[derive(Debug, Clone, PartialEq)]
pub struct Condition {
    /// `SEVERITY_*` code.
    pub severity: u8,
    /// Reason text naming the values.
    pub reason: String,
}

/// A published state change.
#[derive(Debug, Clone, PartialEq)]
pub struct Change {
    /// `STATE_*` code.
    pub state: u8,
    /// `SEVERITY_*` code (on a clear: the severity the alert had).
    pub severity: u8,
    /// GPS time of the alert's raise, ns.
    pub raised_gps_ns: i64,
    /// Reason text.
    pub reason: String,
}

/// Where an alert is in its life cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// Not raised; the condition is absent.
    Inactive,
    /// Not raised yet; the condition holds since `since_ns`.
    Pending {
        /// GPS time of the first evaluation that saw the condition, ns.
        since_ns: i64,
    },
    /// Raised.
    Raised {
        /// GPS time of the raise, ns.
        raised_ns: i64,
        /// Severity published.
        severity: u8,
        /// GPS time of the first evaluation without the condition, ns, while it is absent.
        absent_since_ns: Option<i64>,
    },
    /// The condition cleared but the alert latched: it waits for an acknowledgement.
    Latched {
        /// GPS time of the raise, ns.
        raised_ns: i64,
        /// Severity it had.
        severity: u8,
        /// GPS time the condition came back, ns, while it holds again (a raise is pending).
        pending_since_ns: Option<i64>,
    },
}

/// One alert's life-cycle state.
#[derive(Debug, Clone, PartialEq)]
pub struct Lifecycle {
    phase: Phase,
    last_reason: String,
    ack_requested: bool,
}

impl Default for Lifecycle {
    fn default() -> Self {
        Self::new()
    }
}

impl Lifecycle {
    /// An inactive alert.
    pub fn new() -> Self {
        Self {
            phase: Phase::Inactive,
            last_reason: String::new(),
            ack_requested: false,
        }
    }

    /// The current phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// True when nothing is pending, raised or latched (the state can be forgotten).
    pub fn is_idle(&self) -> bool {
        self.phase == Phase::Inactive
    }

    /// Reason of the newest evaluation that saw the condition (empty before any).
    pub fn reason(&self) -> &str {
        &self.last_reason
    }

    /// True while the alert is raised or latched (published as active).
    pub fn is_active(&self) -> bool {
        matches!(self.phase, Phase::Raised { .. } | Phase::Latched { .. })
    }

    /// Asks to clear a latched alert; it is cleared (CLEARED published) at the next step.
    /// Returns false, and does nothing, unless the alert is latched.
    pub fn acknowledge(&mut self) -> bool {
        if matches!(self.phase, Phase::Latched { .. }) {
            self.ack_requested = true;
            true
        } else {
            false
        }
    }

    /// Evaluates at GPS time `t_ns` with the condition `cond` (`None`: absent). Returns the state
    /// change to publish, if any. One step per phase (see the diagram in the module
    /// documentation); the reason of a present condition is kept for the clearing texts.
    pub fn step(
        &mut self,
        t_ns: i64,
        cond: Option<&Condition>,
        timing: &RuleTiming,
    ) -> Option<Change> {
        if let Some(c) = cond {
            self.last_reason.clone_from(&c.reason);
        }
        match self.phase {
            Phase::Inactive | Phase::Pending { .. } => self.step_not_raised(t_ns, cond, timing),
            Phase::Raised {
                raised_ns,
                severity,
                absent_since_ns,
            } => match cond {
                Some(c) => self.step_raised_held(raised_ns, severity, c),
                None => self.step_raised_absent(t_ns, raised_ns, severity, absent_since_ns, timing),
            },
            Phase::Latched {
                raised_ns,
                severity,
                pending_since_ns,
            } => self.step_latched(t_ns, raised_ns, severity, pending_since_ns, cond, timing),
        }
    }

    /// Not raised (inactive or pending): the first evaluation that sees the condition starts the
    /// raise delay, and the alert raises once the condition has held for it. An absence before
    /// then is a blip shorter than the raise delay: nothing was published, back to inactive.
    fn step_not_raised(
        &mut self,
        t_ns: i64,
        cond: Option<&Condition>,
        timing: &RuleTiming,
    ) -> Option<Change> {
        let Some(c) = cond else {
            self.phase = Phase::Inactive;
            return None;
        };
        let since_ns = match self.phase {
            Phase::Pending { since_ns } => since_ns,
            _ => t_ns,
        };
        self.phase = Phase::Pending { since_ns };
        if held(t_ns, since_ns, timing) {
            self.raise(t_ns, c)
        } else {
            None
        }
    }

    /// Raised and the condition still holds: any absence so far is forgotten, and a change of
    /// severity is published at once as another RAISED (keeping the first raise time).
    fn step_raised_held(&mut self, raised_ns: i64, severity: u8, c: &Condition) -> Option<Change> {
        self.phase = Phase::Raised {
            raised_ns,
            severity: c.severity,
            absent_since_ns: None,
        };
        (c.severity != severity).then(|| Change {
            state: STATE_RAISED,
            severity: c.severity,
            raised_gps_ns: raised_ns,
            reason: c.reason.clone(),
        })
    }

    /// Raised and the condition absent: it stays raised until the condition has been absent for
    /// the clear hysteresis, then clears, or latches (LATCHED, waiting for an acknowledgement)
    /// when the rule latches.
    fn step_raised_absent(
        &mut self,
        t_ns: i64,
        raised_ns: i64,
        severity: u8,
        absent_since_ns: Option<i64>,
        timing: &RuleTiming,
    ) -> Option<Change> {
        let since = absent_since_ns.unwrap_or(t_ns);
        if t_ns.saturating_sub(since) < timing.clear_hysteresis_ns() {
            self.phase = Phase::Raised {
                raised_ns,
                severity,
                absent_since_ns: Some(since),
            };
            return None;
        }
        if timing.latch {
            self.phase = Phase::Latched {
                raised_ns,
                severity,
                pending_since_ns: None,
            };
            self.ack_requested = false;
            Some(Change {
                state: STATE_LATCHED,
                severity,
                raised_gps_ns: raised_ns,
                reason: format!("latched until acknowledged: {}", self.last_reason),
            })
        } else {
            self.phase = Phase::Inactive;
            Some(Change {
                state: STATE_CLEARED,
                severity,
                raised_gps_ns: raised_ns,
                reason: format!("cleared: {}", self.last_reason),
            })
        }
    }

    /// Latched: an acknowledgement clears it (CLEARED; a condition already back starts its raise
    /// delay now). Otherwise a condition back for the raise delay raises it again; an absent one
    /// restarts that delay.
    fn step_latched(
        &mut self,
        t_ns: i64,
        raised_ns: i64,
        severity: u8,
        pending_since_ns: Option<i64>,
        cond: Option<&Condition>,
        timing: &RuleTiming,
    ) -> Option<Change> {
        if self.ack_requested {
            self.ack_requested = false;
            // The condition may already be back: its raise delay starts now.
            self.phase = match cond {
                Some(_) => Phase::Pending { since_ns: t_ns },
                None => Phase::Inactive,
            };
            return Some(Change {
                state: STATE_CLEARED,
                severity,
                raised_gps_ns: raised_ns,
                reason: format!("acknowledged: {}", self.last_reason),
            });
        }
        let Some(c) = cond else {
            self.phase = Phase::Latched {
                raised_ns,
                severity,
                pending_since_ns: None,
            };
            return None;
        };
        let since = pending_since_ns.unwrap_or(t_ns);
        if held(t_ns, since, timing) {
            self.raise(t_ns, c)
        } else {
            self.phase = Phase::Latched {
                raised_ns,
                severity,
                pending_since_ns: Some(since),
            };
            None
        }
    }

    fn raise(&mut self, t_ns: i64, c: &Condition) -> Option<Change> {
        self.phase = Phase::Raised {
            raised_ns: t_ns,
            severity: c.severity,
            absent_since_ns: None,
        };
        Some(Change {
            state: STATE_RAISED,
            severity: c.severity,
            raised_gps_ns: t_ns,
            reason: c.reason.clone(),
        })
    }
}

/// Whether a condition seen since `since_ns` has held for the raise delay at `t_ns` (GPS ns).
fn held(t_ns: i64, since_ns: i64, timing: &RuleTiming) -> bool {
    t_ns.saturating_sub(since_ns) >= timing.raise_delay_ns()
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION, SEVERITY_WARNING};

    const MS: i64 = 1_000_000;

    fn cond(severity: u8, reason: &str) -> Condition {
        Condition {
            severity,
            reason: reason.to_string(),
        }
    }

    /// Steps `lc` every 100 ms from `from_ms` (inclusive) to `to_ms` (exclusive) with the
    /// condition `c`; returns (time in ms, change) of every change.
    fn run(
        lc: &mut Lifecycle,
        from_ms: i64,
        to_ms: i64,
        c: Option<&Condition>,
        timing: &RuleTiming,
    ) -> Vec<(i64, Change)> {
        (from_ms..to_ms)
            .step_by(100)
            .filter_map(|t| lc.step(t * MS, c, timing).map(|ch| (t, ch)))
            .collect()
    }

    #[test]
    fn raises_exactly_after_the_delay() {
        // Delay 1 s; the condition appears at t = 0.5 s: held 1.0 s at t = 1.5 s, not at 1.4 s.
        let timing = RuleTiming::new(1.0, 0.0);
        let c = cond(SEVERITY_CAUTION, "x = 3");
        let mut lc = Lifecycle::new();
        assert!(run(&mut lc, 0, 500, None, &timing).is_empty());
        let changes = run(&mut lc, 500, 3000, Some(&c), &timing);
        assert_eq!(changes.len(), 1, "{changes:?}");
        let (t, ch) = &changes[0];
        assert_eq!(*t, 1500);
        assert_eq!(
            ch,
            &Change {
                state: STATE_RAISED,
                severity: SEVERITY_CAUTION,
                raised_gps_ns: 1500 * MS,
                reason: "x = 3".into()
            }
        );
    }

    #[test]
    fn zero_delay_raises_at_the_first_evaluation() {
        let timing = RuleTiming::new(0.0, 0.0);
        let mut lc = Lifecycle::new();
        let ch = lc
            .step(7, Some(&cond(SEVERITY_WARNING, "r")), &timing)
            .unwrap();
        assert_eq!((ch.state, ch.raised_gps_ns), (STATE_RAISED, 7));
        // Hysteresis 0: cleared at the first evaluation without the condition.
        let ch = lc.step(8, None, &timing).unwrap();
        assert_eq!((ch.state, ch.severity), (STATE_CLEARED, SEVERITY_WARNING));
        assert_eq!(ch.raised_gps_ns, 7);
        assert_eq!(ch.reason, "cleared: r");
        assert!(lc.is_idle());
    }

    #[test]
    fn a_blip_shorter_than_the_delay_raises_nothing() {
        let timing = RuleTiming::new(1.0, 0.0);
        let c = cond(SEVERITY_CAUTION, "blip");
        let mut lc = Lifecycle::new();
        // Held from 0 to 0.9 s (last evaluation with it at 0.9 s: held 0.9 s < 1 s), then gone.
        assert!(run(&mut lc, 0, 1000, Some(&c), &timing).is_empty());
        assert!(run(&mut lc, 1000, 1100, None, &timing).is_empty());
        assert!(lc.is_idle());
        // It comes back: the delay starts again from its return at 1.1 s, so it raises at 2.1 s.
        let changes = run(&mut lc, 1100, 2500, Some(&c), &timing);
        assert_eq!(changes.len(), 1);
        assert_eq!(changes[0].0, 2100);
    }

    #[test]
    fn clears_after_the_hysteresis_and_a_return_resets_it() {
        let timing = RuleTiming::new(0.0, 2.0);
        let c = cond(SEVERITY_ADVISORY, "gnss");
        let mut lc = Lifecycle::new();
        assert_eq!(run(&mut lc, 0, 100, Some(&c), &timing).len(), 1);
        // Absent from 0.1 s to 1.9 s (1.8 s < 2 s): still raised. Back at 2.0 s: the count resets.
        assert!(run(&mut lc, 100, 2000, None, &timing).is_empty());
        assert!(run(&mut lc, 2000, 2100, Some(&c), &timing).is_empty());
        // Absent from 2.1 s: clears at 4.1 s exactly.
        let changes = run(&mut lc, 2100, 6000, None, &timing);
        assert_eq!(changes.len(), 1, "{changes:?}");
        assert_eq!(changes[0].0, 4100);
        assert_eq!(changes[0].1.state, STATE_CLEARED);
        assert_eq!(changes[0].1.raised_gps_ns, 0);
    }

    #[test]
    fn latched_stays_latched_until_acknowledged() {
        let timing = RuleTiming {
            latch: true,
            ..RuleTiming::new(0.0, 0.5)
        };
        let c = cond(SEVERITY_CAUTION, "isolated");
        let mut lc = Lifecycle::new();
        assert!(!lc.acknowledge(), "nothing to acknowledge while inactive");
        assert_eq!(run(&mut lc, 0, 1000, Some(&c), &timing).len(), 1);
        assert!(!lc.acknowledge(), "a raised alert is not acknowledged");
        // Condition gone at 1.0 s: latched at 1.5 s, then nothing for a long time.
        let changes = run(&mut lc, 1000, 60_000, None, &timing);
        assert_eq!(changes.len(), 1, "{changes:?}");
        assert_eq!(changes[0].0, 1500);
        assert_eq!(changes[0].1.state, STATE_LATCHED);
        assert_eq!(changes[0].1.reason, "latched until acknowledged: isolated");
        assert!(lc.is_active());
        // Acknowledged: CLEARED at the next evaluation, then idle.
        assert!(lc.acknowledge());
        let ch = lc.step(60_000 * MS, None, &timing).unwrap();
        assert_eq!((ch.state, ch.raised_gps_ns), (STATE_CLEARED, 0));
        assert!(lc.is_idle());
        assert!(lc.step(60_100 * MS, None, &timing).is_none());
    }

    #[test]
    fn a_latched_alert_whose_condition_returns_raises_again() {
        let timing = RuleTiming {
            latch: true,
            ..RuleTiming::new(1.0, 0.0)
        };
        let c = cond(SEVERITY_CAUTION, "again");
        let mut lc = Lifecycle::new();
        assert_eq!(run(&mut lc, 0, 1100, Some(&c), &timing)[0].0, 1000);
        assert_eq!(
            run(&mut lc, 1100, 1200, None, &timing)[0].1.state,
            STATE_LATCHED
        );
        // Back at 2.0 s for 1 s: RAISED again at 3.0 s with a new raise time.
        assert!(run(&mut lc, 1200, 2000, None, &timing).is_empty());
        let changes = run(&mut lc, 2000, 3500, Some(&c), &timing);
        assert_eq!(changes.len(), 1);
        assert_eq!(changes[0].0, 3000);
        assert_eq!(changes[0].1.state, STATE_RAISED);
        assert_eq!(changes[0].1.raised_gps_ns, 3000 * MS);
    }

    #[test]
    fn severity_changes_while_raised_are_published() {
        let timing = RuleTiming::new(0.0, 0.0);
        let mut lc = Lifecycle::new();
        let adv = cond(SEVERITY_ADVISORY, "preventive");
        let warn = cond(SEVERITY_WARNING, "warning");
        assert!(lc.step(0, Some(&adv), &timing).is_some());
        assert!(
            lc.step(1, Some(&adv), &timing).is_none(),
            "no change, nothing"
        );
        let ch = lc.step(2, Some(&warn), &timing).unwrap();
        assert_eq!((ch.state, ch.severity), (STATE_RAISED, SEVERITY_WARNING));
        assert_eq!(ch.raised_gps_ns, 0, "the first raise time is kept");
        let ch = lc.step(3, Some(&adv), &timing).unwrap();
        assert_eq!(ch.severity, SEVERITY_ADVISORY);
    }
}
