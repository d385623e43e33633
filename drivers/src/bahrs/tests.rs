//! BAHRS decoder tests: hand-built frames with values computed by hand from the document, round
//! trips, and hostile streams.

use approx::assert_relative_eq;
use bytes::BytesMut;
use proptest::prelude::*;

use super::*;
use crate::testkit::{
    XorShift, assert_accounting, assert_split_invariant, assert_survives_random, decode_chunked,
    flip_bits,
};
use crate::{DeviceDecoder, decode_slice};

/// Independent bitwise CRC-32/MPEG-2 (poly 0x04C11DB7, init all ones, no reflection, no final XOR),
/// so frame tests do not check the production table against itself.
fn crc_ref(data: &[u8]) -> u32 {
    let mut reg = 0xFFFF_FFFFu32;
    for &b in data {
        reg ^= u32::from(b) << 24;
        for _ in 0..8 {
            reg = if reg & 0x8000_0000 != 0 {
                (reg << 1) ^ 0x04C1_1DB7
            } else {
                reg << 1
            };
        }
    }
    reg
}

/// Appends the reference CRC, little-endian.
fn with_crc(mut body: Vec<u8>) -> Vec<u8> {
    let crc = crc_ref(&body);
    body.extend_from_slice(&crc.to_le_bytes());
    body
}

fn decode_all(bytes: &[u8]) -> (Vec<Message>, Decoder) {
    let mut d = Decoder::new();
    let msgs = decode_slice(&mut d, bytes);
    (msgs, d)
}

fn one(bytes: &[u8]) -> Message {
    let (msgs, d) = decode_all(bytes);
    assert_eq!(msgs.len(), 1, "{:?} {:?}", d.stats(), d.last_error());
    msgs[0]
}

#[test]
fn inertial_frame_by_hand() {
    let frame = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x01, // header, version 0x0003 LE, type 0x01
        0x2A, // seq 42
        0xE8, 0x03, // fx = 1000
        0x18, 0xFC, // fy = -1000
        0x64, 0xE6, // fz = 0xE664 = -6556
        0x64, 0x00, // wx = 100
        0xFF, 0xFF, // wy = -1
        0xFF, 0x7F, // wz = 32767
        0x55, 0x05, // health 0x0555: all six signals 01 (safe)
        0x00, 0x00, 0x00, 0x00, // padding: 5 + 15 = 20 is word aligned, so PAD_LEN = 4
    ]);
    assert_eq!(frame.len(), 28);
    let Message::Inertial(m) = one(&frame) else {
        panic!("not inertial")
    };
    assert_eq!(m.seq, 42);
    let f = m.specific_force_mps2();
    // 1000 x 1.4964e-3 = 1.4964; 6556 x 1.4964e-3 = 9.8103984.
    assert_relative_eq!(f[0], 1.4964, max_relative = 1e-12);
    assert_relative_eq!(f[1], -1.4964, max_relative = 1e-12);
    assert_relative_eq!(f[2], -9.8103984, max_relative = 1e-12);
    let w = m.angular_rate_radps();
    // 100 x 1.5979452e-4 = 0.015979452; 32767 x 1.5979452e-4 = 5.23598703684 (about 300 deg/s).
    assert_relative_eq!(w[0], 0.015979452, max_relative = 1e-12);
    assert_relative_eq!(w[1], -1.5979452e-4, max_relative = 1e-12);
    assert_relative_eq!(w[2], 5.23598703684, max_relative = 1e-12);
    for axis in 0..3 {
        assert_eq!(m.health.specific_force(axis), Health::Safe);
        assert_eq!(m.health.angular_rate(axis), Health::Safe);
    }
    // Our encoder produces the same bytes (zero padding).
    assert_eq!(Message::Inertial(m).to_frame(), frame);
}

