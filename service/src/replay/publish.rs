//! `vigil replay FILE.mcap --publish [--speed X|max] [--prefix P]` (issue 11): a recorded flight
//! published on the same iceoryx2 services and payloads as `vigil run`, so a DAA stack runs its
//! regression tests against recordings with no hardware and no code change.
//!
//! The recording's raw chunks go through the very path of `vigil run` ([`Service`]: decode,
//! align, fuse, convert, monitor), fed with the recorded host receive times; the integrity report
//! and the monitor are ticked on the recorded host clock every `tick_s`. Everything published is
//! therefore a function of the recording: the GPS times, the payloads and the sequence numbers
//! (one per sample sent, from 1) are the same on every replay. Only `header.send_mono_ns`, the
//! host time of the send (for latency measurements), differs.
//!
//! Pacing: `--speed X` (default 1) sleeps so that chunks go out at X times their recorded pace;
//! `--speed max` does not sleep and switches the bus to its lossless mode
//! ([`BusConfig::lossless_wait_s`]): a publisher whose subscriber's buffer is full waits for it
//! (up to 5 s per sample), so a subscriber that keeps up receives every sample. Its subscribers
//! must use the lossless mode too (same prefix, `lossless_wait_s: Some(..)`).

use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow, bail};
use vigil_bus::{Bus, BusConfig};
use vigil_monitor::MonitorParams;
use vigil_record::{Recorded, read_recording};

use crate::config::{PipelineSection, Port, Protocol};
use crate::runtime::live::BusOutputs;
use crate::{Outputs, Service};

/// How fast to replay.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Speed {
    /// This multiple of the recorded pace.
    Times(f64),
    /// As fast as the subscribers keep up (lossless bus mode).
    Max,
}

impl Speed {
    /// Parses `--speed`: a positive number or `max`.
    pub fn parse(s: Option<&str>) -> Result<Self> {
        match s {
            None => Ok(Speed::Times(1.0)),
            Some("max") => Ok(Speed::Max),
            Some(x) => match x.parse::<f64>() {
                Ok(v) if v.is_finite() && v > 0.0 => Ok(Speed::Times(v)),
                _ => bail!("--speed must be a positive number or max, not {x:?}"),
            },
        }
    }
}

/// Period of the integrity report and the monitor's evaluation, on the recorded host clock.
const TICK_NS: u64 = 1_000_000_000;
/// Lossless mode: longest wait for one subscriber per sample, s.
const LOSSLESS_WAIT_S: f64 = 5.0;

/// What a publishing replay did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PublishSummary {
    /// Raw chunks replayed.
    pub chunks: u64,
    /// Traffic payloads published.
    pub traffic: u64,
    /// Attitude payloads published.
    pub attitude: u64,
    /// Alert payloads published.
    pub alerts: u64,
}

/// The ports of a recording, in the order their channels first appear.
fn ports(mcap: &[u8]) -> Result<Vec<Port>> {
    let mut ports: Vec<Port> = Vec::new();
    read_recording(mcap, |m| -> Result<()> {
        if let Recorded::Raw {
            device,
            protocol,
            link,
            ..
        } = m
            && !ports.iter().any(|p| p.device == device)
        {
            let protocol = Protocol::resolve(protocol, device).ok_or_else(|| {
                anyhow!("channel {device}: protocol {protocol:?} is not one vigil decodes")
            })?;
            // The recorded link (issue 18), as `vigil replay` uses it.
            ports.push(Port::recorded(device, protocol, &link));
        }
        Ok(())
    })?;
    if ports.is_empty() {
        bail!("the recording has no raw device channel");
    }
    Ok(ports)
}

/// Replays `mcap` through the service onto `out`, calling `pace(t_host_ns)` before each chunk.
pub fn replay_into(
    mcap: &[u8],
    out: &mut impl Outputs,
    mut pace: impl FnMut(u64) -> Result<()>,
) -> Result<crate::Counters> {
    let ports = ports(mcap)?;
    // `vigil run`'s default fusion parameters (prompt attitude outputs included).
    let mut service = Service::new(
        &ports,
        PipelineSection::default().pipeline_config(),
        MonitorParams::default(),
        2.0,
    )?;
    let mut opened = vec![false; ports.len()];
    let mut next_tick: Option<u64> = None;
    let mut last = 0u64;
    read_recording(mcap, |m| -> Result<()> {
        let Recorded::Raw {
            device,
            t_host_ns,
            bytes,
            ..
        } = m
        else {
            return Ok(());
        };
        let Some(i) = ports.iter().position(|p| p.device == device) else {
            return Ok(());
        };
        pace(t_host_ns)?;
        let next = next_tick.get_or_insert(t_host_ns + TICK_NS);
        while *next <= t_host_ns {
            service.handle_timeout(*next, out);
            *next += TICK_NS;
        }
        if !opened[i] {
            opened[i] = true;
            service.handle_link(i, true, t_host_ns);
        }
        service.handle_chunk(i, t_host_ns, bytes, out);
        last = last.max(t_host_ns);
        Ok(())
    })?;
    service.finish(last, out);
    service.handle_timeout(last, out);
    Ok(*service.counters())
}

/// Runs `vigil replay FILE --publish`.
pub fn run(input: &Path, mcap: &[u8], prefix: &str, speed: Speed) -> Result<PublishSummary> {
    let bus = Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: "vigil-replay".to_string(),
        handle_signals: true,
        lossless_wait_s: (speed == Speed::Max).then_some(LOSSLESS_WAIT_S),
        ..BusConfig::default()
    })
    .context("connecting to the bus")?;
    let mut out = BusOutputs::new(&bus).context("creating the publishers")?;
    let mut origin: Option<(u64, Instant)> = None;
    let counters = replay_into(mcap, &mut out, |t| {
        if bus.termination_requested() {
            bail!("interrupted");
        }
        if let Speed::Times(x) = speed {
            let (t0, wall0) = *origin.get_or_insert((t, Instant::now()));
            let due = Duration::from_secs_f64(t.saturating_sub(t0) as f64 / 1e9 / x);
            if let Some(wait) = due.checked_sub(wall0.elapsed()) {
                std::thread::sleep(wait);
            }
        }
        Ok(())
    })
    .with_context(|| format!("replaying {}", input.display()))?;
    Ok(PublishSummary {
        chunks: counters.chunks,
        traffic: counters.traffic,
        attitude: counters.attitude,
        alerts: counters.alerts,
    })
}
