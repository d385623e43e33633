//! vigil's deterministic service: raw port chunks in, bus payloads and alerts out.
//!
//! [`Service`] is the whole processing path as a plain struct, sans-IO in the style of
//! quinn-proto: no tokio, no ports, no clock. Time is an argument of every call:
//! - [`Service::handle_chunk`] takes one read chunk of a port with its host monotonic receive time
//!   and runs it through [`Ingest`] (decode, align) -> [`Pipeline`] (fuse) -> [`convert`]
//!   -> [`Outputs`] (publish), feeding the [`Monitor`] with every payload published;
//! - [`Service::handle_link`] tells it a port opened or closed;
//! - [`Service::handle_timeout`] publishes the `integrity` report and the monitor's alerts due at
//!   a host time.
//!
//! Outputs are drained through the [`Outputs`] trait: the bus in `vigil run`
//! ([`runtime::live::BusOutputs`]), UDP and the live view ([`outputs`]), memory in tests
//! ([`Collected`]). The same struct serves `vigil run` ([`runtime`]), `vigil replay` ([`replay`])
//! and the end-to-end tests; given the same calls it gives the same outputs.
//!
//! Also here: the configuration ([`config`], TOML, validated with errors naming the key), the
//! conversion of fused outputs to bus payloads ([`convert`]), the recording's decoded and fused
//! channels ([`recording`]), the golden-file format ([`golden`]) and vigil's JSON names
//! ([`json_names`]).
//!
//! Bad input is counted (decoder counters, per-port in `integrity`), never fatal.

pub mod config;
pub mod convert;
pub mod golden;
pub mod json_names;
pub mod outputs;
pub mod recording;
pub mod replay;
pub mod runtime;

use anyhow::{Result, anyhow};
use vigil_bus::payload::integrity as integ;
use vigil_bus::payload::integrity::DEVICE_TTMRF;
use vigil_bus::{AlertPayload, IntegrityPayload, Payload, TrafficPayload};
use vigil_bus::{AttitudePayload, OwnshipPayload};
use vigil_fusion::magnetic::Wmm;
use vigil_fusion::ownship::Ownship;
use vigil_fusion::pipeline::{Fused, Pipeline, PipelineConfig};
use vigil_fusion::time::aligner::AlignedSample;
use vigil_monitor::{Monitor, MonitorParams};

use crate::recording::{Tapped, identity, messages::active_set};
use config::Port;
use convert::PortReport;
use vigil_fusion::ingest::Ingest;
use vigil_record::PortLink;

/// Where the service's payloads go (the bus in `vigil run`; a collector in tests).
pub trait Outputs {
    /// Publishes a payload. A failure is the sink's to count and log: it never stops the service.
    fn publish<T: Payload>(&mut self, p: &T);

    /// Takes the fused traffic picture itself (absolute positions, velocities, callsigns: more
    /// than the bus payload holds) and the ownship of the same fusion step, for the outputs that
    /// re-encode traffic (MAVLink, GDL90). Called before the picture's payload is published.
    /// Default: ignored.
    fn traffic_picture(
        &mut self,
        _pic: &vigil_fusion::pipeline::TrafficPicture,
        _own: Option<&vigil_fusion::ownship::Ownship>,
    ) {
    }

    /// The end of a processing step (a chunk, a timeout): everything it publishes has been
    /// published. Outputs that wake their readers may do it here, once per step (issue 21).
    /// Default: nothing.
    fn end_step(&mut self) {}
}

/// Counters of the service since start.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Chunks taken.
    pub chunks: u64,
    /// Bytes taken.
    pub bytes: u64,
    /// Attitude payloads published.
    pub attitude: u64,
    /// Ownship payloads published.
    pub ownship: u64,
    /// Traffic payloads published.
    pub traffic: u64,
    /// Integrity payloads published.
    pub integrity: u64,
    /// Alert payloads published.
    pub alerts: u64,
    /// Chunks of an unknown port index (a caller's mistake), ignored.
    pub unknown_port: u64,
    /// Processing errors (counted, the chunk's remaining output is lost).
    pub errors: u64,
}

/// One port's supervision state.
#[derive(Debug, Clone)]
struct PortState {
    port: Port,
    open: bool,
    /// A failure to open or a closure was reported.
    closed_seen: bool,
    opened_host_ns: Option<u64>,
    opens: u64,
    bytes: u64,
    frames: u64,
    last_message_host_ns: Option<u64>,
}

impl PortState {
    fn new(p: &Port) -> Self {
        Self {
            port: p.clone(),
            open: false,
            closed_seen: false,
            opened_host_ns: None,
            opens: 0,
            bytes: 0,
            frames: 0,
            last_message_host_ns: None,
        }
    }
}

