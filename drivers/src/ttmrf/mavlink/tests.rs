//! MAVLink decoder tests: hand-packed frames checked with an independent X.25 checksum,
//! MAVLink 1 and 2, signing, the COLLISION pairing, corruption, truncation, garbage, every
//! split point, random input and encode/decode round trips.

use proptest::prelude::*;

use super::adsb_vehicle::*;
use super::*;
use crate::testkit::{
    XorShift, assert_accounting, assert_split_invariant, assert_survives_random, decode_chunked,
    flip_bits,
};
use crate::traffic::{AddressType, Link, Protocol};

/// X.25 / MCRF4XX checksum as the MAVLink serialisation guide writes `crc_accumulate`, written
/// here independently of the crate.
fn x25(bytes: &[u8]) -> u16 {
    let mut crc: u16 = 0xFFFF;
    for &b in bytes {
        let mut tmp = b ^ (crc & 0xFF) as u8;
        tmp ^= tmp << 4;
        let t = u16::from(tmp);
        crc = (crc >> 8) ^ (t << 8) ^ (t << 3) ^ (t >> 4);
    }
    crc
}

/// CRC_EXTRA of ADSB_VEHICLE and COLLISION from the MAVLink common.xml definitions.
const EXTRA_ADSB_VEHICLE: u8 = 184;
const EXTRA_COLLISION: u8 = 81;

/// ADSB_VEHICLE payload packed by hand (fields ordered by size, little-endian):
/// ICAO_address 0x00AB4549 | lat 449070668 (44.9070668 deg) | lon -1229948616
/// (-122.9948616 deg) | altitude 1524000 mm (5000 ft) | heading 4500 cdeg | hor_velocity
/// 6328 cm/s | ver_velocity -508 cm/s (-1000 ft/min) | flags 0x01BF (coords, altitude, heading,
/// velocity, callsign, squawk, vertical velocity, baro valid) | squawk 7700 (0x1E14) |
/// altitude_type 0 | callsign "N825V" + 4 NUL | emitter_type 1 (light) | tslc 2.
const VEHICLE_PAYLOAD: [u8; 38] = [
    0x49, 0x45, 0xAB, 0x00, 0x4C, 0x46, 0xC4, 0x1A, 0x38, 0x79, 0xB0, 0xB6, 0x20, 0x41, 0x17, 0x00,
    0x94, 0x11, 0xB8, 0x18, 0x04, 0xFE, 0xBF, 0x01, 0x14, 0x1E, 0x00, b'N', b'8', b'2', b'5', b'V',
    0, 0, 0, 0, 0x01, 0x02,
];

/// COLLISION payload: id 0x00DD1234 | time_to_minimum_delta 12.5 s (0x41480000) |
/// altitude_minimum_delta -30 m (0xC1F00000) | horizontal_minimum_delta 250 m (0x437A0000) |
/// src 0 (ADS-B) | action 1 (report) | threat_level 2 (high).
const COLLISION_PAYLOAD: [u8; 19] = [
    0x34, 0x12, 0xDD, 0x00, 0x00, 0x00, 0x48, 0x41, 0x00, 0x00, 0xF0, 0xC1, 0x00, 0x00, 0x7A, 0x43,
    0x00, 0x01, 0x02,
];

fn v1_frame(seq: u8, msgid: u8, payload: &[u8], extra: u8) -> Vec<u8> {
    let mut f = vec![0xFE, payload.len() as u8, seq, 1, 156, msgid];
    f.extend_from_slice(payload);
    let mut crc_in = f[1..].to_vec();
    crc_in.push(extra);
    f.extend_from_slice(&x25(&crc_in).to_le_bytes());
    f
}

fn v2_frame(incompat: u8, seq: u8, msgid: u32, payload: &[u8], extra: u8) -> Vec<u8> {
    let id = msgid.to_le_bytes();
    let mut f = vec![
        0xFD,
        payload.len() as u8,
        incompat,
        0,
        seq,
        1,
        156,
        id[0],
        id[1],
        id[2],
    ];
    f.extend_from_slice(payload);
    let mut crc_in = f[1..].to_vec();
    crc_in.push(extra);
    f.extend_from_slice(&x25(&crc_in).to_le_bytes());
    if incompat & 1 != 0 {
        f.extend_from_slice(&[0xA5; 13]);
    }
    f
}

fn decode_all(bytes: &[u8]) -> (Vec<MavlinkMessage>, DecodeStats) {
    decode_chunked(MavlinkDecoder::new(), bytes, &[bytes.len().max(1)])
}

