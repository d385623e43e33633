//! The attitude and health cross-check (issue 8): one comparison step per BAHRS sample.
//!
//! - `compare_step`: one `AttitudeChecker::compare_at` (interpolation of the VN-200 and Watson by
//!   slerp, declination from the cache, gates, three pairs x three axes with both detectors and
//!   persistence, joint chi-square, isolation, vote, vertical channel, record);
//! - `stream_60s`: a whole 60 s synthetic stream (3000 BAHRS, 3000 VN-200, 711 Watson samples)
//!   through push and next_record, reported per BAHRS sample (Elements = BAHRS samples).
//!
//! - `prompt_step`: one `AttitudeChecker::prompt` (issue 10: the voted attitude at a VN-200
//!   sample's time, published for every VN-200 message, 200-400 a second), after 45 s of the
//!   stream with its records taken, so the verdicts are fresh.
//!
//! All with the WMM2025 declination model (refreshed every 60 s, so the step uses the cache).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_fusion::attitude::checker::AttitudeChecker;
use vigil_fusion::attitude::isolation::Unit;
use vigil_fusion::attitude::params::CheckParams;
use vigil_fusion::attitude::synthetic::{Event, Scenario, Stream};
use vigil_fusion::magnetic::Wmm;

fn checker() -> AttitudeChecker {
    AttitudeChecker::new(CheckParams::default(), Box::new(Wmm)).expect("default parameters")
}

fn bench(c: &mut Criterion) {
    let sc = Scenario {
        duration_s: 60.0,
        ..Default::default()
    };
    let events: Vec<Event> = Stream::new(sc).collect();
    let n_bahrs = events
        .iter()
        .filter(|e| matches!(e, Event::Bahrs(_)))
        .count() as u64;

    // One step: buffers hold 2 s of VN-200 and Watson around a BAHRS sample at t = 45 s
    // (mid-turn, banked), as they do in steady state.
    let mut ch = checker();
    let mut probe = None;
    for e in &events {
        match e {
            Event::Vn200(v) if (44.0e9..46.0e9).contains(&((v.t_gps_ns - sc.t0_gps_ns) as f64)) => {
                ch.push_vn200(*v)
            }
            Event::Watson(w)
                if (44.0e9..46.0e9).contains(&((w.t_gps_ns - sc.t0_gps_ns) as f64)) =>
            {
                ch.push_watson(*w)
            }
            Event::Bahrs(b) if probe.is_none() && b.t_gps_ns - sc.t0_gps_ns >= 45_000_000_000 => {
                probe = Some(*b)
            }
            _ => {}
        }
    }
    let probe = probe.expect("a BAHRS sample at 45 s");
    let mut group = c.benchmark_group("attitude");
    group.throughput(Throughput::Elements(1));
    group.bench_function("compare_step", |bch| {
        bch.iter(|| black_box(ch.compare_at(black_box(&probe), false)))
    });
    group.throughput(Throughput::Elements(n_bahrs));
    group.bench_function("stream_60s", |bch| {
        bch.iter(|| {
            let mut ch = checker();
            let mut n = 0usize;
            for e in &events {
                match e {
                    Event::Bahrs(b) => ch.push_bahrs(*b),
                    Event::Vn200(v) => ch.push_vn200(*v),
                    Event::Watson(w) => ch.push_watson(*w),
                }
                while let Some(r) = ch.next_record() {
                    n += usize::from(r.fault);
                    black_box(&r);
                }
            }
            n
        })
    });
    // The prompt at steady state: the stream up to 45 s through the checker, then a prompt at
    // each iteration's time, 1 ns after the one before (prompt times must increase).
    let mut ch = checker();
    let mut t_last = 0;
    for e in &events {
        let t = match e {
            Event::Bahrs(b) => b.t_gps_ns,
            Event::Vn200(v) => v.t_gps_ns,
            Event::Watson(w) => w.t_gps_ns,
        };
        if t - sc.t0_gps_ns > 45_000_000_000 {
            break;
        }
        match e {
            Event::Bahrs(b) => ch.push_bahrs(*b),
            Event::Vn200(v) => {
                ch.push_vn200(*v);
                t_last = v.t_gps_ns;
            }
            Event::Watson(w) => ch.push_watson(*w),
        }
        while ch.next_record().is_some() {}
    }
    group.throughput(Throughput::Elements(1));
    let mut t = t_last;
    group.bench_function("prompt_step", |bch| {
        bch.iter(|| {
            t += 1;
            black_box(ch.prompt(black_box(t), Unit::Vn200).expect("a later time"))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
