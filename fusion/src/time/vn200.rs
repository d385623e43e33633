//! VN-200 samples on GPS time (issue 7, "VN-200"; ICD 2.2 Common group, 2.3 Time group,
//! 2.5.11-13 GnssTimeUncertainty / GnssTimeInfo, Tables 2.15 TimeStatus and 2.77 InsStatus).
//!
//! - Native GPS time: TimeGps (or GpsWeek + GpsTow) when the device says it is valid: TimeStatus
//!   "time of week" and "date" valid when TimeStatus is in the message; else InsStatus "GNSS fix"
//!   set and "GNSS error" clear; with neither in the message, the validity last reported within
//!   [`Vn200AlignerConfig::status_hold_ns`] of host time. Decision: a message with no status at all
//!   is not trusted (no wrong time claimed as locked). Sigma: the receiver's GnssTimeUncertainty
//!   when output (held), else [`Vn200AlignerConfig::default_sigma_ns`].
//! - Otherwise: TimeStartup (the VN-200's own TCXO clock) mapped through the last valid
//!   (TimeStartup, TimeGps) pair and the rate measured between valid pairs, source
//!   [`TimeSource::DeviceClock`], status coasting, sigma growing with the time since that pair.
//!   TimeStartup going backwards (a device restart) drops the model.
//! - A valid GPS time is cross-checked against the host clock's relation held before it
//!   ([`Vn200Aligner::handle_times_checked`], issue 18 point 4); a disagreeing one is not used.
//! - Each valid message feeds the host clock: the host time its first byte left (arrival minus
//!   transmission time at the baud rate) against its GPS time plus the output delay.
//! - GPS - UTC: GnssTimeInfo's leap seconds when the receiver reports UTC valid, else the table with
//!   its validity flag ([`super::gps::gps_minus_utc_s`]).

use std::collections::VecDeque;

use vigil_drivers::vn200::binary::BinaryOutput;
use vigil_drivers::vn200::status::{InsStatus, TimeStatus};

use super::cross_check::{CrossCheckConfig, host_view};
use super::gps::{self, LeapSeconds, NS_PER_S};
use super::host::HostClock;
use super::host_timed::{first_byte_host_ns, tx_ns};
use super::{AlignedTime, ClockStatus, NotAligned, Rx, TimeSource};

/// Parameters of the VN-200 aligner, with units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vn200AlignerConfig {
    /// Serial baud rate, bit/s (the simulator and the installation use 921 600).
    pub baud: u32,
    /// Delay from the sample instant (TimeGps) to the first byte on the wire, ns. Decision: the ICD
    /// gives none; 0 by default, the host model's link-delay estimate absorbs a constant one for
    /// the VN-200 (not for other ports: set it when measured).
    pub output_delay_ns: i64,
    /// 1-sigma of a valid TimeGps when the receiver gives no GnssTimeUncertainty, ns. Decision:
    /// 100 ns (the VN-200 datasheet's PPS timing accuracy is tens of ns; margin for the output
    /// latching).
    pub default_sigma_ns: f64,
    /// 1-sigma rate error of TimeStartup before a rate was measured, ppm (ICD: TCXO, 20 ppm).
    pub startup_rate_sigma_ppm: f64,
    /// 1-sigma rate wander of TimeStartup once its rate was measured, ppm.
    pub startup_wander_ppm: f64,
    /// Shortest span of valid pairs that measures the TimeStartup rate, ns.
    pub rate_span_ns: i64,
    /// Longest extrapolation through TimeStartup, ns; beyond it the clock is unlocked.
    pub coast_limit_ns: i64,
    /// How long a reported TimeStatus / InsStatus validity applies to messages without one, ns.
    pub status_hold_ns: i64,
}

impl Default for Vn200AlignerConfig {
    fn default() -> Self {
        Self {
            baud: 921_600,
            output_delay_ns: 0,
            default_sigma_ns: 100.0,
            startup_rate_sigma_ppm: 20.0,
            startup_wander_ppm: 0.5,
            rate_span_ns: 10 * NS_PER_S,
            coast_limit_ns: 600 * NS_PER_S,
            status_hold_ns: NS_PER_S,
        }
    }
}

