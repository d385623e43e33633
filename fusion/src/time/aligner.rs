//! One deterministic time aligner for every device (issue 7, "Output").
//!
//! [`Aligner::handle`] takes (device, decoded message, how it was received) and returns the
//! samples that became final, each an [`AlignedSample`] carrying the device's 0-based input index
//! (BAHRS pairing and the waits below reorder the output; the index joins it back to the input
//! and to the simulator's truth). Nothing is dropped: every input comes out exactly once, aligned
//! or marked not aligned with a reason, at most [`AlignerConfig::host_wait_ns`] (host-timed
//! devices waiting for the host clock) or the BAHRS aligner's own holds later in host time, and
//! [`Aligner::flush`] releases the rest at the end of a stream. The output depends only on the
//! inputs (no clock is read).
//!
//! [`Aligner::clock_report`] gives each device's clock status, offset, drift and residuals for
//! the monitor and the logs.

use std::collections::VecDeque;

use serde::Serialize;
use vigil_drivers::ttmrf::asterix::AsterixMessage;
use vigil_drivers::ttmrf::gdl90::Gdl90Message;
use vigil_drivers::ttmrf::mavlink::MavlinkMessage;
use vigil_drivers::ttmrf::raw::RawFrame;
use vigil_drivers::ttmrf::text::TextMessage;
use vigil_drivers::vn200::Vn200Message;
use vigil_drivers::{bahrs, watson};

use super::bahrs::{BahrsAligner, BahrsAlignerConfig};
use super::cross_check::{CrossCheckConfig, host_view};
use super::host::{HostClock, HostClockConfig};
use super::host_timed::{HostTimedLink, first_byte_host_ns, host_timed, last_byte_host_ns};
use super::line_load::LineLoad;
use super::pps::PpsReferences;
use super::ttmrf::{TtAlignerConfig, json_ts, raw_meta};
use super::vn200::{Vn200Aligner, Vn200AlignerConfig, Vn200Times};
use super::{Aligned, AlignedTime, ClockStatus, NotAligned, Reads, Rx, TimeSource};

/// The devices of the installation: the device families of the drivers' protocol table
/// (`vigil_drivers::protocol`), re-exported here so the aligner's users keep their import.
pub use vigil_drivers::protocol::Device;

/// The aligner's per-device slot (the family's index in [`Device::ALL`]).
trait Slot {
    fn slot(self) -> usize;
}

impl Slot for Device {
    fn slot(self) -> usize {
        self as usize
    }
}

/// A decoded message of any device.
#[derive(Debug, Clone, PartialEq)]
pub enum Sample {
    /// BAHRS protocol 2.0.
    Bahrs(bahrs::Message),
    /// Watson line.
    Watson(watson::Line),
    /// VN-200 binary or ASCII message.
    Vn200(Box<Vn200Message>),
    /// TT-Multi-RF text output (CSV, JSON, NMEA, AT).
    TtText(Box<TextMessage>),
    /// TT-Multi-RF raw frame (HEX / Beast).
    TtRaw(Box<RawFrame>),
    /// TT-Multi-RF MAVLink.
    TtMavlink(Box<MavlinkMessage>),
    /// TT-Multi-RF GDL90.
    TtGdl90(Box<Gdl90Message>),
    /// TT-Multi-RF ASTERIX.
    TtAsterix(Box<AsterixMessage>),
}

impl Sample {
    /// The device that sends this kind of message.
    pub fn device(&self) -> Device {
        match self {
            Sample::Bahrs(_) => Device::Bahrs,
            Sample::Watson(_) => Device::Watson,
            Sample::Vn200(_) => Device::Vn200,
            _ => Device::Ttmrf,
        }
    }
}

/// One final sample: its device, its 0-based input index for that device, and its time.
#[derive(Debug, Clone, PartialEq)]
pub struct AlignedSample {
    /// The device.
    pub device: Device,
    /// 0-based order of the sample among the device's inputs.
    pub index: u64,
    /// The sample and its GPS time, or why there is none.
    pub aligned: Aligned<Sample>,
}

/// Parameters of the [`Aligner`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AlignerConfig {
    /// Host clock model.
    pub host: HostClockConfig,
    /// BAHRS aligner.
    pub bahrs: BahrsAlignerConfig,
    /// VN-200 aligner.
    pub vn200: Vn200AlignerConfig,
    /// Watson port.
    pub watson: HostTimedLink,
    /// TT-Multi-RF port.
    pub ttmrf: TtAlignerConfig,
    /// How long a sample that needs the host clock waits for it, ns (the host model needs two
    /// seconds of VN-200 references). Beyond it, the sample is released not aligned.
    pub host_wait_ns: i64,
    /// Most samples waiting for the host clock; the oldest is released beyond it.
    pub host_wait_capacity: usize,
    /// The VN-200's and the TT-Multi-RF's own times against the host clock (issue 18 point 4).
    pub cross_check: CrossCheckConfig,
}

impl Default for AlignerConfig {
    fn default() -> Self {
        Self {
            host: HostClockConfig::default(),
            bahrs: BahrsAlignerConfig::default(),
            vn200: Vn200AlignerConfig::default(),
            watson: HostTimedLink::WATSON,
            ttmrf: TtAlignerConfig::default(),
            host_wait_ns: 3_000_000_000,
            host_wait_capacity: 4096,
            cross_check: CrossCheckConfig::default(),
        }
    }
}

