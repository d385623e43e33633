//! The Aligner with synthetic streams (the simulator has no VN-200 / TT-Multi-RF model yet): a
//! VN-200 at 40 Hz on a host clock 9 s ahead of GPS with a 1 ms link delay, plus Watson lines,
//! TT-Multi-RF JSON and HEX frames and BAHRS messages.

use vigil_drivers::bahrs::{DataTime, Inertial, InertialHealth};
use vigil_drivers::ttmrf::json::JsonMessage;
use vigil_drivers::ttmrf::raw::{ModeSFrame, RxMeta};
use vigil_drivers::vn200::binary::{BinaryOutput, CommonGroup};
use vigil_drivers::vn200::status::InsStatus;
use vigil_drivers::watson::{Kind, Line};

use super::*;
use crate::time::TimeSource;
use crate::time::host::{HostClock, HostClockConfig};
use crate::time::host_timed::tx_ns;

const MS: i64 = 1_000_000;
const S: i64 = 1_000_000_000;
/// Host clock - GPS time.
const OFF: i64 = 9 * S;
/// 2026-06-01 23:59:50 UTC in GPS ns: Unix 1 780 358 390 s - GPS epoch + 18 s.
const G0: i64 = (1_780_358_390 - 315_964_800 + 18) * S;

fn vn200(gps: i64) -> (Sample, Rx) {
    let o = BinaryOutput {
        common: Some(CommonGroup {
            time_gps_ns: Some(gps as u64),
            time_startup_ns: Some((gps - G0 + S) as u64),
            ins_status: Some(InsStatus(0b110)),
            ..Default::default()
        }),
        ..Default::default()
    };
    let len = o.encode().len();
    let rx = Rx {
        host_ns: gps + OFF + tx_ns(len, 921_600) + MS,
        wire_len: len,
        reads: None,
    };
    (Sample::Vn200(Box::new(Vn200Message::Binary(o))), rx)
}

fn watson() -> Sample {
    Sample::Watson(Line {
        kind: Kind::Inertial,
        over_range: false,
        bank_deg: 0.0,
        elevation_deg: 0.0,
        heading_deg: 0.0,
        accel_g: [0.0, 0.0, 1.0],
        rate_dps: [0.0; 3],
        velocity_kmh: 0.0,
    })
}

/// Receive of a Watson line sampled at `gps`: 1 ms output delay, 66.7 ms on the wire, 1 ms link.
fn watson_rx(gps: i64) -> Rx {
    Rx {
        host_ns: gps + OFF + MS + tx_ns(64, 9600) + MS,
        wire_len: 64,
        reads: None,
    }
}

#[test]
fn host_timed_samples_wait_for_the_host_clock_then_align_or_are_marked() {
    let mut al = Aligner::new(AlignerConfig::default());
    let mut out = Vec::new();
    // A Watson line 5 s before any VN-200: it waits 3 s, then comes out not aligned.
    out.extend(al.handle(watson(), watson_rx(G0 - 5 * S)));
    assert!(out.is_empty());
    let mut truth = vec![G0 - 5 * S];
    // VN-200 from G0 at 40 Hz; a Watson line every 100 ms from G0 + 0.05 s.
    for k in 0..400 {
        let g = G0 + k * 25 * MS;
        let (s, rx) = vn200(g);
        out.extend(al.handle(s, rx));
        if k % 4 == 2 {
            let w = g - 12 * MS;
            truth.push(w);
            out.extend(al.handle(watson(), watson_rx(w)));
        }
    }
    out.extend(al.flush());
    let watson: Vec<&AlignedSample> = out.iter().filter(|o| o.device == Device::Watson).collect();
    // Every Watson input came out exactly once, with its index.
    let mut idx: Vec<u64> = watson.iter().map(|o| o.index).collect();
    idx.sort_unstable();
    assert_eq!(idx, (0..truth.len() as u64).collect::<Vec<_>>());
    assert_eq!(
        out.iter().filter(|o| o.device == Device::Vn200).count(),
        400
    );
    for o in &watson {
        match o.aligned.time {
            Ok(a) => {
                // The host model maps with the VN-200's delay; the Watson link matches it.
                let e = a.t_gps_ns - truth[o.index as usize];
                assert!(e.abs() < 100_000, "index {}: {e} ns", o.index);
                assert_eq!(a.source, TimeSource::HostClock);
            }
            Err(why) => {
                // Only the line from before the host clock: held for 3 s, then marked.
                assert_eq!((o.index, why), (0, NotAligned::HostClockUnknown));
            }
        }
    }
    // Early lines (first 2 s) waited for the host model and came out aligned, status locking.
    let early = watson.iter().find(|o| o.index == 1).unwrap();
    assert_eq!(early.aligned.time.unwrap().status, ClockStatus::Locking);
    let report = al.clock_report(G0 + 10 * S + OFF);
    let w = report.iter().find(|r| r.device == Device::Watson).unwrap();
    assert_eq!(w.status, ClockStatus::Locked);
    // The offset is the host clock's 9 s plus the 1 ms link delay (the envelope).
    assert!((w.offset_ns.unwrap() - (OFF + MS) as f64).abs() < 1_000.0);
    let v = report.iter().find(|r| r.device == Device::Vn200).unwrap();
    assert_eq!(v.status, ClockStatus::Locked);
}

#[test]
fn ttmrf_json_ts_and_ts24h_across_utc_midnight_through_the_aligner() {
    let mut al = Aligner::new(AlignerConfig::default());
    let mut out = Vec::new();
    // GPS - UTC = 18 s: UTC midnight of 2026-06-02 is G0 + 10 s.
    let midnight = G0 + 10 * S;
    let mut truth = Vec::new();
    for k in 0..800 {
        let g = G0 + k * 25 * MS;
        let (s, rx) = vn200(g);
        out.extend(al.handle(s, rx));
        if k % 20 == 5 && g > G0 + 3 * S {
            // A JSON message stamped at the whole ms of its instant (truncated), and a HEX frame
            // with TS24h of the same instant, 2 ms (JSON) / 1 ms (HEX) before their receive.
            let t = g + 300_123;
            let ms_of_day = (t - midnight).rem_euclid(86_400 * S) / MS;
            let json = JsonMessage {
                ts_ms: Some(ms_of_day as u32),
                ..Default::default()
            };
            let rx = Rx {
                host_ns: t + OFF + 2 * MS,
                wire_len: 200,
                reads: None,
            };
            truth.push((t, 1_000_000));
            out.extend(al.handle(
                Sample::TtText(Box::new(TextMessage::Json(Box::new(json)))),
                rx,
            ));
            let frame = RawFrame::ModeS(ModeSFrame {
                bytes: [0x8D; 14],
                len: 14,
                meta: RxMeta {
                    ts_utc_ns: Some((t - midnight).rem_euclid(86_400 * S) as u64),
                    ..Default::default()
                },
            });
            let rx = Rx {
                host_ns: t + OFF + MS,
                wire_len: 50,
                reads: None,
            };
            truth.push((t, 1));
            out.extend(al.handle(Sample::TtRaw(Box::new(frame)), rx));
        }
    }
    out.extend(al.flush());
    let tt: Vec<&AlignedSample> = out.iter().filter(|o| o.device == Device::Ttmrf).collect();
    assert_eq!(tt.len(), truth.len());
    let (mut before, mut after) = (0, 0);
    for o in tt {
        let (t, tol) = truth[o.index as usize];
        let a = o.aligned.time.unwrap();
        // JSON: within the ms (truncated stamp + 0.5 ms); TS24h: exact.
        assert!(
            (a.t_gps_ns - t).abs() <= tol / 2,
            "{}: {}",
            o.index,
            a.t_gps_ns - t
        );
        assert!(((a.t_gps_ns - t).abs() as f64) <= 2.0 * a.sigma_ns);
        assert_eq!(a.source, TimeSource::UtcTimeOfDay);
        if t < midnight {
            before += 1;
        } else {
            after += 1;
        }
    }
    // Both days were exercised.
    assert!(before > 10 && after > 10, "{before} {after}");
}

