//! The service core on simulated chunks (no tokio, no bus): the nominal scenario's four ports
//! through [`Service`], outputs collected.

use vigil_bus::TrafficPayload;
use vigil_bus::payload::integrity as integ;
use vigil_fusion::pipeline::{Fused, PipelineConfig};
use vigil_monitor::MonitorParams;
use vigil_service::config::PipelineSection;
use vigil_service::*;
use vigil_sim::scenario::builtin;
use vigil_sim::{MemorySink, Simulator};
use vigil_tests::sim_drive::ports_of;

fn simulate(seconds: i64) -> MemorySink {
    let mut sim = Simulator::new(&builtin("nominal").unwrap(), 7).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * 1_000_000_000, &mut sink).unwrap();
    sink
}

fn service_for(sink: &MemorySink) -> Service {
    service_with(sink, PipelineConfig::default())
}

fn service_with(sink: &MemorySink, pipeline: PipelineConfig) -> Service {
    let ports = ports_of(sink);
    Service::new(&ports, pipeline, MonitorParams::default(), 2.0).unwrap()
}

#[test]
fn nominal_chunks_give_every_payload_in_gps_order() {
    let sink = simulate(12);
    let mut s = service_for(&sink);
    for i in 0..4 {
        s.handle_link(i, true, sink.chunks[0].t_host_ns);
    }
    let mut out = Collected::default();
    let mut next_tick = sink.chunks[0].t_host_ns;
    for c in &sink.chunks {
        while c.t_host_ns >= next_tick {
            s.handle_timeout(next_tick, &mut out);
            next_tick += 1_000_000_000;
        }
        s.handle_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
    }
    let last = sink.chunks.last().unwrap().t_host_ns;
    s.handle_timeout(last, &mut out);

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
    assert_eq!((t.count(), t.dropped), (5, 0));
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
    s.handle_link(1, false, t0);
    let d = s.integrity(t0).devices[1];
    assert_eq!((d.link_state, d.reconnects), (integ::LINK_DISCONNECTED, 0));
    s.handle_link(0, true, t0);
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
        s.handle_chunk(0, c.t_host_ns, &c.bytes, &mut out);
    }
    let tl = sink.chunks.iter().rfind(|c| c.port == 0).unwrap().t_host_ns;
    assert_eq!(s.integrity(tl).devices[0].link_state, integ::LINK_OK);
    s.handle_link(0, false, tl);
    let d = s.integrity(tl).devices[0];
    assert_eq!(d.link_state, integ::LINK_DISCONNECTED);
    s.handle_link(0, true, tl + 1);
    assert_eq!(s.integrity(tl + 1).devices[0].reconnects, 1);
    // Garbage is counted, never fatal.
    s.handle_chunk(0, tl + 2, &[0x55; 300], &mut out);
    s.handle_chunk(9, tl + 3, b"no such port", &mut out);
    assert_eq!(s.counters().unknown_port, 1);
    assert_eq!(s.counters().errors, 0);
    let d = s.integrity(tl + 4).devices[0];
    assert!(d.bytes_received > d.bytes_consumed || d.bytes_skipped >= 300);
}