/// The processing path of `vigil run` (see the module documentation).
pub struct Service {
    ports: Vec<PortState>,
    replay: Ingest,
    pipeline: Pipeline,
    monitor: Monitor,
    fused: Vec<Fused>,
    traffic: Box<TrafficPayload>,
    last_ownship: Option<Ownship>,
    /// Newest output time and the host time it was produced at (ns, ns).
    last_gps: Option<(i64, u64)>,
    silence_ns: u64,
    counters: Counters,
    // --- issue 20: what the service produced, kept for a recorder (`None`: not kept) ---
    tap: Option<Tap>,
}

/// The outputs kept for a recorder (issue 20): (host time, output).
#[derive(Debug, Default)]
struct Tap {
    /// Every decoded sample too (else only the devices' identity messages).
    samples: bool,
    /// Fused outputs, integrity reports and alerts too.
    fused: bool,
    events: Vec<(u64, Tapped)>,
}

/// Hands a port's link to the aligner (through `ingest`): its read interval, its configured or
/// recorded baud (issue 18 point 2), its adapter's latency timer when known (issue 18 point 1)
/// and, on a TT-Multi-RF, its stated transmit buffer. A port of a device a setting does not
/// apply to is left as it is. Used by the service and by `vigil replay --emit aligned`, so
/// both align a port alike.
pub(crate) fn link_settings_to(ingest: &mut Ingest, device: &str, protocol: &str, link: &PortLink) {
    let _ = ingest.set_read_interval(device, protocol, link.read_interval_ns);
    let _ = ingest.set_baud(device, protocol, link.baud);
    let _ = ingest.set_latency_timer(device, protocol, link.latency_timer_ns);
    let _ = ingest.set_output_buffer(device, protocol, link.output_buffer_bytes);
}

impl Service {
    /// A service over `ports` (index order = the port numbers of [`Service::handle_chunk`]).
    pub fn new(
        ports: &[Port],
        pipeline: PipelineConfig,
        monitor: MonitorParams,
        silence_s: f64,
    ) -> Result<Self> {
        let mut replay = Ingest::new();
        for p in ports {
            link_settings_to(&mut replay, &p.device, p.protocol.name(), &p.link());
        }
        Ok(Self {
            ports: ports.iter().map(PortState::new).collect(),
            replay,
            pipeline: Pipeline::new(pipeline, Box::new(Wmm))
                .map_err(|e| anyhow!("pipeline parameters: {e}"))?,
            monitor: Monitor::new(monitor),
            fused: Vec::new(),
            traffic: Box::default(),
            last_ownship: None,
            last_gps: None,
            silence_ns: (silence_s.max(0.0) * 1e9) as u64,
            counters: Counters::default(),
            tap: None,
        })
    }

    /// Counters so far.
    pub fn counters(&self) -> &Counters {
        &self.counters
    }

    /// Port `port` opened (`open`), or closed or failed to open, at host time `t_host_ns`. Every
    /// open after the first counts as a reconnect.
    pub fn handle_link(&mut self, port: usize, open: bool, t_host_ns: u64) {
        if let Some(p) = self.ports.get_mut(port) {
            if open && !p.open {
                p.opens += 1;
                p.opened_host_ns = Some(t_host_ns);
            }
            p.closed_seen |= !open;
            p.open = open;
        }
    }

    /// Takes one chunk read from port `port` at host monotonic time `t_host_ns` and publishes what
    /// it completes.
    pub fn handle_chunk(
        &mut self,
        port: usize,
        t_host_ns: u64,
        bytes: &[u8],
        out: &mut impl Outputs,
    ) {
        let Some(p) = self.ports.get_mut(port) else {
            self.counters.unknown_port += 1;
            return;
        };
        self.counters.chunks += 1;
        self.counters.bytes += bytes.len() as u64;
        p.bytes += bytes.len() as u64;
        let (pipeline, fused, tap) = (&mut self.pipeline, &mut self.fused, &mut self.tap);
        let mut sink = |s: &AlignedSample| -> Result<()> {
            tap_sample(tap, t_host_ns, s);
            pipeline.handle(s, fused);
            Ok(())
        };
        let fed = self.replay.feed(
            &p.port.device,
            p.port.protocol.name(),
            t_host_ns,
            bytes,
            &mut sink,
        );
        if fed.is_err() {
            self.counters.errors += 1;
        }
        if let Some(s) = self.replay.port_stats(&p.port.device)
            && s.frames_decoded > p.frames
        {
            p.frames = s.frames_decoded;
            p.last_message_host_ns = Some(t_host_ns);
        }
        self.publish_fused(t_host_ns, out);
    }