#[test]
fn navigation_frame_by_hand() {
    let frame = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x02, // header
        0x07, // seq 7
        0x93, 0x19, // height raw 0x1993 = 6547
        0xDE, 0xFD, // velocity down raw 0xFDDE = -546
        0xAB, 0xEA, // roll raw 0xEAAB = -5461
        0xAB, 0x0A, // pitch raw 0x0AAB = 2731
        0xFF, 0xFF, // heading raw 65535
        0x55, 0x02, // health: height, vd, roll, pitch safe (01); heading integrity risk (10)
        0x00, 0x00, // padding: 5 + 13 = 18, PAD_LEN = 2
    ]);
    assert_eq!(frame.len(), 24);
    let Message::Navigation(m) = one(&frame) else {
        panic!("not navigation")
    };
    assert_eq!(m.seq, 7);
    // 0.16784924 x 6547 - 1000 = 98.90897428 m.
    assert_relative_eq!(m.pressure_height_m(), 98.90897428, max_relative = 1e-12);
    // 9.155413e-3 x -546 = -4.998855498 m/s (climbing at 5 m/s).
    assert_relative_eq!(m.velocity_down_mps(), -4.998855498, max_relative = 1e-12);
    // 9.587526e-5 x -5461 = -0.52357479486 rad (-29.9986 deg).
    assert_relative_eq!(m.roll_rad(), -0.52357479486, max_relative = 1e-12);
    assert_relative_eq!(m.pitch_rad(), 0.26183533506, max_relative = 1e-12);
    // 65535 x 9.587526e-5 = 6.2831851641 rad, just under 2 pi as section 3.2 promises.
    assert_relative_eq!(m.heading_mag_rad(), 6.2831851641, max_relative = 1e-12);
    assert!(m.heading_mag_rad() < std::f64::consts::TAU);
    assert_eq!(m.health.roll(), Health::Safe);
    assert_eq!(m.health.heading(), Health::IntegrityRisk);
    assert_eq!(Message::Navigation(m).to_frame(), frame);
}

#[test]
fn pressure_height_is_unsigned() {
    // Decision in `Navigation`: raw 0xFFFF is +9999.99 m (0.16784924 x 65535 - 1000 = 9999.9999),
    // not the -1000.17 m a signed reading would give; raw 0 is the -1000 m floor.
    let nav = |raw: u16| Navigation {
        seq: 0,
        pressure_height_raw: raw,
        velocity_down_raw: 0,
        roll_raw: 0,
        pitch_raw: 0,
        heading_raw: 0,
        health: NavigationHealth::default(),
    };
    let Message::Navigation(top) = one(&Message::Navigation(nav(0xFFFF)).to_frame()) else {
        panic!()
    };
    assert_relative_eq!(top.pressure_height_m(), 9999.9999434, max_relative = 1e-12);
    assert_relative_eq!(nav(0).pressure_height_m(), -1000.0);
    // 5958 x 0.16784924 - 1000 = 0.0397 m: sea level sits near raw 5958.
    assert!(nav(5958).pressure_height_m().abs() < 0.1);
}

#[test]
fn from_si_rounds_to_the_nearest_lsb() {
    let m = Navigation::from_si(
        3,
        98.90897428,
        -4.998855498,
        -0.52357479486,
        0.26183533506,
        -1e-9, // wraps to just under 2 pi
        NavigationHealth::new(
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
        ),
    );
    assert_eq!(m.pressure_height_raw, 6547);
    assert_eq!(m.velocity_down_raw, -546);
    assert_eq!(m.roll_raw, -5461);
    assert_eq!(m.pitch_raw, 2731);
    // 2 pi / 9.587526e-5 = 65535.0015 LSB, so 2 pi - 1e-9 rounds to the last code, 65535.
    assert_eq!(m.heading_raw, 65535);
    let i = Inertial::from_si(
        0,
        [1.4964, 0.0, 1e9],
        [0.0, -1.5979452e-4, f64::NAN],
        InertialHealth(0),
    );
    assert_eq!(i.specific_force_raw, [1000, 0, i16::MAX]);
    assert_eq!(i.angular_rate_raw, [0, -1, 0]);
}

#[test]
fn accuracy_zero_means_invalid() {
    let frame = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x03, // header
        0x09, // seq
        0x0A, 0x00, // std N raw 10
        0x00, 0x00, // std E raw 0: invalid
        0x34, 0x12, // std heading raw 0x1234 = 4660
        0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11, // MCU time 0x1122334455667788 us
        0, 0, 0, 0, // padding
    ]);
    let Message::Accuracy(m) = one(&frame) else {
        panic!()
    };
    assert_relative_eq!(
        m.std_north_rad().unwrap(),
        9.587526e-4,
        max_relative = 1e-12
    );
    assert_eq!(m.std_east_rad(), None);
    // 4660 x 9.587526e-5 = 0.44677871 rad.
    assert_relative_eq!(
        m.std_heading_rad().unwrap(),
        0.44677871160,
        max_relative = 1e-10
    );
    assert_eq!(m.mcu_time_us, 0x1122_3344_5566_7788);
}