#[test]
fn bahrs_indices_survive_late_time_messages_and_time_messages_come_out() {
    let mut al = Aligner::new(AlignerConfig::default());
    let data = |seq| {
        Sample::Bahrs(bahrs::Message::Inertial(Inertial {
            seq,
            specific_force_raw: [0; 3],
            angular_rate_raw: [0; 3],
            health: InertialHealth(0),
        }))
    };
    let time = |seq, us| {
        Sample::Bahrs(bahrs::Message::InertialTime(DataTime {
            seq,
            data_seq: seq,
            mcu_time_us: us,
        }))
    };
    let rx = |ms: i64| Rx {
        host_ns: ms * MS,
        wire_len: 20,
        reads: None,
    };
    let mut out = Vec::new();
    // Data 255 (index 0), data 0 (index 1, the counter wrapped), time of 255 (index 2), time of 0
    // (index 3): the time messages arrive after the next data message.
    out.extend(al.handle(data(255), rx(0)));
    out.extend(al.handle(data(0), rx(10)));
    out.extend(al.handle(time(255, 1_000), rx(11)));
    out.extend(al.handle(time(0, 11_000), rx(21)));
    out.extend(al.flush());
    let mut idx: Vec<u64> = out.iter().map(|o| o.index).collect();
    idx.sort_unstable();
    assert_eq!(idx, vec![0, 1, 2, 3]);
    // No pulse and no host clock: nothing is aligned, each says why.
    for o in &out {
        let why = o.aligned.time.unwrap_err();
        assert!(
            matches!(why, NotAligned::ClockUnlocked),
            "{}: {why:?}",
            o.index
        );
    }
}

#[test]
fn ttmrf_csv_line_is_host_timed_with_its_transmission_time() {
    use vigil_drivers::decode_slice;
    use vigil_drivers::ttmrf::text::{TextDecoder, TextMode};
    // The manual's first CSV example (7.2.1), as the module sends it.
    let line =
        b"#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE\r\n";
    let msgs = decode_slice(&mut TextDecoder::new(TextMode::Auto), line);
    assert_eq!(msgs.len(), 1);
    assert!(matches!(msgs[0], TextMessage::Csv(_)));
    let mut al = Aligner::new(AlignerConfig::default());
    for k in 0..400 {
        let (s, rx) = vn200(G0 + k * 25 * MS);
        al.handle(s, rx);
    }
    // Instant G0 + 9.9 s; first byte at once (the assumed output delay: 0); 83 bytes at
    // 921 600 baud take 0.90 ms; read 1 ms (the VN-200's link delay) after the last byte.
    let t = G0 + 9_900 * MS;
    let rx = Rx {
        host_ns: t + OFF + tx_ns(line.len(), 921_600) + MS,
        wire_len: line.len(),
        reads: None,
    };
    let out = al.handle(Sample::TtText(Box::new(msgs[0].clone())), rx);
    let a = out
        .iter()
        .find(|o| o.device == Device::Ttmrf)
        .unwrap()
        .aligned
        .time
        .unwrap();
    assert!((a.t_gps_ns - t).abs() < 2_000, "{}", a.t_gps_ns - t);
    assert_eq!(
        (a.source, a.status),
        (TimeSource::HostClock, ClockStatus::Locked)
    );
    // The sigma carries the assumed output delay's 0.5 ms.
    assert!(a.sigma_ns >= 500_000.0);
}

#[test]
fn random_inputs_never_panic_and_every_input_comes_out_once() {
    use crate::time::testrng::Lcg;
    use vigil_drivers::bahrs::{Accuracy, SyncPulseTime};
    let mut rng = Lcg(2024);
    let next = |rng: &mut Lcg| (rng.unit() * u64::MAX as f64) as u64;
    for round in 0..4 {
        let mut al = Aligner::new(AlignerConfig::default());
        let mut inputs = [0u64; 4];
        let mut outs = Vec::new();
        let mut host = G0;
        for _ in 0..5_000 {
            // Mostly plausible host times, sometimes wild ones (backwards, extreme).
            host = match (rng.unit() * 20.0) as u32 {
                0 => next(&mut rng) as i64,
                1 => i64::MIN + (rng.unit() * 1e9) as i64,
                2 => i64::MAX - (rng.unit() * 1e9) as i64,
                3 => host.saturating_sub((rng.unit() * 10.0 * S as f64) as i64),
                _ => host.saturating_add((rng.unit() * 50.0 * MS as f64) as i64),
            };
            let rx = Rx {
                host_ns: host,
                wire_len: (rng.unit() * 2000.0) as usize,
                reads: None,
            };
            let pick = (rng.unit() * 7.0) as u32;
            let wild = round % 2 == 1;
            let u = |rng: &mut Lcg, plausible: u64| if wild { next(rng) } else { plausible };
            let sample = match pick {
                0 => {
                    let gps = u(&mut rng, host.wrapping_sub(OFF) as u64);
                    let st = u(&mut rng, host.wrapping_sub(G0) as u64);
                    Sample::Vn200(Box::new(Vn200Message::Binary(BinaryOutput {
                        common: Some(CommonGroup {
                            time_gps_ns: Some(gps),
                            time_startup_ns: Some(st),
                            time_gps_pps_ns: Some(u(&mut rng, gps % S as u64)),
                            ins_status: Some(InsStatus((rng.unit() * 65536.0) as u16)),
                            ..Default::default()
                        }),
                        ..Default::default()
                    })))
                }
                1 => watson(),
                2 => Sample::Bahrs(bahrs::Message::SyncPulseTime(SyncPulseTime {
                    seq: (rng.unit() * 256.0) as u8,
                    mcu_time_us: u(&mut rng, (host.wrapping_sub(G0) / 1000) as u64),
                })),
                3 => Sample::Bahrs(bahrs::Message::Accuracy(Accuracy {
                    seq: 0,
                    std_north_raw: 1,
                    std_east_raw: 1,
                    std_heading_raw: 1,
                    mcu_time_us: u(&mut rng, (host.wrapping_sub(G0) / 1000) as u64),
                })),
                4 => Sample::Bahrs(bahrs::Message::InertialTime(DataTime {
                    seq: (rng.unit() * 256.0) as u8,
                    data_seq: (rng.unit() * 256.0) as u8,
                    mcu_time_us: next(&mut rng),
                })),
                5 => Sample::TtText(Box::new(TextMessage::Json(Box::new(JsonMessage {
                    ts_ms: Some(next(&mut rng) as u32),
                    ..Default::default()
                })))),
                _ => Sample::TtRaw(Box::new(RawFrame::ModeS(ModeSFrame {
                    bytes: [0; 14],
                    len: 7,
                    meta: RxMeta {
                        ts_utc_ns: (rng.unit() < 0.5).then(|| next(&mut rng)),
                        ts_pps_ns: Some(next(&mut rng) % (2 * S as u64)),
                        ..Default::default()
                    },
                }))),
            };
            inputs[sample.device() as usize] += 1;
            outs.extend(al.handle(sample, rx));
        }
        outs.extend(al.flush());
        for d in Device::ALL {
            let mut idx: Vec<u64> = outs
                .iter()
                .filter(|o| o.device == d)
                .map(|o| o.index)
                .collect();
            idx.sort_unstable();
            assert_eq!(idx, (0..inputs[d as usize]).collect::<Vec<_>>(), "{d:?}");
        }
        let _ = al.clock_report(host);
    }
}

/// A VN-200 message sampled at `gps` with TimeGps, TimeGpsPps (PPS on whole GPS seconds) and
/// InsStatus `ins`.
fn vn200_pps(gps: i64, ins: u16) -> (Sample, Rx) {
    let o = BinaryOutput {
        common: Some(CommonGroup {
            time_gps_ns: Some(gps as u64),
            time_gps_pps_ns: Some(gps.rem_euclid(S) as u64),
            ins_status: Some(InsStatus(ins)),
            ..Default::default()
        }),
        ..Default::default()
    };
    let len = o.encode().len();
    let rx = Rx {
        host_ns: gps + OFF + tx_ns(len, 921_600) + MS,
        wire_len: len,
        reads: None,
    };
    (Sample::Vn200(Box::new(Vn200Message::Binary(o))), rx)
}

