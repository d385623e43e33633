//! `vigil replay FLIGHT.mcap --out RICH.mcap [--channels SET] [--config FILE]` (issue 20): the
//! recording written again with its decoded and fused channels, re-processed through the path of
//! `vigil run` ([`Service`]) with the flight's configuration. The raw channels are copied as they
//! are (every chunk, in receive order, with its host time), so RICH.mcap replays like the
//! original; the derived channels are what `vigil run` with `[record] channels = SET` would have
//! written (see `recording`), on the UTC timeline. Streams: one chunk in memory at a time.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::Path;

use anyhow::{Context, Result};
use vigil_record::RawRecorder;

use crate::Service;
use crate::config::Config;
use crate::recording::{ChannelSet, METADATA_RUN, RichRecorder, run_metadata};
use crate::replay::ReplaySummary;
use crate::replay::config::ConfigSource;
use crate::replay::fused::{Discard, Step, replay_service};

/// Writes `out` from `input` (see the module documentation).
pub fn replay_rich(
    input: &Path,
    cfg: &Config,
    source: &ConfigSource,
    out: &Path,
    set: ChannelSet,
) -> Result<ReplaySummary> {
    let reader = BufReader::with_capacity(
        1 << 16,
        File::open(input).with_context(|| format!("cannot read {}", input.display()))?,
    );
    let file = File::create(out).with_context(|| format!("cannot create {}", out.display()))?;
    let raw = RawRecorder::new(BufWriter::new(file), &[])?;
    let mut rec = RichRecorder::new(raw, set)?;
    let mut meta = run_metadata("vigil replay --out", &toml::to_string(cfg)?);
    meta.insert(
        "source_recording".to_string(),
        input
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
    );
    meta.insert(
        "config_source".to_string(),
        match source {
            ConfigSource::File(p) => format!("file {p}"),
            ConfigSource::Recording => "recording".to_string(),
            ConfigSource::Defaults => "defaults".to_string(),
        },
    );
    rec.write_metadata(METADATA_RUN, meta)?;
    let mut service = Service::new(
        &[],
        cfg.pipeline.pipeline_config(),
        cfg.monitor,
        cfg.link.silence_s,
    )?;
    service.set_tap(set.fused(), set.decoded());
    // Recorder port index of each device, in order of appearance.
    let mut ports: BTreeMap<String, u16> = BTreeMap::new();
    let summary = replay_service(reader, cfg, &mut service, &mut Discard, |s, step| {
        if let Step::Chunk {
            device,
            protocol,
            link,
            t_host_ns,
            bytes,
        } = step
        {
            let port = match ports.get(device) {
                Some(&p) => p,
                None => {
                    // The channel's timing metadata carries over (issue 18: a replay of the
                    // re-processed file aligns as the original's did).
                    let p = rec.add_port(device, protocol, &link)?;
                    ports.insert(device.to_string(), p);
                    p
                }
            };
            rec.set_clock(
                t_host_ns,
                s.utc_offset_ns(t_host_ns),
                s.clock_references_seen(),
            )?;
            rec.raw(port, t_host_ns, bytes)?;
        }
        for (t, x) in s.drain_tap() {
            rec.tapped(t, &x)?;
        }
        Ok(())
    })?;
    for (t, x) in service.drain_tap() {
        rec.tapped(t, &x)?;
    }
    let mut w = rec
        .finish()
        .with_context(|| format!("finishing {}", out.display()))?;
    w.flush()?;
    Ok(summary)
}
