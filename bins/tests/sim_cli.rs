//! `vigil sim` and `vigil replay` end to end: byte-identical recordings for the same seed,
//! identical replays, replay against the truth file, truncated recordings, bad arguments.

use std::path::{Path, PathBuf};

use serde_json::Value;

mod common;
use common::vigil;

fn tmp(name: &str) -> PathBuf {
    common::tmp("sim_cli", name)
}

fn sim(scenario: &str, seconds: &str, seed: &str, out: &Path, truth: &Path) {
    let o = vigil(&[
        "sim",
        "--scenario",
        scenario,
        "--duration",
        seconds,
        "--seed",
        seed,
        "--out",
        out.to_str().unwrap(),
        "--truth",
        truth.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn lines(bytes: &[u8]) -> Vec<Value> {
    bytes
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect()
}

#[test]
fn same_seed_same_bytes_and_replay_is_repeatable() {
    let (a, ta, b, tb) = (tmp("a.mcap"), tmp("a.jsonl"), tmp("b.mcap"), tmp("b.jsonl"));
    sim("link-errors", "30", "5", &a, &ta);
    sim("link-errors", "30", "5", &b, &tb);
    assert!(
        std::fs::read(&a).unwrap() == std::fs::read(&b).unwrap(),
        "mcap differs"
    );
    assert!(
        std::fs::read(&ta).unwrap() == std::fs::read(&tb).unwrap(),
        "truth differs"
    );
    let r1 = vigil(&["replay", a.to_str().unwrap()]);
    let r2 = vigil(&["replay", a.to_str().unwrap()]);
    assert!(r1.status.success());
    assert!(!r1.stdout.is_empty());
    assert!(
        r1.stdout == r2.stdout && r1.stderr == r2.stderr,
        "replays differ"
    );
}

#[test]
fn replay_lists_the_truth_messages_of_a_clean_run() {
    let (m, t) = (tmp("nominal.mcap"), tmp("nominal.jsonl"));
    sim("nominal", "12", "9", &m, &t);
    let truth = lines(&std::fs::read(&t).unwrap());
    let o = vigil(&["replay", m.to_str().unwrap()]);
    assert!(o.status.success());
    let replayed = lines(&o.stdout);
    assert_eq!(replayed.len(), truth.len());
    for device in ["bahrs", "watson"] {
        let t: Vec<_> = truth.iter().filter(|v| v["device"] == device).collect();
        let r: Vec<_> = replayed.iter().filter(|v| v["device"] == device).collect();
        assert_eq!(t.len(), r.len(), "{device}");
        for (t, r) in t.iter().zip(&r) {
            assert_eq!(t["index"], r["index"]);
            if device == "bahrs" {
                assert_eq!(t["type"], r["message"]["type"]);
                assert_eq!(t.get("seq"), r["message"].get("seq"));
            }
            // Received after the first byte left the device (host clock is within 10 ppm of GPS
            // and offset by the run's host-clock offset, so compare intervals instead).
            assert!(r["t_host_ns"].as_u64().unwrap() > 0);
        }
        // Receive-time intervals follow the true intervals within a few ms (latency jitter,
        // chunking and line time).
        let dt_true = (t.last().unwrap()["t_gps_ns"].as_i64().unwrap()
            - t[0]["t_gps_ns"].as_i64().unwrap()) as f64;
        let dt_host = (r.last().unwrap()["t_host_ns"].as_u64().unwrap()
            - r[0]["t_host_ns"].as_u64().unwrap()) as f64;
        assert!(
            (dt_true - dt_host).abs() < 80e6,
            "{device}: {dt_true} vs {dt_host}"
        );
    }
    let summary: Value = serde_json::from_slice(o.stderr.trim_ascii()).unwrap();
    assert_eq!(summary["damage"], Value::Null);
    assert_eq!(summary["devices"]["bahrs"]["bytes_skipped"], 0);
}

#[test]
fn truncated_recording_replays_up_to_the_damage() {
    let (m, t) = (tmp("trunc.mcap"), tmp("trunc.jsonl"));
    sim("nominal", "10", "2", &m, &t);
    let full = vigil(&["replay", m.to_str().unwrap()]);
    let bytes = std::fs::read(&m).unwrap();
    let cut = tmp("cut.mcap");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let o = vigil(&["replay", cut.to_str().unwrap()]);
    assert!(o.status.success());
    let (a, b) = (lines(&full.stdout).len(), lines(&o.stdout).len());
    assert!(b > 0 && b < a, "{b} of {a}");
    let summary: Value = serde_json::from_slice(o.stderr.trim_ascii()).unwrap();
    assert!(summary["damage"].is_string());
}

#[test]
fn unknown_scenario_is_an_error() {
    let o = vigil(&[
        "sim",
        "--scenario",
        "no-such",
        "--out",
        tmp("x.mcap").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("nominal"));
}

#[test]
fn replay_offsets_join_the_truth_under_link_faults() {
    let (m, t) = (tmp("faults.mcap"), tmp("faults.jsonl"));
    sim("link-errors", "45", "8", &m, &t);
    let truth = lines(&std::fs::read(&t).unwrap());
    let o = vigil(&["replay", m.to_str().unwrap()]);
    assert!(o.status.success());
    let replayed = lines(&o.stdout);
    for device in ["bahrs", "watson"] {
        let by_offset: std::collections::BTreeMap<u64, &Value> = replayed
            .iter()
            .filter(|v| v["device"] == device)
            .map(|v| (v["offset"].as_u64().unwrap(), v))
            .collect();
        let (mut intact, mut corrupted) = (0, 0);
        for r in truth.iter().filter(|v| v["device"] == device) {
            if r["corrupted"] == true {
                corrupted += 1;
                continue;
            }
            intact += 1;
            let d = by_offset
                .get(&r["rx_offset"].as_u64().unwrap())
                .unwrap_or_else(|| panic!("{device} truth index {} not replayed", r["index"]));
            if device == "bahrs" {
                assert_eq!(d["message"]["type"], r["type"]);
                assert_eq!(d["message"].get("seq"), r.get("seq"));
            }
        }
        assert!(
            corrupted > 0 && intact > 0,
            "{device}: {intact} intact, {corrupted} corrupted"
        );
        // Decoded messages that match no intact truth message come from corrupted ones.
        assert!(by_offset.len() - intact <= corrupted);
    }
}

#[test]
fn scenario_from_a_toml_file() {
    let file = tmp("mine.toml");
    std::fs::write(
        &file,
        r#"
name = "mine"
start_utc = "2026-03-01T08:00:00Z"
[ownship]
lat_deg = -33.9
lon_deg = 151.2
height_m = 50.0
track_deg = 270.0
speed_mps = 25.0
segments = [{ kind = "turn", duration_s = 10.0, rate_dps = -6.0 }]
[devices.watson]
"#,
    )
    .unwrap();
    let (m, t) = (tmp("mine.mcap"), tmp("mine.jsonl"));
    sim(file.to_str().unwrap(), "3", "1", &m, &t);
    let truth = lines(&std::fs::read(&t).unwrap());
    // Only the Watson is present: about 11.85 lines per second.
    assert!(truth.iter().all(|v| v["device"] == "watson"));
    assert!((34..=37).contains(&truth.len()), "{}", truth.len());
    // Left turn at 6 deg/s and 25 m/s: bank = -atan(25 x 0.10472 / 9.80665) = -14.95 deg.
    let bank = truth[5]["bank_deg"].as_f64().unwrap();
    assert!((bank + 14.95).abs() < 0.01, "{bank}");
    // A bad key in the file is named in the error.
    std::fs::write(
        &file,
        std::fs::read_to_string(&file)
            .unwrap()
            .replace("speed_mps", "sped_mps"),
    )
    .unwrap();
    let o = vigil(&[
        "sim",
        "--scenario",
        file.to_str().unwrap(),
        "--out",
        m.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("sped_mps"));
}

#[test]
fn replay_at_a_given_speed_is_paced_and_gives_the_same_output() {
    let (m, t) = (tmp("speed.mcap"), tmp("speed.jsonl"));
    sim("headon", "2", "1", &m, &t);
    let fast = vigil(&["replay", m.to_str().unwrap()]);
    let start = std::time::Instant::now();
    let paced = vigil(&["replay", m.to_str().unwrap(), "--speed", "4"]);
    let wall = start.elapsed().as_secs_f64();
    assert!(paced.status.success());
    assert!(paced.stdout == fast.stdout);
    // 2 s of recording at 4x: about 0.5 s (the first chunk arrives a few ms after the start).
    assert!(wall > 0.45, "{wall}");
    let o = vigil(&["replay", m.to_str().unwrap(), "--speed", "0"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn truth_channel_can_be_left_out() {
    let (a, ta, b, tb) = (
        tmp("with.mcap"),
        tmp("with.jsonl"),
        tmp("without.mcap"),
        tmp("without.jsonl"),
    );
    sim("headon", "5", "3", &a, &ta);
    let o = vigil(&[
        "sim",
        "--scenario",
        "headon",
        "--duration",
        "5",
        "--seed",
        "3",
        "--no-truth-channel",
        "--out",
        b.to_str().unwrap(),
        "--truth",
        tb.to_str().unwrap(),
    ]);
    assert!(o.status.success());
    assert!(std::fs::read(&ta).unwrap() == std::fs::read(&tb).unwrap());
    let (la, lb) = (
        std::fs::metadata(&a).unwrap().len(),
        std::fs::metadata(&b).unwrap().len(),
    );
    // With zstd chunks (issue 20) the truth channel compresses better than the raw bytes, so the
    // file without it is smaller, no longer a third of the size.
    assert!(lb < la, "{lb} vs {la}");
    let ra = vigil(&["replay", a.to_str().unwrap()]);
    let rb = vigil(&["replay", b.to_str().unwrap()]);
    assert!(ra.stdout == rb.stdout);
}

#[test]
fn replaying_something_else_is_an_error() {
    let f = tmp("not.mcap");
    std::fs::write(&f, b"hello, not a recording").unwrap();
    let o = vigil(&["replay", f.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a readable mcap recording"));
    let o = vigil(&["replay", tmp("missing.mcap").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
}
