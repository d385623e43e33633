//! Time alignment against the simulator's truth (issue 7, "Done when").
//!
//! The simulator runs its own scenarios with all four device models (BAHRS, Watson, VN-200,
//! TT-Multi-RF); every port's received bytes are decoded with the drivers and aligned, and each
//! aligned sample is joined to its truth record by device and stream offset (`rx_offset`), so
//! messages lost or damaged by link faults do not shift the join (damaged ones have no truth).
//!
//! Decoding follows `vigil replay --emit aligned` (`bins/src/replay_aligned.rs`): BAHRS and Watson
//! with their decoders, the wire length by re-encoding; VN-200 with its decoder and the TT-Multi-RF
//! port with the text decoder (auto mode) and the HEX decoder side by side over the same bytes,
//! merged by offset, each message's length running to the next message's start (the last to the
//! end of the stream). Each message's [`Rx`] is the host time of the read holding its last byte
//! ([`ChunkClock`]) and its wire length. Differences, on purpose: each port's stream is decoded
//! whole (the decoders give the same messages for any split of the bytes: the drivers' split
//! invariant), and the messages of all ports are handed to the aligner in order of that receive
//! time, as a live host would see them (replay hands a message over when the next one of its
//! port is decoded).
//!
//! Runs:
//! - `nominal` (TT-Multi-RF JSON plus HEX with TS24h / TS1s): every budget after the first 10 s.
//! - `nominal` with the TT-Multi-RF on CSV and HEXd (no time stamps) and BAHRS time messages 3
//!   data messages late (a scenario variant built here): the host-timed budget for CSV, NMEA and
//!   HEXd lines, the BAHRS budget with late time messages.
//! - `link-errors`: every budget after 10 s; BAHRS reset at 40 s and PPS loss 50-53 s re-lock.
//! - `gnss-outage`: GNSS and PPS lost 60-120 s; VN-200, BAHRS and host clock re-lock.
//!
//! Budgets (issue 7): BAHRS p99 |error| <= 50 us; VN-200 <= 1 us; TT-Multi-RF JSON <= 1 ms; raw
//! frames with TS24h <= 10 us; host-timed samples p99 <= 2 ms beyond the link latency jitter
//! (+-0.5 ms in these scenarios: 2.5 ms); at least 95 % of errors within 2 sigma per device and
//! message class. "A wrong time claimed as locked" is, here, a sample with status locked whose
//! |error| exceeds 5 sigma or the budget of its time source (native GPS 1 us, PPS-disciplined
//! 50 us, JSON `ts` 1 ms, TS24h / TS1s 10 us, host clock 2.5 ms); none may occur in any run, the
//! first 10 s included. Decision: the BAHRS service messages (hardware / software version, sent
//! after a start or reset) carry no measurement and no device time; they are host-timed with
//! their unknown wait in the device's transmit queue stated in their sigma (2 ms, see
//! `fusion::time::bahrs`), so they are held to the 5-sigma test only (the simulator's reset
//! sends them behind a burst of frames: up to ~4 ms late).

use std::collections::BTreeMap;

use bytes::BytesMut;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::bahrs::Decoder as BahrsDecoder;
use vigil_drivers::ttmrf::raw::{HexDecoder, RawFrame};
use vigil_drivers::ttmrf::text::{TextDecoder, TextMessage, TextMode};
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};
use vigil_drivers::watson::Decoder as WatsonDecoder;
use vigil_fusion::time::aligner::{
    AlignedSample, Aligner, AlignerConfig, ClockReport, Device, Sample,
};
use vigil_fusion::time::host_timed::ChunkClock;
use vigil_fusion::time::{ClockStatus, Rx, TimeSource};
use vigil_sim::scenario::{Scenario, builtin};
use vigil_sim::{Chunk, MemorySink, Simulator, TruthRecord};

const S: i64 = 1_000_000_000;
const US: i64 = 1_000;
const MS: i64 = 1_000_000;

