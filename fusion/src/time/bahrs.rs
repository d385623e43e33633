//! BAHRS samples on GPS time.
//!
//! - 0x06 (time of the latest synchronisation pulse) gives the MCU time of a PPS edge. The GPS
//!   time of that edge is taken from the VN-200's own PPS time (TimeGps - TimeGpsPps) of the
//!   VN-200 message nearest in host time to the 0x06 ([`PpsReferences`]: the sync input is wired
//!   to the VN-200 PPS). Without such a message (no VN-200, its time invalid, its PPS lost or
//!   stale) it falls back to the host clock model (learned from the VN-200): the host receive
//!   time of the 0x06, minus its transmission time, mapped to GPS, rounded to the nearest second
//!   (it arrives milliseconds after the edge, far inside +-0.5 s). The counters say which was
//!   used for how many pulses, and [`BahrsAligner::last_pulse_source`] for the latest.
//! - Those pairs feed a [`PpsClock`] (MCU microseconds -> GPS ns with drift).
//! - 0x06 itself is placed through the clock (its sample instant is the pulse); so are 0x04/0x05
//!   (their data's instant), an invalid one (zero sequence and time) comes out "device time
//!   invalid": every message handed in comes out once.
//! - 0x01/0x02 are paired with their 0x05/0x04 by sequence counter ([`SeqMatcher`]) and mapped
//!   through the clock. 0x03 carries its own MCU time.
//! - A sample whose time message never comes is emitted "not aligned: no time message"; a sample
//!   waiting for the clock is held for at most `clock_wait_s`, then emitted "not aligned: clock
//!   unlocked"; a device reset (MCU time going backwards) starts a new clock epoch, and samples of
//!   the old epoch still waiting are emitted "not aligned: outside clock epoch" rather than mapped
//!   through the new model.

use std::collections::VecDeque;

use vigil_drivers::bahrs::{Message, frame::layout};

use super::host::HostClock;
use super::mcu_host::{McuHostClock, McuHostConfig};
use super::pps::{PpsClock, PpsClockConfig, PpsReferences, PulseSecondSource, pulse_second};
use super::seq::SeqMatcher;
use super::{Aligned, AlignedTime, ClockStatus, NotAligned, TimeSource};

/// Parameters of the BAHRS aligner.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BahrsAlignerConfig {
    /// Serial baud rate of the BAHRS port (the protocol document does not state one; set it per
    /// installation), bit/s. Used for the transmission time of 0x06.
    pub baud: u32,
    /// How long a data message waits for its time message, s.
    pub pair_hold_s: f64,
    /// How long a timed sample waits for the clock model, s.
    pub clock_wait_s: f64,
    /// The MCU clock model.
    pub clock: PpsClockConfig,
    // --- issue 18 / issue 25 point 3: the MCU clock against host time ---
    /// The MCU-to-host envelope (pulse naming, cross-check, fallback without pulses).
    pub mcu_host: McuHostConfig,
    /// A pulse whose named GPS time differs from the host clock's view of its MCU time by more
    /// than this many combined sigmas is refused and raises the clock disagreement.
    pub cross_check_sigmas: f64,
}

impl Default for BahrsAlignerConfig {
    fn default() -> Self {
        Self {
            baud: 115_200,
            pair_hold_s: 0.5,
            clock_wait_s: 2.0,
            clock: PpsClockConfig::default(),
            mcu_host: McuHostConfig::default(),
            cross_check_sigmas: 5.0,
        }
    }
}

/// Counters of the BAHRS aligner.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize)]
pub struct BahrsAlignerStats {
    /// Pulses accepted into the clock model.
    pub pulses_used: u64,
    /// Pulses whose GPS second could not be identified (no VN-200 PPS time near them and the
    /// host clock not established).
    pub pulses_unidentified: u64,
    /// Pulses whose GPS time came from the VN-200's PPS time (TimeGps - TimeGpsPps).
    pub pulses_from_vn200_pps: u64,
    /// Pulses whose GPS second came from the host clock (no VN-200 PPS time near them).
    pub pulses_from_host_clock: u64,
    /// Pulses rejected as outliers.
    pub pulses_rejected: u64,
    /// Time messages flagged invalid by the device (zero sequence and zero time).
    pub invalid_time_messages: u64,
    /// Samples emitted without a time.
    pub not_aligned: u64,
    // --- issue 18 / issue 25 point 3 ---
    /// Pulse reports repeating the last pulse (same MCU time): one pulse, not counted again.
    pub pulse_reports_repeated: u64,
    /// Pulse reports older than the last pulse used (a late report, not a reset): ignored.
    pub pulse_reports_stale: u64,
    /// Pulses refused because their named GPS time disagreed with the host clock's view of
    /// their MCU time (wrong edge, wrong second).
    pub pulses_disagreeing: u64,
    /// Pulses not used because no host-clock view of their MCU time existed to cross-check them.
    pub pulses_unverified: u64,
    /// Samples placed through the MCU-to-host envelope and the host clock (no usable pulses).
    pub host_fallback: u64,
}

/// Most samples held while the clock model is unavailable (2 s of 0x01 + 0x02 + 0x03 at default
/// rates is 302); the oldest is released unaligned beyond that.
const WAIT_CAPACITY: usize = 512;

/// 1-sigma of the wait of a service message (versions) in the device's transmit queue, ns.
/// Decision: the document gives no send time for them; the versions follow a reset together with
/// the first data, so each can wait behind a few frames (the simulator measured up to 2.2 ms at
/// 115 200 baud): 2 ms, added to the host clock's sigma, so their time is not overstated.
const SERVICE_QUEUE_SIGMA_NS: f64 = 2_000_000.0;

struct Waiting<T> {
    msg: T,
    ticks: u64,
    epoch: u64,
    host_ns: i64,
}

/// A BAHRS sample as the aligner carries it: the decoded message, or the message with a caller's
/// tag (e.g. its per-device index, kept through the reordering that sequence pairing causes).
pub trait BahrsSample {
    /// The BAHRS message.
    fn bahrs(&self) -> &Message;
}

impl BahrsSample for Message {
    fn bahrs(&self) -> &Message {
        self
    }
}

impl<U> BahrsSample for (U, Message) {
    fn bahrs(&self) -> &Message {
        &self.1
    }
}

/// Aligns a BAHRS message stream (`T`: the message, or the message with a tag).
pub struct BahrsAligner<T = Message> {
    cfg: BahrsAlignerConfig,
    clock: PpsClock,
    inertial: SeqMatcher<T>,
    navigation: SeqMatcher<T>,
    waiting: VecDeque<Waiting<T>>,
    stats: BahrsAlignerStats,
    last_pulse_source: Option<PulseSecondSource>,
    /// Mean (ns) and variance (ns^2) of the wait between a message's last byte and the read that
    /// stamps it (read pacing, USB latency timer); see [`Self::set_link_wait`].
    wait_mean_ns: f64,
    wait_var_ns2: f64,
    /// The MCU clock against host time (issue 18 point 3).
    mcu_host: McuHostClock,
    /// Host time of the last pulse report with a new MCU time, ns.
    last_pulse_host_ns: Option<i64>,
    /// The latest pulse disagreed with the host clock (cleared by the next agreeing pulse).
    disagreement: bool,
    /// Latest host time seen, ns.
    now_ns: i64,
}

