//! The work every BAHRS frame needs, without the decoder's stream handling: a reference point
//! between the per-frame CRC floor and the decoder (`--bench bahrs`), on the same stream.
//!
//! A separate binary on purpose: with this function in the `bahrs` binary, thin LTO stopped
//! inlining `BytesMut::advance` into the decoder's loop there and the decoder measured about
//! 30 % slower, so the decoder's figure would depend on what else the binary holds.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_drivers::bahrs::Message;
use vigil_drivers::bahrs::frame::{CRC_LEN, HEADER_LEN, crc32_mpeg2, layout};

fn walk(c: &mut Criterion) {
    let (stream, frames) = vigil_benches::bahrs::bahrs_stream(100);
    let mut group = c.benchmark_group("bahrs");
    group.throughput(Throughput::Bytes(stream.len() as u64));
    // A walk over a slice that takes each frame's length from its type, checks its CRC and decodes
    // its payload: no marker or version checks, no counters, no buffer to advance. The decoder's
    // distance above this is what its stream handling costs.
    group.bench_function("walk_crc_and_payload", |b| {
        b.iter(|| {
            let s = black_box(&stream[..]);
            let (mut at, mut n) = (0, 0usize);
            while let Some(&msg_type) = s.get(at + 4) {
                let layout = layout(msg_type).expect("documented type");
                let f = &s[at..at + layout.frame_len()];
                let (body, crc) = f.split_at(f.len() - CRC_LEN);
                assert_eq!(
                    crc32_mpeg2(body),
                    u32::from_le_bytes(crc.try_into().unwrap())
                );
                let payload = &body[HEADER_LEN..HEADER_LEN + layout.payload_len];
                black_box(&Message::decode_payload(msg_type, payload));
                at += f.len();
                n += 1;
            }
            assert_eq!(n, frames);
            n
        })
    });
    group.finish();
}

criterion_group!(benches, walk);
criterion_main!(benches);
