//! The golden replay suite (issue 11): every recording under `tests/data/replay/` replays to
//! its committed golden file within tolerance; a perturbed golden value fails with a report that
//! names the record, the field, both values and the difference; `--bless` reproduces the
//! committed file byte for byte (the replay is deterministic).

use std::path::{Path, PathBuf};

mod common;
use common::vigil;

fn library() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/replay")
}

fn recordings() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(library())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "mcap"))
        .collect();
    v.sort();
    v
}

fn check(mcap: &Path, golden: &Path) -> std::process::Output {
    vigil(&[
        "replay",
        mcap.to_str().unwrap(),
        "--check",
        golden.to_str().unwrap(),
    ])
}

#[test]
fn every_recording_matches_its_golden_file() {
    let recs = recordings();
    // Seven from issue 11, six fail-safe scenarios from issue 24.
    assert_eq!(recs.len(), 13, "{recs:?}");
    for mcap in recs {
        let golden = mcap.with_extension("golden");
        let o = check(&mcap, &golden);
        assert!(
            o.status.success(),
            "{}: {}",
            mcap.display(),
            String::from_utf8_lossy(&o.stderr)
        );
        assert!(String::from_utf8_lossy(&o.stderr).contains("records match"));
    }
}

#[test]
fn a_perturbed_output_fails_with_a_readable_report() {
    let mcap = library().join("headon.mcap");
    let text = std::fs::read_to_string(mcap.with_extension("golden")).unwrap();
    // Perturb the first traffic record: its target's range by 50 m and its alert level by one.
    let mut lines: Vec<String> = text.lines().map(str::to_owned).collect();
    let i = lines
        .iter()
        .position(|l| l.contains(r#""kind":"traffic""#) && l.contains("horizontal_distance_m"))
        .unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&lines[i]).unwrap();
    let t = &mut v["targets"][0];
    let range = t["horizontal_distance_m"].as_f64().unwrap();
    t["horizontal_distance_m"] = serde_json::json!(range + 50.0);
    // Golden format 3: alert levels are words (none, preventive, corrective, warning).
    let level = t["alert_level"].as_str().unwrap().to_string();
    let perturbed_level = if level == "warning" {
        "corrective"
    } else {
        "warning"
    };
    t["alert_level"] = serde_json::json!(perturbed_level);
    lines[i] = serde_json::to_string(&v).unwrap();
    let path = common::tmp("golden_replay", "headon-perturbed.golden");
    std::fs::write(&path, lines.join("\n") + "\n").unwrap();
    let o = check(&mcap, &path);
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("2 field(s) differ in 1 record(s)"), "{err}");
    // Golden line numbers count the header as line 1.
    assert!(
        err.contains(&format!("line {} traffic at ", i + 1)),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "targets[0].horizontal_distance_m: golden {}, now {range} (-50",
            range + 50.0
        )),
        "{err}"
    );
    assert!(
        err.contains(&format!(
            "targets[0].alert_level: golden \"{perturbed_level}\", now \"{level}\""
        )),
        "{err}"
    );
}

#[test]
fn bless_reproduces_the_committed_golden_file() {
    let mcap = library().join("bahrs-fault.mcap");
    let path = common::tmp("golden_replay", "bahrs-fault.golden");
    let o = vigil(&[
        "replay",
        mcap.to_str().unwrap(),
        "--check",
        path.to_str().unwrap(),
        "--bless",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&path).unwrap(),
        std::fs::read(mcap.with_extension("golden")).unwrap()
    );
    // A golden file that is not one is refused with a reason.
    std::fs::write(&path, "{\"kind\":\"ownship\"}\n").unwrap();
    let o = check(&mcap, &path);
    assert!(!o.status.success());
    assert!(String::from_utf8_lossy(&o.stderr).contains("not a golden file"));
}
