//! Cross-checking a device's own time against the host clock (issue 18 point 4, "VN-200 GPS
//! time vs host; TT time vs host").
//!
//! The witness is the host monotonic clock, which does not jump: each host-to-GPS relation
//! ([`HostClock`]) is learned only from device times that passed this check, so it is the relation
//! held before a fault, whichever device fed it. Two exist: the VN-200's and the TT-Multi-RF's
//! (issue 18 point 6). A device time is compared with the better (smaller sigma) of the two,
//! extrapolated past their coast limit if need be ([`HostClock::extrapolate`]).
//!
//! Decisions:
//! - **Threshold.** A device time `t_dev` (1-sigma `s_dev`) and the host clock's view of the same
//!   instant `t_host` (1-sigma `s_host`, the port's link and output delay included) disagree when
//!   `|t_dev - t_host| > k * sqrt(s_dev^2 + s_host^2) + unknown_link`, with `k` =
//!   [`CrossCheckConfig::sigmas`] (5) and `unknown_link` = [`CrossCheckConfig::unknown_link_ns`]
//!   (20 ms). The second term is the link latency the aligner may not know of: an FTDI adapter
//!   whose latency timer is not configured holds a sparse port's message up to 16 ms (Linux
//!   default) and the stated sigmas do not cover it. A correct device time must not be replaced
//!   by a host time that is worse; the price is that a device time wrong by less than about
//!   25 ms is not caught here (the faults this is for are a second or more: a leap second, a
//!   week, a `ts` a second off, a wrong PPS edge of 100 ms).
//! - **Action.** A disagreeing time is not used and does not feed its host-clock relation; the
//!   sample falls back to another clock with that clock's sigma (the VN-200: its TimeStartup
//!   clock if modelled, else the host clock; the TT-Multi-RF: the host clock), or is marked
//!   [`NotAligned::ClockDisagreement`](super::NotAligned::ClockDisagreement) when there is none;
//!   the device's `clock_disagreement` bit is set until one of its times agrees again. Never a
//!   wrong time with a small sigma.
//! - **Start.** Before either relation was ever locked there is nothing to check against: the
//!   first device times are used unchecked (they are what the host clock is learned from). A
//!   device wrong from power-on therefore defines the relation, and a later, right device is the
//!   one that disagrees (a vote needs a third independent clock; not built).

use super::host::HostClock;

/// Parameters of the cross-check, with units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CrossCheckConfig {
    /// Combined sigmas beyond which two clocks disagree (`k` above).
    pub sigmas: f64,
    /// Link latency the aligner may not know of, ns (added to the tolerance; see the module doc).
    pub unknown_link_ns: f64,
}

impl Default for CrossCheckConfig {
    fn default() -> Self {
        Self {
            sigmas: 5.0,
            unknown_link_ns: 20e6,
        }
    }
}

impl CrossCheckConfig {
    /// The tolerance for a device time of 1-sigma `s_dev` against a host view of 1-sigma
    /// `s_host`, ns: `k * sqrt(s_dev^2 + s_host^2) + unknown_link`.
    pub fn tolerance_ns(&self, s_dev: f64, s_host: f64) -> f64 {
        self.sigmas * (s_dev * s_dev + s_host * s_host).sqrt() + self.unknown_link_ns
    }

    /// Whether a device time `(t, sigma)` disagrees with the host view `(t, sigma)`, ns.
    pub fn disagrees(&self, dev: (i64, f64), host: (i64, f64)) -> bool {
        self.disagrees_after_queue(dev, host, 0)
    }

    /// As [`Self::disagrees`], for a device whose output may have waited up to `queue_ns` in
    /// its own transmit buffer (a full line, [`super::line_load`]): its time may then precede
    /// the host's view of its sending by up to that much more, never follow it. One-sided:
    /// a device time later than the view by more than the tolerance still disagrees (nothing
    /// is received before it is made), and so does one earlier by more than the tolerance and
    /// the queue.
    pub fn disagrees_after_queue(&self, dev: (i64, f64), host: (i64, f64), queue_ns: i64) -> bool {
        let tol = self.tolerance_ns(dev.1, host.1);
        let d = dev.0.saturating_sub(host.0) as f64;
        d > tol || self.early_beyond_queue(dev, host, queue_ns)
    }

    /// The early side of [`Self::disagrees_after_queue`]: the device time precedes the host
    /// view by more than the tolerance and `queue_ns`. On a full line that is a queue longer
    /// than `queue_ns` or a wrong clock, which the host cannot tell apart.
    pub fn early_beyond_queue(&self, dev: (i64, f64), host: (i64, f64), queue_ns: i64) -> bool {
        let tol = self.tolerance_ns(dev.1, host.1);
        let d = dev.0.saturating_sub(host.0) as f64;
        -d > tol + queue_ns.max(0) as f64
    }
}

