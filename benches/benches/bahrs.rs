//! BAHRS decoding throughput on a long mixed stream (goal: >= 1 GB/s on one core).

use bytes::BytesMut;
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::bahrs::Decoder;
use vigil_drivers::bahrs::frame::{CRC_LEN, crc32_mpeg2, layout};

fn decode_stream(c: &mut Criterion) {
    // 100 s at default rates: 702,000 bytes, 30 100 frames (301 per second).
    let (stream, frames) = vigil_benches::bahrs::bahrs_stream(100);
    let mut group = c.benchmark_group("bahrs");
    group.throughput(Throughput::Bytes(stream.len() as u64));
    group.bench_function(format!("decode_mixed_{}_frames", frames), |b| {
        b.iter_batched(
            || BytesMut::from(&stream[..]),
            |mut buf| {
                let mut d = Decoder::new();
                let mut n = 0usize;
                while let Some(m) = d.decode(&mut buf) {
                    black_box(&m);
                    n += 1;
                }
                assert_eq!(n, frames);
                n
            },
            BatchSize::LargeInput,
        )
    });
    // The floor: the decoder's own CRC function alone over the same bytes, in one call (no frame
    // boundaries, so no per-call overhead). Decode throughput is judged as a fraction of this.
    group.bench_function("crc32_mpeg2_floor", |b| {
        b.iter(|| crc32_mpeg2(black_box(&stream[..])))
    });
    // The floor as the decoder meets it: one CRC call per frame over its covered bytes (the
    // stream is back-to-back frames; each frame's length comes from its type).
    let mut frames_at = Vec::new();
    let mut at = 0;
    while at < stream.len() {
        assert_eq!(&stream[at..at + 2], b"NE", "frame at byte {at}");
        let len = layout(stream[at + 4]).expect("documented type").frame_len();
        frames_at.push((at, len));
        at += len;
    }
    group.bench_function("crc32_mpeg2_per_frame_floor", |b| {
        b.iter(|| {
            let s = black_box(&stream[..]);
            let mut bad = 0usize;
            for &(at, len) in &frames_at {
                let f = &s[at..at + len];
                let crc = u32::from_le_bytes(f[len - CRC_LEN..].try_into().unwrap());
                bad += usize::from(crc32_mpeg2(&f[..len - CRC_LEN]) != crc);
            }
            assert_eq!(bad, 0);
            bad
        })
    });
    group.finish();
}

criterion_group!(benches, decode_stream);
criterion_main!(benches);