/// Runs 20 s of a VN-200 at 40 Hz sampled 1 ms before each whole second (its message nearest to
/// each pulse reports the previous PPS) and a BAHRS reporting each PPS edge (0x06, MCU clock
/// 20 ppm fast); from `pps_lost_at` the VN-200 reports "GNSS error" (no valid PPS) while the
/// pulses go on. The BAHRS also sends 0x01 + 0x05 at 50 Hz (its MCU-to-host relation, which
/// cross-checks every pulse: issue 18). Returns the aligner and (pulse number, aligned 0x06).
fn pulses_near_vn200(pps_lost_at: Option<i64>) -> (Aligner, Vec<(i64, AlignedSample)>) {
    use vigil_drivers::bahrs::SyncPulseTime;
    let mut al = Aligner::new(AlignerConfig::default());
    let ticks = |gps: i64| 3_000_000 + ((gps - G0) as f64 * (1.0 + 20e-6) / 1000.0) as u64;
    let mut inputs: Vec<(Sample, Rx)> = Vec::new();
    for k in 0..800 {
        let g = G0 + k * 25 * MS - MS;
        let lost = pps_lost_at.is_some_and(|l| g >= G0 + l * S);
        inputs.push(vn200_pps(g, if lost { 0x43 } else { 0b110 }));
    }
    for n in 0..20 {
        let pulse = G0 + n * S;
        let p = Sample::Bahrs(bahrs::Message::SyncPulseTime(SyncPulseTime {
            seq: n as u8,
            mcu_time_us: ticks(pulse),
        }));
        // Ready 0.5 ms after the edge, 12 bytes at 115 200 baud, 1 ms link.
        let rx = Rx {
            host_ns: pulse + OFF + MS / 2 + tx_ns(12, 115_200) + MS,
            wire_len: 12,
            reads: None,
        };
        inputs.push((p, rx));
    }
    for k in 0..1_000 {
        let sample = G0 + k * 20 * MS;
        let seq = k as u8;
        let data = bahrs::Message::Inertial(Inertial {
            seq,
            specific_force_raw: [0; 3],
            angular_rate_raw: [0; 3],
            health: InertialHealth(0),
        });
        let time = bahrs::Message::InertialTime(DataTime {
            seq,
            data_seq: seq,
            mcu_time_us: ticks(sample),
        });
        // 0x01 (28 bytes) then 0x05, ready 0.5 ms after the sample, 1 ms link.
        let (l1, l5) = (data.to_frame().len(), time.to_frame().len());
        let end1 = sample + OFF + MS / 2 + tx_ns(l1, 115_200) + MS;
        inputs.push((
            Sample::Bahrs(data),
            Rx {
                host_ns: end1,
                wire_len: l1,
                reads: None,
            },
        ));
        inputs.push((
            Sample::Bahrs(time),
            Rx {
                host_ns: end1 + tx_ns(l5, 115_200),
                wire_len: l5,
                reads: None,
            },
        ));
    }
    inputs.sort_by_key(|(_, rx)| rx.host_ns);
    let mut out = Vec::new();
    for (s, rx) in inputs {
        out.extend(al.handle(s, rx));
    }
    out.extend(al.flush());
    let pulses = out
        .into_iter()
        .filter_map(|o| match &o.aligned.message {
            Sample::Bahrs(bahrs::Message::SyncPulseTime(p)) => Some((i64::from(p.seq), o)),
            _ => None,
        })
        .collect();
    (al, pulses)
}

#[test]
fn bahrs_pulses_named_by_the_vn200_pps_time_across_the_second_boundary() {
    let (al, pulses) = pulses_near_vn200(None);
    // The nearest VN-200 message to each pulse was sampled 1 ms before it (TimeGpsPps 999 ms,
    // its last PPS the previous second); the pulse is still named by its own second. The
    // pulses before the host clock and the MCU-to-host relation exist (2 s of references, the
    // pulses at 0, 1 and 2 s) cannot be cross-checked and are not used.
    let st = al.bahrs().stats();
    assert_eq!(st.pulses_from_vn200_pps, 17, "{st:?}");
    assert_eq!(
        (st.pulses_unverified, st.pulses_disagreeing),
        (3, 0),
        "{st:?}"
    );
    assert_eq!(st.pulses_from_host_clock, 0);
    assert_eq!(
        al.bahrs().last_pulse_source(),
        Some(crate::time::pps::PulseSecondSource::Vn200Pps)
    );
    assert_eq!(pulses.len(), 20);
    for (n, o) in &pulses {
        // Each 0x06 is placed at its edge: exactly (whole us, MCU time of the edge) through the
        // PPS clock; within its sigma (about 1 ms) through the host-clock fallback. The first
        // pulses' 0x06 wait (2 s) for a clock that is not there yet: not aligned.
        let Ok(a) = o.aligned.time else {
            assert!(*n < 3, "{n}: {o:?}");
            continue;
        };
        let e = (a.t_gps_ns - (G0 + n * S)).abs();
        if a.source == TimeSource::PpsDisciplined && *n >= 3 {
            assert!(e <= 2_000, "{n}: {a:?}");
        } else {
            assert!((e as f64) < 3.0 * a.sigma_ns && *n < 5, "{n}: {a:?}");
        }
    }
    assert_eq!(al.bahrs().clock().relocks, 0);
}

#[test]
fn bahrs_pulses_fall_back_to_the_host_clock_when_the_vn200_pps_is_lost() {
    // From 10 s the VN-200 reports no valid PPS: its PPS times are not used; after the last one
    // is more than 1 s away the host clock (coasting on the VN-200 references before 10 s) names
    // the pulses, still the right seconds.
    let (al, pulses) = pulses_near_vn200(Some(10));
    let st = al.bahrs().stats();
    // Pulses 0-2 cannot be cross-checked yet (see above).
    assert_eq!(st.pulses_from_vn200_pps, 8, "{st:?}");
    assert_eq!(st.pulses_from_host_clock, 9, "{st:?}");
    assert_eq!(
        al.bahrs().last_pulse_source(),
        Some(crate::time::pps::PulseSecondSource::HostClock)
    );
    for (n, o) in pulses.iter().filter(|(n, _)| *n >= 3) {
        let a = o.aligned.time.unwrap();
        assert!((a.t_gps_ns - (G0 + n * S)).abs() <= 2_000, "{n}: {a:?}");
    }
    assert_eq!((st.pulses_rejected, al.bahrs().clock().relocks), (0, 0));
}

#[test]
fn vn200_without_gps_time_or_startup_clock_is_host_timed() {
    let mut al = Aligner::new(AlignerConfig::default());
    // Invalid from the start: no host clock either, the VN-200's reason stands.
    let (s, rx) = vn200_pps(G0 - S, 0x43);
    let o = al.handle(s, rx);
    assert_eq!(o[0].aligned.time, Err(NotAligned::DeviceTimeInvalid));
    // 10 s valid at 40 Hz, then 5 s of GNSS outage (no TimeStartup in the output).
    let mut out = Vec::new();
    for k in 0..600 {
        let g = G0 + k * 25 * MS;
        let (s, rx) = vn200_pps(g, if k < 400 { 0b110 } else { 0x43 });
        out.extend(al.handle(s, rx).into_iter().map(|o| (g, o)));
    }
    for (g, o) in &out[400..] {
        let a = o.aligned.time.unwrap();
        assert_eq!(a.source, TimeSource::HostClock);
        // The synthetic VN-200 has no output delay, the 1 ms link is the envelope: exact but
        // for rounding; the sigma carries the reference delay's 0.5 ms.
        assert!((a.t_gps_ns - g).abs() < 10_000, "{}", a.t_gps_ns - g);
        assert!(a.sigma_ns >= 500_000.0);
    }
    // The host clock coasts 2 s after its last reference.
    let last = out.last().unwrap().1.aligned.time.unwrap();
    assert_eq!(last.status, ClockStatus::Coasting);
}

// --- issue 23: behaviours the mutation run found unpinned ---

/// An aligner whose host clock is locked on 10 s of the synthetic VN-200 (G0 .. G0 + 10 s).
fn locked_on_vn200() -> Aligner {
    let mut al = Aligner::new(AlignerConfig::default());
    for k in 0..400 {
        let (s, rx) = vn200(G0 + k * 25 * MS);
        al.handle(s, rx);
    }
    al
}

/// The time `al` gives a Watson line received as `rx`.
fn watson_time(al: &mut Aligner, rx: Rx) -> AlignedTime {
    al.handle(watson(), rx)
        .into_iter()
        .find(|o| o.device == Device::Watson)
        .unwrap()
        .aligned
        .time
        .unwrap()
}

