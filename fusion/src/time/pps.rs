//! A device clock disciplined by PPS pulses: the map from a device's own counter (e.g. the BAHRS
//! MCU microseconds) to GPS time, with an honest uncertainty.
//!
//! In the installation the BAHRS synchronisation input is wired to the VN-200 PPS, and the BAHRS
//! reports the MCU time of each pulse (message 0x06). Each pulse therefore gives one pair
//! (device ticks, GPS time of a whole second). The caller identifies the GPS time of each pulse
//! (from the VN-200's TimeGps - TimeGpsPps around the same host time, [`PpsReferences`]; else
//! from the host clock, [`pulse_second`]); this module fits `t_gps = a + b * ticks` over a
//! sliding window of pulses by least squares, rejects outliers (a pulse whose residual is far
//! outside the fit, e.g. a mis-identified second), detects device resets (time going backwards,
//! or a run of mutually consistent outliers) and re-locks.
//!
//! Uncertainty of a mapped time: the least-squares prediction interval (residual scatter, with a
//! floor of the tick quantisation and pulse jitter) plus the drift uncertainty times the time since
//! the last pulse. With a single pulse the rate is the nominal one with the configured maximum drift
//! (+-50 ppm by default, as a uniform bound: 1 sigma = 50/sqrt(3) ppm).

use std::collections::VecDeque;

use super::ClockStatus;

/// Parameters of a [`PpsClock`], with units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PpsClockConfig {
    /// Nominal length of one device tick, ns (1000 for a microsecond counter).
    pub tick_ns: f64,
    /// Largest frequency error of the device clock, ppm (bound, not sigma).
    pub max_drift_ppm: f64,
    /// Pulses in the fitting window.
    pub window: usize,
    /// Pulses needed after a (re)start before the clock is "locked".
    pub pulses_to_lock: usize,
    /// Device-time gap after the last pulse beyond which the clock is "coasting", s.
    pub coast_after_s: f64,
    /// Device-time gap after the last pulse beyond which no time is given, s.
    pub coast_limit_s: f64,
    /// 1-sigma jitter of the device's pulse time stamp, ns.
    pub pulse_jitter_ns: f64,
    /// 1-sigma random wander of the clock rate between pulses, ppm.
    pub rate_wander_ppm: f64,
    /// A pulse whose residual against the prediction exceeds this (or 6 sigma, if larger) is an
    /// outlier, ns.
    pub outlier_ns: f64,
    /// Consecutive mutually consistent outliers that mean the device clock restarted.
    pub outliers_to_relock: usize,
    /// How far device time may step backwards between observations before it counts as a reset
    /// (time messages of different data streams interleave), s.
    pub backwards_tolerance_s: f64,
}

impl Default for PpsClockConfig {
    fn default() -> Self {
        Self {
            tick_ns: 1000.0,
            max_drift_ppm: 50.0,
            window: 16,
            pulses_to_lock: 3,
            coast_after_s: 1.5,
            coast_limit_s: 30.0,
            pulse_jitter_ns: 2000.0,
            rate_wander_ppm: 0.05,
            outlier_ns: 200_000.0,
            outliers_to_relock: 3,
            backwards_tolerance_s: 0.2,
        }
    }
}

/// What became of a pulse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PulseOutcome {
    /// Taken into the fit.
    Accepted,
    /// Rejected as an outlier.
    Outlier,
    /// The device clock restarted: the fit was cleared and starts again from this pulse.
    Relocked,
}

/// Why a device time could not be mapped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum MapError {
    /// No pulse since start or since the last reset.
    #[error("no synchronisation pulse yet")]
    NoPulse,
    /// The last pulse is longer ago than the coasting limit.
    #[error("last synchronisation pulse too long ago")]
    PulsesLost,
    /// The device time lies before the pulses of the current fit (e.g. a sample from before a
    /// device reset).
    #[error("device time before the current clock model")]
    BeforeModel,
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct Fit {
    /// Reference tick (first pulse of the window).
    tick0: u64,
    /// GPS ns of the reference pulse.
    gps0: i64,
    /// Intercept, ns, relative to gps0 at tick0.
    a: f64,
    /// Slope, ns per tick.
    b: f64,
    /// Mean of x (ticks since tick0) of the window.
    x_mean: f64,
    /// Sum of squared deviations of x.
    sxx: f64,
    /// Residual standard deviation, ns (with its floor).
    s: f64,
    /// Residual scatter beyond the tick quantisation, ns (no floor; 0 below 4 pulses): the
    /// pulse capture jitter the fit sees.
    capture_ns: f64,
    /// Pulses in the fit.
    n: usize,
    /// Tick of the last accepted pulse.
    last_tick: u64,
}

/// A PPS-disciplined device clock model.
#[derive(Debug, Clone)]
pub struct PpsClock {
    cfg: PpsClockConfig,
    pulses: VecDeque<(u64, i64)>,
    outliers: Vec<(u64, i64)>,
    fit: Option<Fit>,
    pulses_since_start: usize,
    last_observed: Option<u64>,
    /// Number of re-locks after a detected device reset.
    pub relocks: u64,
    /// Number of pulses rejected as outliers.
    pub outliers_rejected: u64,
}

impl PpsClock {
    /// A clock with no pulses yet.
    pub fn new(cfg: PpsClockConfig) -> Self {
        Self {
            cfg,
            pulses: VecDeque::with_capacity(cfg.window + 1),
            outliers: Vec::with_capacity(cfg.outliers_to_relock),
            fit: None,
            pulses_since_start: 0,
            last_observed: None,
            relocks: 0,
            outliers_rejected: 0,
        }
    }

