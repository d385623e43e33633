//! The Foxglove/Lichtblick live view of `vigil run` (issue 10, "bins/": "an optional,
//! feature-gated live view ... (the `foxglove` crate, bound to localhost, off the safety path)
//! publishes ownship, traffic and alerts"). Compiled only with the cargo feature `foxglove`.
//!
//! A WebSocket server of the `foxglove` SDK, bound to 127.0.0.1 only, serves these channels:
//!
//! | topic                   | encoding | schema                           | rate                  |
//! |-------------------------|----------|----------------------------------|-----------------------|
//! | `/vigil/ownship`        | JSON     | `vigil.Ownship.v1` (JSON schema) | as published (1 Hz)   |
//! | `/vigil/ownship/fix`    | protobuf | `foxglove.LocationFix` (Map)     | valid ownship only    |
//! | `/vigil/traffic`        | JSON     | `vigil.Traffic.v1`               | at most 1 Hz          |
//! | `/vigil/traffic/geojson`| protobuf | `foxglove.GeoJSON` (Map)         | with the traffic      |
//! | `/vigil/alerts`         | JSON     | `vigil.Alert.v1`                 | every transition      |
//! | `/vigil/attitude`       | JSON     | `vigil.Attitude.v4`              | at most 10 Hz         |
//! | `/vigil/integrity`      | JSON     | `vigil.Integrity.v4`             | as published (1 Hz)   |
//!
//! The JSON messages are the bus payloads' own serde form (the same as `vigil listen`: NaN is
//! `null`); each JSON schema is derived from that form (see [`json_schema`]), so it cannot drift
//! from the payload.
//!
//! Off the safety path, by construction:
//! - The processing loop only checks whether a client subscribed to the channel (an atomic
//!   load), applies the rate limit, copies the payload and `try_send`s it into a bounded queue
//!   ([`QUEUE`] items). A full queue drops the payload and counts it ([`FoxgloveView::dropped`]);
//!   nothing ever waits.
//! - Serialisation, the server and every client connection run on the view's own thread with its
//!   own single-threaded tokio runtime. The SDK's per-client queues are lossy too: a slow client
//!   loses messages, it never pushes back.
//! - A server that fails to start is an error of [`FoxgloveView::start`]; the caller
//!   ([`crate::outputs::live_view::start`]) logs it and the service runs without the view.
//!
//! Decisions:
//! - Message log times are the host's wall clock at serialisation (the Foxglove tools' live
//!   timeline); the data's own GPS time stays in each JSON message's `header.gps_time_ns`, and
//!   the `LocationFix` timestamp is that GPS time converted to UTC with the leap-second table.
//! - `LocationFix.altitude`: the geometric (ellipsoid) altitude, else the pressure altitude,
//!   else 0 (the Map panel ignores it); the covariance is diagonal from the 1-sigma horizontal
//!   and vertical uncertainties when both are known.
//! - Traffic on the map: each target's position is the ownship's (the newest valid ownship
//!   within [`GEOJSON_MAX_OWNSHIP_AGE_NS`] of the picture) offset by the target's relative north
//!   and east distances on the WGS-84 local radii of curvature: a display approximation (error
//!   about d^2 tan(lat) / (2 R), the meridians' convergence: 2 m at 5 km and 8.5 m at 10 km at
//!   47 deg latitude), not a navigation quantity.

use std::any::Any;
use std::sync::Arc;
use std::thread::JoinHandle;
use std::time::Duration;

use foxglove::messages::{GeoJson, LocationFix, Timestamp, Vector3};
use foxglove::{Channel, Context, RawChannel, Schema};
use serde::Serialize;
use serde_json::{Map, Value, json};
use tokio::sync::mpsc;
use vigil_bus::payload::{read_text, traffic};
use vigil_bus::{
    AlertPayload, AttitudePayload, IntegrityPayload, OwnshipPayload, Payload, Topic, TrafficPayload,
};
use vigil_fusion::geometry::wgs84::{A_M as WGS84_A_M, E2 as WGS84_E2};
use vigil_fusion::time::gps;

