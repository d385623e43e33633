//! Truth at any GPS time: the ownship's position, velocity, attitude, body rates and specific
//! force, pressure altitude and magnetic declination, and every intruder's state; plus the
//! per-message truth records the simulator writes.

use serde::Serialize;

use crate::geo::LocalFrame;
use crate::magnetic::{Declination, MagneticModel};
use crate::scenario::{Intruder, Link, Scenario, ScenarioError};
use crate::trajectory::{Kinematics, Trajectory};
use crate::units::{
    G0_MPS2, NS_PER_S, geopotential_m, isa_pressure_pa, parse_utc_to_gps_ns, pressure_altitude_m,
};

/// The ownship's true state at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OwnshipTruth {
    /// GPS time, ns since 1980-01-06.
    pub t_gps_ns: i64,
    /// Latitude, deg (WGS-84).
    pub lat_deg: f64,
    /// Longitude, deg (WGS-84).
    pub lon_deg: f64,
    /// Height above the WGS-84 ellipsoid (= above mean sea level in the simulated world), m.
    pub height_m: f64,
    /// Velocity north, east, down, m/s.
    pub vel_ned_mps: [f64; 3],
    /// True heading (3-2-1 yaw), rad, 0 .. 2 pi.
    pub yaw_rad: f64,
    /// Pitch, rad.
    pub pitch_rad: f64,
    /// Roll, rad.
    pub roll_rad: f64,
    /// Attitude quaternion body relative to NED, ordered (x, y, z, w) like the VN-200.
    pub quat_xyzw: [f64; 4],
    /// Body angular rate (x forward, y right, z down), rad/s.
    pub angular_rate_body_radps: [f64; 3],
    /// Body specific force, m/s^2 (level and unaccelerated: (0, 0, -9.80665)).
    pub specific_force_body_mps2: [f64; 3],
    /// Static pressure, Pa.
    pub pressure_pa: f64,
    /// Pressure altitude (standard datum 1013.25 hPa), m.
    pub alt_pressure_m: f64,
    /// Magnetic declination, rad, east positive.
    pub declination_rad: f64,
    /// 1-sigma uncertainty of the declination model, rad.
    pub declination_sigma_rad: f64,
    /// Magnetic heading = yaw - declination, rad, 0 .. 2 pi.
    pub heading_mag_rad: f64,
}

/// One intruder's true state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IntruderTruth {
    /// 24-bit address, hex.
    pub address: String,
    /// Link.
    pub link: Link,
    /// Callsign.
    pub callsign: String,
    /// Emitter category.
    pub emitter_category: String,
    /// Latitude, deg.
    pub lat_deg: f64,
    /// Longitude, deg.
    pub lon_deg: f64,
    /// Height above the WGS-84 ellipsoid, m.
    pub height_m: f64,
    /// Pressure altitude, m.
    pub alt_pressure_m: f64,
    /// Velocity north, east, down, m/s.
    pub vel_ned_mps: [f64; 3],
    /// Track over ground, rad.
    pub track_rad: f64,
    /// For a spoofed target, the position it reports: (lat deg, lon deg, height m).
    pub reported_position: Option<[f64; 3]>,
    // --- issue 24 ---
    /// Fields its reports leave out ("altitude", "velocity", "vertical_rate").
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub omit: Vec<String>,
    /// Age of the data its reports carry, s.
    pub report_age_s: f64,
    /// Not received at this time (silent).
    pub silent: bool,
}

impl IntruderTruth {
    /// Whether its reports leave `field` out.
    pub fn omits(&self, field: &str) -> bool {
        self.omit.iter().any(|f| f == field)
    }
}

struct IntruderTrack {
    meta: Intruder,
    trajectory: Trajectory,
}

/// The simulated world: trajectories, atmosphere and magnetic field.
pub struct World {
    /// GPS time of the scenario start, ns.
    pub start_gps_ns: i64,
    /// Local frame at the scenario origin.
    pub frame: LocalFrame,
    ownship: Trajectory,
    intruders: Vec<IntruderTrack>,
    qnh_pa: f64,
    magnetic: Box<dyn MagneticModel>,
}

