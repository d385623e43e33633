//! Issue 25, "a listener started 10 s after a warning was raised prints it as active": the
//! integrity report carries the active alert set, and `vigil listen alerts` prints it before any
//! transition. A publisher in this process stands in for `vigil run`: it raised a warning 10 s
//! (of GPS time) before the report it publishes now, and keeps publishing reports (and no
//! transition) while a listener started now runs.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use vigil_bus::payload::alerts::{SEVERITY_WARNING, STATE_RAISED};
use vigil_bus::payload::integrity::ActiveAlert;
use vigil_bus::payload::write_text;
use vigil_bus::{Bus, BusConfig, IntegrityPayload};

mod common;

use common::Guard;

#[test]
fn a_late_listener_prints_the_active_warning_first() {
    let prefix = format!("vigil-test-{}-listen-active", std::process::id());
    let b = Bus::new(&BusConfig {
        prefix: prefix.clone(),
        node_name: "listen-active-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let mut publ = b.publisher::<IntegrityPayload>().unwrap();
    let raised_ns: i64 = 1_400_000_000_000_000_000;
    let mut report = IntegrityPayload {
        active_alert_count: 1,
        active_alert_total: 1,
        ..IntegrityPayload::default()
    };
    report.active_alerts[0] = ActiveAlert {
        alert_id: 0x0400_0000,
        severity: SEVERITY_WARNING,
        state: STATE_RAISED,
        raised_gps_ns: raised_ns,
        ..ActiveAlert::default()
    };
    write_text(
        &mut report.active_alerts[0].reason,
        "voted attitude unusable; unit fault flags BAHRS 0x01 VN-200 0x02 Watson 0x02",
    );
    // The report published 10 s after the raise, before the listener exists.
    report.header.gps_time_ns = raised_ns + 10_000_000_000;
    publ.publish(&report).unwrap();
    let mut child = Guard(
        Command::new(env!("CARGO_BIN_EXE_vigil"))
            .args(["listen", "alerts", "--prefix", &prefix, "--count", "1"])
            .stdout(Stdio::piped())
            .spawn()
            .unwrap(),
    );
    // Reports every 250 ms, as `vigil run` with `integrity_period_s = 0.25`.
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.0.try_wait().unwrap() {
            break s;
        }
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "listen did not finish"
        );
        std::thread::sleep(Duration::from_millis(250));
        report.header.gps_time_ns += 250_000_000;
        publ.publish(&report).unwrap();
    };
    assert!(status.success());
    let lines: Vec<String> = BufReader::new(child.0.stdout.take().unwrap())
        .lines()
        .map(Result::unwrap)
        .collect();
    assert_eq!(lines.len(), 1, "{lines:?}");
    let v: serde_json::Value = serde_json::from_str(&lines[0]).unwrap();
    assert_eq!(v["topic"], "alerts");
    assert_eq!(v["active"], true);
    assert_eq!(v["alert_id"], 0x0400_0000);
    // Issue 26: words for the codes, UTC beside the GPS times. GPS 1 400 000 000 s is Unix
    // 1 400 000 000 + 315 964 800 (GPS epoch) - 18 (GPS - UTC since 2017) = 1 715 964 782 s:
    // 19 860 days (2024-01-01 is day 19 723; +137 in leap 2024 = May 17) and 60 782 s (16:53:02).
    assert_eq!(v["severity"], "warning");
    assert_eq!(v["state"], "raised");
    assert_eq!(v["raised_gps_ns"], raised_ns);
    assert_eq!(v["raised_utc"], "2024-05-17T16:53:02.000Z");
    // The report listened to is 10 to 30 s after the raise (published every 250 ms, 20 s limit).
    assert!(
        v["as_of_utc"]
            .as_str()
            .unwrap()
            .starts_with("2024-05-17T16:53:")
    );
    assert!(v["as_of_gps_ns"].as_i64().unwrap() >= raised_ns + 10_000_000_000);
    assert!(
        v["reason"]
            .as_str()
            .unwrap()
            .starts_with("voted attitude unusable")
    );
}
