//! MCAP recordings: byte-identical for the same scenario and seed, read back exactly, and readable
//! up to the damage when truncated.

use std::io::Cursor;

use vigil_record::{Recorded, read_metadata, read_recording, recorded_span};
use vigil_sim::record::McapSink;
use vigil_sim::scenario::builtin;
use vigil_sim::{MemorySink, Simulator};

fn record(name: &str, seconds: i64, seed: u64) -> Vec<u8> {
    record_scenario(&builtin(name).unwrap(), seconds, seed)
}

fn record_scenario(s: &vigil_sim::Scenario, seconds: i64, seed: u64) -> Vec<u8> {
    let mut sim = Simulator::new(s, seed).unwrap();
    let mut sink = McapSink::new(Cursor::new(Vec::new()), None).unwrap();
    sim.run(seconds * 1_000_000_000, &mut sink).unwrap();
    sink.finish().unwrap().into_inner()
}

#[test]
fn same_scenario_and_seed_give_identical_bytes() {
    let a = record("link-errors", 30, 42);
    let b = record("link-errors", 30, 42);
    assert!(a.len() > 100_000);
    assert!(a == b, "two runs differ");
    let c = record("link-errors", 30, 43);
    assert!(a != c, "another seed gives another recording");
}

#[test]
fn binary_ttmrf_protocols_record_byte_identically() {
    for protocol in ["mavlink", "gdl90", "asterix"] {
        let mut s = builtin("link-errors").unwrap();
        let t = s.devices.ttmrf.as_mut().unwrap();
        t.protocol = protocol.into();
        t.raw = "off".into();
        let a = record_scenario(&s, 20, 42);
        let b = record_scenario(&s, 20, 42);
        assert!(a == b, "{protocol}: two runs differ");
    }
}

#[test]
fn recording_reads_back_the_chunks_and_truth() {
    let s = builtin("nominal").unwrap();
    let mut sim = Simulator::new(&s, 7).unwrap();
    let mut mem = MemorySink::default();
    sim.run(5_000_000_000, &mut mem).unwrap();
    let bytes = record("nominal", 5, 7);
    let mut chunks = Vec::new();
    let mut truth = Vec::new();
    let outcome = read_recording::<()>(&bytes, |m| {
        match m {
            Recorded::Raw {
                device,
                t_host_ns,
                bytes,
                ..
            } => chunks.push((device.to_string(), t_host_ns, bytes.to_vec())),
            Recorded::Truth { json, .. } => {
                truth.push(serde_json::from_slice::<serde_json::Value>(json).unwrap())
            }
            Recorded::Other { topic } => panic!("unexpected topic {topic}"),
        }
        Ok(())
    })
    .unwrap();
    assert_eq!(outcome.damage, None);
    let info = mem.info.unwrap();
    let expected: Vec<_> = mem
        .chunks
        .iter()
        .map(|c| {
            (
                info.ports[usize::from(c.port)].device.to_string(),
                c.t_host_ns,
                c.bytes.clone(),
            )
        })
        .collect();
    assert_eq!(chunks, expected);
    // Chunks are in host-time order across ports.
    assert!(chunks.windows(2).all(|w| w[0].1 <= w[1].1));
    assert_eq!(truth.len(), mem.truth.len());
    assert_eq!(truth[0]["device"], "bahrs");
    assert_eq!(truth[0]["index"], 0);
    assert_eq!(truth[0]["type"], "software_version");
    let meta = read_metadata(&bytes).unwrap();
    assert_eq!(meta["scenario"], "nominal");
    assert_eq!(meta["seed"], "7");
    // Every device of the scenario has its model now.
    assert_eq!(meta["devices_without_model"], "");
}

#[test]
fn truncated_recording_is_read_up_to_the_damage() {
    let bytes = record("nominal", 20, 1);
    let count = |b: &[u8]| {
        let mut n = 0u64;
        let o = read_recording::<()>(b, |_| {
            n += 1;
            Ok(())
        })
        .unwrap();
        (n, o)
    };
    let (all, o) = count(&bytes);
    assert_eq!(o.damage, None);
    let mut last = 0;
    for frac in [0.25, 0.5, 0.75, 0.99] {
        let cut = (bytes.len() as f64 * frac) as usize;
        let (n, o) = count(&bytes[..cut]);
        assert!(o.damage.is_some(), "cut at {cut} is noticed");
        // Everything in the chunks before the cut is there (chunks hold at most 64 KiB).
        assert!(n > last && n < all, "cut {frac}: {n} of {all}");
        last = n;
    }
}

