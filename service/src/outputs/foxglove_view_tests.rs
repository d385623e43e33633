//! Tests of the Foxglove live view: the pure conversions against hand computations, and the
//! server end to end with a WebSocket client (tungstenite, blocking) on an ephemeral port.

use std::net::TcpStream;
use std::time::{Duration, Instant};

use serde_json::Value;
use tungstenite::client::IntoClientRequest;
use tungstenite::http::HeaderValue;
use tungstenite::{Message, WebSocket};
use vigil_bus::payload::ownship::SOURCE_VN200_INS;
use vigil_bus::payload::traffic::Target;
use vigil_bus::payload::write_text;
use vigil_fusion::geometry::wgs84::{EnuFrame, geodetic_to_ecef};

use super::*;

fn ownship() -> OwnshipPayload {
    let mut o = OwnshipPayload {
        lat_deg: 47.25,
        lon_deg: 8.5,
        alt_pressure_m: 480.0,
        alt_geometric_m: 530.5,
        vel_north_mps: 10.0,
        vel_east_mps: -5.0,
        vel_up_mps: 1.5,
        ground_speed_mps: 11.18,
        track_deg: 270.0,
        sigma_horizontal_m: 2.0,
        sigma_vertical_m: 3.0,
        sigma_velocity_mps: 0.1,
        source: SOURCE_VN200_INS,
        valid: 1,
        ..OwnshipPayload::default()
    };
    o.header.gps_time_ns = 1_388_102_418_500_000_000;
    o
}

#[test]
fn json_schema_follows_the_payload_form() {
    let v = serde_json::to_value(OwnshipPayload::default()).unwrap();
    let s = json_schema(&v);
    assert_eq!(s["type"], "object");
    // Floats (and NaN printed as null) may be null; integer codes are integers.
    assert_eq!(
        s["properties"]["lat_deg"]["type"],
        json!(["number", "null"])
    );
    assert_eq!(
        s["properties"]["alt_geometric_m"]["type"],
        json!(["number", "null"])
    );
    assert_eq!(s["properties"]["source"]["type"], "integer");
    assert_eq!(
        s["properties"]["header"]["properties"]["seq"]["type"],
        "integer"
    );
    // Skipped padding is not part of the form.
    assert!(s["properties"].get("reserved").is_none());

    let mut t = TrafficPayload::default();
    t.set_targets(&[Target::EMPTY]);
    let s = json_schema(&serde_json::to_value(t).unwrap());
    let target = &s["properties"]["targets"]["items"]["properties"];
    assert_eq!(target["callsign"]["type"], "string");
    assert_eq!(target["address"]["type"], "integer");
    assert_eq!(target["tau_mod_s"]["type"], json!(["number", "null"]));
    // An empty array has no item schema.
    assert_eq!(json_schema(&json!([])), json!({ "type": "array" }));
}

#[test]
fn rate_limit_passes_one_per_interval_and_restarts_on_a_time_jump() {
    let mut r = RateLimit::new(ATTITUDE_MIN_INTERVAL_NS);
    // 400 Hz for 1 s (2.5 ms steps): one every 100 ms -> t = 0, 100, ..., 900 ms: 10.
    let passed = (0..400).filter(|i| r.admit(i * 2_500_000)).count();
    assert_eq!(passed, 10);
    // Backwards (a replay restarting): passes, and becomes the reference.
    assert!(r.admit(5));
    assert!(!r.admit(5 + ATTITUDE_MIN_INTERVAL_NS - 1));
    assert!(r.admit(5 + ATTITUDE_MIN_INTERVAL_NS));
}

#[test]
fn utc_timestamp_applies_the_leap_seconds() {
    // 2024-01-01T00:00:00.5 UTC: Unix 1_704_067_200 s; GPS = Unix - 315_964_800 + 18 (GPS - UTC
    // since 2017) = 1_388_102_418 s.
    let ts = utc_timestamp(1_388_102_418_500_000_000).unwrap();
    assert_eq!((ts.sec(), ts.nsec()), (1_704_067_200, 500_000_000));
    assert!(utc_timestamp(0).is_none());
    assert!(utc_timestamp(-5).is_none());
}