/// The inputs bounded. Decision: times beyond 2^61 ns (73 years after the GPS epoch or the
/// start-up) are garbage: dropped, so differences of times below fit in an i64; a host time is
/// clamped to the same range.
fn bounded(t: &Vn200Times, rx: Rx) -> (Vn200Times, Rx) {
    let t = Vn200Times {
        time_gps_ns: t.time_gps_ns.filter(|g| (1..=MAX_TIME_NS).contains(g)),
        time_startup_ns: t.time_startup_ns.filter(|s| *s <= MAX_TIME_NS as u64),
        ..*t
    };
    let rx = Rx {
        host_ns: rx.host_ns.clamp(0, MAX_TIME_NS),
        ..rx
    };
    (t, rx)
}

/// The time fields of one binary output message.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vn200Times {
    /// TimeGps (or GpsWeek + GpsTow), ns since the GPS epoch.
    pub time_gps_ns: Option<i64>,
    /// TimeStartup, ns.
    pub time_startup_ns: Option<u64>,
    /// TimeGpsPps: time since the last GNSS PPS, ns (ICD 2.2 Common group, 2.3 Time group).
    pub time_gps_pps_ns: Option<u64>,
    /// TimeStatus.
    pub time_status: Option<TimeStatus>,
    /// InsStatus.
    pub ins_status: Option<InsStatus>,
    /// GnssTimeUncertainty, s.
    pub time_u_s: Option<f32>,
    /// GnssTimeInfo: (status, GPS - UTC in s).
    pub time_info: Option<(TimeStatus, i8)>,
}

impl Vn200Times {
    /// Collects the time fields of any group.
    pub fn of(o: &BinaryOutput) -> Self {
        let mut t = Self::default();
        if let Some(c) = &o.common {
            t.time_gps_ns = c.time_gps_ns.map(|v| v as i64);
            t.time_startup_ns = c.time_startup_ns;
            t.time_gps_pps_ns = c.time_gps_pps_ns;
            t.ins_status = c.ins_status;
        }
        if let Some(g) = &o.time {
            t.time_gps_ns = t.time_gps_ns.or(g.time_gps_ns.map(|v| v as i64));
            if t.time_gps_ns.is_none()
                && let (Some(w), Some(tow)) = (g.gps_week, g.gps_tow_ns)
            {
                t.time_gps_ns = Some(gps::gps_ns_from_week_tow(w, 0.0) + tow as i64);
            }
            t.time_startup_ns = t.time_startup_ns.or(g.time_startup_ns);
            t.time_gps_pps_ns = t.time_gps_pps_ns.or(g.time_gps_pps_ns);
            t.time_status = g.time_status;
        }
        if let Some(i) = &o.ins {
            t.ins_status = t.ins_status.or(i.ins_status);
        }
        for g in [&o.gnss, &o.gnss2].into_iter().flatten() {
            t.time_u_s = t.time_u_s.or(g.time_u_s);
            t.time_info = t
                .time_info
                .or(g.time_info.map(|i| (i.status, i.leap_seconds)));
        }
        t
    }
}

/// Largest time accepted (GPS, start-up, host), ns: 2^61, 73 years.
const MAX_TIME_NS: i64 = 1 << 61;

/// Counters of the VN-200 aligner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct Vn200AlignerStats {
    /// Messages with a valid native GPS time.
    pub native: u64,
    /// Messages timed through TimeStartup.
    pub startup_clock: u64,
    /// Messages without a time.
    pub not_aligned: u64,
    /// Device restarts detected (TimeStartup going backwards).
    pub restarts: u64,
    /// Messages whose valid GPS time disagreed with the host clock (issue 18 point 4): not used
    /// as GPS time, nor as a host-clock reference.
    pub disagreeing: u64,
}

/// Aligns VN-200 binary output messages.
#[derive(Debug, Clone)]
pub struct Vn200Aligner {
    cfg: Vn200AlignerConfig,
    /// Valid (TimeStartup, TimeGps) pairs, one per second at most, over the rate span.
    pairs: VecDeque<(u64, i64)>,
    /// Last valid pair.
    anchor: Option<(u64, i64)>,
    /// TimeStartup rate error against GPS (fraction) and whether it was measured.
    rate: Option<f64>,
    last_startup: Option<u64>,
    /// Last reported validity and its host time.
    validity: Option<(bool, i64)>,
    time_sigma_ns: Option<f64>,
    leap: Option<i8>,
    last_valid_host_ns: Option<i64>,
    /// Host time of the read that delivered the previous message's last byte, ns.
    last_read_host_ns: Option<i64>,
    stats: Vn200AlignerStats,
    /// The latest cross-checked GPS time disagreed with the host clock (issue 18 point 4).
    disagreement: bool,
}

