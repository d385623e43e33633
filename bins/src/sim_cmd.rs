//! `vigil sim`: run a scenario into an MCAP recording (and optionally a truth JSON Lines file).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use anyhow::{Context, Result, anyhow};
use clap::Args;
use vigil_sim::record::McapSink;
use vigil_sim::scenario::{BUILTIN_NAMES, Scenario, builtin};
use vigil_sim::{Chunk, RunInfo, Simulator, Sink, SinkError, TruthRecord};

use crate::progress::ProgressBar;

/// Arguments of `vigil sim`.
#[derive(Debug, Args)]
pub struct SimArgs {
    /// A built-in scenario name or a scenario TOML file.
    #[arg(long)]
    pub scenario: String,
    /// Simulated duration, s.
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// Seed of every random draw (same scenario and seed: byte-identical output).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output MCAP file.
    #[arg(long, required_unless_present = "pty_dir", conflicts_with = "pty_dir")]
    pub out: Option<PathBuf>,
    /// Run live on pseudo-terminals instead: `DIR/<device>` links to each port's terminal.
    #[arg(long, value_name = "DIR")]
    pub pty_dir: Option<PathBuf>,
    /// Live only: pace at this multiple of real time.
    #[arg(long, default_value_t = 1.0, requires = "pty_dir")]
    pub speed: f64,
    /// Also write the truth as JSON Lines to this file.
    #[arg(long)]
    pub truth: Option<PathBuf>,
    /// Leave the `/truth` channel out of the MCAP file (most of its size; `--truth` still works).
    #[arg(long)]
    pub no_truth_channel: bool,
}

/// Resolves a built-in name or reads a TOML file.
pub fn load_scenario(name_or_file: &str) -> Result<Scenario> {
    if BUILTIN_NAMES.contains(&name_or_file) {
        return Ok(builtin(name_or_file)?);
    }
    let text = std::fs::read_to_string(name_or_file).with_context(|| {
        format!(
            "{name_or_file:?} is neither a built-in scenario ({}) nor a readable file",
            BUILTIN_NAMES.join(", ")
        )
    })?;
    Scenario::from_toml(&text).with_context(|| format!("in {name_or_file}"))
}

/// Shows a progress bar on stderr when it is a terminal ([`ProgressBar`]), in simulated time.
struct Progress<'a> {
    inner: &'a mut dyn Sink,
    start_host_ns: u64,
    bar: ProgressBar,
}

impl Sink for Progress<'_> {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        self.start_host_ns = info.host_clock.offset_ns;
        self.bar = ProgressBar::new(
            "vigil sim",
            info.duration_ns.max(1) as u64,
            self.bar.enabled(),
        );
        self.inner.start(info)
    }
    fn chunk(&mut self, chunk: &Chunk) -> Result<(), SinkError> {
        self.bar
            .set(chunk.t_host_ns.saturating_sub(self.start_host_ns));
        self.inner.chunk(chunk)
    }
    fn truth(&mut self, record: &TruthRecord, t_host_ns: u64) -> Result<(), SinkError> {
        self.inner.truth(record, t_host_ns)
    }
}

/// Runs `vigil sim`.
pub fn run(args: &SimArgs) -> Result<()> {
    if !(args.duration.is_finite() && args.duration > 0.0 && args.duration <= 366.0 * 86_400.0) {
        return Err(anyhow!("--duration must be within 0 .. 366 days"));
    }
    let scenario = load_scenario(&args.scenario)?;
    let mut sim = Simulator::new(&scenario, args.seed)?;
    let duration_ns = (args.duration * 1e9).round() as i64;
    if let Some(dir) = &args.pty_dir {
        return run_live(&mut sim, dir, args.speed, duration_ns);
    }
    let Some(path) = &args.out else {
        return Err(anyhow!("--out or --pty-dir is required"));
    };
    let out = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let truth: Option<Box<dyn Write>> = match &args.truth {
        Some(p) => Some(Box::new(BufWriter::new(
            File::create(p).with_context(|| format!("cannot create {}", p.display()))?,
        ))),
        None => None,
    };
    let mut sink = McapSink::new(BufWriter::new(out), truth)?;
    if args.no_truth_channel {
        sink = sink.without_truth_channel();
    }
    let mut progress = Progress {
        inner: &mut sink,
        start_host_ns: 0,
        bar: ProgressBar::stderr("vigil sim", duration_ns.max(1) as u64),
    };
    sim.run(duration_ns, &mut progress)
        .map_err(|e| anyhow!("simulation: {e}"))?;
    progress.bar.finish();
    let mut w = sink
        .finish()
        .map_err(|e| anyhow!("writing {}: {e}", path.display()))?;
    w.flush()?;
    Ok(())
}

#[cfg(target_os = "linux")]
fn run_live(
    sim: &mut Simulator,
    dir: &std::path::Path,
    speed: f64,
    duration_ns: i64,
) -> Result<()> {
    use crate::sim_live::{LiveSink, link_ports, open_pty};
    if !(speed.is_finite() && speed > 0.0) {
        return Err(anyhow!("--speed must be a positive number"));
    }
    let ports = sim.ports();
    let ptys = ports
        .iter()
        .map(|_| open_pty())
        .collect::<Result<Vec<_>>>()?;
    let names: Vec<&str> = ports.iter().map(|p| p.device).collect();
    link_ports(dir, &names, &ptys)?;
    {
        let mut out = std::io::stdout().lock();
        for (p, pty) in ports.iter().zip(&ptys) {
            writeln!(out, "{} {} {}", p.device, pty.path.display(), p.baud)?;
        }
        out.flush()?;
    }
    let mut sink = LiveSink::new(ptys, speed);
    sim.run(duration_ns, &mut sink)
        .map_err(|e| anyhow!("simulation: {e}"))?;
    if sink.dropped_bytes() > 0 {
        eprintln!(
            "vigil sim: {} bytes dropped (terminals nobody read)",
            sink.dropped_bytes()
        );
    }
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn run_live(_: &mut Simulator, _: &std::path::Path, _: f64, _: i64) -> Result<()> {
    Err(anyhow!("--pty-dir needs Linux pseudo-terminals"))
}
