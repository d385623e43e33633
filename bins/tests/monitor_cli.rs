//! `vigil monitor` as a separate process: this test publishes hand-made payloads over iceoryx2 and
//! receives the alerts the monitor raises and clears on `vigil/alerts`.

mod common;

use common::Guard;

use std::io::{BufRead, BufReader, Read};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use vigil_bus::payload::alerts::{SEVERITY_CAUTION, STATE_CLEARED, STATE_RAISED};
use vigil_bus::payload::attitude::{FAULT_HEALTH, UNIT_BAHRS};
use vigil_bus::{AlertPayload, AttitudePayload, Bus, BusConfig, Subscriber};

fn bus(prefix: &str) -> Bus {
    Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: "monitor-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap()
}

/// Publishes `att` (stamped with a GPS time advancing 20 ms per sample from `*t_ns`) every 20 ms
/// until an alert with `alert_id` and `state` arrives; returns it. Other alerts (the topics this
/// test does not publish fall silent) are skipped.
fn publish_until(
    publ: &mut vigil_bus::Publisher<AttitudePayload>,
    alerts: &mut Subscriber<AlertPayload>,
    att: &AttitudePayload,
    t_ns: &mut i64,
    alert_id: u32,
    state: u8,
) -> AlertPayload {
    let start = Instant::now();
    loop {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "no alert 0x{alert_id:08X} in state {state}"
        );
        let mut a = *att;
        a.header.gps_time_ns = *t_ns;
        publ.publish(&a).unwrap();
        *t_ns += 20_000_000;
        std::thread::sleep(Duration::from_millis(20));
        while let Some(r) = alerts.try_receive().unwrap() {
            let got = *r.payload();
            if got.alert_id == alert_id && got.state == state {
                return got;
            }
        }
    }
}

#[test]
fn monitor_raises_and_clears_the_bahrs_integrity_risk_alert() {
    let prefix = format!("vigil-test-{}-monitor", std::process::id());
    let config = common::tmp("monitor_cli", "monitor.toml");
    // A shorter clear hysteresis than the default 1 s keeps the test quick and shows that the
    // `[monitor]` section is read; the other sections of the file are ignored.
    std::fs::write(
        &config,
        "[ports]\nbahrs = \"/dev/null\"\n\n[monitor.unit_health]\nclear_hysteresis_s = 0.2\n",
    )
    .unwrap();
    let b = bus(&prefix);
    let mut alerts = b.subscriber::<AlertPayload>().unwrap();
    let mut publ = b.publisher::<AttitudePayload>().unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["monitor", "--prefix", &prefix, "--config"])
        .arg(&config)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut guard = Guard(child);

    let healthy = AttitudePayload {
        valid: 1,
        ..AttitudePayload::default()
    };
    let mut risky = healthy;
    risky.units[usize::from(UNIT_BAHRS)].fault_flags = FAULT_HEALTH;
    // Rule unit_health (code 0x03), subject BAHRS (0).
    let id = 0x0300_0000;
    let mut t_ns = 1_400_000_000_000_000_000;
    let raised = publish_until(&mut publ, &mut alerts, &risky, &mut t_ns, id, STATE_RAISED);
    assert_eq!(raised.severity, SEVERITY_CAUTION);
    assert!(
        raised.reason().starts_with("BAHRS health integrity risk"),
        "{}",
        raised.reason()
    );
    // Raised at the time of a risky sample: at or after the first one sent.
    assert!(raised.raised_gps_ns >= 1_400_000_000_000_000_000);
    assert_eq!(raised.header.gps_time_ns, raised.raised_gps_ns);

    let cleared = publish_until(
        &mut publ,
        &mut alerts,
        &healthy,
        &mut t_ns,
        id,
        STATE_CLEARED,
    );
    assert_eq!(cleared.raised_gps_ns, raised.raised_gps_ns);
    // The hysteresis from the configuration: at least 0.2 s of GPS time after the raise.
    assert!(cleared.header.gps_time_ns - raised.raised_gps_ns >= 200_000_000);
    assert!(cleared.header.seq > raised.header.seq);

    // Publishing stops: the monitor's clock goes on with host time, so the attitude feed is
    // reported silent (rule feed_silent 0x0A, subject attitude 0) after the 2 s limit.
    let stopped = Instant::now();
    let silent = loop {
        let r = alerts
            .receive_timeout(Duration::from_secs(10))
            .unwrap()
            .expect("no feed-silent alert within 10 s");
        if r.alert_id == 0x0A00_0000 && r.state == STATE_RAISED {
            break *r.payload();
        }
    };
    assert!(stopped.elapsed() >= Duration::from_millis(1900));
    assert!(
        silent.reason().starts_with("no attitude payload for 2."),
        "{}",
        silent.reason()
    );

    // SIGTERM ends it cleanly, with its summary line.
    common::signal(&guard.0, "TERM");
    let status = common::wait_exit(&mut guard.0, Duration::from_secs(10));
    let mut stderr = String::new();
    guard
        .0
        .stderr
        .as_mut()
        .unwrap()
        .read_to_string(&mut stderr)
        .unwrap();
    assert!(status.success(), "{status:?}\n{stderr}");
    assert!(stderr.contains("vigil monitor: stopped;"), "{stderr}");
    assert!(stderr.contains("raised 0x03000000 caution"), "{stderr}");
}

#[test]
fn a_bad_monitor_key_is_named() {
    let config = common::tmp("monitor_cli", "bad.toml");
    std::fs::write(&config, "[monitor]\nfeed_silent_s = 2.0\nraise_delay = 1\n").unwrap();
    let o = common::vigil(&[
        "monitor",
        "--prefix",
        "vigil-test-bad-key",
        "--config",
        config.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("raise_delay"), "{err}");
}

#[test]
fn sigint_ends_it_cleanly() {
    let prefix = format!("vigil-test-{}-monitor-int", std::process::id());
    let child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["monitor", "--prefix", &prefix])
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut guard = Guard(child);
    // Signals are handled once it says it runs.
    let mut err = BufReader::new(guard.0.stderr.take().unwrap());
    let mut first = String::new();
    err.read_line(&mut first).unwrap();
    assert_eq!(
        first.trim_end(),
        format!(
            "vigil monitor: running: {p}/vigil/attitude, {p}/vigil/ownship, {p}/vigil/traffic, \
             {p}/vigil/integrity -> {p}/vigil/alerts",
            p = prefix
        )
    );
    common::signal(&guard.0, "INT");
    let status = common::wait_exit(&mut guard.0, Duration::from_secs(10));
    let mut stderr = String::new();
    err.read_to_string(&mut stderr).unwrap();
    assert!(status.success(), "{status:?}\n{stderr}");
    // Nothing was published, so it never had a GPS time and raised nothing.
    assert!(
        stderr.contains("0 payloads received (0 missed), 0 alerts published"),
        "{stderr}"
    );
}
