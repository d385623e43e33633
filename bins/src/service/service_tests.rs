//! The service core on simulated chunks (no tokio, no bus): the nominal scenario's four ports
//! through [`Service`], outputs collected.

use vigil_bus::payload::integrity as integ;
use vigil_sim::scenario::builtin;
use vigil_sim::{MemorySink, Simulator};

use super::config::{Port, Protocol};
use super::*;

fn simulate(seconds: i64) -> MemorySink {
    let mut sim = Simulator::new(&builtin("nominal").unwrap(), 7).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * 1_000_000_000, &mut sink).unwrap();
    sink
}

fn service_for(sink: &MemorySink) -> Service {
    let ports: Vec<Port> = sink
        .info
        .as_ref()
        .unwrap()
        .ports
        .iter()
        .map(|p| Port {
            device: p.device.to_string(),
            path: "/dev/null".into(),
            baud: p.baud,
            protocol: Protocol::resolve(p.protocol, p.device).unwrap(),
            setup: None,
        })
        .collect();
    Service::new(
        &ports,
        PipelineConfig::default(),
        MonitorParams::default(),
        2.0,
    )
    .unwrap()
}

#[test]
fn nominal_chunks_give_every_payload_in_gps_order() {
    let sink = simulate(12);
    let mut s = service_for(&sink);
    for i in 0..4 {
        s.on_link(i, true, sink.chunks[0].t_host_ns);
    }
    let mut out = Collected::default();
    let mut next_tick = sink.chunks[0].t_host_ns;
    for c in &sink.chunks {
        while c.t_host_ns >= next_tick {
            s.tick(next_tick, &mut out);
            next_tick += 1_000_000_000;
        }
        s.on_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
    }
    let last = sink.chunks.last().unwrap().t_host_ns;
    s.tick(last, &mut out);

    assert_eq!(s.counters().errors, 0);
    assert_eq!(s.counters().chunks, sink.chunks.len() as u64);
    // BAHRS navigation at 50 Hz: one attitude record each once the clocks lock (~2 s).
    assert!(out.attitude.len() > 300, "{}", out.attitude.len());
    assert!(
        out.attitude
            .windows(2)
            .all(|w| w[0].header.gps_time_ns <= w[1].header.gps_time_ns)
    );
    // 1 s steps: one ownship and one traffic picture per step, at the same times.
    assert!(out.ownship.len() >= 6, "{}", out.ownship.len());
    assert_eq!(out.ownship.len(), out.traffic.len());
    for (o, t) in out.ownship.iter().zip(&out.traffic) {
        assert_eq!(o.header.gps_time_ns, t.header.gps_time_ns);
        assert_eq!(o.header.gps_time_ns % 1_000_000_000, 0, "on the 1 s grid");
        assert_eq!(o.valid, 1);
    }
    // Nominal: five intruders; the last picture holds them all, none dropped.
    let t = out.traffic.last().unwrap();
    assert_eq!((t.count, t.dropped), (5, 0));
    let i = out.integrity.last().unwrap();
    assert_eq!(i.device_count, 4);
    for d in i.devices() {
        assert_eq!(
            d.link_state,
            integ::LINK_OK,
            "{}",
            vigil_bus::payload::read_text(&d.name)
        );
        assert!(d.messages > 0);
        assert_eq!(d.reconnects, 0);
        assert!(d.bytes_received >= d.bytes_consumed);
    }
    assert_ne!(i.clock_status, integ::CLOCK_NOT_LOCKED);
    assert!(i.header.gps_time_ns > 0);
}

