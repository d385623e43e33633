use vigil_drivers::vn200::binary::{CommonGroup, GnssGroup, GnssTimeInfo, TimeGroup};

use super::*;
use crate::time::host::HostClockConfig;

const MS: i64 = 1_000_000;
const S: i64 = 1_000_000_000;
/// 2026-06-01 10:00:00 UTC = Unix 1 780 308 000 s; GPS = Unix - 315 964 800 + 18.
const G0: i64 = (1_780_308_000 - 315_964_800 + 18) * S;

/// InsStatus: mode 2 (tracking, bits 0-1) and GNSS fix (bit 2) = 0b110.
const INS_OK: u16 = 0b110;
/// InsStatus: tracking, no fix, GNSS error (bit 6).
const INS_NO_GNSS: u16 = 0b100_0010;

fn common(gps: i64, startup: u64, ins: u16) -> BinaryOutput {
    BinaryOutput {
        common: Some(CommonGroup {
            time_startup_ns: Some(startup),
            time_gps_ns: Some(gps as u64),
            ins_status: Some(InsStatus(ins)),
            ..Default::default()
        }),
        ..Default::default()
    }
}

fn rx(host_ns: i64) -> Rx {
    Rx {
        host_ns,
        wire_len: 100,
        reads: None,
    }
}

#[test]
fn valid_time_is_native_and_feeds_the_host_clock() {
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    let off = 42 * S;
    // 100 bytes at 921 600 baud: 1000 / 921600 s = 1.085 ms on the wire, then 1 ms latency.
    let tx = 1_085_069;
    for k in 0..400 {
        let gps = G0 + k * 25 * MS;
        let a = al
            .handle(
                &common(gps, 7 * S as u64 + (k * 25 * MS) as u64, INS_OK),
                rx(gps + off + tx + MS),
                &mut host,
            )
            .unwrap();
        assert_eq!(
            (a.t_gps_ns, a.source, a.status),
            (gps, TimeSource::NativeGps, ClockStatus::Locked)
        );
        assert_eq!(a.sigma_ns, 100.0);
    }
    // The host clock learned host = GPS + 42 s + 1 ms (the constant latency is the envelope).
    let (t, _) = host.to_gps(G0 + 20 * S + off + MS).unwrap();
    assert!((t - (G0 + 20 * S)).abs() < 1_000, "{}", t - (G0 + 20 * S));
    assert_eq!(al.stats().native, 400);
}

#[test]
fn invalid_time_coasts_on_time_startup_with_growing_sigma() {
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    // TimeStartup runs 15 ppm fast: startup = 1 s + (gps - G0) (1 + 15e-6).
    let st = |gps: i64| (S as f64 + (gps - G0) as f64 * (1.0 + 15e-6)) as u64;
    for k in 0..=30 {
        let gps = G0 + k * S;
        al.handle(&common(gps, st(gps), INS_OK), rx(gps), &mut host)
            .unwrap();
    }
    let drift = al.startup_drift_ppm().unwrap();
    assert!((drift - 15.0).abs() < 0.01, "{drift}");
    // GNSS lost at G0 + 30 s: TimeGps still output (frozen or garbage) but flagged.
    for (dt_s, max_err) in [(1, 10), (10, 100), (100, 1_000)] {
        let gps = G0 + (30 + dt_s) * S;
        let a = al
            .handle(
                &common(gps + 123 * S, st(gps), INS_NO_GNSS),
                rx(gps),
                &mut host,
            )
            .unwrap();
        assert_eq!(
            (a.source, a.status),
            (TimeSource::DeviceClock, ClockStatus::Coasting)
        );
        // The measured rate leaves only rounding: well under a microsecond.
        assert!(
            (a.t_gps_ns - gps).abs() < max_err,
            "{dt_s} s: {}",
            a.t_gps_ns - gps
        );
        // sigma = sqrt(100^2 + (dt x 0.5 ppm)^2): 0.5 ppm of 100 s = 50 us.
        let expect = (100f64.powi(2) + (dt_s as f64 * 1e9 * 0.5e-6).powi(2)).sqrt();
        assert!(
            (a.sigma_ns - expect).abs() < 0.01 * expect,
            "{} vs {expect}",
            a.sigma_ns
        );
    }
    assert_eq!(al.status(G0 + 40 * S), ClockStatus::Coasting);
    // Past the coast limit (600 s): unlocked.
    let gps = G0 + 700 * S;
    assert_eq!(
        al.handle(&common(gps, st(gps), INS_NO_GNSS), rx(gps), &mut host),
        Err(NotAligned::ClockUnlocked)
    );
    // GNSS back: native and locked again at once.
    let a = al
        .handle(&common(gps, st(gps), INS_OK), rx(gps), &mut host)
        .unwrap();
    assert_eq!((a.t_gps_ns, a.status), (gps, ClockStatus::Locked));
    // Counted: 32 native, 3 through TimeStartup, 1 not aligned.
    let st = al.stats();
    assert_eq!((st.native, st.startup_clock, st.not_aligned), (32, 3, 1));
}

