//! `vigil`: the one command-line program (run, demo, monitor, config, decode, geometry, sim,
//! record, replay, listen).

mod bridge;
mod cli_values;
mod decode;
#[cfg(target_os = "linux")]
mod demo;
mod geometry;
mod info;
mod listen;
#[cfg(target_os = "linux")]
mod measure;
#[cfg(target_os = "linux")]
mod measure_floor;
mod monitor_cmd;
mod progress;
mod record_cmd;
mod replay;
#[cfg(target_os = "linux")]
mod run_cmd;
mod sim_cmd;
#[cfg(target_os = "linux")]
mod sim_live;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// vigil: sensor fusion and integrity monitoring for small unmanned aircraft.
#[derive(Debug, Parser)]
#[command(name = "vigil", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// The whole system on one machine: simulator on pseudo-terminals, `vigil run`, live view.
    #[cfg(target_os = "linux")]
    Demo(demo::DemoArgs),
    /// Decode a raw byte stream from one device into JSON Lines (one object per message).
    Decode(decode::DecodeArgs),
    /// DO-365 well-clear geometry of ownship/intruder pairs (JSON Lines in and out).
    Geometry(geometry::GeometryArgs),
    /// Simulate a scenario into an MCAP recording (and a truth JSON Lines file).
    Sim(sim_cmd::SimArgs),
    /// Record live serial ports into an MCAP file (Ctrl-C ends it cleanly).
    Record(record_cmd::RecordArgs),
    /// Decode a recording's raw chunks into JSON Lines (device, index, host receive time, message).
    Replay(replay::ReplayArgs),
    /// Summarise a recording like `mcap info`: time range, chunks, channels with counts,
    /// rates and schemas, metadata.
    Info(info::InfoArgs),
    /// Print what a vigil iceoryx2 service publishes, as JSON Lines (or latency statistics).
    Listen(listen::ListenArgs),
    /// Publish a running vigil's topics on Zenoh as vigil/<vehicle>/<topic>, for other computers.
    #[cfg(feature = "bridge")]
    Bridge(bridge::BridgeArgs),
    /// The integrity monitor as a separate process: subscribes to the fused topics, publishes alerts.
    Monitor(monitor_cmd::MonitorArgs),
    /// Run the service: read the ports, fuse, publish on the bus, monitor, record.
    #[cfg(target_os = "linux")]
    Run(run_cmd::RunArgs),
    /// Print an example configuration (`--example`) or validate one (`--check FILE`).
    #[cfg(target_os = "linux")]
    Config(run_cmd::ConfigArgs),
    /// Measure `vigil run` on simulated ports: VN-200 byte to fused attitude latency at a
    /// subscriber in another process, CPU and memory.
    #[cfg(target_os = "linux")]
    Measure(measure::MeasureArgs),
    /// The reader `vigil measure --floor` starts in `vigil run`'s place (reads and discards).
    #[cfg(target_os = "linux")]
    #[command(hide = true)]
    MeasureFloor(measure_floor::FloorArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    demo::sweep_stale_temp_dirs();
    let result = match cli.command {
        #[cfg(target_os = "linux")]
        Command::Demo(args) => demo::run(&args),
        Command::Decode(args) => decode::run(&args),
        Command::Geometry(args) => geometry::run(&args),
        Command::Sim(args) => sim_cmd::run(&args),
        Command::Record(args) => record_cmd::run(&args),
        Command::Replay(args) => replay::run(&args),
        Command::Info(args) => info::run(&args),
        Command::Listen(args) => listen::run(&args),
        #[cfg(feature = "bridge")]
        Command::Bridge(args) => bridge::run(&args),
        Command::Monitor(args) => monitor_cmd::run(&args),
        #[cfg(target_os = "linux")]
        Command::Run(args) => run_cmd::run(&args),
        #[cfg(target_os = "linux")]
        Command::Config(args) => run_cmd::config(&args),
        #[cfg(target_os = "linux")]
        Command::Measure(args) => measure::run(&args),
        #[cfg(target_os = "linux")]
        Command::MeasureFloor(args) => measure_floor::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("vigil: error: {e:#}");
            ExitCode::from(2)
        }
    }
}

/// Logs to stderr at `info` (or as `RUST_LOG` says), coloured on a terminal.
pub fn init_logging() {
    let _ = tracing_subscriber::fmt()
        .with_writer(std::io::stderr)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_default_env()
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .try_init();
}
