//! Stream-level tests of the ASTERIX decoder: the real CAT021 sample, multi-record blocks, both
//! categories, resynchronisation after garbage, corruption, truncation, every split point,
//! random input and block round trips.

use proptest::prelude::*;

use super::cat021::tests::{FLARM_RECORD, SKIPPING_RECORD};
use super::cat023::{Cat023Record, ServiceType};
use super::common::DataSource;
use super::*;
use crate::testkit::{
    XorShift, assert_accounting, assert_split_invariant, assert_survives_random, decode_chunked,
    flip_bits,
};
use crate::{Codec, Located};

fn decode_all(bytes: &[u8]) -> (Vec<AsterixMessage>, DecodeStats) {
    decode_chunked(AsterixDecoder::default(), bytes, &[bytes.len().max(1)])
}

fn heartbeat() -> AsterixMessage {
    AsterixMessage::Cat023(Box::new(Cat023Record {
        data_source: Some(DataSource { sac: 0, sic: 129 }),
        report_type: Some(1),
        service: Some(ServiceType { sid: 0, styp: 2 }),
        time_of_day_s: Some(100.0),
        ..Default::default()
    }))
}

/// One CAT021 block with three records (FLARM, the skipping record, the FLARM one again), then a
/// CAT023 block.
fn mixed_stream() -> Vec<u8> {
    let mut recs = FLARM_RECORD.to_vec();
    recs.extend_from_slice(SKIPPING_RECORD);
    recs.extend_from_slice(FLARM_RECORD);
    let mut out = Vec::new();
    encode_block(21, &recs, &mut out);
    heartbeat().encode_block(&mut out);
    out
}

#[test]
fn real_sample_stream() {
    let Some(path) = crate::testkit::shared_data("asterix/cat21_re.ast") else {
        return;
    };
    let bytes = std::fs::read(path).unwrap();
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs.len(), 2);
    assert_eq!(stats.frames_decoded, 2);
    assert_eq!(stats.bytes_skipped, 0);
    assert_eq!(stats.malformed + stats.unknown_types, 0);
    let addresses: Vec<u32> = msgs
        .iter()
        .map(|m| m.to_traffic().unwrap().address)
        .collect();
    assert_eq!(addresses, [1, 2]);
    assert_split_invariant(AsterixDecoder::default, &bytes);
    // Offsets of the two blocks: 0 and 44 (the first block's LEN).
    use tokio_util::codec::Decoder;
    let mut codec = Codec(AsterixDecoder::default());
    let mut buf = BytesMut::from(&bytes[..]);
    let mut offsets = Vec::new();
    while let Some(Located { offset, .. }) = codec.decode(&mut buf).unwrap() {
        offsets.push(offset);
    }
    assert_eq!(offsets, [0, 44]);
}

#[test]
fn multi_record_blocks_and_both_categories() {
    let bytes = mixed_stream();
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs.len(), 4);
    assert!(matches!(&msgs[0], AsterixMessage::Cat021(r) if r.target_address == Some(0xDD1234)));
    assert!(matches!(&msgs[1], AsterixMessage::Cat021(r) if r.undecoded.len() == 12));
    assert_eq!(msgs[0], msgs[2]);
    assert_eq!(msgs[3], heartbeat());
    assert!(msgs[3].to_traffic().is_none());
    assert_eq!(stats.frames_decoded, 4);
    assert_eq!(stats.bytes_skipped, 0);
    assert_split_invariant(AsterixDecoder::default, &bytes);
    // The three records of the first block carry its offset, the CAT023 record its own.
    use tokio_util::codec::Decoder;
    let mut codec = Codec(AsterixDecoder::default());
    let mut buf = BytesMut::from(&bytes[..]);
    let mut offsets = Vec::new();
    while let Some(l) = codec.decode(&mut buf).unwrap() {
        offsets.push(l.offset);
    }
    let first_len = u64::from(u16::from_be_bytes([bytes[1], bytes[2]]));
    assert_eq!(offsets, [0, 0, 0, first_len]);
}

#[test]
fn resynchronises_after_garbage() {
    let good = mixed_stream();
    let mut bytes = b"\x00\xFFgarbage\x15\x00".to_vec();
    bytes.extend_from_slice(&good);
    bytes.extend_from_slice(&[0x17, 0x99, 0x42]);
    bytes.extend_from_slice(&good);
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs.len(), 8);
    // The leading 11 garbage bytes and the 3 between the copies are skipped. Only the first
    // failure after a good block counts: the leading garbage (in sync at start: one
    // unknown category) and the 0x17 byte (category 23 with LEN 0x9942 > max: malformed).
    assert_eq!(stats.bytes_skipped, 11 + 3);
    assert_eq!(stats.unknown_types, 1);
    assert_eq!(stats.malformed, 1);
    assert_split_invariant(AsterixDecoder::default, &bytes);
}

