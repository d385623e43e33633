//! Issue 18 acceptance: time alignment that stays honest on every adapter and every reading of
//! the documents, judged against the simulator's truth (method: `sim_truth.rs`).
//!
//! Every case is a built-in scenario or `nominal` with one option of issue 18 / issue 25 set
//! (below). After a 10 s warm-up, per device, time source and message class:
//! - no sample is passed off as aligned (any status) with an error beyond 5 sigma AND beyond the
//!   goal of its source;
//! - at least 95 % of the errors lie inside 2 stated sigma;
//! - p99 |error|: PPS-disciplined (BAHRS) <= 50 us, VN-200 native GPS <= 1 us, TT-Multi-RF JSON
//!   `ts` <= 1 ms, TS24h <= 10 us, host-timed (and the BAHRS host-clock fallback) <= the port's
//!   link jitter + 2 ms. The link jitter is the scenario's latency half-width (0.5 ms), plus the
//!   latency timer on an FTDI port (its tail waits 0 ..= the timer).
//!
//! The figures are printed as a table (`cargo test -p vigil-tests --test time_acceptance --
//! --nocapture`); the README's time section quotes them.

mod truth_run;

use std::collections::BTreeMap;

use truth_run::*;
use vigil_fusion::time::TimeSource;
use vigil_fusion::time::aligner::{Aligner, Device};
use vigil_sim::scenario::{Fault, Scenario, builtin};
use vigil_tests::sim_drive::full_rates_csv_hexd;

/// One acceptance case: a scenario, how long, and what the aligner is told about the ports.
struct Case {
    name: &'static str,
    scenario: Scenario,
    seconds: i64,
    /// Per-port settings handed to the aligner (what `[[ports]]` / the recording says).
    setup: fn(&mut Aligner),
    /// Extra link jitter of host-timed samples per device (an FTDI latency timer), ns.
    extra_jitter_ns: fn(Device) -> i64,
    /// The devices whose `clock_disagreement` bit the case must raise; no other may be raised
    /// (issue 18 point 4: a false disagreement replaces a right time by a worse one).
    disagreeing: &'static [Device],
    /// Whether the TT-Multi-RF's line must be seen busy ([`Aligner::ttmrf_line_busy`]); in a
    /// case that does not fill it, it must never be (a busy line widens host-timed sigmas).
    busy_tt_line: bool,
}

fn none(_: &mut Aligner) {}
fn no_jitter(_: Device) -> i64 {
    0
}

fn nominal_with(f: impl FnOnce(&mut Scenario)) -> Scenario {
    let mut s = builtin("nominal").unwrap();
    f(&mut s);
    s
}

/// Goal of a time source and message class, ns (`None`: BAHRS service messages, 5-sigma only).
fn goal_ns(source: TimeSource, class: &str, jitter_ns: i64) -> Option<i64> {
    Some(match source {
        TimeSource::HostClock if class == "bahrs" => return None,
        TimeSource::NativeGps => US,
        TimeSource::PpsDisciplined => 50 * US,
        TimeSource::UtcTimeOfDay if class == "json" => MS,
        TimeSource::UtcTimeOfDay => 10 * US,
        TimeSource::HostClock | TimeSource::DeviceClock | TimeSource::DeviceClockViaHost => {
            jitter_ns + 2 * MS
        }
    })
}

/// A row of the table: one device, source and class in one case.
struct Row {
    n: usize,
    p50: i64,
    p99: i64,
    within_2_sigma: f64,
    median_sigma_ns: f64,
    goal_ns: Option<i64>,
    bad: usize,
}