    /// The configuration.
    pub fn config(&self) -> &PpsClockConfig {
        &self.cfg
    }

    fn floor_sigma_ns(&self) -> f64 {
        (self.cfg.tick_ns * self.cfg.tick_ns / 12.0 + self.cfg.pulse_jitter_ns.powi(2)).sqrt()
    }

    fn reset_with(&mut self, tick: u64, gps_ns: i64) {
        self.pulses.clear();
        self.outliers.clear();
        self.fit = None;
        self.pulses_since_start = 0;
        self.last_observed = Some(tick);
        self.push(tick, gps_ns);
    }

    fn push(&mut self, tick: u64, gps_ns: i64) {
        if self.pulses.len() == self.cfg.window.max(2) {
            self.pulses.pop_front();
        }
        self.pulses.push_back((tick, gps_ns));
        self.pulses_since_start += 1;
        self.refit();
    }

    fn refit(&mut self) {
        let Some(&(tick0, gps0)) = self.pulses.front() else {
            self.fit = None;
            return;
        };
        let n = self.pulses.len();
        let xs = self
            .pulses
            .iter()
            .map(|&(t, _)| t.wrapping_sub(tick0) as f64);
        let ys = self.pulses.iter().map(|&(_, g)| (g - gps0) as f64);
        let x_mean = xs.clone().sum::<f64>() / n as f64;
        let y_mean = ys.clone().sum::<f64>() / n as f64;
        let sxx: f64 = xs.clone().map(|x| (x - x_mean).powi(2)).sum();
        let sxy: f64 = xs
            .clone()
            .zip(ys.clone())
            .map(|(x, y)| (x - x_mean) * (y - y_mean))
            .sum();
        let b = if n >= 2 && sxx > 0.0 {
            sxy / sxx
        } else {
            self.cfg.tick_ns
        };
        let a = y_mean - b * x_mean;
        let floor = self.floor_sigma_ns();
        let raw = if n >= 3 {
            let ss: f64 = xs.zip(ys).map(|(x, y)| (y - a - b * x).powi(2)).sum();
            Some((ss / (n - 2) as f64).sqrt())
        } else {
            None
        };
        let s = raw.map_or(floor, |r| r.max(floor));
        let capture_ns = match raw {
            Some(r) if n >= 4 => (r * r - self.cfg.tick_ns.powi(2) / 12.0).max(0.0).sqrt(),
            _ => 0.0,
        };
        let last_tick = self.pulses.back().map_or(tick0, |p| p.0);
        self.fit = Some(Fit {
            tick0,
            gps0,
            a,
            b,
            x_mean,
            sxx,
            s,
            capture_ns,
            n,
            last_tick,
        });
    }

    /// Prediction and its 1-sigma for a tick, from the current fit (no gating).
    fn predict(&self, fit: &Fit, tick: u64) -> (f64, f64) {
        let x = tick as f64 - fit.tick0 as f64;
        let y = fit.a + fit.b * x;
        let since_last_s = (tick as f64 - fit.last_tick as f64) * self.cfg.tick_ns * 1e-9;
        let dt_ns = since_last_s.abs() * 1e9;
        let var = if fit.n >= 2 && fit.sxx > 0.0 {
            fit.s * fit.s * (1.0 + 1.0 / fit.n as f64 + (x - fit.x_mean).powi(2) / fit.sxx)
        } else {
            // One pulse: nominal rate with a uniform frequency error bound.
            let rate_sigma = self.cfg.max_drift_ppm * 1e-6 / 3f64.sqrt();
            2.0 * fit.s * fit.s + (rate_sigma * dt_ns).powi(2)
        };
        let wander = self.cfg.rate_wander_ppm * 1e-6 * dt_ns;
        (y, (var + wander * wander).sqrt())
    }

    /// Adds a pulse: the device time stamp of the pulse and the GPS time (ns) of the whole second
    /// it marks.
    pub fn add_pulse(&mut self, tick: u64, gps_ns: i64) -> PulseOutcome {
        if self.pulses.back() == Some(&(tick, gps_ns)) {
            // The same pulse reported twice: nothing new.
            return PulseOutcome::Outlier;
        }
        let backwards = self.pulses.back().is_some_and(|&(t, _)| tick <= t);
        if backwards && self.fit.is_some() {
            self.relocks += 1;
            self.reset_with(tick, gps_ns);
            return PulseOutcome::Relocked;
        }
        // Decision (issue 18): a pulse report's MCU time is not a device-time observation for
        // reset detection: the document does not say when 0x06 is sent, so a late or repeated
        // report carries an MCU time well behind the data's. Resets show in the data messages'
        // times ([`Self::observe`], called by the aligner).
        let Some(fit) = self.fit else {
            self.reset_with(tick, gps_ns);
            return PulseOutcome::Accepted;
        };
        let (pred, sigma) = self.predict(&fit, tick);
        let resid = (gps_ns - fit.gps0) as f64 - pred;
        if resid.abs() <= self.cfg.outlier_ns.max(6.0 * sigma) {
            self.outliers.clear();
            self.push(tick, gps_ns);
            return PulseOutcome::Accepted;
        }
        self.outliers_rejected += 1;
        self.outliers.push((tick, gps_ns));
        if self.outliers.len() >= self.cfg.outliers_to_relock && self.outliers_consistent() {
            let run = std::mem::take(&mut self.outliers);
            self.relocks += 1;
            self.reset_with(run[0].0, run[0].1);
            for &(t, g) in &run[1..] {
                self.push(t, g);
            }
            return PulseOutcome::Relocked;
        }
        if self.outliers.len() >= self.cfg.outliers_to_relock {
            self.outliers.remove(0);
        }
        PulseOutcome::Outlier
    }