use crate::Outputs;

/// Capacity of the queue from the processing loop to the view's thread, payloads.
pub const QUEUE: usize = 64;
/// Shortest interval between two attitude messages of the view (10 Hz), ns of GPS time.
pub const ATTITUDE_MIN_INTERVAL_NS: i64 = 100_000_000;
/// Shortest interval between two traffic messages of the view (1 Hz), ns of GPS time.
pub const TRAFFIC_MIN_INTERVAL_NS: i64 = 1_000_000_000;
/// Oldest ownship the traffic map positions are computed from, ns before the picture.
pub const GEOJSON_MAX_OWNSHIP_AGE_NS: i64 = 2_000_000_000;
/// How long [`FoxgloveView::start`] waits for the server to bind.
const START_TIMEOUT: Duration = Duration::from_secs(5);

/// Topic of the ownship JSON messages.
pub const TOPIC_OWNSHIP: &str = "/vigil/ownship";
/// Topic of the ownship `foxglove.LocationFix` messages (Map panel).
pub const TOPIC_OWNSHIP_FIX: &str = "/vigil/ownship/fix";
/// Topic of the traffic JSON messages.
pub const TOPIC_TRAFFIC: &str = "/vigil/traffic";
/// Topic of the traffic `foxglove.GeoJSON` messages (Map panel).
pub const TOPIC_TRAFFIC_GEOJSON: &str = "/vigil/traffic/geojson";
/// Topic of the alert JSON messages.
pub const TOPIC_ALERTS: &str = "/vigil/alerts";
/// Topic of the attitude JSON messages.
pub const TOPIC_ATTITUDE: &str = "/vigil/attitude";
/// Topic of the integrity JSON messages.
pub const TOPIC_INTEGRITY: &str = "/vigil/integrity";