/// Host-timed budget: 2 ms beyond the scenarios' link latency jitter (+-0.5 ms).
const HOST_BUDGET_NS: i64 = 2_500_000;

/// One aligned sample with its truth.
#[derive(Debug, Clone, Copy)]
struct Joined {
    device: Device,
    /// Message class from the decoded sample (see [`class`]).
    class: &'static str,
    /// Truth message type.
    kind: &'static str,
    /// Seconds since the scenario start (truth).
    at_s: f64,
    err_ns: Option<i64>,
    sigma_ns: f64,
    status: Option<ClockStatus>,
    source: Option<TimeSource>,
}

struct Run {
    name: String,
    joined: Vec<Joined>,
    /// Inputs per device and outputs per device (every input must come out once).
    inputs: BTreeMap<Device, u64>,
    outputs: BTreeMap<Device, u64>,
    /// Clock reports at the last receive time.
    report: Vec<ClockReport>,
    /// The simulated host clock's drift against GPS, ppm (truth).
    host_drift_ppm: f64,
    /// Pulses whose GPS second came from the VN-200's PPS time, and from the host clock.
    pulses_vn200: u64,
    pulses_host: u64,
}

/// The class of a decoded sample: what kind of time it carries.
fn class(s: &Sample) -> &'static str {
    match s {
        Sample::Bahrs(_) => "bahrs",
        Sample::Watson(_) => "watson",
        Sample::Vn200(m) => match &**m {
            Vn200Message::Binary(_) => "binary",
            Vn200Message::Ascii(_) => "ascii",
        },
        Sample::TtText(m) => match &**m {
            TextMessage::Json(j) if j.ts_ms.is_some() => "json",
            TextMessage::Json(_) => "json_no_ts",
            TextMessage::Csv(_) => "csv",
            TextMessage::Nmea(_) => "nmea",
            TextMessage::At(_) => "at",
        },
        Sample::TtRaw(f) => {
            let meta = match &**f {
                RawFrame::ModeS(s) => s.meta,
                RawFrame::ModeAc(a) => a.meta,
                RawFrame::Uat(u) => u.meta,
            };
            match (meta.ts_utc_ns, meta.ts_pps_ns) {
                (Some(_), _) => "hex_ts24h",
                (None, Some(_)) => "hex_ts1s",
                (None, None) => "hex_no_ts",
            }
        }
        _ => "other",
    }
}

/// Budget of a time source (and class), ns: what "wrong" means for a locked sample; `None`:
/// only the 5-sigma test applies (see the module doc).
fn budget_ns(source: TimeSource, class: &str) -> Option<i64> {
    Some(match source {
        // BAHRS service messages (versions, after a start or reset).
        TimeSource::HostClock if class == "bahrs" => return None,
        TimeSource::NativeGps => US,
        TimeSource::PpsDisciplined => 50 * US,
        TimeSource::UtcTimeOfDay if class == "json" => MS,
        TimeSource::UtcTimeOfDay => 10 * US,
        TimeSource::HostClock | TimeSource::DeviceClock => HOST_BUDGET_NS,
    })
}

/// Decodes a whole port stream with one decoder: (start offset, message).
fn located<D: DeviceDecoder>(mut d: D, bytes: &[u8]) -> Vec<(u64, D::Message)> {
    let mut buf = BytesMut::from(bytes);
    let mut out = Vec::new();
    while let Some(m) = d.decode(&mut buf) {
        out.push((d.stats().last_frame_start, m));
    }
    while let Some(m) = d.decode_eof(&mut buf) {
        out.push((d.stats().last_frame_start, m));
    }
    out
}