#[test]
fn a_paced_watson_port_behind_a_latency_timer_takes_both_waits_off_and_adds_their_variances() {
    let mut al = locked_on_vn200();
    // Unpaced: the line of G0 + 9.5 s, received as `watson_rx` says, is placed at its instant.
    let w1 = G0 + 9_500 * MS;
    let base = watson_time(&mut al, watson_rx(w1));
    assert!(
        (base.t_gps_ns - w1).abs() < 100_000,
        "{}",
        base.t_gps_ns - w1
    );
    // Read every 10 ms behind a 4 ms latency timer: two uniform waits, on average 10/2 + 4/2 =
    // 7 ms; variances 10^2/12 + 4^2/12 = 116/12 ms^2 added to the sigma^2.
    al.set_read_interval(Device::Watson, 10 * MS as u64);
    al.set_latency_timer(Device::Watson, 4 * MS as u64);
    let w2 = G0 + 9_510 * MS;
    let mut rx = watson_rx(w2);
    rx.host_ns += 7 * MS;
    let paced = watson_time(&mut al, rx);
    assert!(
        (paced.t_gps_ns - w2).abs() < 100_000,
        "{}",
        paced.t_gps_ns - w2
    );
    let added_ms2 = (paced.sigma_ns.powi(2) - base.sigma_ns.powi(2)) / 1e12;
    assert!((added_ms2 - 116.0 / 12.0).abs() < 0.05, "{added_ms2}");
}

#[test]
fn a_paced_ttmrf_port_takes_half_the_interval_off_its_host_timed_messages() {
    // A JSON message without `ts`: host-timed with the port's link.
    let csv = || Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    let time = |al: &mut Aligner, rx| {
        al.handle(csv(), rx)
            .into_iter()
            .find(|o| o.device == Device::Ttmrf)
            .unwrap()
            .aligned
            .time
            .unwrap()
    };
    let mut al = locked_on_vn200();
    // A message of 80 bytes at 921 600 baud, first byte at its instant (output delay 0), read 1 ms
    // (the VN-200's link) after its last byte.
    let rx = |t: i64| Rx {
        host_ns: t + OFF + tx_ns(80, 921_600) + MS,
        wire_len: 80,
        reads: None,
    };
    let t1 = G0 + 9_500 * MS;
    let base = time(&mut al, rx(t1));
    assert!(
        (base.t_gps_ns - t1).abs() < 100_000,
        "{}",
        base.t_gps_ns - t1
    );
    // Read every 10 ms: 5 ms later on average, 100/12 ms^2 more variance. (100 ms after the
    // first, so the two cannot have been sent back to back.)
    al.set_read_interval(Device::Ttmrf, 10 * MS as u64);
    let t2 = G0 + 9_600 * MS;
    let mut r = rx(t2);
    r.host_ns += 5 * MS;
    let paced = time(&mut al, r);
    assert!(
        (paced.t_gps_ns - t2).abs() < 100_000,
        "{}",
        paced.t_gps_ns - t2
    );
    let added_ms2 = (paced.sigma_ns.powi(2) - base.sigma_ns.powi(2)) / 1e12;
    assert!((added_ms2 - 100.0 / 12.0).abs() < 0.05, "{added_ms2}");
}

/// Two 100-byte TT-Multi-RF messages at 115 200 baud (8 680 555 ns of line each), stamped 20 ms
/// apart by a port read every 20 ms: back to back on the wire they would end 8.68 ms apart, and
/// a read every 20 ms may stamp one up to 20 ms later than the other, so the second may have
/// waited behind the first. Its wait of 0 ..= 8 680 556 ns (the two messages' line time less
/// its own, each rounded down) is taken as uniform: it is placed 4 340 278 ns earlier than the
/// same message with nothing before it, and its sigma^2 is larger by 8 680 556^2 / 12 (by
/// hand). The read interval is what allows it: stamped so, the two cannot have been back to
/// back on a port read as its bytes arrive (a read's spread, 5 ms, does not cover 11.3 ms).
#[test]
fn a_message_stamped_within_a_reads_reach_of_the_one_before_may_have_queued_behind_it() {
    let no_ts = || Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    let rx = |host_ns: i64| Rx {
        host_ns,
        wire_len: 100,
        reads: None,
    };
    let h1 = G0 + 9_500 * MS + OFF + 3 * MS;
    let h2 = h1 + 20 * MS;
    let aligner = |interval_ms: u64| {
        let mut al = locked_on_vn200();
        al.set_baud(Device::Ttmrf, 115_200);
        al.set_read_interval(Device::Ttmrf, interval_ms * MS as u64);
        al
    };
    let second_after_first = |interval_ms| {
        let mut al = aligner(interval_ms);
        tt_out(&mut al, (no_ts(), rx(h1))).unwrap();
        tt_out(&mut al, (no_ts(), rx(h2))).unwrap()
    };
    let alone = |interval_ms| tt_out(&mut aligner(interval_ms), (no_ts(), rx(h2))).unwrap();
    let (queued, quiet) = (second_after_first(20), alone(20));
    assert_eq!(quiet.t_gps_ns - queued.t_gps_ns, 4_340_278);
    let added = queued.sigma_ns.powi(2) - quiet.sigma_ns.powi(2);
    assert!((added - 8_680_556f64.powi(2) / 12.0).abs() < 1e3, "{added}");
    let (queued, quiet) = (second_after_first(0), alone(0));
    assert_eq!(queued, quiet);
}

#[test]
fn a_watson_port_at_another_baud_rate_is_timed_with_it_and_zero_keeps_it() {
    let mut al = locked_on_vn200();
    al.set_baud(Device::Watson, 19_200);
    // 0: "keep the built-in rate" must not undo or break the one set.
    al.set_baud(Device::Watson, 0);
    // 64 bytes at 19 200 baud take 33.3 ms on the wire (at the built-in 9600: 66.7 ms).
    let w = G0 + 9_500 * MS;
    let rx = Rx {
        host_ns: w + OFF + MS + tx_ns(64, 19_200) + MS,
        wire_len: 64,
        reads: None,
    };
    let a = watson_time(&mut al, rx);
    assert!((a.t_gps_ns - w).abs() < 100_000, "{}", a.t_gps_ns - w);
}

#[test]
fn bahrs_clock_report_gives_its_mcu_clock_minus_gps_time() {
    let (al, _) = pulses_near_vn200(None);
    // The last BAHRS message is the 0x05 of the sample at G0 + 19.98 s: MCU time
    // 3 s + 19.98 s * (1 + 20 ppm). MCU clock minus GPS time there:
    // 3e9 + 19.98e9 * (1 + 20e-6) - (G0 + 19.98e9) = 3e9 - G0 + 399 600 ns.
    let expected = 3e9 - G0 as f64 + 399_600.0;
    let r = al.clock_report(G0 + 20 * S + OFF);
    let b = r.iter().find(|r| r.device == Device::Bahrs).unwrap();
    let offset = b.offset_ns.unwrap();
    // The tick is truncated to the us, the fit is within a few us.
    assert!((offset - expected).abs() < 5_000.0, "{}", offset - expected);
    assert!(
        (b.drift_ppm.unwrap() - 20.0).abs() < 1.0,
        "{:?}",
        b.drift_ppm
    );
}

/// A host clock with a reference every 25 ms from GPS time `G0 + from_ms` to `G0 + to_ms`
/// (host = GPS + OFF + 1 ms link).
fn host_clock(from_ms: i64, to_ms: i64) -> HostClock {
    let mut c = HostClock::new(HostClockConfig::default());
    for g in (from_ms..to_ms).step_by(25).map(|ms| G0 + ms * MS) {
        c.add(g + OFF + MS, g);
    }
    c
}

#[test]
fn pick_takes_the_coasting_clock_with_the_smaller_sigma_and_the_vn200_on_a_tie() {
    // Both coasting at G0 + 15 s: the one silent for 3 s (references to 12 s) has grown less
    // sigma than the one silent for 5 s (references to 10 s).
    let h = G0 + 15 * S + OFF;
    let (short, long) = (host_clock(0, 10_000), host_clock(0, 12_000));
    assert_eq!(short.status(h), ClockStatus::Coasting);
    assert_eq!(long.status(h), ClockStatus::Coasting);
    assert!(std::ptr::eq(Aligner::pick(&short, &long, h), &long));
    assert!(std::ptr::eq(Aligner::pick(&long, &short, h), &long));
    // Equal sigmas (the same references): the VN-200's stays.
    let twin = host_clock(0, 10_000);
    assert!(std::ptr::eq(Aligner::pick(&short, &twin, h), &short));
    // A VN-200 model that never had a reference: the TT-Multi-RF's, whatever its state.
    let none = HostClock::new(HostClockConfig::default());
    assert!(std::ptr::eq(Aligner::pick(&none, &long, h), &long));
}

