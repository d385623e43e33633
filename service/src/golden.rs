//! Golden files of the fused outputs, and `vigil replay FILE.mcap --check GOLDEN [--bless]`
//! (issue 11).
//!
//! A golden file is JSON Lines: a header line (`"kind": "golden"`, the format version and the
//! recording's file name), then one line per fused output in the order the pipeline emits them,
//! each a projection of the output onto the fields a reviewer and the DAA/integrity consumers care
//! about, with numbers rounded to a fixed resolution so the file is stable and its diffs readable:
//! - `attitude_check`: every 10th record (5 Hz at the BAHRS' 50 Hz) and every record whose verdict
//!   (fault, isolated unit, magnetic disturbance, integrity risk, per-pair verdicts) differs from
//!   the previous record's: the voted attitude, the pairwise differences and joint test ratios;
//! - `ownship`: every step: source, position, altitudes, velocity, heading;
//! - `traffic`: every step: per target (priority order) address, range, bearings, vertical
//!   separation, range rate, CPA, modified tau, loss-of-well-clear interval (`lowc_interval_s`,
//!   [start, end] in s from now: the interval, not the payload's `time_to_lowc_s`, which is its
//!   start alone), raw and filtered alert levels, plausibility flags;
//! - `alert` (format 2, issue 20): every transition of the integrity monitor (`vigil run`'s
//!   monitor, with the flight's configuration: see `replay_config`), exactly, with its reason;
//!   then `alerts_active`: the active set after the evaluation. A regression of the monitor (or
//!   a changed threshold) shows in the diff like any other field.
//!
//! Format 3 (issue 26): the lines have vigil's JSON names (`crate::json_names`): alert levels and
//! severities as words, addresses as six hex digits, `t_utc` (and `raised_utc`) beside each GPS
//! time, `lowc_interval_s` for the interval that format 2 called `lowc_s`. The values are the
//! same; only their representation changed.
//!
//! `--check` compares field by field, record by record: strings (words, addresses, UTC times)
//! exactly, numbers with a tolerance per field chosen by the unit in its name (below); the replay is deterministic, so on one machine the outputs are
//! identical and the tolerances only absorb floating-point differences between platforms. A
//! difference beyond tolerance is reported as record, field, golden value, new value and
//! difference. `--bless` rewrites the golden file from the replay.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::{Context, Result, bail};
use serde_json::{Map, Value, json};
use vigil_fusion::attitude::record::{AttitudeRecord, PairRecord};
use vigil_fusion::ownship::OwnshipSolution;
use vigil_fusion::pipeline::{Fused, TrafficPicture};

use crate::config::Config;
use crate::replay::fused::{FusedEvent, active_line, alert_line};

/// Format version of the golden files (2: alert transitions and active sets added; 3: vigil's
/// JSON names, see the module documentation).
pub const FORMAT: u64 = 3;

/// Every n-th attitude record is kept (plus every change of verdict).
const ATTITUDE_EVERY: u64 = 10;

/// Most differences listed in a report.
const MAX_REPORTED: usize = 25;

/// Rounds to `decimals` decimal places (NaN and infinities become null).
fn r(x: f64, decimals: i32) -> Value {
    if !x.is_finite() {
        return Value::Null;
    }
    let k = 10f64.powi(decimals);
    json!((x * k).round() / k)
}

fn ro(x: Option<f64>, decimals: i32) -> Value {
    x.map_or(Value::Null, |x| r(x, decimals))
}

/// The verdict string of a pair record: roll, pitch, heading, joint as P(ass)/F(ail)/-.
fn verdicts(p: &PairRecord) -> String {
    use vigil_fusion::attitude::isolation::PairVerdict;
    [
        p.roll.verdict,
        p.pitch.verdict,
        p.heading.verdict,
        p.joint.verdict,
    ]
    .iter()
    .map(|v| match v {
        PairVerdict::Pass => 'P',
        PairVerdict::Fail => 'F',
        PairVerdict::NotCompared => '-',
    })
    .collect()
}

/// `v` with vigil's JSON names (`crate::json_names`).
fn named(mut v: Value) -> Value {
    crate::json_names::normalise(&mut v);
    v
}