impl Vn200Aligner {
    /// The port runs at `baud` bit/s (configured or recorded): transmission times use it.
    pub fn set_baud(&mut self, baud: u32) {
        self.cfg.baud = baud.max(1);
    }

    /// An aligner with no model.
    pub fn new(cfg: Vn200AlignerConfig) -> Self {
        Self {
            cfg,
            pairs: VecDeque::new(),
            anchor: None,
            rate: None,
            last_startup: None,
            validity: None,
            time_sigma_ns: None,
            leap: None,
            last_valid_host_ns: None,
            last_read_host_ns: None,
            stats: Vn200AlignerStats::default(),
            disagreement: false,
        }
    }

    /// Counters.
    pub fn stats(&self) -> &Vn200AlignerStats {
        &self.stats
    }

    /// GPS - UTC at GPS time `t_gps_ns`: the receiver's GnssTimeInfo value once reported (valid),
    /// else the table's.
    pub fn gps_minus_utc(&self, t_gps_ns: i64) -> LeapSeconds {
        match self.leap {
            Some(l) => LeapSeconds {
                gps_minus_utc_s: i32::from(l),
                table_valid: true,
            },
            None => {
                // The table is indexed by UTC; 18 s of difference cannot cross a boundary that
                // matters here except within 18 s of it, where the GPS time is used as is.
                let unix_s = (t_gps_ns.div_euclid(NS_PER_S)) + gps::GPS_EPOCH_UNIX_S;
                let first = gps::gps_minus_utc_s(unix_s);
                gps::gps_minus_utc_s(unix_s - i64::from(first.gps_minus_utc_s))
            }
        }
    }

    /// TimeStartup rate error against GPS, ppm (positive: TimeStartup runs fast), once measured.
    pub fn startup_drift_ppm(&self) -> Option<f64> {
        self.rate.map(|r| r * 1e6)
    }

    /// State of the clock at host time `now_ns`: locked while valid GPS time arrives, coasting on
    /// TimeStartup after it stopped, unlocked without a TimeStartup model. Decision: a VN-200
    /// whose output carries no TimeStartup (the default Register 75 output) is locked while valid
    /// TimeGps arrives, although it has no start-up clock model to coast on.
    pub fn status(&self, now_ns: i64) -> ClockStatus {
        match (self.last_valid_host_ns, self.anchor) {
            (Some(h), _) if now_ns - h <= 2 * self.cfg.status_hold_ns => ClockStatus::Locked,
            (Some(h), Some(_)) if now_ns - h <= self.cfg.coast_limit_ns => ClockStatus::Coasting,
            _ => ClockStatus::Unlocked,
        }
    }

    /// GPS time of one message received as `rx`; feeds `host` with it when valid.
    pub fn handle(
        &mut self,
        o: &BinaryOutput,
        rx: Rx,
        host: &mut HostClock,
    ) -> Result<AlignedTime, NotAligned> {
        let t = Vn200Times::of(o);
        self.handle_times(&t, rx, host)
    }

    /// As [`Vn200Aligner::handle`], from the extracted time fields.
    pub fn handle_times(
        &mut self,
        t: &Vn200Times,
        rx: Rx,
        host: &mut HostClock,
    ) -> Result<AlignedTime, NotAligned> {
        self.handle_inner(t, rx, host, None)
    }

    /// True while the latest cross-checked GPS time disagreed with the host clock
    /// ([`Self::handle_times_checked`]; `clock_disagreement` in the integrity topic).
    pub fn clock_disagreement(&self) -> bool {
        self.disagreement
    }

    /// As [`Self::handle_times`], with a valid GPS time first cross-checked against the host
    /// clock ([`super::cross_check`], issue 18 point 4): the view of `host` (the relation the
    /// VN-200's own earlier times built) or `other` (the TT-Multi-RF's), whichever is better.
    /// Decision: the VN-200 is normally the host clock's reference, so the check is against the
    /// relation held BEFORE this message (a host monotonic clock does not jump), never one that
    /// includes it. A disagreeing time is not used, feeds neither the host clock nor the
    /// TimeStartup model, and the message is timed by TimeStartup where that model exists
    /// (the VN-200's own crystal, independent of how it names GPS time), else
    /// [`NotAligned::ClockDisagreement`] (the caller may place it by the host clock).
    pub fn handle_times_checked(
        &mut self,
        t: &Vn200Times,
        rx: Rx,
        host: &mut HostClock,
        other: &HostClock,
        check: &CrossCheckConfig,
    ) -> Result<AlignedTime, NotAligned> {
        self.handle_inner(t, rx, host, Some((other, check)))
    }

