//! `vigil run --config FILE`: the live service on serial ports (issue 10, "bins/").
//!
//! One tokio task per port reads with tokio-serial and reopens the port with exponential
//! backoff when it fails to open or disappears (the [`Service`] reports it disconnected
//! meanwhile); a port with a configured device set-up runs it each time it opens
//! ([`super::setup`]). Every read chunk, stamped with the host monotonic time of the read, goes over one
//! mpsc channel to the single processing loop, so the processing order is the channel's order.
//! The loop records the raw chunks in MCAP when configured (flushed at least once a second),
//! feeds the [`Service`], publishes on the bus, ticks the integrity report and the monitor, logs
//! a one-line status periodically, and stops cleanly on SIGINT or SIGTERM (recording finalised).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use clap::Args;
use tokio::io::AsyncReadExt;
use tokio::sync::mpsc;
use tokio_serial::SerialPortBuilderExt;
use tracing::{error, info, warn};
use vigil_bus::clock::monotonic_ns;
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, IntegrityPayload, OwnshipPayload, Payload,
    Publisher, Topic, TrafficPayload,
};
use vigil_sim::record::RawRecorder;

use super::config::{Config, LinkSection, Port};
use super::{Outputs, Service};

/// Arguments of `vigil run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Configuration file (TOML; `vigil config --example` prints one).
    #[arg(long)]
    pub config: PathBuf,
    /// Stop after this many seconds (default: until SIGINT/SIGTERM).
    #[arg(long)]
    pub duration: Option<f64>,
}

/// What a port task reports.
enum PortEvent {
    /// The port opened.
    Opened(usize),
    /// A chunk read at host monotonic time (ns).
    Chunk(usize, u64, Vec<u8>),
    /// The port closed or failed (reason); it will be reopened.
    Closed(usize, String),
}

/// The bus publishers of every topic: the [`Outputs`] of `vigil run` (and of anything else that
/// publishes a [`Service`]'s payloads). Failed publications are counted and the first ten
/// logged.
pub struct BusOutputs {
    attitude: Publisher<AttitudePayload>,
    ownship: Publisher<OwnshipPayload>,
    traffic: Publisher<TrafficPayload>,
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
            traffic: bus.publisher()?,
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
                .map(|p| self.attitude.publish(p)),
            Topic::Ownship => any
                .downcast_ref::<OwnshipPayload>()
                .map(|p| self.ownship.publish(p)),
            // 140 KiB: copied once, into the loaned sample.
            Topic::Traffic => any
                .downcast_ref::<TrafficPayload>()
                .map(|p| self.traffic.publish_with(|s| *s = *p)),
            Topic::Integrity => any
                .downcast_ref::<IntegrityPayload>()
                .map(|p| self.integrity.publish(p)),
            Topic::Alerts => any
                .downcast_ref::<AlertPayload>()
                .map(|p| self.alerts.publish(p)),
        };
        if let Some(Err(e)) = r {
            self.errors += 1;
            // The first failures are logged; later ones only counted (status line).
            if self.errors <= 10 {
                warn!("publish {}: {e}", T::TOPIC);
            }
        }
    }
}

/// Runs `vigil run`.
pub fn run(args: &RunArgs) -> Result<()> {
    let _ = tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .try_init();
    if args.duration.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
        bail!("--duration must be a positive number of seconds");
    }
    let (config, ports) = Config::load(&args.config)?;
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    rt.block_on(live(config, ports, args.duration))
}

fn secs(s: f64) -> Duration {
    Duration::from_secs_f64(s.max(1e-3))
}

/// Reads one port forever, reopening it with exponential backoff.
async fn port_task(i: usize, port: Port, link: LinkSection, tx: mpsc::Sender<PortEvent>) {
    let initial = secs(link.reconnect_initial_s);
    let mut delay = initial;
    let mut buf = vec![0u8; 4096];
    loop {
        let path = port.path.to_string_lossy().into_owned();
        match tokio_serial::new(&path, port.baud).open_native_async() {
            Ok(mut serial) => {
                delay = initial;
                if tx.send(PortEvent::Opened(i)).await.is_err() {
                    return;
                }
                if let Some(setup) = port.setup {
                    // What the device sends during the session goes to the service afterwards,
                    // each read with its own receive time.
                    let mut during: Vec<(u64, Vec<u8>)> = Vec::new();
                    let mut forward = |b: Vec<u8>| during.push((monotonic_ns(), b));
                    super::setup::run(&port.device, setup, &mut serial, &mut forward).await;
                    for (t, b) in during {
                        if tx.send(PortEvent::Chunk(i, t, b)).await.is_err() {
                            return;
                        }
                    }
                }
                let reason = loop {
                    match serial.read(&mut buf).await {
                        Ok(0) => break "end of file".to_string(),
                        Ok(n) => {
                            let t = monotonic_ns();
                            let chunk = PortEvent::Chunk(i, t, buf[..n].to_vec());
                            if tx.send(chunk).await.is_err() {
                                return;
                            }
                        }
                        Err(e) => break e.to_string(),
                    }
                };
                if tx.send(PortEvent::Closed(i, reason)).await.is_err() {
                    return;
                }
            }
            Err(e) => {
                if tx
                    .send(PortEvent::Closed(i, format!("cannot open: {e}")))
                    .await
                    .is_err()
                {
                    return;
                }
            }
        }
        tokio::time::sleep(delay).await;
        delay = (delay * 2).min(secs(link.reconnect_max_s));
    }
}