/// A TT-Multi-RF JSON message sent at GPS time `t` with `ts` = the UTC ms of day of GPS time
/// `ts_of` (UTC midnight at G0 + 10 s, and whole days from it): 200 bytes at 921 600 baud, first
/// byte at `t`, read 1 ms (the VN-200's link delay) after the last.
fn json_at(t: i64, ts_of: i64) -> (Sample, Rx) {
    let midnight = G0 + 10 * S;
    let json = JsonMessage {
        ts_ms: Some(((ts_of - midnight).rem_euclid(86_400 * S) / MS) as u32),
        ..Default::default()
    };
    let rx = Rx {
        host_ns: t + OFF + tx_ns(200, 921_600) + MS,
        wire_len: 200,
        reads: None,
    };
    (
        Sample::TtText(Box::new(TextMessage::Json(Box::new(json)))),
        rx,
    )
}

/// The TT-Multi-RF output of handling `(s, rx)`.
fn tt_out(al: &mut Aligner, (s, rx): (Sample, Rx)) -> Result<AlignedTime, NotAligned> {
    al.handle(s, rx)
        .into_iter()
        .find(|o| o.device == Device::Ttmrf)
        .unwrap()
        .aligned
        .time
}

#[test]
fn a_ttmrf_ts_a_second_off_is_reported_counted_and_replaced_by_the_host_clock() {
    let mut al = locked_on_vn200();
    assert!(al.clock_disagreements().is_empty());
    assert_eq!(al.ttmrf_times_disagreeing(), 0);
    // `ts` names the instant 1 s later than the message was sent: far beyond the 5-sigma +
    // 20 ms tolerance of the cross-check.
    let t = G0 + 9_500 * MS;
    let a = tt_out(&mut al, json_at(t, t + S)).unwrap();
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
    assert_eq!(al.ttmrf_times_disagreeing(), 1);
    // Placed by the host clock instead, at its instant (the host clock's 1 ms link is the
    // port's; exact but for rounding).
    assert_eq!(a.source, TimeSource::HostClock);
    assert!((a.t_gps_ns - t).abs() < 100_000, "{}", a.t_gps_ns - t);
    // A right `ts` clears the report; the count stays.
    let t = G0 + 9_600 * MS;
    let a = tt_out(&mut al, json_at(t, t)).unwrap();
    assert_eq!(a.source, TimeSource::UtcTimeOfDay);
    assert!(al.clock_disagreements().is_empty());
    assert_eq!(al.ttmrf_times_disagreeing(), 1);
}

#[test]
fn only_a_locked_ttmrf_time_of_day_teaches_the_second_host_clock() {
    // 500 days after G0 (2027-10-14), past the leap-second table's end (2027-07-01): a JSON `ts`
    // is placed, but coasting (a leap second may have been announced since), and is no
    // reference.
    let g1 = G0 + 500 * 86_400 * S;
    let mut al = Aligner::new(AlignerConfig::default());
    for k in 0..400 {
        let (s, rx) = vn200(g1 + k * 25 * MS);
        al.handle(s, rx);
    }
    let t = g1 + 9_500 * MS;
    let a = tt_out(&mut al, json_at(t, t)).unwrap();
    assert_eq!(
        (a.source, a.status),
        (TimeSource::UtcTimeOfDay, ClockStatus::Coasting)
    );
    assert_eq!(al.tt_host_clock().last_reference_host_ns(), None);
    // Host-timed TT output (a JSON without `ts`) and Watson lines are no references either.
    let mut al = locked_on_vn200();
    let (_, rx) = json_at(G0 + 9_300 * MS, G0);
    let s = Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    assert_eq!(
        tt_out(&mut al, (s, rx)).unwrap().source,
        TimeSource::HostClock
    );
    watson_time(&mut al, watson_rx(G0 + 9_400 * MS));
    assert_eq!(al.tt_host_clock().last_reference_host_ns(), None);
    // Locked: the host time its first byte left (200 bytes at 921 600 baud before the read, no
    // output delay assumed).
    let t = G0 + 9_500 * MS;
    let (s, rx) = json_at(t, t);
    assert_eq!(
        tt_out(&mut al, (s, rx)).unwrap().status,
        ClockStatus::Locked
    );
    assert_eq!(
        al.tt_host_clock().last_reference_host_ns(),
        Some(rx.host_ns - tx_ns(200, 921_600))
    );
}

#[test]
fn the_vn200_pps_times_are_kept_for_the_bahrs_pulses() {
    let mut al = Aligner::new(AlignerConfig::default());
    assert!(al.vn200_pps().nearest(G0 + OFF).is_none());
    // Sampled 0.5 s after a whole GPS second: its last PPS was that second.
    let g = G0 + 500 * MS;
    let (s, rx) = vn200_pps(g, 0b110);
    al.handle(s, rx);
    let r = al.vn200_pps().nearest(rx.host_ns).unwrap();
    assert_eq!((r.t_gps_ns, r.pps_gps_ns), (g, G0));
}

#[test]
fn a_bahrs_sample_left_unpaired_comes_out_when_another_device_moves_host_time_on() {
    let mut al = Aligner::new(AlignerConfig::default());
    let data = Sample::Bahrs(bahrs::Message::Inertial(Inertial {
        seq: 7,
        specific_force_raw: [0; 3],
        angular_rate_raw: [0; 3],
        health: InertialHealth(0),
    }));
    let h0 = G0 + OFF;
    assert!(
        al.handle(
            data,
            Rx {
                host_ns: h0,
                wire_len: 28,
                reads: None
            }
        )
        .is_empty()
    );
    // Its 0x05 never comes; the pairing hold is 0.5 s. A Watson line 1 s later (itself held for
    // the host clock) releases it, marked.
    let out = al.handle(
        watson(),
        Rx {
            host_ns: h0 + S,
            wire_len: 64,
            reads: None,
        },
    );
    assert_eq!(out.len(), 1, "{out:?}");
    assert_eq!((out[0].device, out[0].index), (Device::Bahrs, 0));
    assert!(out[0].aligned.time.is_err());
}

#[test]
fn a_ttmrf_ts_is_checked_with_the_coasting_host_clocks_grown_sigma() {
    // A host clock whose rate is known to 100 ppm only: 60 s after its last VN-200 reference
    // (G0 + 10 s) its view has grown a 6 ms sigma.
    let cfg = AlignerConfig {
        host: HostClockConfig {
            rate_sigma_ppm: 100.0,
            ..HostClockConfig::default()
        },
        ..AlignerConfig::default()
    };
    let mut al = Aligner::new(cfg);
    for k in 0..400 {
        let (s, rx) = vn200(G0 + k * 25 * MS);
        al.handle(s, rx);
    }
    // Tolerance (cross_check's rule): 5 * sqrt(s_dev^2 + s_host^2) + 20 ms, with s_dev the ms
    // stamp's 0.433 ms and s_host = sqrt(6^2 + 0.5^2 (reference delay) + 0.5^2 (the port's
    // output delay) + ~0) ms = 6.04 ms: 5 * 6.06 + 20 = 50.3 ms. A `ts` 35 ms late agrees
    // (without the host's sigma it would not: 5 * 0.8 + 20 = 24 ms).
    let t = G0 + 70 * S;
    let a = tt_out(&mut al, json_at(t, t + 35 * MS)).unwrap();
    assert_eq!(a.source, TimeSource::UtcTimeOfDay);
    assert!(al.clock_disagreements().is_empty());
    // 60 ms late does not.
    let t = G0 + 70_100 * MS;
    let a = tt_out(&mut al, json_at(t, t + 60 * MS)).unwrap();
    assert_eq!(a.source, TimeSource::HostClock);
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
}