/// The host clock's view (GPS time, 1-sigma, ns) of host time `host_ns`: the better (smaller
/// sigma) of the two relations, each extrapolated from its last accepted reference; `None` when
/// neither was ever locked (the check cannot run).
pub fn host_view(a: &HostClock, b: &HostClock, host_ns: i64) -> Option<(i64, f64)> {
    match (a.extrapolate(host_ns), b.extrapolate(host_ns)) {
        (Some(x), Some(y)) => Some(if y.1 < x.1 { y } else { x }),
        (x, y) => x.or(y),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::host::HostClockConfig;

    const MS: i64 = 1_000_000;
    const S: i64 = 1_000_000_000;

    #[test]
    fn tolerance_by_hand() {
        let c = CrossCheckConfig::default();
        // 5 x sqrt(0.3^2 + 0.4^2) ms = 2.5 ms, plus 20 ms.
        assert!((c.tolerance_ns(300e3, 400e3) - 22.5e6).abs() < 1.0);
        assert!(!c.disagrees((1_000 * S + 22 * MS, 300e3), (1_000 * S, 400e3)));
        // Exactly at the tolerance (22.5 ms, exact in binary): still agrees; 1 ns more does not.
        assert!(!c.disagrees((1_000 * S + 22_500_000, 300e3), (1_000 * S, 400e3)));
        assert!(c.disagrees((1_000 * S + 22_500_001, 300e3), (1_000 * S, 400e3)));
        assert!(c.disagrees((1_000 * S + 23 * MS, 300e3), (1_000 * S, 400e3)));
        assert!(c.disagrees((1_000 * S - S, 300e3), (1_000 * S, 400e3)));
    }

    #[test]
    fn a_queue_widens_the_early_side_only_by_hand() {
        let c = CrossCheckConfig::default();
        let host = (1_000 * S, 400e3);
        // Tolerance 22.5 ms (above); a queue of up to 500 ms: early by up to 522.5 ms agrees.
        assert!(!c.disagrees_after_queue((1_000 * S - 522_500_000, 300e3), host, 500 * MS));
        assert!(c.disagrees_after_queue((1_000 * S - 522_500_001, 300e3), host, 500 * MS));
        // Late: the queue does not help (a message is not received before it is made).
        assert!(!c.disagrees_after_queue((1_000 * S + 22_500_000, 300e3), host, 500 * MS));
        assert!(c.disagrees_after_queue((1_000 * S + 22_500_001, 300e3), host, 500 * MS));
        // The early side alone: the same boundary; late is never early.
        assert!(!c.early_beyond_queue((1_000 * S - 522_500_000, 300e3), host, 500 * MS));
        assert!(c.early_beyond_queue((1_000 * S - 522_500_001, 300e3), host, 500 * MS));
        assert!(!c.early_beyond_queue((1_000 * S + S, 300e3), host, 500 * MS));
        // Without a queue: the tolerance alone; a negative queue counts as none.
        assert!(!c.early_beyond_queue((1_000 * S - 22_500_000, 300e3), host, 0));
        assert!(c.early_beyond_queue((1_000 * S - 22_500_001, 300e3), host, -MS));
        assert!(!c.early_beyond_queue((1_000 * S - 22_000_000, 300e3), host, -MS));
        // A second early is still a second off.
        assert!(c.disagrees_after_queue((1_000 * S - S, 300e3), host, 500 * MS));
        // 40 ms early (the simulator's full line): only with the queue.
        assert!(c.disagrees((1_000 * S - 40 * MS, 300e3), host));
        assert!(!c.disagrees_after_queue((1_000 * S - 40 * MS, 300e3), host, 500 * MS));
    }

    #[test]
    fn the_view_is_the_relation_held_before_past_the_coast_limit() {
        // A host clock 3 s ahead of GPS, 1 ms link, references for 10 s.
        let mut a = HostClock::new(HostClockConfig::default());
        let b = HostClock::new(HostClockConfig::default());
        assert_eq!(host_view(&a, &b, 0), None);
        for k in 0..1_000 {
            let g = 1_000 * S + k * 10 * MS;
            a.add(g + 3 * S + MS, g);
        }
        // 600 s after the last reference (past the 120 s coast limit): no time to place a sample
        // by, but the view for a check, sigma grown by 1 ppm x 600 s = 0.6 ms.
        let h = 1_610 * S + 3 * S + MS;
        assert_eq!(a.to_gps(h), None);
        let (t, sigma) = host_view(&a, &b, h).unwrap();
        assert!((t - 1_610 * S).abs() < 10_000, "{}", t - 1_610 * S);
        // 0.6 ms of drift and the reference's 0.5 ms output delay in quadrature: 0.78 ms.
        assert!((sigma - 781_000.0).abs() < 5_000.0, "{sigma}");
        // A time a second off disagrees with it.
        assert!(CrossCheckConfig::default().disagrees((t + S, 100.0), (t, sigma)));
    }

    #[test]
    fn the_view_is_the_relation_with_the_smaller_sigma() {
        // Two relations 2 ms apart, from references every 10 ms: the first for 10 s, the second
        // for 5 s only, so its last reference is older and its extrapolation wider.
        let mut fresh = HostClock::new(HostClockConfig::default());
        let mut older = HostClock::new(HostClockConfig::default());
        for k in 0..1_000 {
            let g = 1_000 * S + k * 10 * MS;
            fresh.add(g + 3 * S, g);
            if k < 500 {
                older.add(g + 3 * S + 2 * MS, g);
            }
        }
        let h = 1_020 * S + 3 * S;
        let (sf, so) = (fresh.extrapolate(h).unwrap(), older.extrapolate(h).unwrap());
        assert!(sf.1 < so.1, "{sf:?} {so:?}");
        assert_eq!(host_view(&fresh, &older, h), Some(sf));
        assert_eq!(host_view(&older, &fresh, h), Some(sf));
    }
}
