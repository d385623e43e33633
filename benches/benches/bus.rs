//! iceoryx2 bus latency in one process: publish (loan, copy, stamp, send, event notify) plus
//! receive, for the small attitude payload and the full 1024-target traffic payload, and a
//! two-thread ping-pong where the receiver sleeps on the event service (the wake-up path a
//! consumer uses). The issue quotes iceoryx2 alone at about 15 us median between two processes
//! with event wake-up.

use std::hint::black_box;
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use vigil_bus::{AttitudePayload, Bus, BusConfig, OwnshipPayload, Target, TrafficPayload};

fn bus(prefix: &str, node: &str) -> Bus {
    Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: node.to_string(),
        ..BusConfig::default()
    })
    .expect("bus")
}

fn prefix(name: &str) -> String {
    static N: AtomicU32 = AtomicU32::new(0);
    format!(
        "vigil-bench-{}-{}-{name}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    )
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("bus");

    // Same thread: publish one attitude, receive it.
    let b = bus(&prefix("att"), "bench");
    let mut publ = b.publisher::<AttitudePayload>().unwrap();
    let mut sub = b.subscriber::<AttitudePayload>().unwrap();
    let att = AttitudePayload::default();
    group.bench_function("attitude_publish_receive", |bch| {
        bch.iter(|| {
            publ.publish(black_box(&att)).unwrap();
            let r = sub.try_receive().unwrap().unwrap();
            black_box(r.header.seq);
        })
    });

    // Same thread: publish a picture (its targets copied once into a loaned slice of their
    // count) and receive it; the full capacity, and the common case of 10 targets.
    let bt = bus(&prefix("traffic"), "bench");
    let mut tpub = bt.traffic_publisher().unwrap();
    let mut tsub = bt.traffic_subscriber().unwrap();
    for n in [vigil_bus::MAX_TARGETS, 10] {
        let mut picture = TrafficPayload::default();
        picture.set_targets(&vec![Target::EMPTY; n]);
        group.bench_function(format!("traffic_{n}_publish_receive"), |bch| {
            bch.iter(|| {
                tpub.publish(black_box(&picture)).unwrap();
                let r = tsub.try_receive().unwrap().unwrap();
                black_box(r.targets().len());
            })
        });
    }

    // Two threads: this one publishes on `ping` and sleeps on the `pong` event until the echo
    // thread (which sleeps on `ping`'s event) answers. Half the round trip is the one-way
    // latency with event wake-up.
    let p = prefix("pingpong");
    let echo_prefix = p.clone();
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let stop_echo = stop.clone();
    let (ready_tx, ready_rx) = std::sync::mpsc::channel();
    let echo = std::thread::spawn(move || {
        let ping = bus(&format!("{echo_prefix}/ping"), "echo-in");
        let pong = bus(&format!("{echo_prefix}/pong"), "echo-out");
        let mut sub = ping.subscriber::<OwnshipPayload>().unwrap();
        let mut publ = pong.publisher::<OwnshipPayload>().unwrap();
        ready_tx.send(()).unwrap();
        while !stop_echo.load(Ordering::Relaxed) {
            while let Some(r) = sub.try_receive().unwrap() {
                publ.publish(r.payload()).unwrap();
            }
            sub.wait(Duration::from_millis(50)).unwrap();
        }
    });
    ready_rx.recv().unwrap();
    let ping = bus(&format!("{p}/ping"), "ping-out");
    let pong = bus(&format!("{p}/pong"), "ping-in");
    let mut ppub = ping.publisher::<OwnshipPayload>().unwrap();
    let mut psub = pong.subscriber::<OwnshipPayload>().unwrap();
    let own = OwnshipPayload::default();
    // Warm the connection: the first samples connect the ports.
    for _ in 0..50 {
        ppub.publish(&own).unwrap();
        let _ = psub.receive_timeout(Duration::from_millis(100)).unwrap();
    }
    group.bench_function("ownship_round_trip_two_threads_event_wakeup", |bch| {
        bch.iter_custom(|iters| {
            let start = Instant::now();
            for _ in 0..iters {
                ppub.publish(&own).unwrap();
                let r = psub
                    .receive_timeout(Duration::from_secs(1))
                    .unwrap()
                    .expect("echo");
                black_box(r.header.seq);
            }
            start.elapsed()
        })
    });
    group.finish();
    stop.store(true, Ordering::Relaxed);
    echo.join().unwrap();
}

criterion_group!(benches, bench);
criterion_main!(benches);