/// `vigil run`'s default: one attitude payload per VN-200 message, published in the very call
/// that took the message's last byte, at the message's own time (the simulator's truth says
/// where each message ends in the port's byte stream, and its sample time).
#[test]
fn prompt_attitude_follows_every_vn200_message_at_once() {
    let sink = simulate(12);
    let cfg = PipelineSection::default().pipeline_config();
    assert!(cfg.prompt_attitude);
    let mut s = service_with(&sink, cfg);
    let mut out = Collected::default();
    let ports = &sink.info.as_ref().unwrap().ports;
    let vn200 = ports.iter().position(|p| p.device == "vn200").unwrap();
    // (end offset in the port's stream, GPS time) of every VN-200 message, in stream order.
    let mut ends: std::collections::VecDeque<(u64, i64)> = sink
        .truth
        .iter()
        .filter(|r| r.device == "vn200")
        .map(|r| (r.rx_offset + r.wire.len() as u64, r.t_gps_ns))
        .collect();
    let messages = ends.len();
    let (mut written, mut at_once, mut late) = (0u64, 0usize, Vec::new());
    for c in &sink.chunks {
        let before = out.attitude.len();
        s.handle_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
        if usize::from(c.port) != vn200 {
            continue;
        }
        written += c.bytes.len() as u64;
        let published = &out.attitude[before..];
        while let Some(&(_, t)) = ends.front().filter(|(end, _)| *end <= written) {
            ends.pop_front();
            if published.iter().any(|a| a.header.gps_time_ns == t) {
                at_once += 1;
            } else {
                late.push(t);
            }
        }
    }
    let att = &out.attitude;
    assert!(
        att.windows(2)
            .all(|w| w[0].header.gps_time_ns < w[1].header.gps_time_ns)
    );
    // Every VN-200 message (its GPS time is its own: no clock to lock first).
    assert!(messages > 2000, "{messages}");
    assert_eq!(at_once, messages, "late: {:?}", &late[..late.len().min(5)]);
    // The others come from BAHRS or Watson samples newer than the newest VN-200 sample.
    assert!(
        att.len() <= messages + messages / 2,
        "{} for {messages}",
        att.len()
    );
    let half = &att[att.len() / 2..];
    let valid = half.iter().filter(|a| a.valid == 1).count();
    assert_eq!(valid, half.len(), "all valid in the second half");
    // Nominal: all three units agree; the verdicts, those of the checks, say so.
    let last = att.last().unwrap();
    assert_eq!(
        last.isolation,
        vigil_bus::payload::attitude::ISOLATION_NO_FAULT
    );
    assert!(last.units.iter().all(|u| u.valid == 1));
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
            s.handle_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
        }
        let mut lines: Vec<String> = out.attitude.iter().map(json).collect();
        lines.extend(out.ownship.iter().map(json));
        lines.extend(out.traffic.iter().map(json));
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
        s.handle_chunk(usize::from(c.port), c.t_host_ns, &c.bytes, &mut out);
    }
    s.finish(sink.chunks.last().unwrap().t_host_ns, &mut out);
    let mut live: Vec<String> = out.attitude.iter().map(json).collect();
    live.extend(out.ownship.iter().map(json));
    live.extend(out.traffic.iter().map(json));

    let info = sink.info.as_ref().unwrap();
    let specs: Vec<(&str, &str, u32)> = info
        .ports
        .iter()
        .map(|p| (p.device, p.protocol, p.baud))
        .collect();
    let mut rec = vigil_record::RawRecorder::new(Cursor::new(Vec::new()), &specs).unwrap();
    for c in &sink.chunks {
        rec.write_raw(c.port, c.t_host_ns, &c.bytes).unwrap();
    }
    let mcap = rec.finish().unwrap().into_inner();
    let (mut att, mut own, mut traffic) = (Vec::new(), Vec::new(), Vec::new());
    let mut last_own = None;
    // The replay's configuration with the pipeline of `service_for` (checks, not prompts).
    let mut cfg = vigil_service::config::Config::default();
    cfg.pipeline.attitude_output = vigil_service::config::AttitudeOutput::Checks;
    vigil_service::replay::fused::replay_fused_with(&mcap[..], &cfg, |e| {
        let vigil_service::replay::fused::FusedEvent::Fused(f) = e else {
            return Ok(());
        };
        match f {
            Fused::Attitude(r) | Fused::Prompt(r) => att.push(json(&convert::attitude(r))),
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

/// A TT-Multi-RF sending CSV and HEXd at 115 200 baud, more than its line carries (the
/// full-rates traffic: 300 intruders), through the service as `vigil run` feeds it, for 30 s.
/// Without its transmit buffer stated, its samples are not aligned once the line has been full
/// for 0.5 s, so the tracks of its first second time out (20 s) and no traffic picture after
/// 23 s has a target; with the simulator's buffer stated on the port (`[[ports]]
/// output_buffer_bytes`), every picture carries targets to the end. (Whether their times are
/// right is `time_acceptance`'s test of the same line.) A recording of the same chunks keeps
/// the statement as channel metadata, and its replay places the line's samples as the live
/// service does: nearly none without it, every one with it.
#[test]
fn a_stated_tt_buffer_keeps_a_saturated_csv_lines_traffic_live_and_in_replay() {
    let sc = vigil_tests::sim_drive::full_rates_csv_hexd(115_200);
    let mut sim = Simulator::new(&sc, 3).unwrap();
    let mut sink = MemorySink::default();
    sim.run(30_000_000_000, &mut sink).unwrap();
    let with_targets_after_23_s = |buffer: Option<u32>| {
        let mut ports = ports_of(&sink);
        for p in ports.iter_mut().filter(|p| p.device == "ttmrf") {
            p.output_buffer_bytes = buffer;
        }
        let cfg = PipelineSection::default().pipeline_config();
        let mut s = Service::new(&ports, cfg, MonitorParams::default(), 2.0).unwrap();
        let mut out = Collected::default();
        vigil_tests::sim_drive::drive(&mut s, &sink, &mut out, 100_000_000, |_, _| {});
        let t23 = out.traffic.first().unwrap().header.gps_time_ns + 23_000_000_000;
        let late: Vec<&TrafficPayload> = out
            .traffic
            .iter()
            .filter(|t| t.header.gps_time_ns > t23)
            .collect();
        let with = late.iter().filter(|t| t.count() > 0).count();
        println!(
            "buffer {buffer:?}: {with} of {} pictures after 23 s have targets",
            late.len()
        );
        (with, late.len())
    };
    let (without, late) = with_targets_after_23_s(None);
    assert!(late >= 4 && without == 0, "{without} of {late}");
    let (with, late) = with_targets_after_23_s(Some(vigil_sim::link::TX_BUFFER_BYTES as u32));
    assert!(late >= 4 && with == late, "{with} of {late}");
    // The replay of a recording of these chunks, with and without the statement.
    let replayed = |buffer: Option<u32>| {
        let mut rec =
            vigil_record::RawRecorder::new(std::io::Cursor::new(Vec::new()), &[]).unwrap();
        for p in &sink.info.as_ref().unwrap().ports {
            let stated = if p.device == "ttmrf" { buffer } else { None };
            let link = vigil_record::PortLink {
                output_buffer_bytes: stated,
                ..vigil_record::PortLink::baud(p.baud)
            };
            rec.add_port_with_link(p.device, p.protocol, &link).unwrap();
        }
        for c in &sink.chunks {
            rec.write_raw(c.port, c.t_host_ns, &c.bytes).unwrap();
        }
        let mcap = rec.finish().unwrap().into_inner();
        let (mut placed, mut all) = (0, 0);
        vigil_service::replay::aligned::replay_aligned_with(&mcap[..], |s| {
            if s.device == vigil_fusion::time::aligner::Device::Ttmrf {
                all += 1;
                placed += usize::from(s.aligned.time.is_ok());
            }
            Ok(())
        })
        .unwrap();
        println!("replay, buffer {buffer:?}: {placed} of {all} TT-Multi-RF samples placed");
        (placed, all)
    };
    let (placed, all) = replayed(None);
    assert!(all > 5_000 && placed * 50 < all, "{placed} of {all}");
    let (placed, all) = replayed(Some(vigil_sim::link::TX_BUFFER_BYTES as u32));
    assert!(all > 5_000 && placed == all, "{placed} of {all}");
}
