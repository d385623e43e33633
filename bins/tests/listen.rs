//! `vigil listen` as a second-process consumer: it prints what a publisher in this process sends
//! (JSON Lines), and its latency summary.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use vigil_bus::payload::alerts::SEVERITY_CAUTION;
use vigil_bus::payload::traffic::{ADDRESS_FLARM_FIXED, ALERT_CORRECTIVE, ALTITUDE_GEOMETRIC};
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, FixedPayload, Publisher, Target, TrafficPayload,
};

fn bus(prefix: &str) -> Bus {
    Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: "listen-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap()
}

/// Runs `vigil listen ARGS` while publishing `make(i)` every `period` until it exits; returns
/// its stdout lines.
fn listen_while_publishing<T: FixedPayload>(
    args: &[&str],
    publ: &mut Publisher<T>,
    period: Duration,
    make: impl Fn(u64) -> T,
) -> Vec<String> {
    listen_while(args, period, |i| {
        publ.publish(&make(i)).unwrap();
    })
}

/// Runs `vigil listen ARGS` while calling `send(i)` every `period` until it exits; returns its
/// stdout lines.
fn listen_while(args: &[&str], period: Duration, mut send: impl FnMut(u64)) -> Vec<String> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .arg("listen")
        .args(args)
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let mut i = 0;
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "listen did not finish"
        );
        send(i);
        i += 1;
        std::thread::sleep(period);
    };
    assert!(status.success());
    BufReader::new(child.stdout.take().unwrap())
        .lines()
        .map(Result::unwrap)
        .collect()
}

#[test]
fn listen_prints_alerts_as_json_lines() {
    let prefix = format!("vigil-test-{}-listen-alerts", std::process::id());
    let b = bus(&prefix);
    let mut publ = b.publisher::<AlertPayload>().unwrap();
    let lines = listen_while_publishing(
        &["alerts", "--prefix", &prefix, "--count", "3"],
        &mut publ,
        Duration::from_millis(20),
        |i| {
            let mut a = AlertPayload {
                alert_id: 100 + i as u32,
                severity: SEVERITY_CAUTION,
                ..Default::default()
            };
            a.set_reason(&format!("gnss lost #{i}"));
            a
        },
    );
    assert_eq!(lines.len(), 3, "{lines:?}");
    let mut prev_seq = 0;
    for line in &lines {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["topic"], "alerts");
        assert_eq!(v["missed_before"], 0);
        assert_eq!(v["severity"], "caution");
        // The publisher left the GPS time 0 (no time): its UTC is null.
        assert_eq!(v["header"]["gps_time_ns"], 0);
        assert!(v["header"]["time_utc"].is_null());
        // The alert published as number i carries seq i + 1, id 100 + i and reason "#i".
        let seq = v["header"]["seq"].as_u64().unwrap();
        assert!(seq > prev_seq);
        prev_seq = seq;
        assert_eq!(v["alert_id"].as_u64().unwrap(), 100 + seq - 1);
        assert_eq!(v["reason"], format!("gnss lost #{}", seq - 1));
        assert_eq!(v["header"]["schema_version"], vigil_bus::SCHEMA_VERSION);
    }
}

/// Issue 26: traffic (schema 3) is a slice service; `vigil listen traffic` prints each picture
/// with as many targets as were published, and the new absolute state.
#[test]
fn listen_prints_traffic_pictures_of_their_own_length() {
    let prefix = format!("vigil-test-{}-listen-traffic", std::process::id());
    let b = bus(&prefix);
    let mut publ = b.traffic_publisher().unwrap();
    let lines = listen_while(
        &["traffic", "--prefix", &prefix, "--count", "3"],
        Duration::from_millis(20),
        |i| {
            // Picture i holds i % 3 + 1 targets, the first 150 m below the ownship.
            let n = (i % 3 + 1) as usize;
            let targets: Vec<Target> = (0..n)
                .map(|k| Target {
                    address: 0xC0FFE0 + k as u32,
                    lat_deg: 47.5,
                    lon_deg: -8.25,
                    rel_down_m: 150.0,
                    ..Target::EMPTY
                })
                .collect();
            let mut p = TrafficPayload::default();
            p.set_targets(&targets);
            publ.publish(&p).unwrap();
        },
    );
    assert_eq!(lines.len(), 3, "{lines:?}");
    for line in &lines {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        assert_eq!(v["topic"], "traffic");
        let seq = v["header"]["seq"].as_u64().unwrap();
        // Published picture number seq - 1 held (seq - 1) % 3 + 1 targets.
        let n = ((seq - 1) % 3 + 1) as usize;
        let targets = v["targets"].as_array().unwrap();
        assert_eq!(targets.len(), n, "{line}");
        assert_eq!(v["count"], n);
        assert_eq!(targets[0]["lat_deg"], 47.5);
        assert_eq!(targets[0]["lon_deg"], -8.25);
        assert_eq!(targets[0]["rel_down_m"], 150.0);
        // Unknowns print as null, never as a number.
        assert!(targets[0]["alt_pressure_m"].is_null());
        assert_eq!(v["header"]["schema_version"], 3);
    }
}