#[test]
fn a_ttmrf_ts_is_checked_with_the_ports_output_delay_sigma() {
    // A TT-Multi-RF port whose output delay is known to 10 ms (1 sigma) only.
    let mut cfg = AlignerConfig::default();
    cfg.ttmrf.link.output_delay_sigma_ns = 10e6;
    let mut al = Aligner::new(cfg);
    for k in 0..400 {
        let (s, rx) = vn200(G0 + k * 25 * MS);
        al.handle(s, rx);
    }
    // Tolerance: 5 * sqrt(0.433^2 (the ms stamp) + s_host^2) + 20 ms, where the host view's
    // sigma carries the port's 10 ms and the locked host clock's ~0.5 ms:
    // 5 * sqrt(0.19 + 100 + 0.25) + 20 = 70.1 ms. A `ts` 60 ms late agrees (without the port's
    // sigma: 5 * 0.7 + 20 = 23.5 ms, it would not); 80 ms late does not.
    let t = G0 + 9_500 * MS;
    let a = tt_out(&mut al, json_at(t, t + 60 * MS)).unwrap();
    assert_eq!(a.source, TimeSource::UtcTimeOfDay);
    assert!(al.clock_disagreements().is_empty());
    let t = G0 + 9_600 * MS;
    let a = tt_out(&mut al, json_at(t, t + 80 * MS)).unwrap();
    assert_eq!(a.source, TimeSource::HostClock);
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
}

#[test]
fn a_watson_line_waits_for_the_host_clock_at_most_host_wait_ns() {
    let mut al = Aligner::new(AlignerConfig::default());
    let rx = |h: i64| Rx {
        host_ns: h,
        wire_len: 64,
        reads: None,
    };
    let h0 = G0 + OFF;
    // No clock: each line waits; the first is released, marked, once it waited longer than
    // `host_wait_ns` (3 s), not at 3 s exactly.
    assert!(al.handle(watson(), rx(h0)).is_empty());
    assert!(al.handle(watson(), rx(h0 + 2_900 * MS)).is_empty());
    assert!(al.handle(watson(), rx(h0 + 3 * S)).is_empty());
    let out = al.handle(watson(), rx(h0 + 3_500 * MS));
    let released: Vec<(u64, _)> = out.iter().map(|o| (o.index, o.aligned.time)).collect();
    assert_eq!(released, vec![(0, Err(NotAligned::HostClockUnknown))]);
}

#[test]
fn the_bahrs_clock_report_follows_the_latest_mcu_time_of_any_timed_message() {
    use vigil_drivers::bahrs::{Accuracy, SyncPulseTime};
    let (mut al, _) = pulses_near_vn200(None);
    // The MCU clock of `pulses_near_vn200`: 3 s at G0, 20 ppm fast. At G0 + x its offset from
    // GPS is 3e9 - G0 + x * 20e-6 ns.
    let ticks = |gps: i64| 3_000_000 + ((gps - G0) as f64 * (1.0 + 20e-6) / 1000.0) as u64;
    let offset_at = |x_s: f64| 3e9 - G0 as f64 + x_s * 1e9 * 20e-6;
    let report = |al: &Aligner| {
        al.clock_report(G0 + 30 * S + OFF)
            .into_iter()
            .find(|r| r.device == Device::Bahrs)
            .unwrap()
            .offset_ns
            .unwrap()
    };
    let rx = |gps: i64| Rx {
        host_ns: gps + OFF + 2 * MS,
        wire_len: 20,
        reads: None,
    };
    // A 0x03 sampled at G0 + 25 s: 500 us.
    let g = G0 + 25 * S;
    let acc = Accuracy {
        seq: 0,
        std_north_raw: 1,
        std_east_raw: 1,
        std_heading_raw: 1,
        mcu_time_us: ticks(g),
    };
    al.handle(Sample::Bahrs(bahrs::Message::Accuracy(acc)), rx(g));
    assert!((report(&al) - offset_at(25.0)).abs() < 5_000.0);
    // A 0x06 of the pulse at G0 + 26 s: 520 us.
    let g = G0 + 26 * S;
    let p = SyncPulseTime {
        seq: 26,
        mcu_time_us: ticks(g),
    };
    al.handle(Sample::Bahrs(bahrs::Message::SyncPulseTime(p)), rx(g));
    assert!((report(&al) - offset_at(26.0)).abs() < 5_000.0);
    // An invalid 0x05 (data sequence and time 0) carries no MCU time: the report stays.
    let invalid = DataTime {
        seq: 1,
        data_seq: 0,
        mcu_time_us: 0,
    };
    al.handle(
        Sample::Bahrs(bahrs::Message::InertialTime(invalid)),
        rx(g + 10 * MS),
    );
    assert!((report(&al) - offset_at(26.0)).abs() < 5_000.0);
}

/// A TT-Multi-RF whose output exceeds its line by 10 % from G0 + 8.1 s: 200-byte JSON messages
/// back to back (one every 2.17 ms at 921 600 baud), each waiting in the module's queue, which
/// grows by a tenth of the time elapsed up to 40 ms (its buffer), so a `ts` precedes its
/// sending by that much. The line reads as full once 100 ms hold 80 % of what it carries
/// (7 373 bytes: the 37th message, 78 ms in), when the queue is 8 ms, inside the cross-check's
/// margin; the 884 messages from there on are counted as on a full line.
#[test]
fn a_busy_ttmrf_line_is_no_reference_and_its_queue_is_no_disagreement() {
    let mut al = locked_on_vn200();
    // A right `ts` on a quiet line teaches the TT's host clock.
    let t = G0 + 8_000 * MS;
    tt_out(&mut al, json_at(t, t)).unwrap();
    assert!(al.tt_host_clock().last_reference_host_ns().is_some());
    assert!(!al.ttmrf_line_busy());
    assert_eq!(al.lines_full(json_at(t, t).1.host_ns).count(), 0);
    let (mut last, start) = (None, G0 + 8_100 * MS);
    for k in 0..921 {
        let t = start + k * tx_ns(200, 921_600);
        let queue = ((t - start) / 10).min(40 * MS);
        last = Some((t, tt_out(&mut al, json_at(t, t - queue)).unwrap()));
    }
    assert!(al.ttmrf_line_busy());
    // The integrity report's view, judged at its own time: the line carried its capacity
    // (200 bytes every 2.17 ms) for 2 s up to the last message at `h`. 100 ms later the last
    // 500 ms still hold 80 % of what the line carries: full; 150 ms later even the whole
    // 640 ms of history hold under 80 % (490 of 640 ms): not full.
    let h = json_at(last.unwrap().0, 0).1.host_ns;
    assert!(al.lines_full(h).eq([Device::Ttmrf]));
    assert!(al.lines_full(h + 100 * MS).eq([Device::Ttmrf]));
    assert_eq!(al.lines_full(h + 150 * MS).count(), 0);
    let busy = al.ttmrf_busy_messages();
    assert!((882..=886).contains(&busy), "{busy}");
    // The TT's host clock was dropped when the line became busy and learned nothing since.
    assert_eq!(al.tt_host_clock().last_reference_host_ns(), None);
    // 40 ms early is a queue, not a disagreement: the `ts` stands (the whole ms at or before
    // the instant it names, plus the 0.25 ms mid-point).
    assert!(al.clock_disagreements().is_empty());
    assert_eq!(al.ttmrf_times_disagreeing(), 0);
    let (t, a) = last.unwrap();
    assert_eq!(a.source, TimeSource::UtcTimeOfDay);
    let e = a.t_gps_ns - (t - 40 * MS);
    assert!((-750_000..=250_000).contains(&e), "{e}");
    // A host-timed message on the busy line: its wait of 0 ..= 0.5 s taken as uniform, 250 ms
    // earlier than on a quiet line, sigma at least 0.5 s / sqrt(12) = 144.3 ms.
    let t = G0 + 10_100 * MS;
    let (_, rx) = json_at(t, t);
    let no_ts = || Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    let busy = tt_out(&mut al, (no_ts(), rx)).unwrap();
    let quiet = tt_out(&mut locked_on_vn200(), (no_ts(), rx)).unwrap();
    assert_eq!(busy.source, TimeSource::HostClock);
    assert!(
        (quiet.t_gps_ns - busy.t_gps_ns - 250 * MS).abs() <= 1,
        "{busy:?} {quiet:?}"
    );
    assert!(busy.sigma_ns >= 144_337_000.0, "{}", busy.sigma_ns);
    assert!(
        (busy.sigma_ns.powi(2) - quiet.sigma_ns.powi(2) - (500e6f64).powi(2) / 12.0).abs() < 1e6,
        "{} {}",
        busy.sigma_ns,
        quiet.sigma_ns
    );
    // One-sided: a `ts` 30 ms after it was sent (nothing arrives before it is made) and a `ts`
    // a second early still disagree.
    let t = G0 + 10_102 * MS;
    assert_eq!(
        tt_out(&mut al, json_at(t, t + 30 * MS)).unwrap().source,
        TimeSource::HostClock
    );
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
    let t = G0 + 10_104 * MS;
    tt_out(&mut al, json_at(t, t)).unwrap();
    assert!(al.clock_disagreements().is_empty());
    // A second early on the full line: a queue longer than the 0.5 s limit or a wrong clock,
    // which the host cannot tell apart, so neither places it, nor a message without a time
    // of its own after it (its wait is unknown).
    let t = G0 + 10_106 * MS;
    assert_eq!(
        tt_out(&mut al, json_at(t, t - S)),
        Err(NotAligned::LineFull)
    );
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
    let at = |t: i64| json_at(t, t).1;
    assert_eq!(
        tt_out(&mut al, (no_ts(), at(G0 + 10_108 * MS))),
        Err(NotAligned::LineFull)
    );
    // 0.4 s early is inside the limit: the `ts` stands, and the line's host-timed messages are
    // placed again.
    let t = G0 + 10_110 * MS;
    let a = tt_out(&mut al, json_at(t, t - 400 * MS)).unwrap();
    assert_eq!(a.source, TimeSource::UtcTimeOfDay);
    assert!(al.clock_disagreements().is_empty());
    let a = tt_out(&mut al, (no_ts(), at(G0 + 10_112 * MS))).unwrap();
    assert_eq!(a.source, TimeSource::HostClock);
    // A second early once more, then the line empties (nothing for a second: the next message
    // finds the last 640 ms empty): its messages are placed again, by the host clock.
    let t = G0 + 10_114 * MS;
    assert_eq!(
        tt_out(&mut al, json_at(t, t - S)),
        Err(NotAligned::LineFull)
    );
    let t = G0 + 11_200 * MS;
    let a = tt_out(&mut al, (no_ts(), at(t))).unwrap();
    assert!(!al.ttmrf_line_busy());
    assert_eq!(a.source, TimeSource::HostClock);
    // A `ts` a second early on a quiet line is a plain disagreement: host-timed.
    let t = G0 + 11_202 * MS;
    assert_eq!(
        tt_out(&mut al, json_at(t, t - S)).unwrap().source,
        TimeSource::HostClock
    );
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
}

