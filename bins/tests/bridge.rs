//! `vigil bridge` (issue 22): secure by default. Nothing a Zenoh peer publishes reaches vigil's
//! iceoryx2 services, and a TLS endpoint serves only a client that trusts its certificate.
//! (The two-vehicle test with a Python Zenoh client is `tests/python/check_zenoh_bridge.py`,
//! run by CI.)
#![cfg(feature = "bridge")]

mod common;

use std::io::{BufRead, BufReader};
use std::net::TcpListener;
use std::path::Path;
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use common::Guard;
use vigil_bus::{AlertPayload, AttitudePayload, Bus, BusConfig};
use zenoh::Wait;

fn free_port() -> u16 {
    TcpListener::bind("127.0.0.1:0")
        .unwrap()
        .local_addr()
        .unwrap()
        .port()
}

fn bus(prefix: &str) -> Bus {
    Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: "bridge-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap()
}

/// Starts `vigil bridge ARGS` and waits for its start line.
fn start_bridge(args: &[&str]) -> Guard {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .arg("bridge")
        .args(args)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    err.read_line(&mut line).unwrap();
    assert!(line.contains("vigil bridge:"), "{line}");
    // Keep its stderr open and drained: its summary at exit must not hit a closed pipe.
    std::thread::spawn(move || for _ in err.lines() {});
    Guard(child)
}

/// Publishes an attitude on `prefix` every 20 ms until dropped.
struct Ticker(Arc<AtomicBool>, Option<std::thread::JoinHandle<()>>);

impl Ticker {
    fn start(prefix: &str) -> Self {
        let stop = Arc::new(AtomicBool::new(false));
        let (flag, prefix) = (Arc::clone(&stop), prefix.to_string());
        let handle = std::thread::spawn(move || {
            let b = bus(&prefix);
            let mut publ = b.publisher::<AttitudePayload>().unwrap();
            while !flag.load(Ordering::Relaxed) {
                publ.publish(&AttitudePayload::default()).unwrap();
                std::thread::sleep(Duration::from_millis(20));
            }
        });
        Self(stop, Some(handle))
    }
}

impl Drop for Ticker {
    fn drop(&mut self) {
        self.0.store(true, Ordering::Relaxed);
        if let Some(h) = self.1.take() {
            let _ = h.join();
        }
    }
}

/// `vigil listen attitude --zenoh ENDPOINT EXTRA...` for at most `seconds`: its stdout lines.
fn listen_remote(endpoint: &str, extra: &[&str], seconds: &str) -> Vec<String> {
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["listen", "attitude", "--zenoh", endpoint, "--count", "1"])
        .args(["--duration", seconds])
        .args(extra)
        .output()
        .unwrap();
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(str::to_string)
        .collect()
}

