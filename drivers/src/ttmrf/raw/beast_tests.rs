//! Beast framing tests: the manual's example, escaping, resynchronisation, the real capture's
//! counts, split points, random input and encoder round trips.

use super::*;
use crate::decode_slice;
use crate::testkit::{assert_split_invariant, assert_survives_random, decode_chunked};
use proptest::prelude::*;

/// The manual's example: short frame, MLAT 0x083E27B6CB6A = 9 063 047 285 610, signal 0x1A
/// (escaped), data 00 A1 84 1A C3 B3 1D (one escaped 0x1A).
const MANUAL: &[u8] = &[
    0x1A, 0x32, 0x08, 0x3E, 0x27, 0xB6, 0xCB, 0x6A, 0x1A, 0x1A, 0x00, 0xA1, 0x84, 0x1A, 0x1A, 0xC3,
    0xB3, 0x1D,
];

#[test]
fn signal_in_dbfs_from_the_rssi_byte() {
    let at = |rssi| {
        RxMeta {
            rssi,
            ..RxMeta::default()
        }
        .signal_dbfs()
    };
    assert_eq!(at(Some(255)), Some(0.0));
    assert_eq!(at(None), None);
    // 0 is taken as 1 (no -infinity): 20 log10(1 / 255) = -48.13 dBFS.
    assert!((at(Some(0)).unwrap() + 48.130_8).abs() < 1e-4);
    assert_eq!(at(Some(0)), at(Some(1)));
}

#[test]
fn manual_example() {
    let (f, s) = decode_chunked(BeastDecoder::new(), MANUAL, &[MANUAL.len()]);
    assert_eq!(s.frames_decoded, 1);
    assert_eq!(s.bytes_skipped, 0);
    let RawFrame::ModeS(m) = &f[0] else {
        panic!("{f:?}")
    };
    assert_eq!(m.meta.mlat_ticks, Some(9_063_047_285_610));
    assert_eq!(m.meta.rssi, Some(26));
    // 20 log10(26 / 255) = -19.83 dBFS (dump1090's scale: 255 is full scale).
    assert!((m.meta.signal_dbfs().unwrap() + 19.831_3).abs() < 1e-4);
    assert_eq!(m.data(), &[0x00, 0xA1, 0x84, 0x1A, 0xC3, 0xB3, 0x1D]);
    // Encoding gives the same bytes back.
    let mut out = BytesMut::new();
    assert!(encode_beast(&f[0], &mut out));
    assert_eq!(&out[..], MANUAL);
}

#[test]
fn the_longest_frame_on_the_wire() {
    // A long Mode S frame whose 6 MLAT, 1 RSSI and 14 data bytes are all 0x1A: every one of the
    // 21 is doubled, so 0x1A 0x33 and 42 bytes, 44 in all (MAX_WIRE_LEN). It decodes whole.
    let frame = RawFrame::ModeS(ModeSFrame {
        bytes: [ESC; 14],
        len: 14,
        meta: RxMeta {
            mlat_ticks: Some(0x1A1A_1A1A_1A1A),
            rssi: Some(ESC),
            ..RxMeta::default()
        },
    });
    let mut wire = BytesMut::new();
    assert!(encode_beast(&frame, &mut wire));
    assert_eq!(wire.len(), 44);
    assert_eq!(MAX_WIRE_LEN, 44);
    assert_eq!(&wire[..2], &[0x1A, 0x33]);
    assert!(wire[2..].iter().all(|&b| b == ESC));
    let (f, s) = decode_chunked(BeastDecoder::new(), &wire, &[7]);
    assert_eq!((f, s.bytes_skipped), (vec![frame], 0));
}

