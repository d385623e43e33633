//! The replay-vs-truth check for the TT-Multi-RF binary decoded protocols (MAVLink, GDL90,
//! ASTERIX): every built-in scenario, switched to each protocol (raw output off), decodes through
//! `replay::Replayer` to exactly the messages the truth lists (at the truth's `rx_offset`,
//! byte-identical when re-encoded), minus those a link fault corrupted (counted). AT lines (the
//! state messages of a power cycle) are not decoded on a binary port: the binary decoder counts
//! them as skipped bytes (see `vigil_drivers::replay`), so they are left out of the comparison.

use std::collections::{BTreeMap, BTreeSet};

use bytes::BytesMut;
use tokio_util::codec::Encoder;
use vigil_drivers::replay::{Decoded, Message, PortSummary, Replayer, TtmrfMessage};
use vigil_drivers::ttmrf::gdl90;
use vigil_drivers::ttmrf::mavlink::MavlinkEncoder;
use vigil_sim::scenario::{BUILTIN_NAMES, builtin};
use vigil_sim::{MemorySink, Simulator};

fn run(name: &str, protocol: &str, seconds: i64) -> Option<MemorySink> {
    let mut s = builtin(name).unwrap();
    let t = s.devices.ttmrf.as_mut()?;
    t.protocol = protocol.into();
    t.raw = "off".into();
    let mut sim = Simulator::new(&s, 5).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * 1_000_000_000, &mut sink).unwrap();
    Some(sink)
}

/// The re-encoded bytes of a decoded binary message.
fn wire(m: &TtmrfMessage<'_>) -> Vec<u8> {
    match m {
        TtmrfMessage::Mavlink(m) => {
            let mut b = BytesMut::new();
            MavlinkEncoder.encode((*m).clone(), &mut b).unwrap();
            b.to_vec()
        }
        TtmrfMessage::Gdl90(m) => {
            let mut b = Vec::new();
            gdl90::encode_frame(m, &mut b);
            b
        }
        TtmrfMessage::Asterix(m) => {
            let mut b = Vec::new();
            m.encode_block(&mut b);
            b
        }
        TtmrfMessage::Text(t) => panic!("text message on a binary port: {t:?}"),
    }
}

/// Replays the recording's chunks: (offset -> re-encoded message) of the TT-Multi-RF port.
fn replay(sink: &MemorySink) -> (BTreeMap<u64, Vec<u8>>, Option<PortSummary>) {
    let info = sink.info.as_ref().unwrap();
    let mut r = Replayer::new();
    let mut got = BTreeMap::new();
    let mut f = |d: Decoded<'_>| -> Result<(), ()> {
        if let Message::Ttmrf(m) = d.message {
            assert!(got.insert(d.offset, wire(&m)).is_none());
        }
        Ok(())
    };
    for c in &sink.chunks {
        let p = &info.ports[usize::from(c.port)];
        r.feed(p.device, p.protocol, c.t_host_ns, &c.bytes, &mut f)
            .unwrap();
    }
    let summary = r.finish(&mut f).unwrap();
    (got, summary.get("ttmrf").copied())
}

#[test]
fn every_builtin_scenario_replays_to_its_truth_in_every_binary_protocol() {
    for protocol in ["mavlink", "gdl90", "asterix"] {
        let mut total = 0;
        for name in BUILTIN_NAMES {
            let seconds = match name {
                "link-errors" => 50,
                "busy-airspace" => 3,
                _ => 6,
            };
            let Some(sink) = run(name, protocol, seconds) else {
                continue;
            };
            let channel = &sink.info.as_ref().unwrap().ports[3].protocol;
            assert_eq!(*channel, format!("ttmrf-{protocol}"));
            let (got, summary) = replay(&sink);
            let truth: Vec<_> = sink
                .truth
                .iter()
                .filter(|r| r.device == "ttmrf" && r.kind != "at")
                .collect();
            let mut intact = BTreeSet::new();
            for r in truth.iter().filter(|r| !r.corrupted) {
                assert_eq!(
                    got.get(&r.rx_offset),
                    Some(&r.wire),
                    "{protocol} {name}: truth index {} ({}) at offset {}",
                    r.index,
                    r.kind,
                    r.rx_offset
                );
                intact.insert(r.rx_offset);
            }
            total += intact.len();
            let corrupted = truth.len() - intact.len();
            let extra = got.keys().filter(|o| !intact.contains(o)).count();
            assert!(extra <= corrupted, "{protocol} {name}: {extra} extra");
            // A scenario without intruders gives MAVLink nothing to send: no port, no truth.
            let Some(PortSummary::Decoded(stats)) = summary else {
                assert!(truth.is_empty(), "{protocol} {name}: {summary:?}");
                continue;
            };
            if name == "link-errors" {
                assert!(corrupted > 0, "{protocol}: link loss corrupts nothing");
                // The power cycle at 45 s sends AT state lines: skipped by the binary decoder.
                assert!(stats.bytes_skipped > 0, "{protocol}");
            } else {
                assert_eq!((corrupted, extra), (0, 0), "{protocol} {name}");
                // Nothing but the truth's messages on the port.
                assert_eq!(stats.bytes_skipped, 0, "{protocol} {name}");
            }
        }
        // busy-airspace alone: 300 intruders (those the protocol carries) for 3 s.
        assert!(total > 500, "{protocol}: {total}");
    }
}
