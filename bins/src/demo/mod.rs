//! `vigil demo [--duration S] [--scenario NAME]`: everything on one machine with no hardware and
//! no root. It starts the simulator on Linux pseudo-terminals (`vigil sim --pty-dir`), `vigil run`
//! on those ports (decode, align, fuse, publish over iceoryx2, monitor), and shows what a consumer
//! receives on the bus as a live terminal view ([`view`]): the ownship, the three attitude units
//! with the cross-check verdicts, the traffic table and the alerts as they rise and clear.
//!
//! The two programs are child processes of the demo (the same executable), so the demo exercises
//! the real serial path and the real inter-process bus; a unique bus prefix keeps it apart from any
//! other vigil on the host. On a terminal the view is redrawn twice a second; otherwise (a pipe, CI)
//! a one-line status is printed every 2 s and every alert transition as it arrives. The demo ends
//! after `--duration` seconds or on Ctrl-C, stopping both children with SIGTERM (so `vigil run`
//! shuts down cleanly) and removing its temporary directory.

pub mod view;

use std::fmt::Write as _;
use std::io::{IsTerminal, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::Args;
use vigil_bus::payload::alerts::AlertPayload;
use vigil_bus::payload::attitude::AttitudePayload;
use vigil_bus::payload::ownship::OwnshipPayload;
use vigil_bus::{Bus, BusConfig};

use view::View;

/// Arguments of `vigil demo`.
#[derive(Debug, Args)]
pub struct DemoArgs {
    /// How long to run, s.
    #[arg(long, default_value_t = 60.0)]
    pub duration: f64,
    /// Built-in scenario (or a scenario TOML file) to simulate; the default `demo` has traffic,
    /// a head-on intruder and a BAHRS fault that rises and clears.
    #[arg(long, default_value = "demo")]
    pub scenario: String,
    /// Seed of the simulation.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    // --- issue 20 ---
    /// Record the flight to this MCAP file (`vigil run`'s `[record] path`); it is kept after the
    /// demo.
    #[arg(long, value_name = "FILE.mcap")]
    pub record: Option<PathBuf>,
    /// With --record: the channels recorded.
    #[arg(long, value_parser = crate::cli_values::channel_set(), default_value = "raw+fused", requires = "record")]
    pub record_channels: vigil_service::recording::ChannelSet,
    /// Also send the fused traffic as MAVLink ADSB_VEHICLE (and HEARTBEAT) over UDP to this
    /// address (`IP:PORT`, e.g. 127.0.0.1:14550 for a ground station on this machine).
    #[arg(long, value_name = "IP:PORT")]
    pub mavlink_out: Option<String>,
    /// Also send traffic and ownship as GDL90 over UDP to this address (`IP:PORT`, e.g.
    /// 127.0.0.1:4000 for an EFB on this machine).
    #[arg(long, value_name = "IP:PORT")]
    pub gdl90_out: Option<String>,
}

/// The `[record]` section of a `vigil run` configuration writing `path` with `channels`.
pub(crate) fn record_section(
    path: &Path,
    channels: vigil_service::recording::ChannelSet,
) -> String {
    format!(
        "[record]\npath = {:?}\nchannels = \"{}\"\n",
        path.display().to_string(),
        channels.name()
    )
}

/// Devices the simulator may serve, in the order of `vigil run`'s ports.
const DEVICES: [&str; 4] = ["bahrs", "vn200", "watson", "ttmrf"];

/// A child process that is stopped (SIGTERM, then SIGKILL after a grace period) when dropped.
pub(crate) struct Guard {
    name: &'static str,
    pub(crate) child: Child,
}

impl Guard {
    pub(crate) fn running(&mut self) -> bool {
        matches!(self.child.try_wait(), Ok(None))
    }

    /// SIGTERM, wait up to `grace`, then SIGKILL; returns whether it exited on its own.
    pub(crate) fn stop(&mut self, grace: Duration) -> bool {
        if !self.running() {
            return true;
        }
        let pid = rustix::process::Pid::from_child(&self.child);
        let _ = rustix::process::kill_process(pid, rustix::process::Signal::TERM);
        let until = Instant::now() + grace;
        while Instant::now() < until {
            if let Ok(Some(status)) = self.child.try_wait() {
                return status.success();
            }
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = self.child.kill();
        let _ = self.child.wait();
        false
    }
}

impl Drop for Guard {
    fn drop(&mut self) {
        self.stop(Duration::from_secs(3));
    }
}

/// One simulated port for [`run_config`].
pub(crate) struct SimPort<'a> {
    /// Device name (the port's `device`).
    pub device: &'a str,
    /// Its terminal.
    pub path: PathBuf,
    /// Its `read_interval_ms`, when not the protocol's default.
    pub read_interval_ms: Option<f64>,
    /// The simulated line's baud rate, when known. A terminal carries bytes at any rate, so
    /// nothing would tell `vigil run` a slower line than the protocol's default; and the
    /// service judges whether a line is full against its configured baud.
    pub baud: Option<u32>,
}

/// The `vigil run` configuration for the simulator's terminals.
pub(crate) fn run_config(prefix: &str, ports: &[SimPort]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# Written by `vigil demo` / `vigil measure`.\n[bus]\nprefix = \"{prefix}\"\n"
    );
    for p in ports {
        let _ = writeln!(
            s,
            "[[ports]]\ndevice = \"{}\"\npath = \"{}\"",
            p.device,
            p.path.display()
        );
        if let Some(ms) = p.read_interval_ms {
            let _ = writeln!(s, "read_interval_ms = {ms:?}");
        }
        if let Some(baud) = p.baud {
            let _ = writeln!(s, "baud = {baud}");
        }
        s.push('\n');
    }
    s
}

