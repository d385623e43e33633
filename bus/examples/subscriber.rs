//! A minimal vigil consumer, to copy into a detect-and-avoid stack: subscribe to the traffic
//! picture and the alerts, wait for the publisher's wake-up (no polling), read samples in place.
//!
//! Run `cargo run -p vigil-bus --example subscriber -- [PREFIX] [SECONDS]` next to a running
//! `vigil run` (or `vigil demo`); PREFIX is the deployment prefix of its configuration (default
//! none), SECONDS how long to listen (default 10).

use std::time::{Duration, Instant};

use vigil_bus::payload::alerts::{SEVERITY_CAUTION, SEVERITY_WARNING, STATE_RAISED};
use vigil_bus::{AlertPayload, Bus, BusConfig};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let prefix = args.next().unwrap_or_default();
    let seconds: f64 = args.next().map(|s| s.parse()).transpose()?.unwrap_or(10.0);

    let mut bus = Bus::new(&BusConfig {
        prefix,
        node_name: "daa-example".into(),
        handle_signals: true,
        ..BusConfig::default()
    })?;
    let mut traffic = bus.traffic_subscriber()?;
    let mut alerts = bus.subscriber::<AlertPayload>()?;

    let end = Instant::now() + Duration::from_secs_f64(seconds);
    while Instant::now() < end && !bus.termination_requested() {
        // Traffic is latest-state-wins: drain and keep only the newest picture.
        let mut latest = None;
        while let Some(sample) = traffic.try_receive()? {
            latest = Some(sample);
        }
        if let Some(t) = latest {
            let most_urgent = t.targets().first();
            println!(
                "traffic seq {} ({} missed so far): {} targets, most urgent {:?}",
                t.header().seq,
                traffic.missed(),
                t.targets().len(),
                most_urgent.map(|x| (
                    format!("{:06X}", x.address),
                    x.alert_level,
                    x.time_to_lowc_s
                )),
            );
        }
        // Alerts are events: read every one; a gap in seq means some were lost.
        while let Some(a) = alerts.try_receive()? {
            let severity = match a.severity {
                SEVERITY_WARNING => "WARNING",
                SEVERITY_CAUTION => "CAUTION",
                _ => "ADVISORY",
            };
            let state = if a.state == STATE_RAISED {
                "raised"
            } else {
                "cleared"
            };
            println!("alert {} {severity} {state}: {}", a.alert_id, a.reason());
            if a.missed_before > 0 {
                println!("  ({} alerts lost before this one)", a.missed_before);
            }
        }
        bus.cleanup_if_due();
        // Sleep until the traffic publisher signals (alerts are checked at least every 100 ms).
        traffic.wait(Duration::from_millis(100))?;
    }
    Ok(())
}
