//! `vigil measure` end to end (issue 10, "Measured and reported"): the simulator writes to
//! pseudo-terminals in the test's process tree, `vigil run` reads them in a child process, and
//! `vigil measure` itself subscribes to `vigil/attitude`. Timing figures are not asserted (speed
//! is measured, not tested); what is asserted is the path: every VN-200 message written in the
//! window comes back as a fused attitude at its own GPS time (or is counted as missed by the
//! subscriber), and the process figures are read.

use std::process::Command;

use serde_json::Value;

/// `vigil measure` on the `nominal` scenario (VN-200 at 200 Hz) for a 3 s window after 2 s,
/// with `extra` arguments: its report, once it has succeeded.
fn measure_nominal(extra: &[&str]) -> Value {
    measure_nominal_with_stderr(extra).0
}

/// [`measure_nominal`], and what it wrote to stderr.
fn measure_nominal_with_stderr(extra: &[&str]) -> (Value, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args([
            "measure",
            "--scenario",
            "nominal",
            "--duration",
            "3",
            "--warmup",
            "2",
        ])
        .args(extra)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "{stderr}");
    (serde_json::from_slice(&out.stdout).unwrap(), stderr)
}

#[test]
fn every_vn200_message_comes_back_as_a_fused_attitude_in_another_process() {
    let r = measure_nominal(&[]);
    let messages = r["vn200_messages"].as_u64().unwrap();
    let matched = r["matched"].as_u64().unwrap();
    let missed = r["missed"].as_u64().unwrap();
    // `nominal`: VN-200 at 200 Hz, 3 s window.
    assert!((500..=700).contains(&messages), "{r}");
    // A payload the subscriber missed (latest-state topic under load) is counted, not silent.
    assert!(
        matched + missed >= messages && matched * 2 > messages,
        "{r}"
    );
    let lat = &r["latency"];
    assert_eq!(lat["samples"].as_u64(), Some(matched));
    assert!(lat["p50_us"].as_f64().unwrap() <= lat["p99_us"].as_f64().unwrap());
    assert!(r["cpu_percent_of_one_core"].as_f64().unwrap() > 0.0, "{r}");
    let rss = r["rss_mb"].as_f64().unwrap();
    assert!(rss > 1.0 && rss < 200.0, "{r}");
    // `nominal`'s devices fit their lines: none loses a message before the terminals, and the
    // service raises no full-line alert.
    assert_eq!(
        r["device_lost_messages"].as_object().map(|m| m.len()),
        Some(0),
        "{r}"
    );
    let alerts = r["alerts"].as_array().unwrap();
    assert!(
        !alerts
            .iter()
            .any(|a| a.as_str().unwrap().contains("fills its serial line")),
        "{r}"
    );
}

/// A TT-Multi-RF whose output exceeds its line (forty targets in JSON and raw HEX at 9600
/// baud, about 960 bytes/s): the simulated module discards what its buffer cannot hold, which
/// `vigil measure` reports from the simulator's truth, and `vigil run`, which never sees those
/// messages, says its line is full (`line_full`, raised about 1.3 s after the start).
#[test]
fn a_ttmrf_line_too_slow_for_its_output_is_reported_and_alerted() {
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../tests/data/rules/base.toml"
    ))
    .unwrap();
    let toml = base.replace(
        "[devices.ttmrf]",
        "[traffic]\ncount = 40\nradius_m = 20000.0\nheight_band_m = 1000.0\nseed = 44\n\n\
         [devices.ttmrf]\nbaud = 9600\nraw = \"hex\"",
    );
    assert_ne!(toml, base);
    let dir = std::env::temp_dir().join(format!("vigil-measure-line-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("slow-tt.toml");
    std::fs::write(&path, toml).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["measure", "--duration", "3", "--warmup", "1", "--scenario"])
        .arg(&path)
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    let lost = &r["device_lost_messages"];
    assert!(lost["ttmrf"].as_u64().unwrap_or(0) > 0, "{r}");
    // Only the TT-Multi-RF's line is too slow.
    assert_eq!(lost.as_object().unwrap().len(), 1, "{r}");
    let alerts = r["alerts"].as_array().unwrap();
    assert!(
        alerts.iter().any(|a| {
            let a = a.as_str().unwrap();
            a.contains("raised: TT-Multi-RF output fills its serial line")
        }),
        "{r}"
    );
    // The terminals themselves lost nothing: the service read in time.
    let dropped = r["dropped_bytes"].as_object().unwrap();
    assert!(dropped.values().all(|v| v.as_u64() == Some(0)), "{r}");
}

#[test]
fn bad_arguments_are_refused() {
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["measure", "--duration", "0"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("--duration"));
}

/// `--floor` (issue 21): a reader of the same terminals in `vigil run`'s place keeps up (no
/// dropped bytes; the VN-200's 22 KB/s would fill its terminal within the run if it were not
/// read), is woken at least once per VN-200 message (read on arrival, 200 Hz in `nominal`),
/// and reports no latency, since it publishes nothing.
#[test]
fn the_floor_reader_reads_every_port_and_publishes_nothing() {
    let r = measure_nominal(&["--floor", "--max-chunk-bytes", "4096"]);
    let dropped = r["dropped_bytes"].as_object().unwrap();
    assert_eq!(dropped.len(), 4, "{r}");
    assert!(dropped.values().all(|v| v.as_u64() == Some(0)), "{r}");
    assert!(r["latency"].is_null(), "{r}");
    assert_eq!(r["matched"].as_u64(), Some(0), "{r}");
    assert!(r["vn200_messages"].as_u64().unwrap() >= 500, "{r}");
    assert!(r["wakeups_per_s"].as_f64().unwrap() >= 150.0, "{r}");
    assert!(r["cpu_percent_of_one_core"].as_f64().unwrap() > 0.0, "{r}");
}