/// A device's clock model, for the monitor and the logs.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ClockReport {
    /// The device.
    pub device: Device,
    /// Model state.
    pub status: ClockStatus,
    /// Device (or host) clock minus GPS time, ns, where the model has one.
    pub offset_ns: Option<f64>,
    /// Clock rate error against GPS, ppm.
    pub drift_ppm: Option<f64>,
    /// 1-sigma of the model's residuals (pulse fit, link-delay spread), ns.
    pub residual_ns: Option<f64>,
}

/// Largest host time accepted, ns (2^61: 73 years of uptime).
const MAX_HOST_NS: i64 = 1 << 61;

/// Largest message length accepted, bytes (far above any of these protocols' frames).
const MAX_WIRE_LEN: usize = 1 << 20;

/// How much later than its neighbour the host may stamp a byte of the TT-Multi-RF's output,
/// beyond the port's read interval and adapter timer, until the VN-200 has shown the spread of
/// a single read's delay, ns. Decision: 5 ms, a host that wakes within a few ms of its reads
/// (the simulator's bursty host stamps 0-6 ms, which the VN-200 then measures); a larger
/// figure only lengthens the runs a message may have queued behind.
const TT_READ_SPREAD_NS: i64 = 5_000_000;

struct Held {
    device: Device,
    index: u64,
    sample: Sample,
    rx: Rx,
    /// The TT-Multi-RF line at its arrival: a message held for the host clock is placed with
    /// the wait its line allowed then, not with the line's state when the clock arrives.
    tt_line: TtLineAt,
}

/// A TT-Multi-RF line's state at a message's arrival: what bounds that message's wait in the
/// module's transmit queue ([`LineLoad`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
struct TtLineAt {
    /// The longest the message can have waited in the module, ns (0: no wait): how long the
    /// line had been full ([`LineLoad::full_for_ns`]) or the line time of the output that can
    /// have been sent back to back before it ([`LineLoad::queued_for_ns`]), whichever is
    /// longer, at most the stated buffer's line time
    /// ([`TtAlignerConfig::output_buffer_bytes`]) and [`TtAlignerConfig::queue_limit_ns`].
    queue_ns: i64,
    /// The line had been full ([`LineLoad::full_for_ns`]): its messages teach the host clock
    /// nothing, and a time of its own too early for the queue is a queue past the limit.
    full: bool,
    /// The line had been full for longer than the limit, and no stated buffer keeps the wait
    /// within it: the wait of a message without a time of its own may pass the limit, unless a
    /// recent time of its own bounds it (`Aligner::tt_queue_bounded_until_ns`).
    beyond_limit: bool,
}

/// Puts the samples of every device on GPS time.
pub struct Aligner {
    cfg: AlignerConfig,
    /// The configuration as given (`cfg` adds the ports' read intervals to it).
    base: AlignerConfig,
    host: HostClock,
    bahrs: BahrsAligner<(u64, bahrs::Message)>,
    vn200: Vn200Aligner,
    /// The VN-200's recent PPS times, naming the BAHRS sync pulses.
    vn_pps: PpsReferences,
    held: VecDeque<Held>,
    next_index: [u64; 4],
    last_host_ns: i64,
    last_bahrs_ticks: Option<u64>,
    // --- issue 18: per-port link settings, applied to `base` to give `cfg` ---
    /// Each port's read interval, ns (0: read as its bytes arrive), by device slot.
    read_interval_ns: [u64; 4],
    /// Each port's USB adapter latency timer, ns (0: none known), by device slot.
    latency_timer_ns: [u64; 4],
    // --- issue 18 point 6: a second source of the host clock ---
    /// The host clock learned from the TT-Multi-RF's GNSS time (JSON `ts`, raw TS24h): used
    /// where the VN-200's model is not locked and this one is better (a VN-200 silent for
    /// minutes).
    tt_host: HostClock,
    // --- issue 18 point 4: the TT-Multi-RF's own time against the host clock ---
    /// The latest cross-checked TT-Multi-RF time (JSON `ts`, TS24h) disagreed with the host clock.
    tt_disagreement: bool,
    /// TT-Multi-RF times that disagreed with the host clock.
    tt_disagreeing: u64,
    // --- a TT-Multi-RF sending more than its line carries ---
    /// Bytes of its messages over the last moments of host time ([`LineLoad`]).
    tt_line: LineLoad,
    /// Its line at its latest message.
    tt_line_at: TtLineAt,
    /// Its messages received while its line was full.
    tt_busy_messages: u64,
    /// Its latest time of its own (JSON `ts`, TS24h) on a full line came earlier than the host
    /// clock's view of its arrival by more than the queue limit, and the line has stayed full
    /// since: its queue is longer than the limit (or its clock is wrong), so a sample timed by
    /// the host clock is not aligned ([`NotAligned::LineFull`]).
    tt_queue_beyond_limit: bool,
    /// Host time (arrival) up to which the latest agreeing time of its own bounds the module's
    /// queue within the limit, ns; `i64::MIN` for none. See [`Self::place_checked`].
    tt_queue_bounded_until_ns: i64,
}

