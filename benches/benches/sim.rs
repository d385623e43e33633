//! Simulating and replaying `nominal` (all four devices: BAHRS, Watson, VN-200 at 200 Hz,
//! TT-Multi-RF JSON with raw HEX frames; 5 intruders) as a
//! multiple of real time. Goals: simulation (MCAP with truth, in memory) >= 200x, replay (read the
//! MCAP, decode every chunk through `vigil_drivers::replay::Replayer` and write JSON Lines to a null
//! sink, exactly as `vigil replay` does) >= 1000x. Each iteration covers 60 simulated seconds: the
//! multiple of real time is 60 s divided by the reported time.

use std::io::{Cursor, Write};

use criterion::{Criterion, criterion_group, criterion_main};
use vigil_drivers::replay::{Decoded, Replayer};
use vigil_record::{Recorded, read_recording};
use vigil_sim::Simulator;
use vigil_sim::record::McapSink;
use vigil_sim::scenario::builtin;

const SECONDS: i64 = 60;

fn simulate() -> Vec<u8> {
    let s = builtin("nominal").unwrap();
    let mut sim = Simulator::new(&s, 1).unwrap();
    let mut sink = McapSink::new(Cursor::new(Vec::with_capacity(8 << 20)), None).unwrap();
    sim.run(SECONDS * 1_000_000_000, &mut sink).unwrap();
    sink.finish().unwrap().into_inner()
}

fn replay(mcap: &[u8]) -> u64 {
    let mut out = std::io::BufWriter::new(std::io::sink());
    let mut n = 0u64;
    let mut emit = |d: Decoded<'_>| -> std::io::Result<()> {
        n += 1;
        serde_json::to_writer(&mut out, &d)?;
        out.write_all(b"\n")
    };
    let mut r = Replayer::new();
    read_recording(mcap, |m| match m {
        Recorded::Raw {
            device,
            protocol,
            t_host_ns,
            bytes,
            ..
        } => r.feed(device, protocol, t_host_ns, bytes, &mut emit),
        _ => Ok(()),
    })
    .unwrap();
    r.finish(&mut emit).unwrap();
    n
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("sim_nominal_60s");
    g.sample_size(10);
    g.bench_function("simulate_to_mcap", |b| {
        b.iter(|| std::hint::black_box(simulate().len()))
    });
    let mcap = simulate();
    let n = replay(&mcap);
    // BAHRS ~301, Watson 11.85, VN-200 200, TT-Multi-RF ~23 messages per second.
    assert!(n > 60 * 530, "{n} messages replayed");
    g.bench_function("replay_decode_json", |b| {
        b.iter(|| std::hint::black_box(replay(&mcap)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