    /// The steps: the inputs bounded; the status fields noted (time sigma, leap seconds, a
    /// device restart); whether the GPS time is valid; then the message timed by its own GPS
    /// time (after the cross-check, when asked), or else by the TimeStartup model.
    fn handle_inner(
        &mut self,
        t: &Vn200Times,
        rx: Rx,
        host: &mut HostClock,
        check: Option<(&HostClock, &CrossCheckConfig)>,
    ) -> Result<AlignedTime, NotAligned> {
        let (t, rx) = bounded(t, rx);
        let previous_read_ns = self.last_read_host_ns.replace(rx.host_ns);
        self.note_status(&t);
        let valid = self.gps_time_valid(&t, rx);
        // `bounded` keeps TimeGps within 1 ..= 2^61 ns.
        match (valid, t.time_gps_ns) {
            (true, Some(gps_ns)) => {
                if let Some((other, cc)) = check
                    && self.disagrees(gps_ns, rx, host, other, cc)
                {
                    return self
                        .by_startup_clock(t.time_startup_ns, Some(NotAligned::ClockDisagreement));
                }
                Ok(self.by_gps_time(&t, gps_ns, rx, previous_read_ns, host))
            }
            _ => self.by_startup_clock(t.time_startup_ns, None),
        }
    }

    /// Notes the status fields of a message: the time uncertainty, the leap seconds (when the
    /// UTC time is valid), and a device restart (TimeStartup going backwards), which drops the
    /// TimeStartup model since the start-up clock no longer relates to the old pairs.
    fn note_status(&mut self, t: &Vn200Times) {
        if let Some(u) = t.time_u_s.filter(|u| u.is_finite() && *u > 0.0) {
            self.time_sigma_ns = Some(f64::from(u) * 1e9);
        }
        if let Some((st, leap)) = t.time_info
            && st.utc_valid()
        {
            self.leap = Some(leap);
        }
        if let Some(s) = t.time_startup_ns {
            if self.last_startup.is_some_and(|l| s < l) {
                // The device restarted: its start-up clock no longer relates to the old pairs.
                self.stats.restarts += 1;
                self.pairs.clear();
                self.anchor = None;
                self.rate = None;
            }
            self.last_startup = Some(s);
        }
    }

    /// Whether the message's GPS time is valid: from its own TimeStatus (time of week and date
    /// valid) and INS status (GNSS fix without error) when it carries them; else the last
    /// reported validity while no older than `status_hold_ns` (a message without status fields
    /// is not trusted on its own).
    fn gps_time_valid(&mut self, t: &Vn200Times, rx: Rx) -> bool {
        let reported = match (t.time_status, t.ins_status) {
            (Some(ts), Some(ins)) => {
                Some(ts.tow_valid() && ts.date_valid() && ins.gnss_fix() && !ins.gnss_error())
            }
            (Some(ts), None) => Some(ts.tow_valid() && ts.date_valid()),
            (None, Some(ins)) => Some(ins.gnss_fix() && !ins.gnss_error()),
            (None, None) => None,
        };
        if let Some(v) = reported {
            self.validity = Some((v, rx.host_ns));
        }
        reported.unwrap_or_else(|| {
            self.validity
                .is_some_and(|(v, h)| v && rx.host_ns - h <= self.cfg.status_hold_ns)
        })
    }

    /// The cross-check of the GPS time `gps_ns` against the host clock's view (`host` and
    /// `other`), at the first byte's host time; false when no view exists (the check cannot
    /// run). Remembered for the caller and counted.
    fn disagrees(
        &mut self,
        gps_ns: i64,
        rx: Rx,
        host: &HostClock,
        other: &HostClock,
        cc: &CrossCheckConfig,
    ) -> bool {
        let Some(view) = host_view(host, other, first_byte_host_ns(rx, self.cfg.baud)) else {
            return false;
        };
        let sent = gps_ns.saturating_add(self.cfg.output_delay_ns);
        let sigma = self.time_sigma_ns.unwrap_or(self.cfg.default_sigma_ns);
        self.disagreement = cc.disagrees((sent, sigma), view);
        if self.disagreement {
            self.stats.disagreeing += 1;
        }
        self.disagreement
    }