#[test]
fn no_valid_time_yet_and_device_restart_are_not_aligned() {
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    // Before any valid time: no model.
    assert_eq!(
        al.handle(&common(0, S as u64, INS_NO_GNSS), rx(0), &mut host),
        Err(NotAligned::DeviceTimeInvalid)
    );
    al.handle(&common(G0, 5 * S as u64, INS_OK), rx(0), &mut host)
        .unwrap();
    // The device restarts (TimeStartup back to 0.2 s) without GNSS: the old pair is dropped.
    assert_eq!(
        al.handle(
            &common(G0 + S, 200 * MS as u64, INS_NO_GNSS),
            rx(S),
            &mut host
        ),
        Err(NotAligned::DeviceTimeInvalid)
    );
    assert_eq!(al.stats().restarts, 1);
    // A message with no status at all is not trusted either.
    let bare = BinaryOutput {
        common: Some(CommonGroup {
            time_gps_ns: Some(G0 as u64),
            ..Default::default()
        }),
        ..Default::default()
    };
    assert_eq!(
        al.handle(&bare, rx(2 * S), &mut host),
        Err(NotAligned::DeviceTimeInvalid)
    );
}

#[test]
fn time_group_status_week_tow_uncertainty_and_leap_seconds() {
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    // GPS week and time of week instead of TimeGps; TimeStatus bits 0 and 1 (tow, date) set.
    let week = (G0 / (7 * 86_400 * S)) as u16;
    let tow = G0 - i64::from(week) * 7 * 86_400 * S;
    let o = BinaryOutput {
        time: Some(TimeGroup {
            gps_week: Some(week),
            gps_tow_ns: Some(tow as u64),
            time_status: Some(TimeStatus(0b011)),
            ..Default::default()
        }),
        gnss: Some(Box::new(GnssGroup {
            time_u_s: Some(20e-9),
            time_info: Some(GnssTimeInfo {
                status: TimeStatus(0b111),
                leap_seconds: 19,
            }),
            ..Default::default()
        })),
        ..Default::default()
    };
    let a = al.handle(&o, rx(0), &mut host).unwrap();
    assert_eq!(a.t_gps_ns, G0);
    assert!((a.sigma_ns - 20.0).abs() < 1e-3);
    // The receiver's leap seconds (here a hypothetical 19) win over the table's 18.
    assert_eq!(al.gps_minus_utc(G0).gps_minus_utc_s, 19);
    // Date not valid: not native.
    let mut bad = o.clone();
    bad.time.as_mut().unwrap().time_status = Some(TimeStatus(0b001));
    assert_eq!(
        al.handle(&bad, rx(S), &mut host),
        Err(NotAligned::DeviceTimeInvalid)
    );
    // Without GnssTimeInfo the table answers, flagged valid for 2026.
    let fresh = Vn200Aligner::new(Vn200AlignerConfig::default());
    assert_eq!(
        fresh.gps_minus_utc(G0),
        LeapSeconds {
            gps_minus_utc_s: 18,
            table_valid: true
        }
    );
}

#[test]
fn leap_table_boundary_through_the_aligner() {
    // 2017-01-01 00:00:00 UTC (Unix 1 483 228 800) is the last insertion: one GPS second before
    // it (UTC 23:59:59 + the leap second 23:59:60 lies between) GPS - UTC is 17, after it 18.
    let al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let gps_at_2017 = (1_483_228_800 - 315_964_800 + 18) * S;
    assert_eq!(al.gps_minus_utc(gps_at_2017).gps_minus_utc_s, 18);
    assert_eq!(al.gps_minus_utc(gps_at_2017 - 2 * S).gps_minus_utc_s, 17);
    // Past the table's validity (2027-07-01): the value is kept but flagged.
    let gps_2028 = (1_830_297_600 - 315_964_800 + 18) * S;
    assert!(!al.gps_minus_utc(gps_2028).table_valid);
}

