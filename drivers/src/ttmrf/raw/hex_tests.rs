//! HEX / HEXd / AVR framing tests: the manual's examples, every payload kind, malformed lines,
//! split points, random input and encoder round trips.

use super::*;
use crate::testkit::{assert_split_invariant, assert_survives_random, decode_chunked};
use crate::{decode_slice, modes::squawk::Squawk};
use proptest::prelude::*;

fn one(line: &[u8]) -> (Vec<RawFrame>, DecodeStats) {
    decode_chunked(HexDecoder::new(), line, &[line.len().max(1)])
}

#[test]
fn manual_short_and_long_examples() {
    // Manual 7.2.2: "*5D4B18FFFC710B; (-70,3,75BCD15,2B5792B49315)\r\n" (the OCR shows '=70').
    // TS1s 0x75BCD15 = 123 456 789 ns; TS24h 0x2B5792B49315 = 47 655 123 456 789 ns
    // (13:14:15.123456789, as the manual says).
    let (f, s) = one(b"*5D4B18FFFC710B; (-70,3,75BCD15,2B5792B49315)\r\n");
    assert_eq!(s.frames_decoded, 1);
    assert_eq!(s.bytes_skipped, 0);
    let RawFrame::ModeS(m) = &f[0] else {
        panic!("{f:?}")
    };
    assert_eq!(m.data(), &[0x5D, 0x4B, 0x18, 0xFF, 0xFC, 0x71, 0x0B]);
    assert_eq!(m.meta.signal_dbm, Some(-70));
    assert_eq!(m.meta.signal_quality, Some(3));
    assert_eq!(m.meta.ts_pps_ns, Some(123_456_789));
    assert_eq!(m.meta.ts_utc_ns, Some(47_655_123_456_789));
    assert!((m.meta.time_s().unwrap() - 47_655.123_456_789).abs() < 1e-9);
    let (f, _) = one(b"*8D4CA7E858B9838206BA422BBD7B; (-71,4,75BCD15,2B5792B49315)\r\n");
    let RawFrame::ModeS(m) = &f[0] else {
        panic!("{f:?}")
    };
    assert_eq!(m.len, 14);
    assert_eq!(m.bytes[0], 0x8D);
    assert_eq!(m.bytes[13], 0x7B);
}

#[test]
fn mode_ac_octal_digits() {
    // Manual: "*7700; (...)": four octal digits.
    let (f, _) = one(b"*7700; (-95,16,75BCD15,2B5792B49315)\r\n");
    assert_eq!(
        f[0],
        RawFrame::ModeAc(ModeAcFrame {
            code: Squawk(0x7700),
            meta: RxMeta {
                signal_dbm: Some(-95),
                signal_quality: Some(16),
                ts_pps_ns: Some(0x75B_CD15),
                ts_utc_ns: Some(0x2B57_92B4_9315),
                ..RxMeta::default()
            }
        })
    );
    let (f, s) = one(b"*0363;\n");
    assert_eq!(f.len(), 1);
    assert_eq!(s.malformed, 0);
    // 8 is not an octal digit.
    let (f, s) = one(b"*0383;\n");
    assert!(f.is_empty());
    assert_eq!(s.malformed, 1);
}

#[test]
fn hexd_and_avr_timestamp_lines() {
    let (f, s) = one(b"*5D4B18FFFC710B;\n*8D4CA7E858B9838206BA422BBD7B;\r\n");
    assert_eq!(f.len(), 2);
    assert_eq!(s.bytes_consumed, s.bytes_consumed - s.bytes_skipped);
    let RawFrame::ModeS(m) = &f[0] else { panic!() };
    assert_eq!(m.meta, RxMeta::default());
    // dump1090 AVR with MLAT: '@' + 12 hex digits of 12 MHz ticks + frame.
    let (f, _) = one(b"@030BF18CC2AB5F4001594B0FBB;\n");
    let RawFrame::ModeS(m) = &f[0] else {
        panic!("{f:?}")
    };
    assert_eq!(m.meta.mlat_ticks, Some(0x030B_F18C_C2AB));
    assert_eq!(m.data(), &[0x5F, 0x40, 0x01, 0x59, 0x4B, 0x0F, 0xBB]);
}

