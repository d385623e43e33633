//! The inputs of the cross-check: one time-aligned sample per unit, in SI units, built from the
//! decoded messages (issue 8, "Inputs and references").
//!
//! The samples carry their GPS time and its 1-sigma uncertainty from the aligners
//! (`fusion::time`); a message that could not be aligned never becomes a sample.

use nalgebra::{Quaternion, UnitQuaternion};
use serde::Serialize;
use vigil_drivers::bahrs::{Accuracy, Health, Inertial, Navigation, NavigationHealth};
use vigil_drivers::vn200::binary::BinaryOutput;
use vigil_drivers::vn200::status::{ImuStatus, InsStatus};
use vigil_drivers::watson::Line;

use super::angles::from_ypr;
use crate::time::AlignedTime;

const DEG: f64 = std::f64::consts::PI / 180.0;

/// A BAHRS navigation sample (0x02) with the latest accuracy (0x03) and rates (0x01).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BahrsSample {
    /// GPS time, ns.
    pub t_gps_ns: i64,
    /// 1-sigma of the time, ns.
    pub sigma_ns: f64,
    /// Roll, rad.
    pub roll_rad: f64,
    /// Pitch, rad.
    pub pitch_rad: f64,
    /// Magnetic heading, rad.
    pub heading_mag_rad: f64,
    /// Downward velocity, m/s.
    pub velocity_down_mps: f64,
    /// Pressure height, m (standard atmosphere).
    pub pressure_height_m: f64,
    /// Per-signal health of 0x02.
    pub health: NavigationHealth,
    /// Attitude standard deviations (north tilt, east tilt, heading), rad, `None` inside when the
    /// unit marks one invalid (0); `None` outside when no 0x03 was received yet.
    pub accuracy_rad: Option<[Option<f64>; 3]>,
    /// Body angular rates x/y/z, rad/s, when the latest 0x01 says they are safe.
    pub rates_radps: Option<[f64; 3]>,
    /// The latest 0x01 with its own aligned time, for the inertial channel (issue 25 point 5);
    /// set by the pipeline (which aligns 0x01 through 0x05), `None` from [`BahrsSample::new`].
    /// Not serialised: the aligned replay output stays as it was.
    #[serde(skip)]
    pub inertial: Option<BahrsInertial>,
}

/// A BAHRS inertial sample (0x01) on GPS time, SI units, in the BAHRS body frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BahrsInertial {
    /// GPS time of the 0x01 (from its 0x05), ns.
    pub t_gps_ns: i64,
    /// 1-sigma of the time, ns.
    pub sigma_ns: f64,
    /// Specific force x/y/z, m/s^2.
    pub specific_force_mps2: [f64; 3],
    /// Angular rate x/y/z, rad/s.
    pub angular_rate_radps: [f64; 3],
    /// Health of specific force x/y/z then angular rate x/y/z.
    pub health: [Health; 6],
}

impl BahrsInertial {
    /// Builds the sample from an aligned 0x01.
    pub fn new(time: &AlignedTime, i: &Inertial) -> Self {
        let h = i.health;
        Self {
            t_gps_ns: time.t_gps_ns,
            sigma_ns: time.sigma_ns,
            specific_force_mps2: i.specific_force_mps2(),
            angular_rate_radps: i.angular_rate_radps(),
            health: [
                h.specific_force(0),
                h.specific_force(1),
                h.specific_force(2),
                h.angular_rate(0),
                h.angular_rate(1),
                h.angular_rate(2),
            ],
        }
    }
}

impl BahrsSample {
    /// Builds the sample from an aligned 0x02 and the latest 0x03 and 0x01 (if any).
    pub fn new(
        time: &AlignedTime,
        nav: &Navigation,
        accuracy: Option<&Accuracy>,
        inertial: Option<&Inertial>,
    ) -> Self {
        let rates = inertial.and_then(|i| {
            (0..3)
                .all(|a| i.health.angular_rate(a) == Health::Safe)
                .then(|| i.angular_rate_radps())
        });
        Self {
            t_gps_ns: time.t_gps_ns,
            sigma_ns: time.sigma_ns,
            roll_rad: nav.roll_rad(),
            pitch_rad: nav.pitch_rad(),
            heading_mag_rad: nav.heading_mag_rad(),
            velocity_down_mps: nav.velocity_down_mps(),
            pressure_height_m: nav.pressure_height_m(),
            health: nav.health,
            accuracy_rad: accuracy
                .map(|a| [a.std_north_rad(), a.std_east_rad(), a.std_heading_rad()]),
            rates_radps: rates,
            inertial: None,
        }
    }
}

