//! TT-Multi-RF model tests: the port decoded with the drivers' decoders, against the truth and
//! hand-computed values.

use vigil_drivers::decode_slice;
use vigil_drivers::modes::decoder::ModesMessage;
use vigil_drivers::modes::{ModesDecoder, TrackerConfig};
use vigil_drivers::ttmrf::at::AtResponse;
use vigil_drivers::ttmrf::text::{TextDecoder, TextMessage, TextMode};

use super::super::scripted_host::ScriptedHost;
use super::*;
use crate::Simulator;
use crate::engine::MemorySink;
use crate::scenario::builtin;
use crate::truth::TruthRecord;

fn run(
    s: &crate::Scenario,
    ns: i64,
    script: Vec<(usize, Vec<u8>)>,
) -> (MemorySink, Vec<u8>, Vec<TruthRecord>) {
    let mut sim = Simulator::new(s, 3).unwrap();
    let mut host = ScriptedHost::new("ttmrf", script);
    sim.run(ns, &mut host).unwrap();
    let port = host.port;
    let sink = host.inner;
    let bytes = sink
        .chunks
        .iter()
        .filter(|c| c.port == port)
        .flat_map(|c| c.bytes.clone())
        .collect();
    let truth = sink
        .truth
        .iter()
        .filter(|r| r.device == "ttmrf")
        .cloned()
        .collect();
    (sink, bytes, truth)
}

#[test]
fn emitter_category_and_time_of_day() {
    assert_eq!(ecat_number("A3"), Some(3));
    assert_eq!(ecat_number("B1"), Some(9));
    assert_eq!(ecat_number("B6"), Some(14));
    assert_eq!(ecat_number(""), None);
    assert_eq!(ecat_number("A8"), None);
    // 2026-06-01T10:00:00Z = GPS 10:00:18 of that day: 36 000 000 ms since UTC midnight.
    let t = crate::units::parse_utc_to_gps_ns("2026-06-01T10:00:00Z").unwrap();
    assert_eq!(utc_ms_of_day(t), 36_000_000);
    assert_eq!(utc_ms_of_day(t + 1_234_000_000), 36_001_234);
}

#[test]
fn json_traffic_once_per_second_per_intruder_with_gnss() {
    let s = builtin("nominal").unwrap();
    let (_, bytes, truth) = run(&s, 3_000_000_000, Vec::new());
    let msgs = decode_slice(&mut TextDecoder::new(TextMode::Auto), &bytes);
    let json: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            TextMessage::Json(j) => Some(j),
            _ => None,
        })
        .collect();
    let traffic: Vec<_> = truth
        .iter()
        .filter(|r| matches!(r.kind, "adsb" | "uat" | "flarm" | "gnss"))
        .collect();
    // 5 intruders + GNSS per second, 3 s (the GNSS of the start second is at the start itself).
    assert!((17..=18).contains(&traffic.len()), "{}", traffic.len());
    assert_eq!(json.len(), traffic.len());
    let start = crate::units::parse_utc_to_gps_ns("2026-06-01T10:00:00Z").unwrap();
    for (m, r) in json.iter().zip(&traffic) {
        assert_eq!(m.to_wire().as_bytes(), r.wire.as_slice());
        // ts = ms since UTC midnight (10:00:00 UTC = 36 000 000 ms).
        assert_eq!(
            i64::from(m.ts_ms.unwrap()),
            36_000_000 + (r.t_gps_ns - start) / 1_000_000
        );
        if let Some(a) = m.adsb.first() {
            let alt = r.values["alt_pressure_m"].as_f64().unwrap() / 0.3048;
            assert!((a.alt_baro_ft.unwrap() - alt).abs() <= 0.5);
            assert_eq!((a.nic, a.nac_p), (Some(8), Some(9)));
            let lat = r.values["lat_deg"].as_f64().unwrap();
            assert!((a.lat_deg.unwrap() - lat).abs() < 1e-6);
        }
        if let Some(g) = &m.gnss {
            assert_eq!(g.fix, Some(1));
            let dn =
                (g.lat_deg.unwrap() - r.values["lat_deg"].as_f64().unwrap()).to_radians() * 6.37e6;
            assert!(dn.abs() < 6.0 * GNSS_H_SIGMA_M, "{dn}");
        }
    }
    // Intruder 0 of 5 reports at 1000 / 6 = 166 ms into each second.
    let first = truth.iter().find(|r| r.kind == "adsb").unwrap();
    assert_eq!(first.t_gps_ns.rem_euclid(NS_PER_S), 166 * MS);
}

