//! `vigil record`: the serial loop of `vigil run` ([`crate::runtime::serial`]) with processing
//! off. Every read goes into an MCAP file's raw channel of its port (log time = host monotonic
//! receive time), nothing is decoded or published, so a recording is exactly what the ports
//! delivered. The open chunk is flushed every second, so a killed recorder leaves a file readable
//! up to its last flush; SIGINT, SIGTERM or the end of the duration finish it cleanly.
//!
//! Decision: a port that fails to open or disappears is reopened with backoff, as in `vigil run`
//! (an earlier recorder ended the port for the rest of the run); the failure is logged once until
//! the port opens again.

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::rc::Rc;
use std::time::Duration;

use anyhow::{Context, Result, anyhow};
use tracing::{error, info, warn};
use vigil_record::RawRecorder;

use crate::config::LinkSection;
use crate::runtime::serial::{PortSink, SerialPort, port_task};

/// Name of the recording's metadata record (ports and their paths).
pub const METADATA_RECORD: &str = "vigil.record";

/// A port to record: how to read it, and the wire protocol named in its channel's metadata (may
/// be empty: `vigil replay` then picks the decoder by the device name).
#[derive(Debug, Clone)]
pub struct RecordPort {
    /// The port.
    pub serial: SerialPort,
    /// Wire protocol name, or empty.
    pub protocol: String,
}

/// What a recording wrote per port, bytes (by device name).
pub type RecordSummary = BTreeMap<String, u64>;

struct RecordCtx {
    devices: Vec<String>,
    recorder: Option<RawRecorder<BufWriter<File>>>,
    bytes: Vec<u64>,
    closed_logged: Vec<bool>,
    epoch: tokio::time::Instant,
    error: Option<String>,
}

impl RecordCtx {
    /// A write error stops the recording (logged once; reported at the end).
    fn written(&mut self, r: Result<(), mcap::McapError>) {
        if let Err(e) = r {
            error!("recording stopped: {e}");
            self.error.get_or_insert(e.to_string());
            self.recorder = None;
        }
    }
}

impl PortSink for RecordCtx {
    fn chunk(&mut self, port: usize, t_host_ns: u64, bytes: &[u8]) {
        self.bytes[port] += bytes.len() as u64;
        if let Some(rec) = &mut self.recorder {
            let r = rec.write_raw(port as u16, t_host_ns, bytes);
            self.written(r);
        }
    }

    fn opened(&mut self, port: usize) {
        self.closed_logged[port] = false;
        info!("port {}: open", self.devices[port]);
    }

    fn closed(&mut self, port: usize, reason: &str) {
        if !self.closed_logged[port] {
            warn!(
                "port {}: {reason}; retrying with backoff",
                self.devices[port]
            );
            self.closed_logged[port] = true;
        }
    }

    fn epoch(&self) -> tokio::time::Instant {
        self.epoch
    }
}

/// Records `ports` into `out` until `duration`, s, has passed (`None`: until SIGINT/SIGTERM),
/// reopening failed ports as `link` says; returns the bytes written per port.
pub fn record(
    ports: &[RecordPort],
    out: &Path,
    link: LinkSection,
    duration: Option<f64>,
) -> Result<RecordSummary> {
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build_local(tokio::runtime::LocalOptions::default())?;
    rt.block_on(run(ports, out, link, duration))
}

async fn run(
    ports: &[RecordPort],
    out: &Path,
    link: LinkSection,
    duration: Option<f64>,
) -> Result<RecordSummary> {
    let file = File::create(out).with_context(|| format!("cannot create {}", out.display()))?;
    let specs: Vec<(&str, &str, u32)> = ports
        .iter()
        .map(|p| (p.serial.device.as_str(), p.protocol.as_str(), p.serial.baud))
        .collect();
    let mut rec = RawRecorder::new(BufWriter::new(file), &specs)?;
    let join = |f: fn(&RecordPort) -> String| ports.iter().map(f).collect::<Vec<_>>().join(",");
    rec.write_metadata(
        METADATA_RECORD,
        BTreeMap::from([
            ("ports".to_string(), join(|p| p.serial.device.clone())),
            (
                "paths".to_string(),
                join(|p| p.serial.path.to_string_lossy().into_owned()),
            ),
        ]),
    )?;
    let ctx = Rc::new(RefCell::new(RecordCtx {
        devices: ports.iter().map(|p| p.serial.device.clone()).collect(),
        recorder: Some(rec),
        bytes: vec![0; ports.len()],
        closed_logged: vec![false; ports.len()],
        epoch: tokio::time::Instant::now(),
        error: None,
    }));
    let tasks: Vec<_> = ports
        .iter()
        .enumerate()
        .map(|(i, p)| tokio::task::spawn_local(port_task(i, p.serial.clone(), link, ctx.clone())))
        .collect();
    let mut flush = tokio::time::interval(Duration::from_secs(1));
    flush.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    let mut sigterm = tokio::signal::unix::signal(tokio::signal::unix::SignalKind::terminate())
        .context("installing the SIGTERM handler")?;
    let ctrl_c = tokio::signal::ctrl_c();
    tokio::pin!(ctrl_c);
    let until = async {
        match duration {
            Some(d) => tokio::time::sleep(Duration::from_secs_f64(d)).await,
            None => std::future::pending().await,
        }
    };
    tokio::pin!(until);
    let why = loop {
        tokio::select! {
            _ = flush.tick() => {
                let mut c = ctx.borrow_mut();
                if let Some(r) = c.recorder.as_mut().map(RawRecorder::flush) {
                    c.written(r);
                }
            }
            _ = &mut ctrl_c => break "SIGINT",
            _ = sigterm.recv() => break "SIGTERM",
            _ = &mut until => break "end of --duration",
        }
    };
    info!("stopping ({why})");
    // Paced ports hold up to one interval of input unread: one more interval drains it.
    if let Some(longest) = ports.iter().map(|p| p.serial.read_interval_ns).max()
        && longest > 0
    {
        tokio::time::sleep(Duration::from_nanos(longest) + Duration::from_millis(1)).await;
    }
    for t in &tasks {
        t.abort();
    }
    let mut c = ctx.borrow_mut();
    if let Some(e) = c.error.take() {
        return Err(anyhow!("writing {}: {e}", out.display()));
    }
    let rec = c.recorder.take().context("recorder gone")?;
    let mut w = rec
        .finish()
        .map_err(|e| anyhow!("writing {}: {e}", out.display()))?;
    w.flush()?;
    Ok(c.devices
        .iter()
        .cloned()
        .zip(c.bytes.iter().copied())
        .collect())
}