fn rows(r: &Run, c: &Case) -> BTreeMap<(Device, String, &'static str), Row> {
    let mut groups: BTreeMap<(Device, String, &'static str), Vec<&Joined>> = BTreeMap::new();
    for j in &r.joined {
        let (Some(_), Some(source)) = (j.err_ns, j.source) else {
            continue;
        };
        if j.at_s < 10.0 {
            continue;
        }
        groups
            .entry((j.device, format!("{source:?}"), j.class))
            .or_default()
            .push(j);
    }
    groups
        .into_iter()
        .map(|(key, js)| {
            let source = js[0].source.unwrap();
            let jitter = 500 * US + (c.extra_jitter_ns)(key.0);
            let goal = goal_ns(source, key.2, jitter);
            let mut abs: Vec<i64> = js.iter().map(|j| j.err_ns.unwrap().abs()).collect();
            abs.sort_unstable();
            let mut sig: Vec<f64> = js.iter().map(|j| j.sigma_ns).collect();
            sig.sort_by(f64::total_cmp);
            let within = js
                .iter()
                .filter(|j| j.err_ns.unwrap().abs() as f64 <= 2.0 * j.sigma_ns)
                .count();
            let bad = js
                .iter()
                .filter(|j| {
                    let e = j.err_ns.unwrap().abs();
                    e as f64 > 5.0 * j.sigma_ns && goal.is_none_or(|g| e > g)
                })
                .count();
            let row = Row {
                n: js.len(),
                p50: percentile(&abs, 0.5),
                p99: percentile(&abs, 0.99),
                within_2_sigma: within as f64 / js.len() as f64,
                median_sigma_ns: sig[sig.len() / 2],
                goal_ns: goal,
                bad,
            };
            (key, row)
        })
        .collect()
}

fn fmt_ns(ns: f64) -> String {
    if ns >= 1e6 {
        format!("{:.2} ms", ns / 1e6)
    } else if ns >= 1e3 {
        format!("{:.1} us", ns / 1e3)
    } else {
        format!("{ns:.0} ns")
    }
}

/// Runs a case, prints its rows, and returns the failures (empty: the case holds).
fn judge(c: &Case, seed: u64) -> (Run, Vec<String>) {
    let r = run_with(&c.scenario, c.seconds, seed, c.setup);
    let mut failures = Vec::new();
    if r.inputs != r.outputs {
        failures.push(format!(
            "{}: inputs {:?} != outputs {:?}",
            c.name, r.inputs, r.outputs
        ));
    }
    let seen: Vec<Device> = r.disagreements_first_s.keys().copied().collect();
    println!(
        "{}: clock_disagreement raised {:?} (first at s), at the end {:?}; disagreeing times: \
         VN-200 {}, TT-Multi-RF {}; TT-Multi-RF messages on a busy line {}",
        c.name,
        r.disagreements_first_s,
        r.disagreements_at_end,
        r.vn200_disagreeing,
        r.tt_disagreeing,
        r.tt_busy_messages
    );
    if (r.tt_busy_messages > 0) != c.busy_tt_line {
        failures.push(format!(
            "{}: {} TT-Multi-RF messages on a busy line, expected {}",
            c.name,
            r.tt_busy_messages,
            if c.busy_tt_line { "some" } else { "none" }
        ));
    }
    if seen != c.disagreeing {
        failures.push(format!(
            "{}: clock_disagreement raised for {seen:?}, expected {:?}",
            c.name, c.disagreeing
        ));
    }
    for ((device, source, class), row) in rows(&r, c) {
        println!(
            "| {} | {device:?} | {source} | {class} | {} | {} | {} | {:.1} % | {} | {} |",
            c.name,
            row.n,
            fmt_ns(row.p50 as f64),
            fmt_ns(row.p99 as f64),
            row.within_2_sigma * 100.0,
            fmt_ns(row.median_sigma_ns),
            row.goal_ns
                .map_or("5 sigma only".into(), |g| fmt_ns(g as f64)),
        );
        let what = format!("{} {device:?} {source} {class}", c.name);
        if row.bad > 0 {
            failures.push(format!("{what}: {} beyond 5 sigma and the goal", row.bad));
        }
        // Small groups (a few service messages) are judged by the 5-sigma rule only.
        if row.n >= 20 && row.within_2_sigma < 0.95 {
            failures.push(format!("{what}: {:.3} within 2 sigma", row.within_2_sigma));
        }
        if let Some(g) = row.goal_ns
            && row.n >= 20
            && row.p99 > g
        {
            failures.push(format!("{what}: p99 {} > goal {}", row.p99, g));
        }
    }
    (r, failures)
}

fn check_all(cases: &[Case]) -> Vec<(&'static str, Run)> {
    println!(
        "| case | device | source | class | n | p50 | p99 | within 2 sigma | median sigma | goal |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    let mut failures = Vec::new();
    let mut runs = Vec::new();
    for c in cases {
        let (r, f) = judge(c, 21);
        failures.extend(f);
        runs.push((c.name, r));
    }
    assert!(failures.is_empty(), "{failures:#?}");
    runs
}

/// The PPS and pulse-report cases: the BAHRS clock.
#[test]
fn pps_and_pulse_report_readings() {
    let sync = |f: fn(&mut vigil_sim::scenario::BahrsSync)| {
        nominal_with(|s| f(&mut s.devices.bahrs.as_mut().unwrap().sync))
    };
    let cases = [
        Case {
            name: "nominal",
            scenario: builtin("nominal").unwrap(),
            seconds: 40,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "0x06 sent 0.3 s late",
            scenario: sync(|y| y.report_delay_ms = Some(300.0)),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "0x06 sent 0.7 s late",
            scenario: sync(|y| y.report_delay_ms = Some(700.0)),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "0x06 repeated every 100 ms",
            scenario: sync(|y| y.report_repeat_ms = 100.0),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "software pulse capture 0-30 us",
            scenario: sync(|y| y.capture_latency_us = 30.0),
            seconds: 40,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "wrong PPS edge (+100 ms)",
            scenario: sync(|y| y.edge_offset_ms = 100.0),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[Device::Bahrs],
            busy_tt_line: false,
        },
        Case {
            name: "PPS absent (sync not wired)",
            scenario: nominal_with(|s| s.devices.vn200.as_mut().unwrap().pps = false),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "BAHRS MCU reset at 20 s",
            scenario: nominal_with(|s| {
                s.faults.push(Fault::DeviceReset {
                    device: "bahrs".into(),
                    at_s: 20.0,
                })
            }),
            seconds: 35,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
    ];
    let runs = check_all(&cases);
    let by = |n: &str| &runs.iter().find(|(name, _)| *name == n).unwrap().1;
    // The wrong edge: every pulse disagrees with the host clock; no PPS time is given at all
    // after the warm-up, and the disagreement is raised.
    let wrong = by("wrong PPS edge (+100 ms)");
    assert!(wrong.disagreement_seen && wrong.bahrs.pulses_disagreeing >= 25);
    assert!(
        wrong
            .joined
            .iter()
            .all(|j| j.device != Device::Bahrs || j.source != Some(TimeSource::PpsDisciplined))
    );
    // Late and repeated reports: locked on the PPS, one pulse per second, never a reset.
    for n in [
        "0x06 sent 0.3 s late",
        "0x06 sent 0.7 s late",
        "0x06 repeated every 100 ms",
    ] {
        let r = by(n);
        println!("{n}: {:?}", r.bahrs);
        assert!(
            r.bahrs.pulses_used >= 25 && r.bahrs.pulses_disagreeing == 0,
            "{n}"
        );
        // On the PPS clock (locked, or coasting between late reports: a 0.7 s late report
        // leaves the last known pulse up to 1.7 s behind a sample).
        let sel: Vec<&Joined> = r
            .joined
            .iter()
            .filter(|j| j.device == Device::Bahrs && j.at_s >= 10.0 && j.at_s < 29.0)
            .collect();
        let pps = sel
            .iter()
            .filter(|j| j.source == Some(TimeSource::PpsDisciplined))
            .count();
        assert!(
            pps as f64 > 0.99 * sel.len() as f64,
            "{n}: {pps} of {}",
            sel.len()
        );
    }
    assert!(
        by("0x06 repeated every 100 ms")
            .bahrs
            .pulse_reports_repeated
            >= 200
    );
}

fn ftdi_16(a: &mut Aligner) {
    a.set_latency_timer(Device::Watson, 16 * MS as u64);
    a.set_latency_timer(Device::Ttmrf, 16 * MS as u64);
}
fn ftdi_16_jitter(d: Device) -> i64 {
    if matches!(d, Device::Watson | Device::Ttmrf | Device::Bahrs) {
        16 * MS
    } else {
        0
    }
}
fn ftdi_1(a: &mut Aligner) {
    a.set_latency_timer(Device::Watson, MS as u64);
    a.set_latency_timer(Device::Ttmrf, MS as u64);
}
fn ftdi_1_jitter(d: Device) -> i64 {
    if matches!(d, Device::Watson | Device::Ttmrf | Device::Bahrs) {
        MS
    } else {
        0
    }
}
fn tt_115200(a: &mut Aligner) {
    a.set_baud(Device::Ttmrf, 115_200);
}
fn bursts_jitter(_: Device) -> i64 {
    // Latency 3 +- 3 ms instead of 1 +- 0.5 ms: 2.5 ms more half-width.
    2_500 * US
}

/// The TT-Multi-RF on CSV and HEXd: everything of it host-timed.
fn tt_host_timed(s: &mut Scenario) {
    let tt = s.devices.ttmrf.as_mut().unwrap();
    tt.protocol = "csv".into();
    tt.raw = "hexd".into();
}

/// Adapters, baud rates, `ts` readings, GNSS outages and the date line: the host clock side.
#[test]
fn links_outages_and_time_stamp_readings() {
    let ftdi = |ms: f64| {
        nominal_with(|s| {
            tt_host_timed(s);
            for d in ["watson", "ttmrf", "bahrs"] {
                s.host.ftdi_latency_timer_ms.insert(d.into(), ms);
            }
        })
    };
    let cases = [
        Case {
            name: "FTDI 16 ms (Watson, TT CSV, BAHRS)",
            scenario: ftdi(16.0),
            seconds: 30,
            setup: ftdi_16,
            extra_jitter_ns: ftdi_16_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "FTDI 1 ms (Watson, TT CSV, BAHRS)",
            scenario: ftdi(1.0),
            seconds: 30,
            setup: ftdi_1,
            extra_jitter_ns: ftdi_1_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "TT-Multi-RF CSV at 115200",
            // CSV alone: with NMEA and HEXd too the 115 200 baud port queues lines behind each
            // other and shares read chunks, which the aligner does not model (see the README).
            scenario: nominal_with(|s| {
                let tt = s.devices.ttmrf.as_mut().unwrap();
                tt.protocol = "csv".into();
                tt.gnss = false;
                tt.baud = 115_200;
            }),
            seconds: 30,
            setup: tt_115200,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "JSON ts rounded",
            scenario: nominal_with(|s| s.devices.ttmrf.as_mut().unwrap().ts_rounded = true),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "GNSS outage 15-60 s (PPS stops)",
            scenario: nominal_with(|s| {
                s.faults.push(Fault::GnssOutage {
                    from_s: 15.0,
                    to_s: Some(60.0),
                    device: None,
                })
            }),
            seconds: 70,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "VN-200 GNSS loss 15-60 s (PPS stops)",
            scenario: nominal_with(|s| {
                s.faults.push(Fault::GnssOutage {
                    from_s: 15.0,
                    to_s: Some(60.0),
                    device: Some("vn200".into()),
                })
            }),
            seconds: 70,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "UTC midnight",
            scenario: nominal_with(|s| s.start_utc = "2026-06-01T23:59:45Z".into()),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
    ];
    let runs = check_all(&cases);
    // Through the outages the BAHRS PPS clock coasts for 30 s (its crystal, checked above), then
    // the BAHRS is placed by its host-clock fallback (no pulses), never left out.
    for (name, r) in &runs {
        if name.contains("15-60") {
            let sel: Vec<&Joined> = r
                .joined
                .iter()
                .filter(|j| j.device == Device::Bahrs && j.at_s > 46.0 && j.at_s < 60.0)
                .collect();
            let fallback = sel
                .iter()
                .filter(|j| j.source == Some(TimeSource::DeviceClockViaHost))
                .count();
            println!("{name}: BAHRS fallback {fallback} of {}", sel.len());
            assert!(fallback as f64 >= 0.99 * sel.len() as f64, "{name}");
        }
    }
}

/// A VN-200 silent for 5 minutes (its serial link lost; its PPS still reaches the BAHRS): the
/// host clock is kept by the TT-Multi-RF's GNSS time, so the JSON ADS-B targets stay aligned
/// (in the traffic picture) throughout, and so do the host-timed Watson and the BAHRS.
#[test]
fn vn200_silent_for_five_minutes_keeps_the_traffic_aligned() {
    let case = Case {
        name: "VN-200 silent 15-315 s",
        scenario: nominal_with(|s| {
            s.faults.push(Fault::LinkLoss {
                device: "vn200".into(),
                from_s: 15.0,
                to_s: Some(315.0),
            })
        }),
        seconds: 325,
        setup: none,
        extra_jitter_ns: no_jitter,
        disagreeing: &[],
        busy_tt_line: false,
    };
    let runs = check_all(std::slice::from_ref(&case));
    let r = &runs[0].1;
    for (device, class) in [(Device::Ttmrf, "json"), (Device::Watson, "watson")] {
        let sel: Vec<&Joined> = r
            .joined
            .iter()
            .filter(|j| j.device == device && j.class == class && j.at_s > 15.0 && j.at_s < 315.0)
            .collect();
        let aligned = sel.iter().filter(|j| j.err_ns.is_some()).count();
        println!(
            "VN-200 silent: {device:?} {class}: {aligned} of {} aligned",
            sel.len()
        );
        assert!(
            !sel.is_empty() && aligned == sel.len(),
            "{device:?} {class}"
        );
    }
}

/// Host stamps in bursts (every read 3 +- 3 ms late instead of 1 +- 0.5 ms). The VN-200's
/// messages span several reads, so their delay is the largest of a few; a Watson line's last
/// read is one read's delay. The host clock learns a single read's delay from the first reads of
/// the VN-200's messages and maps each host-timed message by how its own reads split it (issue
/// 18 point 1; `host_timed::hold_back_ns`). With the VN-200's delay for every port, the Watson
/// came out about 55 % inside 2 sigma.
#[test]
fn host_stamp_bursts() {
    let case = Case {
        name: "host stamp bursts (latency 3 +- 3 ms)",
        scenario: nominal_with(|s| {
            s.host.latency_ms = 3.0;
            s.host.latency_jitter_ms = 3.0;
        }),
        seconds: 30,
        setup: none,
        extra_jitter_ns: bursts_jitter,
        disagreeing: &[],
        busy_tt_line: false,
    };
    check_all(std::slice::from_ref(&case));
}

/// A device's own time a second off from 20 s on (issue 18 point 4).
fn time_offset(device: &str) -> Scenario {
    nominal_with(|s| {
        // HEX frames too: TS24h is checked like JSON `ts`.
        s.devices.ttmrf.as_mut().unwrap().raw = "hex".into();
        s.faults.push(Fault::DeviceTimeOffset {
            device: device.into(),
            from_s: 20.0,
            to_s: None,
            offset_ms: 1_000.0,
        })
    })
}

/// Issue 18 point 4: the VN-200's GPS time and the TT-Multi-RF's `ts` / TS24h each a second off
/// from 20 s on (a leap-second error; a `ts` a second off). Each is cross-checked against the
/// host clock's relation held before (the VN-200 is the host clock's own reference, so the
/// check cannot use a relation that includes its new times): after the fault no sample is
/// passed off with a wrong time (the table's rules), the device's `clock_disagreement` bit is
/// raised at the fault and stays raised, nothing else is raised, and the device's samples keep
/// coming aligned through another clock (the host clock) with that clock's sigma.
#[test]
fn a_device_time_a_second_off_disagrees_with_the_host_clock() {
    let cases = [
        Case {
            name: "VN-200 GPS time +1 s from 20 s",
            scenario: time_offset("vn200"),
            seconds: 45,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[Device::Vn200],
            busy_tt_line: false,
        },
        Case {
            name: "TT-Multi-RF ts / TS24h +1 s from 20 s",
            scenario: time_offset("ttmrf"),
            seconds: 45,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[Device::Ttmrf],
            busy_tt_line: false,
        },
    ];
    let runs = check_all(&cases);
    for ((name, r), device) in runs.iter().zip([Device::Vn200, Device::Ttmrf]) {
        // Raised at the fault (within 0.2 s of truth time), held to the end.
        let first = r.disagreements_first_s[&device];
        assert!((20.0..20.2).contains(&first), "{name}: first at {first} s");
        assert_eq!(r.disagreements_at_end, vec![device], "{name}");
        // After the fault: no sample of the device on its own time; all of them aligned through
        // the host clock.
        let after: Vec<&Joined> = r
            .joined
            .iter()
            .filter(|j| j.device == device && j.at_s >= 20.2)
            .collect();
        let own = after
            .iter()
            .filter(|j| {
                matches!(
                    j.source,
                    Some(TimeSource::NativeGps | TimeSource::UtcTimeOfDay)
                )
            })
            .count();
        let host = after
            .iter()
            .filter(|j| j.source == Some(TimeSource::HostClock))
            .count();
        println!(
            "{name}: after the fault {} samples: {own} on their own time, {host} host-timed",
            after.len()
        );
        assert!(
            !after.is_empty() && own == 0 && host == after.len(),
            "{name}"
        );
    }
    // Before the fault the VN-200 was on its GPS time.
    let vn = &runs[0].1;
    assert!(vn.joined.iter().any(|j| j.device == Device::Vn200
        && j.at_s < 20.0
        && j.source == Some(TimeSource::NativeGps)));
}

/// Issue 18 point 4, with no second host-clock source: the TT-Multi-RF on CSV (no GNSS time of
/// its own) and the VN-200's GPS time a second off from 20 s to the end (200 s). The relation
/// held before keeps refusing the VN-200's time past the host clock's 120 s coast limit, so the
/// VN-200 never re-seeds the host clock with its wrong time: its samples are host-timed while
/// the host clock coasts, then not aligned (reason `clock_disagreement`), never wrong.
#[test]
fn a_vn200_time_a_second_off_without_a_second_source_is_never_passed_off() {
    let case = Case {
        name: "VN-200 GPS time +1 s from 20 s, TT on CSV, 200 s",
        scenario: nominal_with(|s| {
            tt_host_timed(s);
            s.faults.push(Fault::DeviceTimeOffset {
                device: "vn200".into(),
                from_s: 20.0,
                to_s: None,
                offset_ms: 1_000.0,
            })
        }),
        seconds: 200,
        setup: none,
        extra_jitter_ns: no_jitter,
        disagreeing: &[Device::Vn200],
        busy_tt_line: false,
    };
    let runs = check_all(std::slice::from_ref(&case));
    let r = &runs[0].1;
    assert_eq!(r.disagreements_at_end, vec![Device::Vn200]);
    let vn = |from: f64, to: f64| -> Vec<&Joined> {
        r.joined
            .iter()
            .filter(|j| j.device == Device::Vn200 && j.at_s >= from && j.at_s < to)
            .collect()
    };
    // While the host clock coasts (up to 120 s after its last reference): host-timed.
    let coasting = vn(20.2, 135.0);
    assert!(
        coasting
            .iter()
            .all(|j| j.source == Some(TimeSource::HostClock))
    );
    // Past it: not aligned (no clock left to place them by), and still refused.
    let late = vn(145.0, 200.0);
    let aligned = late.iter().filter(|j| j.err_ns.is_some()).count();
    println!(
        "VN-200 +1 s, TT on CSV: {} host-timed 20-135 s; 145-200 s: {aligned} of {} aligned",
        coasting.len(),
        late.len()
    );
    assert!(!late.is_empty() && aligned == 0);
}

/// Issue 18 point 1, named adapters: the Watson and the TT-Multi-RF (CSV and HEXd: host-timed)
/// behind a native UART or a USB CDC bridge, the VN-200 (the host clock's reference) on the
/// default link. The aligner is told nothing: it maps their reads with the single-read delay it
/// learned on the VN-200's port.
#[test]
fn native_uart_and_usb_cdc_ports() {
    use vigil_sim::scenario::Adapter;
    let on = |a: Adapter| {
        nominal_with(move |s| {
            tt_host_timed(s);
            for d in ["watson", "ttmrf"] {
                s.host.adapters.insert(d.into(), a);
            }
        })
    };
    let cases = [
        Case {
            name: "native UART (Watson, TT CSV)",
            scenario: on(Adapter::NativeUart),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
        Case {
            name: "USB CDC (Watson, TT CSV)",
            scenario: on(Adapter::UsbCdc),
            seconds: 30,
            setup: none,
            extra_jitter_ns: no_jitter,
            disagreeing: &[],
            busy_tt_line: false,
        },
    ];
    check_all(&cases);
}

/// The TT-Multi-RF sending more than its line carries: `vigil measure`'s full-rates scenario
/// (300 intruders, JSON and raw HEX at 921 600 baud, about 101 kB/s of output for 92 kB/s of
/// line). The simulated module queues its output up to its transmit buffer (about 40 ms) and
/// discards what does not fit, as a UART device does. Its `ts` / TS24h stay right (they name
/// when each report was made, not when it left); the host sees every message 33-45 ms after
/// it. No clock may be called disagreeing for it, and no time may be passed off.
#[test]
fn a_saturated_tt_line_queues_without_a_false_disagreement() {
    let case = Case {
        name: "TT-Multi-RF line saturated (full-rates)",
        scenario: Scenario::from_toml(include_str!("../data/full-rates.toml")).unwrap(),
        seconds: 30,
        setup: none,
        extra_jitter_ns: no_jitter,
        disagreeing: &[],
        busy_tt_line: true,
    };
    let runs = check_all(std::slice::from_ref(&case));
    // The line is seen busy: its TT-Multi-RF messages are counted so, from the first second.
    let r = &runs[0].1;
    assert!(r.tt_busy_messages > 0, "the line was not seen busy");
}

/// The TT-Multi-RF's samples of a run.
fn tt_samples(r: &Run) -> Vec<&Joined> {
    r.joined
        .iter()
        .filter(|j| j.device == Device::Ttmrf)
        .collect()
}

/// A busy line's host-timed samples are late by an unknown queue of up to the limit (0.5 s):
/// their goal is that limit.
fn queue_limit_jitter(d: Device) -> i64 {
    if d == Device::Ttmrf { 500 * MS } else { 0 }
}

fn tt_9600(a: &mut Aligner) {
    a.set_baud(Device::Ttmrf, 9600);
}

/// As above at 9600 baud (960 bytes/s for about 101 kB/s of output): the module's 4 KiB buffer
/// now holds 4.3 s, far beyond the aligner's 0.5 s queue limit, so a `ts` comes seconds before
/// its arrival. The host cannot tell such a queue from a clock a second off: the TT-Multi-RF's
/// clock is called disagreeing, and what neither its own time nor the host clock can place is
/// not aligned (`line_full`); no time may be passed off with a sigma that does not cover it
/// (before this was handled, the frames whose TS24h was called disagreeing were host-timed
/// with the 0.5 s queue limit in their sigma: 306 beyond 5 sigma, seconds wrong).
#[test]
fn a_tt_line_queued_beyond_the_limit_is_not_aligned_rather_than_wrong() {
    let mut scenario = Scenario::from_toml(include_str!("../data/full-rates.toml")).unwrap();
    scenario.devices.ttmrf.as_mut().unwrap().baud = 9600;
    let case = Case {
        name: "TT-Multi-RF line saturated, JSON and HEX at 9600",
        scenario,
        seconds: 30,
        setup: tt_9600,
        extra_jitter_ns: queue_limit_jitter,
        disagreeing: &[Device::Ttmrf],
        busy_tt_line: true,
    };
    let runs = check_all(std::slice::from_ref(&case));
    let tt = tt_samples(&runs[0].1);
    let placed = tt.iter().filter(|j| j.source.is_some()).count();
    println!("TT-Multi-RF samples: {} in all, {placed} placed", tt.len());
    // Most are not aligned (the queue is seconds long from the first second on) ...
    assert!(placed * 2 < tt.len(), "{placed} of {}", tt.len());
    // ... and none placed by the host clock once the line's own times show the long queue:
    // every host-timed one comes from the first second, before the queue passed the limit.
    let late_host_timed = tt
        .iter()
        .filter(|j| j.source == Some(TimeSource::HostClock) && j.at_s > 2.0)
        .count();
    assert_eq!(late_host_timed, 0);
}

/// As above with CSV and HEXd (no time of their own: every TT-Multi-RF sample host-timed; at
/// 921 600 baud they fit the line), at 115 200 and at 9600 baud. The module's 4 KiB buffer
/// holds 0.36 s of output at 115 200 and 4.3 s at 9600: lines arrive that late against what the
/// host clock says, and the host, which knows no buffer size, sees only how long the line has
/// been full. So a sample is placed, with the 0.5 s limit in its sigma, only while the line has
/// been full for 0.5 s or less, and is not aligned after, at either rate; none may be passed off
/// with a sigma that does not cover it. Before this was handled, the 9600-baud case placed
/// samples seconds late with that sigma.
#[test]
fn a_saturated_tt_line_without_times_of_its_own_is_placed_only_while_its_wait_is_bounded() {
    for (baud, setup) in [(9600, tt_9600 as fn(&mut Aligner)), (115_200, tt_115200)] {
        let scenario = full_rates_csv_hexd(baud);
        let case = Case {
            name: if baud == 9600 {
                "TT-Multi-RF line saturated, CSV and HEXd at 9600"
            } else {
                "TT-Multi-RF line saturated, CSV and HEXd at 115200"
            },
            scenario,
            seconds: 30,
            setup,
            extra_jitter_ns: queue_limit_jitter,
            disagreeing: &[],
            busy_tt_line: true,
        };
        let runs = check_all(std::slice::from_ref(&case));
        let tt = tt_samples(&runs[0].1);
        let placed: Vec<&&Joined> = tt.iter().filter(|j| j.source.is_some()).collect();
        println!(
            "{baud} baud: {} TT-Multi-RF samples, {} placed",
            tt.len(),
            placed.len()
        );
        // The line is full from the start and stays so: only samples that arrived in its first
        // 0.5 s of being full are placed (they wait for the host clock, and are placed with
        // the wait their line allowed at their arrival), nothing after. Every placed one is
        // judged by `check_all` above: within its sigma.
        assert!(placed.iter().all(|j| j.at_s < 1.0), "{baud}");
        assert!(!placed.is_empty(), "{baud}");
        assert!(tt.len() > 500, "{baud}: {}", tt.len());
    }
}

/// The simulated module's transmit buffer (its truth), bytes.
const SIM_BUFFER_BYTES: u32 = vigil_sim::link::TX_BUFFER_BYTES as u32;

fn tt_115200_buffer_stated(a: &mut Aligner) {
    a.set_baud(Device::Ttmrf, 115_200);
    a.set_ttmrf_output_buffer(Some(SIM_BUFFER_BYTES));
}

fn tt_115200_buffer_understated(a: &mut Aligner) {
    a.set_baud(Device::Ttmrf, 115_200);
    a.set_ttmrf_output_buffer(Some(SIM_BUFFER_BYTES / 4));
}

/// The line time of `bytes` at 115 200 baud, 8N1, ns.
fn at_115200_ns(bytes: u32) -> i64 {
    i64::from(bytes) * 10 * 1_000_000_000 / 115_200
}

/// A busy line's host-timed TT-Multi-RF samples wait up to the stated buffer's line time:
/// 4096 bytes at 115 200 baud, 355.6 ms.
fn stated_buffer_jitter(d: Device) -> i64 {
    if d == Device::Ttmrf {
        at_115200_ns(SIM_BUFFER_BYTES)
    } else {
        0
    }
}

fn understated_buffer_jitter(d: Device) -> i64 {
    if d == Device::Ttmrf {
        at_115200_ns(SIM_BUFFER_BYTES / 4)
    } else {
        0
    }
}

/// The case above at 115 200 baud with the module's transmit buffer stated as it is (the
/// simulator's 4096 bytes: 355.6 ms of line, within the 0.5 s limit): a message waited at most
/// that, so the line's CSV and HEXd samples stay placed however long the line is full, with
/// that wait in their sigma, and are judged against the simulator's truth by `check_all`
/// (within 5 sigma or the goal, 95 % within 2 sigma). Without the statement the same line is
/// placed only in its first second (the test above). Stating a quarter of the buffer is
/// caught by the same judge: the times it passes off are about 12 sigma off, which is why
/// vigil assumes no buffer by default.
#[test]
fn a_saturated_tt_line_with_its_buffer_stated_stays_placed_within_its_sigma() {
    let case = Case {
        name: "TT-Multi-RF line saturated, CSV and HEXd at 115200, buffer stated",
        scenario: full_rates_csv_hexd(115_200),
        seconds: 30,
        setup: tt_115200_buffer_stated,
        extra_jitter_ns: stated_buffer_jitter,
        disagreeing: &[],
        busy_tt_line: true,
    };
    let runs = check_all(std::slice::from_ref(&case));
    let tt = tt_samples(&runs[0].1);
    let placed = tt.iter().filter(|j| j.source.is_some()).count();
    println!("{} TT-Multi-RF samples, {placed} placed", tt.len());
    assert!(tt.len() > 500, "{}", tt.len());
    // Every one, from the first to the last second (held ones wait for the host clock).
    assert_eq!(placed, tt.len());
    assert!(tt.iter().any(|j| j.at_s > 29.0));
    let understated = Case {
        name: "TT-Multi-RF line saturated, CSV and HEXd at 115200, a quarter of the buffer stated",
        scenario: full_rates_csv_hexd(115_200),
        seconds: 30,
        setup: tt_115200_buffer_understated,
        extra_jitter_ns: understated_buffer_jitter,
        disagreeing: &[],
        busy_tt_line: true,
    };
    let (_, failures) = judge(&understated, 21);
    println!("{failures:#?}");
    assert!(
        failures
            .iter()
            .any(|f| f.contains("Ttmrf HostClock") && f.contains("beyond 5 sigma")),
        "{failures:#?}"
    );
}

/// A list of targets sent at once: the line time of the nominal scenario's second at 115 200
/// baud (GGA, RMC and five CSV lines, about 700 bytes: 61 ms), the longest a list message
/// waits; its goal.
fn list_jitter(d: Device) -> i64 {
    if d == Device::Ttmrf { 61 * MS } else { 0 }
}

/// As [`list_jitter`] at 921 600 baud: 700 bytes are 7.6 ms.
fn list_jitter_921600(d: Device) -> i64 {
    if d == Device::Ttmrf { 7_600 * US } else { 0 }
}

/// The other reading of the manual's "module is sending list of aircraft every second": the
/// whole list at once, at the whole second after the NMEA, so each CSV line waits on the line
/// behind the ones before it (up to about 60 ms at 115 200 baud), far less than the 100 ms a
/// line needs to count as full. The aligner bounds each wait by the output that can have been
/// sent back to back before it (`LineLoad::queued_for_ns`); before it did, the list's later
/// lines were placed up to 55 ms late with about 1 ms of sigma. Judged against the
/// simulator's truth (the instant the list was made); the spread reading is the nominal case.
#[test]
fn a_list_of_targets_sent_at_once_is_placed_within_its_sigma() {
    let list = |baud: u32, raw: &str| {
        nominal_with(|s| {
            let tt = s.devices.ttmrf.as_mut().unwrap();
            tt.protocol = "csv".into();
            tt.raw = raw.into();
            tt.baud = baud;
            tt.list_at_once = true;
        })
    };
    let case = |name: &'static str,
                baud: u32,
                raw: &str,
                setup: fn(&mut Aligner),
                extra_jitter_ns: fn(Device) -> i64| Case {
        name,
        scenario: list(baud, raw),
        seconds: 30,
        setup,
        extra_jitter_ns,
        disagreeing: &[],
        busy_tt_line: false,
    };
    check_all(&[
        case(
            "TT-Multi-RF list at once, CSV and NMEA at 115200",
            115_200,
            "off",
            tt_115200,
            list_jitter,
        ),
        case(
            "TT-Multi-RF list at once, CSV, NMEA and HEXd at 115200",
            115_200,
            "hexd",
            tt_115200,
            list_jitter,
        ),
        case(
            "TT-Multi-RF list at once, CSV and NMEA at 921600",
            921_600,
            "off",
            none,
            list_jitter_921600,
        ),
    ]);
}
