//! The mixed port decoder against the text and HEX decoders run on each protocol's lines alone,
//! the manual's examples, hand-counted offsets, split points, random and damaged streams.

use super::*;
use crate::decode_slice;
use crate::testkit::{
    XorShift, assert_accounting, assert_split_invariant, assert_survives_random, decode_chunked,
    flip_bits,
};
use crate::ttmrf::raw::HexDecoder;
use crate::ttmrf::text::{TextDecoder, TextMode};

// Manual 7.2.1 CSV example (CRC A9FE), 7.2.2 HEX examples, 9.2.1 NMEA, 6.6 JSON.
const A1: &str = "#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE";
const HEX_LONG: &str = "*8D4CA7E858B9838206BA422BBD7B; (-71,4,75BCD15,2B5792B49315)";
const HEX_SHORT: &str = "*5D4B18FFFC710B; (-70,3,75BCD15,2B5792B49315)";
const MODE_AC: &str = "*7700; (-95,16,75BCD15,2B5792B49315)";
const AVR: &str = "@030BF18CC2AB5F4001594B0FBB;";
const JSON: &str = r#"{"src":"ID-0000001","ts":69061337,"ver":1,"flarm":[{"idType":1,"id":"DABABE","type":13,"danger":1}]}"#;
const GGA: &str = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";

/// The port's lines, in order, each with its line end.
fn lines() -> Vec<String> {
    [
        "AT+RUN_START",
        A1,
        HEX_LONG,
        JSON,
        HEX_SHORT,
        GGA,
        MODE_AC,
        AVR,
        "AT+ERROR (Settings missing, loaded default)",
    ]
    .iter()
    .map(|l| format!("{l}\r\n"))
    .collect()
}

fn port() -> Vec<u8> {
    lines().concat().into_bytes()
}

fn is_raw(line: &str) -> bool {
    line.starts_with('*') || line.starts_with('@')
}

#[test]
fn decodes_both_kinds_in_stream_order_at_their_offsets() {
    let lines = lines();
    let bytes = port();
    let mut d = MixedDecoder::new();
    let mut buf = BytesMut::from(&bytes[..]);
    let mut got = Vec::new();
    while let Some(m) = d.decode(&mut buf) {
        got.push((d.stats().last_frame_start, m));
    }
    assert!(d.decode_eof(&mut buf).is_none());
    // Offsets: the running sum of the line lengths before each line.
    let mut offset = 0u64;
    let mut expected_offsets = Vec::new();
    for l in &lines {
        expected_offsets.push(offset);
        offset += l.len() as u64;
    }
    assert_eq!(got.len(), lines.len());
    for ((off, m), (line, want)) in got.iter().zip(lines.iter().zip(&expected_offsets)) {
        assert_eq!(off, want, "{line}");
        assert_eq!(matches!(m, MixedMessage::Raw(_)), is_raw(line), "{line}");
    }
    // Each message is what the protocol's own decoder makes of its line alone.
    for ((_, m), line) in got.iter().zip(&lines) {
        match m {
            MixedMessage::Raw(f) => {
                assert_eq!(
                    decode_slice(&mut HexDecoder::new(), line.as_bytes()),
                    vec![f.clone()]
                )
            }
            MixedMessage::Text(t) => assert_eq!(
                decode_slice(&mut TextDecoder::new(TextMode::Auto), line.as_bytes()),
                vec![t.clone()]
            ),
        }
    }
    let s = d.stats();
    assert_eq!(s.bytes_consumed, bytes.len() as u64);
    assert_eq!(s.bytes_skipped, 0);
    assert_eq!(s.frames_decoded, 9);
    assert_eq!(
        (s.malformed, s.unknown_types, s.checksum_failures),
        (0, 0, 0)
    );
    let c = d.counts();
    assert_eq!((c.csv, c.json, c.nmea, c.at, c.raw_mode_s), (1, 1, 1, 2, 4));
    // Manual 7.2.2: TS24h 0x2B5792B49315 = 47 655 123 456 789 ns.
    let MixedMessage::Raw(RawFrame::ModeS(f)) = &got[2].1 else {
        panic!("{:?}", got[2])
    };
    assert_eq!(f.meta.ts_utc_ns, Some(47_655_123_456_789));
    assert_eq!(f.data()[0], 0x8D);
}

#[test]
fn every_split_point_and_byte_at_a_time() {
    assert_split_invariant(MixedDecoder::new, &port());
    // With garbage between the lines, a damaged line and no final line end.
    let mut b = b"\x00\xffnoise*ZZ;\r\n".to_vec();
    b.extend(port());
    b.extend_from_slice(b"#A:1,\r\n~~");
    b.extend_from_slice(HEX_SHORT.as_bytes());
    assert_split_invariant(MixedDecoder::new, &b);
}

