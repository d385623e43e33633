//! A DAA-side regression test against a recorded flight: subscribe (lossless mode), have
//! `vigil replay --publish --speed max` publish the recording, and assert on what arrived. Copy
//! it into a DAA stack's test suite and replace the assertions with the stack's own.
//!
//! Run from the vigil repository (after `cargo build --release`):
//! `cargo run -p vigil-bus --example daa_regression -- target/release/vigil tests/data/replay/headon.mcap`
//!
//! The head-on recording (55 s): an ADS-B intruder 3 km ahead, closing at 100 m/s, at the
//! ownship's height; closest approach at 30 s, beyond DTHR (1219 m) again at 42 s. Every traffic
//! picture must hold it, the range changing by about 100 m per 1 s picture, at a warning
//! (level 3) once the filter has seen two steps and while it is inside DTHR, and no longer
//! alerting at the end of the recording.

use std::process::Command;
use std::time::{Duration, Instant};

use vigil_bus::payload::traffic::ALERT_WARNING;
use vigil_bus::{Bus, BusConfig};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let vigil = args.next().unwrap_or_else(|| "vigil".into());
    let recording = args
        .next()
        .unwrap_or_else(|| "tests/data/replay/headon.mcap".into());
    let prefix = format!("daa-regression-{}", std::process::id());

    // 1. Subscribe first, in the lossless mode the replay publishes in.
    let bus = Bus::new(&BusConfig {
        prefix: prefix.clone(),
        node_name: "daa-regression".into(),
        lossless_wait_s: Some(5.0),
        ..BusConfig::default()
    })?;
    let mut traffic = bus.traffic_subscriber()?;

    // 2. Replay the recording onto the bus, as fast as this subscriber keeps up.
    let mut replay = Command::new(&vigil)
        .args(["replay", &recording, "--publish", "--speed", "max"])
        .args(["--prefix", &prefix])
        .spawn()?;

    // 3. Collect every picture until the replay ends.
    let mut pictures: Vec<(u64, u32, f64, u8)> = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        let done = replay.try_wait()?.is_some();
        traffic.wait(Duration::from_millis(20))?;
        while let Some(t) = traffic.try_receive()? {
            let first = t.targets().first().copied();
            pictures.push((
                t.header().seq,
                first.map_or(0, |x| x.address),
                first.map_or(f64::NAN, |x| x.horizontal_distance_m),
                first.map_or(0, |x| x.alert_level),
            ));
        }
        if done || Instant::now() > deadline {
            break;
        }
    }
    let status = replay.wait()?;
    assert!(status.success(), "vigil replay failed: {status}");

    // 4. Assert on what arrived.
    assert!(!pictures.is_empty(), "no traffic picture arrived");
    for (i, p) in pictures.iter().enumerate() {
        assert_eq!(p.0, i as u64 + 1, "picture {} missing", i + 1);
        assert_eq!(p.1, 0x4B1A01, "the intruder is in every picture");
    }
    for w in pictures.windows(2) {
        // Closing, then opening (100 m/s, +-15 m of report noise); the step that spans the
        // closest approach changes less.
        let change = (w[0].2 - w[1].2).abs();
        let near_cpa = w[0].2.min(w[1].2) < 150.0;
        assert!(
            near_cpa || (85.0..115.0).contains(&change),
            "range change {change} m per step"
        );
    }
    let closest = (0..pictures.len())
        .min_by(|&a, &b| pictures[a].2.total_cmp(&pictures[b].2))
        .unwrap();
    let inside_dthr_until = (closest..pictures.len())
        .take_while(|&i| pictures[i].2 < 1219.2)
        .last()
        .unwrap_or(closest);
    assert!(
        pictures[2..=inside_dthr_until]
            .iter()
            .all(|p| p.3 == ALERT_WARNING)
    );
    assert_eq!(
        pictures[pictures.len() - 1].3,
        0,
        "still alerting at the end"
    );
    println!(
        "ok: {} pictures, range {:.0} m -> {:.0} m, warning until clear of DTHR, then cleared",
        pictures.len(),
        pictures[0].2,
        pictures[pictures.len() - 1].2
    );
    Ok(())
}