/// Projects fused outputs onto golden lines.
#[derive(Debug, Default)]
pub struct Projector {
    attitude_count: u64,
    last_key: Option<String>,
}

impl Projector {
    /// The golden lines of a fused replay's event (alerts: each transition, then the active set).
    pub fn project_event(&mut self, e: FusedEvent<'_>) -> Vec<Value> {
        // Alert lines come with the JSON names already (`alert_line`, `active_line`).
        match e {
            FusedEvent::Fused(o) => self.project(o).into_iter().collect(),
            FusedEvent::Alerts(alerts, active) => {
                let mut v: Vec<Value> = alerts.iter().map(alert_line).collect();
                let t = alerts.last().map_or(0, |a| a.header.gps_time_ns);
                v.push(active_line(t, active));
                v
            }
        }
    }

    /// The golden line of `o`, or `None` for an attitude record that is decimated away.
    pub fn project(&mut self, o: &Fused) -> Option<Value> {
        match o {
            Fused::Attitude(a) => self.attitude(a).map(named),
            Fused::Ownship(o) => Some(named(ownship(o))),
            Fused::Traffic(p) => Some(named(traffic(p))),
            // The golden files hold the check records; prompt outputs (a `vigil run` option,
            // off in replays) repeat their verdicts.
            Fused::Prompt(_) => None,
        }
    }

    fn attitude(&mut self, a: &AttitudeRecord) -> Option<Value> {
        let p = &a.pairs;
        let key = format!(
            "{}{:?}{}{}{}/{}/{}",
            a.fault,
            a.isolated,
            a.magnetic_disturbance,
            a.bahrs_integrity_risk,
            verdicts(&p.bahrs_vn200),
            verdicts(&p.bahrs_watson),
            verdicts(&p.vn200_watson)
        );
        let n = self.attitude_count;
        self.attitude_count += 1;
        let changed = self.last_key.as_deref() != Some(key.as_str());
        self.last_key = Some(key);
        if !changed && !n.is_multiple_of(ATTITUDE_EVERY) {
            return None;
        }
        let diffs = |pr: &PairRecord| {
            Value::Array(
                [&pr.roll, &pr.pitch, &pr.heading]
                    .iter()
                    .map(|x| ro(x.comparison.map(|c| c.diff_deg), 4))
                    .collect(),
            )
        };
        let voted = |v: &Option<vigil_fusion::attitude::record::VotedAxis>| {
            ro(v.as_ref().map(|v| v.value_deg), 4)
        };
        Some(json!({
            "kind": "attitude_check",
            "t_gps_ns": a.t_gps_ns,
            "fault": a.fault,
            "isolated": a.isolated,
            "magnetic_disturbance": a.magnetic_disturbance,
            "bahrs_integrity_risk": a.bahrs_integrity_risk,
            "verdicts_bv_bw_vw": format!("{}/{}/{}", verdicts(&p.bahrs_vn200),
                verdicts(&p.bahrs_watson), verdicts(&p.vn200_watson)),
            "voted_deg": [voted(&a.voted.roll), voted(&a.voted.pitch), voted(&a.voted.heading)],
            "diff_bahrs_vn200_deg": diffs(&p.bahrs_vn200),
            "diff_bahrs_watson_deg": diffs(&p.bahrs_watson),
            "diff_vn200_watson_deg": diffs(&p.vn200_watson),
            "joint_ratio": [ro(p.bahrs_vn200.joint.ratio, 4), ro(p.bahrs_watson.joint.ratio, 4),
                ro(p.vn200_watson.joint.ratio, 4)],
        }))
    }
}

fn ownship(o: &OwnshipSolution) -> Value {
    let s = &o.ownship;
    json!({
        "kind": "ownship",
        "t_gps_ns": s.t_gps_ns,
        "source": s.source,
        "lat_deg": r(s.lat_deg, 7),
        "lon_deg": r(s.lon_deg, 7),
        "alt_pressure_m": ro(s.alt_pressure_m, 2),
        "alt_geometric_m": ro(s.alt_geometric_m, 2),
        "track_deg": ro(s.track_deg, 3),
        "ground_speed_mps": ro(s.ground_speed_mps, 3),
        "vertical_rate_mps": ro(s.vertical_rate_mps, 3),
        "heading_deg": ro(s.heading_deg, 3),
        "heading_source": o.heading_source,
        "position_sigma_m": ro(s.position_sigma_m, 2),
    })
}

