//! The model's binary decoded protocols (MAVLink, GDL90, ASTERIX) on the port, decoded by the
//! drivers' decoders and checked against the truth: same messages at the truth's offsets,
//! byte-identical when re-encoded, values within the fields' resolution.

use bytes::BytesMut;
use tokio_util::codec::Encoder;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::ttmrf::asterix::{AsterixDecoder, AsterixMessage};
use vigil_drivers::ttmrf::gdl90::{self, Gdl90Decoder, Gdl90Message, TrafficAltitude};
use vigil_drivers::ttmrf::mavlink::{MavlinkDecoder, MavlinkEncoder, MavlinkMessage};

use super::*;

fn scenario(protocol: &str) -> crate::Scenario {
    let mut s = builtin("nominal").unwrap();
    let t = s.devices.ttmrf.as_mut().unwrap();
    t.protocol = protocol.into();
    t.raw = "off".into();
    s
}

fn located<D: DeviceDecoder>(mut d: D, bytes: &[u8]) -> (Vec<(u64, D::Message)>, u64) {
    let mut buf = BytesMut::from(bytes);
    let mut out = Vec::new();
    while let Some(m) = d.decode(&mut buf) {
        out.push((d.stats().last_frame_start, m));
    }
    while let Some(m) = d.decode_eof(&mut buf) {
        out.push((d.stats().last_frame_start, m));
    }
    (out, d.stats().bytes_skipped)
}

/// Every decoded message is the truth record at the same offset, byte for byte.
fn same_as_truth(decoded: &[(u64, Vec<u8>)], truth: &[TruthRecord]) {
    assert_eq!(decoded.len(), truth.len());
    for ((o, wire), r) in decoded.iter().zip(truth) {
        assert_eq!(*o, r.rx_offset, "{} {}", r.kind, r.index);
        assert_eq!(wire, &r.wire, "{} {}", r.kind, r.index);
    }
}

fn count(truth: &[TruthRecord], kind: &str) -> usize {
    truth.iter().filter(|r| r.kind == kind).count()
}

fn f(r: &TruthRecord, key: &str) -> f64 {
    r.values[key].as_f64().unwrap()
}

#[test]
fn mavlink_sends_one_adsb_vehicle_per_target_per_second() {
    let (sink, bytes, truth) = run(&scenario("mavlink"), 3_000_000_000, Vec::new());
    assert_eq!(
        sink.info.as_ref().unwrap().ports[3].protocol,
        "ttmrf-mavlink"
    );
    let (msgs, skipped) = located(MavlinkDecoder::new(), &bytes);
    assert_eq!(skipped, 0);
    let wires: Vec<_> = msgs
        .iter()
        .map(|(o, m)| {
            let mut b = BytesMut::new();
            MavlinkEncoder.encode(m.clone(), &mut b).unwrap();
            (*o, b.to_vec())
        })
        .collect();
    same_as_truth(&wires, &truth);
    // 3 ADS-B, 1 UAT, 1 FLARM target, 3 s: 15 reports (the last may fall past the end).
    assert!((14..=15).contains(&truth.len()), "{}", truth.len());
    assert_eq!(
        count(&truth, "adsb") + count(&truth, "uat") + count(&truth, "flarm"),
        truth.len()
    );
    for (i, ((_, m), r)) in msgs.iter().zip(&truth).enumerate() {
        let MavlinkMessage::AdsbVehicle { frame, vehicle } = m else {
            panic!("{m:?}")
        };
        // One sequence counter for the port.
        assert_eq!(usize::from(frame.sequence), i);
        assert_eq!(format!("{:06X}", vehicle.icao_address), r.values["address"]);
        // Position rounded to 1e-6 deg (as the text protocols), sent in 1e-7 steps.
        assert!((vehicle.lat_deg - f(r, "reported_lat_deg")).abs() < 1e-9);
        let (alt, ty) = if r.kind == "flarm" {
            (f(r, "reported_height_m"), 1)
        } else {
            (f(r, "alt_pressure_m"), 0)
        };
        // Millimetre resolution.
        assert!((vehicle.altitude_m - alt).abs() <= 0.0005, "{r:?}");
        assert_eq!(vehicle.altitude_type, ty);
        let [vn, ve, vd] = [0, 1, 2].map(|k| r.values["vel_ned_mps"][k].as_f64().unwrap());
        assert!((vehicle.hor_velocity_mps - vn.hypot(ve)).abs() <= 0.005);
        assert!((vehicle.ver_velocity_mps + vd).abs() <= 0.005);
    }
}

