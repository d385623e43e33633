//! A simulator run fed through a [`Service`] as `vigil run` feeds its ports (no tokio, no bus),
//! shared by the service, coverage, channel and rule tests.

use vigil_monitor::MonitorParams;
use vigil_service::config::{PipelineSection, Port, Protocol};
use vigil_service::{Collected, Outputs, Service};
use vigil_sim::{MemorySink, Scenario, Simulator};

/// The simulator's ports as `[[ports]]` entries (the path is unused: chunks are fed directly).
pub fn ports_of(sink: &MemorySink) -> Vec<Port> {
    sink.info
        .as_ref()
        .expect("the simulator ran")
        .ports
        .iter()
        .map(|p| Port {
            device: p.device.to_string(),
            path: "/dev/null".into(),
            baud: p.baud,
            protocol: Protocol::resolve(p.protocol, p.device).unwrap(),
            setup: None,
            read_interval_ns: 0,
            latency_timer_ns: None,
            output_buffer_bytes: None,
        })
        .collect()
}

/// Feeds every chunk of `sink` to `s` in receive order, with every port's link up at the first
/// chunk and `tick` every `tick_ns` of host time from then on; `now` is told the host time
/// before each tick and each chunk (for outputs that stamp what they collect).
pub fn drive<O: Outputs>(
    s: &mut Service,
    sink: &MemorySink,
    out: &mut O,
    tick_ns: u64,
    mut now: impl FnMut(&mut O, u64),
) {
    let Some(t0) = sink.chunks.first().map(|c| c.t_host_ns) else {
        return;
    };
    for i in 0..sink.info.as_ref().map_or(0, |i| i.ports.len()) {
        s.handle_link(i, true, t0);
    }
    let mut next_tick = t0;
    for c in &sink.chunks {
        while c.t_host_ns >= next_tick {
            now(out, next_tick);
            s.handle_timeout(next_tick, out);
            next_tick += tick_ns;
        }
        now(out, c.t_host_ns);
        s.handle_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, out);
    }
}

/// Runs `sc` for `seconds` (seed 3) through a service with `vigil run`'s pipeline configuration
/// (prompt attitude), ticking every 100 ms of host time; returns every payload published.
pub fn run_service(sc: &Scenario, seconds: i64) -> Collected {
    let mut sim = Simulator::new(sc, 3).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * 1_000_000_000, &mut sink).unwrap();
    let ports = ports_of(&sink);
    let cfg = PipelineSection::default().pipeline_config();
    let mut s = Service::new(&ports, cfg, MonitorParams::default(), 2.0).unwrap();
    let mut out = Collected::default();
    drive(&mut s, &sink, &mut out, 100_000_000, |_, _| {});
    out
}

/// `vigil measure`'s full-rates scenario (`tests/data/full-rates.toml`, 300 intruders) with the
/// TT-Multi-RF sending CSV and HEXd, no time of their own, at `baud`: at 115 200 or 9600 baud
/// more than its line carries, so its module queues and discards output.
pub fn full_rates_csv_hexd(baud: u32) -> Scenario {
    let mut sc = Scenario::from_toml(include_str!("../data/full-rates.toml"))
        .expect("the full-rates scenario parses");
    let tt = sc
        .devices
        .ttmrf
        .as_mut()
        .expect("full-rates has a TT-Multi-RF");
    tt.protocol = "csv".into();
    tt.raw = "hexd".into();
    tt.baud = baud;
    sc
}
