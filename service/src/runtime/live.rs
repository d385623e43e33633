//! The live runtime of `vigil run --config FILE`: the service on serial ports (issue 10).
//!
//! One task per port opens it with tokio-serial, runs its configured device set-up
//! ([`crate::runtime::setup`]) and then reads it ([`crate::runtime::reader`]: on arrival, or paced for ports that
//! allow it), reopening it with exponential backoff when it fails to open or disappears (the
//! [`Service`] reports it disconnected meanwhile). Everything runs on one thread: each read
//! chunk, stamped with the host monotonic time of the read, goes straight from its port task into
//! the shared `Ctx` (recorded in MCAP when configured, flushed at least once a second, then fed
//! to the [`Service`]) with no queue or task switch between the read and the publication. The
//! main loop ticks the integrity report and the monitor, logs a one-line status periodically,
//! and stops cleanly on SIGINT or SIGTERM (recording finalised).

use std::cell::RefCell;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::rc::Rc;
use std::time::Duration;

use anyhow::{Context, Result};
use tracing::{error, info, warn};
use vigil_bus::clock::monotonic_ns;
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, IntegrityPayload, OwnshipPayload, Payload,
    Publisher, Topic, TrafficPayload, TrafficPublisher,
};
use vigil_fusion::time::ttmrf::TtAlignerConfig;
use vigil_record::RawRecorder;

use crate::recording::{METADATA_RUN, RichRecorder, run_metadata};

use crate::config::{Config, Port};
use crate::outputs::gdl90_out::Gdl90Udp;
use crate::outputs::live_view::{Tee, View};
use crate::outputs::mavlink_out::MavlinkUdp;
use crate::runtime::serial::{PortSink, SerialPort, port_task, secs};
use crate::{Outputs, Service};

/// The bus publishers of every topic: the [`Outputs`] of `vigil run` (and of anything else that
/// publishes a [`Service`]'s payloads). Failed publications are counted and the first ten
/// logged. Samples are sent as they are published and their subscribers woken once per
/// processing step ([`Outputs::end_step`]; issue 21): one event per topic that published.
pub struct BusOutputs {
    attitude: Publisher<AttitudePayload>,
    ownship: Publisher<OwnshipPayload>,
    traffic: TrafficPublisher,
    integrity: Publisher<IntegrityPayload>,
    alerts: Publisher<AlertPayload>,
    errors: u64,
}

impl BusOutputs {
    /// A publisher per topic on `bus`.
    pub fn new(bus: &Bus) -> Result<Self> {
        Ok(Self {
            attitude: bus.publisher()?,
            ownship: bus.publisher()?,
            traffic: bus.traffic_publisher()?,
            integrity: bus.publisher()?,
            alerts: bus.publisher()?,
            errors: 0,
        })
    }

    /// Publications that failed so far.
    pub fn errors(&self) -> u64 {
        self.errors
    }
}

impl Outputs for BusOutputs {
    fn publish<T: Payload>(&mut self, p: &T) {
        use std::any::Any;
        let any = p as &dyn Any;
        let r = match T::TOPIC {
            Topic::Attitude => any
                .downcast_ref::<AttitudePayload>()
                .map(|p| self.attitude.publish_deferred(p)),
            Topic::Ownship => any
                .downcast_ref::<OwnshipPayload>()
                .map(|p| self.ownship.publish_deferred(p)),
            // The targets are copied once, into a loaned slice of their count.
            Topic::Traffic => any
                .downcast_ref::<TrafficPayload>()
                .map(|p| self.traffic.publish_deferred(p)),
            Topic::Integrity => any
                .downcast_ref::<IntegrityPayload>()
                .map(|p| self.integrity.publish_deferred(p)),
            Topic::Alerts => any
                .downcast_ref::<AlertPayload>()
                .map(|p| self.alerts.publish_deferred(p)),
        };
        if let Some(Err(e)) = r {
            self.errors += 1;
            // The first failures are logged; later ones only counted (status line).
            if self.errors <= 10 {
                warn!("publish {}: {e}", T::TOPIC);
            }
        }
    }

    fn end_step(&mut self) {
        self.attitude.notify_pending();
        self.ownship.notify_pending();
        self.traffic.notify_pending();
        self.integrity.notify_pending();
        self.alerts.notify_pending();
    }
}

/// Runs the service on the configured serial ports until `duration`, s, has passed (`None`:
/// until SIGINT/SIGTERM), on this thread.
pub fn run(config: Config, ports: Vec<Port>, duration: Option<f64>) -> Result<()> {
    // Port tasks share the service on this one thread (see the module documentation): a local
    // runtime, whose `spawn_local` tasks are scheduled like any task of a current-thread
    // runtime. (A `LocalSet` would cost an eventfd write per read: a task woken by the I/O driver
    // is queued remotely and the runtime unparked.)
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build_local(tokio::runtime::LocalOptions::default())?;
    rt.block_on(live(config, ports, duration))
}

