//! `vigil replay`: feed a recording's raw chunks through the drivers' decoders and write every
//! decoded message as one JSON line: `device`, `index` (0-based order of decoded messages of that
//! device), `offset` (the stream offset of its first byte, `Located::offset`), `t_host_ns` (host
//! receive time of the chunk holding that byte) and `message` (the driver's message as serde
//! writes it).
//!
//! `index` equals the truth file's `index` as long as no message of that device was lost or
//! damaged; `offset` equals the truth's `rx_offset` for every intact message, always.
//!
//! The decoder of a channel is chosen by its `protocol` metadata (`bahrs-2.0`, `watson-ahrs-e304`,
//! `vn200-icd`, `ttmrf-text`, `ttmrf-mavlink`, `ttmrf-gdl90`, `ttmrf-asterix`), or by the device
//! name when the channel has none.
//!
//! With `--emit decoded` on a terminal, a progress bar on stderr follows the recording's log time
//! (from the MCAP statistics record; a file without one, e.g. a truncated recording, shows none).
//!
//! Output is a deterministic function of the file: replaying twice gives identical bytes. Ports of an
//! unknown protocol are counted in the summary on stderr, with each decoder's counters and any
//! damage found in the file.
//!
//! Issue 20: every mode but `--publish` streams the file ([`vigil_record::read`]: one chunk
//! in memory at a time, raw messages in receive order per port, damaged chunks skipped and
//! listed in the summary's `damage`). `--emit fused`, `--check` and `--out` run with the flight's
//! configuration (`--config FILE`, else the recording's own, see `replay_config`). `--out
//! RICH.mcap` writes the recording again with its decoded and fused channels
//! (`replay_rich`).

use std::fs::File;
use std::io::{self, BufReader, BufWriter, Read, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};
use clap::Args;
use vigil_drivers::replay::{Decoded, Replayer};
use vigil_record::Recorded;
use vigil_record::{read_recording_from, recorded_span_from};
use vigil_service::replay::ReplaySummary;

use crate::progress::ProgressBar;

/// Arguments of `vigil replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The MCAP recording.
    pub input: PathBuf,
    /// Pace the replay at this multiple of real time (default: as fast as possible; with
    /// --publish: 1, or `max` for as fast as the subscribers keep up).
    #[arg(long)]
    pub speed: Option<String>,
    /// Publish the fused outputs on the iceoryx2 services, as `vigil run` does, paced by the
    /// recorded times (`--speed X`, default 1) or as fast as subscribers keep up (`--speed max`,
    /// lossless bus mode).
    #[arg(long, conflicts_with_all = ["check", "emit"])]
    pub publish: bool,
    /// Bus prefix of the services (with --publish).
    #[arg(long, default_value = "", requires = "publish")]
    pub prefix: String,
    /// What to write: the decoded messages, every message on GPS time (`aligned`: see
    /// `replay_aligned`), or the fused outputs (`fused`: see `replay_fused`).
    #[arg(long, value_enum, default_value = "decoded")]
    pub emit: Emit,
    /// Compare the fused outputs with this golden file (see `golden`); exits non-zero with a
    /// report of every difference beyond tolerance.
    #[arg(long, value_name = "GOLDEN")]
    pub check: Option<PathBuf>,
    /// With --check: rewrite the golden file from this replay instead of comparing.
    #[arg(long, requires = "check")]
    pub bless: bool,
    // --- issue 20 ---
    /// The flight's configuration (a `vigil run` TOML file) for --emit fused, --check and --out;
    /// default: the one recorded in the file, else `vigil run`'s defaults.
    #[arg(long, value_name = "FILE")]
    pub config: Option<PathBuf>,
    /// Write the recording again to this MCAP file with decoded and fused channels (see
    /// `--channels`), re-processed with the flight's configuration.
    #[arg(long, value_name = "RICH.mcap", conflicts_with_all = ["check", "publish"])]
    pub out: Option<PathBuf>,
    /// With --out: the channels to write.
    #[arg(long, value_parser = crate::cli_values::channel_set(), default_value = "all", requires = "out")]
    pub channels: vigil_service::recording::ChannelSet,
}

/// Output of `vigil replay`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Emit {
    /// Decoded messages with their receive times.
    Decoded,
    /// Every message's GPS time, 1-sigma and time source (issue 7).
    Aligned,
    /// Attitude-check records, ownship states and traffic pictures (issues 8 and 9).
    Fused,
}

/// Writes one decoded message as a JSON line, with vigil's JSON names (`vigil_service::json_names`).
fn write_line<W: Write>(out: &mut W, d: Decoded<'_>) -> Result<()> {
    let v = vigil_service::json_names::named_value(&d)?;
    serde_json::to_writer(&mut *out, &v)?;
    out.write_all(b"\n")?;
    Ok(())
}