impl Aligner {
    /// An aligner with no clock models yet.
    pub fn new(cfg: AlignerConfig) -> Self {
        Self {
            cfg,
            base: cfg,
            host: HostClock::new(cfg.host),
            bahrs: BahrsAligner::new(cfg.bahrs),
            vn200: Vn200Aligner::new(cfg.vn200),
            vn_pps: PpsReferences::new(),
            held: VecDeque::new(),
            next_index: [0; 4],
            last_host_ns: i64::MIN,
            last_bahrs_ticks: None,
            read_interval_ns: [0; 4],
            latency_timer_ns: [0; 4],
            tt_host: HostClock::new(cfg.host),
            tt_disagreement: false,
            tt_disagreeing: 0,
            tt_line: LineLoad::default(),
            tt_line_at: TtLineAt::default(),
            tt_busy_messages: 0,
            tt_queue_beyond_limit: false,
            tt_queue_bounded_until_ns: i64::MIN,
        }
    }

    /// The host clock learned from the TT-Multi-RF's GNSS time (see [`Self::host_clock`]).
    pub fn tt_host_clock(&self) -> &HostClock {
        &self.tt_host
    }

    /// The host clock model to map host time `h` with: the VN-200's while it is locked; else
    /// whichever of it and the TT-Multi-RF's gives the smaller sigma (a coasting VN-200 model
    /// is often still the better one).
    #[inline]
    fn pick<'a>(vn: &'a HostClock, tt: &'a HostClock, h: i64) -> &'a HostClock {
        if matches!(vn.status(h), ClockStatus::Locked | ClockStatus::Locking) {
            return vn;
        }
        match (vn.to_gps(h), tt.to_gps(h)) {
            (Some((_, a)), Some((_, b))) if b < a => tt,
            (None, Some(_)) => tt,
            _ => vn,
        }
    }

    /// The devices whose clock disagrees with another beyond their combined sigmas now
    /// (`clock_disagreement`, issue 18 point 4): the BAHRS when its latest pulse contradicted
    /// the host clock's view of its MCU time; the VN-200 when its latest valid GPS time, the
    /// TT-Multi-RF when its latest `ts` / TS24h, contradicted the host clock
    /// ([`super::cross_check`]).
    pub fn clock_disagreements(&self) -> Vec<Device> {
        let mut v = Vec::new();
        if self.bahrs.clock_disagreement() {
            v.push(Device::Bahrs);
        }
        if self.vn200.clock_disagreement() {
            v.push(Device::Vn200);
        }
        if self.tt_disagreement {
            v.push(Device::Ttmrf);
        }
        v
    }

    /// TT-Multi-RF times (JSON `ts`, TS24h) that disagreed with the host clock so far.
    pub fn ttmrf_times_disagreeing(&self) -> u64 {
        self.tt_disagreeing
    }

    /// Whether the TT-Multi-RF's line was full at its latest message ([`LineLoad`]): its
    /// output waits in the module, so its times teach no host clock, its own time may precede
    /// its arrival by as long as the line has been full (at most
    /// [`TtAlignerConfig::queue_limit_ns`]), and its host-timed samples carry that wait in
    /// their sigma, or are not aligned once it cannot be bounded (`place_checked`).
    pub fn ttmrf_line_busy(&self) -> bool {
        self.tt_line_at.full
    }

    /// The devices whose serial line is full at host time `host_ns` (`line_full` in the
    /// integrity topic): the TT-Multi-RF when its messages have filled at least 80 % of its
    /// line for at least the last 100 ms up to `host_ns` ([`LineLoad::full_for_ns`]). Judged at
    /// `host_ns`, not at the latest message, so a module that falls silent after a full spell
    /// is not reported full for ever. Decision: only the TT-Multi-RF is watched, because its
    /// load grows with the traffic it hears; the other devices send a fixed configured output,
    /// and their lines are not watched (README, time alignment, "Not yet right").
    /// An iterator, not a `Vec`: the report runs on the live path, which allocates nothing
    /// in steady state.
    pub fn lines_full(&self, host_ns: i64) -> impl Iterator<Item = Device> + use<> {
        let full = self.tt_line.full_for_ns(host_ns, self.base.ttmrf.link.baud);
        (full > 0).then_some(Device::Ttmrf).into_iter()
    }

    /// TT-Multi-RF messages received while its line was full, so far.
    pub fn ttmrf_busy_messages(&self) -> u64 {
        self.tt_busy_messages
    }