type Recorder = RawRecorder<BufWriter<File>>;

fn open_recorder(path: &PathBuf, ports: &[Port]) -> Result<Recorder> {
    let out = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let specs: Vec<(&str, &str, u32)> = ports
        .iter()
        .map(|p| (p.device.as_str(), p.protocol.name(), p.baud))
        .collect();
    let mut rec = RawRecorder::new(BufWriter::new(out), &specs)?;
    rec.write_metadata(
        "vigil.run",
        BTreeMap::from([
            (
                "ports".to_string(),
                specs.iter().map(|s| s.0).collect::<Vec<_>>().join(","),
            ),
            (
                "paths".to_string(),
                ports
                    .iter()
                    .map(|p| p.path.to_string_lossy().into_owned())
                    .collect::<Vec<_>>()
                    .join(","),
            ),
        ]),
    )?;
    Ok(rec)
}

async fn live(config: Config, ports: Vec<Port>, duration: Option<f64>) -> Result<()> {
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
    let mut out = super::live_view::Tee(
        BusOutputs::new(&bus).context("creating the publishers")?,
        super::live_view::start(&config.live_view),
    );
    let mut recorder = match &config.record.path {
        Some(p) => Some(open_recorder(p, &ports)?),
        None => None,
    };
    let mut service = Service::new(
        &ports,
        config.pipeline.pipeline_config(),
        config.monitor,
        config.link.silence_s,
    )?;
    let (tx, mut rx) = mpsc::channel::<PortEvent>(1024);
    let mut tasks = Vec::new();
    for (i, p) in ports.iter().enumerate() {
        info!(
            "port {}: {} at {} baud ({})",
            p.device,
            p.path.display(),
            p.baud,
            p.protocol.name()
        );
        tasks.push(tokio::spawn(port_task(
            i,
            p.clone(),
            config.link,
            tx.clone(),
        )));
    }
    drop(tx);
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
    // Closures are logged once per port until it opens again.
    let mut closed_logged = vec![false; ports.len()];
    let mut record_errors = 0u64;
    let why = loop {
        tokio::select! {
            ev = rx.recv() => match ev {
                Some(PortEvent::Chunk(i, t, bytes)) => {
                    if let Some(rec) = &mut recorder
                        && let Err(e) = rec.write_raw(i as u16, t, &bytes)
                    {
                        record_errors += 1;
                        error!("recording stopped: {e}");
                        recorder = None;
                    }
                    service.on_chunk(i, t, &bytes, &mut out);
                }
                Some(PortEvent::Opened(i)) => {
                    service.on_link(i, true, monotonic_ns());
                    closed_logged[i] = false;
                    info!("port {}: open", ports[i].device);
                }
                Some(PortEvent::Closed(i, reason)) => {
                    service.on_link(i, false, monotonic_ns());
                    if !closed_logged[i] {
                        warn!("port {}: {reason}; retrying with backoff", ports[i].device);
                        closed_logged[i] = true;
                    }
                }
                None => break "every port task ended",
            },
            _ = tick.tick() => {
                service.tick(monotonic_ns(), &mut out);
                if let Some(r) = bus.cleanup_if_due()
                    && r.cleaned > 0
                {
                    info!("bus: cleaned {} dead node(s)", r.cleaned);
                }
            }
            _ = flush.tick() => {
                if let Some(rec) = &mut recorder
                    && let Err(e) = rec.flush()
                {
                    record_errors += 1;
                    error!("recording stopped: {e}");
                    recorder = None;
                }
            }
            _ = status.tick() => {
                info!("status: {} | publish errors {}", service.status_line(monotonic_ns()), out.0.errors());
            }
            _ = &mut ctrl_c => break "SIGINT",
            _ = sigterm.recv() => break "SIGTERM",
            _ = &mut until => break "end of --duration",
        }
    };
    info!("stopping ({why})");
    for t in &tasks {
        t.abort();
    }
    // Chunks already read are processed and recorded before the recording is finalised.
    while let Ok(ev) = rx.try_recv() {
        if let PortEvent::Chunk(i, t, bytes) = ev {
            if let Some(rec) = &mut recorder
                && rec.write_raw(i as u16, t, &bytes).is_err()
            {
                record_errors += 1;
                recorder = None;
            }
            service.on_chunk(i, t, &bytes, &mut out);
        }
    }
    if let Some(rec) = recorder {
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
    let c = service.counters();
    info!(
        "final status: {} | {} chunks, {} bytes | publish errors {} | recording errors \
         {record_errors}",
        service.status_line(monotonic_ns()),
        c.chunks,
        c.bytes,
        out.0.errors()
    );
    Ok(())
}

/// Arguments of `vigil config`.
#[derive(Debug, Args)]
pub struct ConfigArgs {
    /// Print a commented example configuration (every key at its default).
    #[arg(long, conflicts_with = "check")]
    pub example: bool,
    /// Validate a configuration file and print its ports.
    #[arg(long, value_name = "FILE")]
    pub check: Option<PathBuf>,
}

/// Runs `vigil config`.
pub fn config(args: &ConfigArgs) -> Result<()> {
    if args.example {
        print!("{}", super::config::example());
        return Ok(());
    }
    let Some(path) = &args.check else {
        bail!("give --example or --check FILE");
    };
    let (_, ports) = Config::load(path)?;
    for p in ports {
        println!(
            "{} {} {} {}",
            p.device,
            p.path.display(),
            p.baud,
            p.protocol.name()
        );
    }
    Ok(())
}