    /// How many more bytes complete port `port`'s next message, when the live reader may wait
    /// for it whole (issue 21; see [`Ingest::bytes_until_whole_message`]): only the VN-200's
    /// binary stream.
    /// Decision: not the host-timed ports (Watson, TT-Multi-RF, BAHRS navigation): a message
    /// of another length read late would carry the wait in its time.
    pub fn bytes_until_whole_message(&self, port: usize) -> Option<usize> {
        let p = self.ports.get(port)?;
        if p.port.protocol != vigil_drivers::protocol::Protocol::Vn200 {
            return None;
        }
        self.replay.bytes_until_whole_message(&p.port.device)
    }

    fn publish_fused(&mut self, t_host_ns: u64, out: &mut impl Outputs) {
        let mut fused = std::mem::take(&mut self.fused);
        for f in fused.drain(..) {
            // The newest output time (a check record is older than the prompts around it).
            if self.last_gps.is_none_or(|(t, _)| f.t_gps_ns() > t) {
                self.last_gps = Some((f.t_gps_ns(), t_host_ns));
            }
            match &f {
                // With prompt outputs on, the check records reach the bus inside them (their
                // verdicts), and the topic's times increase; without, each check is published.
                Fused::Attitude(_) if self.pipeline.config().prompt_attitude => {}
                Fused::Attitude(r) | Fused::Prompt(r) => {
                    let p = convert::attitude(r);
                    self.monitor.attitude(&p);
                    out.publish(&p);
                    self.counters.attitude += 1;
                }
                Fused::Ownship(o) => {
                    self.last_ownship = Some(o.ownship);
                    let p = convert::ownship(o);
                    self.monitor.ownship(&p);
                    out.publish(&p);
                    self.counters.ownship += 1;
                }
                Fused::Traffic(pic) => {
                    let own = self.last_ownship.filter(|o| o.t_gps_ns == pic.t_gps_ns);
                    out.traffic_picture(pic, own.as_ref());
                    convert::traffic(pic, own.as_ref(), &mut self.traffic);
                    self.monitor.traffic(&self.traffic);
                    out.publish(&*self.traffic);
                    self.counters.traffic += 1;
                }
            }
            // Tapped last, so the record moves into the tap instead of being cloned (a clone of
            // every check record was a tenth of a fused replay's time).
            if let Some(tap) = &mut self.tap
                && tap.fused
                && !matches!(f, Fused::Prompt(_))
            {
                tap.events.push((t_host_ns, Tapped::Fused(Box::new(f))));
            } else {
                self.pipeline.recycle(f);
            }
        }
        self.fused = fused;
        out.end_step();
    }

    /// Ends every stream (a recording's end: `vigil replay --publish`): releases what the
    /// aligner and the pipeline still hold and publishes it. Not for a live service, whose
    /// streams go on.
    // Used by the tests now, and by `vigil replay --publish` (issue 11) next.
    #[cfg_attr(not(test), allow(dead_code))]
    pub fn finish(&mut self, t_host_ns: u64, out: &mut impl Outputs) {
        let (pipeline, fused, tap) = (&mut self.pipeline, &mut self.fused, &mut self.tap);
        let mut sink = |s: &AlignedSample| -> Result<()> {
            tap_sample(tap, t_host_ns, s);
            pipeline.handle(s, fused);
            Ok(())
        };
        if self.replay.finish(&mut sink).is_err() {
            self.counters.errors += 1;
        }
        self.pipeline.finish(&mut self.fused);
        self.publish_fused(t_host_ns, out);
    }

    /// GPS time at host time `t_host_ns`: from the host-clock model when it has one, else
    /// extrapolated from the newest output; `None` before any.
    pub fn gps_time(&self, t_host_ns: u64) -> Option<i64> {
        let h = i64::try_from(t_host_ns).unwrap_or(i64::MAX);
        if let Some((t, _)) = self.replay.aligner().host_clock().to_gps(h) {
            return Some(t);
        }
        self.last_gps.map(|(t, at)| {
            t.saturating_add(i64::try_from(t_host_ns.saturating_sub(at)).unwrap_or(0))
        })
    }