#[test]
fn uat_lines_pass_with_fields() {
    let down = format!("*{};(-70,1,7F0A)\r\n", "0D".repeat(18));
    let (f, _) = one(down.as_bytes());
    let RawFrame::Uat(u) = &f[0] else {
        panic!("{f:?}")
    };
    assert!(!u.uplink);
    assert_eq!(u.bytes.len(), 18);
    assert_eq!(u.meta.signal_dbm, Some(-70));
    assert_eq!(u.meta.ts_pps_ns, Some(0x7F0A));
    let up = format!("*{};\r\n", "A5".repeat(552));
    let (f, s) = one(up.as_bytes());
    assert_eq!(s.frames_decoded, 1);
    let RawFrame::Uat(u) = &f[0] else { panic!() };
    assert!(u.uplink);
    // 20 bytes is neither Mode S nor UAT.
    let (f, s) = one(format!("*{};\n", "00".repeat(20)).as_bytes());
    assert!(f.is_empty());
    assert_eq!(s.malformed, 1);
}

#[test]
fn malformed_lines_are_counted_and_skipped() {
    let bad: &[&[u8]] = &[
        b"*5D4B18FFFC710;\n",        // 13 digits
        b"*5D4B18FFFC710G;\n",       // not hex
        b"*5D4B18FFFC710B\n",        // no ';'
        b"*5D4B18FFFC710B; (x,3)\n", // bad SIGS
        b"*5D4B18FFFC710B; (-70)\n", // one field
        b"*5D4B18FFFC710B; (-70,3,1,2,3)\n",
        b"*5D4B18FFFC710B; junk\n",
        b"@0000000000;\n",
    ];
    for l in bad {
        let (f, s) = one(l);
        assert!(f.is_empty(), "{}", String::from_utf8_lossy(l));
        assert_eq!(s.malformed, 1, "{}", String::from_utf8_lossy(l));
        assert_eq!(s.bytes_skipped, l.len() as u64);
    }
    // A broken frame followed by a good one on the same line: only the broken part goes.
    let (f, s) = one(b"*8D4CA7E8*5D4B18FFFC710B;\n");
    assert_eq!(f.len(), 1);
    assert_eq!((s.malformed, s.bytes_skipped), (1, 9));
    // A complete frame with no line end before the next start byte is still a cut line: it
    // goes (it may have lost its fields), and the next frame is not swallowed with it.
    let (f, s) = one(b"*8D4CA7E858B9838206BA422BBD7B;*5D4B18FFFC710B;\n");
    let [RawFrame::ModeS(m)] = &f[..] else {
        panic!("{f:?}")
    };
    assert_eq!(m.len, 7);
    assert_eq!((s.malformed, s.bytes_skipped), (1, 30));
    // A last line without its newline that does not parse is counted at the end of the stream.
    let (f, s) = one(b"*5D4B18FFFC710G;");
    assert!(f.is_empty());
    assert_eq!((s.malformed, s.bytes_skipped), (1, 16));
    // A line longer than MAX_LINE without an end is dropped without waiting for more.
    let mut long = vec![b'*'];
    long.extend(std::iter::repeat_n(b'0', MAX_LINE + 10));
    long.extend_from_slice(b"\n*5D4B18FFFC710B;\n");
    let (f, s) = one(&long);
    assert_eq!(f.len(), 1);
    assert!(s.malformed >= 1);
}

#[test]
fn extended_field_number_forms() {
    // SIGS and SIGQ: signed decimals of up to five digits, with an optional sign; TS1s and
    // TS24h: up to 16 hex digits (64 bits).
    let meta = |fields: &str| {
        let line = format!("*5D4B18FFFC710B; ({fields})\n");
        match &one(line.as_bytes()).0[..] {
            [RawFrame::ModeS(m)] => Some(m.meta),
            [] => None,
            other => panic!("{other:?}"),
        }
    };
    let m = meta("+5,-12345").unwrap();
    assert_eq!((m.signal_dbm, m.signal_quality), (Some(5), Some(-12_345)));
    let m = meta("-70,3,FFFFFFFFFFFFFFFF,0000000000000001").unwrap();
    assert_eq!((m.ts_pps_ns, m.ts_utc_ns), (Some(u64::MAX), Some(1)));
    for bad in [
        "000001,3",                // six digits
        "-,3",                     // a sign alone
        ",3",                      // empty
        "40000,3",                 // beyond i16
        "-70,3,",                  // empty TS1s
        "-70,3,10000000000000000", // 17 hex digits
    ] {
        assert_eq!(meta(bad), None, "{bad}");
    }
}

