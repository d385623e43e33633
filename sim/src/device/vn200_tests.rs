//! VN-200 model tests: decoded with the driver's decoder, compared with truth and hand values.

use vigil_drivers::decode_slice;
use vigil_drivers::vn200::ascii::{AsciiMessage, ErrorCode, RegisterValue};
use vigil_drivers::vn200::status::InsMode;
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};

use super::super::scripted_host::ScriptedHost;
use super::*;
use crate::Simulator;
use crate::engine::MemorySink;
use crate::scenario::builtin;

fn run(name: &str, ns: i64, script: Vec<(usize, Vec<u8>)>) -> (MemorySink, Vec<Vn200Message>) {
    run_scenario(&builtin(name).unwrap(), ns, script)
}

fn run_scenario(
    s: &crate::Scenario,
    ns: i64,
    script: Vec<(usize, Vec<u8>)>,
) -> (MemorySink, Vec<Vn200Message>) {
    let mut sim = Simulator::new(s, 7).unwrap();
    let mut host = ScriptedHost::new("vn200", script);
    sim.run(ns, &mut host).unwrap();
    let sink = host.inner;
    let port = sink
        .info
        .as_ref()
        .unwrap()
        .ports
        .iter()
        .position(|p| p.device == "vn200")
        .unwrap() as u16;
    let bytes: Vec<u8> = sink
        .chunks
        .iter()
        .filter(|c| c.port == port)
        .flat_map(|c| c.bytes.clone())
        .collect();
    let msgs = decode_slice(&mut Vn200Decoder::new(), &bytes);
    (sink, msgs)
}

#[test]
fn default_output_is_200_hz_on_whole_5_ms_with_exact_gps_time() {
    let (sink, msgs) = run("nominal", 2_000_000_000, Vec::new());
    let truth: Vec<_> = sink.truth.iter().filter(|r| r.device == "vn200").collect();
    // 200 Hz for 2 s: samples at start + 5 ms .. start + 2 s (the last may be cut by the end).
    assert!((398..=400).contains(&truth.len()), "{}", truth.len());
    assert_eq!(msgs.len(), truth.len());
    for (m, r) in msgs.iter().zip(&truth) {
        let Vn200Message::Binary(b) = m else {
            panic!("{m:?}")
        };
        let c = b.common.as_ref().unwrap();
        assert_eq!(c.time_gps_ns, Some(r.t_gps_ns as u64));
        assert_eq!(r.t_gps_ns % 5_000_000, 0);
        assert_eq!(c.time_gps_pps_ns, Some((r.t_gps_ns % 1_000_000_000) as u64));
        assert_eq!(c.ins_status.unwrap().mode(), InsMode::Tracking);
        assert_eq!(b.time.as_ref().unwrap().time_status.unwrap().0, 0b111);
        // Noise within 6 sigma of what the message reports.
        let u = b.attitude.as_ref().unwrap().ypr_u.unwrap();
        let ypr = c.ypr.unwrap();
        let wrap = |d: f64| (d + 180.0).rem_euclid(360.0) - 180.0;
        let yaw_err =
            wrap(f64::from(ypr.yaw_deg) - r.values["yaw_rad"].as_f64().unwrap().to_degrees());
        assert!(yaw_err.abs() < 6.0 * f64::from(u.yaw_deg), "{yaw_err}");
        let roll_err =
            f64::from(ypr.roll_deg) - r.values["roll_rad"].as_f64().unwrap().to_degrees();
        assert!(
            roll_err.abs() < 6.0 * f64::from(u.roll_deg) + 1e-4,
            "{roll_err}"
        );
        let pos_u = f64::from(b.ins.as_ref().unwrap().pos_u_m.unwrap());
        let lla = c.pos_lla.unwrap();
        let dn = (lla.lat_deg - r.values["lat_deg"].as_f64().unwrap()).to_radians() * 6.37e6;
        assert!(dn.abs() < 6.0 * pos_u, "{dn}");
        // The quaternion is the (noisy) Euler angles' own: x, y, z, w of 3-2-1.
        let q = c.quaternion.unwrap();
        let e = crate::truth::quat_xyzw(
            f64::from(ypr.yaw_deg).to_radians(),
            f64::from(ypr.pitch_deg).to_radians(),
            f64::from(ypr.roll_deg).to_radians(),
        );
        for (a, b) in [q.x, q.y, q.z, q.s].iter().zip(e) {
            assert!((f64::from(*a) - b).abs() < 1e-5);
        }
    }
}

