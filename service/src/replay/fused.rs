//! `vigil replay FILE.mcap --emit fused`: the fused outputs of a recording as JSON Lines
//! (issues 8, 9 and 20).
//!
//! The recording is streamed ([`vigil_record::read`]) through the very path of `vigil run`
//! ([`Service`]: decode, align, fuse, convert, monitor) with the recorded host receive times, and
//! the flight's configuration ([`crate::replay::config`]: `--config FILE`, else the one in the
//! recording's metadata, else `vigil run`'s defaults). The integrity report and the monitor are
//! evaluated every `status.integrity_period_s` of recorded host time, as `vigil run` does. One
//! line per output, each with its `kind`:
//! - `attitude_check`: one per BAHRS navigation sample (`t_gps_ns`, `fault`, `isolated`, the
//!   three units' values, pairwise differences, test ratios, verdicts, vote);
//! - `ownship`: the ownship at each fusion step (1 s grid of GPS time by default);
//! - `traffic`: the traffic picture at each fusion step, targets in priority order with their
//!   DO-365 geometry and filtered alert level;
//! - `alert` (issue 20): each alert transition of the monitor (`alert_id`, `rule`, `severity`,
//!   `state`, `reason`, ...), then after the transitions of one evaluation an `alerts_active` line
//!   with the active set.
//!
//! Prompt attitude outputs (`attitude_output = "prompt"`, `vigil run`'s default) are fed to the
//! monitor as in flight but not written: they repeat the check verdicts at the VN-200's rate.
//! Every line has vigil's JSON names (`crate::json_names`): addresses as six hex digits, alert
//! levels and severities as words, `t_utc` beside `t_gps_ns`, `lowc_interval_s`.
//! The output is a deterministic function of the file and the configuration.

use std::io::{Read, Write};

use anyhow::Result;
use serde_json::json;
use vigil_bus::AlertPayload;
use vigil_drivers::replay::PortSummary;
use vigil_fusion::pipeline::Fused;
use vigil_record::read_recording_from;
use vigil_record::{PortLink, Recorded};

use crate::config::{Config, Port, Protocol};
use crate::recording::messages::{ActiveAlert, state_name};
use crate::replay::ReplaySummary;
use crate::{Outputs, Service};

/// What a service replay hands its caller after each step.
#[derive(Debug, Clone, Copy)]
pub enum Step<'a> {
    /// A raw chunk, after processing.
    Chunk {
        /// Device name.
        device: &'a str,
        /// Its channel's protocol (may be empty).
        protocol: &'a str,
        /// Its channel's link (read interval, baud, adapter timer, stated buffer).
        link: PortLink,
        /// Host receive time, ns.
        t_host_ns: u64,
        /// The bytes.
        bytes: &'a [u8],
    },
    /// The integrity report and the monitor were evaluated.
    Tick,
}

/// Outputs that go nowhere (the replays read the service's tap instead).
pub struct Discard;

impl Outputs for Discard {
    fn publish<T: vigil_bus::Payload>(&mut self, _: &T) {}
}