/// Why the live view did not start.
#[derive(Debug, thiserror::Error)]
pub enum ViewError {
    /// The view's thread or runtime could not be created.
    #[error("cannot start the live view's thread: {0}")]
    Thread(#[from] std::io::Error),
    /// A channel could not be created.
    #[error("cannot create channel {topic}: {reason}")]
    Channel {
        /// The channel's topic.
        topic: &'static str,
        /// The SDK's error.
        reason: String,
    },
    /// The WebSocket server could not bind or start.
    #[error("cannot start the WebSocket server on 127.0.0.1:{port}: {reason}")]
    Server {
        /// The configured port.
        port: u16,
        /// The SDK's error.
        reason: String,
    },
    /// The server did not report within the start timeout.
    #[error("the WebSocket server did not start within {0:?}")]
    Timeout(Duration),
}

/// A payload on its way to the view's thread.
enum Item {
    Attitude(Box<AttitudePayload>),
    Ownship(OwnshipPayload),
    Traffic(Box<TrafficPayload>),
    // Boxed: 824 bytes, published at 1 Hz.
    Integrity(Box<IntegrityPayload>),
    Alert(AlertPayload),
}

/// The view's channels (shared by the processing loop, which only asks `has_sinks`, and the
/// view's thread, which logs).
struct Channels {
    ownship: Arc<RawChannel>,
    ownship_fix: Channel<LocationFix>,
    traffic: Arc<RawChannel>,
    traffic_geojson: Channel<GeoJson>,
    alerts: Arc<RawChannel>,
    attitude: Arc<RawChannel>,
    integrity: Arc<RawChannel>,
}

impl Channels {
    fn new(ctx: &Arc<Context>) -> Result<Self, ViewError> {
        let mut traffic_sample = TrafficPayload::default();
        traffic_sample.set_targets(&[traffic::Target::EMPTY]);
        Ok(Self {
            ownship: json_channel(
                ctx,
                TOPIC_OWNSHIP,
                "vigil.Ownship.v2",
                &OwnshipPayload::default(),
            )?,
            ownship_fix: ctx.channel_builder(TOPIC_OWNSHIP_FIX).build(),
            traffic: json_channel(ctx, TOPIC_TRAFFIC, "vigil.Traffic.v2", &traffic_sample)?,
            traffic_geojson: ctx.channel_builder(TOPIC_TRAFFIC_GEOJSON).build(),
            alerts: json_channel(
                ctx,
                TOPIC_ALERTS,
                "vigil.Alert.v1",
                &AlertPayload::default(),
            )?,
            attitude: json_channel(
                ctx,
                TOPIC_ATTITUDE,
                "vigil.Attitude.v4",
                &AttitudePayload::default(),
            )?,
            integrity: json_channel(
                ctx,
                TOPIC_INTEGRITY,
                "vigil.Integrity.v4",
                &IntegrityPayload::default(),
            )?,
        })
    }
}

/// A JSON channel whose JSON schema is derived from `sample` (a payload with every array
/// non-empty, so their item schemas are known).
fn json_channel<T: Serialize>(
    ctx: &Arc<Context>,
    topic: &'static str,
    schema_name: &str,
    sample: &T,
) -> Result<Arc<RawChannel>, ViewError> {
    let err = |reason: String| ViewError::Channel { topic, reason };
    let sample = serde_json::to_value(sample).map_err(|e| err(e.to_string()))?;
    let mut schema = json_schema(&sample);
    if let Value::Object(m) = &mut schema {
        m.insert("title".into(), Value::String(schema_name.into()));
    }
    let data = serde_json::to_vec(&schema).map_err(|e| err(e.to_string()))?;
    ctx.channel_builder(topic)
        .message_encoding("json")
        .schema(Schema::new(schema_name, "jsonschema", data))
        .build_raw()
        .map_err(|e| err(e.to_string()))
}

/// The JSON schema of values shaped like `sample` (a payload's serde form): objects with their
/// properties, arrays with their first element's schema, integers, strings. Every float and
/// every `null` is `["number", "null"]`: the payloads print an unknown (NaN) float as `null`.
pub fn json_schema(sample: &Value) -> Value {
    match sample {
        Value::Object(m) => {
            let props: Map<String, Value> =
                m.iter().map(|(k, v)| (k.clone(), json_schema(v))).collect();
            json!({ "type": "object", "properties": props })
        }
        Value::Array(a) => match a.first() {
            Some(first) => json!({ "type": "array", "items": json_schema(first) }),
            None => json!({ "type": "array" }),
        },
        Value::Number(n) if !n.is_f64() => json!({ "type": "integer" }),
        Value::Number(_) | Value::Null => json!({ "type": ["number", "null"] }),
        Value::String(_) => json!({ "type": "string" }),
        Value::Bool(_) => json!({ "type": "boolean" }),
    }
}

/// Passes at most one value per `min_ns` of (GPS) time; a time going backwards restarts it.
#[derive(Debug, Clone, Copy)]
pub struct RateLimit {
    min_ns: i64,
    last: Option<i64>,
}

impl RateLimit {
    /// At most one value per `min_ns`.
    pub const fn new(min_ns: i64) -> Self {
        Self { min_ns, last: None }
    }