#[test]
fn gnss_outage_gives_gnss_lost_and_invalid_time() {
    let (sink, msgs) = run("gnss-outage", 62_000_000_000, Vec::new());
    let truth: Vec<_> = sink.truth.iter().filter(|r| r.device == "vn200").collect();
    assert_eq!(msgs.len(), truth.len());
    let start = sink.info.unwrap().start_gps_ns;
    let mut lost = 0;
    for (m, r) in msgs.iter().zip(&truth) {
        let Vn200Message::Binary(b) = m else { panic!() };
        let st = b.common.as_ref().unwrap().ins_status.unwrap();
        let ts = b.time.as_ref().unwrap().time_status.unwrap();
        let inside = r.t_gps_ns - start >= 60_000_000_000;
        assert_eq!(st.mode() == InsMode::GnssLost, inside);
        assert!(st.attitude_valid());
        assert_eq!(st.position_valid(), !inside);
        assert_eq!(ts.tow_valid(), !inside);
        lost += usize::from(inside);
    }
    assert!(lost >= 399, "{lost}");
}

/// Issue 25: an INS reset at 1 s with 1.5 s of aligning: mode 0 over [1, 2) s, 1 over [2, 3.5) s,
/// Tracking before and after (the ICD's "holds INS Status Mode at 0 for 1 second"); the GNSS fix
/// bit stays set and the output keeps its rate.
#[test]
fn ins_reset_holds_not_tracking_for_1_s_then_aligning() {
    let mut s = builtin("nominal").unwrap();
    s.faults = vec![crate::scenario::Fault::InsReset {
        at_s: 1.0,
        aligning_s: 1.5,
    }];
    let (sink, msgs) = run_scenario(&s, 4_500_000_000, Vec::new());
    let truth: Vec<_> = sink.truth.iter().filter(|r| r.device == "vn200").collect();
    assert_eq!(msgs.len(), truth.len());
    assert!(msgs.len() >= 4 * 200, "{}", msgs.len());
    let start = sink.info.unwrap().start_gps_ns;
    let mut seen = [0usize; 3];
    for (m, r) in msgs.iter().zip(&truth) {
        let Vn200Message::Binary(b) = m else { panic!() };
        let st = b.common.as_ref().unwrap().ins_status.unwrap();
        let t_s = (r.t_gps_ns - start) as f64 * 1e-9;
        let want = if (1.0..2.0).contains(&t_s) {
            InsMode::NotTracking
        } else if (2.0..3.5).contains(&t_s) {
            InsMode::Aligning
        } else {
            InsMode::Tracking
        };
        assert_eq!(st.mode(), want, "at {t_s} s");
        assert!(st.gnss_fix());
        seen[match want {
            InsMode::NotTracking => 0,
            InsMode::Aligning => 1,
            _ => 2,
        }] += 1;
    }
    // 200 Hz: 200 samples in NotTracking, 300 aligning.
    assert!(
        (199..=201).contains(&seen[0]) && (299..=301).contains(&seen[1]),
        "{seen:?}"
    );
}

#[test]
fn ascii_commands_are_answered_and_register_75_changes_the_output() {
    // Window 2 (0.2 s): read 75, a bad checksum, an unknown command, an unmodelled register.
    // Window 5 (0.5 s): write 75 = 40 Hz (divisor 20), Common TimeGps (bit 1) + Ypr (bit 3) = 0x000A.
    let write = b"$VNWRG,75,1,20,01,000A*XX\r\n".to_vec();
    let script = vec![
        (2, b"$VNRRG,75*XX\r\n".to_vec()),
        (2, b"$VNRRG,75*00\r\n".to_vec()),
        (2, b"$VNXYZ*XX\r\n".to_vec()),
        (2, b"$VNRRG,200*XX\r\n".to_vec()),
        (5, write),
        (5, b"$VNRRG,75*XX\r\n".to_vec()),
    ];
    let (sink, msgs) = run("headon", 1_500_000_000, script);
    let ascii: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            Vn200Message::Ascii(a) => Some(a.clone()),
            _ => None,
        })
        .collect();
    assert_eq!(ascii.len(), 6, "{ascii:?}");
    let AsciiMessage::ReadResponse {
        value: RegisterValue::BinaryOutput { index: 1, config },
    } = &ascii[0]
    else {
        panic!("{:?}", ascii[0])
    };
    assert_eq!((config.async_mode, config.rate_divisor), (1, 4));
    assert_eq!(config.masks().unwrap(), default_masks());
    assert_eq!(
        ascii[1],
        AsciiMessage::Error {
            code: ErrorCode::InvalidChecksum
        }
    );
    assert_eq!(
        ascii[2],
        AsciiMessage::Error {
            code: ErrorCode::InvalidCommand
        }
    );
    assert_eq!(
        ascii[3],
        AsciiMessage::Error {
            code: ErrorCode::InvalidRegister
        }
    );
    // The echo of the write carries the new contents; the read after it returns them.
    let AsciiMessage::Command {
        command: Command::WriteRegister(v),
    } = &ascii[4]
    else {
        panic!("{:?}", ascii[4])
    };
    assert_eq!(v.body(), "75,1,20,01,000A");
    let AsciiMessage::ReadResponse { value } = &ascii[5] else {
        panic!()
    };
    assert_eq!(value.body(), "75,1,20,01,000A");
    // The echo's checksum: XOR of "VNWRG,75,1,20,01,000A".
    let wire = sink
        .truth
        .iter()
        .find(|r| r.device == "vn200" && r.kind == "ascii" && r.wire.starts_with(b"$VNWRG"))
        .unwrap();
    let cs = b"VNWRG,75,1,20,01,000A".iter().fold(0u8, |a, b| a ^ b);
    assert_eq!(
        wire.wire,
        format!("$VNWRG,75,1,20,01,000A*{cs:02X}\r\n").into_bytes()
    );
    // After the write (at 0.5 s + 1 ms), binary messages carry only TimeGps and Ypr at 40 Hz.
    let after: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            Vn200Message::Binary(b) if b.time.is_none() => Some(b),
            _ => None,
        })
        .collect();
    assert!((39..=41).contains(&after.len()), "{}", after.len());
    for b in &after {
        let c = b.common.as_ref().unwrap();
        assert!(c.ypr.is_some() && c.quaternion.is_none() && b.ins.is_none());
        assert_eq!(c.time_gps_ns.unwrap() % 25_000_000, 0);
    }
}