    /// Counts a TT-Multi-RF message on its line and notes how long it can have waited in the
    /// module: as long as the line has been full, or the line time of the output that can
    /// have been sent back to back before it (a list of targets sent at once queues its later
    /// messages long before the line counts as full).
    /// Decision: when the line becomes full the TT's host clock is dropped, since the
    /// references it learned just before may already have been queued (a line full from
    /// power-on is seen within its first 100 ms, long before five seconds of references could
    /// lock it). A short run is not full, and its messages still teach the TT's host clock:
    /// the run's first one waited for nothing, and the clock's envelope follows the earliest
    /// arrivals. The queued ones do raise its mean excess and spread over the envelope (a JSON
    /// list sent at once teaches it a longer link delay than an unqueued message has); not
    /// learning from a message that may have queued is the stricter choice, not made yet.
    fn note_tt_line(&mut self, rx: Rx) {
        let baud = self.base.ttmrf.link.baud;
        // Where the reads tell, the message's end rather than its read's (a read may hold the
        // start of the next message too: a run's stamps would then be uneven by up to a read).
        let end_ns = last_byte_host_ns(rx, baud);
        self.tt_line.add(end_ns, rx.wire_len);
        let full_ns = self.tt_line.full_for_ns(end_ns, baud);
        let run_ns = self
            .tt_line
            .queued_for_ns(end_ns, baud, rx.wire_len, self.tt_read_slack_ns());
        let waited_ns = full_ns.max(run_ns);
        // A stated transmit buffer bounds the wait as well: a message waited at most for the
        // bytes ahead of it (`TtAlignerConfig::output_buffer_bytes`).
        let bound_ns = self
            .cfg
            .ttmrf
            .buffer_wait_ns(baud)
            .map_or(waited_ns, |w| waited_ns.min(w));
        let queue_ns = bound_ns.min(self.cfg.ttmrf.queue_limit_ns);
        let full = full_ns > 0;
        if full && !self.tt_line_at.full {
            self.tt_host = HostClock::new(self.cfg.host);
        }
        self.tt_line_at = TtLineAt {
            queue_ns,
            full,
            beyond_limit: bound_ns > self.cfg.ttmrf.queue_limit_ns,
        };
        self.tt_busy_messages += u64::from(full);
        // An empty line has no queue.
        self.tt_queue_beyond_limit &= full;
    }

    /// The most the host may stamp one byte of the TT-Multi-RF's output later than another
    /// beyond their spacing on the wire, ns ([`LineLoad::queued_for_ns`]): the port's read
    /// interval, its adapter's latency timer and the spread of a single read's delay (learned
    /// from the VN-200; [`TT_READ_SPREAD_NS`] until it is known).
    fn tt_read_slack_ns(&self) -> i64 {
        let slot = Device::Ttmrf.slot();
        let spread = self
            .host
            .read_spread_ns()
            .unwrap_or(TT_READ_SPREAD_NS as f64);
        let fixed = self.read_interval_ns[slot].saturating_add(self.latency_timer_ns[slot]);
        i64::try_from(fixed)
            .unwrap_or(i64::MAX)
            .saturating_add(spread.ceil() as i64)
    }

    /// The TT-Multi-RF's link for its host-timed samples: while its line is full, a message
    /// waited in the module between 0 and the time the line has been full (at most the queue
    /// limit) before it was sent, taken as uniform (half of it added to its delay, it /
    /// sqrt(12) to its sigma).
    fn tt_link(&self, line: TtLineAt) -> HostTimedLink {
        // A wait of 0 (a line not full) leaves the link as it is.
        self.cfg
            .ttmrf
            .link
            .with_read_interval(u64::try_from(line.queue_ns).unwrap_or(0))
    }

    /// The host clock model.
    pub fn host_clock(&self) -> &HostClock {
        &self.host
    }

    /// The BAHRS aligner (its counters and MCU clock).
    pub fn bahrs(&self) -> &BahrsAligner<(u64, bahrs::Message)> {
        &self.bahrs
    }

    /// The VN-200 aligner (its counters and start-up clock).
    pub fn vn200(&self) -> &Vn200Aligner {
        &self.vn200
    }

    /// The VN-200's recent PPS times (what names the BAHRS sync pulses).
    pub fn vn200_pps(&self) -> &PpsReferences {
        &self.vn_pps
    }

    /// Takes one decoded message, received as `rx`; returns every sample that became final.
    pub fn handle(&mut self, sample: Sample, rx: Rx) -> Vec<AlignedSample> {
        let mut out = Vec::new();
        self.handle_into(sample, rx, &mut out);
        out
    }

    /// [`Aligner::handle`], appending the samples that became final to `out` (a buffer the
    /// caller reuses: no allocation per message once it has grown; issue 21).
    pub fn handle_into(&mut self, sample: Sample, rx: Rx, out: &mut Vec<AlignedSample>) {
        let rx = bounded(rx);
        let device = sample.device();
        let index = self.next_index[device.slot()];
        self.next_index[device.slot()] += 1;
        self.last_host_ns = self.last_host_ns.max(rx.host_ns);
        // The BAHRS's expiry below, done already with the same host clock (see the branch).
        let mut bahrs_expired = false;
        match sample {
            Sample::Bahrs(m) => bahrs_expired = self.handle_bahrs(index, m, rx, out),
            Sample::Vn200(m) => {
                let time = self.vn200_time(&m, rx);
                out.push(AlignedSample {
                    device,
                    index,
                    aligned: Aligned {
                        message: Sample::Vn200(m),
                        time,
                    },
                });
                // A new host-clock reference may free what waits for it.
                self.retry_held(out);
            }
            other => self.handle_other(device, index, other, rx, out),
        }
        let now = self.last_host_ns;
        if !bahrs_expired {
            let host = Self::pick(&self.host, &self.tt_host, now);
            out.extend(self.bahrs.expire(now, host).into_iter().map(bahrs_out));
        }
        self.expire_held(now, out);
    }