    fn link_state(&self, p: &PortState, now: u64) -> u8 {
        if !p.open {
            // Not yet tried: unknown; failed to open or lost: disconnected (retried).
            return if p.closed_seen {
                integ::LINK_DISCONNECTED
            } else {
                integ::LINK_UNKNOWN
            };
        }
        let since = p.last_message_host_ns.or(p.opened_host_ns).unwrap_or(now);
        if now.saturating_sub(since) > self.silence_ns {
            integ::LINK_SILENT
        } else if p.last_message_host_ns.is_some() {
            integ::LINK_OK
        } else {
            integ::LINK_UNKNOWN
        }
    }

    /// Traffic records the pipeline dropped for impossible values (issue 24).
    fn ttmrf_invalid_values(&self) -> u64 {
        self.pipeline
            .activity()
            .iter()
            .find(|(d, _)| *d == vigil_fusion::time::aligner::Device::Ttmrf)
            .map_or(0, |(_, a)| a.invalid_values)
    }

    /// The integrity report at host time `t_host_ns`.
    pub fn integrity(&self, t_host_ns: u64) -> IntegrityPayload {
        let reports: Vec<PortReport<'_>> = self
            .ports
            .iter()
            .map(|p| PortReport {
                name: &p.port.device,
                protocol: p.port.protocol,
                link_state: self.link_state(p, t_host_ns),
                last_message_age_s: p
                    .last_message_host_ns
                    .map(|t| t_host_ns.saturating_sub(t) as f64 * 1e-9),
                bytes_received: p.bytes,
                stats: self.replay.port_stats(&p.port.device).map(|mut s| {
                    // Issue 24: records the fusion dropped at its entry (raw Mode S decoded
                    // there) count for the TT-Multi-RF port like the decoders' own.
                    if convert::device_code(p.port.protocol) == DEVICE_TTMRF {
                        s.invalid_values += self.ttmrf_invalid_values();
                    }
                    s
                }),
                reconnects: p.opens.saturating_sub(1),
            })
            .collect();
        let h = i64::try_from(t_host_ns).unwrap_or(i64::MAX);
        let clocks = self.replay.aligner().clock_report(h);
        let t_gps = self.gps_time(t_host_ns).unwrap_or(0);
        let leap = self
            .replay
            .aligner()
            .vn200()
            .gps_minus_utc(t_gps)
            .table_valid;
        let mut p = convert::integrity(&reports, &clocks, leap, t_gps);
        // Issue 18: the clocks' cross-checks.
        p.clock_disagreement = convert::device_bits(self.replay.aligner().clock_disagreements());
        // A serial line carrying its capacity: output queued, perhaps lost, in the device.
        p.line_full = convert::device_bits(self.replay.aligner().lines_full(h));
        // Issue 25 point 4: every BAHRS signal's health and the health cross-check.
        convert::health(&mut p, self.pipeline.health(), self.gps_time(t_host_ns));
        p
    }

    /// Publishes the integrity report, evaluates the monitor and publishes its alerts (call
    /// periodically, at host time `t_host_ns`).
    pub fn handle_timeout(&mut self, t_host_ns: u64, out: &mut impl Outputs) {
        let mut p = self.integrity(t_host_ns);
        self.monitor.integrity(&p);
        if let Some(t) = self.gps_time(t_host_ns) {
            let alerts = self.monitor.poll(t);
            for a in &alerts {
                out.publish::<AlertPayload>(a);
                self.counters.alerts += 1;
            }
            if let Some(tap) = &mut self.tap
                && tap.fused
                && !alerts.is_empty()
            {
                let active = active_set(self.monitor.active());
                tap.events.push((t_host_ns, Tapped::Alerts(alerts, active)));
            }
        }
        // Issue 25: the integrity report carries the active set after this poll's transitions
        // (a late subscriber reads what is raised or latched now from the latest report).
        self.monitor.fill_active(&mut p);
        out.publish(&p);
        out.end_step();
        self.counters.integrity += 1;
        if let Some(tap) = &mut self.tap
            && tap.fused
        {
            tap.events.push((t_host_ns, Tapped::Integrity(Box::new(p))));
        }
    }

    // --- issue 20: recording tap and timeline; ports added as a replay meets them ---

    /// Adds a port after the start (a replay meets its ports as their channels appear) and
    /// returns its index.
    pub fn add_port(&mut self, p: &Port) -> usize {
        link_settings_to(&mut self.replay, &p.device, p.protocol.name(), &p.link());
        self.ports.push(PortState::new(p));
        self.ports.len() - 1
    }

    /// The decoder counters of port `device` so far.
    pub fn port_stats(&self, device: &str) -> Option<vigil_drivers::DecodeStats> {
        self.replay.port_stats(device)
    }

