//! `vigil replay FILE --publish --speed max` while `vigil listen traffic --lossless` runs in
//! another process (issue 11, "Done when"): the subscriber receives every traffic message, in
//! order, and two replays publish the same sequence (same GPS times, same content).

use std::io::{BufRead, BufReader};
use std::path::Path;
use std::process::{Command, Stdio};

use serde_json::Value;

mod common;

fn replay_and_listen(prefix: &str) -> (Vec<Value>, String) {
    let mcap = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/replay/headon.mcap");
    let mut listen = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["listen", "traffic", "--lossless", "--prefix", prefix])
        .args(["--duration", "60", "--count", "54"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start vigil listen");
    // Wait until it is subscribed, so the first sample is not missed.
    let mut err = BufReader::new(listen.stderr.take().unwrap()).lines();
    let line = err.next().expect("listen stderr").unwrap();
    assert!(line.contains("subscribed to"), "{line}");
    let replay = common::vigil(&[
        "replay",
        mcap.to_str().unwrap(),
        "--publish",
        "--speed",
        "max",
        "--prefix",
        prefix,
    ]);
    assert!(
        replay.status.success(),
        "{}",
        String::from_utf8_lossy(&replay.stderr)
    );
    let summary = String::from_utf8_lossy(&replay.stderr).into_owned();
    let out = listen.wait_with_output().unwrap();
    let lines = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    (lines, summary)
}

#[test]
fn a_subscriber_in_another_process_receives_every_traffic_message_in_order() {
    let prefix = format!("vigil-test-{}-replay-publish", std::process::id());
    let (a, summary) = replay_and_listen(&format!("{prefix}-a"));
    // The recording is 55 s: one traffic picture per 1 s step once the clocks lock (the golden
    // file lists 54 of them).
    assert!(summary.contains("\"traffic\":54"), "{summary}");
    let seqs: Vec<&Value> = a.iter().map(|m| &m["header"]["seq"]).collect();
    assert_eq!(a.len(), 54, "{seqs:?}");
    for (i, m) in a.iter().enumerate() {
        assert_eq!(m["header"]["seq"], i as u64 + 1, "in order, none missing");
        assert_eq!(m["missed_before"], 0);
        assert_eq!(m["count"], 1);
        assert_eq!(m["targets"][0]["address"], "4B1A01");
    }
    // Pictures one GPS second apart.
    let t: Vec<i64> = a
        .iter()
        .map(|m| m["header"]["gps_time_ns"].as_i64().unwrap())
        .collect();
    assert!(t.windows(2).all(|w| w[1] - w[0] == 1_000_000_000), "{t:?}");
    // Deterministic: a second replay publishes the same sequence (the send time aside).
    let (b, _) = replay_and_listen(&format!("{prefix}-b"));
    let strip = |v: &[Value]| -> Vec<Value> {
        v.iter()
            .cloned()
            .map(|mut m| {
                m["header"]["send_mono_ns"] = Value::Null;
                m
            })
            .collect()
    };
    assert_eq!(strip(&a), strip(&b));
}