#[test]
fn location_fix_carries_position_heading_velocity_and_covariance() {
    let f = location_fix(&ownship()).unwrap();
    assert_eq!((f.latitude, f.longitude, f.altitude), (47.25, 8.5, 530.5));
    // Track 270 deg = 3 pi / 2 rad, clockwise from north.
    assert!((f.heading.unwrap() - 1.5 * std::f64::consts::PI).abs() < 1e-12);
    // ENU: east -5, north 10, up 1.5.
    let v = f.velocity.unwrap();
    assert_eq!((v.x, v.y, v.z), (-5.0, 10.0, 1.5));
    // Diagonal 2^2, 2^2, 3^2; type DIAGONAL_KNOWN (2).
    assert_eq!(
        f.position_covariance,
        vec![4.0, 0.0, 0.0, 0.0, 4.0, 0.0, 0.0, 0.0, 9.0]
    );
    assert_eq!(f.position_covariance_type, 2);
    assert_eq!(f.timestamp.unwrap().sec(), 1_704_067_200);

    // Pressure altitude when the geometric one is unknown; no covariance without sigmas.
    let mut o = ownship();
    o.alt_geometric_m = f64::NAN;
    o.sigma_vertical_m = f64::NAN;
    let f = location_fix(&o).unwrap();
    assert_eq!(f.altitude, 480.0);
    assert!(f.position_covariance.is_empty());
    assert_eq!(f.position_covariance_type, 0);

    o.valid = 0;
    assert!(location_fix(&o).is_none());
    assert!(location_fix(&OwnshipPayload::default()).is_none());
}

#[test]
fn offset_matches_hand_values_at_the_equator() {
    // Meridian radius at the equator M = a (1 - e^2) = 6_335_439.327 m: 1000 m north is
    // 1000 / M rad = 0.009043695 deg. Prime vertical N = a: 1000 m east is 0.008983153 deg.
    let (lat, lon) = offset_deg(0.0, 10.0, 1000.0, 0.0);
    assert!((lat - 0.009_043_695).abs() < 1e-9, "{lat}");
    assert_eq!(lon, 10.0);
    let (lat, lon) = offset_deg(0.0, 10.0, 0.0, 1000.0);
    assert_eq!(lat, 0.0);
    assert!((lon - 10.008_983_153).abs() < 1e-9, "{lon}");
    // Across the antimeridian the longitude wraps into [-180, 180).
    let (_, lon) = offset_deg(0.0, 179.999, 0.0, 1000.0);
    assert!(
        (lon - (179.999 + 0.008_983_153 - 360.0)).abs() < 1e-9,
        "{lon}"
    );
}

#[test]
fn offset_agrees_with_the_enu_frame_within_display_accuracy() {
    // Independent check: the offset point, placed back in the ENU frame of the origin by the
    // ECEF geometry, is where it was asked to be, up to the meridians' convergence
    // d^2 tan(lat) / (2 R): at 47.25 deg and 5 km, 25e6 * 1.0818 / (2 * 6.371e6) = 2.12 m.
    let (lat0, lon0) = (47.25, 8.5);
    let frame = EnuFrame::at(lat0, lon0, 0.0);
    let bound = 5000.0_f64.powi(2) * lat0.to_radians().tan() / (2.0 * 6.371e6);
    assert!((bound - 2.12).abs() < 0.01);
    for (n, e) in [
        (3000.0, 4000.0),
        (-5000.0, 0.0),
        (0.0, -5000.0),
        (-2500.0, 3500.0),
    ] {
        let (lat, lon) = offset_deg(lat0, lon0, n, e);
        let enu = frame.position(&geodetic_to_ecef(lat, lon, 0.0).0);
        let err = (enu.x - e).hypot(enu.y - n);
        assert!(
            err < bound * 1.05,
            "({n}, {e}): ENU ({}, {}), error {err} m",
            enu.y,
            enu.x
        );
    }
    // Near the origin it is exact to the millimetre.
    let (lat, lon) = offset_deg(lat0, lon0, 30.0, -40.0);
    let enu = frame.position(&geodetic_to_ecef(lat, lon, 0.0).0);
    assert!(
        (enu.x + 40.0).abs() < 1e-3 && (enu.y - 30.0).abs() < 1e-3,
        "{enu:?}"
    );
}

fn picture() -> TrafficPayload {
    let mut t = TrafficPayload::default();
    t.header.gps_time_ns = ownship().header.gps_time_ns + 1_000_000_000;
    let mut a = Target {
        address: 0x4B1A2C,
        alert_level: traffic::ALERT_CORRECTIVE,
        rel_north_m: 1000.0,
        rel_east_m: 0.0,
        horizontal_distance_m: 1000.0,
        ..Target::EMPTY
    };
    write_text(&mut a.callsign, "SWR123");
    let b = Target {
        address: 0xABC,
        rel_north_m: 0.0,
        rel_east_m: -2000.0,
        ..Target::EMPTY
    };
    t.set_targets(&[a, b]);
    t
}

