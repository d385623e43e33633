//! `vigil measure`: the figures issue 10 asks of `vigil run`, measured on simulated ports.
//!
//! - **Latency**: from the moment the write of the last byte of a VN-200 message to its
//!   pseudo-terminal returns, to the moment its fused attitude (the prompt output at the
//!   message's GPS time) is received here, in another process than `vigil run`. Both stamps are
//!   `CLOCK_MONOTONIC`, one clock for every process of the host. The path in between is the
//!   whole service: the kernel's terminal, tokio-serial, decode, alignment, fusion, iceoryx2
//!   publication and the event that wakes this subscriber.
//! - **CPU and memory** of the `vigil run` process over the measured window: user + system time
//!   from `/proc/PID/stat` divided by the wall time (percent of one core), and its resident set
//!   (`VmRSS`, and the peak `VmHWM`) from `/proc/PID/status`.
//!
//! - **The floor** (`--floor`, issue 21): the same figures for a reader that reads the same ports
//!   the same way and discards the bytes ([`crate::measure_floor`]), started in `vigil run`'s
//!   place: what being woken for the bytes costs on this machine. With whole-message reads it
//!   is a floor under `vigil run`'s CPU; at smaller reads it is a plain reader's cost (see
//!   there). `--floor-publish` has it also publish each VN-200 message's GPS time, matched like
//!   `vigil run`'s attitudes: the latency floor.
//!
//! The simulator runs in this process (its writes are stamped), `vigil run` is a child process
//! (this executable) on the terminals, with a unique bus prefix. The first `--warmup` seconds
//! (clock locking, device set-up) are left out of every figure. The default scenario is
//! `tests/data/full-rates.toml`: VN-200 at 400 Hz, BAHRS at 100 Hz, the Watson, and 300
//! intruders on the TT-Multi-RF, whose output (about 101 kB/s) exceeds its 921 600 baud line
//! (92 kB/s): the simulated module queues it 33-45 ms and discards about a fifth, as a device
//! would; the aligner sees the line full (`fusion::time::line_load`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::sync::mpsc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use serde::Serialize;
use vigil_bus::clock::monotonic_ns;
use vigil_bus::payload::alerts::{AlertPayload, STATE_CLEARED, STATE_LATCHED, STATE_RAISED};
use vigil_bus::payload::attitude::AttitudePayload;
use vigil_bus::{Bus, BusConfig};
use vigil_sim::Simulator;
use vigil_sim::scenario::Scenario;

use crate::demo::SimPort;
use crate::listen::LatencyStats;
use crate::sim_live::{LiveSink, Stamp, Stamper, link_ports, open_pty};

/// The default scenario: full simulated rates.
const FULL_RATES: &str = include_str!("../../tests/data/full-rates.toml");