/// Where `vigil run` sends its outputs: the bus first, then the optional live view and the
/// optional MAVLink and GDL90 traffic outputs (off the safety path).
type LiveOutputs = Tee<BusOutputs, Tee<Option<View>, Tee<Option<MavlinkUdp>, Option<Gdl90Udp>>>>;

/// Everything the port tasks and the main loop share (one thread; borrowed only between
/// awaits).
struct Ctx {
    ports: Vec<Port>,
    service: Service,
    out: LiveOutputs,
    recorder: Option<Recorder>,
    record_errors: u64,
    /// Closures are logged once per port until it opens again.
    closed_logged: Vec<bool>,
    /// Origin of the paced ports' common drain grid.
    epoch: tokio::time::Instant,
}

impl Ctx {
    /// A chunk of port `i` read at host time `t` (ns): processed and published, then recorded
    /// with what it produced.
    fn chunk(&mut self, i: usize, t: u64, bytes: &[u8]) {
        self.service.handle_chunk(i, t, bytes, &mut self.out);
        if let Some(rec) = &mut self.recorder {
            let r = rec
                .set_clock(
                    t,
                    self.service.utc_offset_ns(t),
                    self.service.clock_references_seen(),
                )
                .and_then(|()| rec.raw(i as u16, t, bytes));
            self.recorded(r);
            self.record_tap();
        }
    }

    /// Records what the service produced since the last call (issue 20).
    fn record_tap(&mut self) {
        let tapped = self.service.drain_tap();
        if let Some(rec) = &mut self.recorder {
            let r = tapped.iter().try_for_each(|(t, x)| rec.tapped(*t, x));
            self.recorded(r);
        }
    }

    /// A recording error stops the recording (logged once), never the service.
    fn recorded(&mut self, r: Result<()>) {
        if let Err(e) = r {
            self.record_errors += 1;
            error!("recording stopped: {e}");
            self.recorder = None;
        }
    }

    fn flush(&mut self) {
        self.record_tap();
        if let Some(rec) = &mut self.recorder {
            let r = rec.flush();
            self.recorded(r);
        }
    }
}

impl PortSink for Ctx {
    fn chunk(&mut self, i: usize, t: u64, bytes: &[u8]) {
        Ctx::chunk(self, i, t, bytes);
    }

    fn epoch(&self) -> tokio::time::Instant {
        self.epoch
    }

    fn bytes_until_whole_message(&self, i: usize) -> Option<usize> {
        self.service.bytes_until_whole_message(i)
    }

    fn opened(&mut self, i: usize) {
        self.service.handle_link(i, true, monotonic_ns());
        self.closed_logged[i] = false;
        info!("port {}: open", self.ports[i].device);
    }

    fn closed(&mut self, i: usize, reason: &str) {
        self.service.handle_link(i, false, monotonic_ns());
        if !self.closed_logged[i] {
            warn!(
                "port {}: {reason}; retrying with backoff",
                self.ports[i].device
            );
            self.closed_logged[i] = true;
        }
    }
}

type Recorder = RichRecorder<BufWriter<File>>;