    /// A BAHRS message (`index`-th of the device): to the BAHRS aligner, which pairs it with its
    /// time messages. Returns whether the BAHRS's expiry was done here already.
    fn handle_bahrs(
        &mut self,
        index: u64,
        m: bahrs::Message,
        rx: Rx,
        out: &mut Vec<AlignedSample>,
    ) -> bool {
        if let Some(t) = bahrs_ticks(&m) {
            self.last_bahrs_ticks = Some(t);
        }
        let host = Self::pick(&self.host, &self.tt_host, rx.host_ns);
        let done = self
            .bahrs
            .handle((index, m), rx.host_ns, host, &self.vn_pps);
        out.extend(done.into_iter().map(bahrs_out));
        // A BAHRS sample changes no host clock, and in order (the usual case) it is the newest
        // host time: the expiry after the match would pick the same clock again (choosing it was
        // 3 % of `handle`'s instructions).
        if rx.host_ns == self.last_host_ns {
            let now = self.last_host_ns;
            out.extend(self.bahrs.expire(now, host).into_iter().map(bahrs_out));
            return true;
        }
        false
    }

    /// The time of a VN-200 message: its own GPS time (binary outputs, which also name the
    /// BAHRS's pulses and feed the host clock), else the host clock.
    fn vn200_time(&mut self, m: &Vn200Message, rx: Rx) -> Result<AlignedTime, NotAligned> {
        let o = match m {
            Vn200Message::Binary(o) => o,
            Vn200Message::Ascii(_) => return host_timed(&self.host, rx, self.vn200_link()),
        };
        let times = Vn200Times::of(o);
        let time = self.vn200.handle_times_checked(
            &times,
            rx,
            &mut self.host,
            &self.tt_host,
            &self.cfg.cross_check,
        );
        // Its PPS time names the BAHRS pulses, when its GPS time is valid.
        if let (Ok(a), Some(pps)) = (&time, times.time_gps_pps_ns)
            && a.source == TimeSource::NativeGps
        {
            self.vn_pps
                .add(first_byte_host_ns(rx, self.cfg.vn200.baud), a.t_gps_ns, pps);
        }
        match time {
            // Decision: without valid GPS time and without a start-up clock model (the default
            // output has no TimeStartup), the message is placed by the host clock, like an ASCII
            // one: its attitude stays valid through a GNSS outage (ICD Table 2.78) and the host
            // clock coasts on the references from before it. Without a host clock the VN-200's
            // own reason stands.
            Err(why @ (NotAligned::DeviceTimeInvalid | NotAligned::ClockUnlocked)) => {
                host_timed(&self.host, rx, self.vn200_link()).or(Err(why))
            }
            // Its GPS time disagreed with the host clock (and it has no TimeStartup model):
            // placed by the host clock, the better of the two relations, with its sigma (issue
            // 18 point 4).
            Err(NotAligned::ClockDisagreement) => {
                let host = Self::pick(&self.host, &self.tt_host, rx.host_ns);
                host_timed(host, rx, self.vn200_link()).or(Err(NotAligned::ClockDisagreement))
            }
            t => t,
        }
    }

    /// A Watson or TT-Multi-RF message: placed by its own time or the host clock (held while the
    /// host clock is not known yet); a TT-Multi-RF time may teach the host clock.
    fn handle_other(
        &mut self,
        device: Device,
        index: u64,
        other: Sample,
        rx: Rx,
        out: &mut Vec<AlignedSample>,
    ) {
        if device == Device::Ttmrf {
            self.note_tt_line(rx);
        }
        let time = self.place_checked(&other, rx, self.tt_line_at);
        if self.learn_tt_host(&other, rx, &time) {
            // A new host-clock reference may free what waits for it.
            self.retry_held(out);
        }
        if time == Err(NotAligned::HostClockUnknown) {
            self.hold(
                Held {
                    device,
                    index,
                    sample: other,
                    rx,
                    tt_line: self.tt_line_at,
                },
                out,
            );
        } else {
            out.push(AlignedSample {
                device,
                index,
                aligned: Aligned {
                    message: other,
                    time,
                },
            });
        }
    }

    /// Releases everything still held (end of stream): what cannot be aligned now is marked.
    pub fn flush(&mut self) -> Vec<AlignedSample> {
        let host = Self::pick(&self.host, &self.tt_host, self.last_host_ns);
        let mut out: Vec<AlignedSample> =
            self.bahrs.flush(host).into_iter().map(bahrs_out).collect();
        self.retry_held(&mut out);
        for h in std::mem::take(&mut self.held) {
            out.push(not_aligned(h, NotAligned::HostClockUnknown));
        }
        out
    }

    /// Clock status of every device at host time `now_ns`.
    pub fn clock_report(&self, now_ns: i64) -> Vec<ClockReport> {
        let now_ns = now_ns.clamp(0, MAX_HOST_NS);
        let host_status = self.host.status(now_ns);
        let host_offset = self.host.to_gps(now_ns).map(|(t, _)| (now_ns - t) as f64);
        let host_sigma = self.host.to_gps(now_ns).map(|(_, s)| s);
        Device::ALL
            .iter()
            .map(|&device| match device {
                Device::Bahrs => {
                    let clock = self.bahrs.clock();
                    let status = self
                        .last_bahrs_ticks
                        .map_or(ClockStatus::Unlocked, |t| clock.status(t));
                    let offset_ns = self.last_bahrs_ticks.and_then(|t| {
                        clock
                            .to_gps(t)
                            .ok()
                            .map(|(g, _)| t as f64 * 1000.0 - g as f64)
                    });
                    ClockReport {
                        device,
                        status,
                        offset_ns,
                        drift_ppm: clock.drift_ppm(),
                        residual_ns: clock.residual_sigma_ns(),
                    }
                }
                Device::Vn200 => ClockReport {
                    device,
                    status: self.vn200.status(now_ns),
                    offset_ns: None,
                    drift_ppm: self.vn200.startup_drift_ppm(),
                    residual_ns: None,
                },
                Device::Watson | Device::Ttmrf => ClockReport {
                    device,
                    status: host_status,
                    offset_ns: host_offset,
                    drift_ppm: self.host.drift_ppm(),
                    residual_ns: host_sigma,
                },
            })
            .collect()
    }