#[test]
fn accuracy_each_deviation_has_its_own_validity() {
    // The other way round from the frame above: north invalid (0), east and heading valid.
    // Section 3.3: 3 x 9.587526e-5 = 2.8762578e-4 rad; 65535 x 9.587526e-5 = 6.2831851641 rad.
    let m = Accuracy {
        seq: 0,
        std_north_raw: 0,
        std_east_raw: 3,
        std_heading_raw: 0xFFFF,
        mcu_time_us: 0,
    };
    assert_eq!(m.std_north_rad(), None);
    assert_relative_eq!(
        m.std_east_rad().unwrap(),
        2.8762578e-4,
        max_relative = 1e-12
    );
    assert_relative_eq!(
        m.std_heading_rad().unwrap(),
        6.2831851641,
        max_relative = 1e-10
    );
    let none = Accuracy {
        std_heading_raw: 0,
        ..m
    };
    assert_eq!(none.std_heading_rad(), None);
}

#[test]
fn time_messages_by_hand() {
    let nav_time = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x04, 0x10, 0x33, // seq 16, navigation seq 0x33
        0x40, 0x42, 0x0F, 0x00, 0x00, 0x00, 0x00, 0x00, // 1_000_000 us
        0x00, // padding: 5 + 10 = 15, PAD_LEN 1
    ]);
    assert_eq!(
        one(&nav_time),
        Message::NavigationTime(DataTime {
            seq: 16,
            data_seq: 0x33,
            mcu_time_us: 1_000_000
        })
    );
    let invalid = DataTime {
        seq: 5,
        data_seq: 0,
        mcu_time_us: 0,
    };
    assert!(!invalid.is_valid());
    assert!(
        DataTime {
            seq: 5,
            data_seq: 0,
            mcu_time_us: 1
        }
        .is_valid()
    );
    assert!(
        DataTime {
            seq: 5,
            data_seq: 1,
            mcu_time_us: 0
        }
        .is_valid()
    );
    // An invalid time message is still delivered (with its flag), not dropped.
    assert_eq!(
        one(&Message::InertialTime(invalid).to_frame()),
        Message::InertialTime(invalid)
    );
    let pulse = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x06, 0xFF, // seq 255
        0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08, // 0x0807060504030201 us
        0x00, 0x00, // padding: 5 + 9 = 14, PAD_LEN 2
    ]);
    assert_eq!(
        one(&pulse),
        Message::SyncPulseTime(SyncPulseTime {
            seq: 255,
            mcu_time_us: 0x0807_0605_0403_0201
        })
    );
}

#[test]
fn sequence_counter_is_the_first_payload_byte_of_0x01_to_0x06() {
    // Sections 3.1-3.6: byte 1 of these payloads is the sequence counter; 0x0F, 0x1F and the
    // service messages have none. (type, LEN, PAD_LEN by hand from section 2.2).
    for (t, len, pad) in [
        (0x01u8, 15, 4),
        (0x02, 13, 2),
        (0x03, 15, 4),
        (0x04, 10, 1),
        (0x05, 10, 1),
        (0x06, 9, 2),
        (0x0F, 7, 4),
        (0x1F, 14, 1),
        (0xFF, 2, 0),
    ] {
        let mut body = vec![0x4E, 0x45, 0x03, 0x00, t, 0xA0 ^ t];
        body.resize(5 + len + pad, 0);
        let want = (t <= 0x06).then_some(0xA0 ^ t);
        assert_eq!(one(&with_crc(body)).seq(), want, "type {t:#04x}");
    }
}

