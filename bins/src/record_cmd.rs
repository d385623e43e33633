//! `vigil record --config FILE --out FILE.mcap`: record live serial ports into an MCAP file with the
//! same layout as the simulator's (one `/<device>/raw` channel per port, log time = host monotonic
//! receive time of each read, ns), so `vigil replay` reads both alike.
//!
//! The serial loop is `vigil run`'s with processing off (`vigil_service::runtime::record`): a
//! port that fails is reopened with backoff. Ctrl-C (SIGINT) or SIGTERM ends the recording cleanly
//! (summary written). The open chunk is flushed to the file every second, so a killed recorder
//! leaves a file readable up to its last flush.
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

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use clap::Args;
use serde::Deserialize;
use vigil_drivers::protocol::Protocol;
use vigil_service::config::LinkSection;
use vigil_service::runtime::record::{RecordPort, record};
use vigil_service::runtime::serial::SerialPort;

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
        // A protocol is recorded as given and selects the decoder in `vigil replay`, which
        // matches names exactly: a misspelt one would leave the port undecoded, so it is refused
        // here. Empty is allowed (the device name then picks the decoder, or none).
        if !p.protocol.is_empty() && Protocol::resolve(&p.protocol, &p.device).is_none() {
            let names: Vec<&str> = Protocol::ALL.iter().map(|p| p.name()).collect();
            bail!(
                "{}: ports[{i}].protocol: {:?} is not one of {} (or leave it out)",
                path.display(),
                p.protocol,
                names.join(", ")
            );
        }
    }
    Ok(c)
}

/// Runs `vigil record`: `vigil run`'s serial loop with processing off
/// (`vigil_service::runtime::record`).
pub fn run(args: &RecordArgs) -> Result<()> {
    crate::init_logging();
    if args.duration.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
        bail!("--duration must be a positive number of seconds");
    }
    let config = load(&args.config)?;
    let ports: Vec<RecordPort> = config
        .ports
        .into_iter()
        .map(|p| RecordPort {
            serial: SerialPort {
                device: p.device,
                path: p.path.into(),
                baud: p.baud,
                setup: None,
                read_interval_ns: 0,
            },
            protocol: p.protocol,
        })
        .collect();
    let bytes = record(&ports, &args.out, LinkSection::default(), args.duration)?;
    eprintln!(
        "{}",
        serde_json::json!({ "kind": "summary", "bytes": bytes })
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn load_text(name: &str, text: &str) -> Result<Config> {
        let dir = std::env::temp_dir().join(format!("vigil-record-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let r = load(&path);
        let _ = std::fs::remove_file(&path);
        r
    }

    #[test]
    fn a_protocol_must_be_one_of_the_table_or_absent() {
        let port = |protocol: &str| {
            format!("[[ports]]\ndevice = \"imu\"\npath = \"/dev/null\"\nbaud = 115200\n{protocol}")
        };
        let e = load_text("bad.toml", &port("protocol = \"bahrs-2\"\n")).unwrap_err();
        assert!(e.to_string().contains("ports[0].protocol"), "{e}");
        assert!(e.to_string().contains("bahrs-2.0"), "{e}");
        let c = load_text("good.toml", &port("protocol = \"bahrs-2.0\"\n")).unwrap();
        assert_eq!(c.ports[0].protocol, "bahrs-2.0");
        // No protocol: recorded as is (an unknown device is then counted, not decoded).
        assert!(load_text("none.toml", &port("")).is_ok());
    }
}