    /// True when a value at time `t_ns` may pass (then it is the new reference).
    pub fn admit(&mut self, t_ns: i64) -> bool {
        if let Some(last) = self.last
            && t_ns >= last
            && t_ns.saturating_sub(last) < self.min_ns
        {
            return false;
        }
        self.last = Some(t_ns);
        true
    }
}

/// UTC timestamp of a GPS time (ns since the GPS epoch); `None` for 0 (unknown) or out of range.
pub fn utc_timestamp(t_gps_ns: i64) -> Option<Timestamp> {
    if t_gps_ns <= 0 {
        return None;
    }
    // The table is indexed by UTC; GPS - UTC is at most a few tens of seconds, so looking it up
    // at the GPS time read as UTC errs only within that long after a leap second.
    let approx_unix_s = t_gps_ns.div_euclid(gps::NS_PER_S) + gps::GPS_EPOCH_UNIX_S;
    let leap = gps::gps_minus_utc_s(approx_unix_s).gps_minus_utc_s;
    let unix_ns = gps::unix_ns_from_gps_ns(t_gps_ns, leap);
    let sec = u32::try_from(unix_ns.div_euclid(gps::NS_PER_S)).ok()?;
    let nsec = u32::try_from(unix_ns.rem_euclid(gps::NS_PER_S)).ok()?;
    Timestamp::new_checked(sec, nsec)
}

/// The ownship as a `foxglove.LocationFix` (Map panel); `None` when invalid or without a finite
/// position.
pub fn location_fix(o: &OwnshipPayload) -> Option<LocationFix> {
    if o.valid == 0 || !o.lat_deg.is_finite() || !o.lon_deg.is_finite() {
        return None;
    }
    let altitude = [o.alt_geometric_m, o.alt_pressure_m]
        .into_iter()
        .find(|a| a.is_finite())
        .unwrap_or(0.0);
    let (sh, sv) = (o.sigma_horizontal_m, o.sigma_vertical_m);
    let (position_covariance, covariance_type) = if sh.is_finite() && sv.is_finite() {
        // East, north, up (ENU), row-major.
        let (h, v) = (sh * sh, sv * sv);
        (vec![h, 0.0, 0.0, 0.0, h, 0.0, 0.0, 0.0, v], 2) // DIAGONAL_KNOWN
    } else {
        (Vec::new(), 0) // UNKNOWN
    };
    let velocity = [o.vel_east_mps, o.vel_north_mps, o.vel_up_mps]
        .iter()
        .all(|v| v.is_finite())
        .then_some(Vector3 {
            x: o.vel_east_mps,
            y: o.vel_north_mps,
            z: o.vel_up_mps,
        });
    Some(LocationFix {
        timestamp: utc_timestamp(o.header.gps_time_ns),
        frame_id: "ownship".into(),
        latitude: o.lat_deg,
        longitude: o.lon_deg,
        altitude,
        position_covariance,
        position_covariance_type: covariance_type,
        heading: o
            .track_deg
            .is_finite()
            .then(|| o.track_deg.to_radians().rem_euclid(std::f64::consts::TAU)),
        velocity,
        ..Default::default()
    })
}

/// The position `north_m`, `east_m` away from (`lat_deg`, `lon_deg`) on the local radii of
/// curvature (meridian M, prime vertical N): a display approximation for short distances.
pub fn offset_deg(lat_deg: f64, lon_deg: f64, north_m: f64, east_m: f64) -> (f64, f64) {
    let phi = lat_deg.to_radians();
    let w2 = 1.0 - WGS84_E2 * phi.sin().powi(2);
    let m = WGS84_A_M * (1.0 - WGS84_E2) / (w2 * w2.sqrt());
    let n = WGS84_A_M / w2.sqrt();
    let lat = lat_deg + (north_m / m).to_degrees();
    // The east distance is taken on the target's parallel, where the origin's tangent-plane
    // east coordinate is N cos(lat) d(lon) to first order. At a pole the east offset has no
    // longitude; keep the ownship's.
    let cos = lat.to_radians().cos();
    let lon = if cos.abs() > 1e-9 {
        lon_deg + (east_m / (n * cos)).to_degrees()
    } else {
        lon_deg
    };
    (lat, (lon + 180.0).rem_euclid(360.0) - 180.0)
}

/// The traffic picture as a GeoJSON `FeatureCollection` of points (Map panel), placed around
/// `own`; `None` without a valid ownship within [`GEOJSON_MAX_OWNSHIP_AGE_NS`] of the picture.
pub fn traffic_geojson(t: &TrafficPayload, own: Option<&OwnshipPayload>) -> Option<GeoJson> {
    let o = own.filter(|o| {
        o.valid != 0
            && o.lat_deg.is_finite()
            && o.lon_deg.is_finite()
            && t.header
                .gps_time_ns
                .saturating_sub(o.header.gps_time_ns)
                .abs()
                <= GEOJSON_MAX_OWNSHIP_AGE_NS
    })?;
    let features: Vec<Value> = t
        .targets()
        .iter()
        .filter(|x| x.rel_north_m.is_finite() && x.rel_east_m.is_finite())
        .map(|x| {
            let (lat, lon) = offset_deg(o.lat_deg, o.lon_deg, x.rel_north_m, x.rel_east_m);
            let address = format!("{:06X}", x.address);
            let callsign = read_text(&x.callsign).trim();
            let name = if callsign.is_empty() {
                address.clone()
            } else {
                callsign.to_string()
            };
            json!({
                "type": "Feature",
                "geometry": { "type": "Point", "coordinates": [lon, lat] },
                "properties": {
                    "name": name,
                    "address": address,
                    "alert_level": x.alert_level,
                    "horizontal_distance_m": x.horizontal_distance_m,
                    "vertical_separation_m": x.vertical_separation_m(),
                    "time_to_lowc_s": x.time_to_lowc_s,
                },
            })
        })
        .collect();
    Some(GeoJson {
        geojson: json!({ "type": "FeatureCollection", "features": features }).to_string(),
    })
}

/// The running live view: an [`Outputs`] that hands payloads to the view's thread (see the
/// module documentation). Dropping it stops the server.
pub struct FoxgloveView {
    tx: Option<mpsc::Sender<Item>>,
    channels: Arc<Channels>,
    port: u16,
    thread: Option<JoinHandle<()>>,
    attitude_limit: RateLimit,
    traffic_limit: RateLimit,
    dropped: u64,
    queued: u64,
}

impl std::fmt::Debug for FoxgloveView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FoxgloveView")
            .field("port", &self.port)
            .field("queued", &self.queued)
            .field("dropped", &self.dropped)
            .finish_non_exhaustive()
    }
}