/// Rotation body -> NED (`C_nb`) of 3-2-1 Euler angles; rows are NED axes.
pub fn dcm_nb(yaw: f64, pitch: f64, roll: f64) -> [[f64; 3]; 3] {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let (sr, cr) = roll.sin_cos();
    [
        [cp * cy, sr * sp * cy - cr * sy, cr * sp * cy + sr * sy],
        [cp * sy, sr * sp * sy + cr * cy, cr * sp * sy - sr * cy],
        [-sp, sr * cp, cr * cp],
    ]
}

/// Quaternion (x, y, z, w) of 3-2-1 Euler angles.
pub fn quat_xyzw(yaw: f64, pitch: f64, roll: f64) -> [f64; 4] {
    let (sy, cy) = (yaw / 2.0).sin_cos();
    let (sp, cp) = (pitch / 2.0).sin_cos();
    let (sr, cr) = (roll / 2.0).sin_cos();
    [
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    ]
}

impl World {
    /// Builds the world of a scenario with the given magnetic model.
    pub fn new(s: &Scenario, magnetic: Box<dyn MagneticModel>) -> Result<Self, ScenarioError> {
        let start_gps_ns = parse_utc_to_gps_ns(&s.start_utc)?;
        let frame = LocalFrame::new(s.ownship.lat_deg, s.ownship.lon_deg);
        let o = &s.ownship;
        let ownship = Trajectory::new(
            0.0,
            0.0,
            o.height_m,
            o.track_deg,
            o.speed_mps,
            &o.expanded_segments(),
        );
        let intruders = s
            .all_intruders()
            .into_iter()
            .map(|i| IntruderTrack {
                trajectory: Trajectory::new(
                    i.north_m,
                    i.east_m,
                    i.height_m,
                    i.track_deg,
                    i.speed_mps,
                    &i.segments,
                ),
                meta: i,
            })
            .collect();
        Ok(Self {
            start_gps_ns,
            frame,
            ownship,
            intruders,
            qnh_pa: s.qnh_hpa * 100.0,
            magnetic,
        })
    }

    /// Seconds since the scenario start of a GPS time.
    pub fn elapsed_s(&self, t_gps_ns: i64) -> f64 {
        (t_gps_ns - self.start_gps_ns) as f64 / NS_PER_S as f64
    }

    /// Pressure altitude of a height above mean sea level, m.
    pub fn alt_pressure_m(&self, height_m: f64) -> f64 {
        pressure_altitude_m(self.pressure_pa(height_m))
    }

    fn pressure_pa(&self, height_m: f64) -> f64 {
        isa_pressure_pa(geopotential_m(height_m), self.qnh_pa)
    }

    /// The ownship's kinematic state (local plane) at a GPS time.
    pub fn ownship_kinematics(&self, t_gps_ns: i64) -> Kinematics {
        self.ownship.at(self.elapsed_s(t_gps_ns))
    }