/// The TT's host clock and a line that fills: an aligner fed a VN-200 at 40 Hz and, from G0,
/// one right JSON `ts` every 100 ms (2 kB/s: a quiet line), which lock the TT's host clock;
/// then JSON messages back to back (200 bytes every 2.17 ms) only until the line first reads
/// as full, then quiet again. The TT's host clock is dropped at that first full message (the
/// references just before may have been queued), learns nothing while the line is full, and
/// learns again once it is quiet.
#[test]
fn the_tt_host_clock_is_dropped_when_the_line_fills_and_learns_again_when_it_empties() {
    let mut al = Aligner::new(AlignerConfig::default());
    let mut vn_next = G0;
    let mut feed_vn_until = |al: &mut Aligner, t: i64| {
        while vn_next <= t {
            let (s, rx) = vn200(vn_next);
            al.handle(s, rx);
            vn_next += 25 * MS;
        }
    };
    for k in 0..80 {
        let t = G0 + k * 100 * MS;
        feed_vn_until(&mut al, t);
        // The first ones wait for a host clock (they come out later): not looked at.
        let (s, rx) = json_at(t, t);
        al.handle(s, rx);
    }
    let h = G0 + 7_900 * MS + OFF;
    assert_eq!(al.tt_host_clock().status(h), ClockStatus::Locked);
    assert!(!al.ttmrf_line_busy());
    assert_eq!(al.ttmrf_busy_messages(), 0);
    // Back to back until the line reads as full (the 37th message, by hand: see the test
    // above), then stop.
    let start = G0 + 8_000 * MS;
    let mut k = 0;
    while !al.ttmrf_line_busy() {
        let t = start + k * tx_ns(200, 921_600);
        feed_vn_until(&mut al, t);
        tt_out(&mut al, json_at(t, t)).unwrap();
        k += 1;
        assert!(k < 100, "the line never read as full");
    }
    assert_eq!(al.ttmrf_busy_messages(), 1);
    assert_eq!(al.tt_host_clock().last_reference_host_ns(), None);
    // Quiet again from 1 s later: the line no longer reads as full, and each right `ts`
    // teaches the TT's host clock again.
    let t = start + 1_000 * MS;
    feed_vn_until(&mut al, t);
    let (s, rx) = json_at(t, t);
    tt_out(&mut al, (s, rx)).unwrap();
    assert!(!al.ttmrf_line_busy());
    assert_eq!(al.ttmrf_busy_messages(), 1);
    assert_eq!(
        al.tt_host_clock().last_reference_host_ns(),
        Some(rx.host_ns - tx_ns(200, 921_600))
    );
}

/// A TT-Multi-RF line with no time of its own (CSV, HEXd without TS24h) sending all its line
/// carries, 200-byte messages back to back at 921 600 baud from G0 + 8 s. A message's
/// wait is bounded by how long the line has been full (a [`LineLoad`] fed the same messages
/// is the oracle, its own tests by hand), and the host-timed sigma covers a wait up to the
/// 0.5 s limit: so every message is placed while that span is 500 ms or less (exactly 500 ms
/// included: the bound then equals the limit) and not aligned after (`LineFull`). About 400 ms
/// in, by hand: back-to-back output over `E` ms covers a span of up to `E / 0.8` ms at the 80 %
/// threshold. A `ts` that agrees bounds the wait again, for the limit less its own wait and
/// the cross-check's tolerance; the line's emptying ends it all.
#[test]
fn a_full_line_without_times_of_its_own_is_not_aligned_once_its_wait_may_pass_the_limit() {
    let mut al = locked_on_vn200();
    let mut oracle = LineLoad::default();
    let no_ts = || Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    let at = |t: i64| json_at(t, t).1;
    let start = G0 + 8_000 * MS;
    let step = tx_ns(200, 921_600);
    let (mut first_full, mut placed_at_500) = (None, 0);
    let mut k = 0;
    let mut t = start;
    while t < start + 700 * MS {
        let rx = at(t);
        oracle.add(rx.host_ns, rx.wire_len);
        let full = oracle.full_for_ns(rx.host_ns, 921_600);
        let got = tt_out(&mut al, (no_ts(), rx));
        if full > 500 * MS {
            assert_eq!(got, Err(NotAligned::LineFull), "at {} ms", (t - start) / MS);
            first_full.get_or_insert(t - start);
        } else {
            let a = got.unwrap();
            assert_eq!(a.source, TimeSource::HostClock);
            placed_at_500 += usize::from(full == 500 * MS);
        }
        k += 1;
        t = start + k * step;
    }
    assert!(placed_at_500 > 0, "no message saw a span of exactly 500 ms");
    let first = first_full.unwrap();
    assert!((395 * MS..=415 * MS).contains(&first), "{first}");
    // A `ts` 40 ms early agrees (the line has been full: a queue) and bounds the wait: for the
    // limit less those 40 ms and the tolerance (20 ms unknown link and 5 sigmas of about 1 ms).
    let t = start + k * step;
    let e = (json_at(t, t - 40 * MS).1).host_ns;
    let a = tt_out(&mut al, json_at(t, t - 40 * MS)).unwrap();
    assert_eq!(a.source, TimeSource::UtcTimeOfDay);
    let until = al.tt_queue_bounded_until_ns;
    assert!(
        (e + 500 * MS - 40 * MS - 30 * MS..=e + 500 * MS - 40 * MS - 20 * MS).contains(&until),
        "{} ms",
        (until - e) / MS
    );
    // The line stays full; host-timed messages are placed up to that bound, exactly at it
    // included, and not aligned 1 ns after it.
    k += 1;
    while start + k * step < until - OFF - step - MS {
        let t = start + k * step;
        assert_eq!(
            tt_out(&mut al, (no_ts(), at(t))).unwrap().source,
            TimeSource::HostClock
        );
        k += 1;
    }
    let on_bound = Rx {
        host_ns: until,
        ..at(t)
    };
    assert_eq!(
        tt_out(&mut al, (no_ts(), on_bound)).unwrap().source,
        TimeSource::HostClock
    );
    let past = Rx {
        host_ns: until + 1,
        ..at(t)
    };
    assert_eq!(tt_out(&mut al, (no_ts(), past)), Err(NotAligned::LineFull));
    // After a second of silence the line is empty and its messages are placed again.
    let t = start + 2_200 * MS;
    assert_eq!(
        tt_out(&mut al, (no_ts(), at(t))).unwrap().source,
        TimeSource::HostClock
    );
    assert!(!al.ttmrf_line_busy());
}