pub(crate) fn spawn(name: &'static str, args: &[&str], log: &Path) -> Result<Guard> {
    let exe = std::env::current_exe().context("locating the vigil executable")?;
    let log_file =
        std::fs::File::create(log).with_context(|| format!("cannot create {}", log.display()))?;
    let mut cmd = Command::new(exe);
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(log_file);
    die_with_parent(&mut cmd);
    let child = cmd
        .spawn()
        .with_context(|| format!("starting vigil {name}"))?;
    Ok(Guard { name, child })
}

/// The child gets SIGTERM when this process dies, however it dies (a SIGKILLed `vigil demo` left
/// its `vigil run` reparented to init, publishing for good): SIGTERM, not SIGKILL, so the child
/// still shuts down cleanly and removes its bus resources.
#[cfg(target_os = "linux")]
fn die_with_parent(cmd: &mut Command) {
    use std::os::unix::process::CommandExt;
    let parent = rustix::process::getpid();
    // SAFETY: the closure runs in the forked child before exec and calls only prctl and
    // getppid, both async-signal-safe system calls; it allocates nothing and takes no lock.
    unsafe {
        cmd.pre_exec(move || {
            rustix::process::set_parent_process_death_signal(Some(rustix::process::Signal::TERM))?;
            // The parent may have died between fork and prctl: then no signal will come.
            if rustix::process::getppid() != Some(parent) {
                return Err(std::io::Error::other(
                    "the parent exited before the child started",
                ));
            }
            Ok(())
        });
    }
}

#[cfg(not(target_os = "linux"))]
fn die_with_parent(_cmd: &mut Command) {}

