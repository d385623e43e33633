//! `vigil listen TOPIC`: prints what one of vigil's iceoryx2 services publishes, as JSON Lines (a
//! debugging tool and a second-process consumer for tests), or with `--latency` the receive latency
//! statistics.
//!
//! Each line is the payload as serde writes it (units in the field names, NaN as `null`), preceded
//! by `topic` and `missed_before` (samples of that publisher missed just before this one: a gap in
//! `header.seq`), with vigil's JSON names (`vigil_service::json_names`): addresses as six hex digits,
//! codes (alert level, severity, state, address type, ...) as words, and beside every GPS time
//! (`header.gps_time_ns`, `raised_gps_ns`) its UTC (`time_utc`, `raised_utc`). With `--latency`
//! no sample is printed; one summary object is printed at the end: latency from the publisher's
//! `CLOCK_MONOTONIC` send stamp to reception, in microseconds.
//!
//! It stops after `--count` samples, after `--duration` seconds, or at SIGINT/SIGTERM (quietly,
//! exit status 0). When nothing has arrived after 2 s and no publisher is connected, it says so on
//! stderr, with the prefixes under which vigil services do run (a wrong `--prefix` is the usual
//! cause), and goes on waiting.
//!
//! `vigil listen alerts` prints the active set first (issue 25): one line per alert raised or
//! latched now, from the latest `vigil/integrity` report (`"active": true`, `alert_id`,
//! `severity`, `state`, `raised_gps_ns`, `reason`, and `as_of_gps_ns`, the report's time, each
//! GPS time with its `_utc`), then the
//! transitions. It waits up to 2 s for a report (`vigil run` publishes one a second); without one
//! it says so on stderr and goes on with the transitions. The lines count towards `--count`.

use std::io::{self, BufWriter, Write};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;
use serde_json::{Map, Value};
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, IntegrityPayload, OwnshipPayload, Payload,
    Subscriber, Topic, TopicSubscriber, TrafficSubscriber,
};

/// Arguments of `vigil listen`.
#[derive(Debug, Args)]
pub struct ListenArgs {
    /// Topic: attitude, ownship, traffic, integrity or alerts.
    pub topic: Topic,
    /// Deployment prefix of the service names (as in the publisher's configuration).
    #[arg(long, default_value = "")]
    pub prefix: String,
    /// Stop after this many samples.
    #[arg(long)]
    pub count: Option<u64>,
    /// Stop after this many seconds.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Print receive latency statistics at the end instead of the samples.
    #[arg(long)]
    pub latency: bool,
    /// Subscribe in the bus's lossless mode, to receive every sample of a `vigil replay
    /// --publish --speed max` (see `BusConfig::lossless_wait_s`).
    #[arg(long)]
    pub lossless: bool,
    /// Receive from `vigil bridge` over Zenoh at this endpoint (e.g. `tcp/127.0.0.1:7447`)
    /// instead of from iceoryx2 on this host (cargo feature `bridge`).
    #[cfg(feature = "bridge")]
    #[arg(long, value_name = "ENDPOINT")]
    pub zenoh: Option<String>,
    /// With `--zenoh`: the vehicle whose topic to receive (`*`: every vehicle).
    #[cfg(feature = "bridge")]
    #[arg(long, default_value = "*", requires = "zenoh")]
    pub vehicle: String,
    /// With `--zenoh` on a `tls/` endpoint: the CA certificate that signed the bridge's.
    #[cfg(feature = "bridge")]
    #[arg(long, requires = "zenoh", value_name = "PEM")]
    pub zenoh_ca: Option<std::path::PathBuf>,
}

/// Receive latency summary, us.
#[derive(Debug, Serialize, PartialEq)]
pub struct LatencyStats {
    /// Samples measured.
    pub samples: usize,
    /// Samples missed (sequence gaps).
    pub missed: u64,
    /// Smallest latency, us.
    pub min_us: f64,
    /// Median, us.
    pub p50_us: f64,
    /// 90th percentile, us.
    pub p90_us: f64,
    /// 99th percentile, us.
    pub p99_us: f64,
    /// Largest, us.
    pub max_us: f64,
    /// Mean, us.
    pub mean_us: f64,
}