/// Arguments of `vigil measure`.
#[derive(Debug, Args)]
pub struct MeasureArgs {
    /// Scenario (built-in name or TOML file); default: full rates (VN-200 400 Hz, BAHRS
    /// 100 Hz, 300 intruders).
    #[arg(long)]
    pub scenario: Option<String>,
    /// Measured time, s (after the warm-up).
    #[arg(long, default_value_t = 30.0)]
    pub duration: f64,
    /// Time left out at the start, s.
    #[arg(long, default_value_t = 5.0)]
    pub warmup: f64,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Override the scenario's `host.max_chunk_bytes`: the largest read a simulated USB
    /// adapter returns (reads are uniform in 1 ..= this, and end when the line goes idle). The
    /// default 64 is a stress case: about 5 reads per VN-200 message.
    #[arg(long, conflicts_with = "usb_packets")]
    pub max_chunk_bytes: Option<u32>,
    /// Model the USB adapters as FTDI full-speed ones instead: reads of 62 bytes (a 64-byte
    /// packet less its 2 status bytes) while the line is busy, and the rest when it goes idle
    /// (the scenario's `host.full_chunks`, `host.max_chunk_bytes = 62`).
    #[arg(long)]
    pub usb_packets: bool,
    /// A port's `read_interval_ms` for `vigil run`, as DEVICE=MS (repeatable; e.g. bahrs=0 reads
    /// the BAHRS on arrival). Ports not named keep their protocol's default.
    #[arg(long = "read-interval-ms", value_name = "DEVICE=MS", value_parser = parse_interval)]
    pub read_interval_ms: Vec<(String, f64)>,
    /// Run `vigil run` with `[realtime] cpu_wakeup_latency_us` set to this (Linux PM QoS,
    /// needs root; 0 keeps idle CPUs polling).
    #[arg(long)]
    pub cpu_wakeup_latency_us: Option<u32>,
    // --- issue 20 ---
    /// Record with `vigil run` (`[record]`, into the temporary directory) with these channels,
    /// to measure the recording's cost; the output states the file's size.
    #[arg(long, value_parser = crate::cli_values::channel_set())]
    pub record: Option<vigil_service::recording::ChannelSet>,
    // --- issue 21 ---
    /// Measure the floor instead of `vigil run`: a reader of the same ports, read the same way
    /// (on arrival or on the paced grid), that throws the bytes away. Its CPU and wake-ups are
    /// what being woken for the bytes costs on this machine (see `measure_floor.rs`); there is
    /// no latency (nothing is published).
    #[arg(long, conflicts_with_all = ["record", "cpu_wakeup_latency_us"])]
    pub floor: bool,
    /// The floor with a latency: the reader also decodes the VN-200's messages and publishes
    /// each one's GPS time at once as an attitude sample, which is matched as `vigil run`'s are.
    /// Its latency (the terminal, one wake-up, one iceoryx2 publication and its event) is the
    /// least a service woken and publishing as `vigil run` is can have on this machine; its CPU
    /// is the floor's plus the decode and the publication.
    #[arg(long, conflicts_with_all = ["floor", "record", "cpu_wakeup_latency_us"])]
    pub floor_publish: bool,
}

/// CPU time and memory of a process at one moment.
#[derive(Debug, Clone, Copy)]
struct ProcSample {
    at: Instant,
    /// User CPU time, s.
    user_s: f64,
    /// System (kernel) CPU time, s.
    system_s: f64,
    /// Resident set, kB.
    rss_kb: u64,
    /// Peak resident set, kB.
    hwm_kb: u64,
    /// Context switches of all its threads so far (voluntary + involuntary): each is the
    /// process going to sleep or being put off the CPU, so their count is its wake-ups.
    switches: u64,
}

/// Context switches of every thread of process `pid` (`/proc/PID/task/*/status`), voluntary and
/// involuntary. (`/proc/PID/status` counts the main thread only.) A thread that ended in between
/// is no longer counted: `vigil run`'s threads live as long as it does.
fn context_switches(pid: u32) -> Result<u64> {
    let mut total = 0;
    for task in std::fs::read_dir(format!("/proc/{pid}/task"))? {
        let Ok(status) = std::fs::read_to_string(task?.path().join("status")) else {
            continue; // the thread ended meanwhile
        };
        total += status
            .lines()
            .filter_map(|l| {
                l.strip_prefix("voluntary_ctxt_switches:")
                    .or_else(|| l.strip_prefix("nonvoluntary_ctxt_switches:"))
            })
            .filter_map(|v| v.trim().parse::<u64>().ok())
            .sum::<u64>();
    }
    Ok(total)
}

