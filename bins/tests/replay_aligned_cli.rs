//! `vigil replay FILE --emit aligned` end to end on a simulator recording: one line per decoded
//! message, each (device, index) of the truth exactly once, the fields the issue names, and a
//! reason for every sample without a time. The host clock is learned from the simulated VN-200, so
//! nearly everything is aligned; only what arrives before the model exists comes out with a reason
//! (the aligned accuracy is tested in vigil-fusion's `sim_truth`).

use std::collections::BTreeSet;
use std::path::PathBuf;

use serde_json::Value;

mod common;
use common::vigil;

fn tmp(name: &str) -> PathBuf {
    common::tmp("replay_aligned_cli", name)
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
    // With the simulated VN-200 feeding the host clock, nearly every message has a time; the few
    // that came before any clock model existed say why.
    let aligned = out.iter().filter(|l| !l["t_gps_ns"].is_null()).count();
    assert!(
        aligned * 100 >= out.len() * 99,
        "{aligned} of {} aligned",
        out.len()
    );
    let reasons: BTreeSet<&str> = out
        .iter()
        .filter_map(|l| l["not_aligned"].as_str())
        .collect();
    assert!(
        reasons.is_subset(&BTreeSet::from([
            "host_clock_unknown",
            "clock_unlocked",
            "no_time_message"
        ])),
        "{reasons:?}"
    );
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