fn traffic(p: &TrafficPicture) -> Value {
    let targets: Vec<Value> = p
        .targets
        .iter()
        .map(|t| {
            let g = t.geometry.as_ref();
            let mut m = Map::new();
            m.insert("address".into(), json!(t.key.address));
            m.insert("altitude_kind".into(), json!(t.altitude_kind));
            m.insert("bearing_true_deg".into(), r(t.bearing_true_deg, 3));
            m.insert("bearing_relative_deg".into(), ro(t.bearing_relative_deg, 3));
            m.insert(
                "horizontal_distance_m".into(),
                ro(g.map(|g| g.horizontal_distance_m), 1),
            );
            m.insert(
                "vertical_separation_m".into(),
                ro(g.and_then(|g| g.vertical_separation_m), 1),
            );
            m.insert(
                "range_rate_mps".into(),
                ro(g.and_then(|g| g.range_rate_mps), 2),
            );
            m.insert("tcpa_s".into(), ro(g.and_then(|g| g.tcpa_s), 2));
            m.insert("hmd_m".into(), ro(g.and_then(|g| g.hmd_m), 1));
            m.insert("tau_mod_s".into(), ro(g.and_then(|g| g.tau_mod_s), 2));
            m.insert(
                "lowc_interval_s".into(),
                g.and_then(|g| g.loss_of_well_clear_interval_s)
                    .map_or(Value::Null, |iv| json!([r(iv.0, 2), r(iv.1, 2)])),
            );
            m.insert("raw_alert_level".into(), json!(t.raw_alert_level));
            m.insert("alert_level".into(), json!(t.alert_level));
            m.insert("suspect".into(), json!(t.flags.any()));
            // Issue 24: the fail-safe rules that applied, by name (empty when none).
            m.insert("fail_safe".into(), json!(fail_safe_names(&t.fail_safe)));
            Value::Object(m)
        })
        .collect();
    json!({
        "kind": "traffic",
        "t_gps_ns": p.t_gps_ns,
        "targets": targets,
    })
}

/// The names of the fail-safe rules that applied to a target, in a fixed order.
fn fail_safe_names(f: &vigil_fusion::traffic::policy::FailSafeFlags) -> Vec<&'static str> {
    [
        (f.ownship_velocity_unknown, "ownship_velocity_unknown"),
        (
            f.ownship_vertical_rate_unknown,
            "ownship_vertical_rate_unknown",
        ),
        (f.altitude_unknown, "altitude_unknown"),
        (f.velocity_unknown, "velocity_unknown"),
        (f.vertical_rate_unknown, "vertical_rate_unknown"),
        (f.altitude_reference_mixed, "altitude_reference_mixed"),
        (f.stale, "stale"),
        (f.time_from_receipt, "time_from_receipt"),
    ]
    .iter()
    .filter(|(on, _)| *on)
    .map(|(_, n)| *n)
    .collect()
}

/// The tolerance of a field, by the unit in its name: the rounding of the projection plus
/// margin for floating-point differences between platforms. `None`: must be equal.
fn tolerance(field: &str) -> Option<f64> {
    let f = field.trim_end_matches(|c: char| c == ']' || c.is_ascii_digit() || c == '[');
    if f == "t_gps_ns" {
        return None;
    }
    [
        ("lat_deg", 2e-7),
        ("lon_deg", 2e-7),
        ("_deg", 2e-4),
        ("_mps", 2e-3),
        ("_m", 0.2),
        ("_s", 0.02),
        ("ratio", 2e-4),
    ]
    .iter()
    .find(|(suffix, _)| f.ends_with(suffix))
    .map(|(_, t)| *t)
}

/// One difference found by [`compare`].
#[derive(Debug, Clone, PartialEq)]
pub struct Difference {
    /// 1-based line of the golden file (header = line 1).
    pub line: usize,
    /// Kind of the record.
    pub kind: String,
    /// GPS time of the record, ns.
    pub t_gps_ns: Option<i64>,
    /// Field path, e.g. `targets[0].alert_level`.
    pub field: String,
    /// Value in the golden file.
    pub golden: Value,
    /// Value now.
    pub now: Value,
}