/// A VN-200 sample: attitude (true heading), its uncertainty, status, and position/velocity.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Vn200Sample {
    /// GPS time, ns.
    pub t_gps_ns: i64,
    /// 1-sigma of the time, ns.
    pub sigma_ns: f64,
    /// Attitude, body relative to NED (true north).
    #[serde(skip)]
    pub attitude: UnitQuaternion<f64>,
    /// YprU: 1-sigma of yaw, pitch, roll, rad.
    pub ypr_sigma_rad: Option<[f64; 3]>,
    /// INS status.
    pub ins_status: InsStatus,
    /// IMU status, when output.
    pub imu_status: Option<ImuStatus>,
    /// Body angular rates, rad/s.
    pub rates_radps: Option<[f64; 3]>,
    /// Body specific force (VN-200 Accel, compensated), m/s^2; level at rest z = -9.81.
    #[serde(skip)]
    pub accel_mps2: Option<[f64; 3]>,
    /// Latitude, longitude (deg), height above the ellipsoid (m).
    pub lla: Option<[f64; 3]>,
    /// NED velocity, m/s.
    pub vel_ned_mps: Option<[f64; 3]>,
    /// PosU, m.
    pub pos_u_m: Option<f64>,
    /// VelU, m/s.
    pub vel_u_mps: Option<f64>,
}

/// The VN-200 quaternion (vector part then scalar, body relative to NED) as a unit quaternion;
/// `None` when it is not finite or far from unit length.
pub fn vn200_quaternion(x: f32, y: f32, z: f32, s: f32) -> Option<UnitQuaternion<f64>> {
    let q = Quaternion::new(f64::from(s), f64::from(x), f64::from(y), f64::from(z));
    let n = q.norm();
    (n.is_finite() && (n - 1.0).abs() < 0.01).then(|| UnitQuaternion::from_quaternion(q))
}

impl Vn200Sample {
    /// Builds the sample from one aligned binary output; `None` without attitude or InsStatus.
    /// The quaternion is preferred to yaw/pitch/roll when both are present (no Euler wrap).
    pub fn from_output(time: &AlignedTime, out: &BinaryOutput) -> Option<Self> {
        let common = out.common.as_ref();
        let att = out.attitude.as_ref();
        let ins = out.ins.as_ref();
        let quat = common
            .and_then(|c| c.quaternion)
            .or_else(|| att.and_then(|a| a.quaternion))
            .and_then(|q| vn200_quaternion(q.x, q.y, q.z, q.s));
        let ypr = common
            .and_then(|c| c.ypr)
            .or_else(|| att.and_then(|a| a.ypr));
        let attitude = quat.or_else(|| {
            ypr.map(|y| {
                from_ypr(
                    f64::from(y.yaw_deg) * DEG,
                    f64::from(y.pitch_deg) * DEG,
                    f64::from(y.roll_deg) * DEG,
                )
            })
        })?;
        let ins_status = common
            .and_then(|c| c.ins_status)
            .or_else(|| ins.and_then(|i| i.ins_status))?;
        let ypr_sigma_rad = att.and_then(|a| a.ypr_u).map(|u| {
            [
                f64::from(u.yaw_deg) * DEG,
                f64::from(u.pitch_deg) * DEG,
                f64::from(u.roll_deg) * DEG,
            ]
        });
        let f3 = |v: [f32; 3]| v.map(f64::from);
        Some(Self {
            t_gps_ns: time.t_gps_ns,
            sigma_ns: time.sigma_ns,
            attitude,
            ypr_sigma_rad,
            ins_status,
            imu_status: out.imu.as_ref().and_then(|i| i.imu_status),
            rates_radps: common
                .and_then(|c| c.angular_rate_radps)
                .or_else(|| out.imu.as_ref().and_then(|i| i.angular_rate_radps))
                .map(f3),
            accel_mps2: common
                .and_then(|c| c.accel_mps2)
                .or_else(|| out.imu.as_ref().and_then(|i| i.accel_mps2))
                .map(f3),
            lla: common
                .and_then(|c| c.pos_lla)
                .or_else(|| ins.and_then(|i| i.pos_lla))
                .map(|l| [l.lat_deg, l.lon_deg, l.alt_m]),
            vel_ned_mps: common
                .and_then(|c| c.vel_ned_mps)
                .or_else(|| ins.and_then(|i| i.vel_ned_mps))
                .map(f3),
            pos_u_m: ins.and_then(|i| i.pos_u_m).map(f64::from),
            vel_u_mps: ins.and_then(|i| i.vel_u_mps).map(f64::from),
        })
    }
}