impl<T: BahrsSample> BahrsAligner<T> {
    /// An aligner with no clock model yet.
    pub fn new(cfg: BahrsAlignerConfig) -> Self {
        let hold = (cfg.pair_hold_s * 1e9) as i64;
        Self {
            cfg,
            clock: PpsClock::new(cfg.clock),
            inertial: SeqMatcher::new(hold, 256),
            navigation: SeqMatcher::new(hold, 256),
            waiting: VecDeque::with_capacity(WAIT_CAPACITY),
            stats: BahrsAlignerStats::default(),
            last_pulse_source: None,
            wait_mean_ns: 0.0,
            wait_var_ns2: 0.0,
            mcu_host: McuHostClock::new(cfg.mcu_host),
            last_pulse_host_ns: None,
            disagreement: false,
            now_ns: i64::MIN,
        }
    }

    /// True while the latest synchronisation pulse disagreed with the host clock's view of its
    /// MCU time (`clock_disagreement` in the integrity topic): the PPS model is dropped and the
    /// samples fall back to the host clock until pulses agree again.
    pub fn clock_disagreement(&self) -> bool {
        self.disagreement
    }

    /// The MCU-to-host envelope.
    pub fn mcu_host(&self) -> &McuHostClock {
        &self.mcu_host
    }

    /// The port is read every `interval_ns` (0: as its bytes arrive). Only the host-timed
    /// messages (versions, service) and the host-clock fallback feel it: their receive time is
    /// late by a wait uniform over the interval, so half of it is taken off their time and
    /// `interval / sqrt(12)` added (root-sum-square) to their sigma. The PPS-timed samples come
    /// from the MCU clock, and the pulses' seconds are named to +-0.5 s, far beyond any allowed
    /// interval.
    pub fn set_read_interval(&mut self, interval_ns: u64) {
        let i = interval_ns as f64;
        self.set_link_wait(i / 2.0, i * i / 12.0);
    }

    /// The wait of a message's last byte for the read that stamps it: mean `mean_ns`, variance
    /// `var_ns2` (a read interval and a USB latency timer together); see
    /// [`Self::set_read_interval`].
    pub fn set_link_wait(&mut self, mean_ns: f64, var_ns2: f64) {
        self.wait_mean_ns = mean_ns.max(0.0);
        self.wait_var_ns2 = var_ns2.max(0.0);
    }

    /// The port runs at `baud` bit/s (transmission times of its frames).
    pub fn set_baud(&mut self, baud: u32) {
        self.cfg.baud = baud.max(1);
    }

    /// Where the GPS time of the latest identified pulse came from.
    pub fn last_pulse_source(&self) -> Option<PulseSecondSource> {
        self.last_pulse_source
    }

    /// Counters.
    pub fn stats(&self) -> &BahrsAlignerStats {
        &self.stats
    }

    /// The MCU clock model.
    pub fn clock(&self) -> &PpsClock {
        &self.clock
    }

    /// Transmission time of a frame of `msg_type` at the configured baud rate (10 bits per byte),
    /// ns.
    fn tx_ns(&self, msg_type: u8) -> i64 {
        let len = layout(msg_type).map_or(0, |l| l.frame_len()) as i64;
        len * 10 * 1_000_000_000 / i64::from(self.cfg.baud.max(1))
    }

    /// Takes one decoded message, received (last byte) at host time `host_ns`; returns every
    /// sample that became final. `host` is the host clock model, `vn_pps` the VN-200's recent PPS
    /// times (empty without a VN-200).
    pub fn handle(
        &mut self,
        msg: T,
        host_ns: i64,
        host: &HostClock,
        vn_pps: &PpsReferences,
    ) -> Vec<Aligned<T>> {
        let mut out = Vec::new();
        self.now_ns = self.now_ns.max(host_ns);
        match *msg.bahrs() {
            Message::Inertial(m) => {
                let paired = self.inertial.push_data(m.seq, host_ns, msg);
                self.place_paired(paired, host, &mut out);
            }
            Message::Navigation(m) => {
                let paired = self.navigation.push_data(m.seq, host_ns, msg);
                self.place_paired(paired, host, &mut out);
            }
            Message::InertialTime(t) | Message::NavigationTime(t) => {
                if !t.is_valid() {
                    self.stats.invalid_time_messages += 1;
                    self.stats.not_aligned += 1;
                    out.push(Aligned {
                        message: msg,
                        time: Err(NotAligned::DeviceTimeInvalid),
                    });
                } else {
                    self.observe(t.mcu_time_us, &mut out);
                    let matcher = if matches!(msg.bahrs(), Message::InertialTime(_)) {
                        &mut self.inertial
                    } else {
                        &mut self.navigation
                    };
                    if let Some(p) = matcher.push_time(t.data_seq, host_ns, t.mcu_time_us) {
                        self.place_paired([p], host, &mut out);
                    }
                    // The time message is a sample of the stream too: its instant is its data's.
                    self.place(msg, t.mcu_time_us, host_ns, host, &mut out);
                }
            }
            Message::Accuracy(a) => {
                self.observe(a.mcu_time_us, &mut out);
                let first_byte = host_ns.saturating_sub(self.tx_ns(0x03));
                self.mcu_host.add(a.mcu_time_us, first_byte);
                self.place(msg, a.mcu_time_us, host_ns, host, &mut out);
            }
            Message::SyncPulseTime(p) => {
                self.on_pulse(p.mcu_time_us, host_ns, host, vn_pps, &mut out);
                // The 0x06 sample instant is the pulse itself: its MCU time through the clock.
                self.place(msg, p.mcu_time_us, host_ns, host, &mut out);
            }
            // Versions and service messages carry no device time: host clock.
            _ => out.push(self.host_timed(msg, host_ns, host)),
        }
        out
    }

    /// Releases what waited too long at host time `now_ns` (call periodically and at the end):
    /// through the host-clock fallback where it can, else not aligned.
    pub fn expire(&mut self, now_ns: i64, host: &HostClock) -> Vec<Aligned<T>> {
        let mut out = Vec::new();
        self.now_ns = self.now_ns.max(now_ns);
        // Nearly always both are empty: no iterator chain and no collect then (they were a
        // twentieth of the aligner's instructions).
        let inertial = self.inertial.expire(now_ns);
        let navigation = self.navigation.expire(now_ns);
        if !inertial.is_empty() {
            self.place_paired(inertial, host, &mut out);
        }
        if !navigation.is_empty() {
            self.place_paired(navigation, host, &mut out);
        }
        let wait_ns = (self.cfg.clock_wait_s * 1e9) as i64;
        while self
            .waiting
            .front()
            .is_some_and(|w| now_ns - w.host_ns > wait_ns)
        {
            if let Some(w) = self.waiting.pop_front() {
                self.release(w, host, &mut out);
            }
        }
        out
    }

    /// Releases everything still held (end of stream).
    pub fn flush(&mut self, host: &HostClock) -> Vec<Aligned<T>> {
        let mut out = Vec::new();
        let rest: Vec<_> = self
            .inertial
            .flush()
            .into_iter()
            .chain(self.navigation.flush())
            .collect();
        self.place_paired(rest, host, &mut out);
        for w in std::mem::take(&mut self.waiting) {
            self.release(w, host, &mut out);
        }
        out
    }

    /// A waiting sample whose wait is over: the host-clock fallback, or not aligned.
    fn release(&mut self, w: Waiting<T>, host: &HostClock, out: &mut Vec<Aligned<T>>) {
        let time = if w.epoch == self.clock.epoch() {
            self.fallback(w.ticks, host)
                .ok_or(NotAligned::ClockUnlocked)
        } else {
            Err(NotAligned::OutsideClockEpoch)
        };
        self.push_out(w.msg, time, out);
    }

