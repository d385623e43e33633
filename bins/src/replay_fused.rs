//! `vigil replay FILE.mcap --emit fused`: the fused outputs of a recording as JSON Lines
//! (issues 8 and 9).
//!
//! The recording goes through the same path as `--emit aligned` ([`AlignedReplay`]) and then
//! through the fusion pipeline ([`Pipeline`]). One line per output, each with its `kind`:
//! - `attitude_check`: one per BAHRS navigation sample (`t_gps_ns`, `fault`, `isolated`, the
//!   three units' values, pairwise differences, test ratios, verdicts, vote);
//! - `ownship`: the ownship at each fusion step (1 s grid of GPS time by default);
//! - `traffic`: the traffic picture at each fusion step, targets in priority order with their
//!   DO-365 geometry and filtered alert level.
//!
//! The output is a deterministic function of the file.

use std::io::Write;

use anyhow::{Result, anyhow};
use vigil_fusion::magnetic::Wmm;
use vigil_fusion::pipeline::{Fused, Pipeline, PipelineConfig};

use crate::replay::ReplaySummary;
use crate::replay_aligned::replay_aligned_with;

/// Replays `mcap` through alignment and fusion, handing every output to `f` in order.
pub fn replay_fused_with(
    mcap: &[u8],
    cfg: PipelineConfig,
    mut f: impl FnMut(&Fused) -> Result<()>,
) -> Result<ReplaySummary> {
    let mut pipeline =
        Pipeline::new(cfg, Box::new(Wmm)).map_err(|e| anyhow!("pipeline parameters: {e}"))?;
    let mut buf: Vec<Fused> = Vec::new();
    let summary = replay_aligned_with(mcap, |s| {
        pipeline.handle(s, &mut buf);
        buf.drain(..).try_for_each(|o| f(&o))
    })?;
    pipeline.finish(&mut buf);
    buf.drain(..).try_for_each(|o| f(&o))?;
    Ok(summary)
}

/// Replays `mcap` into `out` as fused JSON lines.
pub fn replay_fused<W: Write>(mcap: &[u8], out: &mut W) -> Result<ReplaySummary> {
    replay_fused_with(mcap, PipelineConfig::default(), |o| {
        serde_json::to_writer(&mut *out, o)?;
        out.write_all(b"\n")?;
        Ok(())
    })
}

#[cfg(test)]
#[path = "fused_scenarios_tests.rs"]
mod scenario_tests;

#[cfg(test)]
#[path = "failsafe_scenarios_tests.rs"]
mod failsafe_tests;