    /// The ownship's true state at a GPS time. A magnetic model that cannot be evaluated there
    /// gives a declination of 0 with an infinite sigma.
    pub fn ownship(&self, t_gps_ns: i64) -> OwnshipTruth {
        let k = self.ownship_kinematics(t_gps_ns);
        let (lat, lon) = self.frame.to_geodetic_rad(k.north_m, k.east_m);
        let (roll, roll_rate) = self.ownship.roll_at(self.elapsed_s(t_gps_ns));
        let (yaw, pitch) = (k.track_rad, k.pitch_rad());
        let c = dcm_nb(yaw, pitch, roll);
        // Specific force f = a - g, gravity (0, 0, g0) in NED; body = C_nb^T f.
        let f_ned = [
            k.accel_ned_mps2[0],
            k.accel_ned_mps2[1],
            k.accel_ned_mps2[2] - G0_MPS2,
        ];
        let f_body = [0, 1, 2].map(|j| (0..3).map(|i| c[i][j] * f_ned[i]).sum::<f64>());
        // Euler rates: yaw' = omega, pitch' = 0, roll' = 0 within a segment (and the roll-in
        // rate at a boundary).
        let w = k.turn_rate_radps;
        let rates = [
            roll_rate - w * pitch.sin(),
            w * roll.sin() * pitch.cos(),
            w * roll.cos() * pitch.cos(),
        ];
        let d = self
            .magnetic
            .declination(lat, lon, k.height_m, t_gps_ns)
            .unwrap_or(Declination {
                declination_rad: 0.0,
                sigma_rad: f64::INFINITY,
            });
        let pressure_pa = self.pressure_pa(k.height_m);
        OwnshipTruth {
            t_gps_ns,
            lat_deg: lat.to_degrees(),
            lon_deg: lon.to_degrees(),
            height_m: k.height_m,
            vel_ned_mps: k.vel_ned_mps,
            yaw_rad: yaw,
            pitch_rad: pitch,
            roll_rad: roll,
            quat_xyzw: quat_xyzw(yaw, pitch, roll),
            angular_rate_body_radps: rates,
            specific_force_body_mps2: f_body,
            pressure_pa,
            alt_pressure_m: pressure_altitude_m(pressure_pa),
            declination_rad: d.declination_rad,
            declination_sigma_rad: d.sigma_rad,
            heading_mag_rad: (yaw - d.declination_rad).rem_euclid(std::f64::consts::TAU),
        }
    }

    /// Number of intruders.
    pub fn intruder_count(&self) -> usize {
        self.intruders.len()
    }

    /// Every intruder's true state at a GPS time.
    pub fn intruders(&self, t_gps_ns: i64) -> Vec<IntruderTruth> {
        (0..self.intruders.len())
            .filter_map(|i| self.intruder(i, t_gps_ns))
            .collect()
    }

    /// Intruder `i`'s true state at a GPS time (`None` past the last intruder); device models
    /// that report one target at a time use it rather than evaluating every intruder.
    pub fn intruder(&self, i: usize, t_gps_ns: i64) -> Option<IntruderTruth> {
        let t = self.elapsed_s(t_gps_ns);
        let i = self.intruders.get(i)?;
        let k = i.trajectory.at(t);
        let (lat, lon) = self.frame.to_geodetic_rad(k.north_m, k.east_m);
        let m = &i.meta;
        // Spoofing over [spoof_from_s, spoof_to_s).
        let spoofed = t >= m.spoof_from_s && m.spoof_to_s.is_none_or(|to| t < to);
        let drift = m.spoof_drift_ne_mps.filter(|_| spoofed).map(|d| {
            let dt = t - m.spoof_from_s;
            [d[0] * dt, d[1] * dt, 0.0]
        });
        let spoofing = match (m.spoof_offset_ned_m.filter(|_| spoofed), drift) {
            (Some(o), Some(d)) => Some([o[0] + d[0], o[1] + d[1], o[2]]),
            (o, d) => o.or(d),
        };
        let reported_position = spoofing.map(|o| {
            let (la, lo) = self
                .frame
                .to_geodetic_rad(k.north_m + o[0], k.east_m + o[1]);
            [la.to_degrees(), lo.to_degrees(), k.height_m - o[2]]
        });
        Some(IntruderTruth {
            address: i.meta.address.clone(),
            link: i.meta.link,
            callsign: i.meta.callsign.clone(),
            emitter_category: i.meta.emitter_category.clone(),
            lat_deg: lat.to_degrees(),
            lon_deg: lon.to_degrees(),
            height_m: k.height_m,
            alt_pressure_m: self.alt_pressure_m(k.height_m),
            vel_ned_mps: k.vel_ned_mps,
            track_rad: k.track_rad,
            reported_position,
            omit: i.meta.omit.clone(),
            report_age_s: i.meta.report_age_s,
            silent: i.meta.silent_from_s.is_some_and(|s| t >= s),
        })
    }
}

