//! Issue 20: `vigil replay --out RICH.mcap`, a recording re-processed into a rich one.

use std::collections::BTreeSet;
use std::fs::File;

use vigil_service::config::Config;
use vigil_service::recording::ChannelSet;
use vigil_service::replay::config::ConfigSource;
use vigil_service::replay::rich::replay_rich;
use vigil_sim::record::McapSink;
use vigil_sim::scenario::builtin;

/// Issue 20: a re-processed recording has a schema on every channel, the original raw
/// chunks (host times in `publish_time`), the fused channels, and log times on the flight's
/// UTC timeline: the first within a second of the simulator's start (its own truth), every
/// raw one at its host time plus one constant offset (to the rounding of the clock model).
#[test]
fn regression_20_rich_recording_is_on_the_utc_timeline_with_schemas() {
    let dir = std::env::temp_dir().join(format!("vigil-rich-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (src, out) = (dir.join("headon.mcap"), dir.join("rich.mcap"));
    let mut sim = vigil_sim::Simulator::new(&builtin("headon").unwrap(), 3).unwrap();
    let mut sink = McapSink::new(File::create(&src).unwrap(), None)
        .unwrap()
        .without_truth_channel();
    sim.run(40_000_000_000, &mut sink).unwrap();
    sink.finish().unwrap();
    let start_gps_ns: i64 =
        vigil_record::read_metadata(&std::fs::read(&src).unwrap()).unwrap()["start_gps_ns"]
            .parse()
            .unwrap();
    let summary = replay_rich(
        &src,
        &Config::default(),
        &ConfigSource::Defaults,
        &out,
        ChannelSet::All,
    )
    .unwrap();
    assert_eq!(summary.damage, None);
    let bytes = std::fs::read(&out).unwrap();
    let mut topics = BTreeSet::new();
    let mut raw = 0u64;
    let mut first_log = u64::MAX;
    let mut offsets = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let schema = m
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        if m.channel.message_encoding == "json" {
            assert_eq!(schema.encoding, "jsonschema", "{}", m.channel.topic);
            let v: serde_json::Value = serde_json::from_slice(&m.data).unwrap();
            assert!(v.is_object());
        } else {
            assert!(schema.name.starts_with("vigil.raw."), "{}", schema.name);
            raw += 1;
            offsets.push(m.log_time as i64 - m.publish_time as i64);
        }
        topics.insert(m.channel.topic.clone());
        first_log = first_log.min(m.log_time);
    }
    let in_raw: u64 = summary
        .devices
        .values()
        .map(|d| match d {
            vigil_drivers::replay::PortSummary::Decoded(_) => 0,
            vigil_drivers::replay::PortSummary::NoDecoder { chunks, .. } => *chunks,
        })
        .sum::<u64>();
    assert_eq!(in_raw, 0, "every port decoded");
    let mut n_in = 0u64;
    vigil_record::read_recording::<()>(&std::fs::read(&src).unwrap(), |m| {
        n_in += u64::from(matches!(m, vigil_record::Recorded::Raw { .. }));
        Ok(())
    })
    .unwrap();
    assert_eq!(raw, n_in);
    for t in [
        "/vigil/attitude_check",
        "/vigil/ownship",
        "/vigil/ownship/fix",
        "/vigil/traffic",
        "/vigil/traffic/geojson",
        "/vigil/integrity",
        "/vigil/alerts",
        "/vigil/alerts/log",
        "/vn200/decoded",
    ] {
        assert!(topics.contains(t), "{t} missing: {topics:?}");
    }
    // GPS -> UTC by hand: the GPS epoch is 315 964 800 s after the Unix epoch; 18 leap s.
    let start_utc_ns = start_gps_ns + (315_964_800 - 18) * 1_000_000_000;
    let d = first_log as i64 - start_utc_ns;
    assert!(
        d.abs() < 1_000_000_000,
        "first log time {d} ns from the start"
    );
    let (lo, hi) = (offsets.iter().min().unwrap(), offsets.iter().max().unwrap());
    assert!(hi - lo < 5_000_000, "offset varies by {} ns", hi - lo);
    let _ = std::fs::remove_dir_all(&dir);
}