impl FoxgloveView {
    /// Starts the WebSocket server on 127.0.0.1:`port` (0: an ephemeral port, for tests) on
    /// the view's own thread, and waits (at most 5 s, once, at start) for it to bind.
    pub fn start(port: u16) -> Result<Self, ViewError> {
        let ctx = Context::new();
        let channels = Arc::new(Channels::new(&ctx)?);
        let (tx, rx) = mpsc::channel(QUEUE);
        let (ready_tx, ready_rx) = std::sync::mpsc::channel::<Result<u16, ViewError>>();
        let ch = Arc::clone(&channels);
        let thread = std::thread::Builder::new()
            .name("vigil-live-view".into())
            .spawn(move || {
                let rt = match tokio::runtime::Builder::new_current_thread()
                    .enable_all()
                    .build()
                {
                    Ok(rt) => rt,
                    Err(e) => {
                        let _ = ready_tx.send(Err(ViewError::Thread(e)));
                        return;
                    }
                };
                rt.block_on(async move {
                    let server = ctx
                        .websocket_server()
                        .name("vigil")
                        .bind("127.0.0.1", port)
                        .start()
                        .await;
                    let server = match server {
                        Ok(s) => s,
                        Err(e) => {
                            let reason = e.to_string();
                            let _ = ready_tx.send(Err(ViewError::Server { port, reason }));
                            return;
                        }
                    };
                    let _ = ready_tx.send(Ok(server.port()));
                    serve(rx, &ch).await;
                    // A client that does not close in time is dropped with the runtime.
                    let _ =
                        tokio::time::timeout(Duration::from_secs(1), server.stop().wait()).await;
                });
            })?;
        let port = match ready_rx.recv_timeout(START_TIMEOUT) {
            Ok(Ok(p)) => p,
            Ok(Err(e)) => {
                let _ = thread.join();
                return Err(e);
            }
            // The thread ends on its own once the server starts and finds the queue closed.
            Err(_) => return Err(ViewError::Timeout(START_TIMEOUT)),
        };
        Ok(Self {
            tx: Some(tx),
            channels,
            port,
            thread: Some(thread),
            attitude_limit: RateLimit::new(ATTITUDE_MIN_INTERVAL_NS),
            traffic_limit: RateLimit::new(TRAFFIC_MIN_INTERVAL_NS),
            dropped: 0,
            queued: 0,
        })
    }

