//! Issue 24 acceptance, "no field in any output line is NaN where the payload documents a
//! number": every golden recording (the six fail-safe cases among them) is replayed through the
//! service, and every traffic and ownship payload it publishes is checked field by field against
//! the payloads' documentation (bus/src/payload/traffic.rs and ownship.rs): a field may be NaN
//! only where its doc comment or a set `FLAG_*` bit says it is unknown; nothing is infinite.

use std::path::Path;

use vigil_bus::payload::ownship::{
    FLAG_VELOCITY_UNKNOWN as OWN_VELOCITY, FLAG_VERTICAL_RATE_UNKNOWN as OWN_VERTICAL,
};
use vigil_bus::payload::traffic::{
    FLAG_ALTITUDE_UNKNOWN, FLAG_OWNSHIP_VELOCITY_UNKNOWN, FLAG_OWNSHIP_VERTICAL_RATE_UNKNOWN,
    FLAG_STALE, FLAG_VELOCITY_UNKNOWN, FLAG_VERTICAL_RATE_UNKNOWN, Target,
};
use vigil_bus::{OwnshipPayload, Payload, TrafficPayload};

use vigil_service::config::Config;
use vigil_service::replay::fused::replay_service;
use vigil_service::{Outputs, Service};

#[derive(Default)]
struct Audit {
    targets: u64,
    ownships: u64,
    nan_fields: u64,
    problems: Vec<String>,
}

impl Audit {
    /// `value` may be NaN only when `allowed` (and is never infinite).
    fn field(&mut self, what: &str, name: &str, value: f64, allowed: bool) {
        if value.is_nan() {
            self.nan_fields += 1;
        }
        if value.is_infinite() || (value.is_nan() && !allowed) {
            self.problems.push(format!("{what}: {name} = {value}"));
        }
    }

    fn target(&mut self, x: &Target) {
        self.targets += 1;
        let what = format!("target {:06X} flags {:#x}", x.address, x.flags);
        let has = |bits: u64| x.flags & bits != 0;
        let stale = has(FLAG_STALE);
        let velocity = stale || has(FLAG_OWNSHIP_VELOCITY_UNKNOWN | FLAG_VELOCITY_UNKNOWN);
        let vertical = stale || has(FLAG_ALTITUDE_UNKNOWN);
        let rate = velocity
            || vertical
            || has(FLAG_VERTICAL_RATE_UNKNOWN | FLAG_OWNSHIP_VERTICAL_RATE_UNKNOWN);
        for (name, v, ok) in [
            ("rel_north_m", x.rel_north_m, stale),
            ("rel_east_m", x.rel_east_m, stale),
            ("horizontal_distance_m", x.horizontal_distance_m, stale),
            ("bearing_deg", x.bearing_deg, stale),
            ("age_s", x.age_s, false),
            ("rel_down_m", x.rel_down_m, vertical),
            ("rel_vel_north_mps", x.rel_vel_north_mps, velocity),
            ("rel_vel_east_mps", x.rel_vel_east_mps, velocity),
            ("range_rate_mps", x.range_rate_mps, velocity),
            ("tcpa_s", x.tcpa_s, velocity),
            ("hmd_m", x.hmd_m, velocity),
            ("rel_vel_down_mps", x.rel_vel_down_mps, rate),
            // Documented NaN when undefined (diverging, inside DMOD; no loss predicted).
            ("tau_mod_s", x.tau_mod_s, true),
            ("time_to_lowc_s", x.time_to_lowc_s, true),
        ] {
            self.field(&what, name, v, ok);
        }
    }

    fn ownship(&mut self, o: &OwnshipPayload) {
        if o.valid == 0 {
            return;
        }
        self.ownships += 1;
        let what = format!("ownship at {} flags {:#x}", o.header.gps_time_ns, o.flags);
        let velocity = o.flags & OWN_VELOCITY != 0;
        let vertical = o.flags & OWN_VERTICAL != 0;
        for (name, v, ok) in [
            ("lat_deg", o.lat_deg, false),
            ("lon_deg", o.lon_deg, false),
            ("vel_north_mps", o.vel_north_mps, velocity),
            ("vel_east_mps", o.vel_east_mps, velocity),
            ("ground_speed_mps", o.ground_speed_mps, velocity),
            ("track_deg", o.track_deg, velocity),
            ("vel_up_mps", o.vel_up_mps, vertical),
            // Documented "NaN when unknown" without a flag of their own.
            ("alt_pressure_m", o.alt_pressure_m, true),
            ("alt_geometric_m", o.alt_geometric_m, true),
            ("sigma_horizontal_m", o.sigma_horizontal_m, true),
            ("sigma_vertical_m", o.sigma_vertical_m, true),
            ("sigma_velocity_mps", o.sigma_velocity_mps, true),
        ] {
            self.field(&what, name, v, ok);
        }
    }
}

impl Outputs for Audit {
    fn publish<T: Payload>(&mut self, p: &T) {
        use std::any::Any;
        let any = p as &dyn Any;
        if let Some(t) = any.downcast_ref::<TrafficPayload>() {
            for x in t.targets() {
                self.target(x);
            }
        } else if let Some(o) = any.downcast_ref::<OwnshipPayload>() {
            self.ownship(o);
        }
    }
}

#[test]
fn regression_24_no_payload_field_is_nan_unless_documented_unknown() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../tests/data/replay");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| {
            let p = e.unwrap().path();
            (p.extension()? == "mcap").then_some(p)
        })
        .collect();
    names.sort();
    assert!(names.len() >= 13, "{} recordings", names.len());
    let cfg = Config::default();
    let mut total = Audit::default();
    for path in names {
        let mut audit = Audit::default();
        let mut service = Service::new(
            &[],
            cfg.pipeline.pipeline_config(),
            cfg.monitor,
            cfg.link.silence_s,
        )
        .unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        replay_service(file, &cfg, &mut service, &mut audit, |_, _| Ok(())).unwrap();
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        eprintln!(
            "{name}: {} targets, {} ownship states, {} documented-unknown NaN fields",
            audit.targets, audit.ownships, audit.nan_fields
        );
        assert!(audit.ownships > 0, "{name}: no ownship state published");
        assert!(
            audit.problems.is_empty(),
            "{name}: {} undocumented NaN or infinite fields, first: {:?}",
            audit.problems.len(),
            &audit.problems[..audit.problems.len().min(5)]
        );
        total.targets += audit.targets;
        total.nan_fields += audit.nan_fields;
    }
    // The fail-safe recordings do exercise unknowns: the audit is not vacuous.
    assert!(total.targets > 300 && total.nan_fields > 1000);
}