#[test]
fn raw_hex_frames_decode_to_the_reported_positions() {
    let mut s = builtin("spoofed-target").unwrap();
    // The scenario starts spoofing at 60 s; from the start here.
    s.intruders[0].spoof_from_s = 0.0;
    let (_, bytes, truth) = run(&s, 4_000_000_000, Vec::new());
    let raw: Vec<_> = truth
        .iter()
        .filter(|r| r.kind.starts_with("raw_"))
        .collect();
    // Two ADS-B targets, 4.2 frames per second each, over about 4 s.
    assert!(raw.len() >= 28, "{}", raw.len());
    let mut dec = ModesDecoder::hex(TrackerConfig::default(), Default::default());
    let out = decode_slice(&mut dec, &bytes);
    let modes: Vec<_> = out
        .iter()
        .filter_map(|m| match m {
            ModesMessage::ModeS(o) => Some(o),
            _ => None,
        })
        .collect();
    assert_eq!(modes.len(), raw.len());
    let mut positions = 0;
    for (o, r) in modes.iter().zip(&raw) {
        // TS24h of the frame = ns since UTC midnight of its truth time.
        assert_eq!(o.frame.meta.ts_utc_ns, r.values["ts_utc_ns"].as_u64());
        if let Some(p) = &o.position {
            positions += 1;
            // The spoofed target reports 2 km north and east of its true position: the frames
            // carry the reported one (CPR airborne resolution about 5 m).
            let dn =
                (p.lat_deg - r.values["reported_lat_deg"].as_f64().unwrap()).to_radians() * 6.37e6;
            assert!(dn.abs() < 10.0, "{dn}");
            let spoof = r.values["reported_lat_deg"].as_f64().unwrap()
                - r.values["lat_deg"].as_f64().unwrap();
            let is_spoofed = r.values["address"] == "4B1B01";
            assert_eq!(spoof.abs() > 0.01, is_spoofed);
        }
    }
    assert!(positions >= 10, "{positions}");
}

#[test]
fn configuration_state_stops_run_output_and_at_lines_are_answered() {
    let s = builtin("headon").unwrap();
    // 0.5 s: enter CONFIGURATION; 2.0 s: back to RUN.
    let script = vec![
        (5, b"AT+CONFIG=1\r\n".to_vec()),
        (20, b"AT+CONFIG=0\r\n".to_vec()),
    ];
    let (sink, bytes, truth) = run(&s, 3_000_000_000, script);
    let start = sink.info.unwrap().start_gps_ns;
    let at: Vec<_> = truth.iter().filter(|r| r.kind == "at").collect();
    assert!(at.len() >= 4, "{at:?}");
    // No RUN output while in CONFIGURATION (0.501 .. 2.001 s).
    for r in truth.iter().filter(|r| r.kind != "at") {
        let dt = r.t_gps_ns - start;
        assert!(!(501 * MS..2001 * MS).contains(&dt), "{} at {dt}", r.kind);
    }
    let msgs = decode_slice(&mut TextDecoder::new(TextMode::Auto), &bytes);
    let at_msgs: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            TextMessage::At(a) => Some(a),
            _ => None,
        })
        .collect();
    assert_eq!(at_msgs.len(), at.len());
    assert!(at_msgs.iter().any(|a| matches!(a, AtResponse::Ok)));
    assert!(
        at_msgs
            .iter()
            .any(|a| matches!(a, AtResponse::State { .. }))
    );
}

