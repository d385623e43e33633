//! `vigil`: the one command-line program (decode and geometry now; run, demo, sim, record, replay
//! and listen as their issues land).

mod decode;
mod geometry;

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
    /// Decode a raw byte stream from one device into JSON Lines (one object per message).
    Decode(decode::DecodeArgs),
    /// DO-365 well-clear geometry of ownship/intruder pairs (JSON Lines in and out).
    Geometry(geometry::GeometryArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Decode(args) => decode::run(&args),
        Command::Geometry(args) => geometry::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("vigil: error: {e:#}");
            ExitCode::from(2)
        }
    }
}