#[test]
fn recorded_span_is_the_first_and_last_log_time() {
    let bytes = record("nominal", 3, 2);
    let (mut first, mut last) = (u64::MAX, 0);
    read_recording::<()>(&bytes, |m| {
        let t = match m {
            Recorded::Raw { t_host_ns, .. } | Recorded::Truth { t_host_ns, .. } => t_host_ns,
            _ => return Ok(()),
        };
        first = first.min(t);
        last = last.max(t);
        Ok(())
    })
    .unwrap();
    let (t0, t1) = recorded_span(&bytes).unwrap();
    // Every message counts: chunks (receive time) and truth records (the host time their first
    // byte started on the wire, earlier than its receipt).
    assert_eq!((t0, t1), (first, last));
    assert!(t1 - t0 > 2_500_000_000);
    // A truncated file has no summary: no span.
    assert_eq!(recorded_span(&bytes[..bytes.len() / 2]), None);
}

#[test]
fn read_intervals_are_kept_per_channel_and_read_back() {
    use vigil_record::RawRecorder;
    let ports = [
        ("vn200", "vn200-icd", 921_600),
        ("ttmrf", "ttmrf-text", 921_600),
    ];
    let mut rec =
        RawRecorder::with_read_intervals(Cursor::new(Vec::new()), &ports, &[0, 10_000_000])
            .unwrap();
    rec.write_raw(0, 100, b"ab").unwrap();
    rec.write_raw(1, 200, b"cd").unwrap();
    let bytes = rec.finish().unwrap().into_inner();
    let mut got = Vec::new();
    read_recording::<()>(&bytes, |m| {
        if let Recorded::Raw { device, link, .. } = m {
            got.push((device.to_string(), link.read_interval_ns));
        }
        Ok(())
    })
    .unwrap();
    // 0 is not written (a recording without the key reads as "on arrival").
    assert_eq!(
        got,
        [("vn200".to_string(), 0), ("ttmrf".to_string(), 10_000_000)]
    );
}

/// Issue 18 point 1: a port's adapter latency timer, baud and stated transmit buffer are
/// channel metadata, read back with every chunk of the channel; a port without a timer reads
/// 0, one without a stated buffer `None`, and so does a buffer of 0 bytes (no statement).
#[test]
fn adapter_timers_and_bauds_are_kept_per_channel_and_read_back() {
    use vigil_record::{PortLink, RawRecorder};
    let watson = PortLink {
        latency_timer_ns: 16_000_000,
        read_interval_ns: 2_000_000,
        ..PortLink::baud(9600)
    };
    let ttmrf = PortLink {
        output_buffer_bytes: Some(4096),
        ..PortLink::baud(115_200)
    };
    let zero_buffer = PortLink {
        output_buffer_bytes: Some(0),
        ..PortLink::baud(115_200)
    };
    let mut rec = RawRecorder::new(Cursor::new(Vec::new()), &[]).unwrap();
    rec.add_port_with_link("watson", "watson-ahrs-e304", &watson)
        .unwrap();
    rec.add_port("vn200", "vn200-icd", 921_600, 0).unwrap();
    rec.add_port_with_link("ttmrf", "ttmrf-text", &ttmrf)
        .unwrap();
    rec.add_port_with_link("adsb", "ttmrf-gdl90", &zero_buffer)
        .unwrap();
    rec.write_raw(0, 100, b"ab").unwrap();
    rec.write_raw(1, 200, b"cd").unwrap();
    rec.write_raw(2, 300, b"ef").unwrap();
    rec.write_raw(3, 400, b"gh").unwrap();
    rec.write_raw(0, 500, b"ij").unwrap();
    let bytes = rec.finish().unwrap().into_inner();
    let mut got = Vec::new();
    read_recording::<()>(&bytes, |m| {
        if let Recorded::Raw { device, link, .. } = m {
            got.push((device.to_string(), link));
        }
        Ok(())
    })
    .unwrap();
    let name = |d: &str| d.to_string();
    assert_eq!(
        got,
        [
            (name("watson"), watson),
            (name("vn200"), PortLink::baud(921_600)),
            (name("ttmrf"), ttmrf),
            (name("adsb"), PortLink::baud(115_200)),
            (name("watson"), watson),
        ]
    );
}

/// Issue 20: messages grouped by channel inside a chunk (a writer that buffers per port) replay
/// in receive order, and the file is zstd-compressed by default.
#[test]
fn regression_20_any_order_within_a_chunk_replays_in_receive_order() {
    use vigil_record::RawRecorder;
    let ports = [
        ("bahrs", "bahrs-2.0", 115_200),
        ("vn200", "vn200-icd", 921_600),
    ];
    let mut rec = RawRecorder::new(Cursor::new(Vec::new()), &ports).unwrap();
    // Port 0 at 10, 30, 50 ns, then port 1 at 20, 40, 60 ns: grouped, not in time order.
    for (port, t) in [(0u16, 10u64), (0, 30), (0, 50), (1, 20), (1, 40), (1, 60)] {
        rec.write_raw(port, t, &[t as u8]).unwrap();
    }
    rec.flush().unwrap();
    // The next chunk starts later: everything before it is released in order.
    rec.write_raw(1, 70, &[70]).unwrap();
    let bytes = rec.finish().unwrap().into_inner();
    let mut got = Vec::new();
    let o = read_recording::<()>(&bytes, |m| {
        if let Recorded::Raw {
            t_host_ns, bytes, ..
        } = m
        {
            assert_eq!(bytes, [t_host_ns as u8]);
            got.push(t_host_ns);
        }
        Ok(())
    })
    .unwrap();
    assert_eq!(got, [10, 20, 30, 40, 50, 60, 70]);
    assert_eq!(o.damage, None);
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert!(
        summary
            .chunk_indexes
            .iter()
            .all(|c| c.compression == "zstd")
    );
}

