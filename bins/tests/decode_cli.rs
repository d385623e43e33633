//! `vigil decode` end to end: the committed sample files, the JSON Lines output, the counters on
//! stderr and the exit codes.
//!
//! The samples under `tests/data/` are built here from the drivers' encoders, so the fixture and the
//! wire format cannot drift apart: `VIGIL_BLESS=1 cargo test -p vigil --test decode_cli` rewrites
//! them after a deliberate change.

use std::path::PathBuf;
use std::process::{Command, Output};

use serde_json::Value;
use vigil_drivers::bahrs::{
    self, DataTime, Health, InertialHealth, Message, NavigationHealth, SyncPulseTime,
};
use vigil_drivers::watson;

fn data(rel: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data")
        .join(rel)
}

/// One second of a BAHRS in a gentle right turn: versions, 100 Hz inertial + 0x05, 50 Hz
/// navigation + 0x04, a sync pulse, accuracy; then a frame with a bit error and some line noise.
fn bahrs_sample() -> Vec<u8> {
    let mut out = Vec::new();
    let push = |m: Message, out: &mut Vec<u8>| m.encode(out);
    push(
        Message::SoftwareVersion(bahrs::SoftwareVersion {
            project_code: *b"BHR",
            major: 2,
            minor: 0,
        }),
        &mut out,
    );
    push(
        Message::HardwareVersion(bahrs::HardwareVersion {
            mcu_id: 0x0413,
            unique_id: [0x0031_0042, 0x3235_5111, 0x2020_4E45],
        }),
        &mut out,
    );
    let safe = Health::Safe;
    let t0_us = 12_000_000u64;
    for k in 0..100u64 {
        let t = t0_us + k * 10_000;
        let seq = k as u8;
        push(
            Message::Inertial(bahrs::Inertial::from_si(
                seq,
                [0.05, 0.0, -9.95],
                [0.0, 0.0, 0.052],
                InertialHealth::new([safe; 3], [safe; 3]),
            )),
            &mut out,
        );
        push(
            Message::InertialTime(DataTime {
                seq,
                data_seq: seq,
                mcu_time_us: t,
            }),
            &mut out,
        );
        if k % 2 == 0 {
            let nseq = (k / 2) as u8;
            push(
                Message::Navigation(bahrs::Navigation::from_si(
                    nseq,
                    350.0 + 0.02 * k as f64,
                    -0.5,
                    10f64.to_radians(),
                    2f64.to_radians(),
                    (90.0 + 0.03 * k as f64).to_radians(),
                    NavigationHealth::new(safe, safe, safe, safe, safe),
                )),
                &mut out,
            );
            push(
                Message::NavigationTime(DataTime {
                    seq: nseq,
                    data_seq: nseq,
                    mcu_time_us: t,
                }),
                &mut out,
            );
        }
        if k == 50 {
            push(
                Message::SyncPulseTime(SyncPulseTime {
                    seq: 12,
                    mcu_time_us: t - 137,
                }),
                &mut out,
            );
        }
    }
    push(
        Message::Accuracy(bahrs::Accuracy {
            seq: 12,
            std_north_raw: 52,
            std_east_raw: 52,
            std_heading_raw: 0,
            mcu_time_us: t0_us + 1_000_000,
        }),
        &mut out,
    );
    // A frame hit by a bit error, then noise: both show in the counters only.
    let mut bad = Message::SyncPulseTime(SyncPulseTime {
        seq: 13,
        mcu_time_us: 13_000_000,
    })
    .to_frame();
    bad[8] ^= 0x10;
    out.extend_from_slice(&bad);
    out.extend_from_slice(b"\x00\xFFnoise NE");
    out
}

fn watson_sample() -> Vec<u8> {
    let mut out = Vec::new();
    for k in 0..24 {
        let line = watson::Line {
            kind: if k % 12 == 11 {
                watson::Kind::Reference
            } else {
                watson::Kind::Inertial
            },
            over_range: false,
            bank_deg: 10.0,
            elevation_deg: 2.0,
            heading_deg: 90.0 + 0.3 * f64::from(k),
            accel_g: [0.01, 0.17, 1.02],
            rate_dps: [0.0, 0.1, 3.0],
            velocity_kmh: 120.0,
        };
        line.encode(&mut out);
    }
    // A line garbled on the link.
    out.extend_from_slice(b"I +010.0 +02.0 09#.1  +0.01\r");
    out
}

fn check_fixture(rel: &str, bytes: &[u8]) {
    let path = data(rel);
    if std::env::var_os("VIGIL_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, bytes).unwrap();
    }
    let committed = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    assert!(
        committed == bytes,
        "{rel} is stale: rerun with VIGIL_BLESS=1 after a deliberate change"
    );
}

#[test]
fn sample_files_match_their_generators() {
    check_fixture("bahrs/sample.bin", &bahrs_sample());
    check_fixture("watson/sample.txt", &watson_sample());
}

fn vigil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(args)
        .output()
        .expect("run vigil")
}

fn lines(out: &Output) -> Vec<Value> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).expect("each stdout line is JSON"))
        .collect()
}