#[test]
fn versions_and_service_messages_by_hand() {
    let sw = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x0F, b'B', b'H', b'R', 0x02, 0x00, 0x11, 0x00, 0, 0, 0, 0,
    ]);
    let Message::SoftwareVersion(v) = one(&sw) else {
        panic!()
    };
    assert_eq!(
        (v.project_code_str().as_str(), v.major, v.minor),
        ("BHR", 2, 17)
    );
    let hw = with_crc(vec![
        0x4E, 0x45, 0x03, 0x00, 0x1F, 0x13, 0x04, // MCU id 0x0413
        0x01, 0x00, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00, 0xEF, 0xBE, 0xAD,
        0xDE, // ids 1, 2, 0xDEADBEEF
        0x00, // padding: 5 + 14 = 19, PAD_LEN 1
    ]);
    assert_eq!(
        one(&hw),
        Message::HardwareVersion(HardwareVersion {
            mcu_id: 0x0413,
            unique_id: [1, 2, 0xDEAD_BEEF]
        })
    );
    // Host -> device requests: 0xF0/0xF1 padded (3 bytes), 0xF2 not padded.
    assert_eq!(
        Message::EnterDiagnostics.to_frame(),
        with_crc(vec![0x4E, 0x45, 3, 0, 0xF0, 0, 0, 0])
    );
    assert_eq!(
        Message::ExitDiagnostics.to_frame(),
        with_crc(vec![0x4E, 0x45, 3, 0, 0xF1, 0, 0, 0])
    );
    assert_eq!(
        Message::ReadNvmPage { page: 249 }.to_frame(),
        with_crc(vec![0x4E, 0x45, 3, 0, 0xF2, 249])
    );
    // Device -> host: 0xF3 and 0xFF, not padded.
    let mut page = vec![0x4E, 0x45, 3, 0, 0xF3, 12];
    page.extend(0u8..32);
    let Message::NvmPage(p) = one(&with_crc(page)) else {
        panic!()
    };
    assert_eq!(p.page, 12);
    assert_eq!(p.data[31], 31);
    assert_eq!(
        one(&with_crc(vec![0x4E, 0x45, 3, 0, 0xFF, 0xF2, 0x00])),
        Message::Ack(Ack {
            acked_type: 0xF2,
            status: 0
        })
    );
}

#[test]
fn nvm_page_out_of_range_is_malformed() {
    let (msgs, d) = decode_all(&with_crc(vec![0x4E, 0x45, 3, 0, 0xF2, 250]));
    assert!(msgs.is_empty());
    assert_eq!(d.stats().malformed, 1);
    assert!(matches!(
        d.last_error(),
        Some(Error::Malformed { page: 250, .. })
    ));
}

#[test]
fn nvm_pages_0_to_249_are_accepted_and_250_rejected_in_both_directions() {
    // Sections 5.3 and 5.4: "from 0 to 249", for the request (0xF2) and the page data (0xF3).
    for t in [0xF2u8, 0xF3] {
        let frame = |page: u8| {
            let mut body = vec![0x4E, 0x45, 3, 0, t, page];
            if t == 0xF3 {
                body.extend([0xA5; 32]);
            }
            with_crc(body)
        };
        for page in [0, 249] {
            let m = one(&frame(page));
            let got = match m {
                Message::ReadNvmPage { page } => page,
                Message::NvmPage(p) => p.page,
                other => panic!("{other:?}"),
            };
            assert_eq!((m.type_id(), got), (t, page));
        }
        let (msgs, d) = decode_all(&frame(250));
        assert!(msgs.is_empty(), "type {t:#04x}");
        assert_eq!(d.stats().malformed, 1, "type {t:#04x}");
    }
}

