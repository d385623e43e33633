use bytes::BytesMut;
use proptest::prelude::*;

use super::*;
use crate::bahrs::SyncPulseTime;
use crate::testkit::{XorShift, assert_accounting, flip_bits};

#[test]
fn every_protocol_round_trips_through_its_name() {
    for p in Protocol::ALL {
        // Whatever the device is called: a named protocol wins.
        assert_eq!(Protocol::resolve(p.name(), "gyro"), Some(p), "{p:?}");
        assert_eq!(Protocol::resolve(p.name(), "vn200"), Some(p), "{p:?}");
        assert_eq!(PortDecoder::new(p).protocol(), p);
    }
    let mut names: Vec<&str> = Protocol::ALL.iter().map(|p| p.name()).collect();
    names.sort_unstable();
    names.dedup();
    assert_eq!(names.len(), Protocol::ALL.len(), "names are distinct");
}

#[test]
fn an_empty_protocol_is_implied_by_the_standard_device_names_only() {
    let cases = [
        ("bahrs", Some(Protocol::Bahrs)),
        ("watson", Some(Protocol::Watson)),
        ("vn200", Some(Protocol::Vn200)),
        ("ttmrf", Some(Protocol::TtmrfText)),
        ("adsb", None),
        ("", None),
    ];
    for (device, p) in cases {
        assert_eq!(Protocol::resolve("", device), p, "{device}");
    }
    // The family of each implied protocol is the device of that name.
    for d in Device::ALL {
        let p = Protocol::resolve("", d.name()).unwrap();
        assert_eq!(p.device(), d);
    }
}

#[test]
fn names_match_exactly_not_by_prefix() {
    // The module's decision: a name that only starts like a known one is not decoded.
    for name in [
        "vn200-binary",
        "ttmrf-hex-v2",
        "ttmrf",
        "bahrs",
        "BAHRS-2.0",
        " vn200-icd",
    ] {
        assert_eq!(Protocol::resolve(name, "vn200"), None, "{name}");
    }
}

#[test]
fn every_ttmrf_output_belongs_to_the_ttmrf_family() {
    for p in Protocol::ALL {
        let expected = match p.name().split('-').next() {
            Some("bahrs") => Device::Bahrs,
            Some("watson") => Device::Watson,
            Some("vn200") => Device::Vn200,
            Some("ttmrf") => Device::Ttmrf,
            other => panic!("{other:?}"),
        };
        assert_eq!(p.device(), expected, "{p:?}");
    }
}

#[test]
fn default_bauds_are_rates_the_device_documents_allow() {
    // Watson AHRS-E304 document: "The string is sent at 9600 baud".
    assert_eq!(Protocol::Watson.default_baud(), 9600);
    // VN-200 ICD, Register 5 (Baud Rate), enumeration BaudRate.
    let vn200 = [
        9600, 19_200, 38_400, 57_600, 115_200, 128_000, 230_400, 460_800, 921_600,
    ];
    assert!(vn200.contains(&Protocol::Vn200.default_baud()));
    // TT-Multi-RF manual: BAUDRATE setting "Baudrate in RUN state: 0 - 115200bps, 1 - 921600bps"
    // (and Table 8: 57600 to 3000000 bps). Every TT-Multi-RF output shares the one UART.
    for p in Protocol::ALL
        .into_iter()
        .filter(|p| p.device() == Device::Ttmrf)
    {
        assert!([115_200, 921_600].contains(&p.default_baud()), "{p:?}");
    }
    // The BAHRS protocol 2.0 document names no baud rate: its default (115 200) is the
    // installation's choice and cannot be checked against the document.
}

/// Two BAHRS 0x06 frames (20 bytes each).
fn two_bahrs_frames() -> Vec<u8> {
    let mut bytes = Vec::new();
    for seq in 0..2 {
        bahrs::Message::SyncPulseTime(SyncPulseTime {
            seq,
            mcu_time_us: 7,
        })
        .encode(&mut bytes);
    }
    assert_eq!(bytes.len(), 40);
    bytes
}

