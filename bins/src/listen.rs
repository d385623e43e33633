//! `vigil listen TOPIC`: prints what one of vigil's iceoryx2 services publishes, as JSON Lines (a
//! debugging tool and a second-process consumer for tests), or with `--latency` the receive latency
//! statistics.
//!
//! Each line is the payload as serde writes it (units in the field names, NaN as `null`), preceded
//! by `topic` and `missed_before` (samples of that publisher missed just before this one: a gap in
//! `header.seq`). With `--latency` no sample is printed; one summary object is printed at the end:
//! latency from the publisher's `CLOCK_MONOTONIC` send stamp to reception, in microseconds.
//!
//! It stops after `--count` samples, after `--duration` seconds, or at SIGINT/SIGTERM.

use std::io::{self, BufWriter, Write};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Args;
use serde::Serialize;
use serde_json::{Map, Value};
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, FixedPayload, IntegrityPayload, OwnshipPayload,
    Topic,
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
    match args.topic {
        Topic::Attitude => listen::<AttitudePayload>(&mut bus, args, &mut out),
        Topic::Ownship => listen::<OwnshipPayload>(&mut bus, args, &mut out),
        Topic::Traffic => listen_traffic(&mut bus, args, &mut out),
        Topic::Integrity => listen::<IntegrityPayload>(&mut bus, args, &mut out),
        Topic::Alerts => listen::<AlertPayload>(&mut bus, args, &mut out),
    }
}

/// One received sample as `listen` needs it, whatever the topic's wire form.
struct Got {
    json: Value,
    missed_before: u64,
    latency_ns: u64,
}

fn listen<T: FixedPayload>(bus: &mut Bus, args: &ListenArgs, out: &mut impl Write) -> Result<()> {
    let mut sub = bus
        .subscriber::<T>()
        .with_context(|| format!("subscribing to {}", args.topic))?;
    let mut next = |wait: Option<Duration>| -> Result<Option<Got>> {
        if let Some(w) = wait {
            sub.wait(w)?;
            return Ok(None);
        }
        Ok(match sub.try_receive()? {
            Some(r) => Some(Got {
                json: serde_json::to_value(r.payload())?,
                missed_before: r.missed_before,
                latency_ns: r.latency_ns(),
            }),
            None => None,
        })
    };
    let latencies = listen_loop(bus, args, T::TOPIC, &mut next, out)?;
    finish(args, latencies, sub.missed(), out)
}

/// [`listen`] for the traffic picture (a header and a slice on the wire).
fn listen_traffic(bus: &mut Bus, args: &ListenArgs, out: &mut impl Write) -> Result<()> {
    let mut sub = bus.traffic_subscriber().context("subscribing to traffic")?;
    let mut next = |wait: Option<Duration>| -> Result<Option<Got>> {
        if let Some(w) = wait {
            sub.wait(w)?;
            return Ok(None);
        }
        Ok(match sub.try_receive()? {
            Some(r) => Some(Got {
                json: serde_json::to_value(&r)?,
                missed_before: r.missed_before,
                latency_ns: r.latency_ns(),
            }),
            None => None,
        })
    };
    let latencies = listen_loop(bus, args, Topic::Traffic, &mut next, out)?;
    finish(args, latencies, sub.missed(), out)
}

/// Receives until the count, the deadline or a signal: `next(None)` takes a sample,
/// `next(Some(timeout))` waits for the publisher's wake-up. Returns the receive latencies (ns)
/// with `--latency`.
fn listen_loop(
    bus: &mut Bus,
    args: &ListenArgs,
    topic: Topic,
    next: &mut dyn FnMut(Option<Duration>) -> Result<Option<Got>>,
    out: &mut impl Write,
) -> Result<Vec<u64>> {
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
    'outer: loop {
        while let Some(r) = next(None)? {
            seen += 1;
            if args.latency {
                latencies.push(r.latency_ns);
            } else {
                let mut line = Map::new();
                line.insert("topic".into(), Value::from(topic.as_str()));
                line.insert("missed_before".into(), Value::from(r.missed_before));
                if let Value::Object(fields) = r.json {
                    line.extend(fields);
                }
                serde_json::to_writer(&mut *out, &line)?;
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
        bus.cleanup_if_due();
        // Wake on the publisher's event; the timeout bounds the reaction to a signal or deadline.
        next(Some(Duration::from_millis(100)))?;
    }
    Ok(latencies)
}

/// With `--latency`, prints the statistics of the samples received; flushes.
fn finish(args: &ListenArgs, latencies: Vec<u64>, missed: u64, out: &mut impl Write) -> Result<()> {
    if args.latency {
        match LatencyStats::from_ns(latencies, missed) {
            Some(stats) => serde_json::to_writer(&mut *out, &stats)?,
            None => out.write_all(b"{\"samples\":0}")?,
        }
        out.write_all(b"\n")?;
    }
    out.flush()?;
    Ok(())
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