    /// The TCP port the server listens on (127.0.0.1).
    pub fn port(&self) -> u16 {
        self.port
    }

    /// Payloads dropped because the queue to the view's thread was full (or the thread ended).
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// Payloads handed to the view's thread.
    pub fn queued(&self) -> u64 {
        self.queued
    }

    fn send(&mut self, item: Item) {
        let sent = self.tx.as_ref().is_some_and(|tx| tx.try_send(item).is_ok());
        if sent {
            self.queued += 1;
        } else {
            self.dropped += 1;
        }
    }
}

impl Outputs for FoxgloveView {
    fn publish<T: Payload>(&mut self, p: &T) {
        let any = p as &dyn Any;
        let t = p.header().gps_time_ns;
        let ch = &self.channels;
        // Nothing is copied unless a client subscribed to a channel the payload feeds.
        let item = match T::TOPIC {
            Topic::Attitude if ch.attitude.has_sinks() && self.attitude_limit.admit(t) => any
                .downcast_ref::<AttitudePayload>()
                .map(|p| Item::Attitude(Box::new(*p))),
            // The traffic map needs the ownship too.
            Topic::Ownship
                if ch.ownship.has_sinks()
                    || ch.ownship_fix.has_sinks()
                    || ch.traffic_geojson.has_sinks() =>
            {
                any.downcast_ref::<OwnshipPayload>()
                    .map(|p| Item::Ownship(*p))
            }
            Topic::Traffic
                if (ch.traffic.has_sinks() || ch.traffic_geojson.has_sinks())
                    && self.traffic_limit.admit(t) =>
            {
                any.downcast_ref::<TrafficPayload>()
                    .map(|p| Item::Traffic(Box::new(p.clone())))
            }
            Topic::Integrity if ch.integrity.has_sinks() => any
                .downcast_ref::<IntegrityPayload>()
                .map(|p| Item::Integrity(Box::new(*p))),
            Topic::Alerts if ch.alerts.has_sinks() => {
                any.downcast_ref::<AlertPayload>().map(|p| Item::Alert(*p))
            }
            _ => None,
        };
        if let Some(item) = item {
            self.send(item);
        }
    }
}

impl Drop for FoxgloveView {
    /// Closes the queue (the view's thread stops the server and ends) and waits for the thread.
    fn drop(&mut self) {
        self.tx = None;
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
        tracing::info!(
            "live view stopped: {} payloads served, {} dropped",
            self.queued(),
            self.dropped()
        );
    }
}

/// Logs `p` as JSON on `ch` when a client subscribed.
fn log_json<T: Serialize>(ch: &RawChannel, p: &T) {
    if ch.has_sinks()
        && let Ok(bytes) = serde_json::to_vec(p)
    {
        ch.log(&bytes);
    }
}

/// The view thread's loop: serialises and logs every payload until the queue closes.
async fn serve(mut rx: mpsc::Receiver<Item>, ch: &Channels) {
    let mut own: Option<OwnshipPayload> = None;
    while let Some(item) = rx.recv().await {
        match item {
            Item::Attitude(p) => log_json(&ch.attitude, &p),
            Item::Ownship(p) => {
                log_json(&ch.ownship, &p);
                if ch.ownship_fix.has_sinks()
                    && let Some(fix) = location_fix(&p)
                {
                    ch.ownship_fix.log(&fix);
                }
                if p.valid != 0 {
                    own = Some(p);
                }
            }
            Item::Traffic(p) => {
                log_json(&ch.traffic, &*p);
                if ch.traffic_geojson.has_sinks()
                    && let Some(g) = traffic_geojson(&p, own.as_ref())
                {
                    ch.traffic_geojson.log(&g);
                }
            }
            Item::Integrity(p) => log_json(&ch.integrity, &*p),
            Item::Alert(p) => log_json(&ch.alerts, &p),
        }
    }
}

#[cfg(test)]
#[path = "foxglove_view_tests.rs"]
mod tests;