fn expected_vehicle() -> AdsbVehicle {
    AdsbVehicle {
        icao_address: 0xAB4549,
        lat_deg: 44.907_066_8,
        lon_deg: -122.994_861_6,
        altitude_m: 1524.0,
        altitude_type: 0,
        heading_deg: 45.0,
        hor_velocity_mps: 63.28,
        ver_velocity_mps: -5.08,
        flags: 0x01BF,
        squawk: 7700,
        callsign: "N825V".to_string(),
        emitter_type: 1,
        tslc_s: 2,
    }
}

#[test]
fn x25_reference_value() {
    // The CRC-16/MCRF4XX check value of "123456789" is 0x6F91.
    assert_eq!(x25(b"123456789"), 0x6F91);
}

#[test]
fn hand_packed_v1_adsb_vehicle() {
    let frame = v1_frame(5, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE);
    assert_eq!(frame.len(), 8 + 38);
    let (msgs, stats) = decode_all(&frame);
    assert_eq!(stats.frames_decoded, 1);
    assert_eq!(stats.bytes_skipped, 0);
    let MavlinkMessage::AdsbVehicle {
        frame: info,
        vehicle,
    } = &msgs[0]
    else {
        panic!("{msgs:?}")
    };
    assert_eq!(
        *info,
        FrameInfo {
            version: 1,
            sequence: 5,
            system_id: 1,
            component_id: 156,
            signed: false
        }
    );
    assert_eq!(*vehicle, expected_vehicle());
    // The crate's encoder produces the same bytes.
    let mut out = Vec::new();
    encode_adsb_vehicle(info, vehicle, &mut out);
    assert_eq!(out, frame);

    let t = msgs[0].to_traffic().unwrap();
    assert_eq!(t.protocol, Protocol::Mavlink);
    assert_eq!(t.link, Link::Adsb1090);
    assert_eq!(t.address_hex(), "AB4549");
    assert_eq!(t.address_type, AddressType::Unknown);
    assert_eq!(t.callsign.as_deref(), Some("N825V"));
    assert_eq!(t.squawk, Some(7700));
    assert_eq!(t.emitter_category, Some(1));
    assert!((t.lat_deg.unwrap() - 44.907_066_8).abs() < 1e-9);
    assert!((t.lon_deg.unwrap() + 122.994_861_6).abs() < 1e-9);
    assert!((t.alt_pressure_m.unwrap() - 1524.0).abs() < 1e-9);
    assert_eq!(t.alt_geometric_m, None);
    assert!((t.track_deg.unwrap() - 45.0).abs() < 1e-9);
    assert!((t.ground_speed_mps.unwrap() - 63.28).abs() < 1e-9);
    assert!((t.vertical_rate_mps.unwrap() + 5.08).abs() < 1e-9);
    assert!(!t.flags.test);
    // tslc 2 s: the position's age.
    assert_eq!(t.data_age_s, Some(2.0));
}

#[test]
fn hand_packed_v2_and_signed() {
    let frame = v2_frame(0, 9, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE);
    let (msgs, _) = decode_all(&frame);
    let MavlinkMessage::AdsbVehicle {
        frame: info,
        vehicle,
    } = &msgs[0]
    else {
        panic!()
    };
    assert_eq!((info.version, info.sequence, info.signed), (2, 9, false));
    assert_eq!(*vehicle, expected_vehicle());
    let mut out = Vec::new();
    encode_adsb_vehicle(info, vehicle, &mut out);
    assert_eq!(out, frame);
    // Signed: incompat flag 0x01 (inside the checksum) and 13 signature bytes after it.
    let signed = v2_frame(1, 9, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE);
    assert_eq!(signed.len(), frame.len() + 13);
    let (msgs, stats) = decode_all(&signed);
    assert_eq!(msgs.len(), 1);
    assert!(msgs[0].frame().signed);
    assert_eq!(stats.bytes_consumed, signed.len() as u64);
    assert_eq!(stats.bytes_skipped, 0);
    // MAVLink 2 payload truncation: with tslc = 0 and emitter_type = 0 the sender drops every
    // trailing zero, the callsign's four NULs included: 38 - 6 = 32 bytes.
    let mut p = VEHICLE_PAYLOAD;
    p[36] = 0;
    p[37] = 0;
    let short = v2_frame(0, 1, 246, &p[..32], EXTRA_ADSB_VEHICLE);
    let (msgs, _) = decode_all(&short);
    let MavlinkMessage::AdsbVehicle { vehicle, .. } = &msgs[0] else {
        panic!()
    };
    assert_eq!((vehicle.emitter_type, vehicle.tslc_s), (0, 0));
    let mut out = Vec::new();
    encode_adsb_vehicle(&msgs[0].frame(), vehicle, &mut out);
    assert_eq!(out, short);
}