fn sample_messages() -> Vec<Message> {
    let nav = Navigation::from_si(
        1,
        120.0,
        0.5,
        0.1,
        -0.05,
        3.0,
        NavigationHealth::new(
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
        ),
    );
    vec![
        Message::SoftwareVersion(SoftwareVersion {
            project_code: *b"BHR",
            major: 2,
            minor: 0,
        }),
        Message::HardwareVersion(HardwareVersion {
            mcu_id: 1,
            unique_id: [2, 3, 4],
        }),
        Message::Inertial(Inertial::from_si(
            0,
            [0.1, -0.2, -9.81],
            [0.01, 0.0, -0.02],
            InertialHealth(0x555),
        )),
        Message::InertialTime(DataTime {
            seq: 0,
            data_seq: 0,
            mcu_time_us: 10_000,
        }),
        Message::Navigation(nav),
        Message::NavigationTime(DataTime {
            seq: 0,
            data_seq: 1,
            mcu_time_us: 10_050,
        }),
        Message::Accuracy(Accuracy {
            seq: 0,
            std_north_raw: 10,
            std_east_raw: 11,
            std_heading_raw: 0,
            mcu_time_us: 10_100,
        }),
        Message::SyncPulseTime(SyncPulseTime {
            seq: 0,
            mcu_time_us: 1_000_000,
        }),
        Message::EnterDiagnostics,
        Message::ReadNvmPage { page: 3 },
        Message::NvmPage(NvmPage {
            page: 3,
            data: [0x4E; 32],
        }),
        Message::Ack(Ack {
            acked_type: 0xF0,
            status: 1,
        }),
        Message::ExitDiagnostics,
    ]
}

fn stream_of(msgs: &[Message]) -> Vec<u8> {
    let mut out = Vec::new();
    for m in msgs {
        m.encode(&mut out);
    }
    out
}

#[test]
fn every_type_round_trips_in_one_stream() {
    let msgs = sample_messages();
    let bytes = stream_of(&msgs);
    let (decoded, d) = decode_all(&bytes);
    assert_eq!(decoded, msgs);
    assert_eq!(d.stats().bytes_skipped, 0);
    assert_eq!(d.stats().frames_decoded, msgs.len() as u64);
    assert_accounting(d.stats(), bytes.len());
}

#[test]
fn split_at_every_point() {
    let mut bytes = b"xxNE\x03".to_vec(); // garbage with a truncated false marker
    bytes.extend(stream_of(&sample_messages()));
    bytes.extend_from_slice(b"N"); // a trailing partial marker
    assert_split_invariant(Decoder::new, &bytes);
}

#[test]
fn false_markers_and_garbage_do_not_hide_frames() {
    let msgs = sample_messages();
    let mut bytes = Vec::new();
    let mut expected_skipped = 0;
    for (i, m) in msgs.iter().enumerate() {
        // Garbage that contains 'N', 'NE', and a complete false header of a known type with
        // version 3 whose "frame" cannot check out.
        let junk: &[u8] = match i % 3 {
            0 => b"NNNE",
            1 => b"NE\x03\x00\x01garbage",
            _ => b"\x00\xFFN",
        };
        bytes.extend_from_slice(junk);
        expected_skipped += junk.len();
        m.encode(&mut bytes);
    }
    let (decoded, d) = decode_all(&bytes);
    assert_eq!(decoded, msgs);
    assert_eq!(d.stats().bytes_skipped, expected_skipped as u64);
    // The false 0x01 headers each failed their CRC once.
    let false_headers = (0..msgs.len()).filter(|i| i % 3 == 1).count();
    assert_eq!(d.stats().checksum_failures, false_headers as u64);
}

#[test]
fn unknown_types_are_skipped_by_resynchronising() {
    // An undocumented debug message (type 0x10) with a valid CRC over 20 payload bytes: its length
    // is unknown to us, so the decoder resynchronises on the next frame that checks out.
    let mut debug = vec![0x4E, 0x45, 0x03, 0x00, 0x10];
    debug.extend_from_slice(&[0x11; 20]);
    let debug = with_crc(debug);
    let good = Message::SyncPulseTime(SyncPulseTime {
        seq: 1,
        mcu_time_us: 5,
    });
    let mut bytes = debug.clone();
    good.encode(&mut bytes);
    let (decoded, d) = decode_all(&bytes);
    assert_eq!(decoded, vec![good]);
    assert_eq!(d.stats().unknown_types, 1);
    assert_eq!(d.stats().bytes_skipped, debug.len() as u64);
    assert!(matches!(
        d.last_error(),
        Some(Error::UnknownType {
            offset: 0,
            msg_type: 0x10
        })
    ));
}

