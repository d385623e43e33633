//! `vigil replay FILE --emit fused` end to end on a simulator recording of `headon`: the three
//! kinds of line with the fields the issues name, on a 1 s grid for ownship and traffic, and the
//! same bytes from two replays.

use std::path::PathBuf;

use serde_json::Value;

mod common;
use common::vigil;

fn tmp(name: &str) -> PathBuf {
    common::tmp("replay_fused_cli", name)
}

#[test]
fn fused_lines_have_the_named_fields_and_replays_are_identical() {
    let m = tmp("headon.mcap");
    let o = vigil(&[
        "sim",
        "--scenario",
        "headon",
        "--duration",
        "25",
        "--seed",
        "5",
        "--out",
        m.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let run = || {
        let o = vigil(&["replay", m.to_str().unwrap(), "--emit", "fused"]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        o.stdout
    };
    let (a, b) = (run(), run());
    assert_eq!(a, b, "two replays differ");
    let lines: Vec<Value> = a
        .split(|&c| c == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect();
    let of = |k: &str| -> Vec<&Value> { lines.iter().filter(|l| l["kind"] == k).collect() };
    let (att, own, traffic) = (of("attitude_check"), of("ownship"), of("traffic"));
    // Issue 20: the monitor's alert transitions and the active set after each are fused outputs too.
    let (alerts, active) = (of("alert"), of("alerts_active"));
    assert_eq!(alerts.len(), active.len());
    assert_eq!(
        att.len() + own.len() + traffic.len() + alerts.len() + active.len(),
        lines.len()
    );
    // BAHRS navigation at 50 Hz for 25 s (minus the start-up before the clocks lock).
    assert!(att.len() > 20 * 50, "{} attitude checks", att.len());
    for r in &att {
        assert!(r["t_gps_ns"].is_i64());
        assert_eq!(r["fault"], false);
        assert!(r["isolated"].is_null());
        for pair in ["bahrs_vn200", "bahrs_watson", "vn200_watson"] {
            assert!(r["pairs"][pair]["roll"]["verdict"].is_string());
        }
    }
    // Ownship and traffic once per second, on whole seconds of GPS time.
    assert!(own.len() >= 22 && own.len() == traffic.len());
    for (o, t) in own.iter().zip(&traffic) {
        let ts = o["t_gps_ns"].as_i64().unwrap();
        assert_eq!(ts % 1_000_000_000, 0);
        assert_eq!(t["t_gps_ns"].as_i64(), Some(ts));
        assert_eq!(o["source"], "vn200_ins");
        assert!(o["lat_deg"].as_f64().unwrap() > 47.0);
        // Issue 26: UTC beside the GPS time. The scenario starts at 2026-06-01T10:00:00Z (its
        // `start_utc`): Unix 20 605 days (2026-01-01 is day 20 454, + 151 to June 1) x 86 400 +
        // 36 000 = 1 780 308 000 s, GPS 1 780 308 000 - 315 964 800 + 18 = 1 464 343 218 s.
        let since_start_s = ts / 1_000_000_000 - 1_464_343_218;
        assert!((0..60).contains(&since_start_s));
        assert_eq!(
            o["t_utc"],
            format!("2026-06-01T10:00:{since_start_s:02}.000Z")
        );
        assert_eq!(t["t_utc"], o["t_utc"]);
    }
    // The head-on intruder (4B1A01) with its geometry: closing at 100 m/s from 8000 m.
    let last = traffic.last().unwrap();
    let x = &last["targets"][0];
    assert_eq!(x["key"]["address"], "4B1A01");
    let g = &x["geometry"];
    let r = g["horizontal_distance_m"].as_f64().unwrap();
    let rr = g["range_rate_mps"].as_f64().unwrap();
    assert!((rr + 100.0).abs() < 2.0, "range rate {rr}");
    assert!(r > 5000.0 && r < 6000.0, "range {r}");
    assert_eq!(x["alert_level"], "warning");
    assert_eq!(
        x["geometry"]["lowc_interval_s"].as_array().map(Vec::len),
        Some(2)
    );
}