#[test]
fn traffic_geojson_places_the_targets_around_the_ownship() {
    let o = ownship();
    let g = traffic_geojson(&picture(), Some(&o)).unwrap();
    let v: Value = serde_json::from_str(&g.geojson).unwrap();
    assert_eq!(v["type"], "FeatureCollection");
    let f = v["features"].as_array().unwrap();
    assert_eq!(f.len(), 2);
    assert_eq!(f[0]["properties"]["name"], "SWR123");
    assert_eq!(f[0]["properties"]["address"], "4B1A2C");
    assert_eq!(f[0]["properties"]["alert_level"], 2);
    // The second has no callsign: named by its address, 6 hex digits.
    assert_eq!(f[1]["properties"]["name"], "000ABC");
    // GeoJSON coordinates are [lon, lat].
    let (lat, lon) = offset_deg(o.lat_deg, o.lon_deg, 1000.0, 0.0);
    assert_eq!(f[0]["geometry"]["coordinates"], json!([lon, lat]));
    assert!(lat > o.lat_deg && lon == o.lon_deg);
    let c = &f[1]["geometry"]["coordinates"];
    assert!(c[0].as_f64().unwrap() < o.lon_deg);

    // No ownship, an invalid one, or one older than the limit: no map positions.
    assert!(traffic_geojson(&picture(), None).is_none());
    let mut bad = o;
    bad.valid = 0;
    assert!(traffic_geojson(&picture(), Some(&bad)).is_none());
    let mut old = o;
    old.header.gps_time_ns -= GEOJSON_MAX_OWNSHIP_AGE_NS;
    assert!(traffic_geojson(&picture(), Some(&old)).is_none());
}

// ---- The server, end to end. ----

type Client = WebSocket<TcpStream>;

fn connect(port: u16, subprotocol: &'static str) -> Result<Client, String> {
    let mut req = format!("ws://127.0.0.1:{port}")
        .into_client_request()
        .map_err(|e| e.to_string())?;
    req.headers_mut().insert(
        "Sec-WebSocket-Protocol",
        HeaderValue::from_static(subprotocol),
    );
    let stream = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string())?;
    stream
        .set_read_timeout(Some(Duration::from_millis(200)))
        .map_err(|e| e.to_string())?;
    tungstenite::client(req, stream)
        .map(|(ws, _)| ws)
        .map_err(|e| e.to_string())
}

/// The next message within `timeout`, or `None`.
fn next(ws: &mut Client, timeout: Duration) -> Option<Message> {
    let end = Instant::now() + timeout;
    while Instant::now() < end {
        match ws.read() {
            Ok(m) => return Some(m),
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) => {}
            Err(e) => panic!("websocket read: {e}"),
        }
    }
    None
}

/// The advertised channels (topic -> channel object), read until `want` are all known.
fn advertised(ws: &mut Client, want: &[&str]) -> std::collections::BTreeMap<String, Value> {
    let mut channels = std::collections::BTreeMap::new();
    let end = Instant::now() + Duration::from_secs(10);
    while !want.iter().all(|t| channels.contains_key(*t)) {
        assert!(
            Instant::now() < end,
            "advertised so far: {:?}",
            channels.keys()
        );
        if let Some(Message::Text(t)) = next(ws, Duration::from_secs(1)) {
            let v: Value = serde_json::from_str(t.as_str()).unwrap();
            if v["op"] == "advertise" {
                for c in v["channels"].as_array().unwrap() {
                    channels.insert(c["topic"].as_str().unwrap().to_string(), c.clone());
                }
            }
        }
    }
    channels
}

/// A `messageData` frame: opcode 1, subscription id (u32 LE), log time (u64 LE), payload.
fn message_data(m: &Message) -> Option<(u32, &[u8])> {
    let Message::Binary(b) = m else { return None };
    if b.len() < 13 || b[0] != 1 {
        return None;
    }
    let sub = u32::from_le_bytes(b[1..5].try_into().unwrap());
    Some((sub, &b[13..]))
}

/// The port's listening sockets in /proc/net/tcp (local address hex, e.g. `0100007F`).
fn listen_addresses(port: u16) -> Vec<String> {
    let table = std::fs::read_to_string("/proc/net/tcp").unwrap_or_default();
    let suffix = format!(":{port:04X}");
    table
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            // Field 1: local address "ADDR:PORT"; field 3: state, 0A = LISTEN.
            (f.len() > 3 && f[1].ends_with(&suffix) && f[3] == "0A")
                .then(|| f[1].trim_end_matches(&suffix).to_string())
        })
        .collect()
}

