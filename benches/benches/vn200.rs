//! VN-200 decoder throughput on a stream of 112-byte Common-group binary messages (TimeGps, Ypr,
//! Quaternion, AngularRate, PosLla, VelNed, Accel, InsStatus, TimeGpsPps), every message fully
//! decoded into typed fields. Reference: VnSDK 0.99 parses 1.43 M such messages/s (160 MB/s) on
//! one core of the project machine; the goal is >= 7 M msgs/s.
//!
//! Two measurements of the same work: wall-clock time (criterion's default) and the thread's CPU
//! time (`CLOCK_THREAD_CPUTIME_ID`). On the shared 2-core machine, with other builds running,
//! wall-clock figures mostly measure the scheduler; CPU time measures the decoder.

use std::hint::black_box;

use bytes::BytesMut;
use std::time::Duration;

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use vigil_drivers::DeviceDecoder;
use vigil_drivers::vn200::binary::{BinaryOutput, CommonGroup, Lla, Quaternion, Ypr};
use vigil_drivers::vn200::crc::crc16;
use vigil_drivers::vn200::status::InsStatus;
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};

/// Messages per benchmark iteration.
const N: usize = 10_000;

fn message(i: u64) -> BinaryOutput {
    let f = i as f32;
    BinaryOutput {
        common: Some(CommonGroup {
            time_gps_ns: Some(1_400_000_000_000_000_000 + i * 2_500_000),
            ypr: Some(Ypr {
                yaw_deg: f * 0.01,
                pitch_deg: 1.5,
                roll_deg: -2.25,
            }),
            quaternion: Some(Quaternion {
                x: 0.1,
                y: 0.2,
                z: 0.3,
                s: 0.9,
            }),
            angular_rate_radps: Some([0.01, -0.02, f * 1e-4]),
            pos_lla: Some(Lla {
                lat_deg: 32.9 + f64::from(f) * 1e-7,
                lon_deg: -96.7,
                alt_m: 166.0,
            }),
            vel_ned_mps: Some([1.0, 2.0, -0.5]),
            accel_mps2: Some([0.1, 0.2, -9.8]),
            ins_status: Some(InsStatus(0x8086)),
            time_gps_pps_ns: Some(i * 2_500_000 % 1_000_000_000),
            ..Default::default()
        }),
        ..Default::default()
    }
}

fn stream() -> Vec<u8> {
    let mut s = Vec::with_capacity(N * 112);
    for i in 0..N as u64 {
        message(i).encode_into(&mut s);
    }
    assert_eq!(s.len(), N * 112);
    s
}

/// Decodes the whole buffer, looking at each message in place (by reference, as a consumer
/// that dispatches on it would).
fn decode_all(buf: &mut BytesMut) -> usize {
    let mut d = Vn200Decoder::new();
    let mut n = 0;
    loop {
        let m = d.decode(buf);
        match &m {
            Some(Vn200Message::Binary(b)) => {
                black_box(b);
                n += 1;
            }
            Some(_) => {}
            None => break,
        }
    }
    n
}

/// Decodes the whole buffer with [`Vn200Decoder::decode_into`], every message written in place
/// into one reused box (as the ingest stage decodes into its recycled boxes, issue 21).
fn decode_all_into(buf: &mut BytesMut) -> usize {
    let mut d = Vn200Decoder::new();
    let mut m = Box::new(Vn200Message::Binary(BinaryOutput::default()));
    let mut n = 0;
    while d.decode_into(buf, &mut m) {
        if let Vn200Message::Binary(b) = &*m {
            black_box(b);
            n += 1;
        }
    }
    n
}

/// CPU time of the calling thread.
struct ThreadCpuTime;

fn thread_cpu_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes it.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    assert_eq!(rc, 0, "clock_gettime(CLOCK_THREAD_CPUTIME_ID)");
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

static WALL: WallTime = WallTime;

impl Measurement for ThreadCpuTime {
    type Intermediate = u64;
    type Value = Duration;

    fn start(&self) -> u64 {
        thread_cpu_ns()
    }
    fn end(&self, start: u64) -> Duration {
        Duration::from_nanos(thread_cpu_ns().saturating_sub(start))
    }
    fn add(&self, a: &Duration, b: &Duration) -> Duration {
        *a + *b
    }
    fn zero(&self) -> Duration {
        Duration::ZERO
    }
    fn to_f64(&self, v: &Duration) -> f64 {
        v.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        // Values are nanoseconds, as for wall time: reuse its formatting.
        WALL.formatter()
    }
}

fn bench_cpu(c: &mut Criterion<ThreadCpuTime>) {
    let s = stream();
    let setup = || BytesMut::from(&s[..]);
    let mut g = c.benchmark_group("vn200_common_112_cpu");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("msgs", |b| {
        b.iter_batched_ref(setup, decode_all, BatchSize::LargeInput)
    });
    // The same work through `decode_into` (the caller owns the message).
    g.bench_function("msgs_into", |b| {
        b.iter_batched_ref(setup, decode_all_into, BatchSize::LargeInput)
    });
    g.throughput(Throughput::Bytes(s.len() as u64));
    g.bench_function("bytes", |b| {
        b.iter_batched_ref(setup, decode_all, BatchSize::LargeInput)
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    let s = stream();
    assert_eq!(decode_all(&mut BytesMut::from(&s[..])), N);
    assert_eq!(decode_all_into(&mut BytesMut::from(&s[..])), N);
    // The input buffer is copied in the (unmeasured) setup: only decoding is timed.
    let setup = || BytesMut::from(&s[..]);
    let mut g = c.benchmark_group("vn200_common_112");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("msgs", |b| {
        b.iter_batched_ref(setup, decode_all, BatchSize::LargeInput)
    });
    // The same work through `decode_into` (the caller owns the message).
    g.bench_function("msgs_into", |b| {
        b.iter_batched_ref(setup, decode_all_into, BatchSize::LargeInput)
    });
    g.throughput(Throughput::Bytes(s.len() as u64));
    g.bench_function("bytes", |b| {
        b.iter_batched_ref(setup, decode_all, BatchSize::LargeInput)
    });
    g.finish();
    // The floor: the decoder's CRC-16 alone, message by message over the bytes it covers (all but
    // the 0xFA sync byte), as the decoder calls it.
    let mut g = c.benchmark_group("vn200_crc16_112");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("msgs", |b| {
        b.iter(|| {
            let mut acc = 0u16;
            for m in black_box(&s[..]).chunks_exact(112) {
                acc |= crc16(&m[1..]);
            }
            assert_eq!(
                acc, 0,
                "every message's CRC over header, payload and CRC is zero"
            );
            acc
        })
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