    /// `device`'s port is read every `interval_ns` (0: as its bytes arrive): its host-timed
    /// samples get the wait in their delay and sigma ([`HostTimedLink::with_read_interval`]).
    /// For the BAHRS only its host-timed messages and its host-clock fallback feel it
    /// ([`BahrsAligner::set_read_interval`]). The VN-200 is the host clock's reference: its
    /// wait is not modelled, so its port must be read on arrival (`vigil run` refuses pacing it).
    pub fn set_read_interval(&mut self, device: Device, interval_ns: u64) {
        self.read_interval_ns[device.slot()] = interval_ns;
        self.apply_port_settings();
    }

    /// `device`'s port runs at `baud` bit/s (configured or recorded; issue 18 point 2): every
    /// transmission time of that port is computed with it. 0 keeps the built-in rate.
    pub fn set_baud(&mut self, device: Device, baud: u32) {
        if baud == 0 {
            return;
        }
        match device {
            Device::Bahrs => self.base.bahrs.baud = baud,
            Device::Watson => self.base.watson.baud = baud,
            Device::Vn200 => self.base.vn200.baud = baud,
            Device::Ttmrf => self.base.ttmrf.link.baud = baud,
        }
        self.apply_port_settings();
    }

    /// `device`'s port is behind a USB adapter with a latency timer of `timer_ns` (an FTDI
    /// chip: a partial USB packet waits until the timer runs out; issue 18 point 1). A sparse
    /// port's message tail then waits between 0 and the timer after its last byte: like a read
    /// interval, half of it is taken off and `timer / sqrt(12)` added to the sigma of its
    /// host-timed samples (root-sum-square with any read interval). Not applied to the VN-200:
    /// the host clock learns its link delay from it. 0: no timer known.
    pub fn set_latency_timer(&mut self, device: Device, timer_ns: u64) {
        self.latency_timer_ns[device.slot()] = timer_ns;
        self.apply_port_settings();
    }

    /// The TT-Multi-RF's transmit buffer is `bytes` long (`None`: unknown, the default):
    /// while its line is full, a message's wait is bounded by that many bytes' line time as
    /// well as by how long the line has been full ([`TtAlignerConfig::output_buffer_bytes`]).
    /// The other devices' lines are not watched, so they have no such setting. `Some(0)` is
    /// taken as not stated: a buffer of nothing would call a full line empty.
    pub fn set_ttmrf_output_buffer(&mut self, bytes: Option<u32>) {
        self.base.ttmrf.output_buffer_bytes = bytes.filter(|&b| b > 0);
        self.apply_port_settings();
    }

    /// The TT-Multi-RF's transmit buffer as stated, bytes (`None`: not stated).
    pub fn ttmrf_output_buffer_bytes(&self) -> Option<u32> {
        self.cfg.ttmrf.output_buffer_bytes
    }

    /// Derives the working configuration from the base and the per-port settings.
    fn apply_port_settings(&mut self) {
        let wait = |slot: usize| -> (u64, f64) {
            let (i, t) = (self.read_interval_ns[slot], self.latency_timer_ns[slot]);
            // Two independent uniform waits: means add, variances add. As one "interval" for
            // `with_read_interval`: mean i/2 + t/2, variance (i^2 + t^2) / 12.
            (
                i / 2 + t / 2,
                ((i as f64).powi(2) + (t as f64).powi(2)) / 12.0,
            )
        };
        let link = |l: HostTimedLink, (mean, var): (u64, f64)| HostTimedLink {
            output_delay_ns: l
                .output_delay_ns
                .saturating_add(i64::try_from(mean).unwrap_or(i64::MAX)),
            output_delay_sigma_ns: (l.output_delay_sigma_ns.powi(2) + var).sqrt(),
            ..l
        };
        self.cfg.watson = link(self.base.watson, wait(Device::Watson.slot()));
        self.cfg.ttmrf = TtAlignerConfig {
            link: link(self.base.ttmrf.link, wait(Device::Ttmrf.slot())),
            ..self.base.ttmrf
        };
        self.cfg.vn200.baud = self.base.vn200.baud;
        self.cfg.bahrs.baud = self.base.bahrs.baud;
        self.vn200.set_baud(self.base.vn200.baud);
        let (mean, var) = wait(Device::Bahrs.slot());
        self.bahrs.set_link_wait(mean as f64, var);
        self.bahrs.set_baud(self.base.bahrs.baud);
    }

    fn vn200_link(&self) -> HostTimedLink {
        HostTimedLink {
            baud: self.cfg.vn200.baud,
            output_delay_ns: self.cfg.vn200.output_delay_ns,
            output_delay_sigma_ns: 0.0,
        }
    }