#[test]
fn a_closed_port_is_disconnected_then_silent_data_counts_reconnects() {
    let sink = simulate(3);
    let mut s = service_for(&sink);
    let t0 = sink.chunks[0].t_host_ns;
    let mut out = Collected::default();
    // Nothing tried yet: unknown; a port that fails to open: disconnected, no reconnect counted.
    assert_eq!(s.integrity(t0).devices[0].link_state, integ::LINK_UNKNOWN);
    s.on_link(1, false, t0);
    let d = s.integrity(t0).devices[1];
    assert_eq!((d.link_state, d.reconnects), (integ::LINK_DISCONNECTED, 0));
    s.on_link(0, true, t0);
    // Open, no message for more than the silence limit (2 s): silent.
    assert_eq!(
        s.integrity(t0 + 1_000_000_000).devices[0].link_state,
        integ::LINK_UNKNOWN
    );
    assert_eq!(
        s.integrity(t0 + 2_500_000_000).devices[0].link_state,
        integ::LINK_SILENT
    );
    for c in sink.chunks.iter().filter(|c| c.port == 0) {
        s.on_chunk(0, c.t_host_ns, &c.bytes, &mut out);
    }
    let tl = sink.chunks.iter().rfind(|c| c.port == 0).unwrap().t_host_ns;
    assert_eq!(s.integrity(tl).devices[0].link_state, integ::LINK_OK);
    s.on_link(0, false, tl);
    let d = s.integrity(tl).devices[0];
    assert_eq!(d.link_state, integ::LINK_DISCONNECTED);
    s.on_link(0, true, tl + 1);
    assert_eq!(s.integrity(tl + 1).devices[0].reconnects, 1);
    // Garbage is counted, never fatal.
    s.on_chunk(0, tl + 2, &[0x55; 300], &mut out);
    s.on_chunk(9, tl + 3, b"no such port", &mut out);
    assert_eq!(s.counters().unknown_port, 1);
    assert_eq!(s.counters().errors, 0);
    let d = s.integrity(tl + 4).devices[0];
    assert!(d.bytes_received > d.bytes_consumed || d.bytes_skipped >= 300);
}

/// The outputs are a function of (bytes, host times) only: the same chunks twice, the same
/// payloads (compared as JSON, where NaN reads `null`).
#[test]
fn same_chunks_same_outputs() {
    let sink = simulate(6);
    let run = || {
        let mut s = service_for(&sink);
        let mut out = Collected::default();
        for c in &sink.chunks {
            s.on_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
        }
        let mut lines: Vec<String> = out.attitude.iter().map(json).collect();
        lines.extend(out.ownship.iter().map(json));
        lines.extend(out.traffic.iter().map(|p| json(&**p)));
        lines
    };
    let a = run();
    assert!(a.len() > 100);
    assert_eq!(a, run());
}

fn json<T: serde::Serialize>(v: &T) -> String {
    serde_json::to_string(v).unwrap()
}

/// The service and `vigil replay --emit fused` are one path: the same chunks, fed to a
/// [`Service`] (then [`Service::finish`]) or written to an MCAP file and replayed through
/// `replay_fused_with`, give the same payloads.
#[test]
fn service_and_fused_replay_agree() {
    use std::io::Cursor;
    let sink = simulate(6);
    let mut s = service_for(&sink);
    let mut out = Collected::default();
    for c in &sink.chunks {
        s.on_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
    }
    s.finish(sink.chunks.last().unwrap().t_host_ns, &mut out);
    let mut live: Vec<String> = out.attitude.iter().map(json).collect();
    live.extend(out.ownship.iter().map(json));
    live.extend(out.traffic.iter().map(|p| json(&**p)));

    let info = sink.info.as_ref().unwrap();
    let specs: Vec<(&str, &str, u32)> = info
        .ports
        .iter()
        .map(|p| (p.device, p.protocol, p.baud))
        .collect();
    let mut rec = vigil_sim::record::RawRecorder::new(Cursor::new(Vec::new()), &specs).unwrap();
    for c in &sink.chunks {
        rec.write_raw(c.port, c.t_host_ns, &c.bytes).unwrap();
    }
    let mcap = rec.finish().unwrap().into_inner();
    let (mut att, mut own, mut traffic) = (Vec::new(), Vec::new(), Vec::new());
    let mut last_own = None;
    crate::replay_fused::replay_fused_with(&mcap, PipelineConfig::default(), |f| {
        match f {
            Fused::Attitude(r) => att.push(json(&convert::attitude(r))),
            Fused::Ownship(o) => {
                last_own = Some(o.ownship);
                own.push(json(&convert::ownship(o)));
            }
            Fused::Traffic(p) => {
                let mut t = Box::<TrafficPayload>::default();
                convert::traffic(p, last_own.as_ref(), &mut t);
                traffic.push(json(&*t));
            }
        }
        Ok(())
    })
    .unwrap();
    let mut replayed = att;
    replayed.extend(own);
    replayed.extend(traffic);
    assert!(live.len() > 100);
    assert_eq!(live.len(), replayed.len());
    assert!(live == replayed, "the service and the replay differ");
}