/// Lengths from the next message's start (the last message runs to the end of the stream).
fn by_next_offset(mut v: Vec<(u64, Sample)>, end: u64) -> Vec<(u64, usize, Sample)> {
    v.sort_by_key(|e| e.0);
    let starts: Vec<u64> = v.iter().map(|e| e.0).collect();
    v.into_iter()
        .enumerate()
        .map(|(i, (o, s))| {
            let next = starts.get(i + 1).copied().unwrap_or(end);
            (o, next.saturating_sub(o) as usize, s)
        })
        .collect()
}

/// Every message of one port: (start offset, wire length, sample), in offset order.
fn decode_port(device: &str, bytes: &[u8]) -> Vec<(u64, usize, Sample)> {
    let end = bytes.len() as u64;
    match device {
        "bahrs" => located(BahrsDecoder::new(), bytes)
            .into_iter()
            .map(|(o, m)| (o, m.to_frame().len(), Sample::Bahrs(m)))
            .collect(),
        "watson" => located(WatsonDecoder::new(), bytes)
            .into_iter()
            .map(|(o, l)| (o, l.to_bytes().len(), Sample::Watson(l)))
            .collect(),
        "vn200" => by_next_offset(
            located(Vn200Decoder::new(), bytes)
                .into_iter()
                .map(|(o, m)| (o, Sample::Vn200(Box::new(m))))
                .collect(),
            end,
        ),
        "ttmrf" => {
            let text = located(TextDecoder::new(TextMode::Auto), bytes)
                .into_iter()
                .map(|(o, m)| (o, Sample::TtText(Box::new(m))));
            let raw = located(HexDecoder::new(), bytes)
                .into_iter()
                .map(|(o, f)| (o, Sample::TtRaw(Box::new(f))));
            by_next_offset(text.chain(raw).collect(), end)
        }
        other => panic!("no decoder for port {other}"),
    }
}

/// `nominal` with the TT-Multi-RF on CSV and HEXd (no time stamps in any of its lines), and the
/// BAHRS sending each time message (0x05 / 0x04) after the 3rd later data message of its stream
/// (late time messages).
fn nominal_variant() -> Scenario {
    let mut s = builtin("nominal").unwrap();
    let tt = s.devices.ttmrf.as_mut().unwrap();
    tt.protocol = "csv".into();
    tt.raw = "hexd".into();
    s.devices.bahrs.as_mut().unwrap().time_message_lag = 3;
    s
}

