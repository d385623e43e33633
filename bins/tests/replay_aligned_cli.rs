//! `vigil replay FILE --emit aligned` end to end on a simulator recording: one line per decoded
//! message, each (device, index) of the truth exactly once, the fields the issue names, and a
//! reason for every sample without a time. The simulator has no VN-200 model yet, so no host
//! clock can be learned from the recording: BAHRS and Watson samples come out not aligned, with
//! their reasons (the aligned accuracy is tested in vigil-fusion's `sim_truth`).

use std::collections::BTreeSet;
use std::path::PathBuf;
use std::process::{Command, Output};

use serde_json::Value;

fn vigil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(args)
        .output()
        .expect("run vigil")
}

fn tmp(name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("replay_aligned_cli");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn lines(bytes: &[u8]) -> Vec<Value> {
    bytes
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| serde_json::from_slice(l).unwrap())
        .collect()
}

#[test]
fn every_truth_message_comes_out_once_with_a_time_or_a_reason() {
    let (m, t) = (tmp("nominal.mcap"), tmp("nominal.jsonl"));
    let o = vigil(&[
        "sim",
        "--scenario",
        "nominal",
        "--duration",
        "12",
        "--seed",
        "3",
        "--out",
        m.to_str().unwrap(),
        "--truth",
        t.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let truth = lines(&std::fs::read(&t).unwrap());
    let o = vigil(&["replay", m.to_str().unwrap(), "--emit", "aligned"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = lines(&o.stdout);
    let want: BTreeSet<(String, u64)> = truth
        .iter()
        .map(|r| {
            (
                r["device"].as_str().unwrap().to_string(),
                r["index"].as_u64().unwrap(),
            )
        })
        .collect();
    let mut got = BTreeSet::new();
    for l in &out {
        let key = (
            l["device"].as_str().unwrap().to_string(),
            l["index"].as_u64().unwrap(),
        );
        assert!(got.insert(key.clone()), "{key:?} twice");
        for f in [
            "t_gps_ns",
            "sigma_ns",
            "time_source",
            "status",
            "not_aligned",
        ] {
            assert!(l.get(f).is_some(), "{f} missing in {l}");
        }
        // A time, or a reason: never neither.
        assert_ne!(l["t_gps_ns"].is_null(), l["not_aligned"].is_null(), "{l}");
    }
    assert_eq!(got, want);
    // Without VN-200 references nothing has a host clock: the reasons say so.
    let reasons: BTreeSet<&str> = out
        .iter()
        .filter_map(|l| l["not_aligned"].as_str())
        .collect();
    assert!(reasons.contains("host_clock_unknown") || reasons.contains("clock_unlocked"));
    // Deterministic.
    let again = vigil(&["replay", m.to_str().unwrap(), "--emit", "aligned"]);
    assert_eq!(again.stdout, o.stdout);
    // --speed is for decoded output.
    let bad = vigil(&[
        "replay",
        m.to_str().unwrap(),
        "--emit",
        "aligned",
        "--speed",
        "2",
    ]);
    assert!(!bad.status.success());
}
