//! The BAHRS MCU clock against host time (issue 18 point 3, issue 25 point 3).
//!
//! Every BAHRS data message carries (through its time message) the MCU time of its sample, and
//! reaches the host at a known receive time. `d = host time its first byte left - MCU time` is the
//! host-MCU clock offset plus a positive delay (the device's output delay, its transmit queue and
//! the link). As in [`super::host::HostClock`], the minimum of `d` over a second of host time is the
//! offset plus the smallest delay; a line through those minima (the lower envelope) follows the
//! offset and the two crystals' relative drift.
//!
//! The envelope serves three purposes:
//! - naming the GPS second of a synchronisation pulse from the pulse's OWN MCU time (its host time
//!   through the envelope), not from when its 0x06 report happened to arrive (the BAHRS protocol
//!   does not say when it sends 0x06: right after the pulse, late, or repeated);
//! - cross-checking the PPS-disciplined clock: a pulse whose named GPS time disagrees with the host
//!   clock's view of the same MCU time beyond their combined sigma is refused (a wrong edge, a
//!   wrong second);
//! - the fallback when no pulse is usable (sync input not wired, pulses lost, GNSS outage): MCU
//!   time -> host time -> GPS time through the host clock model, with the sigma of both models,
//!   the device's unknown output delay and the port's read pacing.

use std::collections::VecDeque;

/// Parameters of a [`McuHostClock`], with units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McuHostConfig {
    /// Length of one envelope bucket of host time, ns.
    pub bucket_ns: i64,
    /// Buckets kept for the envelope fit.
    pub buckets: usize,
    /// Complete buckets needed before the envelope gives times.
    pub buckets_to_use: usize,
    /// Host time without points after which the envelope gives no time, ns.
    pub stale_after_ns: i64,
    /// Assumed mean of the BAHRS output delay (sample instant to the first byte of its data
    /// message), ns. Decision: the BAHRS protocol document states none; a small MCU sends the
    /// frame right after its sample: 0.5 ms assumed, with [`Self::output_delay_sigma_ns`].
    pub output_delay_ns: i64,
    /// 1-sigma of that output delay, ns (0.5 ms: covers 0 to about 1.5 ms at 2 sigma).
    pub output_delay_sigma_ns: f64,
    /// Complete buckets needed before the slope is fitted; with fewer, the two clocks are taken
    /// to run at the same rate and [`Self::max_relative_drift_ppm`] bounds the error.
    pub buckets_to_fit_slope: usize,
    /// Largest rate difference of the MCU and host clocks, ppm (a bound: 50 ppm of MCU crystal
    /// and 50 of host, assumed).
    pub max_relative_drift_ppm: f64,
}