#[test]
fn collision_pairs_with_the_preceding_vehicle() {
    let mut flarm_vehicle = VEHICLE_PAYLOAD;
    flarm_vehicle[..4].copy_from_slice(&0x00DD_1234u32.to_le_bytes());
    let mut bytes = v2_frame(0, 1, 246, &flarm_vehicle, EXTRA_ADSB_VEHICLE);
    bytes.extend(v2_frame(0, 2, 247, &COLLISION_PAYLOAD, EXTRA_COLLISION));
    // A COLLISION after a vehicle of another id, and one after nothing.
    bytes.extend(v1_frame(3, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE));
    bytes.extend(v1_frame(4, 247, &COLLISION_PAYLOAD, EXTRA_COLLISION));
    bytes.extend(v1_frame(5, 247, &COLLISION_PAYLOAD, EXTRA_COLLISION));
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs.len(), 5);
    assert_eq!(stats.bytes_skipped, 0);
    let MavlinkMessage::Collision {
        collision, target, ..
    } = &msgs[1]
    else {
        panic!()
    };
    assert_eq!(
        *collision,
        Collision {
            src: 0,
            id: 0xDD1234,
            action: 1,
            threat_level: 2,
            time_to_minimum_delta_s: 12.5,
            altitude_minimum_delta_m: -30.0,
            horizontal_minimum_delta_m: 250.0,
        }
    );
    assert_eq!(target.as_ref().map(|v| v.icao_address), Some(0xDD1234));
    assert!(msgs[1].to_traffic().is_none());
    assert!(matches!(
        &msgs[3],
        MavlinkMessage::Collision { target: None, .. }
    ));
    assert!(matches!(
        &msgs[4],
        MavlinkMessage::Collision { target: None, .. }
    ));
    // Encoders reproduce the hand-packed frames.
    let mut out = Vec::new();
    encode_collision(&msgs[3].frame(), collision, &mut out);
    assert_eq!(out, v1_frame(4, 247, &COLLISION_PAYLOAD, EXTRA_COLLISION));
    assert_split_invariant(MavlinkDecoder::new, &bytes);
}

#[test]
fn tokio_encoder_reproduces_the_stream() {
    use tokio_util::codec::Encoder;
    let bytes = sample_stream();
    let (msgs, _) = decode_all(&bytes);
    let mut dst = BytesMut::new();
    for m in msgs {
        MavlinkEncoder.encode(m, &mut dst).unwrap();
    }
    assert_eq!(&dst[..], &bytes[..]);
}

#[test]
fn the_adsb_heartbeat_is_the_hand_packed_frame() {
    // HEARTBEAT (ID 0, CRC extra 50), fields by size: custom_mode 0 (u32), type 27
    // (MAV_TYPE_ADSB), autopilot 8 (MAV_AUTOPILOT_INVALID), base_mode 0, system_status 4
    // (MAV_STATE_ACTIVE), mavlink_version 3.
    let payload = [0, 0, 0, 0, 27, 8, 0, 4, 3];
    for version in [1, 2] {
        let info = FrameInfo {
            version,
            sequence: 7,
            system_id: 1,
            component_id: 156,
            signed: false,
        };
        let mut out = Vec::new();
        encode_adsb_heartbeat(&info, &mut out);
        let want = if version == 1 {
            v1_frame(7, 0, &payload, 50)
        } else {
            v2_frame(0, 7, 0, &payload, 50)
        };
        assert_eq!(out, want, "v{version}");
    }
}

#[test]
fn the_longest_frame_is_max_frame_len() {
    // MAVLink 2, signed, a 255-byte payload: 10 + 255 + 2 + 13 octets.
    assert_eq!(v2_frame(1, 0, 246, &[0; 255], 184).len(), MAX_FRAME_LEN);
}

#[test]
fn a_bad_v2_header_is_refused_with_its_ten_octets_in() {
    // Incompatibility flags other than "signed" (0x02 here): not a frame, known as soon as the
    // header is in; the start byte is skipped without waiting for a payload.
    let mut d = MavlinkDecoder::default();
    let mut buf = BytesMut::from(&[0xFD, 40, 0x02, 0, 0, 1, 156, 246, 0, 0][..]);
    assert!(d.decode(&mut buf).is_none());
    assert!(buf.is_empty());
    assert_eq!(d.stats().bytes_skipped, 10);
}

