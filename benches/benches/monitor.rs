//! The integrity monitor (issue 10, `monitor/`): cost of feeding one payload and evaluating every
//! rule (`Monitor::poll`), as `vigil run` and `vigil monitor` do after each payload.
//!
//! - `attitude_poll_nominal`: one attitude payload + poll with every topic fresh and nothing
//!   alerting (the common case, at the attitude rate).
//! - `attitude_poll_alerting`: the same while a roll miscompare, a BAHRS isolation and 10 traffic
//!   alerts are raised (their reasons are formatted at every poll).
//! - `traffic_300_poll`: one 300-target traffic payload (10 alerting) + poll.

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use vigil_bus::payload::attitude::{
    AXIS_ROLL, ISOLATION_ISOLATED, PAIR_BAHRS_VN200, UNIT_BAHRS, VERDICT_FAIL,
};
use vigil_bus::payload::integrity::{CLOCK_PPS_LOCKED, LINK_OK};
use vigil_bus::payload::ownship::SOURCE_VN200_INS;
use vigil_bus::payload::traffic::{ADDRESS_ICAO, ALERT_CORRECTIVE, ALERT_NONE};
use vigil_bus::{AttitudePayload, IntegrityPayload, OwnshipPayload, Target, TrafficPayload};
use vigil_monitor::{Monitor, MonitorParams};

fn traffic(alerting: usize) -> Box<TrafficPayload> {
    let mut p = Box::<TrafficPayload>::default();
    let targets: Vec<Target> = (0..300u32)
        .map(|i| Target {
            address: 0x400000 + i,
            address_type: ADDRESS_ICAO,
            alert_level: if (i as usize) < alerting {
                ALERT_CORRECTIVE
            } else {
                ALERT_NONE
            },
            horizontal_distance_m: 1000.0 + f64::from(i) * 100.0,
            rel_down_m: -100.0,
            time_to_lowc_s: 30.0,
            ..Target::EMPTY
        })
        .collect();
    p.set_targets(&targets);
    p
}

/// A monitor fed with fresh nominal payloads of every topic, and the attitude payload to feed.
fn setup(alerting: bool) -> (Monitor, AttitudePayload, i64) {
    let mut m = Monitor::new(MonitorParams::default());
    let mut att = AttitudePayload {
        valid: 1,
        ..AttitudePayload::default()
    };
    for u in &mut att.units {
        u.valid = 1;
    }
    if alerting {
        att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_ROLL] = VERDICT_FAIL;
        att.isolation = ISOLATION_ISOLATED;
        att.isolated_unit = UNIT_BAHRS;
    }
    let own = OwnshipPayload {
        valid: 1,
        source: SOURCE_VN200_INS,
        ..OwnshipPayload::default()
    };
    let mut integ = IntegrityPayload {
        clock_status: CLOCK_PPS_LOCKED,
        device_count: 4,
        ..IntegrityPayload::default()
    };
    for d in &mut integ.devices[..4] {
        d.link_state = LINK_OK;
        d.last_message_age_s = 0.01;
    }
    m.ownship(&own);
    m.integrity(&integ);
    m.traffic(&traffic(if alerting { 10 } else { 0 }));
    m.attitude(&att);
    let t = 1_000_000_000_000_000_000;
    m.poll(t);
    (m, att, t)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("monitor");
    // The poll time stays the same in every iteration, so no rule changes state between
    // iterations (no feed falls silent, nothing clears): what is measured is the steady cost of
    // judging every rule.
    for (name, alerting) in [
        ("attitude_poll_nominal", false),
        ("attitude_poll_alerting", true),
    ] {
        let (mut m, att, t) = setup(alerting);
        group.bench_function(name, |b| {
            b.iter(|| {
                m.attitude(black_box(&att));
                black_box(m.poll(black_box(t)))
            })
        });
    }
    let (mut m, _, t) = setup(false);
    let tr = traffic(10);
    group.bench_function("traffic_300_poll", |b| {
        b.iter(|| {
            m.traffic(black_box(&tr));
            black_box(m.poll(black_box(t)))
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