    /// Emits a sample, counting what is not aligned or placed by the fallback.
    fn push_out(
        &mut self,
        msg: T,
        time: Result<AlignedTime, NotAligned>,
        out: &mut Vec<Aligned<T>>,
    ) {
        match &time {
            Err(_) => self.stats.not_aligned += 1,
            Ok(a) if a.source == TimeSource::DeviceClockViaHost => self.stats.host_fallback += 1,
            Ok(_) => {}
        }
        out.push(Aligned { message: msg, time });
    }

    fn observe(&mut self, ticks: u64, out: &mut Vec<Aligned<T>>) {
        if self.clock.observe(ticks) {
            // A new MCU clock epoch: its relation to host time starts over too.
            self.mcu_host.reset();
            self.last_pulse_host_ns = None;
            self.disagreement = false;
            // A new clock epoch: what waits from the old one cannot be mapped any more.
            for w in std::mem::take(&mut self.waiting) {
                self.stats.not_aligned += 1;
                out.push(Aligned {
                    message: w.msg,
                    time: Err(NotAligned::OutsideClockEpoch),
                });
            }
        }
    }

    fn place_paired(
        &mut self,
        paired: impl IntoIterator<Item = super::seq::Paired<T>>,
        host: &HostClock,
        out: &mut Vec<Aligned<T>>,
    ) {
        for p in paired {
            match p.device_ticks {
                Some(ticks) => {
                    // A point of the MCU-to-host envelope: the data message's first byte.
                    let first_byte = p
                        .host_ns
                        .saturating_sub(self.tx_ns(p.data.bahrs().type_id()));
                    self.mcu_host.add(ticks, first_byte);
                    self.place(p.data, ticks, p.host_ns, host, out);
                }
                None => {
                    self.stats.not_aligned += 1;
                    out.push(Aligned {
                        message: p.data,
                        time: Err(NotAligned::NoTimeMessage),
                    });
                }
            }
        }
    }

    /// Maps a timed sample through the PPS clock; without a usable PPS model, through the
    /// host-clock fallback, or holds it until one of them can.
    fn place(
        &mut self,
        msg: T,
        ticks: u64,
        host_ns: i64,
        host: &HostClock,
        out: &mut Vec<Aligned<T>>,
    ) {
        let epoch = self.clock.epoch();
        let err = match self.clock.to_gps(ticks) {
            Ok((t, sigma)) => {
                let time = AlignedTime {
                    t_gps_ns: t,
                    sigma_ns: sigma,
                    source: TimeSource::PpsDisciplined,
                    status: self.clock.status(ticks),
                };
                return self.push_out(msg, Ok(time), out);
            }
            Err(e) => e,
        };
        // Decision (issue 25 point 3): a sample waits for a pulse only while pulses are flowing
        // (a report within the clock wait: the model was just reset or is about to form); with
        // no pulse for longer (never wired, lost, GNSS outage) it takes the fallback at once, so
        // the BAHRS stays comparable with a stated, wider sigma.
        let wait_ns = (self.cfg.clock_wait_s * 1e9) as i64;
        let pulses_flowing = self
            .last_pulse_host_ns
            .is_some_and(|h| self.now_ns.saturating_sub(h) <= wait_ns);
        if !pulses_flowing || self.disagreement || err == super::pps::MapError::BeforeModel {
            if let Some(time) = self.fallback(ticks, host) {
                return self.push_out(msg, Ok(time), out);
            }
            if err == super::pps::MapError::BeforeModel {
                return self.push_out(msg, Err(NotAligned::OutsideClockEpoch), out);
            }
        }
        if self.waiting.len() >= WAIT_CAPACITY
            && let Some(w) = self.waiting.pop_front()
        {
            self.release(w, host, out);
        }
        self.waiting.push_back(Waiting {
            msg,
            ticks,
            epoch,
            host_ns,
        });
    }

    /// GPS time of MCU time `ticks` through the MCU-to-host envelope and the host clock (no
    /// pulses needed), or `None` without both models. The envelope gives the host time the
    /// sample's first byte left at the smallest delay; the host clock maps a receive at the
    /// VN-200's mean delay, so its mean excess is added back (both envelopes sit at their
    /// link's smallest delay) and the BAHRS output delay taken off. Sigma: the host clock's,
    /// the envelope's scatter, the output delay's, and the port's read pacing (the smallest
    /// wait for a read over a bucket lies anywhere in 0 ..= the interval: half of it is taken
    /// off, interval / sqrt(12) added).
    pub fn fallback(&self, ticks: u64, host: &HostClock) -> Option<AlignedTime> {
        let (h, env_sigma) = self.mcu_host.host_ns(ticks, self.now_ns)?;
        let (g, host_sigma) = host.to_gps(h)?;
        let mc = self.mcu_host.config();
        let t = g as f64 + host.excess_delay_ns() - mc.output_delay_ns as f64 - self.wait_mean_ns;
        let sigma = (host_sigma.powi(2)
            + env_sigma.powi(2)
            + mc.output_delay_sigma_ns.powi(2)
            + self.wait_var_ns2)
            .sqrt();
        Some(AlignedTime {
            t_gps_ns: t.round() as i64,
            sigma_ns: sigma,
            source: TimeSource::DeviceClockViaHost,
            status: host.status(h),
        })
    }

    /// A synchronisation pulse report (0x06) at MCU time `ticks`, received at `host_ns`.
    ///
    /// Decisions (issue 18 point 3; the protocol document does not say when 0x06 is sent):
    /// - the pulse is named from its own MCU time (host time through the MCU-to-host envelope,
    ///   then the VN-200's PPS times or the host clock), not from the report's arrival, so a
    ///   report sent late (0.3 s, 0.7 s) names the same second;
    /// - a report repeating the last pulse's MCU time is that pulse again; one older than the
    ///   last pulse is a late report, not a reset (resets show in the data messages' times);
    /// - every pulse is cross-checked against the host clock's view of its MCU time: beyond
    ///   `cross_check_sigmas` combined sigmas (a wrong edge, a wrong second) the pulse is refused,
    ///   the PPS model dropped and the clock disagreement raised; a pulse that cannot be checked
    ///   (no envelope or host clock yet) is not used.
    fn on_pulse(
        &mut self,
        ticks: u64,
        host_ns: i64,
        host: &HostClock,
        vn_pps: &PpsReferences,
        out: &mut Vec<Aligned<T>>,
    ) {
        match self.clock.last_pulse_tick() {
            Some(last) if ticks == last => {
                self.stats.pulse_reports_repeated += 1;
                return;
            }
            Some(last) if ticks < last => {
                self.stats.pulse_reports_stale += 1;
                return;
            }
            _ => {}
        }
        self.last_pulse_host_ns = Some(host_ns);
        // The pulse's host time from its MCU time; before the envelope exists, the report's
        // first byte (naming only: the pulse is not used unchecked, below).
        let pulse_host = match self.mcu_host.host_ns(ticks, self.now_ns) {
            Some((h, _)) => h.saturating_sub(self.cfg.mcu_host.output_delay_ns),
            None => host_ns.saturating_sub(self.tx_ns(0x06)),
        };
        let named = match vn_pps.pulse_gps(pulse_host) {
            Some(t) => Some((t, PulseSecondSource::Vn200Pps)),
            None => host
                .to_gps(pulse_host)
                .map(|(g, _)| (pulse_second(g), PulseSecondSource::HostClock)),
        };
        let Some((second, source)) = named else {
            self.stats.pulses_unidentified += 1;
            return;
        };
        let Some(view) = self.fallback(ticks, host) else {
            self.stats.pulses_unverified += 1;
            return;
        };
        let pulse_sigma = self.clock.residual_sigma_ns().unwrap_or(0.0);
        if pulse_disagrees(
            second.saturating_sub(view.t_gps_ns),
            self.cfg.cross_check_sigmas,
            view.sigma_ns,
            pulse_sigma,
        ) {
            self.stats.pulses_disagreeing += 1;
            self.disagreement = true;
            self.clock.clear();
            return;
        }
        self.disagreement = false;
        match source {
            PulseSecondSource::Vn200Pps => self.stats.pulses_from_vn200_pps += 1,
            PulseSecondSource::HostClock => self.stats.pulses_from_host_clock += 1,
        }
        self.last_pulse_source = Some(source);
        match self.clock.add_pulse(ticks, second) {
            super::pps::PulseOutcome::Outlier => self.stats.pulses_rejected += 1,
            _ => self.stats.pulses_used += 1,
        }
        self.retry_waiting(host, out);
    }