/// As above with the module's transmit buffer stated: 4096 bytes, 4096 x 10 / 921 600 s =
/// 44 444 444 ns of line time (by hand). A message waited at most that however long the line
/// has been full, so every message of the 700 ms is placed (none `LineFull`), with its wait
/// of 0 ..= min(its bound, 44.4 ms) taken as uniform: once the line has been busy for 44.4 ms
/// or more, 22 222 222 ns earlier than the same message on a quiet line, and sigma^2 larger by
/// (44 444 444 ns)^2 / 12. Its bound is the longer of the time full and the line time of the
/// messages before it, all sent back to back here (by hand: `k` of them for message `k`). A `ts` 100 ms early is more than that buffer allows (plus the
/// cross-check's 20-odd ms tolerance): the statement is contradicted, so that message and the
/// host-timed ones after it are not aligned until a time of its own agrees again.
#[test]
fn a_stated_transmit_buffer_bounds_a_full_lines_wait_and_keeps_it_placed() {
    let w: i64 = 44_444_444;
    assert_eq!(tx_ns(4096, 921_600), w);
    let mut al = locked_on_vn200();
    al.set_ttmrf_output_buffer(Some(4096));
    let mut oracle = LineLoad::default();
    let no_ts = || Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    let at = |t: i64| json_at(t, t).1;
    let start = G0 + 8_000 * MS;
    let step = tx_ns(200, 921_600);
    let (mut bounded, mut k) = (0, 0);
    while k * step < 700 * MS {
        let rx = at(start + k * step);
        oracle.add(rx.host_ns, rx.wire_len);
        let full = oracle.full_for_ns(rx.host_ns, 921_600);
        let busy = tt_out(&mut al, (no_ts(), rx)).unwrap();
        assert_eq!(busy.source, TimeSource::HostClock);
        let quiet = tt_out(&mut locked_on_vn200(), (no_ts(), rx)).unwrap();
        // The line time of the `k + 1` messages less this one's own (not `k * step`: each
        // rounds down alone).
        let run = tx_ns((k as usize + 1) * 200, 921_600) - step;
        let wait = full.max(run).min(w);
        assert!(
            (quiet.t_gps_ns - busy.t_gps_ns - wait / 2).abs() <= 1,
            "{k}: {busy:?} {quiet:?}"
        );
        let added = busy.sigma_ns.powi(2) - quiet.sigma_ns.powi(2);
        assert!(
            (added - (wait as f64).powi(2) / 12.0).abs() < 1e3,
            "{k}: {added}"
        );
        bounded += usize::from(full > w);
        k += 1;
    }
    assert!(al.ttmrf_line_busy());
    assert!(bounded > 250, "{bounded} of {k}");
    // 30 ms early is within the buffer's 44.4 ms: a queue, the `ts` stands.
    let t = start + k * step;
    assert_eq!(
        tt_out(&mut al, json_at(t, t - 30 * MS)).unwrap().source,
        TimeSource::UtcTimeOfDay
    );
    assert!(al.clock_disagreements().is_empty());
    // 100 ms early is not: not aligned, and neither is the next message without a time.
    let t = start + (k + 1) * step;
    assert_eq!(
        tt_out(&mut al, json_at(t, t - 100 * MS)),
        Err(NotAligned::LineFull)
    );
    assert_eq!(al.clock_disagreements(), vec![Device::Ttmrf]);
    let t = start + (k + 2) * step;
    assert_eq!(tt_out(&mut al, (no_ts(), at(t))), Err(NotAligned::LineFull));
    // A buffer whose line time passes the limit bounds nothing the limit does not: 65 536
    // bytes at 921 600 baud are 711 ms, so the line behaves as with no buffer stated (the
    // test above: not aligned from about 400 ms in).
    let mut al = locked_on_vn200();
    al.set_ttmrf_output_buffer(Some(65_536));
    let mut k = 0;
    let mut first_not = None;
    while k * step < 700 * MS {
        if tt_out(&mut al, (no_ts(), at(start + k * step))).is_err() {
            first_not.get_or_insert(k * step);
        }
        k += 1;
    }
    let first = first_not.expect("a 711 ms buffer bounds nothing within the limit");
    assert!((395 * MS..=415 * MS).contains(&first), "{first}");
}

/// A TT-Multi-RF message that waits for the host clock is placed with the wait its line
/// allowed at its arrival, not with the line's state when the clock locks. JSON messages
/// without `ts` back to back at 921 600 baud for 300 ms from G0 - 1.5 s (the line reads as
/// full from about 80 ms in), then one more 1.2 s later on a quiet line: all wait, since the
/// host clock is known only from the VN-200's first messages at G0. When they are placed (as
/// soon as it is: `Locking`), the last of the burst carries the wait its line allowed then (a
/// [`LineLoad`] fed the same messages is the oracle), uniform: its variance exceeds the quiet
/// one's by that wait squared over 12. Before,
/// it was placed as the line stood when the clock became known (quiet): no wait, the quiet
/// sigma of 0.7 ms for a message that may have waited 375 ms.
#[test]
fn a_held_ttmrf_message_keeps_the_wait_its_line_allowed_at_its_arrival() {
    let mut al = Aligner::new(AlignerConfig::default());
    let mut oracle = LineLoad::default();
    let no_ts = || Sample::TtText(Box::new(TextMessage::Json(Box::default())));
    let mut out = Vec::new();
    let mut vn_next = G0;
    let mut feed_vn_until = |al: &mut Aligner, t: i64, out: &mut Vec<AlignedSample>| {
        while vn_next <= t {
            let (s, rx) = vn200(vn_next);
            out.extend(al.handle(s, rx));
            vn_next += 25 * MS;
        }
    };
    let (start, step) = (G0 - 1_500 * MS, tx_ns(200, 921_600));
    let (mut k, mut wait) = (0, 0);
    while k * step < 300 * MS {
        let t = start + k * step;
        feed_vn_until(&mut al, t, &mut out);
        let rx = json_at(t, t).1;
        oracle.add(rx.host_ns, rx.wire_len);
        wait = oracle.full_for_ns(rx.host_ns, 921_600).min(500 * MS);
        out.extend(al.handle(no_ts(), rx));
        k += 1;
    }
    assert!(wait >= 250 * MS, "{wait}");
    let quiet_rx = json_at(start + 1_500 * MS, 0).1;
    feed_vn_until(&mut al, start + 1_500 * MS, &mut out);
    out.extend(al.handle(no_ts(), quiet_rx));
    assert!(!al.ttmrf_line_busy());
    // The TT-Multi-RF output of index `i` (the burst is 0 .. k - 1, the quiet one k).
    let tt = |out: &[AlignedSample], i: u64| {
        out.iter()
            .find(|o| o.device == Device::Ttmrf && o.index == i)
            .map(|o| o.aligned.time)
    };
    // Nothing placed yet: the host clock is not known.
    let k = k as u64;
    assert_eq!(tt(&out, k - 1), None);
    feed_vn_until(&mut al, G0 + 10 * S, &mut out);
    let busy = tt(&out, k - 1).unwrap().unwrap();
    let quiet = tt(&out, k).unwrap().unwrap();
    assert_eq!(busy.source, TimeSource::HostClock);
    let extra = busy.sigma_ns.powi(2) - quiet.sigma_ns.powi(2);
    let want = (wait as f64).powi(2) / 12.0;
    assert!(
        (extra - want).abs() < 0.01 * want,
        "{} {} {wait}",
        busy.sigma_ns,
        quiet.sigma_ns
    );
}
