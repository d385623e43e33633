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
//! - group `modes_cpu`: `beast_mix`, `beast_df17` and `hex_df17` again, timed in the thread's
//!   own CPU time ([`cpu_time`]), which stays meaningful when other builds share
//!   the machine's two cores.

use bytes::BytesMut;
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_benches::modes as b;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::modes::{DecodeOptions, ModesDecoder, TrackerConfig};
use vigil_drivers::ttmrf::raw::RawFrame;

use cpu_time::ThreadCpuTime;

/// A criterion `Measurement` of the benchmark thread's own CPU time
/// (`clock_gettime(CLOCK_THREAD_CPUTIME_ID)`, nanoseconds), so that figures taken on a machine
/// shared with other builds measure our code rather than the scheduler. 64-bit Linux only;
/// where the call fails it reads 0 and the bench says its figures are meaningless.
mod cpu_time {
    use criterion::Throughput;
    use criterion::measurement::{Measurement, ValueFormatter};

    #[repr(C)]
    struct Timespec {
        tv_sec: i64,
        tv_nsec: i64,
    }

    unsafe extern "C" {
        fn clock_gettime(clock_id: i32, tp: *mut Timespec) -> i32;
    }

    /// Linux `CLOCK_THREAD_CPUTIME_ID`.
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;

    /// CPU time of the calling thread, ns (0 when unavailable).
    pub fn thread_cpu_ns() -> u64 {
        let mut ts = Timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable timespec (two 64-bit fields on 64-bit Linux, the
        // only target this bench claims), and clock_gettime only writes through the pointer.
        let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        if rc != 0 {
            return 0;
        }
        (ts.tv_sec as u64)
            .wrapping_mul(1_000_000_000)
            .wrapping_add(ts.tv_nsec as u64)
    }

    /// The measurement: thread CPU time in ns.
    #[derive(Debug, Clone, Copy, Default)]
    pub struct ThreadCpuTime;

    /// Formats nanoseconds and elements per second.
    #[derive(Debug, Clone, Copy, Default)]
    pub struct CpuFormatter;

    impl ValueFormatter for CpuFormatter {
        fn scale_values(&self, typical_value: f64, values: &mut [f64]) -> &'static str {
            let (div, unit) = match typical_value {
                t if t < 1e3 => (1.0, "ns cpu"),
                t if t < 1e6 => (1e3, "µs cpu"),
                t if t < 1e9 => (1e6, "ms cpu"),
                _ => (1e9, "s cpu"),
            };
            values.iter_mut().for_each(|v| *v /= div);
            unit
        }

        fn scale_throughputs(
            &self,
            typical_value: f64,
            throughput: &Throughput,
            values: &mut [f64],
        ) -> &'static str {
            let n = match *throughput {
                Throughput::Elements(n) | Throughput::ElementsAndBytes { elements: n, .. } => {
                    n as f64
                }
                Throughput::Bytes(n) | Throughput::BytesDecimal(n) | Throughput::Bits(n) => {
                    n as f64
                }
            };
            let per_s = n * 1e9 / typical_value.max(1e-9);
            let (div, unit) = if per_s >= 1e6 {
                (1e6, "Melem/s cpu")
            } else {
                (1e3, "Kelem/s cpu")
            };
            values
                .iter_mut()
                .for_each(|v| *v = n * 1e9 / v.max(1e-9) / div);
            unit
        }

        fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
            "ns"
        }
    }

    impl Measurement for ThreadCpuTime {
        type Intermediate = u64;
        type Value = u64;

        fn start(&self) -> u64 {
            thread_cpu_ns()
        }
        fn end(&self, i: u64) -> u64 {
            thread_cpu_ns().saturating_sub(i)
        }
        fn add(&self, a: &u64, b: &u64) -> u64 {
            a + b
        }
        fn zero(&self) -> u64 {
            0
        }
        fn to_f64(&self, v: &u64) -> f64 {
            *v as f64
        }
        fn formatter(&self) -> &dyn ValueFormatter {
            &CpuFormatter
        }
    }
}

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

fn bench_cpu(c: &mut Criterion<ThreadCpuTime>) {
    if cpu_time::thread_cpu_ns() == 0 {
        eprintln!("modes bench: no per-thread CPU time on this system; modes_cpu is meaningless");
    }
    let capture = b::beast_capture();
    let frames = b::mode_s_frames(&capture);
    let df17 = b::df17_only(&frames);
    let df17_beast = b::to_beast(&df17);
    let df17_hex = b::to_hex(&df17);
    let cfg = TrackerConfig {
        emit_reports: false,
        ..TrackerConfig::default()
    };
    let opts = DecodeOptions::default();
    let mut g = c.benchmark_group("modes_cpu");
    g.throughput(Throughput::Elements(frames.len() as u64));
    g.bench_function("beast_mix", |bn| {
        bn.iter(|| drain(&mut ModesDecoder::beast(cfg, opts), black_box(&capture)))
    });
    g.throughput(Throughput::Elements(df17.len() as u64));
    g.bench_function("beast_df17", |bn| {
        bn.iter(|| drain(&mut ModesDecoder::beast(cfg, opts), black_box(&df17_beast)))
    });
    g.bench_function("hex_df17", |bn| {
        bn.iter(|| drain(&mut ModesDecoder::hex(cfg, opts), black_box(&df17_hex)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_group! {
    name = benches_cpu;
    config = Criterion::default().with_measurement(ThreadCpuTime);
    targets = bench_cpu
}
criterion_main!(benches, benches_cpu);