#[test]
fn foxglove_server_advertises_the_channels_and_delivers_ownship() {
    let mut view = FoxgloveView::start(0).expect("view starts");
    let port = view.port();
    assert_ne!(port, 0);
    // Bound to 127.0.0.1 (0100007F in /proc/net/tcp), never to every interface.
    assert_eq!(listen_addresses(port), vec!["0100007F".to_string()]);

    let mut ws = connect(port, "foxglove.sdk.v1").expect("handshake");
    let channels = advertised(
        &mut ws,
        &[
            TOPIC_OWNSHIP,
            TOPIC_TRAFFIC,
            TOPIC_ALERTS,
            TOPIC_ATTITUDE,
            TOPIC_INTEGRITY,
            TOPIC_OWNSHIP_FIX,
            TOPIC_TRAFFIC_GEOJSON,
        ],
    );
    for (topic, name, field) in [
        (TOPIC_OWNSHIP, "vigil.Ownship.v2", "lat_deg"),
        (TOPIC_TRAFFIC, "vigil.Traffic.v2", "targets"),
        (TOPIC_ALERTS, "vigil.Alert.v1", "reason"),
        (TOPIC_ATTITUDE, "vigil.Attitude.v4", "roll_rad"),
    ] {
        let c = &channels[topic];
        assert_eq!(c["encoding"], "json", "{topic}");
        assert_eq!(c["schemaName"], name, "{topic}");
        assert_eq!(c["schemaEncoding"], "jsonschema", "{topic}");
        let schema: Value = serde_json::from_str(c["schema"].as_str().unwrap()).unwrap();
        assert_eq!(schema["title"], name);
        assert!(
            schema["properties"].get(field).is_some(),
            "{topic}: {schema}"
        );
    }
    assert_eq!(
        channels[TOPIC_OWNSHIP_FIX]["schemaName"],
        "foxglove.LocationFix"
    );
    assert_eq!(channels[TOPIC_OWNSHIP_FIX]["encoding"], "protobuf");
    assert_eq!(
        channels[TOPIC_TRAFFIC_GEOJSON]["schemaName"],
        "foxglove.GeoJSON"
    );

    // Nobody subscribed yet: nothing is even copied for the view.
    view.publish(&ownship());
    assert_eq!((view.queued(), view.dropped()), (0, 0));

    let id = |t: &str| channels[t]["id"].as_u64().unwrap();
    let sub = json!({ "op": "subscribe", "subscriptions": [
        { "id": 1, "channelId": id(TOPIC_OWNSHIP) },
        { "id": 2, "channelId": id(TOPIC_OWNSHIP_FIX) },
    ]});
    ws.send(Message::text(sub.to_string())).unwrap();

    // The subscription reaches the server asynchronously: publish until both messages arrive.
    let (mut json_msg, mut fix_msg) = (None, None);
    let end = Instant::now() + Duration::from_secs(10);
    while (json_msg.is_none() || fix_msg.is_none()) && Instant::now() < end {
        view.publish(&ownship());
        while let Some(m) = next(&mut ws, Duration::from_millis(50)) {
            match message_data(&m) {
                Some((1, data)) => json_msg = Some(data.to_vec()),
                Some((2, data)) => fix_msg = Some(data.to_vec()),
                _ => {}
            }
        }
    }
    let j: Value = serde_json::from_slice(&json_msg.expect("ownship JSON arrives")).unwrap();
    assert_eq!(j["lat_deg"], 47.25);
    assert_eq!(j["lon_deg"], 8.5);
    assert_eq!(j["alt_geometric_m"], 530.5);
    assert_eq!(j["track_deg"], 270.0);
    assert_eq!(j["source"], 1);
    assert_eq!(j["header"]["gps_time_ns"], 1_388_102_418_500_000_000i64);
    // Protobuf LocationFix: field 1 (latitude, double) is key 0x09 = (1 << 3) | 1 followed by
    // the 8 little-endian bytes; field 2 (longitude) key 0x11.
    let fix = fix_msg.expect("LocationFix arrives");
    let field = |key: u8, v: f64| {
        let mut f = vec![key];
        f.extend_from_slice(&v.to_le_bytes());
        fix.windows(9).any(|w| w == f.as_slice())
    };
    assert!(field(0x09, 47.25) && field(0x11, 8.5), "{fix:02X?}");
    assert!(view.queued() >= 1);
    drop(ws);
    drop(view);
    // Stopped: the port is released.
    assert!(listen_addresses(port).is_empty());
}