#[test]
fn regression_18_a_gps_time_a_second_off_is_refused_and_timed_by_time_startup() {
    // Issue 18 point 4. 20 s of valid times at 40 Hz from a host clock 42 s ahead of GPS with a
    // 1 ms link; TimeStartup counts from 7 s at the GPS rate. Then the VN-200 names GPS time a
    // second late (a leap-second error) for 10 s, then right again.
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    let other = HostClock::new(HostClockConfig::default());
    let check = CrossCheckConfig::default();
    let (off, tx) = (42 * S, 1_085_069);
    let step = |al: &mut Vn200Aligner, host: &mut HostClock, gps: i64, named: i64| {
        let t = Vn200Times::of(&common(named, (7 * S + gps - G0) as u64, INS_OK));
        al.handle_times_checked(&t, rx(gps + off + tx + MS), host, &other, &check)
    };
    for k in 0..800 {
        let gps = G0 + k * 25 * MS;
        let a = step(&mut al, &mut host, gps, gps).unwrap();
        assert_eq!((a.t_gps_ns, a.source), (gps, TimeSource::NativeGps));
    }
    assert!(!al.clock_disagreement());
    let before = host.to_gps(G0 + 25 * S + off + MS).unwrap();
    for k in 800..1_200 {
        let gps = G0 + k * 25 * MS;
        let a = step(&mut al, &mut host, gps, gps + S).unwrap();
        // Never the wrong GPS time: the VN-200's own crystal through the last right pair.
        assert_eq!(a.source, TimeSource::DeviceClock, "{k}");
        assert!(
            (a.t_gps_ns - gps).abs() < 1_000,
            "{k}: {}",
            a.t_gps_ns - gps
        );
        assert!(al.clock_disagreement());
    }
    assert_eq!(al.stats().disagreeing, 400);
    // The wrong times did not move the host clock (still the relation from before).
    let after = host.to_gps(G0 + 25 * S + off + MS).unwrap();
    assert_eq!(before.0, after.0);
    // Right again: native at once, the bit cleared.
    let gps = G0 + 30 * S;
    let a = step(&mut al, &mut host, gps, gps).unwrap();
    assert_eq!((a.t_gps_ns, a.source), (gps, TimeSource::NativeGps));
    assert!(!al.clock_disagreement());
    // Without TimeStartup there is no other clock here: not aligned, with the reason.
    let t = Vn200Times {
        time_startup_ns: None,
        ..Vn200Times::of(&common(gps + 2 * S, 0, INS_OK))
    };
    let mut fresh = Vn200Aligner::new(Vn200AlignerConfig::default());
    assert_eq!(
        fresh.handle_times_checked(&t, rx(gps + off + tx + MS), &mut host, &other, &check),
        Err(NotAligned::ClockDisagreement)
    );
}

#[test]
fn a_time_uncertainty_of_zero_or_not_finite_leaves_the_last_one() {
    // TimeU 20 ns, then 0, infinity and NaN: none is an uncertainty, the 20 ns stands.
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    let with_u = |u: f32| {
        let mut o = common(G0, 7 * S as u64, INS_OK);
        o.gnss = Some(Box::new(GnssGroup {
            time_u_s: Some(u),
            ..Default::default()
        }));
        o
    };
    for (k, u) in [20e-9, 0.0, f32::INFINITY, f32::NAN]
        .into_iter()
        .enumerate()
    {
        let a = al.handle(&with_u(u), rx(k as i64 * S), &mut host).unwrap();
        assert!(
            (a.sigma_ns - 20.0).abs() < 1e-3,
            "TimeU {u}: {}",
            a.sigma_ns
        );
    }
}

#[test]
fn time_startup_repeated_is_no_restart() {
    // Two messages with the same TimeStartup (a repeated output): no restart; going back is.
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    let _ = al.handle(&common(G0, 7 * S as u64, INS_OK), rx(0), &mut host);
    let _ = al.handle(&common(G0, 7 * S as u64, INS_OK), rx(MS), &mut host);
    assert_eq!(al.stats().restarts, 0);
    let _ = al.handle(&common(G0, 7 * S as u64 - 1, INS_OK), rx(2 * MS), &mut host);
    assert_eq!(al.stats().restarts, 1);
}

