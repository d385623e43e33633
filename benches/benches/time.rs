//! Time-alignment throughput: `Aligner::handle` over 60 s of the simulator's `nominal` BAHRS and
//! Watson streams (decoded beforehand, each with the receive time of its last byte) interleaved with
//! a synthetic 40 Hz VN-200 (no simulator model yet) feeding the host clock.

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_drivers::replay::{Decoded, Message, Replayer};
use vigil_drivers::vn200::Vn200Message;
use vigil_drivers::vn200::binary::{BinaryOutput, CommonGroup};
use vigil_drivers::vn200::status::InsStatus;
use vigil_fusion::time::Rx;
use vigil_fusion::time::aligner::{Aligner, AlignerConfig, Sample};
use vigil_fusion::time::host_timed::{ChunkClock, tx_ns};
use vigil_sim::scenario::builtin;
use vigil_sim::{MemorySink, Simulator};

const S: i64 = 1_000_000_000;

/// The input stream: (sample, receive) in host-time order.
fn stream(seconds: i64) -> Vec<(Sample, Rx)> {
    let mut sim = Simulator::new(&builtin("nominal").unwrap(), 1).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * S, &mut sink).unwrap();
    let info = sink.info.clone().unwrap();
    let mut vn = (0..seconds * 40)
        .map(|k| {
            let g = info.start_gps_ns + k * S / 40;
            let o = BinaryOutput {
                common: Some(CommonGroup {
                    time_gps_ns: Some(g as u64),
                    time_startup_ns: Some((k * S / 40) as u64),
                    ins_status: Some(InsStatus(0b110)),
                    ..Default::default()
                }),
                ..Default::default()
            };
            let len = o.encode().len();
            let h = info.host_clock.host_ns(g + tx_ns(len, 921_600)) as i64 + 1_000_000;
            (
                Sample::Vn200(Box::new(Vn200Message::Binary(o))),
                Rx {
                    host_ns: h,
                    wire_len: len,
                    reads: None,
                },
            )
        })
        .peekable();
    let mut out = Vec::new();
    let mut replayer = Replayer::new();
    let mut clocks = std::collections::BTreeMap::<&str, ChunkClock>::new();
    for c in &sink.chunks {
        let port = &info.ports[usize::from(c.port)];
        while vn
            .peek()
            .is_some_and(|(_, rx)| rx.host_ns <= c.t_host_ns as i64)
        {
            out.extend(vn.next());
        }
        let clock = clocks.entry(port.device).or_default();
        clock.push(c.t_host_ns as i64, c.bytes.len());
        let mut f = |d: Decoded<'_>| -> Result<(), ()> {
            let (s, len) = match d.message {
                Message::Bahrs(m) => (Sample::Bahrs(*m), m.to_frame().len()),
                Message::Watson(l) => (Sample::Watson(*l), l.to_bytes().len()),
                // The benchmark's VN-200 is the synthetic stream above (same rates on every run);
                // the simulator's own VN-200 and TT-Multi-RF ports are left out.
                Message::Vn200(_) | Message::Ttmrf(_) | Message::TtmrfRaw(_) => return Ok(()),
            };
            if let Some(rx) = clock.rx(d.offset, len) {
                out.push((s, rx));
            }
            Ok(())
        };
        replayer
            .feed(port.device, port.protocol, c.t_host_ns, &c.bytes, &mut f)
            .unwrap();
    }
    out
}

fn align(c: &mut Criterion) {
    let input = stream(60);
    let mut group = c.benchmark_group("time");
    group.throughput(Throughput::Elements(input.len() as u64));
    group.bench_function(format!("align_nominal_60s_{}_samples", input.len()), |b| {
        b.iter_batched(
            || input.clone(),
            |input| {
                let mut al = Aligner::new(AlignerConfig::default());
                let mut n = 0usize;
                for (s, rx) in input {
                    for o in al.handle(s, rx) {
                        black_box(&o);
                        n += 1;
                    }
                }
                n += al.flush().len();
                n
            },
            BatchSize::LargeInput,
        )
    });
    group.finish();
}

criterion_group!(benches, align);
criterion_main!(benches);