/// Replays `mcap` into `out`. `speed`: pace at this multiple of real time. `span`: the
/// recording's first and last host time, ns, for the progress bar.
pub fn replay<W: Write>(
    mcap: impl Read,
    out: &mut W,
    speed: Option<f64>,
    span: Option<(u64, u64)>,
) -> Result<ReplaySummary> {
    let mut replayer = Replayer::new();
    let mut pace: Option<(u64, Instant)> = None;
    let mut bar = span.map(|(t0, t1)| {
        (
            t0,
            ProgressBar::stderr("vigil replay", t1.saturating_sub(t0)),
        )
    });
    let mut emit = |d: Decoded<'_>| write_line(out, d);
    let outcome = read_recording_from(mcap, |m| -> Result<()> {
        let Recorded::Raw {
            device,
            protocol,
            t_host_ns,
            bytes,
            ..
        } = m
        else {
            return Ok(());
        };
        if let Some(x) = speed {
            let (t0, wall0) = *pace.get_or_insert((t_host_ns, Instant::now()));
            let due = Duration::from_secs_f64(t_host_ns.saturating_sub(t0) as f64 / 1e9 / x);
            if let Some(wait) = due.checked_sub(wall0.elapsed()) {
                std::thread::sleep(wait);
            }
        }
        if let Some((t0, b)) = &mut bar {
            b.set(t_host_ns.saturating_sub(*t0));
        }
        replayer.feed(device, protocol, t_host_ns, bytes, &mut emit)
    })?;
    if let Some((_, b)) = &mut bar {
        b.finish();
    }
    let devices = replayer.finish(&mut emit)?;
    Ok(ReplaySummary {
        kind: "summary",
        mcap_messages: outcome.messages,
        damage: outcome.damage,
        devices,
    })
}

#[cfg(target_os = "linux")]
fn publish(args: &ReplayArgs, data: &[u8]) -> Result<()> {
    let speed = vigil_service::replay::publish::Speed::parse(args.speed.as_deref())?;
    let s = vigil_service::replay::publish::run(&args.input, data, &args.prefix, speed)?;
    eprintln!(
        "{{\"kind\":\"summary\",\"chunks\":{},\"attitude\":{},\"traffic\":{},\"alerts\":{}}}",
        s.chunks, s.attitude, s.traffic, s.alerts
    );
    Ok(())
}

#[cfg(not(target_os = "linux"))]
fn publish(_: &ReplayArgs, _: &[u8]) -> Result<()> {
    Err(anyhow!(
        "--publish needs Linux (iceoryx2 shared memory and vigil run's service)"
    ))
}

/// The recording, buffered for streaming.
fn open(input: &PathBuf) -> Result<BufReader<File>> {
    let f = File::open(input).with_context(|| format!("cannot read {}", input.display()))?;
    Ok(BufReader::with_capacity(1 << 16, f))
}

/// Runs `vigil replay`.
pub fn run(args: &ReplayArgs) -> Result<()> {
    if args.publish {
        let data = std::fs::read(&args.input)
            .with_context(|| format!("cannot read {}", args.input.display()))?;
        return publish(args, &data);
    }
    let speed = match args.speed.as_deref() {
        None => None,
        Some(x) => match x.parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Some(v),
            _ => return Err(anyhow!("--speed must be a positive number")),
        },
    };
    let (cfg, source) =
        vigil_service::replay::config::replay_config(args.config.as_deref(), &args.input)?;
    if let Some(golden) = &args.check {
        if args.speed.is_some() {
            return Err(anyhow!("--speed does not apply to --check"));
        }
        return vigil_service::golden::check(&args.input, &cfg, golden, args.bless);
    }
    if let Some(rich) = &args.out {
        if args.speed.is_some() {
            return Err(anyhow!("--speed does not apply to --out"));
        }
        let summary = vigil_service::replay::rich::replay_rich(
            &args.input,
            &cfg,
            &source,
            rich,
            args.channels,
        )?;
        eprintln!("{}", serde_json::to_string(&summary)?);
        return Ok(());
    }
    let stdout = io::stdout();
    let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
    let input = open(&args.input)?;
    let result = match args.emit {
        Emit::Decoded => {
            let span = File::open(&args.input).ok().and_then(recorded_span_from);
            replay(input, &mut out, speed, span)
        }
        Emit::Aligned => {
            if args.speed.is_some() {
                return Err(anyhow!("--speed applies to --emit decoded only"));
            }
            vigil_service::replay::aligned::replay_aligned(input, &mut out)
        }
        Emit::Fused => {
            if args.speed.is_some() {
                return Err(anyhow!("--speed applies to --emit decoded only"));
            }
            vigil_service::replay::fused::replay_fused(input, &cfg, &mut out)
        }
    };
    let summary = match result {
        Ok(s) => s,
        Err(e)
            if e.downcast_ref::<io::Error>()
                .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe) =>
        {
            return Ok(());
        }
        Err(e) => return Err(e),
    };
    if summary.mcap_messages == 0
        && let Some(d) = &summary.damage
    {
        return Err(anyhow!(
            "{}: not a readable mcap recording ({d})",
            args.input.display()
        ));
    }
    match out.flush() {
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => {
            return Err(e).context("writing standard output");
        }
        _ => {}
    }
    eprintln!("{}", serde_json::to_string(&summary)?);
    Ok(())
}