#[test]
fn status_edges_after_the_last_valid_time() {
    // Locked for 2 x `status_hold_ns` (2 s) after the last valid GPS time, then coasting on
    // TimeStartup for `coast_limit_ns` (600 s), then unlocked. A host time below 0 counts as 0.
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    for k in 0..3 {
        al.handle(
            &common(G0 + k * S, 7 * S as u64 + (k * S) as u64, INS_OK),
            rx(-5 * S + k * S),
            &mut host,
        )
        .unwrap();
    }
    assert_eq!(al.status(2 * S), ClockStatus::Locked);
    assert_eq!(al.status(2 * S + 1), ClockStatus::Coasting);
    assert_eq!(al.status(600 * S), ClockStatus::Coasting);
    assert_eq!(al.status(600 * S + 1), ClockStatus::Unlocked);
}

#[test]
fn the_baud_rate_sets_the_transmission_time_the_host_clock_learns() {
    // 100-byte messages: 1,085,069 ns on the wire at the default 921,600 baud, 8,680,555 ns at
    // 115,200. The same arrivals mean first bytes 7,595,486 ns earlier at the slower rate: a
    // link delay that much smaller, so a host time maps that much later.
    let learn = |baud: Option<u32>| {
        let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
        if let Some(b) = baud {
            al.set_baud(b);
        }
        let mut host = HostClock::new(HostClockConfig::default());
        for k in 0..400 {
            let gps = G0 + k * 25 * MS;
            al.handle(
                &common(gps, 7 * S as u64, INS_OK),
                rx(gps + 42 * S),
                &mut host,
            )
            .unwrap();
        }
        host.to_gps(G0 + 20 * S + 42 * S).unwrap().0
    };
    let fast = learn(None);
    let slow = learn(Some(115_200));
    assert!((slow - fast - 7_595_486).abs() < 1_000, "{}", slow - fast);
}

#[test]
fn gps_time_validity_from_time_status_and_ins_status() {
    // TimeStatus bit 0 = time of week valid, bit 1 = date valid; InsStatus bit 2 = GNSS fix,
    // bit 6 = GNSS error. Each condition the message carries must hold; a fresh aligner has no
    // TimeStartup model, so an invalid time is DeviceTimeInvalid.
    const FIX: u16 = 0b110;
    const NO_FIX: u16 = 0b010;
    const FIX_ERROR: u16 = 0b100_0110;
    let valid = |ts: Option<u8>, ins: Option<u16>| {
        let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
        let mut host = HostClock::new(HostClockConfig::default());
        let t = Vn200Times {
            time_gps_ns: Some(G0),
            time_status: ts.map(TimeStatus),
            ins_status: ins.map(InsStatus),
            ..Default::default()
        };
        al.handle_times(&t, rx(0), &mut host).is_ok()
    };
    for (ts, ins, want) in [
        (Some(0b011), Some(FIX), true),
        (Some(0b010), Some(FIX), false),
        (Some(0b001), Some(FIX), false),
        (Some(0b011), Some(NO_FIX), false),
        (Some(0b011), Some(FIX_ERROR), false),
        (Some(0b011), None, true),
        (Some(0b001), None, false),
        (Some(0b010), None, false),
        (None, Some(FIX), true),
        (None, Some(NO_FIX), false),
        (None, Some(FIX_ERROR), false),
        (None, None, false),
    ] {
        assert_eq!(valid(ts, ins), want, "{ts:?} {ins:?}");
    }
    // A message without either field takes the last reported validity for 1 s
    // (`status_hold_ns`), not longer, and never an invalid one.
    let bare = Vn200Times {
        time_gps_ns: Some(G0),
        ..Default::default()
    };
    let reported = |ins: u16| Vn200Times {
        ins_status: Some(InsStatus(ins)),
        ..bare
    };
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    assert!(
        al.handle_times(&reported(FIX), rx(10 * S), &mut host)
            .is_ok()
    );
    assert!(al.handle_times(&bare, rx(11 * S), &mut host).is_ok());
    assert!(al.handle_times(&bare, rx(11 * S + 1), &mut host).is_err());
    assert!(
        al.handle_times(&reported(NO_FIX), rx(12 * S), &mut host)
            .is_err()
    );
    assert!(al.handle_times(&bare, rx(12 * S + 1), &mut host).is_err());
}