fn walk(path: &str, g: &Value, n: &Value, out: &mut Vec<(String, Value, Value)>) {
    match (g, n) {
        (Value::Object(a), Value::Object(b)) => {
            for (k, va) in a {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                walk(&p, va, b.get(k).unwrap_or(&Value::Null), out);
            }
            for (k, vb) in b {
                if !a.contains_key(k) {
                    out.push((format!("{path}.{k}"), Value::Null, vb.clone()));
                }
            }
        }
        (Value::Array(a), Value::Array(b)) if a.len() == b.len() => {
            for (i, (va, vb)) in a.iter().zip(b).enumerate() {
                walk(&format!("{path}[{i}]"), va, vb, out);
            }
        }
        (Value::Number(a), Value::Number(b)) => {
            let (x, y) = (
                a.as_f64().unwrap_or(f64::NAN),
                b.as_f64().unwrap_or(f64::NAN),
            );
            let ok = match tolerance(path) {
                Some(tol) => (x - y).abs() <= tol,
                None => a == b,
            };
            if !ok {
                out.push((path.to_string(), g.clone(), n.clone()));
            }
        }
        _ if g == n => {}
        _ => out.push((path.to_string(), g.clone(), n.clone())),
    }
}

/// Compares the records of a golden file (without its header) with the new ones.
pub fn compare(golden: &[Value], now: &[Value]) -> Vec<Difference> {
    let mut out = Vec::new();
    for (i, (g, n)) in golden.iter().zip(now).enumerate() {
        let mut fields = Vec::new();
        walk("", g, n, &mut fields);
        for (field, gv, nv) in fields {
            out.push(Difference {
                line: i + 2,
                kind: g["kind"].as_str().unwrap_or("?").to_string(),
                t_gps_ns: g["t_gps_ns"].as_i64(),
                field,
                golden: gv,
                now: nv,
            });
        }
    }
    out
}

/// A readable report of a comparison (empty when nothing differs).
pub fn report(golden: &[Value], now: &[Value], diffs: &[Difference]) -> String {
    let mut s = String::new();
    let t0 = golden
        .first()
        .or(now.first())
        .and_then(|v| v["t_gps_ns"].as_i64())
        .unwrap_or(0);
    if golden.len() != now.len() {
        let _ = writeln!(
            s,
            "record count: golden {}, now {} ({} {})",
            golden.len(),
            now.len(),
            golden.len().abs_diff(now.len()),
            if now.len() > golden.len() {
                "more at the end"
            } else {
                "missing at the end"
            }
        );
    }
    if !diffs.is_empty() {
        let records: std::collections::BTreeSet<usize> = diffs.iter().map(|d| d.line).collect();
        let _ = writeln!(
            s,
            "{} field(s) differ in {} record(s); first {}:",
            diffs.len(),
            records.len(),
            diffs.len().min(MAX_REPORTED)
        );
    }
    for d in diffs.iter().take(MAX_REPORTED) {
        let t = d.t_gps_ns.map_or(String::new(), |t| {
            format!(" at {:.3} s", (t - t0) as f64 * 1e-9)
        });
        let delta = match (d.golden.as_f64(), d.now.as_f64()) {
            (Some(a), Some(b)) => format!(
                " ({:+}, tolerance {})",
                b - a,
                tolerance(&d.field).map_or("exact".to_string(), |t| t.to_string())
            ),
            _ => String::new(),
        };
        let _ = writeln!(
            s,
            "  line {} {}{}: {}: golden {}, now {}{}",
            d.line, d.kind, t, d.field, d.golden, d.now, delta
        );
    }
    s
}

/// The header line of a golden file.
fn header(recording: &Path) -> Value {
    json!({
        "kind": "golden",
        "format": FORMAT,
        "recording": recording.file_name().map(|n| n.to_string_lossy().into_owned()),
        "bless": "vigil replay RECORDING --check THIS_FILE --bless (see README: Golden replays)",
    })
}

/// Replays a recording with configuration `cfg` and projects its fused outputs and alerts onto
/// golden lines.
pub fn golden_lines(input: impl std::io::Read, cfg: &Config) -> Result<Vec<Value>> {
    let mut proj = Projector::default();
    let mut lines = Vec::new();
    let summary = crate::replay::fused::replay_fused_with(input, cfg, |e| {
        lines.extend(proj.project_event(e));
        Ok(())
    })?;
    if summary.mcap_messages == 0 {
        bail!("not a readable mcap recording");
    }
    Ok(lines)
}