#[test]
fn validity_flags_and_uat() {
    // flags = SOURCE_UAT | SIMULATED only: nothing but the address and category is valid.
    let v = AdsbVehicle {
        flags: FLAG_SOURCE_UAT | FLAG_SIMULATED,
        altitude_type: 1,
        ..expected_vehicle()
    };
    let t = v.to_traffic();
    assert_eq!(t.link, Link::Uat978);
    assert!(t.flags.test);
    assert_eq!(
        (t.lat_deg, t.alt_pressure_m, t.alt_geometric_m),
        (None, None, None)
    );
    assert_eq!(
        (t.track_deg, t.ground_speed_mps, t.vertical_rate_mps),
        (None, None, None)
    );
    assert_eq!((t.callsign, t.squawk), (None, None));
    // Geometric altitude type.
    let t = AdsbVehicle {
        flags: FLAG_VALID_ALTITUDE | FLAG_VERTICAL_VELOCITY_VALID,
        altitude_type: 1,
        ..expected_vehicle()
    }
    .to_traffic();
    assert_eq!(t.alt_pressure_m, None);
    assert!((t.alt_geometric_m.unwrap() - 1524.0).abs() < 1e-9);
    assert_eq!(t.ground_speed_mps, None);
    assert!((t.vertical_rate_mps.unwrap() + 5.08).abs() < 1e-9);
}

#[test]
fn unknown_malformed_and_unsupported() {
    let mut bytes = Vec::new();
    // HEARTBEAT (#0, CRC_EXTRA 50) with a valid checksum: known to the dialect, not wanted.
    bytes.extend(v1_frame(0, 0, &[0, 0, 0, 0, 6, 8, 0, 0, 3], 50));
    // ADSB_VEHICLE in MAVLink 1 with a 37-byte payload.
    bytes.extend(v1_frame(1, 246, &VEHICLE_PAYLOAD[..37], EXTRA_ADSB_VEHICLE));
    // COLLISION in MAVLink 1 with an 18-byte payload.
    bytes.extend(v1_frame(1, 247, &COLLISION_PAYLOAD[..18], EXTRA_COLLISION));
    // emitter_type 25 is outside ADSB_EMITTER_TYPE.
    let mut p = VEHICLE_PAYLOAD;
    p[36] = 25;
    bytes.extend(v2_frame(0, 2, 246, &p, EXTRA_ADSB_VEHICLE));
    // Incompatibility flag 0x02 (not supported): skipped byte by byte like garbage.
    let unsupported = v2_frame(2, 3, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE);
    bytes.extend(&unsupported);
    // A message id outside the dialect (v2 id 0x123456): cannot be checked, skipped.
    let foreign = v2_frame(0, 4, 0x12_3456, &[1, 2, 3], 0);
    bytes.extend(&foreign);
    let good = v1_frame(5, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE);
    bytes.extend(&good);
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs.len(), 1);
    assert_eq!(stats.unknown_types, 1);
    assert_eq!(stats.malformed, 3);
    assert_eq!(stats.checksum_failures, 0);
    assert_eq!(
        stats.bytes_skipped,
        (bytes.len() - good.len()) as u64,
        "everything but the good frame is skipped"
    );
    assert_split_invariant(MavlinkDecoder::new, &bytes);
}

fn sample_stream() -> Vec<u8> {
    let mut bytes = Vec::new();
    for seq in 0..4u8 {
        bytes.extend(v1_frame(seq, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE));
        bytes.extend(v2_frame(0, seq, 247, &COLLISION_PAYLOAD, EXTRA_COLLISION));
    }
    bytes
}

#[test]
fn bad_checksum_resynchronises() {
    let mut bytes = b"\xFE\x26garbage\xFD".to_vec();
    let mut bad = v1_frame(0, 246, &VEHICLE_PAYLOAD, EXTRA_ADSB_VEHICLE);
    bad[20] ^= 0x10;
    bytes.extend(&bad);
    bytes.extend(sample_stream());
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs.len(), 8);
    // The damaged frame and the leading false start (its length 0x26 takes the following bytes
    // in): both fail the checksum; every byte before the first good frame is skipped.
    assert_eq!(stats.checksum_failures, 2);
    assert_eq!(stats.bytes_skipped, (10 + bad.len()) as u64);
    assert_split_invariant(MavlinkDecoder::new, &bytes);
}

#[test]
fn truncated_stream() {
    let bytes = sample_stream();
    let (all, _) = decode_all(&bytes);
    for cut in 0..bytes.len() {
        let (msgs, stats) = decode_all(&bytes[..cut]);
        assert_accounting(&stats, cut);
        assert!(all.starts_with(&msgs), "cut {cut}");
    }
}