#[test]
fn resynchronisation_rules() {
    // Garbage, then a frame: found.
    let mut v = vec![0x00, 0x55, 0x31];
    v.extend_from_slice(MANUAL);
    let (f, s) = decode_chunked(BeastDecoder::new(), &v, &[v.len()]);
    assert_eq!((f.len(), s.bytes_skipped), (1, 3));
    // After garbage, "1A 1A 32 ..." is an escaped data byte followed by data, not a frame: the
    // manual's rule (a non-1A byte, then 1A, then a type) refuses it.
    let mut v = vec![0x00, 0x1A];
    v.extend_from_slice(MANUAL);
    let (f, _) = decode_chunked(BeastDecoder::new(), &v, &[v.len()]);
    assert!(f.is_empty());
    // A frame cut short by an unescaped 1A: counted malformed, the next frame is decoded.
    let mut v = MANUAL[..12].to_vec();
    v.extend_from_slice(MANUAL);
    let (f, s) = decode_chunked(BeastDecoder::new(), &v, &[v.len()]);
    assert_eq!((f.len(), s.malformed, s.bytes_skipped), (1, 1, 12));
    // Unknown type 0x34 and a Mode A/C frame with a non-octal nibble.
    let v = [
        0x1A, 0x34, 0x00, 0x1A, 0x31, 0, 0, 0, 0, 0, 1, 0x10, 0x80, 0x00,
    ];
    let (f, s) = decode_chunked(BeastDecoder::new(), &v, &[v.len()]);
    assert!(f.is_empty());
    assert_eq!((s.unknown_types, s.malformed), (1, 1));
    // A type byte outside 0x31..=0x39 is no frame at all (malformed); one inside it but
    // undocumented (0x35) is an unknown type, judged as soon as its two bytes are in, even as
    // the last bytes of the stream.
    let mut v = vec![0x1A, 0x20, 0x55];
    v.extend_from_slice(MANUAL);
    let (f, s) = decode_chunked(BeastDecoder::new(), &v, &[v.len()]);
    assert_eq!((f.len(), s.malformed, s.unknown_types), (1, 1, 0));
    let (f, s) = decode_chunked(BeastDecoder::new(), &[0x1A, 0x35], &[2]);
    assert!(f.is_empty());
    assert_eq!((s.unknown_types, s.malformed, s.bytes_skipped), (1, 0, 2));
    // A doubled 1A in garbage is an escaped data byte, not a damaged frame: skipped, not
    // counted malformed; the frame after it is found.
    let mut v = vec![0x1A, 0x1A, 0x55];
    v.extend_from_slice(MANUAL);
    let (f, s) = decode_chunked(BeastDecoder::new(), &v, &[v.len()]);
    assert_eq!((f.len(), s.malformed, s.bytes_skipped), (1, 0, 3));
    // Mode A/C: MLAT 0 and RSSI 0xFF mean "none".
    let v = [0x1A, 0x31, 0, 0, 0, 0, 0, 0, 0xFF, 0x77, 0x00];
    let (f, _) = decode_chunked(BeastDecoder::new(), &v, &[1]);
    let RawFrame::ModeAc(a) = &f[0] else {
        panic!("{f:?}")
    };
    assert_eq!(a.code.0, 0x7700);
    assert_eq!((a.meta.mlat_ticks, a.meta.rssi), (None, None));
}