/// A Watson sample (magnetic heading).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WatsonSample {
    /// GPS time, ns.
    pub t_gps_ns: i64,
    /// 1-sigma of the time, ns.
    pub sigma_ns: f64,
    /// Bank (roll), rad.
    pub roll_rad: f64,
    /// Elevation (pitch), rad.
    pub pitch_rad: f64,
    /// Magnetic heading, rad.
    pub heading_mag_rad: f64,
    /// Lower-case start letter: over-range error.
    pub over_range: bool,
    /// Body rates x/y/z, rad/s.
    pub rates_radps: [f64; 3],
}

impl WatsonSample {
    /// Builds the sample from an aligned line.
    pub fn new(time: &AlignedTime, line: &Line) -> Self {
        Self {
            t_gps_ns: time.t_gps_ns,
            sigma_ns: time.sigma_ns,
            roll_rad: line.bank_rad(),
            pitch_rad: line.elevation_rad(),
            heading_mag_rad: line.heading_mag_rad(),
            over_range: line.over_range,
            rates_radps: line.rate_radps(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn vn200_quaternion_convention_matches_the_manuals_example() {
        // VN-200 manual, Set Initial Heading: yaw-pitch-roll 73.2, 87.1, 10.2 deg and the
        // quaternion -0.3574, 0.5894, 0.3812, 0.6161 (x, y, z, scalar) are the same attitude.
        // Hand check: Rz(73.2) Ry(87.1) Rx(10.2) as a Hamilton quaternion (w, x, y, z) is
        // (0.61607, -0.35744, 0.58935, 0.38125): the manual's numbers, rounded to 4 digits.
        let q = vn200_quaternion(-0.3574, 0.5894, 0.3812, 0.6161).unwrap();
        let ypr = from_ypr(73.2 * DEG, 87.1 * DEG, 10.2 * DEG);
        // Four digits per component: agreement to about 1e-4 rad.
        assert!(q.angle_to(&ypr) < 2e-4, "{}", q.angle_to(&ypr));
        // Not the conjugate (the other convention): far apart.
        assert!(q.inverse().angle_to(&ypr) > 1.0);
        // Non-unit or non-finite quaternions are refused.
        assert!(vn200_quaternion(0.0, 0.0, 0.0, 0.5).is_none());
        assert!(vn200_quaternion(f32::NAN, 0.0, 0.0, 1.0).is_none());
    }

    fn time() -> AlignedTime {
        AlignedTime {
            t_gps_ns: 1_000,
            sigma_ns: 50.0,
            source: crate::time::TimeSource::NativeGps,
            status: crate::time::ClockStatus::Locked,
        }
    }

    #[test]
    fn vn200_sample_from_a_binary_output() {
        use vigil_drivers::vn200::binary::wire::{Lla, Quaternion as VnQ, Ypr};
        use vigil_drivers::vn200::binary::{AttitudeGroup, CommonGroup, InsGroup};
        // Yaw 30 deg only: quaternion (0, 0, sin 15, cos 15).
        let (s15, c15) = (15.0f64 * DEG).sin_cos();
        let out = BinaryOutput {
            common: Some(CommonGroup {
                quaternion: Some(VnQ {
                    x: 0.0,
                    y: 0.0,
                    z: s15 as f32,
                    s: c15 as f32,
                }),
                // A contradicting YPR: the quaternion wins.
                ypr: Some(Ypr {
                    yaw_deg: 99.0,
                    pitch_deg: 0.0,
                    roll_deg: 0.0,
                }),
                ins_status: Some(InsStatus(0x0006)),
                pos_lla: Some(Lla {
                    lat_deg: 47.0,
                    lon_deg: 8.0,
                    alt_m: 500.0,
                }),
                vel_ned_mps: Some([1.0, 2.0, -0.5]),
                ..Default::default()
            }),
            attitude: Some(AttitudeGroup {
                ypr_u: Some(Ypr {
                    yaw_deg: 0.5,
                    pitch_deg: 0.1,
                    roll_deg: 0.2,
                }),
                ..Default::default()
            }),
            ins: Some(InsGroup {
                pos_u_m: Some(2.5),
                vel_u_mps: Some(0.05),
                ..Default::default()
            }),
            ..Default::default()
        };
        let s = Vn200Sample::from_output(&time(), &out).unwrap();
        let (y, p, r) = super::super::angles::to_ypr(&s.attitude);
        assert!((y - 30.0 * DEG).abs() < 1e-6 && p.abs() < 1e-7 && r.abs() < 1e-7);
        let u = s.ypr_sigma_rad.unwrap();
        assert!((u[0] - 0.5 * DEG).abs() < 1e-9 && (u[2] - 0.2 * DEG).abs() < 1e-8);
        assert!((u[1] - 0.1 * DEG).abs() < 1e-8);
        assert_eq!(s.lla, Some([47.0, 8.0, 500.0]));
        assert_eq!(s.vel_ned_mps, Some([1.0, 2.0, -0.5]));
        assert_eq!(s.pos_u_m, Some(2.5));
        assert_eq!((s.t_gps_ns, s.sigma_ns), (1_000, 50.0));
        // Without a quaternion the YPR is used: yaw 30, pitch 10, roll -20 deg.
        let mut ypr_only = out.clone();
        let c = ypr_only.common.as_mut().unwrap();
        c.quaternion = None;
        c.ypr = Some(Ypr {
            yaw_deg: 30.0,
            pitch_deg: 10.0,
            roll_deg: -20.0,
        });
        let s = Vn200Sample::from_output(&time(), &ypr_only).unwrap();
        let (y, p, r) = super::super::angles::to_ypr(&s.attitude);
        assert!((y - 30.0 * DEG).abs() < 1e-6, "{y}");
        assert!(
            (p - 10.0 * DEG).abs() < 1e-6 && (r + 20.0 * DEG).abs() < 1e-6,
            "{p} {r}"
        );
        // Without InsStatus (validity unknown) or without attitude: no sample.
        let mut no_status = out.clone();
        no_status.common.as_mut().unwrap().ins_status = None;
        assert!(Vn200Sample::from_output(&time(), &no_status).is_none());
        assert!(Vn200Sample::from_output(&time(), &BinaryOutput::default()).is_none());
    }

    #[test]
    fn bahrs_sample_from_messages() {
        use vigil_drivers::bahrs::InertialHealth;
        let h = NavigationHealth::new(
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
        );
        let nav = Navigation::from_si(1, 600.0, -1.0, 10.0 * DEG, 2.0 * DEG, 350.0 * DEG, h);
        // Accuracy raw 100 LSB = 100 x 9.587526e-5 rad (the document's angle LSB) = 0.5493 deg;
        // heading 0 = invalid.
        let acc = Accuracy {
            seq: 1,
            std_north_raw: 100,
            std_east_raw: 100,
            std_heading_raw: 0,
            mcu_time_us: 0,
        };
        let safe = [Health::Safe; 3];
        let mut rate_h = safe;
        let inertial = Inertial::from_si(
            1,
            [0.0; 3],
            [0.01, 0.02, 0.03],
            InertialHealth::new(safe, safe),
        );
        let s = BahrsSample::new(&time(), &nav, Some(&acc), Some(&inertial));
        let a = s.accuracy_rad.unwrap();
        assert!((a[0].unwrap() - 100.0 * 9.587_526e-5).abs() < 1e-15);
        assert_eq!(a[2], None);
        assert!((s.roll_rad - 10.0 * DEG).abs() < 1e-4);
        assert!((s.heading_mag_rad - 350.0 * DEG).abs() < 1e-4);
        assert!(s.rates_radps.is_some());
        // A rate axis not safe: no rates (the timing term falls back to another unit).
        rate_h[1] = Health::IntegrityRisk;
        let inertial = Inertial::from_si(
            1,
            [0.0; 3],
            [0.01, 0.02, 0.03],
            InertialHealth::new(safe, rate_h),
        );
        let s = BahrsSample::new(&time(), &nav, None, Some(&inertial));
        assert!(s.rates_radps.is_none() && s.accuracy_rad.is_none());
    }
}