fn mixed_stream() -> Vec<u8> {
    let mut v = Vec::new();
    v.extend_from_slice(b"garbage\r\n*5D4B18FFFC710B; (-70,3,75BCD15,2B5792B49315)\r\n");
    v.extend_from_slice(b"\x00\xFF*8D4CA7E858B9838206BA422BBD7B;\n*7700; (-95,1)\r\n");
    v.extend_from_slice(b"@030BF18CC2AB5F4001594B0FBB;\n*12;\n*8D4CA7E8");
    v.extend_from_slice(b"*8D4840D6202CC371C32CE0576098; (-60,2,1,2)\r\n*0363;");
    v
}

#[test]
fn every_split_point() {
    assert_split_invariant(HexDecoder::new, &mixed_stream());
    let (f, s) = decode_chunked(HexDecoder::new(), &mixed_stream(), &[3]);
    // 6 good frames, the last one (no newline) decoded at end of stream.
    assert_eq!(f.len(), 6);
    assert_eq!(s.malformed, 2);
}

#[test]
fn random_input() {
    assert_survives_random(HexDecoder::new, 1, 300, 3000);
    // Random bytes drawn from the line alphabet, which do form frames now and then.
    let mut rng = crate::testkit::XorShift::new(2);
    let alphabet = b"*@;\r\n(),-0123456789ABCDEF";
    for _ in 0..300 {
        let n = rng.below(2000) as usize;
        let v: Vec<u8> = (0..n)
            .map(|_| alphabet[rng.below(alphabet.len() as u64) as usize])
            .collect();
        let (_, s) = decode_chunked(HexDecoder::new(), &v, &[1 + rng.below(40) as usize]);
        crate::testkit::assert_accounting(&s, n);
    }
}

#[test]
fn capture_avr_files_decode_completely() {
    for (name, n) in [
        ("adsb/ulss7_avr.txt", 13_954),
        ("adsb/ulss7_avr_mlat.txt", 13_954),
    ] {
        let Some(path) = crate::testkit::shared_data(name) else {
            continue;
        };
        let bytes = std::fs::read(path).unwrap();
        let mut d = HexDecoder::new();
        let frames = decode_slice(&mut d, &bytes);
        assert_eq!(frames.len(), n, "{name}");
        assert_eq!(d.stats().bytes_skipped, 0, "{name}");
        let ac = frames
            .iter()
            .filter(|f| matches!(f, RawFrame::ModeAc(_)))
            .count();
        assert_eq!(ac, 5026, "{name}");
    }
}

fn arb_meta() -> impl Strategy<Value = RxMeta> {
    (
        proptest::option::of(-128i16..0),
        any::<u8>(),
        proptest::option::of(0u64..1_000_000_000),
        proptest::option::of(0u64..86_400_000_000_000),
    )
        .prop_map(|(sigs, q, pps, utc)| RxMeta {
            signal_dbm: sigs,
            signal_quality: sigs.map(|_| i16::from(q)),
            ts_pps_ns: sigs.and(pps),
            ts_utc_ns: sigs.and(pps).and(utc),
            ..RxMeta::default()
        })
}

proptest! {
    #[test]
    fn encode_decode_round_trip(bytes in any::<[u8; 14]>(), long in any::<bool>(), meta in arb_meta(), ac in 0u16..0o10000) {
        let len = if long { 14 } else { 7 };
        let mut b = [0u8; 14];
        b[..len].copy_from_slice(&bytes[..len]);
        let code = Squawk(((ac >> 9) & 7) << 12 | ((ac >> 6) & 7) << 8 | ((ac >> 3) & 7) << 4 | (ac & 7));
        let frames = vec![
            RawFrame::ModeS(ModeSFrame { bytes: b, len: len as u8, meta }),
            RawFrame::ModeAc(ModeAcFrame { code, meta }),
        ];
        for extended in [true, false] {
            let mut out = BytesMut::new();
            for f in &frames {
                encode_hex(f, extended, &mut out);
            }
            let got = decode_slice(&mut HexDecoder::new(), &out);
            if extended {
                prop_assert_eq!(&got, &frames);
            } else {
                prop_assert_eq!(got.len(), 2);
            }
        }
    }
}