#[test]
fn gnss_outage_reports_no_fix() {
    let s = builtin("gnss-outage").unwrap();
    let (_, _, truth) = run(&s, 62_000_000_000, Vec::new());
    let g: Vec<_> = truth.iter().filter(|r| r.kind == "gnss").collect();
    assert!(g.len() >= 62);
    for r in &g {
        let lost = r.values["fix"] == false;
        let wire = String::from_utf8_lossy(&r.wire);
        assert_eq!(wire.contains("\"fix\":0"), lost, "{wire}");
    }
    assert!(g.iter().filter(|r| r.values["fix"] == false).count() >= 2);
}

#[test]
fn csv_protocol_sends_the_manual_lines_with_pressure_altitude() {
    let mut s = builtin("nominal").unwrap();
    s.devices.ttmrf.as_mut().unwrap().protocol = "csv".into();
    s.devices.ttmrf.as_mut().unwrap().raw = "off".into();
    let (_, bytes, truth) = run(&s, 3_000_000_000, Vec::new());
    let msgs = decode_slice(&mut TextDecoder::new(TextMode::Auto), &bytes);
    // 5 intruders per second and GGA + RMC at whole seconds.
    assert!((20..=21).contains(&truth.len()), "{}", truth.len());
    assert_eq!(msgs.len(), truth.len());
    for (m, r) in msgs.iter().zip(&truth) {
        if let TextMessage::Nmea(n) = m {
            assert_eq!(n.to_line().as_bytes(), r.wire.as_slice());
            assert!(r.kind.starts_with("nmea_"));
            continue;
        }
        let TextMessage::Csv(c) = m else {
            panic!("{m:?}")
        };
        assert_eq!(c.to_line().as_bytes(), r.wire.as_slice());
        let rep = &m.traffic_reports()[0];
        assert_eq!(rep.address_hex(), r.values["address"].as_str().unwrap());
        if r.kind != "flarm" {
            // ISA pressure altitude in whole feet.
            let alt = r.values["alt_pressure_m"].as_f64().unwrap();
            assert!((rep.alt_pressure_m.unwrap() - alt).abs() <= 0.5 * 0.3048 + 1e-9);
        }
    }
    assert!(truth.iter().any(|r| r.kind == "uat"));
    assert!(truth.iter().any(|r| r.kind == "flarm"));
    // The start, 2026-06-01T10:00:00Z, at 47.40 N: GGA time 100000.00, latitude 47 deg 24.000'
    // (within noise: 4724.0 +- 0.01'), RMC date 010626.
    let gga = String::from_utf8(truth[0].wire.clone()).unwrap();
    assert!(gga.starts_with("$GPGGA,100000.00,472"), "{gga}");
    let rmc = String::from_utf8(truth[1].wire.clone()).unwrap();
    assert!(rmc.starts_with("$GPRMC,100000.00,A,472"), "{rmc}");
    assert!(rmc.contains(",010626,"), "{rmc}");
}

#[path = "ttmrf_binary_tests.rs"]
mod binary;

#[path = "ttmrf_at_tests.rs"]
mod at_switch;

#[test]
fn unknown_protocols_and_raw_with_binary_are_refused_by_name() {
    let mut s = builtin("nominal").unwrap();
    s.devices.ttmrf.as_mut().unwrap().protocol = "adsc".into();
    let e = Simulator::new(&s, 1).err().unwrap().to_string();
    assert!(e.contains("devices.ttmrf.protocol"), "{e}");
    // nominal has raw = "hex": not with a binary protocol.
    let mut s = builtin("nominal").unwrap();
    s.devices.ttmrf.as_mut().unwrap().protocol = "gdl90".into();
    let e = Simulator::new(&s, 1).err().unwrap().to_string();
    assert!(e.contains("devices.ttmrf.raw"), "{e}");
    s.devices.ttmrf.as_mut().unwrap().raw = "off".into();
    assert!(Simulator::new(&s, 1).is_ok());
    let mut s = builtin("nominal").unwrap();
    s.devices.ttmrf.as_mut().unwrap().raw = "avr".into();
    let e = Simulator::new(&s, 1).err().unwrap().to_string();
    assert!(e.contains("devices.ttmrf.raw"), "{e}");
}