fn proc_sample(pid: u32) -> Result<ProcSample> {
    let stat = std::fs::read_to_string(format!("/proc/{pid}/stat"))?;
    // The command name (field 2) is in parentheses and may hold spaces: fields after the last
    // ')' start at field 3 (state); utime and stime are fields 14 and 15.
    let rest = stat
        .rsplit_once(')')
        .map(|x| x.1)
        .ok_or_else(|| anyhow!("unreadable /proc/{pid}/stat"))?;
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| -> Result<f64> {
        Ok(f.get(i)
            .ok_or_else(|| anyhow!("short /proc/{pid}/stat"))?
            .parse::<u64>()? as f64)
    };
    let hz = rustix::param::clock_ticks_per_second() as f64;
    let (user_s, system_s) = (ticks(11)? / hz, ticks(12)? / hz);
    let status = std::fs::read_to_string(format!("/proc/{pid}/status"))?;
    let kb = |key: &str| {
        status
            .lines()
            .find_map(|l| l.strip_prefix(key))
            .and_then(|v| v.split_whitespace().next()?.parse().ok())
            .unwrap_or(0)
    };
    Ok(ProcSample {
        at: Instant::now(),
        user_s,
        system_s,
        rss_kb: kb("VmRSS:"),
        hwm_kb: kb("VmHWM:"),
        switches: context_switches(pid)?,
    })
}

/// What `vigil measure` prints (one JSON object).
#[derive(Debug, Serialize)]
pub struct Report {
    /// Scenario simulated.
    pub scenario: String,
    /// Measured window, s.
    pub window_s: f64,
    /// VN-200 messages whose last byte was written in the window.
    pub vn200_messages: usize,
    /// Of those, the ones whose fused attitude was received.
    pub matched: usize,
    /// Latency, last byte written to fused attitude received, us.
    pub latency: Option<LatencyStats>,
    /// Its first part, last byte written to the payload's send stamp (`header.send_mono_ns`):
    /// the terminal, the read, decode, alignment, fusion and the publication, us.
    pub write_to_send: Option<LatencyStats>,
    /// Its second part, send stamp to reception: iceoryx2 and the subscriber's wake-up, us.
    pub send_to_receive: Option<LatencyStats>,
    /// CPU of `vigil run` in the window, percent of one core (user + system).
    pub cpu_percent_of_one_core: f64,
    /// Of which in the kernel (reads, waits, wake-ups, notifications), percent of one core.
    pub cpu_system_percent: f64,
    /// Read chunks the simulator wrote to all terminals, per second (each one on a port read on
    /// arrival wakes the service; paced ports are drained every `read_interval_ms`).
    pub chunks_per_s: f64,
    /// Wake-ups of `vigil run` per second in the window: its threads' context switches
    /// (voluntary and involuntary) per second.
    pub wakeups_per_s: f64,
    /// CPU per wake-up, us: the CPU time in the window over its wake-ups.
    pub cpu_us_per_wakeup: Option<f64>,
    /// Bytes the simulator could not write because a terminal was full (the service read too
    /// late), per port (device, bytes), over the whole run. Any is a failure of the run: a
    /// real serial line would have lost them.
    pub dropped_bytes: BTreeMap<String, u64>,
    /// Messages the simulated devices lost before the terminals, per device, over the whole
    /// run (the simulator's truth): a device whose output exceeds its line discards what its
    /// buffer cannot hold, as the default scenario's TT-Multi-RF does (about a fifth of its
    /// output; `vigil run` says so with the `line_full` alert). Not a failure of the service,
    /// which never saw them; a scenario whose devices lose nothing reports an empty map.
    pub device_lost_messages: BTreeMap<String, u64>,
    /// Resident set of `vigil run` at the end, MB.
    pub rss_mb: f64,
    /// Its peak resident set, MB.
    pub peak_rss_mb: f64,
    /// Attitude payloads the subscriber missed (overflow).
    pub missed: u64,
    /// The alerts `vigil run` published during the run, in order, each as "T s: STATE: REASON"
    /// (T: when it was received, s from the start of the run, the warm-up included). They explain
    /// messages that are not matched: while the VN-200's GPS time disagrees with the host clock
    /// (the simulator itself stalled for more than the cross-check's 20 ms margin on a busy
    /// host, say), its samples are timed by another clock, so their attitudes carry that clock's
    /// time, not the simulator's.
    pub alerts: Vec<String>,
    /// With `--record`: the channels recorded and the recording's size at the end, bytes (issue
    /// 20).
    pub recording: Option<(vigil_service::recording::ChannelSet, u64)>,
}

