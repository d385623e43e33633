//! Persistence and hysteresis of one comparison (one pair, one axis), in the manner of the
//! integrity checks of PX4 EKF2: a check returns its raw result every sample, and a fault is only
//! declared after it persists.
//!
//! - The test ratio (|difference| / (threshold x sigma)) is low-passed with a first-order filter of
//!   time constant `filter_tau_s` (about 0.5 s), so a single noisy sample does not count.
//! - A counter rises by the sample interval while the filtered ratio exceeds 1 and falls by it
//!   while it does not; the fault is declared when the counter reaches `declare_after_s` (1 s) and
//!   cleared when it is back to 0: hysteresis of the same length.
//! - An accumulated-excess (CUSUM) detector catches slow drifts that stay just under the threshold:
//!   `S = max(0, S + (z - slack))` over normalised differences `z`, declared at `cusum_limit`.
//!   `S` is capped at twice the limit: it would otherwise keep growing through a long fault and
//!   hold the fault for as long after the units agree again (a 60 s magnetic disturbance kept
//!   its pairs failed for 70 s after it ended); with the cap it drains below the clearing level
//!   (half the limit) in 1.5 x limit / slack samples (45, 0.9 s at 50 Hz, at the defaults).

use serde::Serialize;

/// Parameters of [`Persistence`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PersistenceParams {
    /// Time constant of the test-ratio low-pass filter, s.
    pub filter_tau_s: f64,
    /// Failing time after which a fault is declared (and passing time to clear it), s.
    pub declare_after_s: f64,
    /// CUSUM slack, in sigmas of the normalised difference.
    pub cusum_slack: f64,
    /// CUSUM decision limit, sigma-samples.
    pub cusum_limit: f64,
}

impl Default for PersistenceParams {
    fn default() -> Self {
        Self {
            filter_tau_s: 0.5,
            declare_after_s: 1.0,
            cusum_slack: 2.0,
            cusum_limit: 60.0,
        }
    }
}

/// State of one persistent check.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Persistence {
    /// Low-passed test ratio (1 = at the threshold).
    pub filtered_ratio: f64,
    /// Persistence counter, s.
    pub counter_s: f64,
    /// Accumulated excess of the normalised difference.
    pub cusum: f64,
    /// Fault declared (persistence or CUSUM).
    pub fault: bool,
    initialised: bool,
}

/// One comparison judged by [`Persistence::judge`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Judged {
    /// The difference `a - b`.
    pub diff: f64,
    /// Its test ratio: 1 at `k` combined sigmas.
    pub ratio: f64,
    /// The verdict the persistence holds after taking it.
    pub verdict: super::isolation::PairVerdict,
}

impl Persistence {
    /// Compares `a` with `b` whose combined 1-sigma is `sigma` at `k` sigmas, feeds the result
    /// to the persistence, and returns the difference, ratio and verdict: the step every
    /// signal comparison of the cross-check shares (vertical, inertial).
    pub fn judge(
        &mut self,
        (a, b): (f64, f64),
        sigma: f64,
        k: f64,
        dt_s: f64,
        p: &PersistenceParams,
    ) -> Judged {
        use super::isolation::PairVerdict;
        let diff = a - b;
        let ratio = (diff / sigma).abs() / k;
        let fault = self.update(ratio, diff / sigma, dt_s, p);
        Judged {
            diff,
            ratio,
            verdict: if fault {
                PairVerdict::Fail
            } else {
                PairVerdict::Pass
            },
        }
    }

    /// Updates with one sample: the test ratio `ratio` (1 at the threshold), the normalised
    /// difference `z` (in sigmas) and the time since the previous sample `dt_s`. Returns whether a
    /// fault is declared.
    pub fn update(&mut self, ratio: f64, z: f64, dt_s: f64, p: &PersistenceParams) -> bool {
        let dt = dt_s.clamp(0.0, 1.0);
        if !self.initialised {
            self.filtered_ratio = ratio;
            self.initialised = true;
        } else {
            let alpha = dt / (p.filter_tau_s + dt);
            self.filtered_ratio += alpha * (ratio - self.filtered_ratio);
        }
        if self.filtered_ratio > 1.0 {
            self.counter_s = (self.counter_s + dt).min(p.declare_after_s);
        } else {
            self.counter_s = (self.counter_s - dt).max(0.0);
        }
        self.cusum = (self.cusum + z.abs() - p.cusum_slack).clamp(0.0, 2.0 * p.cusum_limit);
        let cusum_fault = self.cusum >= p.cusum_limit;
        if self.counter_s >= p.declare_after_s || cusum_fault {
            self.fault = true;
        } else if self.counter_s <= 0.0 && self.cusum < p.cusum_limit / 2.0 {
            self.fault = false;
        }
        self.fault
    }