#[test]
fn unknown_category_and_bad_lengths() {
    // A CAT048 block (not sent by the module) right at the start: one unknown type, then its
    // bytes are scanned for a block start.
    let mut bytes = vec![48, 0x00, 0x06, 0x80, 0x00, 0x01];
    heartbeat().encode_block(&mut bytes);
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs, [heartbeat()]);
    assert_eq!(stats.unknown_types, 1);
    assert_eq!(stats.bytes_skipped, 6);
    // LEN below the minimum, FSPEC without FRN 1, records not filling LEN exactly.
    for bad in [
        vec![21u8, 0x00, 0x05, 0x80, 0x00],
        vec![21, 0x00, 0x06, 0x40, 0x00, 0x01],
        vec![21, 0x00, 0x07, 0x80, 0x00, 0x01, 0x00],
    ] {
        let mut b = bad.clone();
        heartbeat().encode_block(&mut b);
        let (msgs, stats) = decode_all(&b);
        assert_eq!(msgs, [heartbeat()], "{bad:02X?}");
        assert_eq!(stats.malformed, 1);
        assert_eq!(stats.bytes_skipped, bad.len() as u64);
    }
}

#[test]
fn false_header_before_the_end_of_stream() {
    // 21 0F FF 80: a plausible CAT021 header claiming 4095 octets. Live, the decoder waits for
    // them; at the end of the stream the header is dropped and the real block after it is found.
    let mut bytes = vec![21, 0x0F, 0xFF, 0x80];
    heartbeat().encode_block(&mut bytes);
    let mut d = AsterixDecoder::default();
    let mut buf = BytesMut::from(&bytes[..]);
    assert!(d.decode(&mut buf).is_none());
    assert_eq!(buf.len(), bytes.len());
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs, [heartbeat()]);
    assert_eq!(stats.bytes_skipped, 4);
    assert_eq!(stats.malformed, 1);
}

#[test]
fn tokio_encoder_writes_one_block_per_record() {
    use tokio_util::codec::Encoder;
    let (msgs, _) = decode_all(&mixed_stream());
    let mut dst = BytesMut::new();
    for m in msgs.clone() {
        AsterixEncoder.encode(m, &mut dst).unwrap();
    }
    let (back, stats) = decode_all(&dst);
    assert_eq!(stats.bytes_skipped, 0);
    // Skipped (undecoded) items are not reproduced; everything else is.
    let expected: Vec<AsterixMessage> = msgs
        .into_iter()
        .map(|m| match m {
            AsterixMessage::Cat021(mut r) => {
                r.undecoded.clear();
                AsterixMessage::Cat021(r)
            }
            other => other,
        })
        .collect();
    assert_eq!(back, expected);
}

#[test]
fn block_length_bound() {
    let d = AsterixDecoder::new(100);
    assert_eq!(d.max_block_len(), 100);
    assert_eq!(AsterixDecoder::new(0).max_block_len(), MIN_BLOCK_LEN);
    // A block longer than the bound is not accepted: the decoder never waits for it.
    let mut recs = Vec::new();
    for _ in 0..3 {
        recs.extend_from_slice(FLARM_RECORD);
    }
    let mut bytes = Vec::new();
    encode_block(21, &recs, &mut bytes);
    assert!(bytes.len() > 100);
    let (msgs, stats) = decode_chunked(AsterixDecoder::new(100), &bytes, &[bytes.len()]);
    assert!(msgs.len() < 3);
    assert_accounting(&stats, bytes.len());
    assert!(stats.malformed >= 1);
}

#[test]
fn a_record_with_an_impossible_value_is_dropped_alone_and_counted() {
    // Two records in one block, the first at latitude 100 deg (I021/131 holds +-180 deg): the
    // other is kept, the bad one counted once as an invalid value.
    let (good, _) = cat021::decode_record(FLARM_RECORD).unwrap();
    let mut bad = good.clone();
    let p = bad.position_high_res.or(bad.position).unwrap();
    let moved = cat021::kinematics::Position {
        lat_deg: 100.0,
        ..p
    };
    bad.position = bad.position.map(|_| moved);
    bad.position_high_res = bad.position_high_res.map(|_| moved);
    let mut recs = Vec::new();
    bad.encode(&mut recs);
    good.encode(&mut recs);
    let mut bytes = Vec::new();
    encode_block(21, &recs, &mut bytes);
    let (msgs, stats) = decode_all(&bytes);
    assert_eq!(msgs, vec![AsterixMessage::Cat021(Box::new(good))]);
    assert_eq!((stats.invalid_values, stats.malformed), (1, 0));
    assert_accounting(&stats, bytes.len());
}