#[test]
fn gdl90_sends_adsb_traffic_and_the_ownship_once_per_second() {
    let (sink, bytes, truth) = run(&scenario("gdl90"), 3_000_000_000, Vec::new());
    let start = sink.info.unwrap().start_gps_ns;
    let (msgs, skipped) = located(Gdl90Decoder::new(TrafficAltitude::Pressure), &bytes);
    assert_eq!(skipped, 0);
    let wires: Vec<_> = msgs
        .iter()
        .map(|(o, m)| {
            let mut b = Vec::new();
            gdl90::encode_frame(m, &mut b);
            (*o, b)
        })
        .collect();
    same_as_truth(&wires, &truth);
    // No FLARM (manual) and no UAT target; 3 ADS-B targets per second.
    assert_eq!(count(&truth, "flarm") + count(&truth, "uat"), 0);
    assert!((8..=9).contains(&count(&truth, "adsb")));
    for k in [
        "gdl90_heartbeat",
        "gdl90_ownship",
        "gdl90_ownship_geo_altitude",
    ] {
        assert!((3..=4).contains(&count(&truth, k)), "{k}");
    }
    for ((_, m), r) in msgs.iter().zip(&truth) {
        match m {
            Gdl90Message::Heartbeat(h) => {
                // 10:00:00 UTC = 36 000 s of day at the start.
                let s = 36_000 + (r.t_gps_ns - start) / 1_000_000_000;
                assert_eq!(i64::from(h.timestamp_s), s);
                assert!(h.gps_pos_valid && h.utc_ok);
            }
            Gdl90Message::OwnshipReport(o) => {
                let dn = (o.lat_deg - f(r, "lat_deg")).to_radians() * 6.37e6;
                assert!(dn.abs() < 6.0 * GNSS_H_SIGMA_M + 2.5, "{dn}");
                assert_eq!((o.nic, o.nac_p), (8, 9));
            }
            Gdl90Message::OwnshipGeoAltitude(g) => {
                let ft = f(r, "height_m") / 0.3048;
                assert!((f64::from(g.geo_altitude_ft) - ft).abs() < 6.0 * 4.0 / 0.3048 + 2.5);
            }
            Gdl90Message::TrafficReport(t) => {
                // Pressure altitude in 25 ft steps.
                let ft = f(r, "alt_pressure_m") / 0.3048;
                assert!((f64::from(t.altitude_ft.unwrap()) - ft).abs() <= 12.5);
                assert_eq!(format!("{:06X}", t.address), r.values["address"]);
            }
        }
    }
}

#[test]
fn asterix_sends_cat021_per_target_and_cat023_per_second() {
    let (_, bytes, truth) = run(&scenario("asterix"), 3_000_000_000, Vec::new());
    let (msgs, skipped) = located(AsterixDecoder::default(), &bytes);
    assert_eq!(skipped, 0);
    let wires: Vec<_> = msgs
        .iter()
        .map(|(o, m)| {
            let mut b = Vec::new();
            m.encode_block(&mut b);
            (*o, b)
        })
        .collect();
    same_as_truth(&wires, &truth);
    assert_eq!(count(&truth, "uat"), 0);
    assert!((8..=9).contains(&count(&truth, "adsb")));
    assert!((2..=3).contains(&count(&truth, "flarm")));
    assert!((3..=4).contains(&count(&truth, "asterix_status")));
    for ((_, m), r) in msgs.iter().zip(&truth) {
        match m {
            AsterixMessage::Cat021(c) => {
                let src = c.data_source.unwrap();
                // FLARM: SAC 0 / SIC 161 (manual 8.2.1); ADS-B: the module's settings (SAC
                // 0, SIC 129 by default, table 13).
                assert_eq!(
                    (src.sac, src.sic),
                    if r.kind == "flarm" {
                        (0, 161)
                    } else {
                        (0, 129)
                    }
                );
                // Time of applicability = UTC of the report, 1/128 s.
                let tod = f64::from(utc_ms_of_day(r.t_gps_ns)) / 1000.0;
                let t = c.time_applicability_position_s.unwrap();
                assert!((t - tod).abs() <= 1.0 / 256.0, "{t} {tod}");
                let p = c.position_high_res.unwrap();
                assert!((p.lat_deg - f(r, "reported_lat_deg")).abs() < 1e-6);
                if r.kind == "adsb" {
                    // FL in 1/4 FL steps: 12.5 ft.
                    let fl = f(r, "alt_pressure_m") / 0.3048 / 100.0;
                    assert!((c.flight_level.unwrap() - fl).abs() <= 0.125);
                } else {
                    assert_eq!(c.flight_level, None);
                }
            }
            AsterixMessage::Cat023(s) => {
                assert_eq!(r.kind, "asterix_status");
                assert_eq!(s.report_type, Some(1));
            }
        }
    }
}

#[test]
fn gdl90_ownship_has_no_position_during_a_gnss_outage() {
    let mut s = builtin("gnss-outage").unwrap();
    let t = s.devices.ttmrf.as_mut().unwrap();
    t.protocol = "gdl90".into();
    t.raw = "off".into();
    let (_, bytes, truth) = run(&s, 62_000_000_000, Vec::new());
    let (msgs, _) = located(Gdl90Decoder::default(), &bytes);
    let mut lost = 0;
    for ((_, m), r) in msgs.iter().zip(&truth) {
        if let Gdl90Message::Heartbeat(h) = m {
            let fix = r.values["fix"] == true;
            assert_eq!(h.gps_pos_valid, fix);
            lost += usize::from(!fix);
        }
        if let Gdl90Message::OwnshipReport(o) = m {
            assert_eq!(o.has_position(), r.values["fix"] == true);
        }
    }
    assert!(lost >= 2, "{lost}");
}