#[test]
fn capture_counts() {
    // README of shared/data/adsb: 13 954 frames, 5 026 Mode A/C, 4 942 short, 3 986 long,
    // no status frames; every byte belongs to a frame.
    let Some(path) = crate::testkit::shared_data("adsb/ulss7_beast.bin") else {
        return;
    };
    let bytes = std::fs::read(path).unwrap();
    let mut d = BeastDecoder::new();
    let frames = decode_slice(&mut d, &bytes);
    let s = *d.stats();
    assert_eq!(frames.len(), 13_954);
    assert_eq!((s.bytes_skipped, s.malformed, s.unknown_types), (0, 0, 0));
    assert_eq!(s.bytes_consumed, 227_244);
    let count = |p: fn(&RawFrame) -> bool| frames.iter().filter(|f| p(f)).count();
    assert_eq!(count(|f| matches!(f, RawFrame::ModeAc(_))), 5_026);
    assert_eq!(
        count(|f| matches!(f, RawFrame::ModeS(m) if m.len == 7)),
        4_942
    );
    assert_eq!(
        count(|f| matches!(f, RawFrame::ModeS(m) if m.len == 14)),
        3_986
    );
    // The capture re-encodes to itself byte for byte.
    let mut out = BytesMut::new();
    for f in &frames {
        encode_beast(f, &mut out);
    }
    assert!(out[..] == bytes[..]);
    // And the derived AVR-with-MLAT file carries the same MLAT times and payloads.
    if let Some(p) = crate::testkit::shared_data("adsb/ulss7_avr_mlat.txt") {
        let avr = decode_slice(
            &mut crate::ttmrf::raw::HexDecoder::new(),
            &std::fs::read(p).unwrap(),
        );
        assert_eq!(avr.len(), frames.len());
        for (a, b) in avr.iter().zip(&frames) {
            match (a, b) {
                (RawFrame::ModeS(a), RawFrame::ModeS(b)) => {
                    assert_eq!(a.data(), b.data());
                    assert_eq!(a.meta.mlat_ticks, b.meta.mlat_ticks);
                }
                (RawFrame::ModeAc(a), RawFrame::ModeAc(b)) => assert_eq!(a.code, b.code),
                _ => panic!("{a:?} {b:?}"),
            }
        }
    }
}

#[test]
fn every_split_point() {
    let mut v = vec![0x42, 0x1A];
    v.extend_from_slice(MANUAL);
    v.extend_from_slice(&MANUAL[..9]);
    v.extend_from_slice(MANUAL);
    v.extend_from_slice(&[0x1A, 0x31, 0, 0, 0, 0, 0, 1, 0x10, 0x07, 0x77, 0x1A]);
    assert_split_invariant(BeastDecoder::new, &v);
    if let Some(path) = crate::testkit::shared_data("adsb/ulss7_beast.bin") {
        let bytes = std::fs::read(path).unwrap();
        assert_split_invariant(BeastDecoder::new, &bytes[..1500]);
    }
}

#[test]
fn random_and_corrupted_input() {
    assert_survives_random(BeastDecoder::new, 3, 300, 3000);
    if let Some(path) = crate::testkit::shared_data("adsb/ulss7_beast.bin") {
        let bytes = std::fs::read(path).unwrap();
        let mut rng = crate::testkit::XorShift::new(4);
        for _ in 0..20 {
            let start = rng.below(bytes.len() as u64 - 5000) as usize;
            let mut v = bytes[start..start + 5000].to_vec();
            crate::testkit::flip_bits(&mut v, 50, &mut rng);
            let (f, s) = decode_chunked(BeastDecoder::new(), &v, &[1 + rng.below(100) as usize]);
            crate::testkit::assert_accounting(&s, v.len());
            // Most frames survive 50 bit errors in 5000 bytes.
            assert!(f.len() > 100, "{}", f.len());
        }
    }
}

proptest! {
    #[test]
    fn encode_decode_round_trip(
        frames in proptest::collection::vec((any::<[u8; 14]>(), any::<bool>(), 1u64..(1 << 48), 0u8..255), 1..20)
    ) {
        let frames: Vec<RawFrame> = frames
            .into_iter()
            .map(|(bytes, long, t, rssi)| {
                let len = if long { 14 } else { 7 };
                let mut b = [0u8; 14];
                b[..len].copy_from_slice(&bytes[..len]);
                let meta = RxMeta { mlat_ticks: Some(t), rssi: Some(rssi), ..RxMeta::default() };
                RawFrame::ModeS(ModeSFrame { bytes: b, len: len as u8, meta })
            })
            .collect();
        let mut out = BytesMut::new();
        for f in &frames {
            prop_assert!(encode_beast(f, &mut out));
        }
        prop_assert_eq!(decode_slice(&mut BeastDecoder::new(), &out), frames);
    }
}