#[test]
fn other_protocol_versions_are_counted_not_decoded() {
    // A protocol 0x0002 frame laid out like 2.0 with a valid CRC: counted, dropped whole.
    let mut v2 = vec![0x4E, 0x45, 0x02, 0x00, 0x06, 0x01];
    v2.extend_from_slice(&42u64.to_le_bytes());
    v2.extend_from_slice(&[0, 0]);
    let v2 = with_crc(v2);
    // A version 0x0001 header of a type unknown to 2.0.
    let v1 = b"NE\x01\x00\x42".to_vec();
    // A version 0x0007 frame with the 2.0 layout and a valid CRC: 0x0007 is no version we know,
    // so its 'N' is taken for data; the frame is skipped as noise, not counted as a version.
    let mut v7 = v2.clone();
    v7[2] = 0x07;
    let v7 = with_crc(v7[..v7.len() - 4].to_vec());
    let good = Message::Ack(Ack {
        acked_type: 1,
        status: 0,
    });
    let mut bytes = v2.clone();
    bytes.extend_from_slice(&v1);
    bytes.extend_from_slice(&v7);
    good.encode(&mut bytes);
    let (decoded, d) = decode_all(&bytes);
    assert_eq!(decoded, vec![good]);
    assert_eq!(d.stats().unsupported_version, 2);
    assert_eq!(d.stats().checksum_failures, 0);
    assert_eq!(
        d.stats().bytes_skipped,
        (v2.len() + v1.len() + v7.len()) as u64
    );
}

#[test]
fn bit_errors_cost_only_the_hit_frames() {
    let msgs: Vec<Message> = (0..200u32)
        .map(|i| {
            Message::SyncPulseTime(SyncPulseTime {
                seq: i as u8,
                mcu_time_us: u64::from(i) * 1_000_000,
            })
        })
        .collect();
    let clean = stream_of(&msgs);
    let frame_len = clean.len() / msgs.len();
    let mut rng = XorShift::new(7);
    let mut bytes = clean.clone();
    // Flip one bit in each of 20 distinct frames (every 10th frame).
    for k in 0..20 {
        let frame = k * 10;
        let bit = rng.below((frame_len * 8) as u64) as usize;
        bytes[frame * frame_len + bit / 8] ^= 1 << (bit % 8);
    }
    let (decoded, d) = decode_all(&bytes);
    // CRC-32 detects every single-bit error, so exactly the 20 hit frames are lost.
    assert_eq!(decoded.len(), 180);
    let expected: Vec<Message> = msgs
        .iter()
        .enumerate()
        .filter(|(i, _)| i % 10 != 0)
        .map(|(_, m)| *m)
        .collect();
    assert_eq!(decoded, expected);
    // Every byte of a hit frame is skipped, and nothing else.
    assert_eq!(d.stats().bytes_skipped, (20 * frame_len) as u64);
    assert_accounting(d.stats(), bytes.len());
}

#[test]
fn truncated_frames_are_not_emitted() {
    let msgs = sample_messages();
    let full = stream_of(&msgs);
    // Cut the stream inside the last frame: everything before it decodes, the stub is skipped.
    let last_len = msgs.last().unwrap().to_frame().len();
    for cut in 1..last_len {
        let bytes = &full[..full.len() - cut];
        let (decoded, d) = decode_all(bytes);
        assert_eq!(decoded, msgs[..msgs.len() - 1], "cut {cut}");
        assert_eq!(d.stats().bytes_skipped, (last_len - cut) as u64);
    }
    // A truncated frame followed by a complete one: the complete one still decodes.
    let mut bytes = full[..20].to_vec();
    msgs[0].encode(&mut bytes);
    let (decoded, _) = decode_all(&bytes);
    assert_eq!(decoded.last(), Some(&msgs[0]));
}

#[test]
fn random_input_never_panics() {
    assert_survives_random(Decoder::new, 1, 300, 4096);
    // Random streams made of real headers followed by random bytes exercise the CRC path.
    let mut rng = XorShift::new(99);
    for _ in 0..300 {
        let mut bytes = Vec::new();
        for _ in 0..rng.below(20) {
            let t = [
                0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x1F, 0xF0, 0xF3, 0xFF, 0x10,
            ][rng.below(12) as usize];
            bytes.extend_from_slice(&[0x4E, 0x45, rng.below(4) as u8, 0, t]);
            let mut junk = vec![0u8; rng.below(48) as usize];
            rng.fill(&mut junk);
            bytes.extend(junk);
        }
        let (_, stats) = decode_chunked(Decoder::new(), &bytes, &[1 + rng.below(50) as usize]);
        assert_accounting(&stats, bytes.len());
    }
}