impl Default for McuHostConfig {
    fn default() -> Self {
        Self {
            bucket_ns: 1_000_000_000,
            buckets: 30,
            buckets_to_use: 2,
            stale_after_ns: 10_000_000_000,
            output_delay_ns: 500_000,
            output_delay_sigma_ns: 500_000.0,
            buckets_to_fit_slope: 5,
            max_relative_drift_ppm: 100.0,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Bucket {
    index: i64,
    min_d: i64,
    tick_at_min: u64,
}

/// Envelope line: `d = c0 + slope * (tick - tick0) * 1000`, with its scatter (all ns).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Line {
    tick0: u64,
    c0: f64,
    slope: f64,
    scatter_ns: f64,
    /// 1-sigma of the slope (fraction).
    slope_sigma: f64,
    /// Mean x of the fit, ns of MCU time after `tick0`.
    x_mean: f64,
    n: usize,
}

/// MCU-microsecond to host-time model of one device clock epoch.
#[derive(Debug, Clone)]
pub struct McuHostClock {
    cfg: McuHostConfig,
    buckets: VecDeque<Bucket>,
    line: Option<Line>,
    last_host_ns: Option<i64>,
}

/// Largest MCU time accepted, us (2^52: the f64 arithmetic below stays exact to the us).
const MAX_TICK_US: u64 = 1 << 52;

impl McuHostClock {
    /// No points yet.
    pub fn new(cfg: McuHostConfig) -> Self {
        Self {
            cfg,
            buckets: VecDeque::with_capacity(cfg.buckets + 1),
            line: None,
            last_host_ns: None,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &McuHostConfig {
        &self.cfg
    }

    /// Forgets every point (the MCU restarted: a new clock epoch).
    pub fn reset(&mut self) {
        self.buckets.clear();
        self.line = None;
        self.last_host_ns = None;
    }

    /// Adds a point: a message whose sample was taken at MCU time `tick_us` and whose first byte
    /// reached the host at `first_byte_host_ns` (its receive minus its transmission time).
    pub fn add(&mut self, tick_us: u64, first_byte_host_ns: i64) {
        if tick_us > MAX_TICK_US {
            return;
        }
        // Bounded: tick below 2^52 us (2^62 ns after the multiplication would overflow, so the
        // product is taken in i128) and host within 0 ..= 2^61 (the aligner clamps it).
        let d = i128::from(first_byte_host_ns) - i128::from(tick_us) * 1000;
        let Ok(d) = i64::try_from(d) else { return };
        let index = first_byte_host_ns.div_euclid(self.cfg.bucket_ns);
        if self
            .last_host_ns
            .is_some_and(|l| first_byte_host_ns < l - self.cfg.bucket_ns)
        {
            // Host time going backwards: not one monotonic clock; start over.
            self.reset();
        }
        self.last_host_ns = Some(
            self.last_host_ns
                .map_or(first_byte_host_ns, |l| l.max(first_byte_host_ns)),
        );
        if let Some(b) = self.buckets.back_mut()
            && b.index == index
        {
            if d < b.min_d {
                b.min_d = d;
                b.tick_at_min = tick_us;
            }
            return;
        }
        self.refit();
        if self.buckets.len() == self.cfg.buckets {
            self.buckets.pop_front();
        }
        self.buckets.push_back(Bucket {
            index,
            min_d: d,
            tick_at_min: tick_us,
        });
    }

    /// Fits the envelope through the complete buckets (every one held when a new one starts).
    fn refit(&mut self) {
        let n = self.buckets.len();
        if n < self.cfg.buckets_to_use.max(1) {
            return;
        }
        let tick0 = self.buckets[0].tick_at_min;
        let d0 = self.buckets[0].min_d;
        // Relative to the first bucket: x in ns of MCU time, y in ns of offset change.
        let xs: Vec<f64> = self
            .buckets
            .iter()
            .map(|b| (b.tick_at_min as f64 - tick0 as f64) * 1000.0)
            .collect();
        let ys: Vec<f64> = self.buckets.iter().map(|b| (b.min_d - d0) as f64).collect();
        let nf = n as f64;
        let xm = xs.iter().sum::<f64>() / nf;
        let ym = ys.iter().sum::<f64>() / nf;
        let sxx: f64 = xs.iter().map(|x| (x - xm).powi(2)).sum();
        let fit_slope = n >= self.cfg.buckets_to_fit_slope.max(3) && sxx > 0.0;
        let slope = if fit_slope {
            xs.iter()
                .zip(&ys)
                .map(|(x, y)| (x - xm) * (y - ym))
                .sum::<f64>()
                / sxx
        } else {
            0.0
        };
        let c = ym - slope * xm;
        let dof = if fit_slope { nf - 2.0 } else { nf - 1.0 };
        let scatter_ns = if dof >= 1.0 {
            let ss: f64 = xs
                .iter()
                .zip(&ys)
                .map(|(x, y)| (y - c - slope * x).powi(2))
                .sum();
            (ss / dof).sqrt()
        } else {
            0.0
        };
        let slope_sigma = if fit_slope {
            scatter_ns / sxx.sqrt()
        } else {
            // A uniform bound as a sigma.
            self.cfg.max_relative_drift_ppm * 1e-6 / 3f64.sqrt()
        };
        self.line = Some(Line {
            tick0,
            c0: d0 as f64 + c,
            slope,
            scatter_ns,
            slope_sigma,
            x_mean: xm,
            n,
        });
    }

    /// Host time at which a message sampled at MCU time `tick_us` would have left its first byte
    /// with the smallest delay seen (ns), and the envelope's 1-sigma (ns: the minima's scatter
    /// and the slope's uncertainty at that distance from the fitted points); `None` before
    /// the envelope is fitted or when its points are older than `stale_after_ns` at host time
    /// `now_ns`.
    pub fn host_ns(&self, tick_us: u64, now_ns: i64) -> Option<(i64, f64)> {
        let line = self.line?;
        let last = self.last_host_ns?;
        if now_ns.saturating_sub(last) > self.cfg.stale_after_ns || tick_us > MAX_TICK_US {
            return None;
        }
        let x = (tick_us as f64 - line.tick0 as f64) * 1000.0;
        let d = line.c0 + line.slope * x;
        let h = tick_us as f64 * 1000.0 + d;
        let sigma = (line.scatter_ns.powi(2) * (1.0 + 1.0 / line.n as f64)
            + (line.slope_sigma * (x - line.x_mean)).powi(2))
        .sqrt();
        Some((h.round() as i64, sigma))
    }

    /// Relative rate of the host clock against the MCU clock, ppm (positive: host fast).
    pub fn drift_ppm(&self) -> Option<f64> {
        self.line.map(|l| l.slope * 1e6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::testrng::Lcg;

    const MS: i64 = 1_000_000;

    #[test]
    fn envelope_follows_offset_and_drift() {
        // An MCU starting at tick 5 s when the host is at 100 s, the host running 40 ppm fast
        // against it; samples at 100 Hz; first byte after a delay uniform in [0.8, 2.8] ms.
        let mut c = McuHostClock::new(McuHostConfig::default());
        let mut rng = Lcg(3);
        let host_of =
            |tick_us: u64| -> f64 { 100e9 + (tick_us as f64 - 5e6) * 1000.0 * (1.0 + 40e-6) };
        for k in 0..2_000u64 {
            let tick = 5_000_000 + k * 10_000;
            let delay = 0.8e6 + rng.unit() * 2e6;
            c.add(tick, (host_of(tick) + delay) as i64);
        }
        // The minima of 100 draws over 2 ms scatter by ~20 us; a line through 20 of them, 1 s
        // apart, has a slope sigma of about 20 us / sqrt(665 s^2) = 0.8 ppm: 2 ppm is 2.5 sigma.
        assert!(
            (c.drift_ppm().unwrap() - 40.0).abs() < 2.0,
            "{:?}",
            c.drift_ppm()
        );
        // A tick 21 s in: the envelope sits at the minimum delay (0.8 ms, within the ~10 us a
        // minimum of 100 uniform draws over 2 ms lies above it).
        let tick = 26_000_000;
        let (h, scatter) = c.host_ns(tick, host_of(tick) as i64).unwrap();
        let err = h as f64 - (host_of(tick) + 0.8e6);
        assert!(err > -1_000.0 && err < 60_000.0, "{err}");
        // Scatter of the minima (~10 us) and the slope's sigma over ~10 s from the fit's mean.
        assert!(scatter < 40_000.0, "{scatter}");
        // Stale after 10 s without points.
        assert_eq!(c.host_ns(tick, host_of(tick) as i64 + 40_000 * MS), None);
        c.reset();
        assert_eq!(c.host_ns(tick, host_of(tick) as i64), None);
    }

    #[test]
    fn garbage_points_do_not_panic() {
        let mut c = McuHostClock::new(McuHostConfig::default());
        for (t, h) in [
            (u64::MAX, i64::MAX),
            (0, 0),
            (MAX_TICK_US, 1 << 61),
            (1, -5),
            (MAX_TICK_US, 0),
        ] {
            c.add(t, h);
            let _ = c.host_ns(t, h);
        }
    }

    const S: i64 = 1_000_000_000;

    /// One point a second: MCU tick `k` s, first byte at host 100 s + `k` s + 1 ms +
    /// `extra[k]` ns (d = host - tick = 100 s + 1 ms + extra).
    fn one_a_second(c: &mut McuHostClock, extra: &[i64]) {
        for (k, e) in extra.iter().enumerate() {
            let k = k as i64;
            c.add(k as u64 * 1_000_000, 100 * S + k * S + MS + e);
        }
    }

    #[test]
    fn envelope_by_hand_before_the_slope_is_fitted() {
        // Two complete buckets (the third point starts a third): minima 0 and 100 ns above
        // 100.001 s. Fewer than 5 buckets: no slope (0 ppm, whatever the minima do), the line at
        // their mean (+50 ns), scatter sqrt(50^2 + 50^2) / (2 - 1) dof = 70.71 ns, and the slope
        // bounded by 100 ppm as a uniform: 100e-6 / sqrt 3.
        let mut c = McuHostClock::new(McuHostConfig::default());
        one_a_second(&mut c, &[0, 100, 0]);
        assert_eq!(c.drift_ppm(), Some(0.0));
        let now = 102 * S;
        // At the points' mean MCU time (0.5 s) only the scatter: 70.71 x sqrt(1 + 1/2).
        let (h, sigma) = c.host_ns(500_000, now).unwrap();
        assert_eq!(h, 500_000_000 + 100 * S + MS + 50);
        assert!((sigma - 86.602_540).abs() < 1e-5, "{sigma}");
        // 1.5 s from it the slope bound adds 57.735 ppb x 1.5 s = 86,602.5 ns.
        let (_, sigma) = c.host_ns(2_000_000, now).unwrap();
        assert!((sigma - 86_602.583_680).abs() < 1e-5, "{sigma}");
    }

    #[test]
    fn envelope_by_hand_with_the_slope_fitted() {
        // Five complete buckets, minima 0, 100, 0, 100, 0 ns at 0..4 s: slope 0 by symmetry,
        // line at +40 ns, residuals -40, 60, -40, 60, -40: ss = 12,000 ns^2 over 5 - 2 dof,
        // scatter 63.2456 ns; sxx = 10 s^2, slope sigma 63.2456 / sqrt(1e19) = 2e-8.
        let mut c = McuHostClock::new(McuHostConfig::default());
        one_a_second(&mut c, &[0, 100, 0, 100, 0, 0]);
        assert_eq!(c.drift_ppm(), Some(0.0));
        let now = 105 * S;
        let (h, sigma) = c.host_ns(2_000_000, now).unwrap();
        assert_eq!(h, 2 * S + 100 * S + MS + 40);
        // At the mean (2 s): 63.2456 x sqrt(1 + 1/5).
        assert!((sigma - 69.282_032).abs() < 1e-5, "{sigma}");
        // 10 s further: sqrt(69.282^2 + (2e-8 x 1e10)^2).
        let (_, sigma) = c.host_ns(12_000_000, now).unwrap();
        assert!((sigma - 211.660_105).abs() < 1e-5, "{sigma}");
        // A drift of exactly 1 ppm (1 us more delay a second) is read as 1 ppm.
        let mut c = McuHostClock::new(McuHostConfig::default());
        one_a_second(&mut c, &[0, 1_000, 2_000, 3_000, 4_000, 5_000]);
        assert!((c.drift_ppm().unwrap() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_stuck_mcu_clock_fits_no_slope() {
        // Six buckets of host time, the MCU time frozen at 7 s: no spread of MCU times to fit a
        // slope through (sxx = 0), so none is fitted rather than 0 / 0.
        let mut c = McuHostClock::new(McuHostConfig::default());
        for k in 0..6 {
            c.add(7_000_000, 100 * S + k * S);
        }
        assert_eq!(c.drift_ppm(), Some(0.0));
        let (_, sigma) = c.host_ns(7_000_000, 105 * S).unwrap();
        assert!(sigma.is_finite());
    }

    #[test]
    fn a_tie_of_minima_keeps_the_first_ones_mcu_time() {
        // Bucket 0 has its minimum twice (MCU 0.2 s and 0.8 s, the same d); buckets 1-5 one each
        // at k + 0.2 s, 1 us more delay a second: through the first of the tie the minima lie on
        // a line of exactly 1 ppm (through the second, 1.08 ppm).
        let mut c = McuHostClock::new(McuHostConfig::default());
        let point = |c: &mut McuHostClock, tick_us: i64, extra: i64| {
            c.add(tick_us as u64, 100 * S + tick_us * 1_000 + MS + extra);
        };
        point(&mut c, 200_000, 0);
        point(&mut c, 800_000, 0);
        for k in 1..=6 {
            point(&mut c, k * 1_000_000 + 200_000, k * 1_000);
        }
        assert!(
            (c.drift_ppm().unwrap() - 1.0).abs() < 1e-9,
            "{:?}",
            c.drift_ppm()
        );
    }

    #[test]
    fn host_time_going_back_more_than_a_bucket_starts_over_and_ticks_end_at_2_pow_52() {
        let fitted = || {
            let mut c = McuHostClock::new(McuHostConfig::default());
            one_a_second(&mut c, &[0, 0, 0]);
            c
        };
        let last = 102 * S + MS;
        // Stale 10 s after the newest point, not at 10 s; MCU times up to 2^52 us only.
        let c = fitted();
        assert!(c.host_ns(1_000_000, last + 10 * S).is_some());
        assert!(c.host_ns(1_000_000, last + 10 * S + 1).is_none());
        assert!(c.host_ns(MAX_TICK_US, last).is_some());
        assert!(c.host_ns(MAX_TICK_US + 1, last).is_none());
        // Exactly one bucket back: kept. 1 ns further: the host clock is not monotonic.
        let mut c = fitted();
        c.add(1_000_000, last - S);
        assert!(c.host_ns(1_000_000, last).is_some());
        let mut c = fitted();
        c.add(1_000_000, last - S - 1);
        assert!(c.host_ns(1_000_000, last).is_none());
        // The largest MCU time taken is 2^52 us: a point there is a point (it keeps the
        // envelope from going stale 10 s on); one past it is refused.
        let later = last + 8 * S;
        let mut c = fitted();
        c.add(MAX_TICK_US, later);
        assert!(c.host_ns(1_000_000, later + 5 * S).is_some());
        let mut c = fitted();
        c.add(MAX_TICK_US + 1, later);
        assert!(c.host_ns(1_000_000, later + 5 * S).is_none());
    }

    #[test]
    fn the_configuration_is_the_one_given() {
        let cfg = McuHostConfig {
            output_delay_ns: 123_456,
            ..McuHostConfig::default()
        };
        assert_eq!(McuHostClock::new(cfg).config(), &cfg);
    }
}