/// Issue 20: a damaged chunk is skipped and said so; the chunks after it are read.
#[test]
fn regression_20_a_damaged_chunk_is_skipped_and_the_rest_replays() {
    let bytes = record("nominal", 20, 1);
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    let chunks = &summary.chunk_indexes;
    assert!(chunks.len() > 4, "{} chunks", chunks.len());
    let count = |b: &[u8]| {
        let mut n = 0u64;
        let o = read_recording::<()>(b, |_| {
            n += 1;
            Ok(())
        })
        .unwrap();
        (n, o)
    };
    let (all, _) = count(&bytes);
    // Flip bytes in the middle of the third chunk's compressed records.
    let c = &chunks[2];
    let mut bad = bytes.clone();
    let mid = (c.chunk_start_offset + c.chunk_length / 2) as usize;
    for b in &mut bad[mid..mid + 16] {
        *b ^= 0x5A;
    }
    let (n, o) = count(&bad);
    assert_eq!(o.skipped_chunks, 1, "{o:?}");
    let damage = o.damage.unwrap();
    assert!(
        damage.contains(&format!("chunk at byte {}", c.chunk_start_offset)),
        "{damage}"
    );
    assert!(n < all && n > all / 2, "{n} of {all}");
}

/// Issue 20 ("a recording is valid in any message order ... whatever writer made it"): a file
/// written without chunks, as other MCAP writers may, replays the same raw messages in the same
/// order as the chunked original, with nothing reported as damaged.
#[test]
fn regression_20_an_unchunked_recording_replays_like_the_chunked_one() {
    let chunked = record("nominal", 5, 3);
    let mut writer = mcap::WriteOptions::new()
        .use_chunks(false)
        .create(Cursor::new(Vec::new()))
        .unwrap();
    let mut copied = 0;
    for m in mcap::MessageStream::new(&chunked).unwrap() {
        writer.write(&m.unwrap()).unwrap();
        copied += 1;
    }
    writer.finish().unwrap();
    let unchunked = writer.into_inner().into_inner();
    let summary = mcap::Summary::read(&unchunked).unwrap().unwrap();
    assert!(summary.chunk_indexes.is_empty(), "the copy has no chunks");
    let raw = |b: &[u8]| {
        let mut got = Vec::new();
        let o = read_recording::<()>(b, |m| {
            if let Recorded::Raw {
                device,
                t_host_ns,
                bytes,
                ..
            } = m
            {
                got.push((device.to_string(), t_host_ns, bytes.to_vec()));
            }
            Ok(())
        })
        .unwrap();
        (got, o)
    };
    let (a, _) = raw(&chunked);
    let (b, o) = raw(&unchunked);
    assert!(
        a.len() > 1000 && copied >= a.len(),
        "{} raw of {copied}",
        a.len()
    );
    assert_eq!(a, b);
    assert_eq!(o.damage, None);
    assert_eq!(o.skipped_chunks, 0);
}

/// Issue 20: a message that arrives in the file long before its receive time (here the sixth
/// one written, received last) waits in the reorder window while megabytes of others pass it;
/// every message comes out once, intact, in receive order (the reader compacts its buffer
/// meanwhile, so its memory stays bounded).
#[test]
fn regression_20_a_long_held_message_keeps_everything_in_order() {
    use vigil_record::RawRecorder;
    let ports = [("vn200", "vn200-icd", 921_600)];
    let mut rec = RawRecorder::new(Cursor::new(Vec::new()), &ports).unwrap();
    let body = |t: u64| -> Vec<u8> { (0..10_000).map(|i| (t as usize + i) as u8).collect() };
    for t in 1..=300u64 {
        rec.write_raw(0, t, &body(t)).unwrap();
        if t == 5 {
            rec.write_raw(0, 10_000, &body(10_000)).unwrap();
        }
    }
    let bytes = rec.finish().unwrap().into_inner();
    let summary = mcap::Summary::read(&bytes).unwrap().unwrap();
    assert!(summary.chunk_indexes.len() > 5, "several chunks");
    let mut got = Vec::new();
    let o = read_recording::<()>(&bytes, |m| {
        if let Recorded::Raw {
            t_host_ns, bytes, ..
        } = m
        {
            assert_eq!(bytes, body(t_host_ns), "message at {t_host_ns}");
            got.push(t_host_ns);
        }
        Ok(())
    })
    .unwrap();
    let want: Vec<u64> = (1..=300).chain([10_000]).collect();
    assert_eq!(got, want);
    assert_eq!(o.damage, None);
}
