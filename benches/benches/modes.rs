//! Mode S decoding throughput on the real Beast capture (`shared/data/adsb/ulss7_beast.bin`,
//! read in place; synthetic frames when it is absent).
//!
//! - `beast_mix`: the whole capture (8 928 Mode S + 5 026 Mode A/C frames) through framing,
//!   parity, decoding and the tracker; throughput counted in Mode S frames.
//! - `beast_df17`: only the capture's 3 436 DF17 frames, re-encoded as Beast, same pipeline.
//! - `hex_df17`: the same DF17 frames as HEX lines with extended fields.
//! - `frame_df17`: parity + decode of already-framed DF17 frames, no framing, no tracker.
//! - `*_reports`: as above with traffic reports built (one `TrafficReport` per position or
//!   velocity frame of a located aircraft).

use bytes::BytesMut;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_benches::modes as b;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::modes::{DecodeOptions, ModesDecoder, TrackerConfig};
use vigil_drivers::ttmrf::raw::RawFrame;

fn drain<D: DeviceDecoder>(d: &mut D, bytes: &[u8]) -> usize {
    let mut buf = BytesMut::from(bytes);
    let mut n = 0;
    while let Some(m) = d.decode(&mut buf) {
        black_box(&m);
        n += 1;
    }
    n
}

fn bench(c: &mut Criterion) {
    let capture = b::beast_capture();
    let frames = b::mode_s_frames(&capture);
    let df17 = b::df17_only(&frames);
    let df17_beast = b::to_beast(&df17);
    let df17_hex = b::to_hex(&df17);
    let cfg = TrackerConfig {
        emit_reports: false,
        ..TrackerConfig::default()
    };
    let cfg_reports = TrackerConfig::default();
    let opts = DecodeOptions::default();

    let mut g = c.benchmark_group("modes");
    g.throughput(Throughput::Elements(frames.len() as u64));
    g.bench_function("beast_mix", |bn| {
        bn.iter(|| drain(&mut ModesDecoder::beast(cfg, opts), black_box(&capture)))
    });
    g.bench_function("beast_mix_reports", |bn| {
        bn.iter(|| {
            drain(
                &mut ModesDecoder::beast(cfg_reports, opts),
                black_box(&capture),
            )
        })
    });
    g.throughput(Throughput::Elements(df17.len() as u64));
    g.bench_function("beast_df17", |bn| {
        bn.iter(|| drain(&mut ModesDecoder::beast(cfg, opts), black_box(&df17_beast)))
    });
    g.bench_function("beast_df17_reports", |bn| {
        bn.iter(|| {
            drain(
                &mut ModesDecoder::beast(cfg_reports, opts),
                black_box(&df17_beast),
            )
        })
    });
    g.bench_function("hex_df17", |bn| {
        bn.iter(|| drain(&mut ModesDecoder::hex(cfg, opts), black_box(&df17_hex)))
    });
    let raw: Vec<[u8; 14]> = df17
        .iter()
        .filter_map(|f| match f {
            RawFrame::ModeS(m) => Some(m.bytes),
            _ => None,
        })
        .collect();
    g.bench_function("frame_df17", |bn| {
        bn.iter(|| {
            let mut ok = 0;
            for f in black_box(&raw) {
                if vigil_drivers::modes::decode(f, opts).is_ok() {
                    ok += 1;
                }
            }
            ok
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
