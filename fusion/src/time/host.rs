//! The host clock model: host monotonic time -> GPS time, learned from messages whose GPS time is
//! known (the VN-200's), for devices that carry no usable time of their own (the Watson, the
//! TT-Multi-RF CSV and MAVLink outputs).
//!
//! Each reference message gives `d = host receive time - GPS time of its transmission`, which is the
//! host-GPS clock offset plus a positive link delay (OS/USB latency). The caller removes what it
//! knows (the frame's transmission time at its baud rate, the device's output delay) before calling
//! [`HostClock::add`]. The minimum of `d` over a second of host time is the offset plus the smallest
//! delay: a line fitted through those per-second minima (the lower envelope) follows the offset and
//! the host crystal's drift. The mean excess of `d` over the envelope, and its spread, describe the
//! delay distribution; assuming the other ports see the same kind of link (same USB adapter class),
//! a message received at host time `h` was sent at about `h - envelope(h) - mean excess`, with the
//! excess spread as its uncertainty.

use std::collections::VecDeque;

use super::ClockStatus;

/// Parameters of a [`HostClock`], with units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostClockConfig {
    /// Length of one envelope bucket of host time, ns.
    pub bucket_ns: i64,
    /// Buckets kept for the envelope fit.
    pub buckets: usize,
    /// Buckets needed before the model is "locked" (2 give a "locking" model).
    pub buckets_to_lock: usize,
    /// Host time without references after which the model is "coasting", ns.
    pub coast_after_ns: i64,
    /// Host time without references after which the model gives no time, ns.
    pub coast_limit_ns: i64,
    /// 1-sigma of the rate wander of the host clock against GPS while coasting, ppm.
    pub rate_sigma_ppm: f64,
    /// 1-sigma of the reference device's unknown output delay (sample instant to first byte),
    /// ns. The envelope takes the references' delay for link delay, and maps every other port
    /// with it, so an error in the assumed output delay of the reference (the VN-200) shifts
    /// every host-timed sample: its uncertainty is part of every mapped time's sigma.
    pub reference_delay_sigma_ns: f64,
}