impl LatencyStats {
    /// Statistics of `latencies_ns` (nearest-rank percentiles); `None` when empty.
    pub fn from_ns(mut latencies_ns: Vec<u64>, missed: u64) -> Option<Self> {
        if latencies_ns.is_empty() {
            return None;
        }
        latencies_ns.sort_unstable();
        let n = latencies_ns.len();
        // Nearest rank: the smallest value with at least p% of the samples at or below it.
        let rank = |p: f64| {
            let r = ((p / 100.0) * n as f64).ceil() as usize;
            latencies_ns[r.clamp(1, n) - 1] as f64 / 1000.0
        };
        let sum: u128 = latencies_ns.iter().map(|&v| u128::from(v)).sum();
        Some(Self {
            samples: n,
            missed,
            min_us: latencies_ns[0] as f64 / 1000.0,
            p50_us: rank(50.0),
            p90_us: rank(90.0),
            p99_us: rank(99.0),
            max_us: latencies_ns[n - 1] as f64 / 1000.0,
            mean_us: sum as f64 / n as f64 / 1000.0,
        })
    }
}

/// Runs `vigil listen`.
pub fn run(args: &ListenArgs) -> Result<()> {
    let mut bus = Bus::new(&BusConfig {
        prefix: args.prefix.clone(),
        node_name: "vigil-listen".to_string(),
        handle_signals: true,
        lossless_wait_s: args.lossless.then_some(5.0),
        ..BusConfig::default()
    })
    .context("connecting to the bus")?;
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    #[cfg(feature = "bridge")]
    if let Some(endpoint) = &args.zenoh {
        return crate::bridge::listen_remote(
            &bus,
            endpoint,
            args.zenoh_ca.as_deref(),
            &args.vehicle,
            args,
            &mut out,
        );
    }
    match args.topic {
        Topic::Attitude => listen::<Subscriber<AttitudePayload>>(&mut bus, args, &mut out),
        Topic::Ownship => listen::<Subscriber<OwnshipPayload>>(&mut bus, args, &mut out),
        Topic::Traffic => listen::<TrafficSubscriber>(&mut bus, args, &mut out),
        Topic::Integrity => listen::<Subscriber<IntegrityPayload>>(&mut bus, args, &mut out),
        Topic::Alerts => listen::<Subscriber<AlertPayload>>(&mut bus, args, &mut out),
    }
}

fn listen<S: TopicSubscriber>(
    bus: &mut Bus,
    args: &ListenArgs,
    out: &mut impl Write,
) -> Result<()> {
    let topic = <S::Payload as Payload>::TOPIC;
    let mut sub = S::open(bus).with_context(|| format!("subscribing to {}", args.topic))?;
    // On stderr, so a script (or test) can wait for it before starting the publisher.
    eprintln!(
        "vigil listen: subscribed to {}",
        topic.service_name(bus.prefix())
    );
    let deadline = args
        .duration
        .map(|s| Instant::now() + Duration::from_secs_f64(s.max(0.0)));
    let mut latencies = Vec::new();
    let mut seen = 0u64;
    // When nothing has arrived and nothing publishes after this long, say so once (a wrong
    // prefix is the usual cause) instead of waiting in silence.
    let mut silence_check = Some(Instant::now() + NO_PUBLISHER_AFTER);
    if topic == Topic::Alerts && !args.latency {
        // Subscribed to the transitions first: none is lost between the set and them.
        seen = print_active(bus, out)?;
        if args.count.is_some_and(|c| seen >= c) {
            out.flush()?;
            return Ok(());
        }
    }
    'outer: loop {
        while let Some(r) = sub.receive_copy()? {
            seen += 1;
            if args.latency {
                latencies.push(r.latency_ns());
            } else {
                serde_json::to_writer(&mut *out, &json_line(topic, r.missed_before, &r.payload)?)?;
                out.write_all(b"\n")?;
                // Flushed per sample: a consumer process reads the lines as they come.
                out.flush()?;
            }
            if args.count.is_some_and(|c| seen >= c) {
                break 'outer;
            }
        }
        if bus.termination_requested() || deadline.is_some_and(|d| Instant::now() >= d) {
            break;
        }
        if silence_check.is_some_and(|t| Instant::now() >= t) {
            silence_check = None;
            if seen == 0 && sub.publishers() == 0 {
                eprintln!("{}", no_publisher_hint(bus, topic));
            }
        }
        bus.cleanup_if_due();
        // Wake on the publisher's event; the timeout bounds the reaction to a signal or deadline.
        sub.wait(Duration::from_millis(100))?;
    }
    if args.latency {
        match LatencyStats::from_ns(latencies, sub.missed()) {
            Some(stats) => serde_json::to_writer(&mut *out, &stats)?,
            None => out.write_all(b"{\"samples\":0}")?,
        }
        out.write_all(b"\n")?;
    }
    out.flush()?;
    Ok(())
}

/// The JSON line of one sample: `topic`, `missed_before`, then the payload's fields (the same
/// for `vigil listen` and `vigil bridge`).
pub fn json_line<P: Serialize>(topic: Topic, missed_before: u64, payload: &P) -> Result<Value> {
    let mut line = Map::new();
    line.insert("topic".into(), Value::from(topic.as_str()));
    line.insert("missed_before".into(), Value::from(missed_before));
    // The payload's fields with vigil's JSON names (hex addresses, words, UTC beside GPS times).
    if let Value::Object(fields) = vigil_service::json_names::named_value(payload)? {
        line.extend(fields);
    }
    Ok(Value::Object(line))
}

