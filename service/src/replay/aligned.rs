//! `vigil replay FILE.mcap --emit aligned`: every decoded message on GPS time (issue 7, "Output").
//!
//! One JSON line per input message, in the order the aligner finalises them (BAHRS pairing and the
//! host-clock wait reorder them; `index` joins them back): `device`, `index` (0-based per device,
//! the truth file's `index` while nothing of the device was lost), `t_gps_ns`, `sigma_ns`,
//! `time_source`, `status` (unlocked / locking / locked / coasting) for aligned samples, or
//! `not_aligned` (the reason) with the three time fields null. Every message comes out once.
//!
//! Decoding and alignment are fusion's ingest stage ([`Ingest`]): every port through the drivers'
//! `PortDecoder`, chosen once per port by the protocol table, each message's receive time that of
//! the read holding its last byte.

use std::io::Write;

use anyhow::Result;
use serde::Serialize;
use vigil_fusion::ingest::Ingest;
use vigil_fusion::time::aligner::AlignedSample;
use vigil_fusion::time::{ClockStatus, NotAligned, TimeSource};
use vigil_record::{Recorded, read_recording_from};

use crate::replay::ReplaySummary;

/// One output line.
#[derive(Debug, Serialize)]
pub struct AlignedLine {
    /// Device name.
    pub device: &'static str,
    /// 0-based per-device input index.
    pub index: u64,
    /// GPS time, ns since 1980-01-06, or null.
    pub t_gps_ns: Option<i64>,
    /// 1-sigma, ns, or null.
    pub sigma_ns: Option<f64>,
    /// Where the time came from, or null.
    pub time_source: Option<TimeSource>,
    /// Clock model state, or null.
    pub status: Option<ClockStatus>,
    /// Why there is no time, or null.
    pub not_aligned: Option<NotAligned>,
}

impl AlignedLine {
    /// The line of one aligned sample.
    pub fn of(s: &AlignedSample) -> Self {
        let (t, why) = match s.aligned.time {
            Ok(a) => (Some(a), None),
            Err(e) => (None, Some(e)),
        };
        Self {
            device: s.device.name(),
            index: s.index,
            t_gps_ns: t.map(|a| a.t_gps_ns),
            sigma_ns: t.map(|a| a.sigma_ns),
            time_source: t.map(|a| a.source),
            status: t.map(|a| a.status),
            not_aligned: why,
        }
    }
}

/// Replays `mcap` through decoding and alignment, handing every aligned sample to `f` in the
/// order the aligner finalises them (also the front half of `vigil replay --emit fused`).
pub fn replay_aligned_with(
    mcap: impl std::io::Read,
    mut f: impl FnMut(&AlignedSample) -> Result<()>,
) -> Result<ReplaySummary> {
    let mut r = Ingest::new();
    let mut seen: Vec<String> = Vec::new();
    let outcome = read_recording_from(mcap, |m| -> Result<()> {
        let Recorded::Raw {
            device,
            protocol,
            t_host_ns,
            bytes,
            link,
        } = m
        else {
            return Ok(());
        };
        // The live service's pacing, as it modelled it, and the port's recorded baud, adapter
        // timer and stated transmit buffer (a channel's metadata: set once).
        if !seen.iter().any(|d| d == device) {
            seen.push(device.to_string());
            crate::link_settings_to(&mut r, device, protocol, &link);
        }
        r.feed(device, protocol, t_host_ns, bytes, &mut f)
    })?;
    let devices = r.finish(&mut f)?;
    Ok(ReplaySummary {
        kind: "summary",
        mcap_messages: outcome.messages,
        damage: outcome.damage,
        devices,
    })
}

/// Replays `mcap` into `out` as aligned JSON lines.
pub fn replay_aligned<W: Write>(mcap: impl std::io::Read, out: &mut W) -> Result<ReplaySummary> {
    replay_aligned_with(mcap, |s| {
        let v = crate::json_names::named_value(&AlignedLine::of(s))?;
        serde_json::to_writer(&mut *out, &v)?;
        out.write_all(b"\n")?;
        Ok(())
    })
}