#[test]
fn output_delay_and_held_back_first_reads_in_what_the_host_clock_learns() {
    // 200 messages at 40 Hz, each in two reads: the first read 1 ms before the last one.
    // `first_after` says whether that first read comes after the previous message's last
    // read (a read after an idle line: a single read's delay) or at the same instant (it may
    // have been held back by it: left out). `delay_ns` is the configured output delay.
    let learn = |first_after: bool, delay_ns: i64| {
        let mut al = Vn200Aligner::new(Vn200AlignerConfig {
            output_delay_ns: delay_ns,
            ..Vn200AlignerConfig::default()
        });
        let mut host = HostClock::new(HostClockConfig::default());
        let mut previous = None;
        for k in 0..200 {
            let gps = G0 + k * 25 * MS;
            let h = gps + 42 * S + 2 * MS;
            let first = match (first_after, previous) {
                (false, Some(p)) => p,
                _ => h - MS,
            };
            let rx = Rx {
                host_ns: h,
                wire_len: 100,
                reads: Some(crate::time::Reads {
                    first_host_ns: first,
                    first_bytes: 50,
                    last_bytes: 50,
                    after_bytes: 0,
                }),
            };
            al.handle(&common(gps, 7 * S as u64, INS_OK), rx, &mut host)
                .unwrap();
            previous = Some(h);
        }
        host
    };
    assert!(learn(true, 0).read_spread_ns().is_some());
    assert!(learn(false, 0).read_spread_ns().is_none());
    // The VN-200 sends 1 ms after its sample: the same arrival was sent 1 ms later in GPS
    // time, so a host time maps 1 ms later.
    let h = G0 + 3 * S + 42 * S;
    let t0 = learn(true, 0).to_gps(h).unwrap().0;
    let t1 = learn(true, MS).to_gps(h).unwrap().0;
    assert_eq!(t1 - t0, MS);
    // The single reads' delay moves with it.
    let t0 = learn(true, 0).to_gps_read(h).unwrap().0;
    let t1 = learn(true, MS).to_gps_read(h).unwrap().0;
    assert_eq!(t1 - t0, MS);
}

#[test]
fn the_time_startup_rate_follows_the_last_minute() {
    // A message every 0.7 s; TimeStartup runs 15 ppm fast for 100 s, then 25 ppm. The rate is
    // measured over the pairs of the last 60 s (6 x `rate_span_ns`, at most one pair a
    // second): at 200 s it is the new 25 ppm alone.
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    let st = |t: i64| {
        let ns_fast = if t <= 100 * S {
            t as f64 * 15e-6
        } else {
            1_500_000.0 + (t - 100 * S) as f64 * 25e-6
        };
        (S + t + ns_fast as i64) as u64
    };
    for k in 0..=286 {
        let t = k * 700 * MS;
        al.handle(&common(G0 + t, st(t), INS_OK), rx(G0 + t), &mut host)
            .unwrap();
    }
    let drift = al.startup_drift_ppm().unwrap();
    assert!((drift - 25.0).abs() < 0.01, "{drift}");
}

#[test]
fn time_startup_coasts_600_s_from_the_last_valid_pair() {
    // The last valid pair at TimeStartup 1 s; GNSS then lost. 600 s of TimeStartup later is the
    // last time given (`coast_limit_ns`), 1 ns more is unlocked.
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    al.handle(&common(G0, S as u64, INS_OK), rx(0), &mut host)
        .unwrap();
    let lost = |startup: u64| common(G0 + 5 * S, startup, INS_NO_GNSS);
    let a = al.handle(&lost(601 * S as u64), rx(S), &mut host).unwrap();
    assert_eq!(a.t_gps_ns, G0 + 600 * S);
    assert_eq!(
        al.handle(&lost(601 * S as u64 + 1), rx(2 * S), &mut host),
        Err(NotAligned::ClockUnlocked)
    );
}

#[test]
fn the_rate_keeps_one_pair_a_second_for_60_s() {
    // Messages every 100 ms for 60 s: one pair kept a second (a pair 1 s after the last kept),
    // so 61 pairs from 0 s to 60 s, not the 601 messages. A pair exactly 60 s old
    // (6 x `rate_span_ns`) is kept; 100 ms later it is dropped, and no pair is added (60.1 s is
    // 0.1 s after the last one kept).
    let mut al = Vn200Aligner::new(Vn200AlignerConfig::default());
    let mut host = HostClock::new(HostClockConfig::default());
    let mut at = |al: &mut Vn200Aligner, t: i64| {
        al.handle(
            &common(G0 + t, (S + t) as u64, INS_OK),
            rx(G0 + t),
            &mut host,
        )
        .unwrap();
    };
    let kept =
        |al: &Vn200Aligner| -> Vec<i64> { al.pairs.iter().map(|p| (p.1 - G0) / S).collect() };
    for k in 0..=600 {
        at(&mut al, k * 100 * MS);
    }
    assert_eq!(kept(&al), (0..=60).collect::<Vec<_>>());
    at(&mut al, 60_100 * MS);
    assert_eq!(kept(&al), (1..=60).collect::<Vec<_>>());
}
