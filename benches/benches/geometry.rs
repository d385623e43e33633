//! One ownship against 1000 intruders: full DO-365 geometry and alert level per intruder
//! (goal <= 100 us for all 1000; DAIDALUS spends 1.6-2.5 us per intruder on this machine).

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_fusion::geometry::{AircraftState, IntruderEcef, OwnshipFrame};

fn intruders(n: usize) -> Vec<AircraftState> {
    let mut x = 7u64;
    let mut next = move || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| AircraftState {
            lat_deg: 47.0 + (next() - 0.5) * 0.6,
            lon_deg: 8.0 + (next() - 0.5) * 0.9,
            alt_m: 300.0 + next() * 3000.0,
            track_deg: next() * 360.0,
            ground_speed_mps: 20.0 + next() * 200.0,
            vertical_rate_mps: (next() - 0.5) * 10.0,
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let own = AircraftState {
        lat_deg: 47.0,
        lon_deg: 8.0,
        alt_m: 1500.0,
        track_deg: 45.0,
        ground_speed_mps: 50.0,
        vertical_rate_mps: 1.0,
    };
    let states = intruders(1000);
    let cached: Vec<IntruderEcef> = states.iter().map(IntruderEcef::new).collect();
    let mut group = c.benchmark_group("geometry");
    // Per fusion step: intruders already in ECEF (converted once per report).
    group.bench_function("1000_intruders_cached_ecef", |b| {
        b.iter(|| {
            let frame = OwnshipFrame::new(black_box(&own));
            let mut alerts = 0u32;
            for i in black_box(&cached) {
                let g = frame.relative(i).geometry();
                alerts += u32::from(g.alert_level);
                black_box(&g);
            }
            alerts
        })
    });
    // From geodetic states: every intruder converted as well.
    group.bench_function("1000_intruders_from_geodetic", |b| {
        b.iter(|| {
            let frame = OwnshipFrame::new(black_box(&own));
            let mut alerts = 0u32;
            for s in black_box(&states) {
                let g = frame.relative(&IntruderEcef::new(s)).geometry();
                alerts += u32::from(g.alert_level);
                black_box(&g);
            }
            alerts
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