/// Parses DEVICE=MS.
fn parse_interval(s: &str) -> Result<(String, f64), String> {
    let (device, ms) = s
        .split_once('=')
        .ok_or_else(|| format!("{s:?}: expected DEVICE=MS, e.g. bahrs=0"))?;
    let ms: f64 = ms
        .parse()
        .map_err(|_| format!("{s:?}: {ms:?} is not a number of ms"))?;
    Ok((device.to_string(), ms))
}

/// Data bytes of an FTDI full-speed USB packet (64 bytes, of which 2 are modem status).
const FTDI_PACKET_DATA_BYTES: u32 = 62;

/// Runs `vigil measure`.
pub fn run(args: &MeasureArgs) -> Result<()> {
    if !(args.duration.is_finite() && args.duration > 0.0) {
        bail!("--duration must be a positive number of seconds");
    }
    if !(args.warmup.is_finite() && args.warmup >= 0.0) {
        bail!("--warmup must be a number of seconds, 0 or more");
    }
    let report = crate::demo::in_temp_dir("measure", |dir, prefix| measure(args, dir, prefix))?;
    println!("{}", serde_json::to_string_pretty(&report)?);
    let lost: u64 = report.dropped_bytes.values().sum();
    if lost > 0 {
        bail!(
            "{lost} bytes dropped by the terminals while the service was reading (a full \
             terminal: the service read too late); per port: {:?}",
            report.dropped_bytes
        );
    }
    Ok(())
}

