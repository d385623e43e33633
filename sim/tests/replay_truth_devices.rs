//! The replay-vs-truth check for the VN-200 and TT-Multi-RF ports (the BAHRS and Watson ports
//! are checked in `replay_truth.rs`): for every built-in scenario, decoding each port's received
//! bytes with the drivers' decoders gives exactly the messages the truth lists (each at the
//! truth's `rx_offset`, byte-identical when re-encoded), minus those a link fault corrupted
//! (counted); and `replay::Replayer` decodes the same messages from the chunks.

mod common;

use std::collections::{BTreeMap, BTreeSet};

use vigil_drivers::replay::{Message, Replayer};
use vigil_drivers::vn200::Vn200Decoder;
use vigil_sim::scenario::{BUILTIN_NAMES, builtin};
use vigil_sim::{MemorySink, Simulator};

fn run(name: &str, seconds: i64, seed: u64) -> MemorySink {
    let s = builtin(name).unwrap();
    let mut sim = Simulator::new(&s, seed).unwrap();
    let mut sink = MemorySink::default();
    sim.run(seconds * 1_000_000_000, &mut sink).unwrap();
    sink
}

fn stream(sink: &MemorySink, device: &str) -> Vec<u8> {
    let info = sink.info.as_ref().unwrap();
    sink.chunks
        .iter()
        .filter(|c| info.ports[usize::from(c.port)].device == device)
        .flat_map(|c| c.bytes.clone())
        .collect()
}

/// (intact messages, corrupted, decoded messages matching no intact truth record).
fn check(sink: &MemorySink, device: &str, decoded: &[(u64, Vec<u8>)]) -> (usize, usize, usize) {
    let truth: Vec<_> = sink.truth.iter().filter(|r| r.device == device).collect();
    let by_offset: BTreeMap<u64, &Vec<u8>> = decoded.iter().map(|(o, m)| (*o, m)).collect();
    let mut intact = BTreeSet::new();
    for r in truth.iter().filter(|r| !r.corrupted) {
        assert_eq!(
            by_offset.get(&r.rx_offset).map(|m| m.as_slice()),
            Some(r.wire.as_slice()),
            "{device}: truth index {} ({}) at offset {}",
            r.index,
            r.kind,
            r.rx_offset
        );
        intact.insert(r.rx_offset);
    }
    let corrupted = truth.len() - intact.len();
    let extra = decoded.iter().filter(|(o, _)| !intact.contains(o)).count();
    assert!(
        extra <= corrupted,
        "{device}: {extra} unexpected decoded messages, {corrupted} corrupted"
    );
    (intact.len(), corrupted, extra)
}

#[test]
fn every_builtin_scenario_decodes_to_its_truth_on_vn200_and_ttmrf() {
    for name in BUILTIN_NAMES {
        let seconds = match name {
            "link-errors" => 50,
            "gnss-outage" => 65,
            _ => 12,
        };
        let sink = run(name, seconds, 11);
        let s = builtin(name).unwrap();
        let faulty = name == "link-errors";
        if s.devices.vn200.is_some() {
            let decoded: Vec<_> =
                common::decode_located(Vn200Decoder::new(), &stream(&sink, "vn200"))
                    .into_iter()
                    .map(|(o, m)| (o, common::vn200_bytes(&m)))
                    .collect();
            let (intact, corrupted, extra) = check(&sink, "vn200", &decoded);
            // 200 Hz.
            assert!(
                (intact + corrupted) as i64 >= 200 * seconds - 2,
                "{name}: {intact} vn200"
            );
            if faulty {
                assert!(corrupted > 0, "{name}: vn200 bit errors corrupt nothing");
            } else {
                assert_eq!((corrupted, extra), (0, 0), "{name} vn200");
            }
        }
        if s.devices.ttmrf.is_some() {
            let decoded = common::ttmrf_located(&stream(&sink, "ttmrf"));
            let (intact, corrupted, extra) = check(&sink, "ttmrf", &decoded);
            let n = sink.truth.iter().filter(|r| r.device == "ttmrf").count();
            assert_eq!(intact + corrupted, n);
            let intruders = Simulator::new(&s, 1).unwrap().world().intruder_count() as i64;
            assert!(
                n as i64 >= (intruders + 1) * (seconds - 2),
                "{name}: {n} ttmrf messages for {intruders} intruders"
            );
            if faulty {
                // Link loss 30-31.5 s: 1.5 s of one intruder and the GNSS section at 1 Hz (raw off).
                assert!(corrupted >= 2, "{name}: {corrupted} ttmrf corrupted");
                assert!(
                    sink.truth
                        .iter()
                        .any(|r| r.device == "ttmrf" && r.kind == "at"),
                    "the power cycle at 45 s announces its states"
                );
            } else {
                assert_eq!((corrupted, extra), (0, 0), "{name} ttmrf");
            }
        }
    }
}

#[test]
fn replayer_decodes_every_vn200_and_ttmrf_text_message() {
    let sink = run("nominal", 5, 2);
    let info = sink.info.as_ref().unwrap();
    let mut r = Replayer::new();
    let mut got: BTreeMap<(String, u64), &'static str> = BTreeMap::new();
    let mut f = |d: vigil_drivers::replay::Decoded<'_>| -> Result<(), ()> {
        let kind = match d.message {
            Message::Vn200(_) => "vn200",
            Message::Ttmrf(_) => "ttmrf",
            Message::TtmrfRaw(_) => "ttmrf_raw",
            _ => return Ok(()),
        };
        got.insert((d.device.to_string(), d.offset), kind);
        Ok(())
    };
    for c in &sink.chunks {
        let p = &info.ports[usize::from(c.port)];
        r.feed(p.device, p.protocol, c.t_host_ns, &c.bytes, &mut f)
            .unwrap();
    }
    r.finish(&mut f).unwrap();
    // Every VN-200 message and every TT-Multi-RF message (text and raw HEX frames) is decoded
    // at its truth offset, and nothing else.
    let want: BTreeSet<(String, u64)> = sink
        .truth
        .iter()
        .filter(|t| t.device == "vn200" || t.device == "ttmrf")
        .map(|t| (t.device.to_string(), t.rx_offset))
        .collect();
    let have: BTreeSet<(String, u64)> = got.keys().cloned().collect();
    assert_eq!(have, want);
    assert!(want.len() > 1000);
    // Raw frames are among them (nominal has raw = "hex").
    assert!(got.values().filter(|k| **k == "ttmrf_raw").count() > 50);
}
