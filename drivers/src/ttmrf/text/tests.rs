//! Auto-detection over a port that carries every text protocol, plus garbage.

use super::*;
use crate::decode_slice;
use crate::testkit::{
    XorShift, assert_split_invariant, assert_survives_random, decode_chunked, flip_bits,
};

const A1: &str = "#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE";
const FLARM: &str = "#ALRM:0,1600BF,2,13,0,535668736,163101952,61,90,0,20,1,2,-3,3,8,9,-56,0,0";
const JSON: &str = r#"{"src":"ID-0000001","ts":69061337,"ver":1,"flarm":[{"idType":1,"id":"DABABE","type":13,"danger":1},{"idType":2,"id":"1600BF","type":1}]}"#;
const GGA: &str = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";

fn mixed() -> Vec<u8> {
    let mut s = String::new();
    s.push_str("AT+RUN_START\r\n");
    s.push_str(&format!("{A1}\r\n"));
    s.push_str("*8D4CA7E858B9838206BA422BBD7B; (=71, 4, 75BCD15, 2B5792B49315)\r\n");
    s.push_str(&format!("{JSON}\r\n"));
    s.push_str("\x7e\x00\x7fgarbage ABC\r\n");
    s.push_str(&format!("{GGA}\r\n"));
    s.push_str(&format!("{FLARM}\r\n"));
    s.push_str("AT+ERROR (Settings missing, loaded default)\r\n");
    s.push_str(&format!("{}\r\n", A1.replace("A9FE", "A9FF")));
    s.push_str(JSON);
    s.into_bytes()
}

#[test]
fn auto_detects_each_line() {
    let bytes = mixed();
    let mut d = TextDecoder::new(TextMode::Auto);
    let msgs = decode_slice(&mut d, &bytes);
    let kinds: Vec<&str> = msgs
        .iter()
        .map(|m| match m {
            TextMessage::Csv(_) => "csv",
            TextMessage::Json(_) => "json",
            TextMessage::Nmea(_) => "nmea",
            TextMessage::At(_) => "at",
        })
        .collect();
    assert_eq!(kinds, ["at", "csv", "json", "nmea", "csv", "at", "json"]);
    let c = d.counts();
    assert_eq!((c.csv, c.json, c.nmea, c.at, c.raw_mode_s), (2, 2, 1, 2, 1));
    let s = d.stats();
    assert_eq!(s.frames_decoded, 7);
    assert_eq!(s.checksum_failures, 1);
    assert_eq!(s.unknown_types, 1, "the raw Mode S line");
    assert_eq!(s.bytes_consumed, bytes.len() as u64);
    // Traffic: one #A, two JSON FLARM targets, one #ALRM, two more JSON targets.
    let traffic: Vec<_> = msgs.iter().flat_map(TextMessage::traffic_reports).collect();
    let ids: Vec<String> = traffic.iter().map(|t| t.address_hex()).collect();
    assert_eq!(
        ids,
        ["4D240E", "DABABE", "1600BF", "1600BF", "DABABE", "1600BF"]
    );
}

#[test]
fn single_modes_match_their_decoders() {
    let bytes = mixed();
    let mut d = TextDecoder::new(TextMode::Csv);
    assert_eq!(decode_slice(&mut d, &bytes).len(), 2);
    let mut d = TextDecoder::new(TextMode::Json);
    assert_eq!(decode_slice(&mut d, &bytes).len(), 2);
    let mut d = TextDecoder::new(TextMode::Nmea);
    assert_eq!(decode_slice(&mut d, &bytes).len(), 1);
    // The AT decoder sees every printable line (free text included).
    let mut d = TextDecoder::new(TextMode::At);
    let at = decode_slice(&mut d, &bytes);
    assert_eq!(
        at[0],
        TextMessage::At(AtResponse::State {
            event: at::StateEvent::RunStart
        })
    );
}

#[test]
fn every_split_point_all_modes() {
    let bytes = mixed();
    for mode in [
        TextMode::Auto,
        TextMode::Csv,
        TextMode::Json,
        TextMode::Nmea,
        TextMode::At,
    ] {
        assert_split_invariant(|| TextDecoder::new(mode), &bytes);
    }
}

#[test]
fn random_corrupted_and_over_long() {
    assert_survives_random(|| TextDecoder::new(TextMode::Auto), 21, 300, 2000);
    let alphabet = b"#$*{}AT+,:\r\n\"0123456789ABCDEF";
    let mut rng = XorShift::new(4);
    for _ in 0..300 {
        let len = rng.below(500) as usize;
        let bytes: Vec<u8> = (0..len)
            .map(|_| alphabet[rng.below(alphabet.len() as u64) as usize])
            .collect();
        let (_, stats) = decode_chunked(
            TextDecoder::new(TextMode::Auto),
            &bytes,
            &[1 + rng.below(9) as usize],
        );
        crate::testkit::assert_accounting(&stats, len);
    }
    let clean = mixed();
    for _ in 0..300 {
        let mut b = clean.clone();
        flip_bits(&mut b, 3, &mut rng);
        let (_, stats) = decode_chunked(TextDecoder::new(TextMode::Auto), &b, &[13]);
        crate::testkit::assert_accounting(&stats, b.len());
    }
    // An over-long CSV line is dropped; the JSON after it is found.
    let mut b = b"#A:".to_vec();
    b.extend(std::iter::repeat_n(b'7', 3000));
    b.extend_from_slice(format!("\r\n{JSON}\r\n").as_bytes());
    let (out, stats) = decode_chunked(TextDecoder::new(TextMode::Auto), &b, &[64]);
    assert_eq!(out.len(), 1);
    assert_eq!(stats.malformed, 1);
}