    /// Keeps what the service produces for a recorder, from now on ([`Service::drain_tap`]):
    /// the devices' identity messages; with `fused` the fused outputs, integrity reports and
    /// alert transitions with the active set; with `samples` every decoded sample.
    pub fn set_tap(&mut self, fused: bool, samples: bool) {
        self.tap = Some(Tap {
            samples,
            fused,
            events: Vec::new(),
        });
    }

    /// What was kept since the last call, in order, with the host time it was produced at.
    pub fn drain_tap(&mut self) -> Vec<(u64, Tapped)> {
        self.tap
            .as_mut()
            .map(|t| std::mem::take(&mut t.events))
            .unwrap_or_default()
    }

    /// UTC (ns since the Unix epoch) minus host time at host time `t_host_ns`, from the host-clock
    /// model and the VN-200's GPS - UTC leap seconds (else the table); `None` while the model is
    /// unlocked.
    pub fn utc_offset_ns(&self, t_host_ns: u64) -> Option<i64> {
        let h = i64::try_from(t_host_ns).ok()?;
        let (t_gps, _) = self.replay.aligner().host_clock().to_gps(h)?;
        let leap = self.replay.aligner().vn200().gps_minus_utc(t_gps);
        let unix = vigil_fusion::time::gps::unix_ns_from_gps_ns(t_gps, leap.gps_minus_utc_s);
        Some(unix - h)
    }

    /// Whether the host clock has had any reference yet (a lock is then expected within
    /// seconds); see [`crate::recording::PRELOCK_HOLD_NS`].
    pub fn clock_references_seen(&self) -> bool {
        self.replay
            .aligner()
            .host_clock()
            .last_reference_host_ns()
            .is_some()
    }

    /// One line of status: per port its link, bytes, messages and bad frames (checksum failures,
    /// malformed, unsupported version); outputs; tracks.
    pub fn status_line(&self, t_host_ns: u64) -> String {
        let link = |s: u8| match s {
            integ::LINK_OK => "ok",
            integ::LINK_SILENT => "silent",
            integ::LINK_DISCONNECTED => "disconnected",
            _ => "unknown",
        };
        let ports: Vec<String> = self
            .ports
            .iter()
            .map(|p| {
                let bad = self.replay.port_stats(&p.port.device).map_or(0, |s| {
                    s.checksum_failures + s.malformed + s.unsupported_version
                });
                format!(
                    "{}={} {}B/{}msg/{}bad",
                    p.port.device,
                    link(self.link_state(p, t_host_ns)),
                    p.bytes,
                    p.frames,
                    bad
                )
            })
            .collect();
        let c = &self.counters;
        format!(
            "{} | attitude {} ownship {} traffic {} ({} tracks) alerts {} errors {}",
            ports.join(" "),
            c.attitude,
            c.ownship,
            c.traffic,
            self.pipeline.tracks(),
            c.alerts,
            c.errors
        )
    }
}

/// Keeps a sample in the tap when it is wanted (every sample, or a device identity).
fn tap_sample(tap: &mut Option<Tap>, t_host_ns: u64, s: &AlignedSample) {
    if let Some(t) = tap
        && (t.samples || identity(s).is_some())
    {
        t.events
            .push((t_host_ns, Tapped::Sample(Box::new(s.clone()))));
    }
}

/// Published payloads kept in memory: the [`Outputs`] of tests and of tools that look at a
/// service's payloads without a bus.
#[derive(Debug, Default)]
pub struct Collected {
    /// Attitude payloads.
    pub attitude: Vec<AttitudePayload>,
    /// Ownship payloads.
    pub ownship: Vec<OwnshipPayload>,
    /// Traffic payloads (count and the first targets only matter to tests; kept whole).
    pub traffic: Vec<TrafficPayload>,
    /// Integrity payloads.
    pub integrity: Vec<IntegrityPayload>,
    /// Alert payloads.
    pub alerts: Vec<AlertPayload>,
}

impl Outputs for Collected {
    fn publish<T: Payload>(&mut self, p: &T) {
        use std::any::Any;
        let any = p as &dyn Any;
        if let Some(p) = any.downcast_ref::<AttitudePayload>() {
            self.attitude.push(*p);
        } else if let Some(p) = any.downcast_ref::<OwnshipPayload>() {
            self.ownship.push(*p);
        } else if let Some(p) = any.downcast_ref::<TrafficPayload>() {
            self.traffic.push(p.clone());
        } else if let Some(p) = any.downcast_ref::<IntegrityPayload>() {
            self.integrity.push(*p);
        } else if let Some(p) = any.downcast_ref::<AlertPayload>() {
            self.alerts.push(*p);
        }
    }
}