/// Removes the temporary directories (`vigil-KIND-PID`) that a `vigil demo` or `vigil measure`
/// killed before it could clean up left behind: those whose process no longer exists. Run at the
/// start of every vigil command; a live process's directory is never touched.
#[cfg(target_os = "linux")]
pub(crate) fn sweep_stale_temp_dirs() {
    let Ok(entries) = std::fs::read_dir(std::env::temp_dir()) else {
        return;
    };
    for e in entries.flatten() {
        let name = e.file_name();
        let Some(pid) = name
            .to_str()
            .and_then(|n| n.strip_prefix("vigil-"))
            .and_then(|rest| rest.split_once('-'))
            .filter(|(kind, _)| ["demo", "measure"].contains(kind))
            .and_then(|(_, pid)| pid.parse::<i32>().ok())
        else {
            continue;
        };
        // EPERM: the process exists but belongs to another user.
        let alive = rustix::process::Pid::from_raw(pid).is_some_and(|p| {
            !matches!(
                rustix::process::test_kill_process(p),
                Err(rustix::io::Errno::SRCH)
            )
        });
        if !alive && e.file_type().is_ok_and(|t| t.is_dir()) {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
}

#[cfg(not(target_os = "linux"))]
pub(crate) fn sweep_stale_temp_dirs() {}

pub(crate) fn tail(path: &Path, lines: usize) -> String {
    let text = std::fs::read_to_string(path).unwrap_or_default();
    let v: Vec<&str> = text.lines().collect();
    v[v.len().saturating_sub(lines)..].join("\n")
}

/// Runs `vigil demo`.
pub fn run(args: &DemoArgs) -> Result<()> {
    if !(args.duration.is_finite() && args.duration > 0.0) {
        bail!("--duration must be a positive number of seconds");
    }
    in_temp_dir("demo", |dir, prefix| demo(args, dir, prefix))
}

/// Runs `f` with a temporary directory `vigil-KIND-PID` (removed afterwards, whatever the
/// outcome) and a bus prefix `KINDPID` unique on the host.
pub(crate) fn in_temp_dir<T>(kind: &str, f: impl FnOnce(&Path, &str) -> Result<T>) -> Result<T> {
    let pid = std::process::id();
    let dir = std::env::temp_dir().join(format!("vigil-{kind}-{pid}"));
    std::fs::create_dir_all(&dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let result = f(&dir, &format!("{kind}{pid}"));
    let _ = std::fs::remove_dir_all(&dir);
    result
}

fn demo(args: &DemoArgs, dir: &Path, prefix: &str) -> Result<()> {
    let pty_dir = dir.join("ports");
    // The scenario's bauds, for `vigil run`'s configuration (the simulator runs in its own
    // process; a terminal does not carry the rate).
    let scenario = crate::sim_cmd::load_scenario(&args.scenario)?;
    let sim_ports = vigil_sim::Simulator::new(&scenario, args.seed)?.ports();
    let baud_of = |d: &str| sim_ports.iter().find(|p| p.device == d).map(|p| p.baud);
    // The simulation runs a little longer than the demo, so the ports stay open to the end.
    let sim_secs = format!("{}", args.duration.ceil() + 10.0);
    let seed = args.seed.to_string();
    let mut sim = spawn(
        "sim",
        &[
            "sim",
            "--scenario",
            &args.scenario,
            "--duration",
            &sim_secs,
            "--seed",
            &seed,
            "--pty-dir",
            pty_dir.to_str().context("temporary directory path")?,
        ],
        &dir.join("sim.log"),
    )?;
    // The simulator creates one link per device it models.
    let until = Instant::now() + Duration::from_secs(10);
    let ports: Vec<SimPort> = loop {
        let found: Vec<SimPort> = DEVICES
            .iter()
            .map(|d| SimPort {
                device: d,
                path: pty_dir.join(d),
                read_interval_ms: None,
                baud: baud_of(d),
            })
            .filter(|p| p.path.exists())
            .collect();
        if !sim.running() {
            bail!("the simulator stopped:\n{}", tail(&dir.join("sim.log"), 10));
        }
        // Give it a moment after the first link to create the others.
        if !found.is_empty() && std::fs::read_dir(&pty_dir)?.count() == found.len() {
            std::thread::sleep(Duration::from_millis(200));
            let again = std::fs::read_dir(&pty_dir)?.count();
            if again == found.len() {
                break found;
            }
        }
        if Instant::now() > until {
            bail!("the simulator created no ports in {}", pty_dir.display());
        }
        std::thread::sleep(Duration::from_millis(50));
    };
    let config = dir.join("vigil.toml");
    let mut text = run_config(prefix, &ports);
    if let Some(path) = &args.record {
        let path = std::path::absolute(path).context("the --record path")?;
        text += &record_section(&path, args.record_channels);
    }
    for (flag, section, addr) in [
        ("--mavlink-out", "mavlink", &args.mavlink_out),
        ("--gdl90-out", "gdl90", &args.gdl90_out),
    ] {
        if let Some(addr) = addr {
            addr.parse::<std::net::SocketAddr>()
                .with_context(|| format!("{flag} {addr:?}: expected IP:PORT"))?;
            text += &format!("\n[outputs.{section}]\naddress = \"{addr}\"\n");
        }
    }
    std::fs::write(&config, text)?;
    let mut run = spawn(
        "run",
        &["run", "--config", config.to_str().context("config path")?],
        &dir.join("run.log"),
    )?;
    let outcome = view_loop(
        args,
        prefix,
        &mut [&mut sim, &mut run],
        &dir.join("run.log"),
    );
    let clean = run.stop(Duration::from_secs(5));
    sim.stop(Duration::from_secs(2));
    outcome?;
    if !clean {
        bail!(
            "vigil run did not shut down cleanly:\n{}",
            tail(&dir.join("run.log"), 10)
        );
    }
    Ok(())
}

fn view_loop(
    args: &DemoArgs,
    prefix: &str,
    children: &mut [&mut Guard],
    run_log: &Path,
) -> Result<()> {
    let bus = Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: "vigil-demo".to_string(),
        handle_signals: true,
        ..BusConfig::default()
    })
    .context("connecting to the bus")?;
    let mut att = bus.subscriber::<AttitudePayload>()?;
    let mut own = bus.subscriber::<OwnshipPayload>()?;
    let mut traffic = bus.traffic_subscriber()?;
    let mut alerts = bus.subscriber::<AlertPayload>()?;
    let tty = std::io::stdout().is_terminal();
    let mut out = std::io::stdout().lock();
    let start = Instant::now();
    let end = start + Duration::from_secs_f64(args.duration);
    let mut v = View::default();
    let mut t0: Option<i64> = None;
    let mut next_draw = start;
    // The bus prefix is this demo's own (`demoPID`, so it never meets another vigil): say how to
    // reach it, at start and under every redraw of the terminal view.
    let attach = format!(
        "attach from another terminal: vigil listen traffic --prefix {prefix}   \
         (or attitude, ownship, integrity, alerts)"
    );
    writeln!(out, "vigil demo: {attach}")?;
    out.flush()?;
    let period = if tty {
        Duration::from_millis(500)
    } else {
        Duration::from_secs(2)
    };
    while Instant::now() < end && !bus.termination_requested() {
        for c in children.iter_mut() {
            if !c.running() {
                bail!("vigil {} stopped early:\n{}", c.name, tail(run_log, 10));
            }
        }
        while let Some(r) = att.try_receive()? {
            t0.get_or_insert(r.payload().header.gps_time_ns);
            v.attitude = Some(*r.payload());
            v.received[0] += 1;
        }
        while let Some(r) = own.try_receive()? {
            v.ownship = Some(*r.payload());
            v.received[1] += 1;
        }
        while let Some(r) = traffic.try_receive()? {
            v.traffic = Some(Box::new(r.to_payload()));
            v.received[2] += 1;
        }
        while let Some(r) = alerts.try_receive()? {
            let a = *r.payload();
            if !tty {
                let rel = (a.header.gps_time_ns - t0.unwrap_or(a.header.gps_time_ns)) as f64 * 1e-9;
                writeln!(out, "alert {rel:.1} s: {}", a.reason())?;
            }
            v.alert(a);
        }
        if Instant::now() >= next_draw {
            next_draw += period;
            if tty {
                write!(
                    out,
                    "\x1b[H\x1b[2J{}\n{attach}\n",
                    view::render(&v, t0.unwrap_or(0))
                )?;
            } else {
                writeln!(
                    out,
                    "{:5.1} s: attitude {} ownship {} traffic {} alerts {}",
                    start.elapsed().as_secs_f64(),
                    v.received[0],
                    v.received[1],
                    v.received[2],
                    v.received[3]
                )?;
            }
            out.flush()?;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    if !tty {
        write!(out, "{}", view::render(&v, t0.unwrap_or(0)))?;
    }
    writeln!(
        out,
        "vigil demo: {:.0} s, received attitude {}, ownship {}, traffic {}, alerts {}",
        start.elapsed().as_secs_f64(),
        v.received[0],
        v.received[1],
        v.received[2],
        v.received[3]
    )?;
    if v.received[0] == 0 {
        bail!(
            "no attitude reached the bus; vigil run's log:\n{}",
            tail(run_log, 10)
        );
    }
    Ok(())
}
