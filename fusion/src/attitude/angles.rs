//! Angles on the circle and rotations on the rotation group.
//!
//! Angle differences are wrapped to (-pi, pi] before any comparison, so 359 deg against 1 deg is
//! 2 deg, not 358. Attitudes are interpolated on the rotation group (slerp of unit quaternions),
//! never component by component across the wrap. Euler angles are the 3-2-1 (yaw, pitch, roll)
//! sequence of the body relative to local NED, as the VN-200 reports them.

use nalgebra::UnitQuaternion;

/// Wraps an angle to (-pi, pi], rad.
pub fn wrap_pi(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// Wraps an angle to [0, 2 pi), rad.
pub fn wrap_2pi(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    // rem_euclid can return TAU itself for tiny negative inputs through rounding.
    if w >= std::f64::consts::TAU { 0.0 } else { w }
}

/// The signed difference `a - b` on the circle, in (-pi, pi], rad.
pub fn angle_diff(a: f64, b: f64) -> f64 {
    wrap_pi(a - b)
}

/// Attitude (body relative to NED) from 3-2-1 Euler angles: yaw, then pitch, then roll, rad.
pub fn from_ypr(yaw: f64, pitch: f64, roll: f64) -> UnitQuaternion<f64> {
    // nalgebra composes roll about x first, then pitch about y, then yaw about z in the fixed
    // frame, which is the body 3-2-1 sequence: R = Rz(yaw) Ry(pitch) Rx(roll).
    UnitQuaternion::from_euler_angles(roll, pitch, yaw)
}

/// 3-2-1 Euler angles (yaw, pitch, roll), rad, yaw in (-pi, pi].
pub fn to_ypr(q: &UnitQuaternion<f64>) -> (f64, f64, f64) {
    let (roll, pitch, yaw) = q.euler_angles();
    (yaw, pitch, roll)
}

/// The attitude at `t` between `(t0, q0)` and `(t1, q1)` (any time unit), by slerp; outside the
/// interval it extrapolates along the same rotation.
pub fn interpolate(
    t0: f64,
    q0: &UnitQuaternion<f64>,
    t1: f64,
    q1: &UnitQuaternion<f64>,
    t: f64,
) -> UnitQuaternion<f64> {
    if t1 == t0 {
        return *q0;
    }
    let u = (t - t0) / (t1 - t0);
    // The relative rotation's axis-angle scaled by u; takes the short way (q and -q are the same
    // rotation), like slerp, and also works for u outside [0, 1].
    let delta = q0.rotation_to(q1);
    let delta = delta.powf(u);
    delta * q0
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const DEG: f64 = PI / 180.0;

    #[test]
    fn wrap_and_difference_on_the_circle() {
        assert!((angle_diff(359.0 * DEG, 1.0 * DEG) + 2.0 * DEG).abs() < 1e-12);
        assert!((angle_diff(1.0 * DEG, 359.0 * DEG) - 2.0 * DEG).abs() < 1e-12);
        assert!((wrap_pi(3.0 * PI) - PI).abs() < 1e-12);
        assert!((wrap_pi(-PI) - PI).abs() < 1e-12);
        assert!((wrap_2pi(-DEG) - 359.0 * DEG).abs() < 1e-12);
        assert!(wrap_2pi(-1e-18) < std::f64::consts::TAU);
    }

    #[test]
    fn euler_321_round_trip_and_meaning() {
        let q = from_ypr(30.0 * DEG, 10.0 * DEG, -20.0 * DEG);
        let (y, p, r) = to_ypr(&q);
        assert!((y - 30.0 * DEG).abs() < 1e-12 && (p - 10.0 * DEG).abs() < 1e-12);
        assert!((r + 20.0 * DEG).abs() < 1e-12);
        // Body x (nose) in NED for yaw 90, pitch 0, roll 0: pointing east.
        let nose = from_ypr(90.0 * DEG, 0.0, 0.0) * nalgebra::Vector3::x();
        assert!((nose - nalgebra::Vector3::y()).norm() < 1e-12);
        // Pitch up 30 deg: nose has a negative down component (NED: z down).
        let nose = from_ypr(0.0, 30.0 * DEG, 0.0) * nalgebra::Vector3::x();
        assert!((nose.z + 0.5).abs() < 1e-12);
    }

    #[test]
    fn slerp_crosses_the_heading_wrap_the_short_way() {
        // Yaw 350 deg at t = 0 and 10 deg at t = 1: halfway is 0 deg, not 180.
        let q0 = from_ypr(350.0 * DEG, 0.0, 0.0);
        let q1 = from_ypr(10.0 * DEG, 0.0, 0.0);
        let (y, _, _) = to_ypr(&interpolate(0.0, &q0, 1.0, &q1, 0.5));
        assert!(y.abs() < 1e-12, "{}", y / DEG);
        let (y, _, _) = to_ypr(&interpolate(0.0, &q0, 1.0, &q1, 0.25));
        assert!((angle_diff(y, 355.0 * DEG)).abs() < 1e-12);
        // Extrapolation continues the rotation: at t = 1.5, 20 deg.
        let (y, _, _) = to_ypr(&interpolate(0.0, &q0, 1.0, &q1, 1.5));
        assert!((y - 20.0 * DEG).abs() < 1e-12);
    }

    #[test]
    fn interpolation_uses_the_fraction_of_the_interval_elapsed() {
        // Yaw 10 deg at t = 100 and 50 deg at t = 110: at t = 102.5 a quarter of the way, 20 deg;
        // at t = 115 (extrapolated) 70 deg.
        let q0 = from_ypr(10.0 * DEG, 0.0, 0.0);
        let q1 = from_ypr(50.0 * DEG, 0.0, 0.0);
        let (y, _, _) = to_ypr(&interpolate(100.0, &q0, 110.0, &q1, 102.5));
        assert!((y - 20.0 * DEG).abs() < 1e-12, "{}", y / DEG);
        let (y, _, _) = to_ypr(&interpolate(100.0, &q0, 110.0, &q1, 115.0));
        assert!((y - 70.0 * DEG).abs() < 1e-12, "{}", y / DEG);
    }

    #[test]
    fn slerp_of_combined_rotations_stays_on_the_great_arc() {
        // Roll 0 -> 40 deg at constant yaw and pitch: the midpoint is roll 20 deg exactly.
        let q0 = from_ypr(100.0 * DEG, 5.0 * DEG, 0.0);
        let q1 = from_ypr(100.0 * DEG, 5.0 * DEG, 40.0 * DEG);
        let (y, p, r) = to_ypr(&interpolate(0.0, &q0, 2.0, &q1, 1.0));
        assert!((r - 20.0 * DEG).abs() < 1e-12 && (p - 5.0 * DEG).abs() < 1e-12);
        assert!((y - 100.0 * DEG).abs() < 1e-12);
    }
}