/// Streams a recording through a [`Service`] configured by `cfg` (ports added as their channels
/// appear; chunks of a protocol vigil does not decode are counted and handed to `each` only),
/// calling `each` after every chunk and every evaluation tick. Returns the summary.
pub fn replay_service<R: Read>(
    input: R,
    cfg: &Config,
    service: &mut Service,
    out: &mut impl Outputs,
    mut each: impl FnMut(&mut Service, Step<'_>) -> Result<()>,
) -> Result<ReplaySummary> {
    let tick_ns = (cfg.status.integrity_period_s.max(1e-3) * 1e9) as u64;
    let mut devices: Vec<(String, Option<usize>, u64, u64)> = Vec::new();
    let mut next_tick: Option<u64> = None;
    let mut last = 0u64;
    let outcome = read_recording_from(input, |m| -> Result<()> {
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
        let k = match devices.iter().position(|d| d.0 == device) {
            Some(k) => k,
            None => {
                // Issue 18: the recorded link, the protocol's default baud where none is.
                let port = Protocol::resolve(protocol, device)
                    .map(|protocol| service.add_port(&Port::recorded(device, protocol, &link)));
                if let Some(i) = port {
                    service.handle_link(i, true, t_host_ns);
                }
                devices.push((device.to_string(), port, 0, 0));
                devices.len() - 1
            }
        };
        let next = next_tick.get_or_insert(t_host_ns.saturating_add(tick_ns));
        while *next <= t_host_ns {
            let t = *next;
            service.handle_timeout(t, out);
            each(service, Step::Tick)?;
            *next += tick_ns;
        }
        last = last.max(t_host_ns);
        let d = &mut devices[k];
        d.2 += 1;
        d.3 += bytes.len() as u64;
        if let Some(i) = d.1 {
            service.handle_chunk(i, t_host_ns, bytes, out);
        }
        each(
            service,
            Step::Chunk {
                device,
                protocol,
                link,
                t_host_ns,
                bytes,
            },
        )
    })?;
    service.finish(last, out);
    service.handle_timeout(last, out);
    each(service, Step::Tick)?;
    let devices = devices
        .iter()
        .map(|(name, port, chunks, bytes)| {
            let s = match port.and_then(|_| service.port_stats(name)) {
                Some(stats) => PortSummary::Decoded(stats),
                None => PortSummary::NoDecoder {
                    no_decoder: true,
                    chunks: *chunks,
                    bytes: *bytes,
                },
            };
            (name.clone(), s)
        })
        .collect();
    Ok(ReplaySummary {
        kind: "summary",
        mcap_messages: outcome.messages,
        damage: outcome.damage,
        devices,
    })
}

/// One output of the fused replay.
#[derive(Debug, Clone, Copy)]
pub enum FusedEvent<'a> {
    /// A fusion output.
    Fused(&'a Fused),
    /// The alert transitions of one monitor evaluation and the active set after them.
    Alerts(&'a [AlertPayload], &'a [ActiveAlert]),
}

/// Replays `input` through the service configured by `cfg`, handing every fused output and
/// alert evaluation to `f` in order.
pub fn replay_fused_with<R: Read>(
    input: R,
    cfg: &Config,
    mut f: impl FnMut(FusedEvent<'_>) -> Result<()>,
) -> Result<ReplaySummary> {
    let mut service = Service::new(
        &[],
        cfg.pipeline.pipeline_config(),
        cfg.monitor,
        cfg.link.silence_s,
    )?;
    service.set_tap(true, false);
    let mut drain = |s: &mut Service| -> Result<()> {
        for (_, t) in s.drain_tap() {
            match &t {
                crate::recording::Tapped::Fused(x) => f(FusedEvent::Fused(x))?,
                crate::recording::Tapped::Alerts(a, active) => f(FusedEvent::Alerts(a, active))?,
                _ => {}
            }
        }
        Ok(())
    };
    let summary = replay_service(input, cfg, &mut service, &mut Discard, |s, _| drain(s))?;
    drain(&mut service)?;
    Ok(summary)
}

/// The JSON line of an alert transition.
pub fn alert_line(a: &AlertPayload) -> serde_json::Value {
    let mut v = json!({
        "kind": "alert",
        "t_gps_ns": a.header.gps_time_ns,
        "alert_id": a.alert_id,
        "rule": vigil_monitor::Rule::of_alert(a.alert_id).map(|r| r.name()),
        "severity": a.severity,
        "state": state_name(a.state),
        "raised_gps_ns": a.raised_gps_ns,
        "reason": a.reason(),
    });
    crate::json_names::normalise(&mut v);
    v
}

/// The JSON line of the active set after an evaluation at GPS time `t_gps_ns`.
pub fn active_line(t_gps_ns: i64, active: &[ActiveAlert]) -> serde_json::Value {
    let mut v = json!({
        "kind": "alerts_active",
        "t_gps_ns": t_gps_ns,
        "active": active,
    });
    crate::json_names::normalise(&mut v);
    v
}

/// Replays `input` into `out` as fused JSON lines.
pub fn replay_fused<R: Read, W: Write>(
    input: R,
    cfg: &Config,
    out: &mut W,
) -> Result<ReplaySummary> {
    // Each line is serialised into one reused buffer and written at once: serde_json's many
    // small writes are cheaper into a Vec than through a `Write` adapter.
    let mut line = Vec::with_capacity(1 << 14);
    replay_fused_with(input, cfg, |e| {
        line.clear();
        match e {
            FusedEvent::Fused(Fused::Prompt(_)) => return Ok(()),
            FusedEvent::Fused(o) => {
                let v = crate::json_names::named_value(o)?;
                serde_json::to_writer(&mut line, &v)?
            }
            FusedEvent::Alerts(alerts, active) => {
                for a in alerts {
                    serde_json::to_writer(&mut line, &alert_line(a))?;
                    line.push(b'\n');
                }
                let t = alerts.last().map_or(0, |a| a.header.gps_time_ns);
                serde_json::to_writer(&mut line, &active_line(t, active))?;
            }
        }
        line.push(b'\n');
        out.write_all(&line)?;
        Ok(())
    })
}