    fn retry_waiting(&mut self, host: &HostClock, out: &mut Vec<Aligned<T>>) {
        let epoch = self.clock.epoch();
        let waiting = std::mem::take(&mut self.waiting);
        for w in waiting {
            if w.epoch != epoch {
                self.push_out(w.msg, Err(NotAligned::OutsideClockEpoch), out);
            } else {
                self.place(w.msg, w.ticks, w.host_ns, host, out);
            }
        }
    }

    /// A message without device time, placed by the host clock (its transmission time removed).
    fn host_timed(&self, msg: T, host_ns: i64, host: &HostClock) -> Aligned<T> {
        let mean_wait_ns = self.wait_mean_ns as i64;
        let time = host
            .to_gps(host_ns)
            .map(|(t, sigma)| AlignedTime {
                t_gps_ns: t
                    .saturating_sub(self.tx_ns(msg.bahrs().type_id()))
                    .saturating_sub(mean_wait_ns),
                sigma_ns: (sigma.powi(2) + SERVICE_QUEUE_SIGMA_NS.powi(2) + self.wait_var_ns2)
                    .sqrt(),
                source: TimeSource::HostClock,
                status: host.status(host_ns),
            })
            .ok_or(NotAligned::HostClockUnknown);
        Aligned { message: msg, time }
    }

    /// Status of the MCU clock model for a sample at MCU time `ticks`.
    pub fn clock_status(&self, ticks: u64) -> ClockStatus {
        self.clock.status(ticks)
    }
}

/// Whether a pulse whose named second is `offset_ns` from the fallback clock's time of it
/// disagrees with that clock: beyond `sigmas` standard deviations of the two errors together,
/// the fallback's (`view_sigma_ns`) and the pulse fit's residual (`pulse_sigma_ns`), taken as
/// independent (their variances add). Exactly at the tolerance still agrees.
fn pulse_disagrees(offset_ns: i64, sigmas: f64, view_sigma_ns: f64, pulse_sigma_ns: f64) -> bool {
    let tol_ns = sigmas * (view_sigma_ns.powi(2) + pulse_sigma_ns.powi(2)).sqrt();
    (offset_ns as f64).abs() > tol_ns
}

#[cfg(test)]
mod tests {
    use vigil_drivers::bahrs::{DataTime, Inertial, InertialHealth, SyncPulseTime};

    use super::*;
    use crate::time::host::HostClockConfig;
    use crate::time::testrng::Lcg;

    const MS: i64 = 1_000_000;
    const S: i64 = 1_000_000_000;
    const G0: i64 = 1_400_000_000 * S;

    /// A BAHRS with an MCU clock `offset_us` at G0, running `ppm` fast, restarting at `reset_at`.
    struct Mcu {
        offset_us: u64,
        ppm: f64,
        reset_at: Option<i64>,
    }

    impl Mcu {
        fn ticks(&self, gps: i64) -> u64 {
            let (start, off) = match self.reset_at {
                Some(r) if gps >= r => (r, 0),
                _ => (G0, self.offset_us),
            };
            off + ((gps - start) as f64 * (1.0 + self.ppm * 1e-6) / 1000.0) as u64
        }
    }

    /// What the VN-200 gives the BAHRS aligner: references to the host clock, and its PPS
    /// times (TimeGps - TimeGpsPps).
    #[derive(Clone, Copy)]
    struct Vn {
        host_clock: bool,
        pps_times: bool,
    }

    /// A VN-200 feeding only the host clock (the pulse seconds come from it).
    const HOST_ONLY: Vn = Vn {
        host_clock: true,
        pps_times: false,
    };

    /// Runs `seconds` of a BAHRS at 100 Hz inertial with PPS and a VN-200 at 100 Hz (as `vn`
    /// says), and returns (aligned samples, truth GPS time per sample index) and the aligner's
    /// counters.
    fn run_with(
        mcu: &Mcu,
        seconds: i64,
        seq_restart_at: Option<i64>,
        vn: Vn,
    ) -> (Vec<(i64, Aligned<Message>)>, BahrsAlignerStats) {
        let host_offset = 777 * S;
        let mut rng = Lcg(3);
        let mut host = HostClock::new(HostClockConfig::default());
        let mut refs = PpsReferences::new();
        let mut al = BahrsAligner::new(BahrsAlignerConfig::default());
        let mut out = Vec::new();
        let lat = |rng: &mut Lcg| MS / 2 + (rng.unit() * MS as f64) as i64;
        let mut seq: u32 = 0;
        for k in 0..seconds * 100 {
            let gps = G0 + k * 10 * MS;
            // VN-200 references at 100 Hz into the host clock and the PPS times.
            let vn_host = gps + host_offset + lat(&mut rng);
            if vn.host_clock {
                host.add(vn_host, gps);
            }
            if vn.pps_times {
                refs.add(vn_host, gps, gps.rem_euclid(S) as u64);
            }
            if seq_restart_at == Some(gps) {
                seq = 0;
            }
            let s = seq as u8;
            seq += 1;
            let ticks = mcu.ticks(gps);
            let data = Message::Inertial(Inertial {
                seq: s,
                specific_force_raw: [(k % 30_000) as i16, 0, 0],
                angular_rate_raw: [0; 3],
                health: InertialHealth(0),
            });
            let rx = gps + host_offset + 2 * MS + lat(&mut rng);
            for a in al.handle(data, rx, &host, &refs) {
                out.push(a);
            }
            let time = Message::InertialTime(DataTime {
                seq: s,
                data_seq: s,
                mcu_time_us: ticks,
            });
            out.extend(al.handle(time, rx + MS, &host, &refs));
            if k % 100 == 0 {
                let pulse = Message::SyncPulseTime(SyncPulseTime {
                    seq: 0,
                    mcu_time_us: ticks,
                });
                let rx = gps + host_offset + 3 * MS + lat(&mut rng);
                out.extend(al.handle(pulse, rx, &host, &refs));
            }
            out.extend(al.expire(rx, &host));
        }
        out.extend(al.flush(&host));
        let samples = out
            .into_iter()
            .filter_map(|a| match a.message {
                Message::Inertial(i) => {
                    Some((G0 + i64::from(i.specific_force_raw[0]) * 10 * MS, a))
                }
                _ => None,
            })
            .collect();
        (samples, *al.stats())
    }