    /// Forgets the history (after a gate closed for long, or a unit recovered).
    pub fn reset(&mut self) {
        *self = Self::default();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn judge_gives_the_difference_its_ratio_and_the_persistent_verdict() {
        use crate::attitude::isolation::PairVerdict;
        let p = PersistenceParams::default();
        let mut per = Persistence::default();
        // 3 against 1 with a combined sigma of 0.5 at 4 sigmas: difference 2 = 4 sigmas, ratio 1.
        let j = per.judge((3.0, 1.0), 0.5, 4.0, 0.1, &p);
        assert_eq!((j.diff, j.ratio), (2.0, 1.0));
        assert_eq!(
            j.verdict,
            PairVerdict::Pass,
            "one sample never declares a fault"
        );
        // Ten times the threshold for longer than declare_after_s: a fault.
        let steps = (p.declare_after_s / 0.1).ceil() as usize + 20;
        let last = (0..steps)
            .map(|_| per.judge((21.0, 1.0), 0.5, 4.0, 0.1, &p))
            .last()
            .unwrap();
        assert_eq!(last.ratio, 10.0);
        assert_eq!(last.verdict, PairVerdict::Fail);
    }

    #[test]
    fn declared_after_one_second_of_failure_and_cleared_after_one_of_passing() {
        let p = PersistenceParams::default();
        let mut s = Persistence::default();
        let dt = 0.01;
        // 100 Hz samples at twice the threshold: the first sample initialises the filter at 2, so
        // the counter starts at once and reaches 1 s after 100 samples.
        let mut declared_at = None;
        for k in 0..200 {
            if s.update(2.0, 0.0, dt, &p) && declared_at.is_none() {
                declared_at = Some(k);
            }
        }
        assert_eq!(declared_at, Some(99));
        // Back to passing: the filter needs ln(2)*0.5 s = 0.35 s to fall below 1, then the counter
        // takes 1 s to drain.
        let mut cleared_at = None;
        for k in 0..300 {
            if !s.update(0.0, 0.0, dt, &p) && cleared_at.is_none() {
                cleared_at = Some(k);
            }
        }
        let k = cleared_at.unwrap();
        assert!((130..=140).contains(&k), "cleared after {k} samples");
    }

    #[test]
    fn a_single_spike_does_not_declare() {
        let p = PersistenceParams::default();
        let mut s = Persistence::default();
        s.update(0.1, 0.0, 0.01, &p);
        // One sample 20x over the threshold: filter alpha = 0.01/0.51, ratio -> 0.1 + 0.0196 x 19.9.
        assert!(!s.update(20.0, 0.0, 0.01, &p));
        for _ in 0..300 {
            assert!(!s.update(0.1, 0.0, 0.01, &p));
        }
    }

    #[test]
    fn a_long_fault_clears_soon_after_the_units_agree_again() {
        let p = PersistenceParams::default();
        let mut s = Persistence::default();
        // 60 s at 50 Hz, 4.42 sigma over (z clamped to the threshold as the checker does).
        for _ in 0..3000 {
            assert!(s.update(0.9, 4.42, 0.02, &p) || s.cusum < p.cusum_limit);
        }
        assert!(s.fault);
        assert_eq!(s.cusum, 2.0 * p.cusum_limit);
        // Agreement again (z = 0): S falls by the slack (2) per sample from 120 to below 30:
        // 46 samples; the counter is already 0 (the ratio stayed under 1).
        let cleared = (1..=200).find(|_| !s.update(0.0, 0.0, 0.02, &p));
        assert_eq!(cleared, Some(46));
    }

    #[test]
    fn cusum_catches_a_drift_under_the_threshold() {
        let p = PersistenceParams::default();
        let mut s = Persistence::default();
        // z = 3 sigma every sample (under a 4.42-sigma threshold): CUSUM grows by 1 per sample and
        // declares after 60 samples.
        let mut at = None;
        for k in 0..100 {
            if s.update(3.0 / 4.42, 3.0, 0.01, &p) && at.is_none() {
                at = Some(k);
            }
        }
        assert_eq!(at, Some(59));
    }

    #[test]
    fn a_ratio_exactly_at_the_threshold_never_counts() {
        // The counter rises while the filtered ratio exceeds 1: at exactly 1 (the first sample
        // sets the filter, and the same ratio leaves it there) it never declares; the next
        // double above 1 declares after declare_after_s (1 s: the 100th sample at 100 Hz).
        let p = PersistenceParams::default();
        let declared_at = |ratio: f64| {
            let mut s = Persistence::default();
            (0..200).find(|_| s.update(ratio, 0.0, 0.01, &p))
        };
        assert_eq!(declared_at(1.0), None);
        assert_eq!(declared_at(1.0f64.next_up()), Some(99));
    }
}
