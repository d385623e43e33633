//! The bridge's runtime: iceoryx2 subscribers in, Zenoh publishers out.
//!
//! Per topic (key expression `vigil/<vehicle>/<topic>`):
//! - state topics (attitude, ownship, traffic, integrity): latest only. Each wake-up keeps the
//!   newest sample of each; it is sent when the topic's interval (`[bridge.rates]`) has passed
//!   since the last one sent, else it waits, replaced by any newer one: a slow link gets the
//!   newest state, never a backlog. Zenoh congestion control `drop`.
//! - alerts: every transition, at once, in order: congestion control `block`, priority
//!   real-time; never rate-limited.
//! - `alerts/active`: the active alert set (from the newest integrity report), published when it
//!   changes and answered to queries on the same key, so a ground station that joins late gets
//!   the active set (`z_get vigil/*/alerts/active`).
//!
//! Decision on waiting: by default the loop sleeps on the alerts topic's wake-up, bounded by
//! [`POLL`]: an alert goes out at once, a state sample waits up to about one poll period (8 ms
//! median, 16 ms at most, measured) for its send. Waking on every attitude sample instead (up
//! to 200 Hz at full rates) cost the other processes of a 2-core machine 30-50 us of median
//! wake-up latency, for nothing the rate-limited topics need. When every attitude sample is
//! forwarded (`attitude_hz = 0`), its latency is what was asked for: the loop then wakes on
//! each attitude sample (bounded by 5 ms) instead.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::Args;
use serde_json::Value;
use vigil_bus::payload::{type_name, wire_bytes};
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, Delivered, IntegrityPayload, OwnshipPayload,
    Payload, Subscriber, Target, Topic, TopicSubscriber, TrafficHeader, TrafficPayload,
    TrafficSubscriber,
};
use zenoh::Wait;
use zenoh::bytes::Encoding;
use zenoh::qos::{CongestionControl, Priority};

use vigil_service::config::Config;
use vigil_service::config::bridge::{BridgeEncoding, BridgeSection, ZenohMode};

use crate::listen::{active_lines, json_line};

/// Longest time a state sample waits for the bridge to look (see the module's decision).
const POLL: Duration = Duration::from_millis(10);

/// Arguments of `vigil bridge`.
#[derive(Debug, Args)]
pub struct BridgeArgs {
    /// Configuration file: its `[bus]` prefix and `[bridge]` section (default: the defaults).
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Bus prefix of the vigil to bridge (overrides `[bus] prefix`).
    #[arg(long)]
    pub prefix: Option<String>,
    /// Vehicle name (overrides `[bridge] vehicle`).
    #[arg(long)]
    pub vehicle: Option<String>,
    /// Zenoh endpoint to listen on (overrides `[bridge] listen`; repeatable).
    #[arg(long)]
    pub listen: Vec<String>,
    /// Zenoh endpoint to connect to (overrides `[bridge] connect`; repeatable).
    #[arg(long)]
    pub connect: Vec<String>,
    /// Stop after this many seconds (default: until SIGINT/SIGTERM).
    #[arg(long)]
    pub duration: Option<f64>,
}

