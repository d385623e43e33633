//! The configuration a replay runs with (issue 20, "Replay is the flight again"): `--config FILE`
//! (a `vigil run` configuration), else the configuration recorded in the file's `vigil.run`
//! metadata by the `vigil run` that made it, else `vigil run`'s defaults (a simulator's recording
//! or one made before issue 20). Its pipeline, monitor, link and status sections are used; the
//! ports come from the recording's channels.

use std::fs::File;
use std::io::BufReader;
use std::path::Path;

use anyhow::{Context, Result};
use vigil_record::read_metadata_from;

use crate::config::Config;
use crate::recording::METADATA_RUN;

/// Where a replay's configuration came from.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum ConfigSource {
    /// `--config FILE`.
    File(String),
    /// The recording's `vigil.run` metadata.
    Recording,
    /// `vigil run`'s defaults.
    Defaults,
}

/// The configuration recorded in a recording's metadata, if any (an unparsable one is an error:
/// replaying with other parameters than the flight's without saying so would mislead).
pub fn recorded_config(input: &Path) -> Result<Option<Config>> {
    let file = File::open(input).with_context(|| format!("cannot read {}", input.display()))?;
    let Some(meta) = read_metadata_from(BufReader::new(file), METADATA_RUN) else {
        return Ok(None);
    };
    let Some(text) = meta.get("config_toml") else {
        return Ok(None);
    };
    let c = Config::parse(text)
        .with_context(|| format!("{}: the recorded configuration", input.display()))?;
    Ok(Some(c))
}

/// The configuration of a replay of `input`: `explicit`, else the recorded one, else defaults.
pub fn replay_config(explicit: Option<&Path>, input: &Path) -> Result<(Config, ConfigSource)> {
    if let Some(path) = explicit {
        let (c, _) = Config::load(path)?;
        return Ok((c, ConfigSource::File(path.display().to_string())));
    }
    Ok(match recorded_config(input)? {
        Some(c) => (c, ConfigSource::Recording),
        None => (Config::default(), ConfigSource::Defaults),
    })
}