    /// [`run_with`] with the pulse seconds from the host clock (no VN-200 PPS times).
    fn run(mcu: &Mcu, seconds: i64, seq_restart_at: Option<i64>) -> Vec<(i64, Aligned<Message>)> {
        run_with(mcu, seconds, seq_restart_at, HOST_ONLY).0
    }

    /// p99 |error| after the first 10 s, and the share within 2 sigma; every sample aligned,
    /// PPS-disciplined and locked.
    fn figures(samples: &[(i64, Aligned<Message>)]) -> (i64, f64) {
        let mut errors = Vec::new();
        let mut within_2s = 0usize;
        for (truth, a) in samples {
            if *truth < G0 + 10 * S {
                continue;
            }
            let t = a.time.as_ref().expect("aligned after the first 10 s");
            assert_eq!(t.source, TimeSource::PpsDisciplined);
            assert_eq!(t.status, ClockStatus::Locked);
            let e = (t.t_gps_ns - truth).abs();
            errors.push(e);
            if (e as f64) <= 2.0 * t.sigma_ns {
                within_2s += 1;
            }
        }
        errors.sort_unstable();
        (
            errors[errors.len() * 99 / 100],
            within_2s as f64 / errors.len() as f64,
        )
    }

    #[test]
    fn a_read_interval_moves_and_widens_only_the_host_timed_messages() {
        // A host clock 5 s ahead of GPS (references with 0.5..1.5 ms of delay).
        let mut host = HostClock::new(HostClockConfig::default());
        let mut rng = Lcg(5);
        for k in 0..1_000 {
            let gps = G0 + k * 10 * MS;
            host.add(gps + 5 * S + MS / 2 + (rng.unit() * MS as f64) as i64, gps);
        }
        let refs = PpsReferences::new();
        let at = G0 + 9 * S + 5 * S;
        let ack = Message::Ack(vigil_drivers::bahrs::Ack {
            acked_type: 0x10,
            status: 0,
        });
        let place = |interval_ns: u64| {
            let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
            al.set_read_interval(interval_ns);
            let out = al.handle(ack, at, &host, &refs);
            out[0].time.unwrap()
        };
        let (on_arrival, paced) = (place(0), place(10 * MS as u64));
        // Read every 10 ms: 5 ms earlier; sigma grows by 10 ms / sqrt(12) = 2.887 ms (rss).
        assert_eq!(on_arrival.t_gps_ns - paced.t_gps_ns, 5 * MS);
        let added = (paced.sigma_ns.powi(2) - on_arrival.sigma_ns.powi(2)).sqrt();
        assert!((added - 2_886_751.0).abs() < 1.0, "{added}");
    }

    #[test]
    fn pulses_without_a_host_clock_are_not_used_unchecked() {
        // The VN-200 gives its PPS times but the host clock never learns: every pulse is named
        // by the VN-200, but none can be cross-checked against another clock (issue 18: a wrong
        // edge or second would pass unseen), so none is used and nothing is aligned.
        let mcu = Mcu {
            offset_us: 42_000_000,
            ppm: -33.0,
            reset_at: None,
        };
        let vn = Vn {
            host_clock: false,
            pps_times: true,
        };
        let (samples, stats) = run_with(&mcu, 20, None, vn);
        assert_eq!(stats.pulses_unverified, 20);
        assert_eq!((stats.pulses_from_vn200_pps, stats.pulses_used), (0, 0));
        assert!(samples.iter().all(|(_, a)| a.time.is_err()));
    }

    #[test]
    fn pulses_fall_back_to_the_host_clock_without_a_vn200_pps_time() {
        // VN-200 absent as a PPS time source: the host clock names every identified pulse.
        let mcu = Mcu {
            offset_us: 1_000,
            ppm: 12.0,
            reset_at: None,
        };
        let (samples, stats) = run_with(&mcu, 15, None, HOST_ONLY);
        assert_eq!(stats.pulses_from_vn200_pps, 0);
        // The host model needs two 1 s buckets: the first pulses are unidentified or cannot be
        // cross-checked yet.
        assert_eq!(
            stats.pulses_from_host_clock + stats.pulses_unidentified + stats.pulses_unverified,
            15
        );
        assert!(stats.pulses_from_host_clock >= 12, "{stats:?}");
        let (p99, within) = figures(&samples);
        assert!(p99 <= 50_000 && within >= 0.95, "{p99} ns, {within}");
        // Neither source: nothing identified, nothing aligned, nothing dropped.
        let none = Vn {
            host_clock: false,
            pps_times: false,
        };
        let (samples, stats) = run_with(&mcu, 5, None, none);
        assert_eq!(stats.pulses_unidentified, 5);
        assert_eq!(samples.len(), 500);
        assert!(samples.iter().all(|(_, a)| a.time.is_err()));
    }

    #[test]
    fn aligns_within_tens_of_microseconds_with_honest_sigma() {
        let mcu = Mcu {
            offset_us: 123_456_789,
            ppm: 37.0,
            reset_at: None,
        };
        let samples = run(&mcu, 30, None);
        assert_eq!(samples.len(), 3000, "every sample emitted once");
        let (p99, within_2s) = figures(&samples);
        eprintln!("bahrs alignment: p99 error {p99} ns, {within_2s:.3} within 2 sigma");
        assert!(p99 <= 50_000, "p99 error {p99} ns");
        assert!(within_2s >= 0.95, "{within_2s} within 2 sigma");
    }

    #[test]
    fn samples_before_the_first_pulse_wait_then_align() {
        let mcu = Mcu {
            offset_us: 5_000_000,
            ppm: -20.0,
            reset_at: None,
        };
        let samples = run(&mcu, 6, None);
        // The host clock needs 2 s of references before it can identify a pulse; samples of the
        // first 2 s wait (bounded) and are then either aligned or marked, never dropped.
        assert_eq!(samples.len(), 600);
        let aligned = samples.iter().filter(|(_, a)| a.time.is_ok()).count();
        eprintln!("aligned {aligned} of 600");
        assert!(aligned >= 350, "{aligned}");
        for (truth, a) in &samples {
            if let Ok(t) = &a.time {
                assert!(
                    (t.t_gps_ns - truth).abs() as f64 <= 5.0 * t.sigma_ns,
                    "claimed {t:?} truth {truth}"
                );
            }
        }
    }

    #[test]
    fn device_reset_relocks_without_wrong_times() {
        // The MCU restarts at t = 20.005 s (its clock from 0 and its counters from 0).
        let reset = G0 + 20 * S + 5 * MS;
        let mcu = Mcu {
            offset_us: 900_000_000,
            ppm: 10.0,
            reset_at: Some(reset),
        };
        let samples = run(&mcu, 30, Some(reset + 5 * MS));
        assert_eq!(samples.len(), 3000);
        let mut relocked_at = None;
        for (truth, a) in &samples {
            if let Ok(t) = &a.time {
                let e = (t.t_gps_ns - truth).abs();
                // Never a wrong time: every claimed time is within 5 sigma, and nothing claimed
                // "locked" to the PPS is off by more than 100 us (the host-clock fallback bridges
                // the reset with its own, ~1 ms sigma).
                assert!(e as f64 <= 5.0 * t.sigma_ns, "truth {truth} claimed {t:?}");
                if t.status == ClockStatus::Locked && t.source == TimeSource::PpsDisciplined {
                    assert!(e <= 100_000, "locked but off by {e} ns");
                }
                if *truth > reset && relocked_at.is_none() {
                    relocked_at = Some(*truth);
                }
            }
        }
        // Re-locked (times given again) within 5 s of the reset.
        assert!(relocked_at.unwrap() - reset < 5 * S, "{:?}", relocked_at);
    }