/// Issue 26: the traffic payload's address as six hex digits, its codes as words, its GPS time
/// with UTC beside it.
#[test]
fn listen_prints_traffic_with_hex_addresses_words_and_utc() {
    let prefix = format!("vigil-test-{}-listen-traffic-names", std::process::id());
    let b = bus(&prefix);
    let mut publ = b.traffic_publisher().unwrap();
    // GPS week 1899 began 2016-05-29 00:00:00 GPS (1899 x 7 days after 1980-01-06); GPS - UTC
    // was 17 s. Tuesday 2016-05-31 10:00:01.250 UTC is 2 d + 10 h + 1.25 s + 17 s into the week.
    let t_gps_ns: i64 = (1899 * 604_800 + 172_800 + 36_018) * 1_000_000_000 + 250_000_000;
    let lines = listen_while(
        &["traffic", "--prefix", &prefix, "--count", "1"],
        Duration::from_millis(20),
        |_| {
            let mut t = TrafficPayload::default();
            t.header.gps_time_ns = t_gps_ns;
            t.set_targets(&[Target {
                address: 0x4B1A01,
                address_type: ADDRESS_FLARM_FIXED,
                alert_level: ALERT_CORRECTIVE,
                altitude_kind: ALTITUDE_GEOMETRIC,
                time_to_lowc_s: 12.5,
                ..Target::EMPTY
            }]);
            publ.publish(&t).unwrap();
        },
    );
    assert_eq!(lines.len(), 1, "{lines:?}");
    let v: serde_json::Value = serde_json::from_str(&lines[0]).unwrap();
    assert_eq!(v["topic"], "traffic");
    assert_eq!(v["header"]["gps_time_ns"], t_gps_ns);
    assert_eq!(v["header"]["time_utc"], "2016-05-31T10:00:01.250Z");
    let x = &v["targets"][0];
    assert_eq!(x["address"], "4B1A01");
    assert_eq!(x["address_type"], "flarm_fixed");
    assert_eq!(x["alert_level"], "corrective");
    assert_eq!(x["altitude_kind"], "geometric");
    assert_eq!(x["time_to_lowc_s"], 12.5);
}

#[test]
fn listen_latency_prints_a_summary() {
    let prefix = format!("vigil-test-{}-listen-latency", std::process::id());
    let b = bus(&prefix);
    let mut publ = b.publisher::<AttitudePayload>().unwrap();
    let lines = listen_while_publishing(
        &[
            "attitude",
            "--prefix",
            &prefix,
            "--count",
            "50",
            "--latency",
        ],
        &mut publ,
        Duration::from_millis(2),
        |_| AttitudePayload::default(),
    );
    assert_eq!(lines.len(), 1, "{lines:?}");
    let v: serde_json::Value = serde_json::from_str(&lines[0]).unwrap();
    assert_eq!(v["samples"], 50);
    let (p50, p99, max) = (
        v["p50_us"].as_f64().unwrap(),
        v["p99_us"].as_f64().unwrap(),
        v["max_us"].as_f64().unwrap(),
    );
    eprintln!("vigil listen --latency: {v}");
    assert!(0.0 < p50 && p50 <= p99 && p99 <= max);
    // Generous: a wake-up on a loaded 2-core machine, far below the 2 ms publishing period x 50.
    assert!(p50 < 100_000.0, "median latency {p50} us");
}

/// Issue 26: with nothing publishing, `vigil listen` says so after about 2 s, naming the
/// prefixes where vigil services do exist (here the test's own publisher's), and SIGINT or
/// SIGTERM ends it quietly with exit status 0 (it once failed with "wait on traffic:
/// InterruptSignal").
#[cfg(target_os = "linux")]
#[test]
fn listen_without_a_publisher_says_so_and_ends_quietly_on_a_signal() {
    let pid = std::process::id();
    // A vigil service under another prefix, for the hint to name.
    let other = format!("listen-other{pid}");
    let b = bus(&other);
    let _publ = b.publisher::<AttitudePayload>().unwrap();
    for signal in ["TERM", "INT"] {
        let start = Instant::now();
        let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
            .args(["listen", "traffic", "--prefix", &format!("nobody{pid}")])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        let mut err = BufReader::new(child.stderr.take().unwrap()).lines();
        let hint = loop {
            let l = err.next().expect("a hint line before stderr ends").unwrap();
            if l.contains("nothing publishes") {
                break l;
            }
        };
        let waited = start.elapsed();
        assert!(
            waited >= Duration::from_millis(1900) && waited < Duration::from_secs(10),
            "{waited:?}"
        );
        assert!(
            hint.contains(&format!("nobody{pid}/vigil/traffic")),
            "{hint}"
        );
        assert!(
            hint.contains(&format!("vigil listen traffic --prefix {other}")),
            "{hint}"
        );
        let kill = Command::new("kill")
            .args([format!("-{signal}"), child.id().to_string()])
            .status()
            .unwrap();
        assert!(kill.success());
        let status = child.wait().unwrap();
        let rest: Vec<String> = err.map_while(Result::ok).collect();
        assert!(status.success(), "SIG{signal}: {status:?}, stderr {rest:?}");
        assert!(
            rest.iter().all(|l| !l.contains("error")),
            "SIG{signal}: {rest:?}"
        );
    }
}