#[test]
fn fuzz_property_on_mutated_streams() {
    // The fuzz targets' property, run here on mutated real streams so CI exercises it too.
    let clean = stream_of(&sample_messages());
    let mut rng = XorShift::new(17);
    for _ in 0..200 {
        let mut bytes = clean.clone();
        flip_bits(&mut bytes, rng.below(8) as usize, &mut rng);
        bytes.truncate(rng.below(bytes.len() as u64 + 1) as usize);
        crate::testkit::check_arbitrary_input(Decoder::new, &bytes);
    }
}

#[test]
fn corrupted_streams_keep_accounting() {
    let clean = stream_of(&sample_messages().repeat(20));
    let mut rng = XorShift::new(3);
    for _ in 0..50 {
        let mut bytes = clean.clone();
        flip_bits(&mut bytes, 1 + rng.below(40) as usize, &mut rng);
        let (decoded, stats) =
            decode_chunked(Decoder::new(), &bytes, &[1 + rng.below(64) as usize]);
        assert_accounting(&stats, bytes.len());
        assert!(decoded.len() <= 13 * 20);
    }
}

#[test]
fn tokio_codec_reports_offsets() {
    use tokio_util::codec::Decoder as _;
    let msgs = sample_messages();
    let mut bytes = b"junk".to_vec();
    let mut offsets = Vec::new();
    for m in &msgs {
        offsets.push(bytes.len() as u64);
        m.encode(&mut bytes);
    }
    let mut codec = crate::Codec(Decoder::new());
    let mut buf = BytesMut::from(&bytes[..]);
    let mut got = Vec::new();
    while let Some(located) = codec.decode(&mut buf).unwrap() {
        got.push(located.offset);
    }
    assert_eq!(got, offsets);
}

fn arb_health() -> impl Strategy<Value = u16> {
    any::<u16>()
}

fn arb_message() -> impl Strategy<Value = Message> {
    prop_oneof![
        (
            any::<u8>(),
            any::<[i16; 3]>(),
            any::<[i16; 3]>(),
            arb_health()
        )
            .prop_map(|(seq, f, w, h)| {
                Message::Inertial(Inertial {
                    seq,
                    specific_force_raw: f,
                    angular_rate_raw: w,
                    health: InertialHealth(h),
                })
            }),
        (
            any::<u8>(),
            any::<u16>(),
            any::<[i16; 3]>(),
            any::<u16>(),
            arb_health()
        )
            .prop_map(
                |(seq, height, a, heading, h)| Message::Navigation(Navigation {
                    seq,
                    pressure_height_raw: height,
                    velocity_down_raw: a[0],
                    roll_raw: a[1],
                    pitch_raw: a[2],
                    heading_raw: heading,
                    health: NavigationHealth(h),
                })
            ),
        (any::<u8>(), any::<[u16; 3]>(), any::<u64>()).prop_map(|(seq, s, t)| {
            Message::Accuracy(Accuracy {
                seq,
                std_north_raw: s[0],
                std_east_raw: s[1],
                std_heading_raw: s[2],
                mcu_time_us: t,
            })
        }),
        (any::<u8>(), any::<u8>(), any::<u64>()).prop_map(|(seq, d, t)| Message::NavigationTime(
            DataTime {
                seq,
                data_seq: d,
                mcu_time_us: t
            }
        )),
        (any::<u8>(), any::<u8>(), any::<u64>()).prop_map(|(seq, d, t)| Message::InertialTime(
            DataTime {
                seq,
                data_seq: d,
                mcu_time_us: t
            }
        )),
        (any::<u8>(), any::<u64>()).prop_map(|(seq, t)| Message::SyncPulseTime(SyncPulseTime {
            seq,
            mcu_time_us: t
        })),
        (any::<[u8; 3]>(), any::<u16>(), any::<u16>()).prop_map(|(c, major, minor)| {
            Message::SoftwareVersion(SoftwareVersion {
                project_code: c,
                major,
                minor,
            })
        }),
        (any::<u16>(), any::<[u32; 3]>()).prop_map(|(id, u)| Message::HardwareVersion(
            HardwareVersion {
                mcu_id: id,
                unique_id: u
            }
        )),
        Just(Message::EnterDiagnostics),
        Just(Message::ExitDiagnostics),
        (0..=MAX_NVM_PAGE).prop_map(|page| Message::ReadNvmPage { page }),
        (0..=MAX_NVM_PAGE, any::<[u8; 32]>())
            .prop_map(|(page, data)| Message::NvmPage(NvmPage { page, data })),
        (any::<u8>(), any::<u8>()).prop_map(|(t, s)| Message::Ack(Ack {
            acked_type: t,
            status: s
        })),
    ]
}