#[test]
fn a_zenoh_peer_publishing_on_the_vehicles_keys_changes_nothing_in_vigil() {
    let prefix = format!("vigil-test-{}-bridge-in", std::process::id());
    let port = free_port();
    let endpoint = format!("tcp/127.0.0.1:{port}");
    let b = bus(&prefix);
    let mut alerts = b.subscriber::<AlertPayload>().unwrap();
    let mut traffic = b.traffic_subscriber().unwrap();
    let mut bridge = start_bridge(&[
        "--prefix",
        &prefix,
        "--vehicle",
        "t1",
        "--listen",
        &endpoint,
    ]);

    // A peer on the bridge's endpoint: first it sees the bridge's output (the link works) ...
    let mut config = zenoh::Config::default();
    for (k, v) in [
        ("mode", "\"peer\"".to_string()),
        ("connect/endpoints", format!("[\"{endpoint}\"]")),
        ("listen/endpoints", "[]".to_string()),
        ("scouting/multicast/enabled", "false".to_string()),
    ] {
        config.insert_json5(k, &v).unwrap();
    }
    let session = zenoh::open(config).wait().unwrap();
    let sub = session
        .declare_subscriber("vigil/t1/attitude")
        .wait()
        .unwrap();
    let _ticker = Ticker::start(&prefix);
    let got = sub.recv_timeout(Duration::from_secs(10)).unwrap();
    assert!(got.is_some(), "no attitude through the bridge");

    // ... then it publishes on every key the bridge uses, as a hostile peer would.
    for key in [
        "vigil/t1/alerts",
        "vigil/t1/traffic",
        "vigil/t1/alerts/active",
    ] {
        let p = session.declare_publisher(key).wait().unwrap();
        for _ in 0..20 {
            p.put(r#"{"alert_id":1,"state":"raised","reason":"spoofed"}"#)
                .wait()
                .unwrap();
            p.put(vec![0u8; 208]).wait().unwrap();
        }
    }
    std::thread::sleep(Duration::from_secs(1));
    assert!(
        alerts.try_receive().unwrap().is_none(),
        "an alert came from the network"
    );
    assert!(
        traffic.try_receive().unwrap().is_none(),
        "traffic came from the network"
    );
    assert_eq!(
        alerts.publishers(),
        0,
        "the bridge publishes nothing into iceoryx2"
    );
    assert_eq!(traffic.publishers(), 0);
    assert!(bridge.0.try_wait().unwrap().is_none(), "the bridge died");
    common::signal(&bridge.0, "TERM");
    assert!(common::wait_exit(&mut bridge.0, Duration::from_secs(5)).success());
}

/// A CA and a certificate for `localhost` signed by it, made with the `openssl` command.
fn make_certificates(dir: &Path, ca_name: &str) {
    let run = |args: &[&str]| {
        let out = Command::new("openssl")
            .args(args)
            .current_dir(dir)
            .output()
            .expect("the openssl command (CI installs it)");
        assert!(out.status.success(), "openssl {args:?}: {out:?}");
    };
    run(&[
        "req",
        "-x509",
        "-newkey",
        "rsa:2048",
        "-nodes",
        "-days",
        "2",
        "-subj",
        &format!("/CN={ca_name}"),
        "-keyout",
        "ca.key",
        "-out",
        "ca.pem",
    ]);
    std::fs::write(
        dir.join("san.ext"),
        "subjectAltName=DNS:localhost,IP:127.0.0.1\nbasicConstraints=CA:FALSE\n",
    )
    .unwrap();
    run(&[
        "req",
        "-newkey",
        "rsa:2048",
        "-nodes",
        "-subj",
        "/CN=localhost",
        "-keyout",
        "bridge.key",
        "-out",
        "bridge.csr",
    ]);
    run(&[
        "x509",
        "-req",
        "-in",
        "bridge.csr",
        "-CA",
        "ca.pem",
        "-CAkey",
        "ca.key",
        "-CAcreateserial",
        "-days",
        "2",
        "-extfile",
        "san.ext",
        "-out",
        "bridge.pem",
    ]);
}

#[test]
fn a_tls_endpoint_serves_only_a_client_that_trusts_its_certificate() {
    let pid = std::process::id();
    let prefix = format!("vigil-test-{pid}-bridge-tls");
    let dir = common::tmp("bridge_tls", "certs");
    let other = common::tmp("bridge_tls", "other-ca");
    for d in [&dir, &other] {
        std::fs::create_dir_all(d).unwrap();
    }
    make_certificates(&dir, "vigil test CA");
    make_certificates(&other, "someone else's CA");
    let port = free_port();
    let endpoint = format!("tls/localhost:{port}");
    let config = dir.join("bridge.toml");
    let p = |f: &str| dir.join(f).display().to_string();
    std::fs::write(
        &config,
        format!(
            "[bus]\nprefix = \"{prefix}\"\n[bridge]\nvehicle = \"tls1\"\nlisten = [\"{endpoint}\"]\n\
             [bridge.tls]\nroot_ca_certificate = \"{}\"\ncertificate = \"{}\"\nprivate_key = \"{}\"\n",
            p("ca.pem"),
            p("bridge.pem"),
            p("bridge.key")
        ),
    )
    .unwrap();
    let _bridge: Guard = start_bridge(&["--config", config.to_str().unwrap()]);
    let _ticker = Ticker::start(&prefix);

    // Trusting the CA: the attitude arrives.
    let start = Instant::now();
    let lines = listen_remote(&endpoint, &["--zenoh-ca", &p("ca.pem")], "15");
    assert_eq!(lines.len(), 1, "nothing over TLS in {:?}", start.elapsed());
    let v: serde_json::Value = serde_json::from_str(&lines[0]).unwrap();
    assert_eq!(v["topic"], "attitude");
    assert_eq!(v["vehicle"], "tls1");

    // Without the CA (the system's roots) or with another CA: no connection, nothing received.
    let other_ca = other.join("ca.pem").display().to_string();
    for extra in [vec![], vec!["--zenoh-ca", other_ca.as_str()]] {
        let lines = listen_remote(&endpoint, &extra, "3");
        assert!(lines.is_empty(), "{extra:?} received {lines:?}");
    }
    // A plain TCP client on the TLS port gets nothing either.
    let lines = listen_remote(&format!("tcp/127.0.0.1:{port}"), &[], "3");
    assert!(lines.is_empty(), "{lines:?}");
}

/// A Zenoh session with `settings` (JSON5 values), or why it could not open.
fn try_session(settings: &[(&str, String)]) -> zenoh::Result<zenoh::Session> {
    let mut config = zenoh::Config::default();
    for (k, v) in settings {
        config.insert_json5(k, v).unwrap();
    }
    zenoh::open(config).wait()
}

/// A Zenoh session with `settings` (JSON5 values).
fn session(settings: &[(&str, String)]) -> zenoh::Session {
    try_session(settings).unwrap()
}

/// The bridge as a client of a router recovers by itself when the router restarts: a subscriber
/// on the router receives the vehicle's topic before, and again after, with nothing restarted
/// but the router.
#[test]
fn a_bridge_behind_a_router_recovers_when_the_router_restarts() {
    let prefix = format!("vigil-test-{}-bridge-router", std::process::id());
    let router_on = |endpoint: &str| {
        try_session(&[
            ("mode", "\"router\"".to_string()),
            ("listen/endpoints", format!("[\"{endpoint}\"]")),
            ("scouting/multicast/enabled", "false".to_string()),
        ])
    };
    // A port found free can be taken by a test running beside this one before the router binds
    // it (seen in CI: "Address already in use"): a few ports are tried.
    let (endpoint, r1) = (0..5)
        .find_map(|_| {
            let endpoint = format!("tcp/127.0.0.1:{}", free_port());
            router_on(&endpoint).ok().map(|r| (endpoint, r))
        })
        .expect("a router on a free port");
    let try_router = || router_on(&endpoint);
    let config = common::tmp("bridge_router", "bridge.toml");
    std::fs::write(
        &config,
        format!(
            "[bus]\nprefix = \"{prefix}\"\n[bridge]\nvehicle = \"r1\"\nmode = \"client\"\n\
             listen = []\nconnect = [\"{endpoint}\"]\n"
        ),
    )
    .unwrap();
    let _bridge = start_bridge(&["--config", config.to_str().unwrap()]);
    let _ticker = Ticker::start(&prefix);
    let ground = session(&[
        ("mode", "\"client\"".to_string()),
        ("connect/endpoints", format!("[\"{endpoint}\"]")),
        ("scouting/multicast/enabled", "false".to_string()),
    ]);
    let sub = ground
        .declare_subscriber("vigil/r1/attitude")
        .wait()
        .unwrap();
    assert!(
        sub.recv_timeout(Duration::from_secs(20)).unwrap().is_some(),
        "nothing through the router"
    );
    // The router goes away: nothing arrives for a second (the outage is real) ...
    r1.close().wait().unwrap();
    drop(r1);
    let deadline = Instant::now() + Duration::from_secs(15);
    while sub.recv_timeout(Duration::from_secs(1)).unwrap().is_some() {
        assert!(
            Instant::now() < deadline,
            "samples still arrive without the router"
        );
    }
    // ... and comes back on the same endpoint. The bind may fail for a while: while the router
    // is away, the clients' reconnect attempts take ephemeral source ports, and one of them can
    // be this very port (the port came from the ephemeral range; a connect to a port nobody
    // listens on can even connect to itself on Linux). Such a socket lives only until its
    // handshake fails, so the new router retries its bind for up to 20 s.
    let bind_deadline = Instant::now() + Duration::from_secs(20);
    let _r2 = loop {
        match try_router() {
            Ok(r) => break r,
            Err(e) if Instant::now() < bind_deadline => {
                eprintln!("router restart: {e}; retrying");
                std::thread::sleep(Duration::from_millis(200));
            }
            Err(e) => panic!("the router could not listen again on {endpoint}: {e}"),
        }
    };
    let start = Instant::now();
    let again = sub.recv_timeout(Duration::from_secs(30)).unwrap();
    assert!(again.is_some(), "the bridge did not come back");
    eprintln!(
        "back through the restarted router after {:?}",
        start.elapsed()
    );
}