fn run(scenario: &Scenario, seconds: i64, seed: u64) -> Run {
    let mut sim = Simulator::new(scenario, seed).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * S, &mut sink).unwrap();
    let info = sink.info.clone().unwrap();
    let start = info.start_gps_ns;
    let truth: BTreeMap<(&str, u64), &TruthRecord> = sink
        .truth
        .iter()
        .filter(|r| !r.corrupted)
        .map(|r| ((r.device, r.rx_offset), r))
        .collect();

    // Per port: the stream and its chunk clock; then every message with its receive.
    struct Input {
        rx: Rx,
        sample: Sample,
        truth: Option<(i64, &'static str)>,
    }
    let mut inputs_all: Vec<Input> = Vec::new();
    for (p, port) in info.ports.iter().enumerate() {
        let chunks: Vec<&Chunk> = sink
            .chunks
            .iter()
            .filter(|c| usize::from(c.port) == p)
            .collect();
        let stream: Vec<u8> = chunks
            .iter()
            .flat_map(|c| c.bytes.iter().copied())
            .collect();
        // The chunk clock is fed as a live port would be: a read at a time, up to the read
        // holding the message's last byte (it keeps a bounded history).
        let mut clock = ChunkClock::default();
        let (mut next, mut fed) = (0, 0u64);
        for (offset, len, sample) in decode_port(port.device, &stream) {
            while fed < offset + len as u64
                && let Some(c) = chunks.get(next)
            {
                clock.push(c.t_host_ns as i64, c.bytes.len());
                fed += c.bytes.len() as u64;
                next += 1;
            }
            let rx = clock.rx(offset, len).unwrap();
            let truth = truth
                .get(&(port.device, offset))
                .map(|r| (r.t_gps_ns, r.kind));
            inputs_all.push(Input { rx, sample, truth });
        }
    }
    // In receive order (stable: a port's messages keep their stream order).
    inputs_all.sort_by_key(|i| i.rx.host_ns);

    let mut aligner = Aligner::new(AlignerConfig::default());
    let mut truth_of: BTreeMap<(Device, u64), (i64, &'static str, &'static str)> = BTreeMap::new();
    let mut inputs: BTreeMap<Device, u64> = BTreeMap::new();
    let mut outs: Vec<AlignedSample> = Vec::new();
    let mut last_host = 0;
    for i in inputs_all {
        let d = i.sample.device();
        let n = inputs.entry(d).or_default();
        if let Some((t, kind)) = i.truth {
            truth_of.insert((d, *n), (t, kind, class(&i.sample)));
        }
        *n += 1;
        last_host = i.rx.host_ns;
        outs.extend(aligner.handle(i.sample, i.rx));
    }
    let report = aligner.clock_report(last_host);
    let stats = *aligner.bahrs().stats();
    println!(
        "{}: BAHRS pulses named by the VN-200 PPS time {}, by the host clock {}, unidentified {}",
        scenario.name,
        stats.pulses_from_vn200_pps,
        stats.pulses_from_host_clock,
        stats.pulses_unidentified
    );
    outs.extend(aligner.flush());
    let mut outputs: BTreeMap<Device, u64> = BTreeMap::new();
    let joined = outs
        .iter()
        .filter_map(|o| {
            *outputs.entry(o.device).or_default() += 1;
            let (truth, kind, class) = *truth_of.get(&(o.device, o.index))?;
            let at_s = (truth - start) as f64 / 1e9;
            let (err_ns, sigma_ns, status, source) = match o.aligned.time {
                Ok(a) => (
                    Some(a.t_gps_ns - truth),
                    a.sigma_ns,
                    Some(a.status),
                    Some(a.source),
                ),
                Err(_) => (None, f64::INFINITY, None, None),
            };
            Some(Joined {
                device: o.device,
                class,
                kind,
                at_s,
                err_ns,
                sigma_ns,
                status,
                source,
            })
        })
        .collect();
    Run {
        name: scenario.name.clone(),
        joined,
        inputs,
        outputs,
        report,
        host_drift_ppm: info.host_clock.drift * 1e6,
        pulses_vn200: stats.pulses_from_vn200_pps,
        pulses_host: stats.pulses_from_host_clock,
    }
}

fn percentile(sorted: &[i64], p: f64) -> i64 {
    sorted[((sorted.len() - 1) as f64 * p).round() as usize]
}

/// Checks one device (and message classes, when given) after `from_s`: p99 |error| and the
/// 2-sigma share; prints the figures.
fn check(run: &Run, device: Device, classes: &[&str], from_s: f64, p99_max_ns: i64) {
    let what = if classes.is_empty() {
        "all".to_string()
    } else {
        classes.join("+")
    };
    check_sel(run, device, &what, p99_max_ns, |j| {
        j.at_s >= from_s && (classes.is_empty() || classes.contains(&j.class))
    })
}