/// Writes a golden file.
pub fn write_golden(path: &Path, recording: &Path, lines: &[Value]) -> Result<()> {
    let mut s = serde_json::to_string(&header(recording))?;
    s.push('\n');
    for l in lines {
        s.push_str(&serde_json::to_string(l)?);
        s.push('\n');
    }
    std::fs::write(path, s).with_context(|| format!("cannot write {}", path.display()))
}

/// Reads a golden file: its records without the header.
pub fn read_golden(path: &Path) -> Result<Vec<Value>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read golden file {}", path.display()))?;
    let mut lines = text.lines().filter(|l| !l.trim().is_empty());
    let head: Value = serde_json::from_str(lines.next().unwrap_or("{}"))
        .with_context(|| format!("{}: line 1 is not JSON", path.display()))?;
    if head["kind"] != "golden" || head["format"] != FORMAT {
        bail!(
            "{}: not a golden file of format {FORMAT} (header: {head})",
            path.display()
        );
    }
    lines
        .enumerate()
        .map(|(i, l)| {
            serde_json::from_str(l)
                .with_context(|| format!("{}: line {} is not JSON", path.display(), i + 2))
        })
        .collect()
}

/// Runs `--check GOLDEN [--bless]` on the recording `input`, replayed with `cfg`.
pub fn check(input: &Path, cfg: &Config, golden: &Path, bless: bool) -> Result<()> {
    let file =
        std::fs::File::open(input).with_context(|| format!("cannot read {}", input.display()))?;
    let now = golden_lines(std::io::BufReader::with_capacity(1 << 16, file), cfg)?;
    if bless {
        write_golden(golden, input, &now)?;
        eprintln!("{}: blessed, {} records", golden.display(), now.len());
        return Ok(());
    }
    let old = read_golden(golden)?;
    let diffs = compare(&old, &now);
    if diffs.is_empty() && old.len() == now.len() {
        eprintln!("{}: ok, {} records match", golden.display(), now.len());
        return Ok(());
    }
    bail!(
        "golden check failed against {}:\n{}",
        golden.display(),
        report(&old, &now, &diffs)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tolerances_follow_the_unit_in_the_name() {
        assert_eq!(tolerance("t_gps_ns"), None);
        assert_eq!(tolerance("voted_deg[2]"), Some(2e-4));
        assert_eq!(tolerance("lat_deg"), Some(2e-7));
        assert_eq!(tolerance("targets[3].horizontal_distance_m"), Some(0.2));
        assert_eq!(tolerance("targets[0].lowc_interval_s[1]"), Some(0.02));
        assert_eq!(tolerance("targets[0].alert_level"), None);
        assert_eq!(tolerance("joint_ratio[1]"), Some(2e-4));
    }

    #[test]
    fn a_change_beyond_tolerance_is_reported_with_both_values() {
        let g = vec![
            json!({"kind": "ownship", "t_gps_ns": 1_000_000_000i64, "lat_deg": 47.1234567,
                "heading_deg": 10.0, "source": "vn200_ins"}),
            json!({"kind": "traffic", "t_gps_ns": 2_000_000_000i64,
                "targets": [{"address": "4B1A01", "alert_level": 2, "tcpa_s": 30.0}]}),
        ];
        let mut n = g.clone();
        // Within tolerance: not reported.
        n[0]["heading_deg"] = json!(10.0001);
        assert!(compare(&g, &n).is_empty());
        n[0]["heading_deg"] = json!(10.5);
        n[1]["targets"][0]["alert_level"] = json!(3);
        n[0]["source"] = json!("tt_multi_rf_gnss");
        let d = compare(&g, &n);
        assert_eq!(d.len(), 3);
        let text = report(&g, &n, &d);
        assert!(text.contains("3 field(s) differ in 2 record(s)"), "{text}");
        assert!(
            text.contains("line 2 ownship at 0.000 s: heading_deg: golden 10.0, now 10.5 (+0.5, tolerance 0.0002)"),
            "{text}"
        );
        assert!(
            text.contains("line 3 traffic at 1.000 s: targets[0].alert_level: golden 2, now 3 (+1, tolerance exact)"),
            "{text}"
        );
        assert!(
            text.contains("source: golden \"vn200_ins\", now \"tt_multi_rf_gnss\""),
            "{text}"
        );
        // A missing record.
        let text = report(&g, &n[..1], &compare(&g, &n[..1]));
        assert!(
            text.contains("record count: golden 2, now 1 (1 missing at the end)"),
            "{text}"
        );
    }

    /// Issue 20: the golden replay of the head-on recording holds the traffic alert's raise and
    /// its clear, at the times the scenario's truth and the documented filter give, and a changed
    /// monitor threshold changes the golden diff.
    #[test]
    fn regression_20_golden_alerts_follow_the_monitor_configuration() {
        let mcap = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../tests/data/replay/headon.mcap");
        let read = || std::io::BufReader::new(std::fs::File::open(&mcap).unwrap());
        let base = Config::default();
        let lines = golden_lines(read(), &base).unwrap();
        let traffic_alerts: Vec<&Value> = lines
            .iter()
            .filter(|l| l["kind"] == "alert" && l["rule"] == "traffic_alert")
            .collect();
        let states: Vec<&str> = traffic_alerts
            .iter()
            .map(|l| l["state"].as_str().unwrap())
            .collect();
        assert_eq!(states, ["raised", "cleared"]);
        // Truth from headon.toml: 3000 m apart at the start (2026-06-01T10:00:00Z, GPS second
        // 1464343218), closing at 40 + 60 m/s, co-altitude. Well clear is violated from the
        // start (tau_mod < 35 s while r < 3882 m) and until the intruder, past CPA at 30 s, is
        // beyond DTHR (4000 ft = 1219.2 m) at 42.19 s. The shown level then falls after the
        // M-of-N level has dropped (2 of 4 steps at 1 Hz: up to 3 steps) and 5 s of hysteresis
        // (fusion/src/traffic/alert_filter.rs); allow 1.5 s for the step grid and report age.
        let start_ns = 1_464_343_218_000_000_000_i64;
        let t_s = |l: &Value| (l["t_gps_ns"].as_i64().unwrap() - start_ns) as f64 * 1e-9;
        let exit_s = 30.0 + 1219.2 / 100.0;
        let (raise_s, clear_s) = (t_s(traffic_alerts[0]), t_s(traffic_alerts[1]));
        assert!(raise_s < 5.0, "raised at {raise_s} s");
        assert!(
            (exit_s + 5.0..exit_s + 3.0 + 5.0 + 1.5).contains(&clear_s),
            "cleared at {clear_s} s, truth leaves DTHR at {exit_s} s"
        );
        // Each transition is followed by the active set; the raise puts the alert in it.
        let i = lines
            .iter()
            .position(|l| {
                l["kind"] == "alert" && l["state"] == "raised" && l["rule"] == "traffic_alert"
            })
            .unwrap();
        let set = lines[i..]
            .iter()
            .find(|l| l["kind"] == "alerts_active")
            .unwrap();
        let id = &lines[i]["alert_id"];
        assert!(
            set["active"]
                .as_array()
                .unwrap()
                .iter()
                .any(|a| &a["alert_id"] == id)
        );
        // A longer raise delay for traffic alerts: the raises come later, the diff says so, and
        // only alert records differ.
        let mut slow = base.clone();
        slow.monitor.traffic_alert.raise_delay_s = 3.0;
        let changed = golden_lines(read(), &slow).unwrap();
        let diffs = compare(&lines, &changed);
        assert!(!diffs.is_empty() || lines.len() != changed.len());
        let n = lines.len().min(changed.len());
        let first = (0..n).find(|&k| lines[k] != changed[k]).unwrap();
        assert!(
            lines[first]["kind"].as_str().unwrap().starts_with("alert"),
            "{}",
            lines[first]
        );
        // Fusion outputs are the same.
        let fused = |v: &[Value]| -> Vec<Value> {
            v.iter()
                .filter(|l| !l["kind"].as_str().unwrap().starts_with("alert"))
                .cloned()
                .collect()
        };
        assert_eq!(fused(&lines), fused(&changed));
    }
}