#[test]
fn a_raw_line_cut_short_loses_only_itself() {
    // "*8D4CA7E8" lost its end; the CSV line glued to it is still decoded. The 9 bytes of the cut
    // line are one malformed frame.
    let s = format!("*8D4CA7E8{A1}\r\n{HEX_SHORT}\r\n");
    let (out, stats) = decode_chunked(MixedDecoder::new(), s.as_bytes(), &[7]);
    assert_eq!(out.len(), 2);
    assert!(matches!(out[0], MixedMessage::Text(TextMessage::Csv(_))));
    assert!(matches!(out[1], MixedMessage::Raw(_)));
    assert_eq!(stats.malformed, 1);
    assert_eq!(stats.bytes_skipped, 9);
    // A raw line whose payload is not a frame (5 hex digits) is malformed, line end included.
    let s = format!("*12345;\r\n{GGA}\r\n");
    let (out, stats) = decode_chunked(MixedDecoder::new(), s.as_bytes(), &[64]);
    assert_eq!(out.len(), 1);
    assert_eq!((stats.malformed, stats.bytes_skipped), (1, 9));
}

#[test]
fn last_line_without_its_end_and_truncated_streams() {
    // The stream ends right after the ';' of a HEXd line: still a frame (as the HEX decoder).
    let (out, stats) = decode_chunked(MixedDecoder::new(), b"*5D4B18FFFC710B;", &[3]);
    assert_eq!(out.len(), 1);
    assert_eq!(stats.bytes_skipped, 0);
    // Cut inside the payload: malformed, every byte counted.
    let bytes = port();
    for cut in 0..bytes.len() {
        let (out, stats) = decode_chunked(MixedDecoder::new(), &bytes[..cut], &[5]);
        assert_accounting(&stats, cut);
        // Every complete line before the cut is decoded.
        let complete = lines()
            .iter()
            .scan(0, |end, l| {
                *end += l.len();
                Some(*end)
            })
            .filter(|&end| end <= cut)
            .count();
        assert!(out.len() >= complete, "cut at {cut}");
    }
}

#[test]
fn over_long_raw_line_is_dropped_and_the_next_line_found() {
    let mut b = b"*".to_vec();
    b.extend(std::iter::repeat_n(b'A', 3000));
    b.extend_from_slice(format!("\r\n{A1}\r\n").as_bytes());
    let (out, stats) = decode_chunked(MixedDecoder::new(), &b, &[100]);
    assert_eq!(out.len(), 1);
    assert!(stats.malformed >= 1);
    assert_accounting(&stats, b.len());
}

#[test]
fn lines_after_an_over_long_json_object_are_decoded() {
    // A JSON object longer than the framer's 64 KiB bound is dropped up to its line end; the raw
    // and CSV lines after it are the port's next messages (not skipped up to the next `{`).
    let mut b = br#"{"src":""#.to_vec();
    b.extend(std::iter::repeat_n(b'x', 70_000));
    b.extend_from_slice(format!("\"}}\r\n{HEX_SHORT}\r\n{A1}\r\n").as_bytes());
    let (out, stats) = decode_chunked(MixedDecoder::new(), &b, &[4096]);
    assert_eq!(out.len(), 2, "{stats:?}");
    assert!(matches!(out[0], MixedMessage::Raw(_)));
    assert!(matches!(out[1], MixedMessage::Text(TextMessage::Csv(_))));
    assert_eq!(stats.malformed, 1);
    assert_accounting(&stats, b.len());
    // The text decoder alone finds the CSV line too.
    let (out, _) = decode_chunked(TextDecoder::new(TextMode::Auto), &b, &[4096]);
    assert_eq!(out.len(), 1);
}

#[test]
fn random_garbage_interleaved_and_bit_flips() {
    assert_survives_random(MixedDecoder::new, 66, 300, 2000);
    let mut rng = XorShift::new(6);
    // Alphabet of both protocols: start bytes, hex digits, separators.
    let alphabet = b"#$*@{}AT+,:;()-\r\n\"0123456789ABCDEF ";
    for _ in 0..300 {
        let len = rng.below(600) as usize;
        let bytes: Vec<u8> = (0..len)
            .map(|_| alphabet[rng.below(alphabet.len() as u64) as usize])
            .collect();
        let (_, stats) = decode_chunked(MixedDecoder::new(), &bytes, &[1 + rng.below(9) as usize]);
        assert_accounting(&stats, len);
    }
    // Garbage between every line: every message is still found.
    let mut b = Vec::new();
    for l in lines() {
        let mut g = [0u8; 5];
        rng.fill(&mut g);
        // Random bytes without any start byte or line end.
        for x in &mut g {
            if matches!(*x, b'#' | b'$' | b'{' | b'A' | b'*' | b'@' | b'\n') {
                *x = b'.';
            }
        }
        b.extend_from_slice(&g);
        b.extend_from_slice(l.as_bytes());
    }
    let (out, stats) = decode_chunked(MixedDecoder::new(), &b, &[17]);
    assert_eq!(out.len(), lines().len());
    assert_eq!(stats.bytes_skipped, 5 * lines().len() as u64);
    // Bit errors: never a panic, accounting holds, splits agree.
    let clean = port();
    for _ in 0..200 {
        let mut b = clean.clone();
        flip_bits(&mut b, 3, &mut rng);
        let (_, stats) = decode_chunked(MixedDecoder::new(), &b, &[13]);
        assert_accounting(&stats, b.len());
    }
    let mut b = clean;
    flip_bits(&mut b, 5, &mut rng);
    assert_split_invariant(MixedDecoder::new, &b);
}