    /// The message timed by its own valid GPS time `gps_ns`: the pair feeds the TimeStartup
    /// model and the host clock (the first byte's send time, and the single-read delay).
    fn by_gps_time(
        &mut self,
        t: &Vn200Times,
        gps_ns: i64,
        rx: Rx,
        previous_read_ns: Option<i64>,
        host: &mut HostClock,
    ) -> AlignedTime {
        self.stats.native += 1;
        if let Some(s) = t.time_startup_ns {
            self.learn(s, gps_ns);
        }
        self.last_valid_host_ns = Some(rx.host_ns);
        host.add(
            first_byte_host_ns(rx, self.cfg.baud),
            gps_ns + self.cfg.output_delay_ns,
        );
        // The read holding the first byte, after an idle line, is one read's latency
        // (issue 18 point 1): the reference of every other port's single reads.
        // Decision: a first read delivered no later than the previous message's last
        // read may have been held back by it (reads come in order): left out, as it
        // would bias the single-read delay late (a 200 Hz VN-200 leaves the line idle
        // only ~4 ms between messages).
        if let Some(r) = rx
            .reads
            .filter(|r| previous_read_ns.is_none_or(|p| r.first_host_ns > p))
        {
            let sent = gps_ns + self.cfg.output_delay_ns + tx_ns(r.first_bytes, self.cfg.baud);
            host.add_read(r.first_host_ns, sent);
        }
        AlignedTime {
            t_gps_ns: gps_ns,
            sigma_ns: self.time_sigma_ns.unwrap_or(self.cfg.default_sigma_ns),
            source: TimeSource::NativeGps,
            status: ClockStatus::Locked,
        }
    }

    /// The message timed by the TimeStartup model, when its GPS time cannot be used. When the
    /// model cannot time it either: `why` when given (the reason the GPS time was refused),
    /// else the model's own reason, or [`NotAligned::DeviceTimeInvalid`] without a TimeStartup.
    fn by_startup_clock(
        &mut self,
        startup_ns: Option<u64>,
        why: Option<NotAligned>,
    ) -> Result<AlignedTime, NotAligned> {
        let timed = match startup_ns {
            Some(s) => self.through_startup(s),
            None => Err(NotAligned::DeviceTimeInvalid),
        };
        match timed {
            Ok(a) => {
                self.stats.startup_clock += 1;
                Ok(a)
            }
            Err(e) => {
                self.stats.not_aligned += 1;
                Err(why.unwrap_or(e))
            }
        }
    }

    /// Records a valid pair and measures the TimeStartup rate over the kept span.
    fn learn(&mut self, startup: u64, gps_ns: i64) {
        self.anchor = Some((startup, gps_ns));
        if self.pairs.back().is_none_or(|b| gps_ns - b.1 >= NS_PER_S) {
            self.pairs.push_back((startup, gps_ns));
        }
        while self
            .pairs
            .front()
            .is_some_and(|f| gps_ns - f.1 > 6 * self.cfg.rate_span_ns)
        {
            self.pairs.pop_front();
        }
        if let Some(&(s0, g0)) = self.pairs.front() {
            let dg = gps_ns - g0;
            if dg >= self.cfg.rate_span_ns {
                let ds = startup.wrapping_sub(s0) as i64;
                self.rate = Some((ds - dg) as f64 / dg as f64);
            }
        }
    }

    /// GPS time of a TimeStartup stamp through the last valid pair.
    fn through_startup(&self, startup: u64) -> Result<AlignedTime, NotAligned> {
        let (s0, g0) = self.anchor.ok_or(NotAligned::DeviceTimeInvalid)?;
        let ds = startup as i64 - s0 as i64;
        if ds.abs() > self.cfg.coast_limit_ns {
            return Err(NotAligned::ClockUnlocked);
        }
        let rate = self.rate.unwrap_or(0.0);
        let rate_sigma = if self.rate.is_some() {
            self.cfg.startup_wander_ppm
        } else {
            self.cfg.startup_rate_sigma_ppm
        } * 1e-6;
        let dg = ds as f64 / (1.0 + rate);
        let base = self.time_sigma_ns.unwrap_or(self.cfg.default_sigma_ns);
        // TimeStartup resolution and the pair's own error, plus the rate error over the gap.
        let sigma = (base.powi(2) + (dg * rate_sigma).powi(2)).sqrt();
        Ok(AlignedTime {
            t_gps_ns: g0 + dg.round() as i64,
            sigma_ns: sigma,
            source: TimeSource::DeviceClock,
            status: ClockStatus::Coasting,
        })
    }
}

#[cfg(test)]
#[path = "vn200_tests.rs"]
mod tests;