    /// GPS time of a sample whose time depends on the host clock (Watson, TT-Multi-RF).
    /// `line`: the TT-Multi-RF line at the sample's arrival.
    fn place_host_dependent(
        &self,
        sample: &Sample,
        rx: Rx,
        line: TtLineAt,
    ) -> Result<AlignedTime, NotAligned> {
        let tt = &TtAlignerConfig {
            link: self.tt_link(line),
            ..self.cfg.ttmrf
        };
        let h = first_byte_host_ns(rx, tt.link.baud);
        let host = Self::pick(&self.host, &self.tt_host, h);
        let leap = self
            .vn200
            .gps_minus_utc(host.to_gps(h).map_or(0, |(t, _)| t));
        match sample {
            Sample::Watson(_) => host_timed(host, rx, self.cfg.watson),
            Sample::TtText(m) => match &**m {
                TextMessage::Json(j) => match j.ts_ms {
                    Some(ts) => json_ts(ts, rx, tt, host, leap),
                    None => host_timed(host, rx, tt.link),
                },
                _ => host_timed(host, rx, tt.link),
            },
            Sample::TtRaw(f) => {
                let meta = match &**f {
                    RawFrame::ModeS(s) => s.meta,
                    RawFrame::ModeAc(a) => a.meta,
                    RawFrame::Uat(u) => u.meta,
                };
                raw_meta(&meta, rx, tt, host, leap).unwrap_or_else(|| host_timed(host, rx, tt.link))
            }
            _ => host_timed(host, rx, tt.link),
        }
    }

    /// As [`Self::place_host_dependent`], with a TT-Multi-RF time of day (JSON `ts`, TS24h)
    /// cross-checked against the host clock's view of the same message (issue 18 point 4,
    /// [`super::cross_check`]): the better relation held before (the VN-200's, or the TT's own
    /// from its earlier agreeing times), its first byte's host time less the port's output
    /// delay, with the port's link sigma. A disagreeing time is replaced by the host-timed
    /// placement (its sigma; not a reference of the TT's host clock), or marked
    /// [`NotAligned::ClockDisagreement`] without a host clock. TS1s is not checked: its second
    /// is named by the host clock itself. While the TT's line is full its time may precede the
    /// view by as long as the line has been full, up to the queue limit
    /// ([`CrossCheckConfig::disagrees_after_queue`]).
    ///
    /// Decision (the manual states neither the module's buffer nor what it does when full): a
    /// time of its own earlier than the view by more than the tolerance and the queue limit, on
    /// a full line, is a queue longer than the limit or a wrong clock, and the host cannot tell
    /// which. Either way neither it nor the host clock can place the message, nor any other
    /// message of that line until one of its own times agrees again or the line empties: they
    /// are [`NotAligned::LineFull`] (a 4 KiB buffer holds 4.3 s at 9600 baud, far beyond any
    /// sigma the host-timed placement could claim).
    ///
    /// Decision (the same silence; a line with no time of its own, CSV or HEXd without TS24h,
    /// gives no such evidence): a message's wait is bounded by how long the line has been full
    /// ([`super::line_load`]), and a host-timed message carries a wait up to the queue limit in
    /// its sigma. Once the line has been full for longer than the limit, that bound no longer
    /// covers it, and only a time of its own can: one that agrees, having preceded the host's
    /// view by `early`, waited at most `early` plus the cross-check's tolerance, and a message
    /// sent after it (in order, behind it in the queue) at most that plus the host time since.
    /// While that stays within the limit the line's host-timed messages are placed with the
    /// limit in their sigma; otherwise they are [`NotAligned::LineFull`]. So a line full for
    /// more than 0.5 s that carries no time of its own is not aligned until it empties: its
    /// module's buffer, which sets the real wait (0.36 s for 4 KiB at 115 200 baud, 4.3 s at
    /// 9600), is not documented, and a buffer assumed would be a guess. An integrator who
    /// knows it states it ([`Self::set_ttmrf_output_buffer`]): a buffer whose line time is
    /// within the limit bounds every wait, and the line stays placed.
    fn place_checked(
        &mut self,
        sample: &Sample,
        rx: Rx,
        line: TtLineAt,
    ) -> Result<AlignedTime, NotAligned> {
        let time = self.place_host_dependent(sample, rx, line);
        let Ok(a) = time else { return time };
        let link = self.cfg.ttmrf.link;
        let h = first_byte_host_ns(rx, link.baud);
        if a.source != TimeSource::UtcTimeOfDay {
            // Host-timed, or a TS1s second named by the host clock.
            if sample.device() == Device::Ttmrf
                && (self.tt_queue_beyond_limit
                    || (line.beyond_limit && rx.host_ns > self.tt_queue_bounded_until_ns))
            {
                return Err(NotAligned::LineFull);
            }
            return time;
        }
        let Some((t, s)) = host_view(&self.host, &self.tt_host, h) else {
            return time;
        };
        let view = (
            t.saturating_sub(link.output_delay_ns),
            (s * s + link.output_delay_sigma_ns.powi(2)).sqrt(),
        );
        self.tt_disagreement = self.cfg.cross_check.disagrees_after_queue(
            (a.t_gps_ns, a.sigma_ns),
            view,
            line.queue_ns,
        );
        if !self.tt_disagreement {
            self.tt_queue_beyond_limit = false;
            // This message waited at most `early_ns + tol_ns` (the cross-check's tolerance); a
            // later one, in order behind it, at most that plus the host time since.
            let early_ns = view.0.saturating_sub(a.t_gps_ns).max(0);
            let tol_ns = self.cfg.cross_check.tolerance_ns(a.sigma_ns, view.1) as i64;
            self.tt_queue_bounded_until_ns = rx
                .host_ns
                .saturating_add(self.cfg.ttmrf.queue_limit_ns)
                .saturating_sub(early_ns.saturating_add(tol_ns));
            return time;
        }
        self.tt_disagreeing += 1;
        let early =
            self.cfg
                .cross_check
                .early_beyond_queue((a.t_gps_ns, a.sigma_ns), view, line.queue_ns);
        if line.full && early {
            self.tt_queue_beyond_limit = true;
            return Err(NotAligned::LineFull);
        }
        let host = Self::pick(&self.host, &self.tt_host, h);
        host_timed(host, rx, self.tt_link(line)).or(Err(NotAligned::ClockDisagreement))
    }