proptest! {
    #[test]
    fn encode_then_decode_is_identity(msgs in proptest::collection::vec(arb_message(), 1..20),
                                      chunk in 1usize..64) {
        let bytes = stream_of(&msgs);
        let (decoded, stats) = decode_chunked(Decoder::new(), &bytes, &[chunk]);
        prop_assert_eq!(decoded, msgs);
        prop_assert_eq!(stats.bytes_skipped, 0);
        prop_assert_eq!(stats.checksum_failures, 0);
    }

    #[test]
    fn si_round_trip_within_half_an_lsb(height in -1000.0f64..9999.0, vd in -299.0f64..299.0,
                                        roll in -3.1f64..3.1, pitch in -1.5f64..1.5,
                                        heading in 0.0f64..6.2) {
        let m = Navigation::from_si(0, height, vd, roll, pitch, heading, NavigationHealth(0));
        prop_assert!((m.pressure_height_m() - height).abs() <= messages_lsb::HEIGHT / 2.0 + 1e-9);
        prop_assert!((m.velocity_down_mps() - vd).abs() <= messages_lsb::VEL / 2.0 + 1e-12);
        prop_assert!((m.roll_rad() - roll).abs() <= messages_lsb::ANGLE / 2.0 + 1e-12);
        prop_assert!((m.pitch_rad() - pitch).abs() <= messages_lsb::ANGLE / 2.0 + 1e-12);
        prop_assert!((m.heading_mag_rad() - heading).abs() <= messages_lsb::ANGLE / 2.0 + 1e-12);
    }
}

mod messages_lsb {
    pub const HEIGHT: f64 = 0.16784924;
    pub const VEL: f64 = 9.155413e-3;
    pub const ANGLE: f64 = 9.587526e-5;
}

#[test]
fn decoder_waits_at_most_one_max_frame() {
    // A valid header of the longest type with nothing after it: the decoder waits (returns None)
    // without consuming; once 42 bytes are there it decides.
    let mut d = Decoder::new();
    let mut buf = BytesMut::from(&[0x4E, 0x45, 0x03, 0x00, 0xF3][..]);
    assert_eq!(d.decode(&mut buf), None);
    assert_eq!(buf.len(), 5);
    buf.extend_from_slice(&[0u8; 37]);
    assert_eq!(d.decode(&mut buf), None);
    assert_eq!(d.stats().checksum_failures, 1);
    assert!(buf.is_empty());
}

#[test]
fn payload_decode_takes_exactly_the_documented_lengths() {
    // Section 5's payload lengths, written out here rather than taken from the layout table.
    let documented: [(u8, usize); 13] = [
        (0x01, 15),
        (0x02, 13),
        (0x03, 15),
        (0x04, 10),
        (0x05, 10),
        (0x06, 9),
        (0x0F, 7),
        (0x1F, 14),
        (0xF0, 0),
        (0xF1, 0),
        (0xF2, 1),
        (0xF3, 33),
        (0xFF, 2),
    ];
    let bytes = [0u8; 40];
    for (t, len) in documented {
        let m = Message::decode_payload(t, &bytes[..len]);
        assert_eq!(m.map(|r| r.map(|m| m.type_id())), Some(Ok(t)), "{t:#04x}");
        assert_eq!(
            Message::decode_payload(t, &bytes[..len + 1]),
            None,
            "{t:#04x} long"
        );
        if len > 0 {
            assert_eq!(
                Message::decode_payload(t, &bytes[..len - 1]),
                None,
                "{t:#04x} short"
            );
        }
    }
    // A type without a layout, at any length.
    for len in [0, 1, 15] {
        assert_eq!(Message::decode_payload(0x10, &bytes[..len]), None);
    }
}
