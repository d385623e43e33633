//! `vigil run` with `[live_view] enabled = true` (issue 10, the Foxglove live view): in a build
//! with the cargo feature `foxglove`, the simulator on pseudo-terminals, `vigil run` on those
//! ports, and this test as both a bus subscriber and a Foxglove WebSocket client: the view serves
//! the very ownship payloads the bus carries, and the traffic on the map. In a build without
//! the feature, the key is refused at start.
#![cfg(target_os = "linux")]

mod common;

#[cfg(not(feature = "foxglove"))]
#[test]
fn live_view_enabled_without_the_feature_is_refused_naming_the_key() {
    let config = common::tmp("run_live_view", "refused.toml");
    std::fs::write(&config, "[live_view]\nenabled = true\n").unwrap();
    let out = common::vigil(&[
        "run",
        "--config",
        config.to_str().unwrap(),
        "--duration",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.contains("live_view.enabled: this vigil was built without the live view"),
        "{err}"
    );
    // Disabled (the default), the section is accepted.
    std::fs::write(&config, "[live_view]\nenabled = false\nport = 9000\n").unwrap();
    let out = common::vigil(&["config", "--check", config.to_str().unwrap()]);
    assert!(out.status.success());
}

#[cfg(feature = "foxglove")]
mod with_feature {
    use std::collections::BTreeMap;
    use std::net::TcpStream;
    use std::process::Stdio;
    use std::time::{Duration, Instant};

    use serde_json::{Value, json};
    use tungstenite::client::IntoClientRequest;
    use tungstenite::http::HeaderValue;
    use tungstenite::{Message, WebSocket};
    use vigil_bus::{Bus, BusConfig, OwnshipPayload};

    use super::common::{self, Guard};

    fn connect(port: u16, until: Instant) -> WebSocket<TcpStream> {
        loop {
            let attempt = TcpStream::connect(("127.0.0.1", port)).map_err(|e| e.to_string());
            if let Ok(stream) = attempt {
                stream
                    .set_read_timeout(Some(Duration::from_millis(100)))
                    .unwrap();
                let mut req = format!("ws://127.0.0.1:{port}")
                    .into_client_request()
                    .unwrap();
                req.headers_mut().insert(
                    "Sec-WebSocket-Protocol",
                    HeaderValue::from_static("foxglove.sdk.v1"),
                );
                return tungstenite::client(req, stream).expect("handshake").0;
            }
            assert!(Instant::now() < until, "live view never listened on {port}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }

    fn read(ws: &mut WebSocket<TcpStream>) -> Option<Message> {
        match ws.read() {
            Ok(m) => Some(m),
            Err(tungstenite::Error::Io(e))
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                None
            }
            Err(e) => panic!("websocket read: {e}"),
        }
    }

    #[test]
    fn foxglove_view_in_vigil_run_serves_the_bus_ownship_and_the_traffic_map() {
        let dir = common::tmp("run_live_view", "pty");
        let prefix = format!("vigil-test-{}-live-view", std::process::id());
        // A free port: bound, read, released (the view binds it a moment later).
        let port = std::net::TcpListener::bind("127.0.0.1:0")
            .unwrap()
            .local_addr()
            .unwrap()
            .port();
        let config = common::tmp("run_live_view", "run.toml");
        let mut text = common::run_config(&prefix, &dir);
        text += &format!("[live_view]\nenabled = true\nport = {port}\n");
        std::fs::write(&config, text).unwrap();

        let _sim = Guard(common::start_sim(&dir, "nominal", "30", "5"));
        let bus = Bus::new(&BusConfig {
            prefix,
            node_name: "live-view-test".to_string(),
            ..BusConfig::default()
        })
        .unwrap();
        let mut bus_ownship = bus.subscriber::<OwnshipPayload>().unwrap();
        let _run = Guard(common::spawn_run(&config, Stdio::null()));

        let deadline = Instant::now() + Duration::from_secs(20);
        let mut ws = connect(port, deadline);
        let mut subscribed = 0;
        // GPS time -> (lat, lon) of every valid ownship, over the bus and over the view.
        let mut on_bus: BTreeMap<i64, (f64, f64)> = BTreeMap::new();
        let mut on_view: BTreeMap<i64, (f64, f64)> = BTreeMap::new();
        let mut map_targets = 0usize;
        let matched = |bus: &BTreeMap<i64, (f64, f64)>, view: &BTreeMap<i64, (f64, f64)>| {
            view.iter().filter(|(t, p)| bus.get(t) == Some(p)).count()
        };
        while (matched(&on_bus, &on_view) < 2 || map_targets < 5) && Instant::now() < deadline {
            while let Some(o) = bus_ownship.try_receive().unwrap() {
                if o.valid == 1 {
                    on_bus.insert(o.header.gps_time_ns, (o.lat_deg, o.lon_deg));
                }
            }
            let Some(m) = read(&mut ws) else { continue };
            match m {
                Message::Text(t) if subscribed < 2 => {
                    let v: Value = serde_json::from_str(t.as_str()).unwrap();
                    if v["op"] != "advertise" {
                        continue;
                    }
                    for c in v["channels"].as_array().unwrap() {
                        let topic = c["topic"].as_str().unwrap();
                        if topic == "/vigil/ownship" || topic == "/vigil/traffic/geojson" {
                            subscribed += 1;
                            let sid = if topic == "/vigil/ownship" { 1 } else { 2 };
                            let sub = json!({ "op": "subscribe", "subscriptions": [
                                { "id": sid, "channelId": c["id"] } ] });
                            ws.send(Message::text(sub.to_string())).unwrap();
                        }
                    }
                }
                // messageData: opcode 1, subscription id u32 LE, log time u64 LE, payload.
                Message::Binary(b) if b.len() > 13 && b[0] == 1 => {
                    let payload = &b[13..];
                    if b[1] == 1 {
                        let v: Value = serde_json::from_slice(payload).unwrap();
                        if v["valid"] == 1 {
                            on_view.insert(
                                v["header"]["gps_time_ns"].as_i64().unwrap(),
                                (
                                    v["lat_deg"].as_f64().unwrap(),
                                    v["lon_deg"].as_f64().unwrap(),
                                ),
                            );
                        }
                    } else if b[1] == 2 {
                        // foxglove.GeoJSON, protobuf: field 1 (string) holds the JSON text.
                        let text = String::from_utf8_lossy(payload);
                        map_targets = map_targets.max(text.matches("\"Feature\"").count());
                    }
                }
                _ => {}
            }
        }
        assert_eq!(subscribed, 2, "channels never advertised");
        assert!(
            matched(&on_bus, &on_view) >= 2,
            "the view's ownship equals the bus's at the same GPS times: bus {on_bus:?}, view \
             {on_view:?}"
        );
        // The nominal scenario's five intruders appear on the map.
        assert_eq!(map_targets, 5, "targets on the map");
    }
}