    /// A TT-Multi-RF sample placed by its own GNSS time (JSON `ts`, raw TS24h) is a reference of
    /// the second host clock: host time its first byte left against its GPS time plus the
    /// port's assumed output delay (issue 18 point 6). TS1s is not one (its second is named by
    /// the host clock itself), nor is any while the TT's line is full (its messages waited in
    /// the module). Returns true when a reference was added.
    fn learn_tt_host(
        &mut self,
        sample: &Sample,
        rx: Rx,
        time: &Result<AlignedTime, NotAligned>,
    ) -> bool {
        let Ok(a) = time else { return false };
        // A full line's messages left the module late by an unknown queue: not references.
        if self.tt_line_at.full
            || a.source != TimeSource::UtcTimeOfDay
            || a.status != ClockStatus::Locked
            || !matches!(sample, Sample::TtText(_) | Sample::TtRaw(_))
        {
            return false;
        }
        let link = self.base.ttmrf.link;
        self.tt_host.add(
            first_byte_host_ns(rx, link.baud),
            a.t_gps_ns.saturating_add(link.output_delay_ns),
        );
        true
    }

    fn hold(&mut self, h: Held, out: &mut Vec<AlignedSample>) {
        if self.held.len() >= self.cfg.host_wait_capacity
            && let Some(old) = self.held.pop_front()
        {
            out.push(not_aligned(old, NotAligned::HostClockUnknown));
        }
        self.held.push_back(h);
    }

    fn retry_held(&mut self, out: &mut Vec<AlignedSample>) {
        if self.held.is_empty()
            || (self.host.status(self.last_host_ns) == ClockStatus::Unlocked
                && self.tt_host.status(self.last_host_ns) == ClockStatus::Unlocked)
        {
            return;
        }
        for h in std::mem::take(&mut self.held) {
            let time = self.place_checked(&h.sample, h.rx, h.tt_line);
            if time == Err(NotAligned::HostClockUnknown) {
                self.held.push_back(h);
            } else {
                out.push(AlignedSample {
                    device: h.device,
                    index: h.index,
                    aligned: Aligned {
                        message: h.sample,
                        time,
                    },
                });
            }
        }
    }

    fn expire_held(&mut self, now: i64, out: &mut Vec<AlignedSample>) {
        while self
            .held
            .front()
            .is_some_and(|h| now - h.rx.host_ns > self.cfg.host_wait_ns)
        {
            if let Some(h) = self.held.pop_front() {
                out.push(not_aligned(h, NotAligned::HostClockUnknown));
            }
        }
    }
}

fn not_aligned(h: Held, why: NotAligned) -> AlignedSample {
    AlignedSample {
        device: h.device,
        index: h.index,
        aligned: Aligned {
            message: h.sample,
            time: Err(why),
        },
    }
}

/// `rx` with its host times and lengths bounded. Decision: a host monotonic time counts from
/// boot; one outside 0 ..= 2^61 ns (73 years) is garbage and is clamped, so every difference of
/// host times fits in an i64.
fn bounded(rx: Rx) -> Rx {
    Rx {
        host_ns: rx.host_ns.clamp(0, MAX_HOST_NS),
        wire_len: rx.wire_len.min(MAX_WIRE_LEN),
        reads: rx.reads.map(|r| Reads {
            first_host_ns: r.first_host_ns.clamp(0, MAX_HOST_NS),
            first_bytes: r.first_bytes.min(MAX_WIRE_LEN),
            last_bytes: r.last_bytes.min(MAX_WIRE_LEN),
            after_bytes: r.after_bytes.min(MAX_WIRE_LEN),
        }),
    }
}

fn bahrs_out(a: Aligned<(u64, bahrs::Message)>) -> AlignedSample {
    let (index, m) = a.message;
    AlignedSample {
        device: Device::Bahrs,
        index,
        aligned: Aligned {
            message: Sample::Bahrs(m),
            time: a.time,
        },
    }
}

/// The MCU time a BAHRS message carries, us.
fn bahrs_ticks(m: &bahrs::Message) -> Option<u64> {
    match m {
        bahrs::Message::InertialTime(t) | bahrs::Message::NavigationTime(t) if t.is_valid() => {
            Some(t.mcu_time_us)
        }
        bahrs::Message::Accuracy(a) => Some(a.mcu_time_us),
        bahrs::Message::SyncPulseTime(p) => Some(p.mcu_time_us),
        _ => None,
    }
}

#[cfg(test)]
#[path = "aligner_tests.rs"]
mod tests;