    // --- issue 23: behaviours the mutation run found unpinned ---

    /// Host = GPS + this, for the small streams below.
    const HOST_OFF: i64 = 777 * S;

    fn pulse(ticks: u64) -> Message {
        Message::SyncPulseTime(SyncPulseTime {
            seq: 0,
            mcu_time_us: ticks,
        })
    }

    /// A BAHRS aligner after `seconds` of 100 Hz inertial pairs and a pulse on every whole
    /// second (MCU clock `mcu`), with the host clock learned from a VN-200 (references at GPS +
    /// [`HOST_OFF`] + 1 ms): its PPS model is locked. Returns the aligner and the host clock.
    fn locked(mcu: &Mcu, seconds: i64) -> (BahrsAligner, HostClock) {
        let mut host = HostClock::new(HostClockConfig::default());
        let refs = PpsReferences::new();
        let mut al = BahrsAligner::new(BahrsAlignerConfig::default());
        for k in 0..seconds * 100 {
            let gps = G0 + k * 10 * MS;
            host.add(gps + HOST_OFF + MS, gps);
            let s = k as u8;
            let rx = gps + HOST_OFF + 2 * MS;
            let data = Message::Inertial(Inertial {
                seq: s,
                specific_force_raw: [0; 3],
                angular_rate_raw: [0; 3],
                health: InertialHealth(0),
            });
            al.handle(data, rx, &host, &refs);
            let time = Message::InertialTime(DataTime {
                seq: s,
                data_seq: s,
                mcu_time_us: mcu.ticks(gps),
            });
            al.handle(time, rx + MS, &host, &refs);
            if k % 100 == 0 {
                al.handle(pulse(mcu.ticks(gps)), gps + HOST_OFF + 3 * MS, &host, &refs);
            }
            al.expire(rx + MS, &host);
        }
        (al, host)
    }

    fn accuracy(ticks: u64) -> Message {
        Message::Accuracy(vigil_drivers::bahrs::Accuracy {
            seq: 0,
            std_north_raw: 1,
            std_east_raw: 1,
            std_heading_raw: 1,
            mcu_time_us: ticks,
        })
    }

    /// A 0x02 with every field zero: only its sequence matters to the aligner.
    fn zero_navigation(seq: u8) -> Message {
        Message::Navigation(vigil_drivers::bahrs::Navigation {
            seq,
            pressure_height_raw: 0,
            velocity_down_raw: 0,
            roll_raw: 0,
            pitch_raw: 0,
            heading_raw: 0,
            health: vigil_drivers::bahrs::NavigationHealth(0),
        })
    }

    const MCU: Mcu = Mcu {
        offset_us: 5_000_000,
        ppm: 15.0,
        reset_at: None,
    };

    #[test]
    fn a_pulse_reported_at_the_wrong_edge_raises_the_clock_disagreement_until_a_right_one() {
        let (mut al, host) = locked(&MCU, 12);
        let refs = PpsReferences::new();
        assert!(!al.clock_disagreement());
        assert!(al.stats().pulses_used >= 8, "{:?}", al.stats());
        // A 0x03 (own MCU time) now goes through the PPS clock: not a host fallback.
        let fallbacks = al.stats().host_fallback;
        let g = G0 + 12_200 * MS;
        let a = al.handle(accuracy(MCU.ticks(g)), g + HOST_OFF + 2 * MS, &host, &refs);
        assert_eq!(a[0].time.unwrap().source, TimeSource::PpsDisciplined);
        assert_eq!(al.stats().host_fallback, fallbacks);
        // A report of an "edge" 300 ms after the 12 s one: named 12 s (the nearest second) by
        // the host clock, while its MCU time maps 300 ms later, far beyond 5 sigma of ~1 ms.
        let bad = G0 + 12_300 * MS;
        let a = al.handle(pulse(MCU.ticks(bad)), bad + HOST_OFF + 3 * MS, &host, &refs);
        assert!(al.clock_disagreement());
        assert_eq!(al.stats().pulses_disagreeing, 1);
        // The PPS model is dropped: the 0x06 itself (a sample at its MCU time) and the next
        // 0x03 take the host fallback, counted, each at its instant within its (wider) sigma.
        let g = G0 + 12_400 * MS;
        let b = al.handle(accuracy(MCU.ticks(g)), g + HOST_OFF + 2 * MS, &host, &refs);
        for (out, truth) in [(a, bad), (b, g)] {
            let t = out[0].time.unwrap();
            assert_eq!(t.source, TimeSource::DeviceClockViaHost);
            assert!(
                ((t.t_gps_ns - truth).abs() as f64) < 3.0 * t.sigma_ns,
                "{t:?}"
            );
        }
        assert_eq!(al.stats().host_fallback, fallbacks + 2);
        // The next right pulse clears it.
        let good = G0 + 13 * S;
        al.handle(
            pulse(MCU.ticks(good)),
            good + HOST_OFF + 3 * MS,
            &host,
            &refs,
        );
        assert!(!al.clock_disagreement());
    }

    #[test]
    fn navigation_pairs_and_accuracy_messages_are_placed_by_their_mcu_time() {
        let (mut al, host) = locked(&MCU, 12);
        let refs = PpsReferences::new();
        // A 0x02 and its 0x04 sampled at g: both at g through the PPS clock (the tick is
        // truncated to the us).
        let g = G0 + 11_995 * MS;
        let h = g + HOST_OFF + 2 * MS;
        let nav = zero_navigation(9);
        let mut out = al.handle(nav, h, &host, &refs);
        let time = Message::NavigationTime(DataTime {
            seq: 9,
            data_seq: 9,
            mcu_time_us: MCU.ticks(g),
        });
        out.extend(al.handle(time, h + MS, &host, &refs));
        // A 0x03 carries its own MCU time.
        let g3 = G0 + 11_997 * MS;
        out.extend(al.handle(
            accuracy(MCU.ticks(g3)),
            g3 + HOST_OFF + 2 * MS,
            &host,
            &refs,
        ));
        let kinds: Vec<u8> = out.iter().map(|a| a.message.type_id()).collect();
        assert_eq!(kinds, vec![0x02, 0x04, 0x03]);
        for (a, truth) in out.iter().zip([g, g, g3]) {
            let t = a.time.unwrap();
            assert_eq!(t.source, TimeSource::PpsDisciplined, "{a:?}");
            assert!((t.t_gps_ns - truth).abs() <= 5_000, "{a:?}");
        }
    }

    #[test]
    fn an_invalid_time_message_comes_out_device_time_invalid_and_is_counted() {
        let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
        let host = HostClock::new(HostClockConfig::default());
        let refs = PpsReferences::new();
        // Sections 3.4 / 3.5: data sequence 0 and time 0 mark a time message invalid.
        let invalid = DataTime {
            seq: 3,
            data_seq: 0,
            mcu_time_us: 0,
        };
        let out = al.handle(Message::InertialTime(invalid), G0, &host, &refs);
        assert_eq!(out.len(), 1);
        assert_eq!(out[0].time, Err(NotAligned::DeviceTimeInvalid));
        let out = al.handle(Message::NavigationTime(invalid), G0, &host, &refs);
        assert_eq!(out[0].time, Err(NotAligned::DeviceTimeInvalid));
        let st = al.stats();
        assert_eq!((st.invalid_time_messages, st.not_aligned), (2, 2));
    }