/// Decodes `bytes` fed in `chunks`-sized pieces then ends the stream: (offset, wire length) of
/// each message and the counters.
fn decode_all(p: Protocol, bytes: &[u8], chunk: usize) -> (Vec<(u64, u64)>, DecodeStats) {
    let mut d = PortDecoder::new(p);
    let mut buf = BytesMut::new();
    let mut got = Vec::new();
    let mut f = |m: PortFrame| -> Result<(), ()> {
        got.push((m.offset, m.wire_len));
        Ok(())
    };
    for c in bytes.chunks(chunk.max(1)) {
        buf.extend_from_slice(c);
        d.decode(&mut buf, false, &mut f).unwrap();
    }
    d.decode(&mut buf, true, &mut f).unwrap();
    assert!(
        buf.is_empty(),
        "{p:?}: bytes left after the end of the stream"
    );
    (got, d.stats())
}

#[test]
fn frames_come_with_their_offset_and_wire_length() {
    let bytes = two_bahrs_frames();
    let (got, stats) = decode_all(Protocol::Bahrs, &bytes, 7);
    assert_eq!(got, vec![(0, 20), (20, 20)]);
    assert_eq!(stats.frames_decoded, 2);
    assert_accounting(&stats, bytes.len());
}

#[test]
fn a_corrupted_frame_is_counted_and_the_next_one_still_decodes() {
    let mut bytes = two_bahrs_frames();
    bytes[10] ^= 0x55; // inside the first frame's payload: its CRC fails
    let (got, stats) = decode_all(Protocol::Bahrs, &bytes, 40);
    assert_eq!(got, vec![(20, 20)]);
    assert_eq!(stats.checksum_failures, 1);
    assert_accounting(&stats, bytes.len());
}

#[test]
fn a_truncated_frame_at_the_end_of_the_stream_is_skipped() {
    let bytes = two_bahrs_frames();
    let cut = &bytes[..30];
    let (got, stats) = decode_all(Protocol::Bahrs, cut, 4);
    assert_eq!(got, vec![(0, 20)]);
    assert_eq!(stats.bytes_skipped, 10);
    assert_accounting(&stats, cut.len());
}

#[test]
fn the_ttmrf_text_port_yields_text_and_raw_lines() {
    let bytes = b"AT+RUN_START\r\n*5D4B18FFFC710B;\r\n";
    let mut d = PortDecoder::new(Protocol::TtmrfText);
    let mut buf = BytesMut::from(&bytes[..]);
    let mut got = Vec::new();
    d.decode(&mut buf, true, &mut |m: PortFrame| -> Result<(), ()> {
        got.push(m);
        Ok(())
    })
    .unwrap();
    assert_eq!(got.len(), 2);
    assert!(matches!(got[0].message, PortMessage::TtmrfText(_)));
    assert_eq!((got[0].offset, got[0].wire_len), (0, 14));
    let json = serde_json::to_value(got[1].message.as_message()).unwrap();
    assert_eq!(json["raw"], "mode_s");
    assert_eq!(json["frame_hex"], "5D4B18FFFC710B");
    assert_eq!((got[1].offset, got[1].wire_len), (14, 18));
}

#[test]
fn every_decoder_survives_bit_errors_in_a_valid_stream() {
    let mut rng = XorShift::new(19);
    for p in Protocol::ALL {
        for _ in 0..50 {
            let mut bytes = two_bahrs_frames();
            bytes.extend_from_slice(b"AT+RUN_START\r\n*5D4B18FFFC710B;\r\n");
            flip_bits(&mut bytes, 3, &mut rng);
            let chunk = 1 + rng.below(16) as usize;
            let (got, stats) = decode_all(p, &bytes, chunk);
            assert_accounting(&stats, bytes.len());
            check_positions(&got, bytes.len());
        }
    }
}

/// Offsets grow, and every message lies inside the stream.
fn check_positions(got: &[(u64, u64)], len: usize) {
    for w in got.windows(2) {
        assert!(w[0].0 < w[1].0, "{got:?}");
    }
    for &(offset, wire_len) in got {
        assert!(wire_len >= 1 && offset + wire_len <= len as u64, "{got:?}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Random bytes in random chunks: no panic, every byte accounted for, positions sane, and the
    /// same frames whatever the split.
    #[test]
    fn random_bytes_never_panic(
        bytes in proptest::collection::vec(any::<u8>(), 0..600),
        chunk in 1usize..64,
        which in 0usize..Protocol::ALL.len(),
    ) {
        let p = Protocol::ALL[which];
        let (got, stats) = decode_all(p, &bytes, chunk);
        assert_accounting(&stats, bytes.len());
        check_positions(&got, bytes.len());
        let (whole, _) = decode_all(p, &bytes, bytes.len());
        prop_assert_eq!(got, whole);
    }
}