#[test]
fn bit_flips_are_caught() {
    let clean = sample_stream();
    let (all, _) = decode_all(&clean);
    let mut rng = XorShift::new(246);
    for round in 0..300 {
        let mut bytes = clean.clone();
        flip_bits(&mut bytes, 1 + round % 5, &mut rng);
        let (msgs, stats) = decode_all(&bytes);
        assert_accounting(&stats, bytes.len());
        for m in &msgs {
            // Anything decoded was sent (pairing may differ when the vehicle before was lost).
            let found = all.iter().any(|a| match (a, m) {
                (
                    MavlinkMessage::Collision {
                        frame, collision, ..
                    },
                    MavlinkMessage::Collision {
                        frame: f2,
                        collision: c2,
                        ..
                    },
                ) => frame == f2 && collision == c2,
                _ => a == m,
            });
            assert!(found, "{m:?}");
        }
    }
}

#[test]
fn random_input() {
    assert_survives_random(MavlinkDecoder::new, 3, 300, 2000);
    let mut rng = XorShift::new(4);
    for _ in 0..200 {
        let bytes: Vec<u8> = (0..800)
            .map(|_| match rng.below(4) {
                0 => 0xFE,
                1 => 0xFD,
                _ => rng.next_u64() as u8,
            })
            .collect();
        let (_, stats) = decode_all(&bytes);
        assert_accounting(&stats, bytes.len());
    }
}

prop_compose! {
    fn vehicle()(
        ints in any::<(u32, i32, i32, i32)>(),
        shorts in any::<(u16, u16, i16, u16, u16)>(),
        alt_type in 0u8..2,
        callsign in "[A-Z0-9 ]{0,8}",
        emitter in 0u8..20,
        tslc in any::<u8>(),
    ) -> AdsbVehicle {
        AdsbVehicle {
            icao_address: ints.0,
            lat_deg: f64::from(ints.1) / 1e7,
            lon_deg: f64::from(ints.2) / 1e7,
            altitude_m: f64::from(ints.3) / 1e3,
            altitude_type: alt_type,
            heading_deg: f64::from(shorts.0) / 100.0,
            hor_velocity_mps: f64::from(shorts.1) / 100.0,
            ver_velocity_mps: f64::from(shorts.2) / 100.0,
            flags: shorts.3,
            squawk: shorts.4,
            callsign,
            emitter_type: emitter,
            tslc_s: tslc,
        }
    }
}

proptest! {
    #[test]
    fn round_trip(v in vehicle(), c in any::<(u32, f32, f32, f32, u8, u8, u8)>(), version in 1u8..3, seq in any::<u8>()) {
        let info = FrameInfo { version, sequence: seq, system_id: 1, component_id: 156, signed: false };
        let collision = Collision {
            id: c.0,
            time_to_minimum_delta_s: c.1,
            altitude_minimum_delta_m: c.2,
            horizontal_minimum_delta_m: c.3,
            src: c.4 % 2,
            action: c.5 % 7,
            threat_level: c.6 % 3,
        };
        let mut bytes = Vec::new();
        encode_adsb_vehicle(&info, &v, &mut bytes);
        encode_collision(&info, &collision, &mut bytes);
        let (msgs, stats) = decode_all(&bytes);
        if v.to_traffic().check_values().is_err() {
            // Issue 24: dropped alone and counted; the COLLISION after it still decodes.
            prop_assert_eq!(stats.invalid_values, 1);
            prop_assert_eq!(msgs.len(), 1);
            return Ok(());
        }
        prop_assert_eq!(stats.bytes_skipped, 0);
        prop_assert_eq!(msgs.len(), 2);
        let MavlinkMessage::AdsbVehicle { vehicle, frame } = &msgs[0] else { panic!() };
        prop_assert_eq!(*frame, info);
        // Callsigns lose trailing NULs only; lat/lon etc. are exact multiples of their LSB.
        prop_assert_eq!(vehicle, &v);
        let MavlinkMessage::Collision { collision: back, target, .. } = &msgs[1] else { panic!() };
        // NaN payloads compare by bits.
        prop_assert_eq!(back.time_to_minimum_delta_s.to_bits(), collision.time_to_minimum_delta_s.to_bits());
        prop_assert_eq!((back.id, back.src, back.action, back.threat_level), (collision.id, collision.src, collision.action, collision.threat_level));
        prop_assert_eq!(target.is_some(), v.icao_address == collision.id);
    }
}