    #[test]
    fn unpaired_data_and_samples_without_a_clock_are_released_after_their_holds() {
        // No host clock, no pulses.
        let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
        let host = HostClock::new(HostClockConfig::default());
        let refs = PpsReferences::new();
        let h0 = G0;
        let inertial = Message::Inertial(Inertial {
            seq: 1,
            specific_force_raw: [0; 3],
            angular_rate_raw: [0; 3],
            health: InertialHealth(0),
        });
        let nav = zero_navigation(2);
        for m in [inertial, nav, accuracy(1_000_000)] {
            assert!(al.handle(m, h0, &host, &refs).is_empty());
        }
        // The data wait 0.5 s (`pair_hold_s`) for their time messages.
        assert!(al.expire(h0 + 400 * MS, &host).is_empty());
        let out = al.expire(h0 + 600 * MS, &host);
        let kinds: Vec<(u8, _)> = out.iter().map(|a| (a.message.type_id(), a.time)).collect();
        assert_eq!(
            kinds,
            vec![
                (0x01, Err(NotAligned::NoTimeMessage)),
                (0x02, Err(NotAligned::NoTimeMessage))
            ]
        );
        // The 0x03 waits 2 s (`clock_wait_s`) for a clock, released once it waited longer (the
        // same strict rule as the pairing hold).
        assert!(al.expire(h0 + 1_500 * MS, &host).is_empty());
        assert!(al.expire(h0 + 2_000 * MS, &host).is_empty());
        let out = al.expire(h0 + 2_500 * MS, &host);
        assert_eq!(out.len(), 1);
        assert_eq!(
            (out[0].message.type_id(), out[0].time),
            (0x03, Err(NotAligned::ClockUnlocked))
        );
        assert_eq!(al.stats().not_aligned, 3);
    }

    #[test]
    fn a_host_timed_message_takes_its_frame_time_at_the_set_baud_rate_off() {
        // A host clock 5 s ahead of GPS.
        let mut host = HostClock::new(HostClockConfig::default());
        for k in 0..1_000 {
            let gps = G0 + k * 10 * MS;
            host.add(gps + 5 * S + MS, gps);
        }
        let refs = PpsReferences::new();
        let at = G0 + 9 * S + 5 * S;
        let ack = Message::Ack(vigil_drivers::bahrs::Ack {
            acked_type: 0x10,
            status: 0,
        });
        let place = |baud: Option<u32>| {
            let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
            if let Some(b) = baud {
                al.set_baud(b);
            }
            al.handle(ack, at, &host, &refs)[0].time.unwrap().t_gps_ns
        };
        // 10 bits per byte: the frame takes len * 10 / 9600 s instead of len * 10 / 115 200 s.
        let len = ack.to_frame().len() as i64;
        let longer = len * 10 * S / 9_600 - len * 10 * S / 115_200;
        assert_eq!(place(None) - place(Some(9_600)), longer);
    }

    /// A host clock on GPS + HOST_OFF (+1 ms link) over 12 s of references, and an aligner
    /// whose host envelope was built from 0x03 at 100 Hz from 3 s to 5 s, no pulse reported.
    fn envelope_without_pulses() -> (HostClock, BahrsAligner) {
        let mut host = HostClock::new(HostClockConfig::default());
        for k in 0..1_200 {
            let gps = G0 + k * 10 * MS;
            host.add(gps + HOST_OFF + MS, gps);
        }
        let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
        for k in 300..500 {
            accuracy_at(&mut al, &host, G0 + k * 10 * MS);
        }
        (host, al)
    }

    /// Hands in the 0x03 of the sample at GPS time `g`: its first byte 0.5 ms after the
    /// sample, its frame on the wire at 115 200 baud, then the VN-200's 1 ms link.
    fn accuracy_at(al: &mut BahrsAligner, host: &HostClock, g: i64) -> Vec<Aligned<Message>> {
        let tx = accuracy(0).to_frame().len() as i64 * 10 * S / 115_200;
        al.handle(
            accuracy(MCU.ticks(g)),
            g + HOST_OFF + MS / 2 + tx + MS,
            host,
            &PpsReferences::new(),
        )
    }

    #[test]
    fn a_sample_waits_for_the_pulse_model_only_while_pulses_are_reported() {
        // With no pulse reported, the envelope's 0x03 take the host fallback.
        let (host, mut al) = envelope_without_pulses();
        let refs = PpsReferences::new();
        let acc_at = |al: &mut BahrsAligner, g: i64| accuracy_at(al, &host, g);
        // A pulse report at 5 s handed in with no host clock (not established at that moment):
        // its second cannot be named, it is not used, but pulses are flowing from then on.
        let p = G0 + 5 * S;
        let none = HostClock::new(HostClockConfig::default());
        al.handle(pulse(MCU.ticks(p)), p + HOST_OFF + 3 * MS, &none, &refs);
        assert_eq!(al.stats().pulses_unidentified, 1);
        for k in 0..150 {
            acc_at(&mut al, p + k * 10 * MS);
        }
        // 1.5 s after the report (within `clock_wait_s`, 2 s): a 0x03 waits for the pulse model
        // although the host fallback could place it.
        let g = p + 1_500 * MS;
        assert!(al.fallback(MCU.ticks(g), &host).is_some());
        assert!(acc_at(&mut al, g).is_empty());
        // 2.5 s after it, no pulse is flowing: the fallback places it at once.
        for k in 151..250 {
            acc_at(&mut al, p + k * 10 * MS);
        }
        let g = p + 2_500 * MS;
        let out = acc_at(&mut al, g);
        let placed = out
            .iter()
            .find(|a| matches!(a.message, Message::Accuracy(x) if x.mcu_time_us == MCU.ticks(g)))
            .expect("placed at once");
        let t = placed.time.unwrap();
        assert_eq!(t.source, TimeSource::DeviceClockViaHost);
        assert!(((t.t_gps_ns - g).abs() as f64) < 3.0 * t.sigma_ns, "{t:?}");
    }

    #[test]
    fn samples_waiting_for_a_clock_are_capped_oldest_first() {
        // No clock at all: every 0x03 waits; the 513th pushes the first out (512 waiting at
        // most), marked.
        let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
        let host = HostClock::new(HostClockConfig::default());
        let refs = PpsReferences::new();
        for k in 0..512u64 {
            let out = al.handle(accuracy(1_000_000 + k * 10_000), G0, &host, &refs);
            assert!(out.is_empty(), "{k}");
        }
        let out = al.handle(accuracy(1_000_000 + 512 * 10_000), G0, &host, &refs);
        assert_eq!(out.len(), 1);
        assert!(matches!(out[0].message, Message::Accuracy(a) if a.mcu_time_us == 1_000_000));
        assert_eq!(out[0].time, Err(NotAligned::ClockUnlocked));
    }