/// As [`check`], for the samples of `device` that `keep` selects (labelled `what`).
fn check_sel(
    run: &Run,
    device: Device,
    what: &str,
    p99_max_ns: i64,
    keep: impl Fn(&Joined) -> bool,
) {
    let name = &run.name;
    let sel: Vec<&Joined> = run
        .joined
        .iter()
        .filter(|j| j.device == device && keep(j))
        .collect();
    let aligned: Vec<&&Joined> = sel.iter().filter(|j| j.err_ns.is_some()).collect();
    let mut abs: Vec<i64> = aligned.iter().map(|j| j.err_ns.unwrap().abs()).collect();
    abs.sort_unstable();
    assert!(!abs.is_empty(), "{name} {device:?} {what}: nothing aligned");
    let within = aligned
        .iter()
        .filter(|j| (j.err_ns.unwrap().abs() as f64) <= 2.0 * j.sigma_ns)
        .count() as f64
        / aligned.len() as f64;
    let (p50, p99, max) = (
        percentile(&abs, 0.5),
        percentile(&abs, 0.99),
        abs[abs.len() - 1],
    );
    let mut sigmas: Vec<f64> = aligned.iter().map(|j| j.sigma_ns).collect();
    sigmas.sort_by(f64::total_cmp);
    println!(
        "{name} {device:?} {what}: n={} aligned={} p50={p50} ns p99={p99} ns max={max} ns \
         within 2 sigma={:.1} % median sigma={:.0} ns",
        sel.len(),
        aligned.len(),
        within * 100.0,
        sigmas[sigmas.len() / 2]
    );
    assert!(
        p99 <= p99_max_ns,
        "{name} {device:?} {what}: p99 {p99} ns > {p99_max_ns} ns"
    );
    assert!(
        within >= 0.95,
        "{name} {device:?} {what}: {within:.3} within 2 sigma"
    );
}

/// No sample of the whole run is locked with a wrong time (see the module doc).
fn check_no_wrong_locked(run: &Run) {
    let mut locked = 0;
    for j in &run.joined {
        let (Some(e), Some(ClockStatus::Locked), Some(source)) = (j.err_ns, j.status, j.source)
        else {
            continue;
        };
        locked += 1;
        let e = e.abs();
        assert!(
            (e as f64) <= 5.0 * j.sigma_ns && budget_ns(source, j.class).is_none_or(|b| e <= b),
            "{} {:?} {} ({}) at {:.3} s: locked, {source:?}, error {e} ns, sigma {:.0} ns",
            run.name,
            j.device,
            j.class,
            j.kind,
            j.at_s,
            j.sigma_ns
        );
    }
    assert!(locked > 0);
}

/// Every input came out exactly once (aligned or marked).
fn check_nothing_dropped(run: &Run) {
    assert_eq!(run.inputs, run.outputs);
}

/// Share of a device's samples in [from, to) s that are aligned and locked.
fn locked_share(run: &Run, device: Device, from: f64, to: f64) -> f64 {
    let sel: Vec<&Joined> = run
        .joined
        .iter()
        .filter(|j| j.device == device && j.at_s >= from && j.at_s < to)
        .collect();
    sel.iter()
        .filter(|j| j.status == Some(ClockStatus::Locked))
        .count() as f64
        / sel.len().max(1) as f64
}

/// Seconds from `from_s` to the first locked sample of `device` after which at least 95 % of its
/// samples over the next 2 s are locked (a re-lock that holds), or `None`.
fn relock_after(run: &Run, device: Device, from_s: f64) -> Option<f64> {
    let mut sel: Vec<&Joined> = run
        .joined
        .iter()
        .filter(|j| j.device == device && j.at_s >= from_s)
        .collect();
    sel.sort_by(|a, b| a.at_s.total_cmp(&b.at_s));
    sel.iter()
        .find(|j| {
            j.status == Some(ClockStatus::Locked)
                && locked_share(run, device, j.at_s, j.at_s + 2.0) >= 0.95
        })
        .map(|j| j.at_s - from_s)
}

/// Checks and prints a re-lock within 5 s of `from_s`.
fn check_relock(run: &Run, device: Device, from_s: f64, what: &str) {
    let r = relock_after(run, device, from_s);
    println!(
        "{} {device:?}: re-locked {r:?} s after {what} ({from_s} s)",
        run.name
    );
    assert!(
        r.is_some_and(|r| r <= 5.0),
        "{} {device:?}: no re-lock within 5 s of {what}: {r:?}",
        run.name
    );
}