    /// True when the recent outliers agree with each other (a new clock, not scattered faults):
    /// their GPS and device time differences agree within the drift bound plus the outlier limit.
    fn outliers_consistent(&self) -> bool {
        self.outliers.windows(2).all(|w| {
            let dt_dev = (w[1].0 as f64 - w[0].0 as f64) * self.cfg.tick_ns;
            let dt_gps = (w[1].1 - w[0].1) as f64;
            dt_dev > 0.0
                && (dt_gps - dt_dev).abs()
                    <= self.cfg.max_drift_ppm * 1e-6 * dt_dev + self.cfg.outlier_ns
        })
    }

    /// Notes a device time seen in the stream (from any time message). A step backwards beyond the
    /// tolerance means the device restarted: the model is dropped until new pulses arrive, so no
    /// sample of the new epoch is mapped through the old model. Returns true on such a reset.
    pub fn observe(&mut self, tick: u64) -> bool {
        let tol = (self.cfg.backwards_tolerance_s * 1e9 / self.cfg.tick_ns) as u64;
        let reset = self
            .last_observed
            .is_some_and(|last| tick.saturating_add(tol) < last);
        if reset && self.fit.is_some() {
            self.pulses.clear();
            self.outliers.clear();
            self.fit = None;
            self.pulses_since_start = 0;
            self.relocks += 1;
        }
        self.last_observed = Some(match self.last_observed {
            Some(last) if !reset => last.max(tick),
            _ => tick,
        });
        reset
    }

    /// The state of the model for a sample at device time `tick`.
    pub fn status(&self, tick: u64) -> ClockStatus {
        match self.fit {
            None => ClockStatus::Unlocked,
            Some(fit) => {
                let since = (tick as f64 - fit.last_tick as f64) * self.cfg.tick_ns * 1e-9;
                if since > self.cfg.coast_limit_s {
                    ClockStatus::Unlocked
                } else if since > self.cfg.coast_after_s {
                    ClockStatus::Coasting
                } else if self.pulses_since_start < self.cfg.pulses_to_lock {
                    ClockStatus::Locking
                } else {
                    ClockStatus::Locked
                }
            }
        }
    }

    /// Maps a device time to GPS time (ns) with its 1-sigma (ns).
    pub fn to_gps(&self, tick: u64) -> Result<(i64, f64), MapError> {
        let fit = self.fit.ok_or(MapError::NoPulse)?;
        let since = (tick as f64 - fit.last_tick as f64) * self.cfg.tick_ns * 1e-9;
        if since > self.cfg.coast_limit_s {
            return Err(MapError::PulsesLost);
        }
        // Samples shortly before the first pulse of the model are fine (e.g. the data just before
        // the first pulse after a restart); far before means another clock epoch.
        let before = (fit.tick0 as f64 - tick as f64) * self.cfg.tick_ns * 1e-9;
        if before > self.cfg.coast_after_s {
            return Err(MapError::BeforeModel);
        }
        let (y, sigma) = self.predict(&fit, tick);
        // Pulse capture jitter (issue 18 point 5): the document does not say how the pulse is
        // captured. A software capture is late by 0 to tens of us, one-sided, so every pulse's
        // MCU time is late and every mapped time early by the mean latency; a hardware capture
        // jitters symmetrically. Decision, to cover both readings: the scatter the fit sees beyond
        // the tick quantisation (`capture_ns`, sigma of a uniform latency of width
        // 2 sqrt(3) sigma, mean sqrt(3) sigma if one-sided) shifts the time by half that mean and
        // adds the shift to the sigma: uniform errors then stay within 2 sigma either way.
        let shift = 3f64.sqrt() / 2.0 * fit.capture_ns;
        Ok((
            fit.gps0 + (y + shift).round() as i64,
            (sigma * sigma + shift * shift).sqrt(),
        ))
    }

    /// Drops the model (its pulses disagreed with another clock) without starting a new device
    /// clock epoch: samples already paired stay mappable once new pulses arrive.
    pub fn clear(&mut self) {
        self.pulses.clear();
        self.outliers.clear();
        self.fit = None;
        self.pulses_since_start = 0;
    }

    /// MCU time of the last pulse in the model, if any.
    pub fn last_pulse_tick(&self) -> Option<u64> {
        self.pulses.back().map(|p| p.0)
    }

    /// The clock epoch: increases at every detected device reset or re-lock. Device times paired
    /// in one epoch must not be mapped through the model of another.
    pub fn epoch(&self) -> u64 {
        self.relocks
    }

    /// Current rate error of the device clock, ppm (positive: the device counts fast), if fitted
    /// from at least two pulses.
    pub fn drift_ppm(&self) -> Option<f64> {
        self.fit
            .filter(|f| f.n >= 2)
            .map(|f| (self.cfg.tick_ns / f.b - 1.0) * 1e6)
    }

    /// Residual standard deviation of the current fit, ns.
    pub fn residual_sigma_ns(&self) -> Option<f64> {
        self.fit.map(|f| f.s)
    }
}

/// The GPS time (ns) of the whole second a pulse marks, given an estimate of the GPS time at which
/// the pulse occurred (e.g. the host receive time of its 0x06 mapped through the host clock, minus
/// the message's transmission time). Rounds to the nearest second, so the estimate may be off by
/// up to +-0.5 s.
pub fn pulse_second(estimate_gps_ns: i64) -> i64 {
    let s = super::gps::NS_PER_S;
    (estimate_gps_ns + s / 2).div_euclid(s) * s
}