#[test]
fn foxglove_old_subprotocol_name_is_refused() {
    // The SDK's server speaks `foxglove.sdk.v1` (the same protocol as the older
    // `foxglove.websocket.v1`, renamed); a client offering only the old name gets HTTP 400.
    let view = FoxgloveView::start(0).unwrap();
    let e = connect(view.port(), "foxglove.websocket.v1").unwrap_err();
    assert!(e.contains("400"), "{e}");
    assert!(connect(view.port(), "foxglove.sdk.v1").is_ok());
}

#[test]
fn foxglove_a_client_that_never_reads_does_not_slow_the_publisher() {
    let mut view = FoxgloveView::start(0).unwrap();
    let mut ws = connect(view.port(), "foxglove.sdk.v1").unwrap();
    let channels = advertised(&mut ws, &[TOPIC_OWNSHIP]);
    let sub = json!({ "op": "subscribe", "subscriptions": [
        { "id": 1, "channelId": channels[TOPIC_OWNSHIP]["id"] },
    ]});
    ws.send(Message::text(sub.to_string())).unwrap();
    let end = Instant::now() + Duration::from_secs(10);
    while view.queued() == 0 {
        assert!(Instant::now() < end, "subscription never seen");
        view.publish(&ownship());
        std::thread::sleep(Duration::from_millis(10));
    }
    // The client now never reads. Every publish returns at once: 100 000 payloads go to the
    // queue or are dropped and counted; nothing waits (a blocking design would hang here once
    // the socket buffers fill).
    let before = view.queued() + view.dropped();
    for _ in 0..100_000 {
        view.publish(&ownship());
    }
    assert_eq!(view.queued() + view.dropped() - before, 100_000);
    assert!(
        view.dropped() > 0,
        "a queue of {QUEUE} cannot take 100 000 at once"
    );
}

#[test]
fn foxglove_a_port_in_use_is_an_error_and_the_service_goes_on() {
    let taken = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port();
    let e = FoxgloveView::start(port).unwrap_err();
    assert!(
        matches!(e, ViewError::Server { port: p, .. } if p == port),
        "{e}"
    );
    assert!(e.to_string().contains(&format!("127.0.0.1:{port}")), "{e}");
    // Through the service's entry point: logged, no view, no panic.
    let section = crate::outputs::live_view::LiveViewSection {
        enabled: true,
        port: u32::from(port),
    };
    assert!(crate::outputs::live_view::start(&section).is_none());
}

#[test]
fn foxglove_attitude_and_traffic_are_rate_limited_on_the_way_to_the_view() {
    let mut view = FoxgloveView::start(0).unwrap();
    let mut ws = connect(view.port(), "foxglove.sdk.v1").unwrap();
    let channels = advertised(&mut ws, &[TOPIC_ATTITUDE, TOPIC_TRAFFIC]);
    let sub = json!({ "op": "subscribe", "subscriptions": [
        { "id": 1, "channelId": channels[TOPIC_ATTITUDE]["id"] },
        { "id": 2, "channelId": channels[TOPIC_TRAFFIC]["id"] },
    ]});
    ws.send(Message::text(sub.to_string())).unwrap();
    // Wait until both subscriptions are live: a payload of each passes (times far in the past,
    // so the rate limits restart at the test's own times below).
    let end = Instant::now() + Duration::from_secs(10);
    let (mut att, mut tr) = (AttitudePayload::default(), TrafficPayload::default());
    let mut probe = 0;
    loop {
        let before = view.queued();
        probe += 10 * TRAFFIC_MIN_INTERVAL_NS;
        att.header.gps_time_ns = probe;
        tr.header.gps_time_ns = probe;
        view.publish(&att);
        let att_live = view.queued() > before;
        view.publish(&tr);
        if att_live && view.queued() == before + 2 {
            break;
        }
        assert!(Instant::now() < end, "subscriptions never seen");
        std::thread::sleep(Duration::from_millis(10));
    }
    // 2 s of attitude at 400 Hz (2.5 ms steps) and of traffic at 4 Hz: at most 10 Hz and
    // 1 Hz pass, i.e. 20 attitude (t = 0, 100, ..., 1900 ms) and 2 traffic (t = 0, 1000 ms).
    let t0 = probe + 10 * TRAFFIC_MIN_INTERVAL_NS;
    let before = view.queued() + view.dropped();
    for i in 0..800 {
        att.header.gps_time_ns = t0 + i * 2_500_000;
        view.publish(&att);
    }
    let attitude_passed = view.queued() + view.dropped() - before;
    for i in 0..8 {
        tr.header.gps_time_ns = t0 + i * 250_000_000;
        view.publish(&tr);
    }
    let traffic_passed = view.queued() + view.dropped() - before - attitude_passed;
    assert_eq!((attitude_passed, traffic_passed), (20, 2));
}