fn open_recorder(config: &Config, path: &PathBuf, ports: &[Port]) -> Result<Recorder> {
    let out = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let raw = RawRecorder::new(BufWriter::new(out), &[])?;
    let mut rec = RichRecorder::new(raw, config.record.channels)?;
    // Each port's timing as the aligner models it (baud, read interval, adapter timer, stated
    // transmit buffer), so a replay aligns as this run did.
    for p in ports {
        rec.add_port(&p.device, p.protocol.name(), &p.link())?;
    }
    let toml = toml::to_string(config).context("writing the configuration as TOML")?;
    let mut meta = run_metadata("vigil run", &toml);
    meta.extend([
        (
            "ports".to_string(),
            ports
                .iter()
                .map(|p| p.device.as_str())
                .collect::<Vec<_>>()
                .join(","),
        ),
        (
            "paths".to_string(),
            ports
                .iter()
                .map(|p| p.path.to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join(","),
        ),
    ]);
    rec.write_metadata(METADATA_RUN, meta)?;
    Ok(rec)
}

/// The latency timer of the FTDI adapter behind serial port `dev` (a `/dev/ttyUSBn` path, or a
/// symlink to one such as `/dev/serial/by-id/...`), ns, from sysfs under `sys_root` (`/sys`):
/// `bus/usb-serial/devices/ttyUSBn/latency_timer` (ms), which only the FTDI driver provides.
/// `None` for any other port (a native UART, a USB CDC device, a pseudo-terminal).
pub fn ftdi_latency_timer_ns(sys_root: &Path, dev: &Path) -> Option<u64> {
    let real = std::fs::canonicalize(dev).unwrap_or_else(|_| dev.to_path_buf());
    let name = real.file_name()?.to_str()?;
    let file = sys_root
        .join("bus/usb-serial/devices")
        .join(name)
        .join("latency_timer");
    let ms: u64 = std::fs::read_to_string(file).ok()?.trim().parse().ok()?;
    Some(ms * 1_000_000)
}

async fn live(config: Config, mut ports: Vec<Port>, duration: Option<f64>) -> Result<()> {
    // Issue 18 point 1: a port whose adapter timer is not configured takes the FTDI driver's,
    // when it is one; the aligner then widens that port's host-timed sigmas by it.
    for p in ports.iter_mut().filter(|p| p.latency_timer_ns.is_none()) {
        p.latency_timer_ns = ftdi_latency_timer_ns(Path::new("/sys"), &p.path);
        if let Some(ns) = p.latency_timer_ns {
            info!(
                "port {}: FTDI adapter, latency timer {} ms (sysfs); its host-timed samples' \
                 sigma covers it (set [[ports]] latency_timer_ms to override)",
                p.device,
                ns / 1_000_000
            );
        }
    }
    // A stated transmit buffer changes what a full line's samples are: said once at start.
    for p in &ports {
        let tt = TtAlignerConfig {
            output_buffer_bytes: p.output_buffer_bytes,
            ..TtAlignerConfig::default()
        };
        if let (Some(bytes), Some(wait_ns)) = (p.output_buffer_bytes, tt.buffer_wait_ns(p.baud)) {
            let (ms, limit_ms) = (wait_ns as f64 * 1e-6, tt.queue_limit_ns as f64 * 1e-6);
            // The aligner's test: the buffer bounds the wait when its line time is within the
            // limit (`Aligner::note_tt_line`).
            let what = if wait_ns <= tt.queue_limit_ns {
                "while its line is full, its samples are placed with up to that wait in their \
                 sigma"
            } else {
                "beyond the queue limit, so it bounds nothing: a line full for longer than the \
                 limit is not aligned without a time of its own"
            };
            info!(
                "port {}: transmit buffer stated as {bytes} bytes ({ms:.1} ms at {} baud, \
                 limit {limit_ms:.0} ms): {what}",
                p.device, p.baud
            );
        }
    }
    // Held (when configured) until the service ends.
    let _wakeup_latency = config.realtime.hold();
    let mut bus = Bus::new(&BusConfig {
        prefix: config.bus.prefix.clone(),
        node_name: config.bus.node_name.clone(),
        handle_signals: false,
        cleanup_period_s: config.bus.cleanup_period_s,
        lossless_wait_s: None,
    })
    .context("connecting to the bus")?;
    // The bus, and the optional live view (off the safety path; see `live_view`).
    // The bus first; then the optional live view and MAVLink output (off the safety path: they
    // never delay the bus, and a failure of theirs is logged, not fatal).
    let mavlink = config.outputs.mavlink.enabled().then(|| {
        let m = &config.outputs.mavlink;
        match MavlinkUdp::open(m) {
            Ok(o) => {
                info!(
                    "MAVLink traffic output to {} (system {}, component {})",
                    m.address, m.system_id, m.component_id
                );
                Some(o)
            }
            Err(e) => {
                tracing::warn!("MAVLink output to {}: {e}; going on without it", m.address);
                None
            }
        }
    });
    let gdl90 = config.outputs.gdl90.enabled().then(|| {
        let g = &config.outputs.gdl90;
        match Gdl90Udp::open(g) {
            Ok(o) => {
                info!("GDL90 traffic output to {}", g.address);
                Some(o)
            }
            Err(e) => {
                tracing::warn!("GDL90 output to {}: {e}; going on without it", g.address);
                None
            }
        }
    });
    let out = Tee(
        BusOutputs::new(&bus).context("creating the publishers")?,
        Tee(
            crate::outputs::live_view::start(&config.live_view),
            Tee(mavlink.flatten(), gdl90.flatten()),
        ),
    );
    let recorder = match &config.record.path {
        Some(p) => Some(open_recorder(&config, p, &ports)?),
        None => None,
    };
    let mut service = Service::new(
        &ports,
        config.pipeline.pipeline_config(),
        config.monitor,
        config.link.silence_s,
    )?;
    if recorder.is_some() {
        let set = config.record.channels;
        service.set_tap(set.fused(), set.decoded());
    }
    let ctx = Rc::new(RefCell::new(Ctx {
        ports: ports.clone(),
        service,
        out,
        recorder,
        record_errors: 0,
        closed_logged: vec![false; ports.len()],
        epoch: tokio::time::Instant::now(),
    }));
    let mut tasks = Vec::new();
    for (i, p) in ports.iter().enumerate() {
        let read = if p.read_interval_ns > 0 {
            format!("read every {} ms", p.read_interval_ns as f64 * 1e-6)
        } else {
            "read on arrival".to_string()
        };
        info!(
            "port {}: {} at {} baud ({}, {read})",
            p.device,
            p.path.display(),
            p.baud,
            p.protocol.name()
        );
        tasks.push(tokio::task::spawn_local(port_task(
            i,
            SerialPort::from(p),
            config.link,
            ctx.clone(),
        )));
    }
    let mut tick = tokio::time::interval(secs(config.status.integrity_period_s));
    let mut flush = tokio::time::interval(secs(config.record.flush_period_s));
    let mut status = tokio::time::interval(secs(config.status.period_s));
    for t in [&mut tick, &mut flush, &mut status] {
        t.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    }
    let mut sigterm = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())
        .context("installing the SIGTERM handler")?;
    let ctrl_c = tokio::signal::ctrl_c();
    tokio::pin!(ctrl_c);
    let deadline = duration.map(|d| tokio::time::Instant::now() + Duration::from_secs_f64(d));
    let until = async {
        match deadline {
            Some(d) => tokio::time::sleep_until(d).await,
            None => std::future::pending().await,
        }
    };
    tokio::pin!(until);
    let why = loop {
        tokio::select! {
            _ = tick.tick() => {
                let mut c = ctx.borrow_mut();
                let c = &mut *c;
                c.service.handle_timeout(monotonic_ns(), &mut c.out);
                c.record_tap();
                if let Some(r) = bus.cleanup_if_due()
                    && r.cleaned > 0
                {
                    info!("bus: cleaned {} dead node(s)", r.cleaned);
                }
            }
            _ = flush.tick() => ctx.borrow_mut().flush(),
            _ = status.tick() => {
                let c = ctx.borrow();
                info!("status: {} | publish errors {}", c.service.status_line(monotonic_ns()), c.out.0.errors());
            }
            _ = &mut ctrl_c => break "SIGINT",
            _ = sigterm.recv() => break "SIGTERM",
            _ = &mut until => break "end of --duration",
        }
    };
    info!("stopping ({why})");
    // Every chunk read so far has been processed and recorded (no queue between the two). The
    // paced ports hold up to one interval of input unread: one more interval lets each drain
    // what arrived before the stop.
    if let Some(longest) = ports.iter().map(|p| p.read_interval_ns).max()
        && longest > 0
    {
        tokio::time::sleep(Duration::from_nanos(longest) + Duration::from_millis(1)).await;
    }
    for t in &tasks {
        t.abort();
    }
    let mut c = ctx.borrow_mut();
    c.record_tap();
    if let Some(rec) = c.recorder.take() {
        let path = config
            .record
            .path
            .as_deref()
            .unwrap_or(std::path::Path::new(""));
        let mut w = rec
            .finish()
            .with_context(|| format!("finishing {}", path.display()))?;
        w.flush()?;
        info!("recording finalised: {}", path.display());
    }
    let counters = *c.service.counters();
    info!(
        "final status: {} | {} chunks, {} bytes | publish errors {} | recording errors {}",
        c.service.status_line(monotonic_ns()),
        counters.chunks,
        counters.bytes,
        c.out.0.errors(),
        c.record_errors
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The FTDI driver's sysfs file is read through the device name (and through a by-id
    /// symlink); a port without it (any other driver) has no timer.
    #[test]
    fn ftdi_latency_timer_from_sysfs() {
        let root = std::env::temp_dir().join(format!("vigil-sysfs-{}", std::process::id()));
        let dev_dir = root.join("bus/usb-serial/devices/ttyUSB7");
        std::fs::create_dir_all(&dev_dir).unwrap();
        std::fs::write(dev_dir.join("latency_timer"), "16\n").unwrap();
        assert_eq!(
            ftdi_latency_timer_ns(&root, Path::new("/dev/ttyUSB7")),
            Some(16_000_000)
        );
        assert_eq!(
            ftdi_latency_timer_ns(&root, Path::new("/dev/ttyACM0")),
            None
        );
        assert_eq!(ftdi_latency_timer_ns(&root, Path::new("/dev/ttyS0")), None);
        let _ = std::fs::remove_dir_all(&root);
    }
}