/// Where the GPS time of a synchronisation pulse came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PulseSecondSource {
    /// The VN-200's own PPS time (TimeGps - TimeGpsPps) of a message received near the pulse.
    Vn200Pps,
    /// The host clock model: the pulse's receive time mapped to GPS time, rounded to the nearest
    /// whole second (used when no VN-200 PPS time is available).
    HostClock,
}

/// One VN-200 PPS time: a message with valid GPS time and its TimeGpsPps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PpsReference {
    /// Host time at which the message's first byte left the VN-200 (arrival minus its
    /// transmission time), ns.
    pub host_ns: i64,
    /// TimeGps of the message, ns since the GPS epoch.
    pub t_gps_ns: i64,
    /// TimeGps - TimeGpsPps: GPS time of the last PPS before the message, ns.
    pub pps_gps_ns: i64,
}

/// Recent VN-200 PPS times by host time, to name the GPS time of each BAHRS synchronisation pulse
/// (issue 7: "Identify the GPS second of each pulse from the VN-200's TimeGps - TimeGpsPps around
/// the same host time"). The BAHRS sync input is wired to the VN-200 PPS, so the pulse the BAHRS
/// reports is one of the VN-200's PPS edges: the reference nearest in host time names the edge
/// it counts from, and the host-time distance (far below +-0.5 s) tells whether the pulse is that
/// edge or a later one.
///
/// Decisions: a reference is taken only when the VN-200 says its GPS time is valid (the caller's
/// check: TimeStatus / InsStatus, whose "GNSS error" bit also means "no valid PPS") and its
/// TimeGpsPps is below [`PpsReferences::MAX_PPS_AGE_NS`] (an older last PPS means the VN-200's PPS
/// stopped: its time would name an edge the BAHRS never saw). References more than
/// [`PpsReferences::MAX_DISTANCE_NS`] of host time from the pulse are not used.
#[derive(Debug, Clone, Default)]
pub struct PpsReferences {
    refs: VecDeque<PpsReference>,
}

impl PpsReferences {
    /// Host time kept behind the newest reference, ns.
    pub const SPAN_NS: i64 = 2 * super::gps::NS_PER_S;
    /// Most references kept (2 s at the VN-200's 400 Hz maximum output rate is 800).
    pub const CAPACITY: usize = 1024;
    /// Largest host-time distance between a pulse and the reference that names it, ns.
    pub const MAX_DISTANCE_NS: i64 = super::gps::NS_PER_S;
    /// Largest TimeGpsPps accepted, ns (a PPS within the last 1.5 s).
    pub const MAX_PPS_AGE_NS: u64 = 1_500_000_000;
    /// Largest host or GPS time accepted, ns (2^61: 73 years).
    pub const MAX_TIME_NS: i64 = 1 << 61;

    /// No references.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the PPS time of a VN-200 message whose GPS time is valid: first byte left at host
    /// time `host_ns`, TimeGps `t_gps_ns`, TimeGpsPps `pps_age_ns`. Returns false when the
    /// reference is not taken (PPS too old, or time before the PPS epoch).
    pub fn add(&mut self, host_ns: i64, t_gps_ns: i64, pps_age_ns: u64) -> bool {
        // Decision: times outside 0 ..= 2^61 ns (73 years) are garbage; refused, so every sum
        // and difference below fits in an i64.
        let range = 0..=Self::MAX_TIME_NS;
        if pps_age_ns > Self::MAX_PPS_AGE_NS
            || !range.contains(&host_ns)
            || !range.contains(&t_gps_ns)
        {
            return false;
        }
        // Bounded above, so the cast and the subtraction cannot overflow.
        let Some(pps_gps_ns) = t_gps_ns.checked_sub(pps_age_ns as i64).filter(|p| *p >= 0) else {
            return false;
        };
        if self
            .refs
            .back()
            .is_some_and(|b| host_ns < b.host_ns - Self::SPAN_NS)
        {
            // Host time went backwards by more than the span: not the same clock any more.
            self.refs.clear();
        }
        if self.refs.len() == Self::CAPACITY {
            self.refs.pop_front();
        }
        self.refs.push_back(PpsReference {
            host_ns,
            t_gps_ns,
            pps_gps_ns,
        });
        let newest = host_ns;
        while self
            .refs
            .front()
            .is_some_and(|f| f.host_ns < newest.saturating_sub(Self::SPAN_NS))
        {
            self.refs.pop_front();
        }
        true
    }

    /// The reference nearest in host time to `host_ns`, within [`Self::MAX_DISTANCE_NS`].
    pub fn nearest(&self, host_ns: i64) -> Option<&PpsReference> {
        self.refs
            .iter()
            .min_by_key(|r| r.host_ns.abs_diff(host_ns))
            .filter(|r| r.host_ns.abs_diff(host_ns) <= Self::MAX_DISTANCE_NS as u64)
    }

