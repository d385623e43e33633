//! `vigil record --config FILE --out FILE.mcap`: record live serial ports into an MCAP file with the
//! same layout as the simulator's (one `/<device>/raw` channel per port, log time = host monotonic
//! receive time of each read, ns), so `vigil replay` reads both alike.
//!
//! Ctrl-C (SIGINT) ends the recording cleanly (summary written). The open chunk is flushed to the
//! file every second, so a killed recorder leaves a file readable up to its last flush.
//!
//! Configuration (TOML):
//! ```toml
//! [[ports]]
//! device = "bahrs"          # channel name
//! path = "/dev/ttyUSB0"
//! baud = 115200
//! protocol = "bahrs-2.0"    # optional: selects the decoder in `vigil replay` (else the device
//!                           # name does: "bahrs", "watson")
//! ```

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use serde::Deserialize;
use tokio::io::AsyncReadExt;
use tokio::sync::mpsc;
use tokio_serial::SerialPortBuilderExt;
use vigil_record::RawRecorder;

/// Arguments of `vigil record`.
#[derive(Debug, Args)]
pub struct RecordArgs {
    /// Port configuration (TOML, `[[ports]]` with device, path, baud).
    #[arg(long)]
    pub config: PathBuf,
    /// Output MCAP file.
    #[arg(long)]
    pub out: PathBuf,
    /// Stop after this many seconds (default: until Ctrl-C).
    #[arg(long)]
    pub duration: Option<f64>,
}

/// The recording configuration.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct Config {
    ports: Vec<PortConfig>,
}

/// One port to record.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct PortConfig {
    device: String,
    path: String,
    baud: u32,
    #[serde(default)]
    protocol: String,
}

/// Host monotonic time, ns (CLOCK_MONOTONIC, the timebase of every recording).
#[cfg(target_os = "linux")]
fn monotonic_ns() -> u64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::Monotonic);
    t.tv_sec as u64 * 1_000_000_000 + t.tv_nsec as u64
}

#[cfg(not(target_os = "linux"))]
fn monotonic_ns() -> u64 {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_nanos() as u64
}

fn load(path: &PathBuf) -> Result<Config> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let c: Config = toml::from_str(&text).with_context(|| format!("in {}", path.display()))?;
    if c.ports.is_empty() {
        bail!("{}: ports: at least one port is needed", path.display());
    }
    for (i, p) in c.ports.iter().enumerate() {
        if p.device.is_empty()
            || !p
                .device
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_')
        {
            bail!(
                "{}: ports[{i}].device: letters, digits, '-' or '_'",
                path.display()
            );
        }
        if c.ports[..i].iter().any(|q| q.device == p.device) {
            bail!(
                "{}: ports[{i}].device: {:?} appears twice",
                path.display(),
                p.device
            );
        }
    }
    Ok(c)
}

/// Runs `vigil record`.
pub fn run(args: &RecordArgs) -> Result<()> {
    if args.duration.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
        bail!("--duration must be a positive number of seconds");
    }
    let config = load(&args.config)?;
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()?;
    rt.block_on(record(config, args))
}

async fn record(config: Config, args: &RecordArgs) -> Result<()> {
    let out =
        File::create(&args.out).with_context(|| format!("cannot create {}", args.out.display()))?;
    let specs: Vec<(&str, &str, u32)> = config
        .ports
        .iter()
        .map(|p| (p.device.as_str(), p.protocol.as_str(), p.baud))
        .collect();
    let mut rec = RawRecorder::new(BufWriter::new(out), &specs)?;
    rec.write_metadata(
        "vigil.record",
        BTreeMap::from([
            (
                "ports".to_string(),
                specs.iter().map(|s| s.0).collect::<Vec<_>>().join(","),
            ),
            (
                "paths".to_string(),
                config
                    .ports
                    .iter()
                    .map(|p| p.path.as_str())
                    .collect::<Vec<_>>()
                    .join(","),
            ),
        ]),
    )?;
    let (tx, mut rx) = mpsc::channel::<(u16, u64, Vec<u8>)>(1024);
    for (i, p) in config.ports.iter().enumerate() {
        let mut port = tokio_serial::new(&p.path, p.baud)
            .open_native_async()
            .with_context(|| format!("cannot open {} ({})", p.path, p.device))?;
        let tx = tx.clone();
        let name = p.device.clone();
        tokio::spawn(async move {
            let mut buf = vec![0u8; 4096];
            loop {
                match port.read(&mut buf).await {
                    Ok(0) => break,
                    Ok(n) => {
                        let t = monotonic_ns();
                        if tx.send((i as u16, t, buf[..n].to_vec())).await.is_err() {
                            break;
                        }
                    }
                    Err(e) => {
                        eprintln!("vigil record: {name}: read error: {e}");
                        break;
                    }
                }
            }
        });
    }
    drop(tx);
    let deadline = args
        .duration
        .map(|d| tokio::time::Instant::now() + Duration::from_secs_f64(d));
    let mut flush = tokio::time::interval(Duration::from_secs(1));
    let ctrl_c = tokio::signal::ctrl_c();
    tokio::pin!(ctrl_c);
    let mut bytes = vec![0u64; config.ports.len()];
    loop {
        let until = async {
            match deadline {
                Some(d) => tokio::time::sleep_until(d).await,
                None => std::future::pending().await,
            }
        };
        tokio::select! {
            m = rx.recv() => match m {
                Some((port, t, data)) => {
                    bytes[usize::from(port)] += data.len() as u64;
                    rec.write_raw(port, t, &data)?;
                }
                None => break,
            },
            _ = flush.tick() => rec.flush()?,
            _ = &mut ctrl_c => break,
            _ = until => break,
        }
    }
    let mut w = rec
        .finish()
        .map_err(|e| anyhow!("writing {}: {e}", args.out.display()))?;
    w.flush()?;
    let summary: BTreeMap<&str, u64> = config
        .ports
        .iter()
        .map(|p| p.device.as_str())
        .zip(bytes)
        .collect();
    eprintln!(
        "{}",
        serde_json::json!({ "kind": "summary", "bytes": summary })
    );
    Ok(())
}