#[test]
fn unsupported_configuration_is_refused() {
    // Group IMU (0x04) is not produced by the model.
    let script = vec![(1, b"$VNWRG,75,1,4,04,0001*XX\r\n".to_vec())];
    let (_, msgs) = run("headon", 300_000_000, script);
    assert!(msgs.iter().any(|m| matches!(
        m,
        Vn200Message::Ascii(AsciiMessage::Error {
            code: ErrorCode::InvalidParameter
        })
    )));
}

#[test]
fn reset_command_echoes_then_output_resumes_after_boot_and_vnbom_polls() {
    // 0.3 s: VNBOM,1 (one binary message answered, 1 ms later); 0.5 s: VNRST.
    let script = vec![
        (3, b"$VNBOM,1*XX\r\n".to_vec()),
        (5, b"$VNRST*XX\r\n".to_vec()),
    ];
    let (sink, msgs) = run("headon", 2_000_000_000, script);
    let start = sink.info.as_ref().unwrap().start_gps_ns;
    let truth: Vec<_> = sink.truth.iter().filter(|r| r.device == "vn200").collect();
    assert_eq!(msgs.len(), truth.len());
    let polled: Vec<_> = truth
        .iter()
        .filter(|r| r.values.contains_key("polled"))
        .collect();
    assert_eq!(polled.len(), 1);
    assert_eq!(polled[0].t_gps_ns - start, 300_000_000);
    let echo = truth.iter().find(|r| r.kind == "ascii").unwrap();
    // XOR of "VNRST": 0x56^0x4E = 0x18, ^0x52 = 0x4A, ^0x53 = 0x19, ^0x54 = 0x4D.
    assert_eq!(echo.wire, b"$VNRST*4D\r\n");
    // No output from the reset (0.501 s) until the boot ends (1.501 s).
    let dts: Vec<i64> = truth
        .iter()
        .filter(|r| r.kind == "binary_output" && !r.values.contains_key("polled"))
        .map(|r| r.t_gps_ns - start)
        .collect();
    assert!(
        dts.iter()
            .all(|d| !(501_000_000..1_501_000_000).contains(d))
    );
    assert!(dts.iter().any(|d| *d >= 1_501_000_000));
    assert!(dts.iter().any(|d| *d <= 500_000_000));
}

#[test]
fn runs_at_400_hz_and_refuses_a_baud_too_slow_for_the_rate() {
    let mut s = builtin("headon").unwrap();
    s.devices.vn200.as_mut().unwrap().rate_hz = 400.0;
    let mut sim = Simulator::new(&s, 1).unwrap();
    let mut sink = MemorySink::default();
    sim.run(1_000_000_000, &mut sink).unwrap();
    let t: Vec<_> = sink.truth.iter().filter(|r| r.device == "vn200").collect();
    // Divisor 2: a message every 2.5 ms, none lost on the 921 600 baud link.
    assert!((399..=400).contains(&t.len()), "{}", t.len());
    assert!(
        t.iter()
            .all(|r| r.t_gps_ns % 2_500_000 == 0 && !r.corrupted)
    );
    // 139 bytes at 400 Hz = 55 600 bytes/s > 115 200 baud / 10.
    s.devices.vn200.as_mut().unwrap().baud = 115_200;
    let e = Simulator::new(&s, 1).err().unwrap().to_string();
    assert!(e.contains("devices.vn200.baud"), "{e}");
}