#[test]
fn a_false_header_is_refused_by_its_fspec_without_waiting_for_its_length() {
    // CAT 21, LEN 256, then an FSPEC without I021/010 (bit 8 clear): not a block start, refused
    // at once, so the real block after it comes out before 256 octets arrive.
    let mut bytes = vec![21, 0x01, 0x00, 0x00];
    encode_block(21, FLARM_RECORD, &mut bytes);
    let mut d = AsterixDecoder::default();
    let mut buf = BytesMut::from(&bytes[..]);
    assert!(d.decode(&mut buf).is_some());
    // A bad header with exactly its four octets in is refused at once, and the rest skipped.
    let mut buf = BytesMut::from(&[21u8, 0x00, 0x02, 0x80][..]);
    assert!(d.decode(&mut buf).is_none());
    assert!(buf.is_empty());
    assert_eq!(d.stats().malformed, 2);
}

#[test]
fn an_oversized_block_is_cut_at_the_largest_len() {
    // LEN is 16 bits and counts CAT and itself: at most 65,535 octets, 65,532 of records.
    let mut bytes = Vec::new();
    encode_block(21, &[0xAB; 70_000], &mut bytes);
    assert_eq!(bytes.len(), 65_535);
    assert_eq!(bytes[..3], [21, 0xFF, 0xFF]);
    bytes.clear();
    encode_block(21, &[0xAB; 65_532], &mut bytes);
    assert_eq!(
        (bytes.len(), bytes[1..3].to_vec()),
        (65_535, vec![0xFF, 0xFF])
    );
}

#[test]
fn truncated_stream() {
    let bytes = mixed_stream();
    let (all, _) = decode_all(&bytes);
    for cut in 0..bytes.len() {
        let (msgs, stats) = decode_all(&bytes[..cut]);
        assert_accounting(&stats, cut);
        assert!(all.starts_with(&msgs), "cut {cut}");
    }
}

#[test]
fn bit_flips_never_panic_and_account() {
    let clean: Vec<u8> = std::iter::repeat_n(mixed_stream(), 5).flatten().collect();
    let mut rng = XorShift::new(21);
    for round in 0..300 {
        let mut bytes = clean.clone();
        flip_bits(&mut bytes, 1 + round % 6, &mut rng);
        let (_, stats) = decode_all(&bytes);
        assert_accounting(&stats, bytes.len());
    }
}

#[test]
fn random_input() {
    assert_survives_random(AsterixDecoder::default, 23, 200, 3000);
    // Random bytes biased towards plausible block starts.
    let mut rng = XorShift::new(7);
    for _ in 0..200 {
        let bytes: Vec<u8> = (0..600)
            .map(|_| match rng.below(5) {
                0 => 21,
                1 => 23,
                2 => 0,
                _ => rng.next_u64() as u8,
            })
            .collect();
        let (msgs, stats) = decode_chunked(AsterixDecoder::new(64), &bytes, &[17]);
        assert_accounting(&stats, bytes.len());
        for m in msgs {
            let _ = m.to_traffic();
        }
    }
}

proptest! {
    #[test]
    fn blocks_round_trip(seeds in proptest::collection::vec((any::<bool>(), any::<u32>(), any::<u8>()), 1..6)) {
        // Records built from FLARM_RECORD with varied address and SIC, and CAT023 heartbeats.
        let base = super::cat021::decode_record(FLARM_RECORD).unwrap().0;
        let msgs: Vec<AsterixMessage> = seeds
            .iter()
            .map(|&(is21, addr, sic)| {
                if is21 {
                    let mut r = base.clone();
                    r.target_address = Some(addr & 0xFF_FFFF);
                    r.data_source = Some(DataSource { sac: 0, sic });
                    AsterixMessage::Cat021(Box::new(r))
                } else {
                    heartbeat()
                }
            })
            .collect();
        let mut bytes = Vec::new();
        for m in &msgs {
            m.encode_block(&mut bytes);
        }
        let (out, stats) = decode_all(&bytes);
        prop_assert_eq!(out, msgs);
        prop_assert_eq!(stats.bytes_skipped, 0);
    }
}