impl Default for HostClockConfig {
    fn default() -> Self {
        Self {
            bucket_ns: 1_000_000_000,
            buckets: 30,
            buckets_to_lock: 5,
            coast_after_ns: 2_000_000_000,
            coast_limit_ns: 120_000_000_000,
            rate_sigma_ppm: 1.0,
            // Decision: the VN-200 ICD states no delay from a sample to its output;
            // `Vn200AlignerConfig::output_delay_ns` assumes 0 and the simulator's model sends
            // 0.5 ms after the sample: 0.5 ms (1 sigma) covers an unknown delay up to ~1 ms.
            reference_delay_sigma_ns: 500_000.0,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Bucket {
    index: i64,
    min_d: i64,
    host_at_min: i64,
    n: u32,
    /// First `d` of the bucket: the sums below are relative to it. Decision: `d` is a host
    /// monotonic time minus a GPS time (about -1.4e18 ns for a host clock counting from boot), so
    /// raw sums of `d` squared would lose every nanosecond to f64 rounding.
    ref_d: i64,
    /// Sum of `d - ref_d`, ns.
    sum_d: f64,
    /// Sum of `(d - ref_d)^2`, ns^2.
    sum_d2: f64,
    /// Single-read references ([`HostClock::add_read`]): count, smallest and largest `d`, ns.
    read_n: u32,
    read_min: i64,
    read_max: i64,
}

/// Host-to-GPS clock model.
#[derive(Debug, Clone)]
pub struct HostClock {
    cfg: HostClockConfig,
    buckets: VecDeque<Bucket>,
    last_host_ns: Option<i64>,
    /// Envelope line: d = c0 + c1 * (host - h0), with h0 the first bucket's host time.
    fit: Option<(i64, f64, f64, f64)>,
    excess_mean_ns: f64,
    excess_sigma_ns: f64,
    /// Mean and 1-sigma of a single read's delay over the envelope, ns, and how many single-read
    /// references gave them (issue 18 point 1).
    read_excess: (f64, f64, f64),
}

/// Single-read references needed before [`HostClock::to_gps_read`] uses their delay
/// distribution (fewer: the reference messages' distribution stands in).
const MIN_READ_REFERENCES: f64 = 50.0;

impl HostClock {
    /// A model with no references.
    pub fn new(cfg: HostClockConfig) -> Self {
        Self {
            cfg,
            buckets: VecDeque::with_capacity(cfg.buckets + 1),
            last_host_ns: None,
            fit: None,
            excess_mean_ns: 0.0,
            excess_sigma_ns: 0.0,
            read_excess: (0.0, 0.0, 0.0),
        }
    }

    /// Adds a single-read reference: a host read at `host_ns` that delivered bytes whose last
    /// one left the device at GPS time `gps_ns`, and nothing that could have held it back (the
    /// first read of a message after an idle line). Its delay over the envelope is one read's
    /// latency: the link delay of a port whose message arrives in one read (issue 18 point 1).
    /// It does not move the envelope (learned from whole messages, [`Self::add`]).
    pub fn add_read(&mut self, host_ns: i64, gps_ns: i64) {
        let d = host_ns.saturating_sub(gps_ns);
        if let Some(b) = self.buckets.back_mut() {
            b.read_n += 1;
            b.read_min = b.read_min.min(d);
            b.read_max = b.read_max.max(d);
        }
    }

    /// Adds a reference: a message received at `host_ns` whose transmission started at GPS time
    /// `gps_ns` (after the caller removed its transmission time and known output delay).
    pub fn add(&mut self, host_ns: i64, gps_ns: i64) {
        let d = host_ns.saturating_sub(gps_ns);
        let index = host_ns.div_euclid(self.cfg.bucket_ns);
        if self
            .last_host_ns
            .is_some_and(|last| host_ns < last - self.cfg.bucket_ns)
        {
            // Host time going backwards by more than a bucket: not a monotonic clock; start over.
            self.buckets.clear();
            self.fit = None;
        }
        self.last_host_ns = Some(self.last_host_ns.map_or(host_ns, |l| l.max(host_ns)));
        match self.buckets.back_mut() {
            Some(b) if b.index == index => {
                if d < b.min_d {
                    b.min_d = d;
                    b.host_at_min = host_ns;
                }
                b.n += 1;
                let e = (d - b.ref_d) as f64;
                b.sum_d += e;
                b.sum_d2 += e * e;
                return;
            }
            _ => {}
        }
        // A new bucket: the previous one is complete, refit with it.
        self.refit();
        if self.buckets.len() == self.cfg.buckets {
            self.buckets.pop_front();
        }
        self.buckets.push_back(Bucket {
            index,
            min_d: d,
            host_at_min: host_ns,
            n: 1,
            ref_d: d,
            sum_d: 0.0,
            sum_d2: 0.0,
            read_n: 0,
            read_min: i64::MAX,
            read_max: i64::MIN,
        });
    }

    /// Fits the envelope through the bucket minima. Called when a new bucket starts, so every bucket
    /// held is complete.
    fn refit(&mut self) {
        // Straight from the buckets (no collected copies: this runs once a second on the live
        // path, which allocates nothing; issue 21).
        let complete = &self.buckets;
        let Some(first) = complete.front() else {
            return;
        };
        let h0 = first.host_at_min;
        let n = complete.len() as f64;
        let xs = || complete.iter().map(|b| (b.host_at_min - h0) as f64);
        let ys = || complete.iter().map(|b| b.min_d as f64);
        let x_mean = xs().sum::<f64>() / n;
        let y_mean = ys().sum::<f64>() / n;
        let sxx: f64 = xs().map(|x| (x - x_mean).powi(2)).sum();
        let slope = if complete.len() >= 2 && sxx > 0.0 {
            xs().zip(ys())
                .map(|(x, y)| (x - x_mean) * (y - y_mean))
                .sum::<f64>()
                / sxx
        } else {
            0.0
        };
        let c0 = y_mean - slope * x_mean;
        // Scatter of the minima around the line: part of the mapping uncertainty.
        let scatter = if complete.len() >= 3 {
            let ss: f64 = xs()
                .zip(ys())
                .map(|(x, y)| (y - c0 - slope * x).powi(2))
                .sum();
            (ss / (n - 2.0)).sqrt()
        } else {
            0.0
        };
        // Excess delay over the envelope: mean and spread of d - min per bucket, pooled.
        let (mut cnt, mut sum, mut sum2) = (0.0, 0.0, 0.0);
        for b in complete {
            // The minimum relative to the bucket's reference (small: within the delay spread).
            let m = (b.min_d - b.ref_d) as f64;
            cnt += f64::from(b.n);
            sum += b.sum_d - m * f64::from(b.n);
            sum2 += b.sum_d2 - 2.0 * m * b.sum_d + m * m * f64::from(b.n);
        }
        // Every bucket holds at least the delay that opened it (n >= 1), and there is one:
        // `cnt >= 1`, so no guard.
        self.excess_mean_ns = sum / cnt;
        self.excess_sigma_ns = (sum2 / cnt - self.excess_mean_ns.powi(2)).max(0.0).sqrt();
        // The single reads: mid-range and range per bucket, over the same envelope. Decision: a
        // read can be held back by the one before it (reads come in order), which raises low
        // delays and never the largest nor (with a few idle-line reads a second) the smallest;
        // mean and sum of squares would be biased late by it, the range is not. The delay is
        // taken as uniform over the range (mid-range mean, range / sqrt(12) sigma).
        let (mut cnt, mut mid, mut range) = (0.0, 0.0, 0.0);
        for b in complete.iter().filter(|b| b.read_n >= 2) {
            let n = f64::from(b.read_n);
            cnt += n;
            mid +=
                n * ((b.read_min as f64 - b.min_d as f64) + (b.read_max - b.read_min) as f64 / 2.0);
            range += n * (b.read_max - b.read_min) as f64;
        }
        // Decision: with no bucket of single reads left, the last measure stands. The delay of a
        // single read is the adapter's and the kernel's, not something that drifts; a port
        // whose reads stop being told apart (its chunks no longer stamped) keeps it.
        if cnt > 0.0 {
            self.read_excess = (mid / cnt, range / cnt / 12f64.sqrt(), cnt);
        }
        self.fit = Some((h0, c0, slope, scatter));
    }

    /// Host time (ns) of the latest reference, `None` before the first: whether a lock can be
    /// expected soon (the recorder holds its first messages for the UTC timeline only then).
    pub fn last_reference_host_ns(&self) -> Option<i64> {
        self.last_host_ns
    }

    /// State of the model at host time `now_ns`.
    #[inline]
    pub fn status(&self, now_ns: i64) -> ClockStatus {
        let Some(last) = self.last_host_ns else {
            return ClockStatus::Unlocked;
        };
        // Two buckets or more means a fit: the second is pushed after a refit over the first
        // (and a restart clears both).
        if self.buckets.len() < 2 {
            return ClockStatus::Unlocked;
        }
        let since = now_ns.saturating_sub(last);
        if since > self.cfg.coast_limit_ns {
            ClockStatus::Unlocked
        } else if since > self.cfg.coast_after_ns {
            ClockStatus::Coasting
        } else if self.buckets.len() < self.cfg.buckets_to_lock {
            ClockStatus::Locking
        } else {
            ClockStatus::Locked
        }
    }

    /// GPS time (ns) at which a message received at host time `host_ns` was sent, with its
    /// 1-sigma (ns), or `None` while the model is unlocked. The link delay is the reference
    /// messages' (the VN-200's: several reads each, the last one held back by the others).
    pub fn to_gps(&self, host_ns: i64) -> Option<(i64, f64)> {
        self.map(host_ns, self.excess_mean_ns, self.excess_sigma_ns)
    }

    /// As [`Self::to_gps`], for bytes that came in one read nothing held back: the link delay is
    /// the single reads' ([`Self::add_read`]) once enough were seen, else the reference
    /// messages' (issue 18 point 1).
    pub fn to_gps_read(&self, host_ns: i64) -> Option<(i64, f64)> {
        match self.read_excess {
            (mean, sigma, n) if n >= MIN_READ_REFERENCES => self.map(host_ns, mean, sigma),
            _ => self.to_gps(host_ns),
        }
    }

    /// The spread (max - min, taken as a uniform's sqrt(12) sigma) of a single read's delay, ns,
    /// once enough single reads were seen: how long a read can be held back by the one before.
    pub fn read_spread_ns(&self) -> Option<f64> {
        let (_, sigma, n) = self.read_excess;
        (n >= MIN_READ_REFERENCES).then_some(sigma * 12f64.sqrt())
    }

    /// As [`Self::to_gps`], past the coast limit too (issue 18 point 4): the host-to-GPS relation
    /// held before, extrapolated with its growing sigma (`rate_sigma_ppm` of the time since the
    /// last reference), to cross-check a device's own time with, never to place a sample by.
    /// Decision: a host monotonic clock does not jump, so an old relation still shows a device
    /// time a second off for hours (1 ppm: 0.2 s of 5-sigma tolerance after 11 h); `None`
    /// before the model was ever locked (fewer buckets leave its slope too loose to carry).
    pub fn extrapolate(&self, host_ns: i64) -> Option<(i64, f64)> {
        if self.buckets.len() < self.cfg.buckets_to_lock {
            return None;
        }
        self.map_any(host_ns, self.excess_mean_ns, self.excess_sigma_ns)
    }

    fn map(&self, host_ns: i64, excess_mean_ns: f64, excess_sigma_ns: f64) -> Option<(i64, f64)> {
        if self.status(host_ns) == ClockStatus::Unlocked {
            return None;
        }
        self.map_any(host_ns, excess_mean_ns, excess_sigma_ns)
    }

    /// The mapping of [`Self::map`] whatever the model's status.
    fn map_any(
        &self,
        host_ns: i64,
        excess_mean_ns: f64,
        excess_sigma_ns: f64,
    ) -> Option<(i64, f64)> {
        let (h0, c0, slope, scatter) = self.fit?;
        let d = c0 + slope * host_ns.saturating_sub(h0) as f64;
        let since = host_ns.saturating_sub(self.last_host_ns?).max(0) as f64;
        let drift = self.cfg.rate_sigma_ppm * 1e-6 * since;
        let sigma = (excess_sigma_ns.powi(2)
            + scatter.powi(2)
            + drift.powi(2)
            + self.cfg.reference_delay_sigma_ns.powi(2))
        .sqrt();
        Some((
            host_ns.saturating_sub((d + excess_mean_ns).round() as i64),
            sigma,
        ))
    }

    /// Mean link delay above the minimum, ns (what the model assumes every port adds).
    pub fn excess_delay_ns(&self) -> f64 {
        self.excess_mean_ns
    }

    /// Host clock rate relative to GPS, ppm (positive: the host clock runs fast).
    pub fn drift_ppm(&self) -> Option<f64> {
        self.fit.map(|(_, _, slope, _)| slope * 1e6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::testrng::Lcg;

    const S: i64 = 1_000_000_000;
    const MS: i64 = 1_000_000;

    /// References at 200 Hz from a host clock offset by `offset` and running `ppm` fast, with a
    /// delay uniform in [0.5, 1.5] ms.
    fn feed(clock: &mut HostClock, seconds: i64, offset: i64, ppm: f64, rng: &mut Lcg) {
        for k in 0..seconds * 200 {
            let gps = 1_000 * S + k * 5 * MS;
            let delay = MS / 2 + (rng.unit() * MS as f64) as i64;
            let host = offset + gps + ((gps - 1_000 * S) as f64 * ppm * 1e-6) as i64 + delay;
            clock.add(host, gps);
        }
    }

    #[test]
    fn learns_offset_drift_and_delay() {
        let mut c = HostClock::new(HostClockConfig::default());
        let mut rng = Lcg(1);
        assert_eq!(c.status(0), ClockStatus::Unlocked);
        let offset = 123_456_789_000;
        feed(&mut c, 20, offset, 30.0, &mut rng);
        // Drift: 30 ppm, fitted from minima that sit within a few us of 0.5 ms.
        assert!(
            (c.drift_ppm().unwrap() - 30.0).abs() < 1.0,
            "{:?}",
            c.drift_ppm()
        );
        // Mean excess delay over the minimum: uniform [0.5, 1.5] ms has mean 1.0 ms, minimum
        // ~0.5 ms, so about 0.5 ms; sigma = 1 ms / sqrt(12) = 0.289 ms.
        assert!(
            (c.excess_delay_ns() - 500_000.0).abs() < 30_000.0,
            "{}",
            c.excess_delay_ns()
        );
        // A message sent at GPS 1019.5 s, received with the mean delay.
        let gps = 1_019_500 * MS;
        let host = offset + gps + ((gps - 1_000 * S) as f64 * 30e-6) as i64 + MS;
        let (est, sigma) = c.to_gps(host).unwrap();
        assert!((est - gps).abs() < 50_000, "error {} ns", est - gps);
        // sigma: the delay spread 0.289 ms and the reference's output delay 0.5 ms (default),
        // in quadrature: sqrt(0.289^2 + 0.5^2) = 0.577 ms.
        assert!((sigma - 577_350.0).abs() < 20_000.0, "sigma {sigma}");
        assert_eq!(c.status(host), ClockStatus::Locked);
    }

    #[test]
    fn delay_spread_survives_a_host_clock_far_from_gps() {
        // Regression: a host clock counting from boot (1e12 ns) against GPS time (1.4e18 ns)
        // gives d = -1.4e18 ns; squared sums of raw d lost the spread to rounding (sigma of
        // seconds). Uniform [0.5, 1.5] ms: sigma 1 ms / sqrt(12) = 0.289 ms.
        // Only the delay spread in the sigma.
        let mut c = HostClock::new(HostClockConfig {
            reference_delay_sigma_ns: 0.0,
            ..HostClockConfig::default()
        });
        let mut rng = Lcg(4);
        let g0 = 1_400_000_000 * S;
        for k in 0..4_000 {
            let gps = g0 + k * 5 * MS;
            let delay = MS / 2 + (rng.unit() * MS as f64) as i64;
            c.add(gps - g0 + 1_000 * S + delay, gps);
        }
        let (_, sigma) = c.to_gps(1_015 * S).unwrap();
        assert!((sigma - 288_675.0).abs() < 30_000.0, "sigma {sigma}");
    }

    #[test]
    fn coasts_then_unlocks_without_references() {
        let mut c = HostClock::new(HostClockConfig::default());
        feed(&mut c, 10, 0, 0.0, &mut Lcg(2));
        let last = 1_010 * S;
        assert_eq!(c.status(last + S), ClockStatus::Locked);
        assert_eq!(c.status(last + 10 * S), ClockStatus::Coasting);
        let (_, s1) = c.to_gps(last + S).unwrap();
        let (_, s2) = c.to_gps(last + 60 * S).unwrap();
        assert!(s2 > s1);
        assert_eq!(c.to_gps(last + 200 * S), None);
    }

    #[test]
    fn single_reads_give_their_own_delay() {
        // Messages 3..4 ms late (several reads each), single reads 1..3 ms late (uniform), both
        // from a host clock 7 s ahead of GPS.
        let mut c = HostClock::new(HostClockConfig::default());
        let mut rng = Lcg(5);
        let off = 7 * S;
        for k in 0..4_000 {
            let gps = 1_000 * S + k * 5 * MS;
            c.add(gps + off + 3 * MS + (rng.unit() * MS as f64) as i64, gps);
            if k < 40 {
                // Fewer than 50 single reads so far: the messages' delay stands in.
                assert_eq!(c.to_gps_read(gps + off), c.to_gps(gps + off));
            }
            c.add_read(gps + off + MS + (rng.unit() * 2.0 * MS as f64) as i64, gps);
        }
        // Spread of the single reads: 2 ms (range per second of 200 uniform draws: within 2 %).
        let spread = c.read_spread_ns().unwrap();
        assert!((spread - 2e6).abs() < 40_000.0, "spread {spread}");
        // A read delivered 2 ms (its mean delay) after bytes sent at GPS 1015 s.
        let gps = 1_015 * S;
        let (est, sigma) = c.to_gps_read(gps + off + 2 * MS).unwrap();
        assert!((est - gps).abs() < 50_000, "error {}", est - gps);
        // sigma: 2 ms / sqrt(12) = 0.577 ms and the reference's 0.5 ms: 0.764 ms.
        assert!((sigma - 763_763.0).abs() < 20_000.0, "sigma {sigma}");
        // The messages' own delay (3.5 ms mean) would put it 1.5 ms early.
        let (msg_est, _) = c.to_gps(gps + off + 2 * MS).unwrap();
        assert!(
            (msg_est - (gps - 1_500_000)).abs() < 50_000,
            "{}",
            msg_est - gps
        );
        // 40 s more of messages without single reads: the 30 buckets that measured them roll
        // out, and their measure stands (the refit finds no bucket of reads and keeps it).
        // (While they roll out, the measure comes from fewer buckets; once the last is gone,
        // 31 s after the reads stopped, nothing changes it.)
        let mut kept = None;
        for k in 4_000..12_000 {
            let gps = 1_000 * S + k * 5 * MS;
            c.add(gps + off + 3 * MS + (rng.unit() * MS as f64) as i64, gps);
            if k == 11_000 {
                kept = c.read_spread_ns();
            }
        }
        let kept = kept.unwrap();
        assert!((kept - 2e6).abs() < 60_000.0, "spread {kept}");
        assert_eq!(c.read_spread_ns(), Some(kept));
    }

    /// A clock whose mapped sigma holds no reference-delay or rate term: the excess spread and
    /// the scatter of the bucket minima alone.
    fn bare() -> HostClock {
        HostClock::new(HostClockConfig {
            reference_delay_sigma_ns: 0.0,
            rate_sigma_ppm: 0.0,
            ..HostClockConfig::default()
        })
    }

    /// References received at host times `host_ns` with link delays `delay_ns`.
    fn add_all(c: &mut HostClock, refs: &[(i64, i64)]) {
        for &(host, delay) in refs {
            c.add(host, host - delay);
        }
    }

    #[test]
    fn the_scatter_of_the_bucket_minima_is_part_of_the_sigma() {
        // One reference a second (one per bucket: no excess spread), delays 1 ms + 0, 100, 0,
        // 100, 0 ns; the sixth starts a bucket and fits the five complete ones. By hand: x at
        // 0 .. 4 s, y 0, 100, 0, 100, 0: slope 0, mean 40, residuals -40, 60, -40, 60, -40,
        // ss = 12 000 ns^2, scatter sqrt(12 000 / (5 - 2)) = 63.2456 ns.
        let mut c = bare();
        let refs: Vec<(i64, i64)> = [0, 100, 0, 100, 0, 0]
            .iter()
            .enumerate()
            .map(|(k, extra)| (1_000 * S + k as i64 * S + 500 * MS, MS + extra))
            .collect();
        add_all(&mut c, &refs);
        let (_, sigma) = c.to_gps(refs[5].0).unwrap();
        assert!((sigma - 4_000f64.sqrt()).abs() < 1e-9, "{sigma}");
    }

    #[test]
    fn a_tie_of_bucket_minima_keeps_the_first_ones_time() {
        // Bucket 0 has its minimum twice, at 0.2 s and 0.8 s; buckets 1-4 one each at k + 0.2 s,
        // 1 us more delay a second: through the first of the tie the minima lie on a line of
        // exactly 1 ppm (through the second they would give 1.12 ppm).
        let mut c = bare();
        let t0 = 1_000 * S;
        let mut refs = vec![(t0 + 200 * MS, MS), (t0 + 800 * MS, MS)];
        refs.extend((1..=5).map(|k| (t0 + k * S + 200 * MS, MS + k * 1_000)));
        add_all(&mut c, &refs);
        let ppm = c.drift_ppm().unwrap();
        assert!((ppm - 1.0).abs() < 1e-9, "{ppm}");
    }

    #[test]
    fn host_time_going_back_more_than_a_bucket_starts_over() {
        // Locked on 6 s of references (one bucket a second). A reference exactly one bucket
        // before the newest is kept; one 1 ns further back means the host clock is not
        // monotonic: the model starts over, unlocked.
        let locked = || {
            let mut c = bare();
            let refs: Vec<(i64, i64)> = (0..6).map(|k| (1_000 * S + k * S, MS)).collect();
            add_all(&mut c, &refs);
            assert_eq!(c.status(1_005 * S), ClockStatus::Locked);
            c
        };
        let mut c = locked();
        c.add(1_004 * S, 1_004 * S - MS);
        assert_eq!(c.status(1_005 * S), ClockStatus::Locked);
        let mut c = locked();
        c.add(1_004 * S - 1, 1_004 * S - 1 - MS);
        assert_eq!(c.status(1_005 * S), ClockStatus::Unlocked);
        assert!(c.to_gps(1_005 * S).is_none());
    }

    #[test]
    fn status_edges_by_bucket_count_and_time_since_the_last_reference() {
        // Defaults: 2 buckets make a "locking" model, 5 a locked one; coasting after 2 s
        // without references, unlocked after 120 s. One reference a second (one per bucket).
        let mut c = bare();
        let t0 = 1_000 * S;
        let want = [
            ClockStatus::Unlocked, // 1 bucket: no fit yet
            ClockStatus::Locking,  // 2
            ClockStatus::Locking,  // 3
            ClockStatus::Locking,  // 4
            ClockStatus::Locked,   // 5
        ];
        for (k, want) in want.into_iter().enumerate() {
            let h = t0 + k as i64 * S;
            c.add(h, h - MS);
            assert_eq!(c.status(h), want, "{} bucket(s)", k + 1);
            assert_eq!(c.to_gps(h).is_some(), want != ClockStatus::Unlocked);
        }
        let last = t0 + 4 * S;
        assert_eq!(c.status(last + 2 * S), ClockStatus::Locked);
        assert_eq!(c.status(last + 2 * S + 1), ClockStatus::Coasting);
        assert_eq!(c.status(last + 120 * S), ClockStatus::Coasting);
        assert_eq!(c.status(last + 120 * S + 1), ClockStatus::Unlocked);
        assert!(c.to_gps(last + 120 * S).is_some());
        assert!(c.to_gps(last + 120 * S + 1).is_none());
    }

    #[test]
    fn single_reads_count_from_fifty() {
        // References 1 ms late, one a second; in the second bucket `reads` single reads 0.5 ms
        // late. From 50 reads on, bytes of one read are placed with the reads' delay: 0.5 ms
        // later than through the references' delay. Below 50, the references' delay stands.
        let through = |reads: i64| {
            let mut c = bare();
            let t0 = 1_000 * S;
            for k in 0..8 {
                let h = t0 + k * S;
                c.add(h, h - MS);
                if k == 1 {
                    for j in 0..reads {
                        let hr = h + (10 + j) * MS;
                        c.add_read(hr, hr - MS / 2);
                    }
                }
            }
            let h = t0 + 7 * S + 100 * MS;
            (c.to_gps_read(h).unwrap().0, c.to_gps(h).unwrap().0)
        };
        let (read, refs) = through(49);
        assert_eq!(read, refs);
        let (read, refs) = through(50);
        assert_eq!(read - refs, MS / 2);
    }
}