#[test]
fn the_floor_does_not_combine_with_options_of_vigil_run() {
    for extra in [["--record", "raw"], ["--cpu-wakeup-latency-us", "0"]] {
        let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
            .args(["measure", "--floor"])
            .args(extra)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{extra:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("cannot be used with"),
            "{extra:?}"
        );
    }
}

/// The floor reads the ports as `vigil run` would (its configuration check), so it refuses
/// what `vigil run` refuses: a paced VN-200.
#[test]
fn the_floor_refuses_a_paced_vn200_like_vigil_run() {
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["measure", "--floor", "--read-interval-ms", "vn200=10"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("it is read as its bytes arrive"),
        "{stderr}"
    );
}

/// `--floor-publish` (issue 21): the floor reader also decodes the VN-200 and publishes each
/// message's GPS time, and `vigil measure` matches those against the simulator's own record of
/// what it wrote (its truth, not the reader's): every message of the window comes back at its
/// own GPS time or is counted as missed, the reader keeps up with every port, and it stops
/// cleanly on SIGTERM (iceoryx2 catches it, so the bus is released).
#[test]
fn the_publishing_floor_returns_every_vn200_time_and_stops_cleanly() {
    let (r, stderr) = measure_nominal_with_stderr(&["--floor-publish"]);
    assert!(!stderr.contains("did not stop cleanly"), "{stderr}");
    let messages = r["vn200_messages"].as_u64().unwrap();
    let matched = r["matched"].as_u64().unwrap();
    let missed = r["missed"].as_u64().unwrap();
    assert!((500..=700).contains(&messages), "{r}");
    assert!(
        matched + missed >= messages && matched * 10 >= messages * 9,
        "{r}"
    );
    assert_eq!(r["latency"]["samples"].as_u64(), Some(matched), "{r}");
    assert_eq!(r["write_to_send"]["samples"].as_u64(), Some(matched), "{r}");
    let dropped = r["dropped_bytes"].as_object().unwrap();
    assert!(dropped.values().all(|v| v.as_u64() == Some(0)), "{r}");
}

/// The hidden reader refuses a `--vn200` that is not one of its ports read on arrival (it would
/// otherwise publish nothing and report no latency without saying why), and `--bus-prefix` and
/// `--vn200` come together.
#[test]
fn the_publishing_floor_needs_its_vn200_among_the_ports_read_on_arrival() {
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
            .arg("measure-floor")
            .args(args)
            .output()
            .unwrap();
        assert!(!out.status.success(), "{args:?}");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let stderr = run(&[
        "--port",
        "10:/dev/null",
        "--bus-prefix",
        "floortest",
        "--vn200",
        "/dev/null",
    ]);
    assert!(
        stderr.contains("not one of the ports read on arrival"),
        "{stderr}"
    );
    let stderr = run(&["--port", "0:/dev/null", "--vn200", "/dev/null"]);
    assert!(stderr.contains("--bus-prefix"), "{stderr}");
    for extra in ["--record=raw", "--floor"] {
        let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
            .args(["measure", "--floor-publish", extra])
            .output()
            .unwrap();
        assert!(!out.status.success(), "{extra}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("cannot be used with"),
            "{extra}"
        );
    }
}

#[test]
fn the_alerts_of_the_run_are_reported_in_order_with_their_time() {
    // The BAHRS flags its roll an integrity risk from the scenario's t = 1 s: the monitor's
    // alert must be in the report, raised, and not before the fault. (The run's start is the
    // simulator's t = 0 give or take the few ms `vigil measure` takes to start writing.)
    let scenario =
        std::env::temp_dir().join(format!("vigil-measure-alert-{}.toml", std::process::id()));
    std::fs::write(
        &scenario,
        r#"
name = "bahrs-roll-health"
description = "BAHRS roll flagged an integrity risk from t = 1 s"
start_utc = "2026-06-01T10:00:00Z"

[ownship]
lat_deg = 47.40
lon_deg = 8.50
height_m = 600.0
track_deg = 90.0
speed_mps = 40.0
segments = [{ kind = "straight", duration_s = 60.0 }]

[[faults]]
kind = "bahrs_health"
from_s = 1.0
signal = "roll"
health = "integrity_risk"

[devices.bahrs]
[devices.watson]
[devices.vn200]
"#,
    )
    .unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["measure", "--scenario"])
        .arg(&scenario)
        .args(["--duration", "3", "--warmup", "1"])
        .output()
        .unwrap();
    let _ = std::fs::remove_file(&scenario);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let r: Value = serde_json::from_slice(&out.stdout).unwrap();
    let alerts: Vec<&str> = r["alerts"]
        .as_array()
        .unwrap_or_else(|| panic!("no alerts array: {r}"))
        .iter()
        .map(|a| a.as_str().unwrap())
        .collect();
    let raised = alerts
        .iter()
        .find(|a| a.contains(": raised: BAHRS health integrity risk"))
        .unwrap_or_else(|| panic!("{alerts:?}"));
    let at_s: f64 = raised.split(" s: ").next().unwrap().parse().unwrap();
    assert!((1.0..4.0).contains(&at_s), "{raised}");
    let times: Vec<f64> = alerts
        .iter()
        .map(|a| a.split(" s: ").next().unwrap().parse().unwrap())
        .collect();
    assert!(times.is_sorted(), "{alerts:?}");
}
