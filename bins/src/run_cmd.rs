//! `vigil run` and `vigil config`: the command line of the live service
//! (`vigil_service::runtime::live`) and of its configuration (`vigil_service::config`).

use std::path::PathBuf;

use anyhow::{Result, bail};
use clap::Args;
use vigil_service::config::Config;

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

/// Runs `vigil run`.
pub fn run(args: &RunArgs) -> Result<()> {
    crate::init_logging();
    if args.duration.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
        bail!("--duration must be a positive number of seconds");
    }
    let (config, ports) = Config::load(&args.config)?;
    vigil_service::runtime::live::run(config, ports, args.duration)
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
        print!("{}", vigil_service::config::example());
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
