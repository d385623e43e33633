//! Live alert filtering per target: M-of-N, minimum persistence, and hysteresis.
//!
//! The raw DO-365 alert level of a target is computed every fusion step with no history; the level
//! shown to a DAA consumer:
//! - rises to level L once at least M of the last N raw levels are >= L (default 2 of 4), so a
//!   single noisy step does not alert;
//! - once raised, is held for at least `persistence_s` (4 s);
//! - falls only after the M-of-N level has stayed below it for `hysteresis_s` (5 s), and then to
//!   that lower level.

use serde::Serialize;

/// Parameters of the alert filter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AlertFilterParams {
    /// Raw levels needed (M) ...
    pub m: usize,
    /// ... among the last N steps.
    pub n: usize,
    /// Minimum time an alert is held once raised, s.
    pub persistence_s: f64,
    /// Time the evidence must stay below the shown level before it falls, s.
    pub hysteresis_s: f64,
}

impl Default for AlertFilterParams {
    fn default() -> Self {
        Self {
            m: 2,
            n: 4,
            persistence_s: 4.0,
            hysteresis_s: 5.0,
        }
    }
}

/// Filter state of one target.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct AlertFilter {
    history: [u8; 8],
    len: usize,
    next: usize,
    /// The filtered level shown.
    pub level: u8,
    raised_at_ns: i64,
    below_since_ns: Option<i64>,
}

impl AlertFilter {
    /// Takes the raw level of a step at GPS time `t_ns`; returns the filtered level.
    pub fn update(&mut self, raw: u8, t_ns: i64, p: &AlertFilterParams) -> u8 {
        let n = p.n.clamp(1, self.history.len());
        self.history[self.next % n] = raw;
        self.next = (self.next + 1) % n;
        self.len = (self.len + 1).min(n);
        let recent = &self.history[..self.len];
        // The highest level that at least M of the last N raw levels reach.
        let evidence = (1..=3u8)
            .rev()
            .find(|&l| recent.iter().filter(|&&r| r >= l).count() >= p.m.max(1))
            .unwrap_or(0);
        if evidence > self.level {
            self.level = evidence;
            self.raised_at_ns = t_ns;
            self.below_since_ns = None;
        } else if evidence < self.level {
            let since = *self.below_since_ns.get_or_insert(t_ns);
            let held = t_ns.saturating_sub(self.raised_at_ns) as f64 * 1e-9 >= p.persistence_s;
            let below = t_ns.saturating_sub(since) as f64 * 1e-9 >= p.hysteresis_s;
            if held && below {
                self.level = evidence;
                self.below_since_ns = None;
                self.raised_at_ns = t_ns;
            }
        } else {
            self.below_since_ns = None;
        }
        self.level
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: i64 = 1_000_000_000;

    fn run(raws: &[u8]) -> Vec<u8> {
        run_with(&AlertFilterParams::default(), raws)
    }

    /// The filtered levels of raw levels given one a second from t = 0.
    fn run_with(p: &AlertFilterParams, raws: &[u8]) -> Vec<u8> {
        let mut f = AlertFilter::default();
        raws.iter()
            .enumerate()
            .map(|(k, &r)| f.update(r, k as i64 * S, p))
            .collect()
    }

    #[test]
    fn one_noisy_step_does_not_alert() {
        assert_eq!(run(&[0, 3, 0, 0, 0, 0]), vec![0; 6]);
    }

    #[test]
    fn two_of_four_raise() {
        assert_eq!(run(&[0, 2, 0, 2, 2]), vec![0, 0, 0, 2, 2]);
        // Mixed levels: two steps >= 2, only one >= 3: level 2.
        assert_eq!(run(&[3, 2, 0, 0])[1], 2);
    }

    #[test]
    fn hysteresis_and_persistence_hold_the_level() {
        // Raised at t = 1 s (2 of 4 at level 3); evidence drops at t = 4 s (only one 3 left in
        // the window at t = 4: [3, 0, 0, 0] has no pair); falls 5 s later at t = 9 s.
        let raws = [3, 3, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        let got = run(&raws);
        assert_eq!(got, vec![0, 3, 3, 3, 3, 3, 3, 3, 3, 0, 0, 0]);
    }

    #[test]
    fn returning_evidence_resets_the_hysteresis() {
        let raws = [2, 2, 0, 0, 0, 2, 2, 0, 0, 0, 0, 0, 0, 0, 0, 0];
        let got = run(&raws);
        // Raised at t = 1. The window loses its second 2 at t = 4 (evidence 0), regains two at
        // t = 6 (which resets the hysteresis), and loses them again at t = 9; the level falls 5 s
        // later, at t = 14.
        assert_eq!(got[..9], [0, 2, 2, 2, 2, 2, 2, 2, 2]);
        assert_eq!(got[13], 2);
        assert_eq!(got[14], 0);
    }

    /// The hold counts from the raise, not from the last step whose evidence matched the level.
    /// Raised at t = 1 s; the evidence stays at the level until t = 10 s and is below from
    /// t = 11 s. With a 2 s hysteresis, a 10 s hold (to t = 11 s) lets it fall at t = 13 s, and a
    /// 14 s hold keeps it to t = 15 s. Counted from t = 10 s instead, it would hold to 20 s or
    /// 24 s; with no hold at all, the second case would fall at t = 13 s.
    #[test]
    fn persistence_counts_from_the_raise() {
        let p = AlertFilterParams {
            persistence_s: 10.0,
            hysteresis_s: 2.0,
            ..AlertFilterParams::default()
        };
        let raws = [2, 2, 2, 2, 2, 2, 2, 2, 2, 0, 0, 0, 0, 0, 0, 0];
        let got = run_with(&p, &raws);
        // The window [2, 2, 0, 0] still holds two 2s at t = 9 and 10; evidence 0 from t = 11.
        assert_eq!(got[..11], [0, 2, 2, 2, 2, 2, 2, 2, 2, 2, 2]);
        // Below since t = 11: the hysteresis ends at t = 13, the hold (from t = 1) at t = 11.
        assert_eq!(got[12], 2);
        assert_eq!(got[13], 0);

        // A hold longer than that: persistence 14 s from the raise at t = 1 ends at t = 15.
        let p = AlertFilterParams {
            persistence_s: 14.0,
            ..p
        };
        let got = run_with(&p, &raws);
        assert_eq!(got[14], 2);
        assert_eq!(got[15], 0);
    }
}