    #[test]
    fn a_device_reset_marks_what_waits_from_the_old_epoch_and_counts_it() {
        let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
        let host = HostClock::new(HostClockConfig::default());
        let refs = PpsReferences::new();
        assert!(al.handle(accuracy(50_000_000), G0, &host, &refs).is_empty());
        // The MCU time restarts near 0 (50 s backwards): the waiting 0x03 cannot be mapped any
        // more.
        let out = al.handle(accuracy(1_000), G0 + 10 * MS, &host, &refs);
        assert_eq!(out.len(), 1);
        assert!(matches!(out[0].message, Message::Accuracy(a) if a.mcu_time_us == 50_000_000));
        assert_eq!(out[0].time, Err(NotAligned::OutsideClockEpoch));
        assert_eq!(al.stats().not_aligned, 1);
    }

    #[test]
    fn repeated_and_late_pulse_reports_are_counted_not_used() {
        let (mut al, host) = locked(&MCU, 12);
        let refs = PpsReferences::new();
        let used = al.stats().pulses_used;
        // The 11 s pulse reported again, then the 10 s one (late: not a reset).
        for s in [11, 10] {
            let g = G0 + s * S;
            al.handle(pulse(MCU.ticks(g)), G0 + 12 * S + HOST_OFF, &host, &refs);
        }
        let st = al.stats();
        assert_eq!(
            (
                st.pulse_reports_repeated,
                st.pulse_reports_stale,
                st.pulses_used
            ),
            (1, 1, used)
        );
    }

    #[test]
    fn the_host_fallback_places_a_sample_at_its_instant_with_the_stated_sigma() {
        // VN-200 references to the host clock (host = GPS + HOST_OFF + link) with a link of
        // 0.5 ms or 2.5 ms alternately: smallest 0.5 ms, mean excess over it 1 ms.
        let mut host = HostClock::new(HostClockConfig::default());
        for k in 0..1_000 {
            let gps = G0 + k * 10 * MS;
            host.add(gps + HOST_OFF + MS / 2 + (k % 2) * 2 * MS, gps);
        }
        let refs = PpsReferences::new();
        let mut al: BahrsAligner = BahrsAligner::new(BahrsAlignerConfig::default());
        // The port is read every 10 ms, at the middle of the interval for every message: 5 ms.
        al.set_read_interval(10 * MS as u64);
        // 0x03 at 100 Hz: first byte 0.5 ms (the assumed output delay) after the sample, a link
        // of 0.5 ms (+ 20 us in odd host seconds, so the envelope's minima scatter) or 1.5 ms
        // alternately, the 5 ms read wait; stamped at its last byte.
        let len = accuracy(0).to_frame().len() as i64;
        let tx = len * 10 * S / 115_200;
        for k in 0..1_000 {
            let g = G0 + k * 10 * MS;
            let link = MS / 2 + (k % 2) * MS + ((k / 100) % 2) * 20_000;
            let rx = g + HOST_OFF + MS / 2 + link + 5 * MS + tx;
            al.handle(accuracy(MCU.ticks(g)), rx, &host, &refs);
        }
        // A sample at g: its first byte at the smallest delay is at g + HOST_OFF + 6 ms; the host
        // clock maps that as a receive at 1.5 ms (0.5 + 1) to g + 4.5 ms; + 1 ms excess - 0.5 ms
        // output delay - 5 ms wait = g (within the envelope's fit).
        let g = G0 + 9_005 * MS;
        let ticks = MCU.ticks(g);
        let a = al.fallback(ticks, &host).unwrap();
        assert!((a.t_gps_ns - g).abs() < 50_000, "{}", a.t_gps_ns - g);
        assert_eq!(a.source, TimeSource::DeviceClockViaHost);
        // Sigma: root-sum-square of the host clock's at that host time, the envelope's, the
        // output delay's 0.5 ms and the read interval's 10 ms / sqrt(12).
        let (h, env) = al
            .mcu_host()
            .host_ns(ticks, G0 + 10 * S + HOST_OFF)
            .unwrap();
        assert!(env > 1_000.0, "{env}");
        let (_, host_sigma) = host.to_gps(h).unwrap();
        let expected = (host_sigma.powi(2) + env.powi(2) + 0.25e12 + 100e12 / 12.0).sqrt();
        assert!(
            (a.sigma_ns - expected).abs() < 1.0,
            "{} {expected}",
            a.sigma_ns
        );
    }

    #[test]
    fn a_pulse_within_the_cross_check_but_off_the_fit_is_rejected_as_an_outlier() {
        let (mut al, host) = locked(&MCU, 12);
        let refs = PpsReferences::new();
        let used = al.stats().pulses_used;
        // The 12 s pulse reported with the MCU time of 1 ms after the edge: within the host
        // cross-check (5 sigma of ~0.7 ms) but 1 ms off the PPS fit (limit 200 us).
        let off = G0 + 12 * S + MS;
        al.handle(pulse(MCU.ticks(off)), off + HOST_OFF + 3 * MS, &host, &refs);
        let st = al.stats();
        assert_eq!((st.pulses_disagreeing, st.pulses_rejected), (0, 1));
        assert_eq!(st.pulses_used, used);
    }

    #[test]
    fn samples_waiting_for_the_pulse_model_are_placed_by_it_once_a_pulse_is_used() {
        // An envelope from 0x03 at 100 Hz, then a pulse report that cannot be named.
        let (host, mut al) = envelope_without_pulses();
        let refs = PpsReferences::new();
        let acc_at = |al: &mut BahrsAligner, g: i64| accuracy_at(al, &host, g);
        let none = HostClock::new(HostClockConfig::default());
        let p = G0 + 5 * S;
        al.handle(pulse(MCU.ticks(p)), p + HOST_OFF + 3 * MS, &none, &refs);
        // A 0x03 at 5.5 s waits for the pulse model.
        let g = p + 500 * MS;
        assert!(acc_at(&mut al, g).is_empty());
        // The 6 s pulse, named by the host clock and cross-checked, forms the model: the waiting
        // 0x03 comes out through it, at its instant (one pulse: the nominal rate, 15 ppm of
        // 0.5 s = 7.5 us off).
        let q = G0 + 6 * S;
        let out = al.handle(pulse(MCU.ticks(q)), q + HOST_OFF + 3 * MS, &host, &refs);
        let placed = out
            .iter()
            .find(|a| matches!(a.message, Message::Accuracy(x) if x.mcu_time_us == MCU.ticks(g)))
            .expect("released by the pulse");
        let t = placed.time.unwrap();
        assert_eq!(t.source, TimeSource::PpsDisciplined);
        assert!((t.t_gps_ns - g).abs() < 20_000, "{t:?}");
    }

    #[test]
    fn a_pulse_disagrees_beyond_the_combined_sigmas_only() {
        // By hand: 3 sigmas of sqrt(3^2 + 4^2) = 5 ns make a 15 ns tolerance, either way. The
        // sum of the sigmas (21 ns) would pass 16 ns; the difference of the variances is not a
        // number, and would pass everything. Without a pulse fit the fallback's 9 ns is all.
        for (offset, disagrees) in [(15, false), (-15, false), (16, true), (-16, true)] {
            assert_eq!(
                pulse_disagrees(offset, 3.0, 3.0, 4.0),
                disagrees,
                "{offset}"
            );
        }
        assert!(pulse_disagrees(10, 3.0, 3.0, 0.0));
        assert!(!pulse_disagrees(9, 3.0, 3.0, 0.0));
        // A saturated offset (a second named i64::MIN away) disagrees.
        assert!(pulse_disagrees(i64::MIN, 5.0, 1e6, 1e3));
    }
}