    /// GPS time (ns) of the PPS edge that left the device at about host time `pulse_host_ns`
    /// (the first byte of its 0x06, less the device's reporting latency, which cancels against
    /// the VN-200's output latency to well under a millisecond), or `None` without a reference
    /// near it. The reference's PPS edge plus the whole number of seconds nearest to the pulse's
    /// distance from it: the reference may be a message sampled just before the pulse, whose
    /// last PPS is the previous one.
    pub fn pulse_gps(&self, pulse_host_ns: i64) -> Option<i64> {
        let r = self.nearest(pulse_host_ns)?;
        let s = super::gps::NS_PER_S;
        // Bounded: the reference's times within 0 ..= 2^61 (`add`) and the distance within
        // MAX_DISTANCE_NS (`nearest`).
        let estimate = r.t_gps_ns + (pulse_host_ns - r.host_ns);
        let k = (estimate - r.pps_gps_ns + s / 2).div_euclid(s);
        Some(r.pps_gps_ns + k * s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::gps::NS_PER_S;

    /// A simulated MCU: starts at `offset_us` when GPS time is `gps_start_ns`, runs `drift_ppm`
    /// fast.
    fn mcu_tick(gps_ns: i64, gps_start_ns: i64, offset_us: u64, drift_ppm: f64) -> u64 {
        offset_us + (((gps_ns - gps_start_ns) as f64) * (1.0 + drift_ppm * 1e-6) / 1000.0) as u64
    }

    #[test]
    fn locks_and_maps_with_drift_by_hand() {
        let mut c = PpsClock::new(PpsClockConfig::default());
        let g0 = 1_400_000_000 * NS_PER_S;
        assert_eq!(c.to_gps(0), Err(MapError::NoPulse));
        assert_eq!(c.status(0), ClockStatus::Unlocked);
        // +40 ppm: 1 s of GPS time is 1 000 040 ticks.
        for k in 0..10 {
            let g = g0 + k * NS_PER_S;
            assert_eq!(
                c.add_pulse(mcu_tick(g, g0, 5_000_000, 40.0), g),
                PulseOutcome::Accepted
            );
        }
        assert!(
            (c.drift_ppm().unwrap() - 40.0).abs() < 0.01,
            "{:?}",
            c.drift_ppm()
        );
        let t = g0 + 9 * NS_PER_S + 250_000_000; // 0.25 s after the last pulse
        let tick = mcu_tick(t, g0, 5_000_000, 40.0);
        assert_eq!(c.status(tick), ClockStatus::Locked);
        let (est, sigma) = c.to_gps(tick).unwrap();
        // Error within the tick quantisation (1 us) plus rounding.
        assert!((est - t).abs() <= 1_500, "error {} ns", est - t);
        assert!(sigma > 500.0 && sigma < 5_000.0, "sigma {sigma}");
    }

    #[test]
    fn single_pulse_uses_nominal_rate_with_drift_bound() {
        let mut c = PpsClock::new(PpsClockConfig::default());
        let g0 = 10 * NS_PER_S;
        c.add_pulse(1_000_000, g0);
        assert_eq!(c.status(1_000_000), ClockStatus::Locking);
        let (est, sigma) = c.to_gps(1_500_000).unwrap();
        assert_eq!(est, g0 + 500_000_000);
        // 0.5 s x 50 ppm / sqrt(3) = 14.4 us of drift sigma, plus sqrt(2) x 2 us of jitter.
        assert!((sigma - (14_433.8f64.powi(2) + 2.0 * 2_000.0f64.powi(2)).sqrt()).abs() < 50.0);
    }

    #[test]
    fn outlier_pulse_is_rejected() {
        let mut c = PpsClock::new(PpsClockConfig::default());
        for k in 0..5 {
            c.add_pulse(1_000_000 * k as u64, k * NS_PER_S);
        }
        // A pulse attributed to the wrong second.
        assert_eq!(c.add_pulse(5_000_000, 6 * NS_PER_S), PulseOutcome::Outlier);
        assert_eq!(c.add_pulse(6_000_000, 6 * NS_PER_S), PulseOutcome::Accepted);
        assert_eq!(c.to_gps(6_500_000).unwrap().0, 6 * NS_PER_S + 500_000_000);
    }

    #[test]
    fn device_reset_is_detected_and_relocks() {
        let mut c = PpsClock::new(PpsClockConfig::default());
        for k in 0..5i64 {
            c.add_pulse(100_000_000 + 1_000_000 * k as u64, k * NS_PER_S);
        }
        // The MCU restarts: its time messages jump back to near zero.
        assert!(c.observe(200_000));
        assert_eq!(c.status(200_000), ClockStatus::Unlocked);
        assert_eq!(c.to_gps(200_000), Err(MapError::NoPulse));
        // The first pulse of the new epoch re-locks.
        assert_eq!(c.add_pulse(700_000, 6 * NS_PER_S), PulseOutcome::Accepted);
        assert_eq!(c.to_gps(900_000).unwrap().0, 6 * NS_PER_S + 200_000_000);
        assert_eq!(c.relocks, 1);
        // A pulse going backwards also re-locks at once.
        let mut c2 = PpsClock::new(PpsClockConfig::default());
        c2.add_pulse(5_000_000, 0);
        c2.add_pulse(6_000_000, NS_PER_S);
        assert_eq!(c2.add_pulse(300_000, 2 * NS_PER_S), PulseOutcome::Relocked);
    }

    #[test]
    fn consistent_outliers_mean_a_new_clock() {
        // The clock jumps forward by 0.3 s (a reset that did not go backwards): three consistent
        // outliers re-lock; the samples in between were never mapped with a wrong "locked" time
        // because the old model still fits the old epoch only.
        let mut c = PpsClock::new(PpsClockConfig::default());
        for k in 0..5i64 {
            c.add_pulse(1_000_000 * k as u64, k * NS_PER_S);
        }
        let jump = 300_000u64;
        assert_eq!(
            c.add_pulse(5_000_000 + jump, 5 * NS_PER_S),
            PulseOutcome::Outlier
        );
        assert_eq!(
            c.add_pulse(6_000_000 + jump, 6 * NS_PER_S),
            PulseOutcome::Outlier
        );
        assert_eq!(
            c.add_pulse(7_000_000 + jump, 7 * NS_PER_S),
            PulseOutcome::Relocked
        );
        assert_eq!(
            c.to_gps(7_500_000 + jump).unwrap().0,
            7 * NS_PER_S + 500_000_000
        );
    }

    #[test]
    fn coasting_and_pulse_loss() {
        let mut c = PpsClock::new(PpsClockConfig::default());
        for k in 0..5i64 {
            c.add_pulse(1_000_000 * k as u64, k * NS_PER_S);
        }
        assert_eq!(c.status(4_000_000 + 1_000_000), ClockStatus::Locked);
        assert_eq!(c.status(4_000_000 + 2_000_000), ClockStatus::Coasting);
        let (_, s_near) = c.to_gps(4_500_000).unwrap();
        let (_, s_far) = c.to_gps(4_000_000 + 20_000_000).unwrap();
        assert!(s_far > s_near);
        assert_eq!(c.to_gps(4_000_000 + 31_000_000), Err(MapError::PulsesLost));
    }

    #[test]
    fn pulse_named_by_the_vn200_pps_near_a_second_boundary() {
        const MS: i64 = 1_000_000;
        // Host clock 7 s ahead of GPS; VN-200 first bytes 2 ms after their sample.
        let off = 7 * NS_PER_S;
        let mut r = PpsReferences::new();
        assert_eq!(r.pulse_gps(100 * NS_PER_S), None);
        // A message sampled 2 ms before the pulse at 100 s: its last PPS was 99 s (TimeGpsPps
        // 998 ms). The pulse's 0x06 leaves about 3 ms after that message: 100 s, not 99 s.
        let t = 100 * NS_PER_S - 2 * MS;
        assert!(r.add(t + off + 2 * MS, t, 998 * MS as u64));
        assert_eq!(r.pulse_gps(100 * NS_PER_S + off + MS), Some(100 * NS_PER_S));
        // A message 1 ms after the pulse (TimeGpsPps 1 ms) names the same edge.
        let t = 100 * NS_PER_S + MS;
        assert!(r.add(t + off + 2 * MS, t, MS as u64));
        assert_eq!(
            r.pulse_gps(100 * NS_PER_S + off + 2 * MS),
            Some(100 * NS_PER_S)
        );
        // Far from every reference: no answer (the caller falls back to the host clock).
        assert_eq!(r.pulse_gps(100 * NS_PER_S + off + 2 * NS_PER_S), None);
        // A PPS edge off the whole second (0.25 s phase) is named as the VN-200 reports it:
        // message at 200.3 s, last PPS 200.25 s; pulse about 1 s later.
        let mut r = PpsReferences::new();
        let t = 200 * NS_PER_S + 300 * MS;
        assert!(r.add(t + off, t, 50 * MS as u64));
        assert_eq!(
            r.pulse_gps(201 * NS_PER_S + 250 * MS + off + MS),
            Some(201 * NS_PER_S + 250 * MS)
        );
    }

    #[test]
    fn stale_pps_times_are_not_references() {
        let mut r = PpsReferences::new();
        // TimeGpsPps of 2 s: the VN-200's PPS stopped.
        assert!(!r.add(10 * NS_PER_S, 10 * NS_PER_S, 2_000_000_000));
        // TimeGpsPps larger than TimeGps: no PPS epoch.
        assert!(!r.add(0, 1_000, 1_000_000));
        assert_eq!(r.pulse_gps(10 * NS_PER_S), None);
        // Garbage times are refused.
        assert!(!r.add(i64::MIN, 10 * NS_PER_S, 0));
        assert!(!r.add(0, i64::MAX, 0));
        // Old references age out: 3 s later only the new one is near.
        assert!(r.add(10 * NS_PER_S, 10 * NS_PER_S, 0));
        assert!(r.add(13 * NS_PER_S, 13 * NS_PER_S, 0));
        assert_eq!(r.nearest(10 * NS_PER_S), None);
        assert_eq!(r.pulse_gps(13 * NS_PER_S + 1_000), Some(13 * NS_PER_S));
    }

    #[test]
    fn pulse_second_rounds_to_the_nearest_second() {
        assert_eq!(pulse_second(5 * NS_PER_S + 3_000_000), 5 * NS_PER_S);
        assert_eq!(pulse_second(5 * NS_PER_S - 3_000_000), 5 * NS_PER_S);
        assert_eq!(pulse_second(5 * NS_PER_S + 499_000_000), 5 * NS_PER_S);
        assert_eq!(pulse_second(5 * NS_PER_S + 501_000_000), 6 * NS_PER_S);
    }

    #[test]
    fn the_configuration_is_the_one_given() {
        let cfg = PpsClockConfig {
            pulses_to_lock: 7,
            ..PpsClockConfig::default()
        };
        assert_eq!(PpsClock::new(cfg).config(), &cfg);
    }

    #[test]
    fn fit_scatter_capture_and_floor_by_hand() {
        // No pulse jitter configured: the floor is the tick quantisation alone, 1 us / sqrt 12
        // = 288.675 ns (with the default 2 us jitter: sqrt(1e6 / 12 + 4e6) = 2,020.726 ns).
        assert!(
            (PpsClock::new(PpsClockConfig::default()).floor_sigma_ns() - 2_020.725_942).abs()
                < 1e-5
        );
        let cfg = PpsClockConfig {
            pulse_jitter_ns: 0.0,
            ..PpsClockConfig::default()
        };
        let g0 = 1_000 * NS_PER_S;
        let tick = |k: i64| 5_000_000 + k as u64 * 1_000_000;
        // Pulses on whole seconds, the 2nd and 4th GPS times 3 us late.
        let late = [0, 3_000, 0, 3_000];
        let mut c = PpsClock::new(cfg);
        for (k, late) in late.iter().enumerate() {
            let k = k as i64;
            assert_eq!(
                c.add_pulse(tick(k), g0 + k * NS_PER_S + late),
                PulseOutcome::Accepted
            );
            if k == 1 {
                // Two pulses leave no residual to measure: the floor.
                assert!((c.residual_sigma_ns().unwrap() - 288.675_134).abs() < 1e-5);
            }
        }
        // Least squares by hand (Python's statistics.linear_regression agrees): slope
        // 1,000.0006 ns a tick, intercept 600 ns, residuals -600, 1800, -1800, 600 ns;
        // ss = 7.2e6 ns^2 over 4 - 2 dof: 1,897.367 ns.
        let s = c.residual_sigma_ns().unwrap();
        assert!((s - 1_897.366_596).abs() < 1e-5, "{s}");
        assert!((c.drift_ppm().unwrap() + 0.6).abs() < 1e-6);
        // Capture scatter beyond the quantisation, sqrt(1897.367^2 - 1e6 / 12) = 1,875.278 ns;
        // the time moves by sqrt 3 / 2 of it (1,624.038 ns), which adds to the sigma:
        // sqrt(1897.367^2 (1 + 1/4 + (1.5e6)^2 / 5e12) + 1624.038^2) = 2,959.307 ns at the last
        // pulse (no wander there).
        let (t, sigma) = c.to_gps(tick(3)).unwrap();
        assert_eq!(t, g0 + 3_000_004_024);
        assert!((sigma - 2_959.307_351).abs() < 1e-5, "{sigma}");
        // 10 s past the last pulse the rate wander adds 0.05 ppm x 10 s = 500 ns (root sum
        // square): sqrt(1897.367^2 (1 + 1/4 + (11.5e6)^2 / 5e12) + 500^2 + 1624.038^2).
        let (t, sigma) = c.to_gps(tick(13)).unwrap();
        assert_eq!(t, g0 + 13_000_010_024);
        assert!((sigma - 10_129.536_021).abs() < 1e-5, "{sigma}");
        // Three pulses (the 2nd 3 us late): residual 2,449.49 ns over 1 dof, but no capture
        // shift before 4 pulses: the line itself, 1,000 ns a tick from +1,000 ns.
        let mut c = PpsClock::new(cfg);
        for (k, late) in [0, 3_000, 0].iter().enumerate() {
            let k = k as i64;
            c.add_pulse(tick(k), g0 + k * NS_PER_S + late);
        }
        assert!((c.residual_sigma_ns().unwrap() - 2_449.489_743).abs() < 1e-5);
        assert_eq!(c.to_gps(tick(2)).unwrap().0, g0 + 2_000_001_000);
        // Five pulses (0, 3, 0, 3, 0 us late): residuals over 5 - 2 dof, 1,897.367 ns.
        let mut c = PpsClock::new(cfg);
        for (k, late) in [0, 3_000, 0, 3_000, 0].iter().enumerate() {
            let k = k as i64;
            c.add_pulse(tick(k), g0 + k * NS_PER_S + late);
        }
        assert!((c.residual_sigma_ns().unwrap() - 1_897.366_596).abs() < 1e-5);
    }

    /// A clock with pulses on the whole seconds 0..5 at ticks 1 s apart.
    fn five_pulses() -> PpsClock {
        let mut c = PpsClock::new(PpsClockConfig::default());
        for k in 0..5i64 {
            c.add_pulse(1_000_000 * k as u64, k * NS_PER_S);
        }
        c
    }

    #[test]
    fn status_edges_pulses_to_lock_and_coasting() {
        // 3 pulses lock; coasting from 1.5 s after the last pulse (exactly 1.5 s is not yet);
        // no time from 30 s on.
        let mut c = PpsClock::new(PpsClockConfig::default());
        c.add_pulse(0, 0);
        c.add_pulse(1_000_000, NS_PER_S);
        assert_eq!(c.status(1_000_000), ClockStatus::Locking);
        c.add_pulse(2_000_000, 2 * NS_PER_S);
        assert_eq!(c.status(2_000_000), ClockStatus::Locked);
        assert_eq!(c.status(3_500_000), ClockStatus::Locked);
        assert_eq!(c.status(3_500_001), ClockStatus::Coasting);
        assert_eq!(c.status(31_000_000), ClockStatus::Coasting);
        assert_eq!(c.status(33_000_000), ClockStatus::Unlocked);
        // A sample up to 1.5 s before the model's first pulse is mapped (data just before the
        // first pulse after a restart); earlier is another epoch. The first pulse is at tick 0
        // here, so start one at 2 s.
        let mut c = PpsClock::new(PpsClockConfig::default());
        c.add_pulse(2_000_000, 2 * NS_PER_S);
        assert_eq!(c.to_gps(500_000).unwrap().0, NS_PER_S / 2);
        assert_eq!(c.to_gps(499_999), Err(MapError::BeforeModel));
    }

    #[test]
    fn relocks_and_outliers_are_counted() {
        // A pulse going backwards re-locks at once; each re-lock opens a new epoch.
        let mut c = five_pulses();
        assert_eq!(c.add_pulse(300_000, 5 * NS_PER_S), PulseOutcome::Relocked);
        assert_eq!((c.relocks, c.epoch()), (1, 1));
        c.add_pulse(1_300_000, 6 * NS_PER_S);
        assert_eq!(c.add_pulse(200_000, 7 * NS_PER_S), PulseOutcome::Relocked);
        assert_eq!(c.epoch(), 2);
        // A wrong second is one outlier.
        let mut c = five_pulses();
        assert_eq!(c.add_pulse(5_000_000, 6 * NS_PER_S), PulseOutcome::Outlier);
        assert_eq!((c.outliers_rejected, c.relocks), (1, 0));
    }

    #[test]
    fn outliers_relock_only_when_they_agree_with_each_other() {
        // Three outliers 999,760 us of MCU time apart for 1 s of GPS: 240 us apart from the
        // nominal, within 50 ppm x 0.99976 s + 200 us = 249.988 us: a new clock (a fourth one
        // would be too late to say so).
        let mut c = five_pulses();
        let run = [(5_300_000, 5), (6_299_760, 6), (7_299_520, 7)];
        let got: Vec<_> = run
            .iter()
            .map(|&(t, s)| c.add_pulse(t, s * NS_PER_S))
            .collect();
        use PulseOutcome::{Outlier, Relocked};
        assert_eq!(got, [Outlier, Outlier, Relocked]);
        assert_eq!((c.outliers_rejected, c.relocks), (3, 1));
        // Scattered outliers (0.3, 0.7 and 0.1 s off) are faults, not a clock: the old model
        // stays and still maps its own epoch.
        let mut c = five_pulses();
        for (t, s) in [(5_300_000, 5), (6_700_000, 6), (7_100_000, 7)] {
            assert_eq!(c.add_pulse(t, s * NS_PER_S), Outlier);
        }
        assert_eq!(c.relocks, 0);
        assert_eq!(c.to_gps(4_500_000).unwrap().0, 4_500_000_000);
        // Nor are outliers 1.2 s of MCU time apart for 1 s of GPS time (a clock 20 % fast,
        // far beyond 50 ppm).
        let mut c = five_pulses();
        for (t, s) in [(5_300_000, 5), (6_500_000, 6), (7_700_000, 7)] {
            assert_eq!(c.add_pulse(t, s * NS_PER_S), Outlier);
        }
        assert_eq!(c.relocks, 0);
        // The same wrong pulse reported three times (the document does not say 0x06 is sent
        // once) is not a run of agreeing pulses either.
        let mut c = five_pulses();
        for _ in 0..3 {
            assert_eq!(c.add_pulse(5_300_000, 5 * NS_PER_S), Outlier);
        }
        assert_eq!(c.relocks, 0);
    }

    #[test]
    fn a_single_pulse_gates_the_next_at_six_sigma_of_its_drift_bound() {
        // One pulse; the next 10 s later on a clock 100 ppm fast (1 ms over the nominal rate),
        // beyond the 200 us outlier limit but within 6 sigma of the 50 ppm bound (6 x sqrt(
        // 2 x 2020.7^2 + (28.87 ppm x 10.001 s)^2 + (0.05 ppm x 10.001 s)^2) = 1.73 ms).
        let mut c = PpsClock::new(PpsClockConfig::default());
        c.add_pulse(1_000_000, 0);
        assert_eq!(
            c.add_pulse(11_001_000, 10 * NS_PER_S),
            PulseOutcome::Accepted
        );
    }

    #[test]
    fn device_time_stepping_back_more_than_0_2_s_is_a_reset() {
        // 0.2 s = 200,000 ticks back is tolerated (time messages of two streams interleave);
        // one more is a reset.
        let mut c = five_pulses();
        assert!(!c.observe(4_000_000));
        assert!(!c.observe(3_800_000));
        assert!(c.observe(3_599_999));
        // The newest time seen counts, not the latest: after 4.0 s and 3.9 s, 3.75 s is
        // 0.25 s back.
        let mut c = five_pulses();
        assert!(!c.observe(4_000_000));
        assert!(!c.observe(3_900_000));
        assert!(c.observe(3_750_000));
    }

    #[test]
    fn pps_references_keep_2_s_and_a_pps_up_to_1_5_s_old() {
        const S: i64 = NS_PER_S;
        let g = 1_000 * S;
        let near = |r: &PpsReferences, h: i64| r.nearest(h).map(|x| x.host_ns);
        // A last PPS 1.5 s old is still a reference; older means the PPS stopped.
        let mut r = PpsReferences::new();
        assert!(r.add(10 * S, g, 1_500_000_000));
        assert!(!r.add(10 * S, g, 1_500_000_001));
        // Kept: 2 s of host time behind the newest, the one exactly 2 s back included.
        let mut r = PpsReferences::new();
        for k in 10..=12 {
            assert!(r.add(k * S, g + k * S, 0));
        }
        assert_eq!(near(&r, 10 * S), Some(10 * S));
        r.add(12 * S + 1, g + 12 * S, 0);
        // The 10 s one is gone; the 11 s one is the nearest, 1 s away (the most allowed).
        assert_eq!(near(&r, 10 * S), Some(11 * S));
        assert_eq!(near(&r, 10 * S - 1), None);
        // Host time going back exactly 2 s keeps the references; 1 ns more starts over.
        let mut r = PpsReferences::new();
        r.add(10 * S, g, 0);
        r.add(8 * S, g, 0);
        assert_eq!(near(&r, 10 * S), Some(10 * S));
        let mut r = PpsReferences::new();
        r.add(10 * S, g, 0);
        r.add(8 * S - 1, g, 0);
        assert_eq!(near(&r, 10 * S), None);
    }
}
