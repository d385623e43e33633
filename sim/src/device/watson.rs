//! Watson AHRS-E304 device model: the 64-byte ASCII attitude line ("RS-232 output format") at about
//! 11.85 Hz on its own free-running clock, sent at 9600 baud (one line takes 66.7 ms on the wire).
//!
//! Decisions (the document defines no axes or signs):
//! - bank = roll, elevation = pitch, heading = magnetic heading (true yaw - declination, plus any
//!   scheduled magnetic disturbance);
//! - accelerations are the body specific force in g with x forward, y right and the z sign
//!   inverted, so a level unit reads z = +1.00 g as in the document's example line;
//! - rates are the body angular rates (x forward, y right, z down) in deg/s;
//! - velocity is the true airspeed (no wind: the 3-D speed) in km/h;
//! - a value beyond a field's range is clamped by the encoder and the line is sent in lower case
//!   (over-range).
//!
//! Its oscillator drifts by a value drawn within +-50 ppm. Truth values are the true quantities in
//! the line's own units.

use serde_json::json;
use vigil_drivers::watson::{Kind, Line};

use vigil_drivers::protocol::Protocol;

use super::{DeviceModel, Emission, FaultSchedule};
use crate::rng::Rng;
use crate::scenario::WatsonConfig;
use crate::truth::World;
use crate::units::G0_MPS2;

/// Time from the sample to the first byte being ready, ns.
pub const LATENCY_NS: i64 = 1_000_000;

/// The Watson model.
pub struct WatsonModel {
    cfg: WatsonConfig,
    noise: Rng,
    period_ns: f64,
    first_ns: i64,
    k: u64,
}

impl WatsonModel {
    /// A Watson powered on before the scenario start, its line phase random.
    pub fn new(cfg: &WatsonConfig, world: &World, seed: u64) -> Self {
        let mut clock = Rng::stream(seed, "watson/clock");
        let drift = clock.range(-50e-6, 50e-6);
        let period_ns = 1e9 / cfg.rate_hz / (1.0 + drift);
        let first_ns = world.start_gps_ns + (clock.uniform() * period_ns) as i64;
        Self {
            cfg: cfg.clone(),
            noise: Rng::stream(seed, "watson/noise"),
            period_ns,
            first_ns,
            k: 0,
        }
    }

    fn sample_time(&self) -> i64 {
        self.first_ns + (self.k as f64 * self.period_ns).round() as i64
    }
}

impl DeviceModel for WatsonModel {
    fn name(&self) -> &'static str {
        "watson"
    }

    fn protocol(&self) -> &'static str {
        Protocol::Watson.name()
    }

    fn baud(&self) -> u32 {
        self.cfg.baud
    }

    fn advance(
        &mut self,
        world: &World,
        faults: &FaultSchedule,
        until_gps_ns: i64,
        out: &mut Vec<Emission>,
    ) {
        loop {
            let t = self.sample_time();
            if t + LATENCY_NS >= until_gps_ns {
                return;
            }
            self.k += 1;
            let o = world.ownship(t);
            let mag = faults.magnetic_offset_rad(world.elapsed_s(t));
            let f = o.specific_force_body_mps2;
            let accel_g = [f[0] / G0_MPS2, f[1] / G0_MPS2, -f[2] / G0_MPS2];
            let rate_dps = o.angular_rate_body_radps.map(f64::to_degrees);
            let speed_kmh = o.vel_ned_mps.iter().map(|v| v * v).sum::<f64>().sqrt() * 3.6;
            let heading_deg = (o.heading_mag_rad + mag).to_degrees().rem_euclid(360.0);
            let n = &self.cfg.noise;
            let mut line = Line {
                kind: Kind::Inertial,
                over_range: false,
                bank_deg: o.roll_rad.to_degrees() + self.noise.gauss(n.tilt_deg),
                elevation_deg: o.pitch_rad.to_degrees() + self.noise.gauss(n.tilt_deg),
                heading_deg: (heading_deg + self.noise.gauss(n.heading_deg)).rem_euclid(360.0),
                accel_g: accel_g.map(|a| a + self.noise.gauss(n.accel_g)),
                rate_dps: rate_dps.map(|r| r + self.noise.gauss(n.rate_dps)),
                velocity_kmh: speed_kmh + self.noise.gauss(n.velocity_kmh),
            };
            line.over_range = line.accel_g.iter().any(|a| a.abs() > 9.99)
                || line.rate_dps.iter().any(|r| r.abs() > 99.9)
                || line.velocity_kmh.abs() > 799.9;
            let values = json!({
                "bank_deg": o.roll_rad.to_degrees(),
                "elevation_deg": o.pitch_rad.to_degrees(),
                "heading_deg": heading_deg,
                "accel_g": accel_g,
                "rate_dps": rate_dps,
                "velocity_kmh": speed_kmh,
                "over_range": line.over_range,
            });
            let values = match values {
                serde_json::Value::Object(m) => m,
                _ => serde_json::Map::new(),
            };
            out.push(Emission {
                t_ready_gps_ns: t + LATENCY_NS,
                bytes: line.to_bytes(),
                kind: "line",
                t_gps_ns: t,
                values,
            });
        }
    }
}