/// The budgets of the "Done when" for a run whose TT-Multi-RF sends JSON and HEX.
fn check_budgets(r: &Run) {
    check(r, Device::Bahrs, &[], 10.0, 50 * US);
    // VN-200: its native GPS time (in a GNSS outage it is host-timed: checked there).
    check_sel(r, Device::Vn200, "binary native_gps", US, |j| {
        j.at_s >= 10.0 && j.class == "binary" && j.source == Some(TimeSource::NativeGps)
    });
    check(r, Device::Watson, &[], 10.0, HOST_BUDGET_NS);
    check(r, Device::Ttmrf, &["json"], 10.0, MS);
}

#[test]
fn nominal_errors_within_budget_after_10_s() {
    let r = run(&builtin("nominal").unwrap(), 60, 5);
    check_nothing_dropped(&r);
    check_no_wrong_locked(&r);
    check_budgets(&r);
    check(&r, Device::Ttmrf, &["hex_ts24h"], 10.0, 10 * US);
    assert!(locked_share(&r, Device::Bahrs, 10.0, 60.0) > 0.99);
    assert!(locked_share(&r, Device::Vn200, 10.0, 60.0) > 0.99);
    // Pulse seconds: from the VN-200's PPS time, not the host clock, once it reports one.
    println!(
        "nominal pulses: {} from the VN-200 PPS time, {} from the host clock",
        r.pulses_vn200, r.pulses_host
    );
    assert!(r.pulses_vn200 >= 55 && r.pulses_host == 0);
    // Clock reports at the end: every model locked; the host drift is the simulated one.
    for c in &r.report {
        assert_eq!(c.status, ClockStatus::Locked, "{c:?}");
    }
    let host = r
        .report
        .iter()
        .find(|c| c.device == Device::Watson)
        .unwrap();
    let d = host.drift_ppm.unwrap();
    println!(
        "host drift {d:.3} ppm, simulated {:.3} ppm",
        r.host_drift_ppm
    );
    // Precision of the envelope slope: a VN-200 message is read with its last chunk, and the
    // simulated host keeps chunk times monotonic, so its delay is about the largest of its ~4
    // chunks' (uniform over 1 ms): the per-second minimum of 200 such lies ~0.27 ms above the
    // floor with ~70 us of spread; the slope over the 30 s window has ~1.5 ppm of sigma (0.1 to
    // 1.6 ppm seen over 19 seeds): 4.5 ppm is 3 sigma.
    assert!(
        (d - r.host_drift_ppm).abs() < 4.5,
        "{d} vs {}",
        r.host_drift_ppm
    );
    let bahrs = r.report.iter().find(|c| c.device == Device::Bahrs).unwrap();
    // The simulator draws the MCU drift within +-50 ppm.
    assert!(bahrs.drift_ppm.unwrap().abs() <= 50.0, "{bahrs:?}");
}

#[test]
fn nominal_csv_hexd_and_late_bahrs_time_messages_within_budget() {
    let r = run(&nominal_variant(), 30, 11);
    check_nothing_dropped(&r);
    check_no_wrong_locked(&r);
    // Late time messages: every data message still paired and aligned.
    check(&r, Device::Bahrs, &[], 10.0, 50 * US);
    assert!(locked_share(&r, Device::Bahrs, 10.0, 30.0) > 0.99);
    // Only the last 3 data messages of each stream (at 50 and 100 Hz: within 60 ms of the end)
    // have no time message: it was never sent before the run ended.
    let unaligned: Vec<&Joined> = r
        .joined
        .iter()
        .filter(|j| j.device == Device::Bahrs && j.at_s >= 10.0 && j.err_ns.is_none())
        .collect();
    assert_eq!(unaligned.len(), 6, "{unaligned:?}");
    assert!(unaligned.iter().all(|j| j.at_s > 29.9), "{unaligned:?}");
    check(&r, Device::Ttmrf, &["csv"], 10.0, HOST_BUDGET_NS);
    check(&r, Device::Ttmrf, &["nmea"], 10.0, HOST_BUDGET_NS);
    check(&r, Device::Ttmrf, &["hex_no_ts"], 10.0, HOST_BUDGET_NS);
    check(&r, Device::Watson, &[], 10.0, HOST_BUDGET_NS);
    // Nothing of the TT-Multi-RF carries a time stamp here: all of it is host-timed.
    assert!(
        r.joined
            .iter()
            .filter(|j| j.device == Device::Ttmrf && j.at_s >= 10.0)
            .all(|j| j.source == Some(TimeSource::HostClock))
    );
}