/// Opens a Zenoh session with the section's settings.
fn open_session(settings: &[(&'static str, Value)]) -> Result<zenoh::Session> {
    let mut config = zenoh::Config::default();
    for (key, value) in settings {
        config
            .insert_json5(key, &value.to_string())
            .map_err(|e| anyhow::anyhow!("zenoh setting {key}: {e}"))?;
    }
    zenoh::open(config)
        .wait()
        .map_err(|e| anyhow::anyhow!("opening the Zenoh session: {e}"))
}

/// The raw bytes of a traffic picture: the `TrafficHeader` then `count` targets, as on iceoryx2.
fn raw_traffic(p: &TrafficPayload) -> Vec<u8> {
    let h = p.wire_header();
    let mut out = wire_bytes(&h).to_vec();
    for t in &p.targets {
        out.extend_from_slice(wire_bytes(t));
    }
    out
}

/// One topic's Zenoh side: publisher, rate limit, the sample waiting for its turn, counters.
struct Lane<'s> {
    topic: Topic,
    publisher: zenoh::pubsub::Publisher<'s>,
    min_interval: Duration,
    last_sent: Option<Instant>,
    pending: Option<Vec<u8>>,
    sent: u64,
    skipped: u64,
}

impl<'s> Lane<'s> {
    fn new(
        session: &'s zenoh::Session,
        vehicle: &str,
        topic: Topic,
        type_name: &str,
        encoding: BridgeEncoding,
        rate_hz: Option<f64>,
    ) -> Result<Self> {
        let key = format!("vigil/{vehicle}/{}", topic.as_str());
        let enc = match encoding {
            BridgeEncoding::Json => Encoding::APPLICATION_JSON,
            BridgeEncoding::Raw => Encoding::ZENOH_BYTES,
        }
        .with_schema(type_name);
        let builder = session.declare_publisher(key.clone()).encoding(enc);
        let publisher = match rate_hz {
            // Events: never dropped, sent before data.
            None => builder
                .congestion_control(CongestionControl::Block)
                .priority(Priority::RealTime),
            // State: a congested link drops, the next sample replaces.
            Some(_) => builder
                .congestion_control(CongestionControl::Drop)
                .priority(Priority::Data),
        }
        .express(true)
        .wait()
        .map_err(|e| anyhow::anyhow!("declaring the publisher {key}: {e}"))?;
        Ok(Self {
            topic,
            publisher,
            min_interval: rate_hz
                .filter(|&hz| hz > 0.0)
                .map_or(Duration::ZERO, |hz| Duration::from_secs_f64(1.0 / hz)),
            last_sent: None,
            pending: None,
            sent: 0,
            skipped: 0,
        })
    }

    /// Takes the newest encoded sample; an older one still waiting is skipped.
    fn offer(&mut self, bytes: Vec<u8>) {
        if self.pending.replace(bytes).is_some() {
            self.skipped += 1;
        }
    }

    /// Sends the waiting sample when the interval allows.
    fn flush(&mut self, now: Instant) -> Result<()> {
        if self.pending.is_none()
            || self
                .last_sent
                .is_some_and(|t| now.duration_since(t) < self.min_interval)
        {
            return Ok(());
        }
        let bytes = self.pending.take().unwrap_or_default();
        self.publisher
            .put(bytes)
            .wait()
            .map_err(|e| anyhow::anyhow!("put on {}: {e}", self.topic))?;
        self.last_sent = Some(now);
        self.sent += 1;
        Ok(())
    }
}

/// Encodes one delivered sample.
fn encode<P: Payload>(
    d: &Delivered<P>,
    encoding: BridgeEncoding,
    raw: impl Fn(&P) -> Vec<u8>,
) -> Result<Vec<u8>> {
    Ok(match encoding {
        BridgeEncoding::Json => {
            serde_json::to_vec(&json_line(P::TOPIC, d.missed_before, &d.payload)?)?
        }
        BridgeEncoding::Raw => raw(&d.payload),
    })
}

/// Drains `sub` into `lane`; returns the samples taken.
fn drain<S: TopicSubscriber>(
    sub: &mut S,
    lane: &mut Lane<'_>,
    encoding: BridgeEncoding,
    raw: impl Fn(&S::Payload) -> Vec<u8>,
    mut seen: impl FnMut(&S::Payload),
) -> Result<usize> {
    let mut n = 0;
    while let Some(d) = sub.receive_copy()? {
        seen(&d.payload);
        lane.offer(encode(&d, encoding, &raw)?);
        n += 1;
        if lane.min_interval.is_zero() {
            // Every sample counts (alerts, or a rate of 0): send before taking the next.
            lane.flush(Instant::now())?;
        }
    }
    Ok(n)
}

/// The effective section: the file's (or the defaults), with the command line's overrides,
/// validated.
fn section(args: &BridgeArgs) -> Result<(String, BridgeSection)> {
    let config = match &args.config {
        Some(path) => Config::load(path)?.0,
        None => Config::default(),
    };
    let mut b = config.bridge;
    if let Some(v) = &args.vehicle {
        b.vehicle = v.clone();
    }
    if !args.listen.is_empty() {
        b.listen = args.listen.clone();
    }
    if !args.connect.is_empty() {
        b.connect = args.connect.clone();
    }
    b.validate()?;
    let prefix = args.prefix.clone().unwrap_or(config.bus.prefix);
    Ok((prefix, b))
}

/// Runs `vigil bridge`.
pub fn run(args: &BridgeArgs) -> Result<()> {
    if args.duration.is_some_and(|d| !(d.is_finite() && d > 0.0)) {
        bail!("--duration must be a positive number of seconds");
    }
    let (prefix, b) = section(args)?;
    let mut bus = Bus::new(&BusConfig {
        prefix: prefix.clone(),
        node_name: "vigil-bridge".to_string(),
        handle_signals: true,
        ..BusConfig::default()
    })
    .context("connecting to the bus")?;
    let mut attitude = Subscriber::<AttitudePayload>::open(&bus)?;
    let mut ownship = Subscriber::<OwnshipPayload>::open(&bus)?;
    let mut traffic = TrafficSubscriber::open(&bus)?;
    let mut integrity = Subscriber::<IntegrityPayload>::open(&bus)?;
    let mut alerts = Subscriber::<AlertPayload>::open(&bus)?;

    let session = open_session(&zenoh_settings(&b))?;
    let v = b.vehicle.as_str();
    let r = &b.rates;
    let e = b.encoding;
    let traffic_type = format!(
        "{}[{}]",
        type_name::<TrafficHeader>(),
        type_name::<Target>()
    );
    let mut l_att = Lane::new(
        &session,
        v,
        Topic::Attitude,
        type_name::<AttitudePayload>(),
        e,
        Some(r.attitude_hz),
    )?;
    let mut l_own = Lane::new(
        &session,
        v,
        Topic::Ownship,
        type_name::<OwnshipPayload>(),
        e,
        Some(r.ownship_hz),
    )?;
    let mut l_tr = Lane::new(
        &session,
        v,
        Topic::Traffic,
        &traffic_type,
        e,
        Some(r.traffic_hz),
    )?;
    let mut l_int = Lane::new(
        &session,
        v,
        Topic::Integrity,
        type_name::<IntegrityPayload>(),
        e,
        Some(r.integrity_hz),
    )?;
    let mut l_al = Lane::new(
        &session,
        v,
        Topic::Alerts,
        type_name::<AlertPayload>(),
        e,
        None,
    )?;

    // The active alert set: JSON lines as `vigil listen alerts` prints them first, published on
    // change and served to queries.
    let active_key = format!("vigil/{v}/alerts/active");
    let active = std::sync::Arc::new(std::sync::Mutex::new(Vec::<u8>::from(&b"[]"[..])));
    let served = std::sync::Arc::clone(&active);
    let reply_key = active_key.clone();
    let _queryable = session
        .declare_queryable(active_key.clone())
        .callback(move |q| {
            let bytes = served.lock().map(|a| a.clone()).unwrap_or_default();
            let _ = q
                .reply(reply_key.clone(), bytes)
                .encoding(Encoding::APPLICATION_JSON)
                .wait();
        })
        .wait()
        .map_err(|e| anyhow::anyhow!("declaring the queryable {active_key}: {e}"))?;
    let active_pub = session
        .declare_publisher(active_key.clone())
        .encoding(Encoding::APPLICATION_JSON)
        .congestion_control(CongestionControl::Block)
        .wait()
        .map_err(|e| anyhow::anyhow!("declaring the publisher {active_key}: {e}"))?;

    let endpoints = b
        .listen
        .iter()
        .chain(&b.connect)
        .cloned()
        .collect::<Vec<_>>();
    eprintln!(
        "vigil bridge: {} -> vigil/{v}/* on Zenoh ({}, {})",
        vigil_bus::service_name(&prefix, "*"),
        match b.mode {
            ZenohMode::Peer => "peer",
            ZenohMode::Client => "client",
        },
        endpoints.join(", ")
    );
    let deadline = args
        .duration
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let mut last_active: Option<Vec<Value>> = None;
    let wake_on_attitude = r.attitude_hz == 0.0;
    loop {
        let mut new_active = None;
        drain(
            &mut alerts,
            &mut l_al,
            e,
            |p| wire_bytes(p).to_vec(),
            |_| {},
        )?;
        drain(
            &mut integrity,
            &mut l_int,
            e,
            |p| wire_bytes(p).to_vec(),
            |p| {
                new_active = active_lines(p).ok();
            },
        )?;
        drain(&mut traffic, &mut l_tr, e, raw_traffic, |_| {})?;
        drain(
            &mut ownship,
            &mut l_own,
            e,
            |p| wire_bytes(p).to_vec(),
            |_| {},
        )?;
        drain(
            &mut attitude,
            &mut l_att,
            e,
            |p| wire_bytes(p).to_vec(),
            |_| {},
        )?;
        if let Some(set) = new_active
            && last_active.as_ref() != Some(&set)
        {
            let bytes = serde_json::to_vec(&set)?;
            if let Ok(mut a) = active.lock() {
                a.clone_from(&bytes);
            }
            active_pub
                .put(bytes)
                .wait()
                .map_err(|e| anyhow::anyhow!("put on {active_key}: {e}"))?;
            last_active = Some(set);
        }
        let now = Instant::now();
        for lane in [&mut l_att, &mut l_own, &mut l_tr, &mut l_int, &mut l_al] {
            lane.flush(now)?;
        }
        if bus.termination_requested() || deadline.is_some_and(|d| now >= d) {
            break;
        }
        bus.cleanup_if_due();
        if wake_on_attitude {
            attitude.wait(Duration::from_millis(5))?;
        } else {
            alerts.wait(POLL)?;
        }
    }
    let lanes = [&l_att, &l_own, &l_tr, &l_int, &l_al];
    eprintln!(
        "vigil bridge: stopped; sent {}; skipped by rate {}; missed on the bus {}",
        lanes
            .iter()
            .map(|l| format!("{} {}", l.topic, l.sent))
            .collect::<Vec<_>>()
            .join(", "),
        lanes.iter().map(|l| l.skipped).sum::<u64>(),
        attitude.missed()
            + ownship.missed()
            + traffic.missed()
            + integrity.missed()
            + alerts.missed()
    );
    Ok(())
}

/// `vigil listen TOPIC --zenoh ENDPOINT`: prints what the bridges reachable at `endpoint`
/// publish on `vigil/<vehicle>/<topic>` (`vehicle` may be `*`), one JSON line per sample with
/// the vehicle added; with `latency` a summary of the latency from the iceoryx2 publication
/// (the payload's `header.send_mono_ns`, the host's monotonic clock: same host only) instead.
pub fn listen_remote(
    bus: &Bus,
    endpoint: &str,
    root_ca: Option<&std::path::Path>,
    vehicle: &str,
    args: &crate::listen::ListenArgs,
    out: &mut impl std::io::Write,
) -> Result<()> {
    let mut settings = vec![
        ("mode", serde_json::json!("peer")),
        ("connect/endpoints", serde_json::json!([endpoint])),
        ("listen/endpoints", serde_json::json!([])),
        ("scouting/multicast/enabled", serde_json::json!(false)),
    ];
    if let Some(ca) = root_ca {
        settings.push((
            "transport/link/tls/root_ca_certificate",
            serde_json::json!(ca.display().to_string()),
        ));
    }
    let session = open_session(&settings)?;
    let key = format!("vigil/{vehicle}/{}", args.topic.as_str());
    let sub = session
        .declare_subscriber(key.clone())
        .wait()
        .map_err(|e| anyhow::anyhow!("subscribing to {key}: {e}"))?;
    eprintln!("vigil listen: subscribed to {key} on Zenoh via {endpoint}");
    let deadline = args
        .duration
        .map(|s| Instant::now() + Duration::from_secs_f64(s.max(0.0)));
    let (mut seen, mut latencies) = (0u64, Vec::new());
    while args.count.is_none_or(|c| seen < c)
        && deadline.is_none_or(|d| Instant::now() < d)
        && !bus.termination_requested()
    {
        let Some(s) = sub
            .recv_timeout(Duration::from_millis(100))
            .map_err(|e| anyhow::anyhow!("receiving on {key}: {e}"))?
        else {
            continue;
        };
        let now = vigil_bus::clock::monotonic_ns();
        let bytes = s.payload().to_bytes();
        let Ok(Value::Object(mut line)) = serde_json::from_slice::<Value>(&bytes) else {
            eprintln!(
                "vigil listen: a sample on {} is not JSON (raw encoding?)",
                s.key_expr()
            );
            continue;
        };
        seen += 1;
        if args.latency {
            if let Some(sent) = line
                .get("header")
                .and_then(|h| h.get("send_mono_ns"))
                .and_then(Value::as_u64)
            {
                latencies.push(now.saturating_sub(sent));
            }
            continue;
        }
        let v = s.key_expr().as_str().split('/').nth(1).unwrap_or("");
        line.insert("vehicle".into(), Value::from(v));
        serde_json::to_writer(&mut *out, &line)?;
        out.write_all(b"\n")?;
        out.flush()?;
    }
    if args.latency {
        match crate::listen::LatencyStats::from_ns(latencies, 0) {
            Some(stats) => serde_json::to_writer(&mut *out, &stats)?,
            None => out.write_all(b"{\"samples\":0}")?,
        }
        out.write_all(b"\n")?;
    }
    out.flush()?;
    Ok(())
}

/// The Zenoh session configuration (JSON5 key, value) pairs of a `[bridge]` section.
fn zenoh_settings(b: &BridgeSection) -> Vec<(&'static str, serde_json::Value)> {
    use serde_json::json;
    let mode = match b.mode {
        ZenohMode::Peer => "peer",
        ZenohMode::Client => "client",
    };
    let mut out = vec![
        ("mode", json!(mode)),
        ("listen/endpoints", json!(b.listen)),
        ("connect/endpoints", json!(b.connect)),
        // Never advertise on the LAN: a subscriber is given the endpoint.
        ("scouting/multicast/enabled", json!(false)),
    ];
    if let Some(t) = &b.tls {
        out.push((
            "transport/link/tls/root_ca_certificate",
            json!(t.root_ca_certificate),
        ));
        if let (Some(c), Some(k)) = (&t.certificate, &t.private_key) {
            out.push(("transport/link/tls/listen_certificate", json!(c)));
            out.push(("transport/link/tls/listen_private_key", json!(k)));
        }
    }
    if let Some(a) = &b.auth {
        out.push(("transport/auth/usrpwd/user", json!(a.user)));
        out.push(("transport/auth/usrpwd/password", json!(a.password)));
        if let Some(d) = &a.dictionary_file {
            out.push(("transport/auth/usrpwd/dictionary_file", json!(d)));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn section(text: &str) -> BridgeSection {
        #[derive(serde::Deserialize)]
        struct File {
            bridge: BridgeSection,
        }
        toml::from_str::<File>(text).unwrap().bridge
    }

    #[test]
    fn zenoh_settings_never_advertise_and_carry_the_certificates() {
        let tls = "[bridge.tls]\nroot_ca_certificate = \"ca.pem\"\ncertificate = \"c.pem\"\n\
                   private_key = \"k.pem\"\n";
        let b = section(&format!(
            "[bridge]\nlisten = [\"tls/127.0.0.1:7447\"]\n{tls}"
        ));
        let s: std::collections::BTreeMap<_, _> = zenoh_settings(&b).into_iter().collect();
        assert_eq!(s["mode"], "peer");
        assert_eq!(s["scouting/multicast/enabled"], false);
        assert_eq!(s["listen/endpoints"][0], "tls/127.0.0.1:7447");
        assert_eq!(s["transport/link/tls/listen_certificate"], "c.pem");
        assert_eq!(s["transport/link/tls/listen_private_key"], "k.pem");
        assert_eq!(s["transport/link/tls/root_ca_certificate"], "ca.pem");
        assert!(!s.contains_key("transport/auth/usrpwd/user"));
    }
}