fn measure(args: &MeasureArgs, dir: &Path, prefix: &str) -> Result<Report> {
    let (name, mut scenario) = match &args.scenario {
        Some(s) => (s.clone(), crate::sim_cmd::load_scenario(s)?),
        None => (
            "full-rates".to_string(),
            Scenario::from_toml(FULL_RATES).context("the built-in full-rates scenario")?,
        ),
    };
    if let Some(n) = args.max_chunk_bytes {
        scenario.host.max_chunk_bytes = n;
    }
    if args.usb_packets {
        scenario.host.max_chunk_bytes = FTDI_PACKET_DATA_BYTES;
        scenario.host.full_chunks = true;
    }
    let mut sim = Simulator::new(&scenario, args.seed)?;
    let ports = sim.ports();
    let vn200 = ports
        .iter()
        .position(|p| p.device == "vn200")
        .ok_or_else(|| anyhow!("scenario {name} has no VN-200"))?;
    let ptys = ports
        .iter()
        .map(|_| open_pty())
        .collect::<Result<Vec<_>>>()?;
    let names: Vec<&str> = ports.iter().map(|p| p.device).collect();
    let pty_dir = dir.join("ports");
    link_ports(&pty_dir, &names, &ptys)?;
    for (device, _) in &args.read_interval_ms {
        if !names.contains(&device.as_str()) {
            bail!(
                "--read-interval-ms {device}=...: the scenario's ports are {}",
                names.join(", ")
            );
        }
    }
    let links: Vec<SimPort> = ports
        .iter()
        .map(|p| SimPort {
            device: p.device,
            path: pty_dir.join(p.device),
            read_interval_ms: args
                .read_interval_ms
                .iter()
                .rev()
                .find(|(device, _)| device == p.device)
                .map(|(_, ms)| *ms),
            baud: Some(p.baud),
        })
        .collect();
    let config = dir.join("vigil.toml");
    let mut text = crate::demo::run_config(prefix, &links);
    if let Some(us) = args.cpu_wakeup_latency_us {
        text += &format!("[realtime]\ncpu_wakeup_latency_us = {us}\n");
    }
    if let Some(set) = args.record {
        text += &crate::demo::record_section(&dir.join("flight.mcap"), set);
    }
    std::fs::write(&config, text)?;
    let log = dir.join("run.log");

    let bus = Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        handle_signals: true,
        ..BusConfig::default()
    })
    .context("connecting to the bus")?;
    let mut sub = bus.subscriber::<AttitudePayload>()?;
    let mut alert_sub = bus.subscriber::<AlertPayload>()?;
    let mut alerts = Vec::new();
    let floor = args.floor || args.floor_publish;
    let mut run = if floor {
        // The ports as `vigil run` would read them: its own configuration check resolves each
        // port's interval (the one given or the protocol's default) and refuses what it
        // refuses (a paced VN-200, an interval longer than the buffer holds).
        let (_, ports) = vigil_service::config::Config::load(&config)?;
        let mut floor_args = vec!["measure-floor".to_string()];
        if args.floor_publish {
            let vn200 = ports
                .iter()
                .find(|p| p.device == "vn200")
                .ok_or_else(|| anyhow!("no VN-200 port in the configuration"))?;
            floor_args.extend(["--bus-prefix".to_string(), prefix.to_string()]);
            floor_args.extend(["--vn200".to_string(), vn200.path.display().to_string()]);
        }
        for port in &ports {
            floor_args.push("--port".into());
            floor_args.push(format!(
                "{}:{}",
                port.read_interval_ns as f64 / 1e6,
                port.path.display()
            ));
        }
        let floor_args: Vec<&str> = floor_args.iter().map(String::as_str).collect();
        crate::demo::spawn("measure-floor", &floor_args, &log)?
    } else {
        crate::demo::spawn(
            "run",
            &["run", "--config", config.to_str().context("config path")?],
            &log,
        )?
    };
    let run_pid = run.child.id();

    // The simulator writes in its own thread, from now on, in real time.
    let total_s = args.warmup + args.duration + 0.5;
    let (tx, stamps) = mpsc::channel::<Stamp>();
    let vn_port = u16::try_from(vn200)?;
    let writer = std::thread::spawn(move || -> Result<(Vec<u64>, u64, BTreeMap<&str, u64>)> {
        let mut sink = LiveSink::new(ptys, 1.0).with_stamper(Stamper::new("vn200", vn_port, tx));
        sim.run((total_s * 1e9) as i64, &mut sink)
            .map_err(|e| anyhow!("simulation: {e}"))?;
        Ok((sink.dropped_by_port, sink.chunks, sink.lost_messages))
    });

    let start = Instant::now();
    let warm_end = start + Duration::from_secs_f64(args.warmup);
    let end = warm_end + Duration::from_secs_f64(args.duration);
    // GPS time -> (send stamp, receive time), ns.
    let mut received: HashMap<i64, (u64, u64)> = HashMap::new();
    let mut first: Option<(ProcSample, u64)> = None;
    let mut last = None;
    // `vigil run` is stopped only once the simulator has written everything and the service
    // has had time to drain its paced ports (their longest interval is 10 ms by default; the
    // margin covers any allowed one): a byte written after the service stopped reading would
    // be dropped by the terminal and reported as lost by a service that lost nothing.
    let mut written_all: Option<Instant> = None;
    while written_all.is_none_or(|t| t.elapsed() < Duration::from_millis(300)) {
        if written_all.is_none() && writer.is_finished() {
            written_all = Some(Instant::now());
        }
        if !run.running() {
            bail!("vigil run stopped:\n{}", crate::demo::tail(&log, 10));
        }
        if bus.termination_requested() {
            bail!("interrupted");
        }
        sub.wait(Duration::from_millis(50))?;
        while let Some(r) = sub.try_receive()? {
            let now = monotonic_ns();
            let h = &r.payload().header;
            received.insert(h.gps_time_ns, (h.send_mono_ns, now));
        }
        while let Some(a) = alert_sub.try_receive()? {
            let a = a.payload();
            let state = match a.state {
                STATE_RAISED => "raised",
                STATE_CLEARED => "cleared",
                STATE_LATCHED => "latched",
                _ => "state unknown",
            };
            // A clearing's reason already starts with "cleared: ".
            let reason = a.reason();
            let reason = reason
                .strip_prefix(state)
                .and_then(|r| r.strip_prefix(": "))
                .unwrap_or(reason);
            let at_s = start.elapsed().as_secs_f64();
            alerts.push(format!("{at_s:.1} s: {state}: {reason}"));
        }
        let now = Instant::now();
        if first.is_none() && now >= warm_end {
            first = Some((proc_sample(run_pid)?, monotonic_ns()));
        }
        if last.is_none() && now >= end {
            last = Some(proc_sample(run_pid)?);
        }
    }
    let clean = run.stop(Duration::from_secs(5));
    let (dropped, chunks, lost) = writer
        .join()
        .map_err(|_| anyhow!("the simulator thread panicked"))??;
    // The floor reader without a bus has no handler: SIGTERM ends it, which is not a failure.
    if !clean && !args.floor {
        let what = if args.floor_publish {
            "the floor reader"
        } else {
            "vigil run"
        };
        eprintln!(
            "vigil measure: {what} did not stop cleanly:\n{}",
            crate::demo::tail(&log, 10)
        );
    }
    let ((p0, warm_mono), p1) = first
        .zip(last)
        .ok_or_else(|| anyhow!("the measurement window did not complete"))?;
    let window_s = p1.at.duration_since(p0.at).as_secs_f64();
    let end_mono = warm_mono + (window_s * 1e9) as u64;
    let (mut latencies, mut first_part, mut second_part) = (Vec::new(), Vec::new(), Vec::new());
    let mut messages = 0;
    for s in stamps.try_iter() {
        if !(warm_mono..end_mono).contains(&s.written_mono_ns) {
            continue;
        }
        messages += 1;
        if let Some(at) = received.get(&s.t_gps_ns) {
            let (sent, at) = *at;
            latencies.push(at.saturating_sub(s.written_mono_ns));
            first_part.push(sent.saturating_sub(s.written_mono_ns));
            second_part.push(at.saturating_sub(sent));
        }
    }
    let cpu_s = p1.user_s + p1.system_s - p0.user_s - p0.system_s;
    let switches = p1.switches.saturating_sub(p0.switches);
    Ok(Report {
        scenario: name,
        window_s,
        vn200_messages: messages,
        matched: latencies.len(),
        latency: LatencyStats::from_ns(latencies, sub.missed()),
        write_to_send: LatencyStats::from_ns(first_part, sub.missed()),
        send_to_receive: LatencyStats::from_ns(second_part, sub.missed()),
        cpu_percent_of_one_core: 100.0 * cpu_s / window_s.max(1e-9),
        cpu_system_percent: 100.0 * (p1.system_s - p0.system_s) / window_s.max(1e-9),
        chunks_per_s: chunks as f64 / total_s,
        wakeups_per_s: switches as f64 / window_s.max(1e-9),
        cpu_us_per_wakeup: (switches > 0).then(|| cpu_s * 1e6 / switches as f64),
        dropped_bytes: names
            .iter()
            .zip(dropped)
            .map(|(n, d)| (n.to_string(), d))
            .collect(),
        device_lost_messages: lost.into_iter().map(|(d, n)| (d.to_string(), n)).collect(),
        rss_mb: p1.rss_kb as f64 / 1024.0,
        peak_rss_mb: p1.hwm_kb as f64 / 1024.0,
        missed: sub.missed(),
        alerts,
        recording: args.record.map(|set| {
            let bytes = std::fs::metadata(dir.join("flight.mcap")).map_or(0, |m| m.len());
            (set, bytes)
        }),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every sleep of a thread is a voluntary context switch: ten sleeps of a new thread add at
    /// least ten to the process's count, which sums all its threads (the main thread's
    /// `/proc/PID/status` alone would not see them).
    #[test]
    fn context_switches_count_every_thread() {
        let pid = std::process::id();
        let before = context_switches(pid).unwrap();
        let (tx, rx) = mpsc::channel();
        let t = std::thread::spawn(move || {
            for _ in 0..10 {
                std::thread::sleep(Duration::from_millis(1));
            }
            // Counted while the thread still exists.
            rx.recv().unwrap()
        });
        std::thread::sleep(Duration::from_millis(50));
        let during = context_switches(pid).unwrap();
        tx.send(()).unwrap();
        t.join().unwrap();
        assert!(during >= before + 10, "{before} -> {during}");
    }
}