/// How long `vigil listen` waits for a first sample before it checks for a publisher.
const NO_PUBLISHER_AFTER: Duration = Duration::from_secs(2);

/// What `vigil listen` says when nothing publishes on its service: the service, and the
/// prefixes under which vigil services do exist on this host (as `--prefix` options to copy).
fn no_publisher_hint(bus: &Bus, topic: Topic) -> String {
    let service = topic.service_name(bus.prefix());
    let prefixes = match bus.prefixes_in_use() {
        Ok(p) => p,
        Err(e) => {
            return format!(
                "vigil listen: nothing publishes on {service}; still waiting (the services on \
                 this host could not be listed: {e})"
            );
        }
    };
    let others: Vec<String> = prefixes
        .into_iter()
        .filter(|p| p != bus.prefix())
        .map(|p| {
            if p.is_empty() {
                format!("vigil listen {topic}")
            } else {
                format!("vigil listen {topic} --prefix {p}")
            }
        })
        .collect();
    if others.is_empty() {
        format!(
            "vigil listen: nothing publishes on {service} (no vigil service runs on this host); \
             still waiting"
        )
    } else {
        format!(
            "vigil listen: nothing publishes on {service}; still waiting. vigil services exist \
             under other prefixes: {}",
            others.join(" | ")
        )
    }
}

/// How long `vigil listen alerts` waits for an integrity report holding the active set.
const ACTIVE_WAIT: Duration = Duration::from_secs(2);

/// Prints the active alert set of the latest integrity report (issue 25); returns the lines
/// printed.
fn print_active(bus: &mut Bus, out: &mut impl Write) -> Result<u64> {
    let mut sub = bus
        .subscriber::<IntegrityPayload>()
        .context("subscribing to integrity (the active alert set)")?;
    let deadline = Instant::now() + ACTIVE_WAIT;
    let report = loop {
        let mut latest = None;
        while let Some(r) = sub.try_receive()? {
            latest = Some(*r.payload());
        }
        if latest.is_some() || Instant::now() >= deadline || bus.termination_requested() {
            break latest;
        }
        sub.wait(Duration::from_millis(100))?;
    };
    let Some(report) = report else {
        eprintln!(
            "vigil listen: no integrity report within {} s: the active alert set is unknown",
            ACTIVE_WAIT.as_secs()
        );
        return Ok(0);
    };
    let mut n = 0;
    for line in active_lines(&report)? {
        serde_json::to_writer(&mut *out, &line)?;
        out.write_all(b"\n")?;
        n += 1;
    }
    if report.active_alert_total > report.active_alert_count {
        eprintln!(
            "vigil listen: {} more active alerts did not fit in the report",
            report.active_alert_total - report.active_alert_count
        );
    }
    out.flush()?;
    Ok(n)
}

/// One line per alert active in `report` (`"active": true`, `as_of_gps_ns`, then the alert's
/// fields), as `vigil listen alerts` prints them first and `vigil bridge` serves them.
pub fn active_lines(report: &IntegrityPayload) -> Result<Vec<Value>> {
    report
        .active_alerts()
        .iter()
        .map(|a| {
            let mut line = Map::new();
            line.insert("topic".into(), Value::from(Topic::Alerts.as_str()));
            line.insert("active".into(), Value::from(true));
            line.insert(
                "as_of_gps_ns".into(),
                Value::from(report.header.gps_time_ns),
            );
            if let Value::Object(fields) = vigil_service::json_names::named_value(a)? {
                line.extend(fields);
            }
            // `as_of_gps_ns` is added here: its UTC sibling too.
            let mut line = Value::Object(line);
            vigil_service::json_names::normalise(&mut line);
            Ok(line)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::LatencyStats;

    #[test]
    fn nearest_rank_percentiles() {
        // 1..=100 us: p50 is the 50th value, p90 the 90th, p99 the 99th; mean 50.5.
        let v: Vec<u64> = (1..=100).rev().map(|us| us * 1000).collect();
        let s = LatencyStats::from_ns(v, 3).unwrap();
        assert_eq!((s.samples, s.missed), (100, 3));
        assert_eq!(
            (s.min_us, s.p50_us, s.p90_us, s.p99_us, s.max_us),
            (1.0, 50.0, 90.0, 99.0, 100.0)
        );
        assert!((s.mean_us - 50.5).abs() < 1e-9);
        assert!(LatencyStats::from_ns(Vec::new(), 0).is_none());
    }
}
