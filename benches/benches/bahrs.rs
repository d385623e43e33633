//! BAHRS decoding throughput on a long mixed stream (goal: >= 1 GB/s on one core).

use bytes::BytesMut;
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::bahrs::Decoder;

fn decode_stream(c: &mut Criterion) {
    // 100 s at default rates: about 3.3 MB, 30 100 frames (301 per second).
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
    group.finish();
}

criterion_group!(benches, decode_stream);
criterion_main!(benches);