/// One line of the truth file: one emitted device message.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TruthRecord {
    /// Device name ("bahrs", "watson", ...).
    pub device: &'static str,
    /// 0-based order of the message within its device's stream.
    pub index: u64,
    /// Message type name (e.g. "inertial", "line").
    #[serde(rename = "type")]
    pub kind: &'static str,
    /// True GPS time the message refers to (its sample instant), ns.
    pub t_gps_ns: i64,
    /// True GPS time its first byte started on the wire, ns.
    pub t_tx_gps_ns: i64,
    /// True when a link fault (bit error, dropped byte, link loss) damaged the message's bytes.
    pub corrupted: bool,
    /// Offset of the message's first byte in the port's received byte stream (where it would
    /// have been if lost). A decoder's `Located.offset` of an intact message equals it, so it joins
    /// `vigil replay` output (`offset`) to the truth even after losses shifted the indices.
    pub rx_offset: u64,
    /// The true values it encodes (names carry units), before noise, plus the device's own
    /// stamps (e.g. `mcu_time_us`).
    #[serde(flatten)]
    pub values: serde_json::Map<String, serde_json::Value>,
    /// The encoded message as the device sent it (before link faults); not written to the truth
    /// file (tests compare decoded messages with it).
    #[serde(skip)]
    pub wire: Vec<u8>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::magnetic::ConstantDeclination;
    use crate::scenario::builtin;

    /// Issue 25: a spoof with `spoof_to_s` reports the offset position over [from, to) only;
    /// `spoof_to_s` not after `spoof_from_s` is refused, naming the key.
    #[test]
    fn spoofing_ends_at_spoof_to_s() {
        let mut s = builtin("spoofed-target").unwrap();
        s.intruders[0].spoof_from_s = 5.0;
        s.intruders[0].spoof_to_s = Some(10.0);
        let w = World::new(&s, Box::new(crate::magnetic::Wmm2025)).unwrap();
        let at = |sec: i64| w.intruder(0, w.start_gps_ns + sec * NS_PER_S).unwrap();
        assert!(at(4).reported_position.is_none());
        let x = at(7);
        let p = x.reported_position.unwrap();
        // 2 km north of the true position: 2000 m / 111.2 km per degree of latitude.
        assert!(
            (p[0] - x.lat_deg - 2000.0 / 111_200.0).abs() < 2e-4,
            "{p:?}"
        );
        assert!(at(10).reported_position.is_none());
        assert!(at(30).reported_position.is_none());
        s.intruders[0].spoof_to_s = Some(5.0);
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("intruders[0].spoof_to_s"), "{e}");
    }

    #[test]
    fn coordinated_turn_attitude_and_forces_by_hand() {
        let s = builtin("nominal").unwrap();
        let mag = ConstantDeclination(Declination {
            declination_rad: 0.05,
            sigma_rad: 0.01,
        });
        let w = World::new(&s, Box::new(mag)).unwrap();
        // Nominal: climb 60 s, descend 60 s, then a 3 deg/s turn from t = 120 s at 40 m/s.
        let t = w.start_gps_ns + 150 * NS_PER_S;
        let o = w.ownship(t);
        // tan(roll) = 40 x 0.0523599 / 9.80665 = 0.213569 -> roll = 12.055 deg.
        assert!(
            (o.roll_rad.to_degrees() - 12.055).abs() < 0.001,
            "{}",
            o.roll_rad.to_degrees()
        );
        // In a level coordinated turn the specific force is along body z: -g / cos(roll)
        // = -9.80665 / 0.977950 = -10.0278 m/s^2, with no lateral component.
        let f = o.specific_force_body_mps2;
        assert!(f[0].abs() < 1e-9 && f[1].abs() < 1e-9, "{f:?}");
        assert!((f[2] + 10.0278).abs() < 1e-3, "{f:?}");
        // Body rates: q = omega sin(roll), r = omega cos(roll).
        let r = o.angular_rate_body_radps;
        assert!((r[1] - 3f64.to_radians() * o.roll_rad.sin()).abs() < 1e-12);
        assert!((r[2] - 3f64.to_radians() * o.roll_rad.cos()).abs() < 1e-12);
        // Magnetic heading = true - declination.
        assert!(
            ((o.yaw_rad - 0.05).rem_euclid(std::f64::consts::TAU) - o.heading_mag_rad).abs()
                < 1e-12
        );
        // Quaternion has unit norm and matches the DCM's z-axis of roll.
        let q = o.quat_xyzw;
        assert!((q.iter().map(|x| x * x).sum::<f64>() - 1.0).abs() < 1e-12);
        // Pressure altitude at 600 m on a standard day: geopotential 599.94 m.
        assert!((o.alt_pressure_m - geopotential_m(o.height_m)).abs() < 1e-6);
    }

    #[test]
    fn quaternion_of_pure_yaw() {
        // 90 deg yaw: (0, 0, sin 45, cos 45).
        let q = quat_xyzw(std::f64::consts::FRAC_PI_2, 0.0, 0.0);
        let h = 0.5f64.sqrt();
        assert!(
            q[0].abs() < 1e-15
                && q[1].abs() < 1e-15
                && (q[2] - h).abs() < 1e-15
                && (q[3] - h).abs() < 1e-15
        );
    }

    fn separation_m(w: &World, t_s: i64) -> (f64, f64) {
        let t = w.start_gps_ns + t_s * NS_PER_S;
        let o = w.ownship(t);
        let i = &w.intruders(t)[0];
        let (on, oe) = w.frame.to_local_m(o.lat_deg, o.lon_deg);
        let (inn, ie) = w.frame.to_local_m(i.lat_deg, i.lon_deg);
        ((on - inn).hypot(oe - ie), i.height_m - o.height_m)
    }

    #[test]
    fn encounter_geometry_of_the_builtins() {
        let mag = || {
            Box::new(ConstantDeclination(Declination {
                declination_rad: 0.0,
                sigma_rad: 0.0,
            }))
        };
        // headon: 8000 m apart closing at 40 + 60 m/s: together at t = 80 s, 1000 m apart at 70 s.
        let w = World::new(&builtin("headon").unwrap(), mag()).unwrap();
        assert!(separation_m(&w, 80).0 < 1e-3);
        assert!((separation_m(&w, 70).0 - 1000.0).abs() < 1e-3);
        // crossing: ownship 40 m/s north reaches 4000 m N at 100 s; the intruder starts 5000 m E
        // flying west at 50 m/s: there at 100 s as well, 30 m above.
        let w = World::new(&builtin("crossing").unwrap(), mag()).unwrap();
        let (d, dh) = separation_m(&w, 100);
        assert!(d < 1e-3 && (dh - 30.0).abs() < 1e-9, "{d} {dh}");
        // The intruder's pressure altitude is that of its height.
        let i = &w.intruders(w.start_gps_ns)[0];
        assert!((i.alt_pressure_m - geopotential_m(630.0)).abs() < 1e-6);
        // spoofed-target: honest for the first 60 s, then the reported position is 2 km north
        // and 2 km east of the true one.
        let w = World::new(&builtin("spoofed-target").unwrap(), mag()).unwrap();
        assert!(w.intruders(w.start_gps_ns)[0].reported_position.is_none());
        let t_spoof = w.start_gps_ns + 60_000_000_000;
        assert!(
            w.intruders(t_spoof - 1_000_000)[0]
                .reported_position
                .is_none()
        );
        let i = &w.intruders(t_spoof)[0];
        let rep = i.reported_position.unwrap();
        let (tn, te) = w.frame.to_local_m(i.lat_deg, i.lon_deg);
        let (rn, re) = w.frame.to_local_m(rep[0], rep[1]);
        assert!((rn - tn - 2000.0).abs() < 1e-6 && (re - te - 2000.0).abs() < 1e-6);
        assert!(w.intruders(t_spoof)[1].reported_position.is_none());
    }
}