fn summary(out: &Output) -> Value {
    let err = String::from_utf8_lossy(&out.stderr);
    serde_json::from_str(err.lines().last().expect("a summary line")).expect("summary is JSON")
}

#[test]
fn decode_bahrs_sample() {
    let path = data("bahrs/sample.bin");
    let out = vigil(&["decode", "--device", "bahrs", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let msgs = lines(&out);
    // 2 versions + 100 x (0x01 + 0x05) + 50 x (0x02 + 0x04) + 1 sync pulse + 1 accuracy.
    assert_eq!(msgs.len(), 2 + 200 + 100 + 1 + 1);
    assert_eq!(msgs[0]["type"], "software_version");
    assert_eq!(msgs[0]["project_code"], "BHR");
    let nav = msgs.iter().find(|m| m["type"] == "navigation").unwrap();
    assert_eq!(nav["type_id"], 2);
    assert_eq!(nav["seq"], 0);
    assert_eq!(nav["health"]["roll"], "safe");
    // 10 deg = 0.174533 rad, rounded to the 9.587526e-5 rad LSB: 1820 LSB = 0.1744930 rad.
    let roll = nav["roll_rad"].as_f64().unwrap();
    assert!((roll - 1820.0 * 9.587526e-5).abs() < 1e-12, "{roll}");
    let acc = msgs.iter().find(|m| m["type"] == "accuracy").unwrap();
    assert!(
        acc["std_heading_rad"].is_null(),
        "0 means invalid, printed as null"
    );
    let s = summary(&out);
    assert_eq!(s["kind"], "summary");
    assert_eq!(s["frames_decoded"], 304);
    assert!(s["checksum_failures"].as_u64().unwrap() >= 1);
    assert_eq!(s["bytes_consumed"], std::fs::metadata(&path).unwrap().len());
}

#[test]
fn decode_watson_sample_from_stdin() {
    let path = data("watson/sample.txt");
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["decode", "--device", "watson", "-"])
        .stdin(std::fs::File::open(&path).unwrap())
        .output()
        .unwrap();
    assert!(out.status.success());
    let msgs = lines(&out);
    assert_eq!(msgs.len(), 24);
    assert_eq!(msgs[0]["kind"], "inertial");
    assert_eq!(msgs[0]["bank_deg"], 10.0);
    assert_eq!(msgs[11]["kind"], "reference");
    assert_eq!(summary(&out)["malformed"], 1);
}

/// Issue 26: a southern or western receiver gives a negative `--ref`; clap once took `-2.5,40`
/// for an unknown option. The Riddle's even airborne frame decodes with it, and an impossible
/// latitude reaches vigil's own range check, so the value got through clap.
#[test]
fn negative_reference_positions_are_accepted() {
    let decode = |r: &str| {
        let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
            .args(["decode", "--device", "ttmrf", "--format", "hex", "--ref", r])
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        use std::io::Write as _;
        child
            .stdin
            .take()
            .unwrap()
            .write_all(b"*8D40621D58C382D690C8AC2863A7;\n")
            .unwrap();
        child.wait_with_output().unwrap()
    };
    let out = decode("-2.5,40");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let msgs = lines(&out);
    assert_eq!(msgs.len(), 1);
    assert_eq!(msgs[0]["icao"], "40621D");
    assert_eq!(summary(&out)["frames_decoded"], 1);
    let out = decode("-33.9,-151.2");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let out = decode("-91,0");
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("latitude must be within +-90"), "{err}");
}

#[test]
fn errors_are_clear_and_non_zero() {
    let out = vigil(&["decode", "--device", "bahrs", "/nonexistent/file.bin"]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("cannot open input /nonexistent/file.bin"),
        "{err}"
    );
    let out = vigil(&["decode", "--device", "toaster", "-"]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("invalid value 'toaster'"));
    let out = vigil(&["decode", "--device", "bahrs", "--format", "csv", "-"]);
    assert!(!out.status.success());
}

#[test]
fn ttmrf_auto_recognises_binary_streams() {
    // The real Beast capture and its AVR rewrite: 8 928 Mode S frames less the 6 whose address
    // was not yet known (as dump1090), plus 5 026 Mode A/C frames (adsb/README.md).
    for rel in ["adsb/ulss7_beast.bin", "adsb/ulss7_avr.txt"] {
        let Some(path) = vigil_drivers::testkit::shared_data(rel) else {
            return;
        };
        let out = vigil(&[
            "decode",
            "--device",
            "ttmrf",
            "--format",
            "auto",
            path.to_str().unwrap(),
        ]);
        assert!(out.status.success());
        assert_eq!(lines(&out).len(), 8_922 + 5_026, "{rel}");
        assert_eq!(summary(&out)["extra"]["mode_s_frames"], 8_928);
    }
    let Some(path) = vigil_drivers::testkit::shared_data("asterix/cat21_re.ast") else {
        return;
    };
    let out = vigil(&[
        "decode",
        "--device",
        "ttmrf",
        "--format",
        "auto",
        path.to_str().unwrap(),
    ]);
    assert_eq!(lines(&out).len(), 2);
    assert_eq!(summary(&out)["extra"]["format"], "asterix");
}