#[test]
fn link_errors_budgets_and_relock_after_reset_and_pps_loss() {
    // link-errors: bit errors, dropped bytes, BAHRS link loss 20-22 s, Watson link loss
    // 25-26.5 s, TT-Multi-RF link loss 30-31.5 s, BAHRS reset at 40 s, TT-Multi-RF power cycle at
    // 45 s, PPS loss 50-53 s.
    let r = run(&builtin("link-errors").unwrap(), 70, 7);
    check_nothing_dropped(&r);
    check_no_wrong_locked(&r);
    check_budgets(&r);
    // The BAHRS reset: output again 0.3 s later, first pulse at 41 s.
    check_relock(&r, Device::Bahrs, 40.0, "BAHRS reset");
    // The PPS loss: the MCU clock coasts (never locked with a wrong time, checked above) and
    // re-locks on the first pulse after it.
    check_relock(&r, Device::Bahrs, 53.0, "PPS loss end");
    let coasting = r
        .joined
        .iter()
        .filter(|j| j.device == Device::Bahrs && j.at_s >= 52.0 && j.at_s < 53.0)
        .filter(|j| j.status == Some(ClockStatus::Coasting))
        .count();
    assert!(coasting > 0, "BAHRS coasts during the PPS loss");
    assert!(locked_share(&r, Device::Vn200, 10.0, 70.0) > 0.99);
}

#[test]
fn gnss_outage_models_relock_without_wrong_locked_times() {
    // GNSS and PPS lost from 60 to 120 s.
    let r = run(&builtin("gnss-outage").unwrap(), 130, 3);
    check_nothing_dropped(&r);
    check_no_wrong_locked(&r);
    check_budgets(&r);
    // During the outage nothing of the VN-200 or the BAHRS is claimed locked, except the BAHRS
    // samples of the last 2 s: they wait (`clock_wait_s`) for the first pulse after the outage
    // and are interpolated between it and the pulses before (their errors are checked above).
    for (d, to) in [(Device::Vn200, 120.0), (Device::Bahrs, 118.0)] {
        let share = locked_share(&r, d, 62.0, to);
        println!("gnss-outage {d:?}: locked share 62-{to} s {share:.3}");
        assert_eq!(share, 0.0);
    }
    // The VN-200 during the outage: no valid GPS time and no TimeStartup in its output, so
    // placed by the host clock (coasting on the references from before the outage).
    check_sel(&r, Device::Vn200, "binary in outage", HOST_BUDGET_NS, |j| {
        j.at_s >= 60.5 && j.at_s < 120.0
    });
    assert!(
        r.joined
            .iter()
            .filter(|j| j.device == Device::Vn200 && j.at_s >= 60.5 && j.at_s < 120.0)
            .all(|j| j.source == Some(TimeSource::HostClock))
    );
    // The host-timed Watson coasts on the host clock (no VN-200 references); a line sampled in
    // the last half second is received after the references resumed and is locked.
    assert!(
        r.joined
            .iter()
            .filter(|j| j.device == Device::Watson && j.at_s >= 65.0 && j.at_s < 119.5)
            .all(|j| j.status != Some(ClockStatus::Locked))
    );
    for d in Device::ALL {
        check_relock(&r, d, 120.0, "GNSS outage end");
    }
}
