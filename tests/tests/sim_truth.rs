//! Time alignment against the simulator's truth (issue 7, "Done when").
//!
//! The simulator runs its own scenarios with all four device models (BAHRS, Watson, VN-200,
//! TT-Multi-RF); every port's received bytes are decoded with the drivers and aligned, and each
//! aligned sample is joined to its truth record by device and stream offset (`rx_offset`), so
//! messages lost or damaged by link faults do not shift the join (damaged ones have no truth).
//!
//! Decoding follows `vigil replay --emit aligned` (`service/src/replay/aligned.rs`): BAHRS and Watson
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

mod truth_run;

use truth_run::*;
use vigil_fusion::time::aligner::Device;
use vigil_fusion::time::{ClockStatus, TimeSource};
use vigil_sim::scenario::{Scenario, builtin};

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
    // During the outage nothing of the VN-200 is claimed locked, and nothing of the BAHRS is
    // claimed PPS-locked (it is placed by its host-clock fallback, issue 25 point 3: its status
    // is the host clock's, which the TT-Multi-RF's GNSS time may keep locked).
    let share = locked_share(&r, Device::Vn200, 62.0, 120.0);
    println!("gnss-outage Vn200: locked share 62-120 s {share:.3}");
    assert_eq!(share, 0.0);
    // The PPS clock coasts for 30 s after its last pulse (60 s), then the fallback takes over.
    assert!(r.joined.iter().all(|j| j.device != Device::Bahrs
        || j.at_s < 62.0
        || j.at_s >= 118.0
        || j.source != Some(TimeSource::PpsDisciplined)
        || j.status != Some(ClockStatus::Locked)));
    let during: Vec<&Joined> = r
        .joined
        .iter()
        .filter(|j| j.device == Device::Bahrs && j.at_s >= 91.0 && j.at_s < 118.0)
        .collect();
    let fallback = during
        .iter()
        .filter(|j| j.source == Some(TimeSource::DeviceClockViaHost))
        .count();
    println!(
        "gnss-outage Bahrs: {fallback} of {} by the host fallback",
        during.len()
    );
    assert!(fallback as f64 >= 0.99 * during.len() as f64);
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
    // The host-timed Watson stays aligned: the VN-200's host clock model coasts, and the one
    // the TT-Multi-RF's JSON `ts` keeps (issue 18 point 6) is locked; the better one places it
    // (its errors are checked above).
    assert!(
        r.joined
            .iter()
            .filter(|j| j.device == Device::Watson && j.at_s >= 65.0 && j.at_s < 119.5)
            .all(|j| j.err_ns.is_some())
    );
    for d in Device::ALL {
        check_relock(&r, d, 120.0, "GNSS outage end");
    }
}
