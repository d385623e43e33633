//! The per-sample comparison of two units on one axis, with both detectors (issue 8, "Tests,
//! persistence, isolation"):
//!
//! - statistical: `z = d / sqrt(var)` with the combined variance
//!   `var = s_a^2 + s_b^2 + m_a^2 + m_b^2 + (rate x s_t)^2 (+ s_D^2 for a true-magnetic heading
//!   pair)`, test ratio `|z| / k` with `k` from the false-alarm probability (4.42 at 1e-5); jointly
//!   `chi2 = sum z^2` over the three axes against the chi-square(3) bound (25.9);
//! - fixed comparator: `|d| / limit` with pitch 5, roll 6, heading 6 deg (12 deg while the bank
//!   exceeds 6 deg), widened by `k x |rate| x s_t` (issue 25): a sample whose time is less sure
//!   (the BAHRS on the host-clock fallback instead of its PPS) moves by up to that much at the
//!   body rates, so both detectors widen by the same stated timing term
//!   ([`AxisComparison::timing_deg`]) and the comparison goes on instead of stopping.
//!
//! Also: tilt sigmas of the BAHRS from its north/east standard deviations, Euler-angle rates from
//! body rates (for the timing term), and mounting correction.

use nalgebra::UnitQuaternion;
use serde::Serialize;

use super::angles::{angle_diff, from_ypr};
use super::params::{CheckParams, Mounting};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// An attitude axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// Roll (bank).
    Roll,
    /// Pitch (elevation).
    Pitch,
    /// Heading (yaw), true.
    Heading,
}

impl Axis {
    /// The three axes in record order.
    pub const ALL: [Axis; 3] = [Axis::Roll, Axis::Pitch, Axis::Heading];
}

/// Roll and pitch variances, rad^2, from tilt standard deviations about north and east (rad) at
/// heading `psi` (rad). The roll axis (body x) points along the heading, `(cos psi, sin psi)` in
/// north/east, so a tilt about it mixes the two as `cos^2 s_N^2 + sin^2 s_E^2`; pitch (body y,
/// `(-sin psi, cos psi)`) as `sin^2 s_N^2 + cos^2 s_E^2` (errors about north and east taken as
/// independent).
pub fn tilt_variances(sigma_north: f64, sigma_east: f64, psi: f64) -> (f64, f64) {
    let (s, c) = psi.sin_cos();
    let (n2, e2) = (sigma_north * sigma_north, sigma_east * sigma_east);
    (c * c * n2 + s * s * e2, s * s * n2 + c * c * e2)
}

/// 3-2-1 Euler-angle rates (roll, pitch, yaw), rad/s, from body rates `p, q, r` (rad/s) at roll
/// `phi` and pitch `theta` (rad). Near +-90 deg pitch the yaw rate is unbounded; cos(theta) is
/// floored at 0.05 so the timing term stays finite (it is then large, which is right).
pub fn euler_rates(body: [f64; 3], phi: f64, theta: f64) -> [f64; 3] {
    let [p, q, r] = body;
    let (sp, cp) = phi.sin_cos();
    let ct = theta.cos().abs().max(0.05).copysign(theta.cos());
    let tt = theta.sin() / ct;
    [
        p + (q * sp + r * cp) * tt,
        q * cp - r * sp,
        (q * sp + r * cp) / ct,
    ]
}

/// The aircraft attitude from a unit's attitude and its mounting: the unit's body frame is the
/// aircraft's rotated by the mounting angles, `q_unit = q_aircraft * q_mount`.
pub fn unmount(q_unit: &UnitQuaternion<f64>, m: &Mounting) -> UnitQuaternion<f64> {
    if m.yaw_deg == 0.0 && m.pitch_deg == 0.0 && m.roll_deg == 0.0 {
        return *q_unit;
    }
    let q_mount = from_ypr(m.yaw_deg * DEG, m.pitch_deg * DEG, m.roll_deg * DEG);
    q_unit * q_mount.inverse()
}

/// One pairwise comparison on one axis (angles in the record in degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AxisComparison {
    /// Difference first unit minus second, deg (heading wrapped to +-180).
    pub diff_deg: f64,
    /// Combined variance, deg^2.
    pub var_deg2: f64,
    /// Normalised difference, sigmas.
    pub z: f64,
    /// Statistical test ratio `|z| / k` (1 at the threshold).
    pub stat_ratio: f64,
    /// Fixed comparator limit in force, deg.
    pub limit_deg: f64,
    /// Fixed comparator ratio `|d| / limit`.
    pub fixed_ratio: f64,
    // --- issue 25 ---
    /// The timing term, 1-sigma, deg: Euler rate of the axis x the relative time sigma of the two
    /// samples. In the variance as its square; added `k` times to the fixed limit.
    pub timing_deg: f64,
}

/// Variance contributions of one pair on one axis, rad^2.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct VarianceTerms {
    /// First unit's own variance.
    pub a: f64,
    /// Second unit's own variance.
    pub b: f64,
    /// Sum of both mounting variances.
    pub mounting: f64,
    /// Euler-angle rate of the axis, rad/s.
    pub rate_radps: f64,
    /// Relative timing sigma of the two samples, s.
    pub timing_sigma_s: f64,
    /// Declination variance (only a pair of one magnetic and one true heading).
    pub declination: f64,
}

impl VarianceTerms {
    /// The combined variance, rad^2.
    pub fn total(&self) -> f64 {
        let timing = self.rate_radps * self.timing_sigma_s;
        self.a + self.b + self.mounting + timing * timing + self.declination
    }
}

/// The fixed comparator limit for `axis`, rad, given the bank angle (rad).
pub fn fixed_limit(p: &CheckParams, axis: Axis, bank_rad: f64) -> f64 {
    DEG * match axis {
        Axis::Roll => p.limit_roll_deg,
        Axis::Pitch => p.limit_pitch_deg,
        Axis::Heading if bank_rad.abs() > p.bank_for_wide_heading_deg * DEG => {
            p.limit_heading_banked_deg
        }
        Axis::Heading => p.limit_heading_deg,
    }
}

/// Compares values `a` and `b` (rad) of `axis` with both detectors; `k` is the per-axis
/// threshold in sigmas, `bank_rad` selects the heading limit.
pub fn compare_axis(
    p: &CheckParams,
    axis: Axis,
    a: f64,
    b: f64,
    var: &VarianceTerms,
    k: f64,
    bank_rad: f64,
) -> AxisComparison {
    let d = match axis {
        Axis::Heading => angle_diff(a, b),
        _ => a - b,
    };
    let v = var.total().max(1e-12);
    let z = d / v.sqrt();
    let timing = (var.rate_radps * var.timing_sigma_s).abs();
    let limit = fixed_limit(p, axis, bank_rad) + k * timing;
    AxisComparison {
        diff_deg: d / DEG,
        var_deg2: v / (DEG * DEG),
        z,
        stat_ratio: z.abs() / k,
        limit_deg: limit / DEG,
        fixed_ratio: d.abs() / limit,
        timing_deg: timing / DEG,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tilt_variances_by_hand() {
        // Heading north: roll about north, pitch about east.
        let (r, p) = tilt_variances(0.01, 0.02, 0.0);
        assert!((r - 1e-4).abs() < 1e-15 && (p - 4e-4).abs() < 1e-15);
        // Heading east (90 deg): swapped.
        let (r, p) = tilt_variances(0.01, 0.02, 90.0 * DEG);
        assert!((r - 4e-4).abs() < 1e-15 && (p - 1e-4).abs() < 1e-15);
        // 45 deg: both are the mean, (1e-4 + 4e-4) / 2.
        let (r, p) = tilt_variances(0.01, 0.02, 45.0 * DEG);
        assert!((r - 2.5e-4).abs() < 1e-15 && (p - 2.5e-4).abs() < 1e-15);
    }

    #[test]
    fn euler_rates_by_hand() {
        // Level: Euler rates are the body rates.
        let e = euler_rates([0.1, 0.2, 0.3], 0.0, 0.0);
        assert!((e[0] - 0.1).abs() < 1e-15 && (e[1] - 0.2).abs() < 1e-15);
        assert!((e[2] - 0.3).abs() < 1e-15);
        // Banked 30 deg in a level coordinated turn: yaw rate psi_dot gives q = psi_dot sin 30,
        // r = psi_dot cos 30; the Euler yaw rate is back psi_dot and the pitch rate 0.
        let w = 0.05;
        let phi = 30.0 * DEG;
        let e = euler_rates([0.0, w * phi.sin(), w * phi.cos()], phi, 0.0);
        assert!((e[2] - w).abs() < 1e-15 && e[1].abs() < 1e-15 && e[0].abs() < 1e-15);
    }

    #[test]
    fn mounting_offsets_are_removed() {
        // A unit mounted 2 deg right in yaw reads heading + 2 deg; unmounted it reads the
        // aircraft's heading.
        let m = Mounting {
            yaw_deg: 2.0,
            ..Default::default()
        };
        let aircraft = from_ypr(100.0 * DEG, 3.0 * DEG, -10.0 * DEG);
        let unit = aircraft * from_ypr(2.0 * DEG, 0.0, 0.0);
        let back = unmount(&unit, &m);
        assert!(back.angle_to(&aircraft) < 1e-12);
        // Level aircraft: the unit's yaw is exactly 102 deg.
        let level = from_ypr(100.0 * DEG, 0.0, 0.0) * from_ypr(2.0 * DEG, 0.0, 0.0);
        let (y, _, _) = super::super::angles::to_ypr(&level);
        assert!((y - 102.0 * DEG).abs() < 1e-12);
    }

    #[test]
    fn both_detectors_by_hand() {
        let p = CheckParams::default();
        // Heading 359 vs 3 deg: d = -4 deg (wrapped). sigmas 1 and 2 deg, mounting 0.1 deg each,
        // rate 10 deg/s x 5 ms = 0.05 deg, declination 0.3 deg:
        // var = 1 + 4 + 0.02 + 0.0025 + 0.09 = 5.1125 deg^2, z = -4 / 2.26108 = -1.76907.
        let var = VarianceTerms {
            a: (1.0 * DEG).powi(2),
            b: (2.0 * DEG).powi(2),
            mounting: 2.0 * (0.1 * DEG).powi(2),
            rate_radps: 10.0 * DEG,
            timing_sigma_s: 0.005,
            declination: (0.3 * DEG).powi(2),
        };
        let c = compare_axis(&p, Axis::Heading, 359.0 * DEG, 3.0 * DEG, &var, 4.42, 0.0);
        assert!((c.diff_deg + 4.0).abs() < 1e-9);
        assert!((c.var_deg2 - 5.1125).abs() < 1e-9);
        assert!((c.z + 4.0 / 5.1125f64.sqrt()).abs() < 1e-9);
        assert!((c.stat_ratio - 4.0 / 5.1125f64.sqrt() / 4.42).abs() < 1e-9);
        // The fixed limit widens by k x timing = 4.42 x 0.05 deg = 0.221 deg.
        assert!((c.timing_deg - 0.05).abs() < 1e-12);
        assert!((c.limit_deg - 6.221).abs() < 1e-12);
        assert!((c.fixed_ratio - 4.0 / 6.221).abs() < 1e-9);
        // Without the timing term, the configured limits. Banked 7 deg: heading limit 12 deg;
        // 6.0 deg bank exactly: still 6.
        let var = VarianceTerms {
            timing_sigma_s: 0.0,
            ..var
        };
        let c = compare_axis(&p, Axis::Heading, 0.0, 0.0, &var, 4.42, 7.0 * DEG);
        assert_eq!(c.limit_deg, 12.0);
        let c = compare_axis(&p, Axis::Heading, 0.0, 0.0, &var, 4.42, -7.0 * DEG);
        assert_eq!(c.limit_deg, 12.0);
        let c = compare_axis(&p, Axis::Heading, 0.0, 0.0, &var, 4.42, 6.0 * DEG);
        assert!((c.limit_deg - 6.0).abs() < 1e-12);
        let c = compare_axis(&p, Axis::Pitch, 0.0, 0.0, &var, 4.42, 30.0 * DEG);
        assert!((c.limit_deg - 5.0).abs() < 1e-12);
        // Roll 6.5 vs 0: fixed ratio 6.5/6.
        let c = compare_axis(&p, Axis::Roll, 6.5 * DEG, 0.0, &var, 4.42, 0.0);
        assert!((c.fixed_ratio - 6.5 / 6.0).abs() < 1e-12);
    }

    /// Issue 25, point 3: a BAHRS sample on the host-clock fallback, stamped 20 ms late with a
    /// stated sigma of 10 ms, during a 30 deg/s roll. Its roll lags the VN-200's by
    /// 30 x 0.02 = 0.6 deg. Unit sigmas 0.1 deg each, no mounting term.
    /// - With the PPS sigma (0.1 ms, timing term 0.003 deg): var = 0.02 + 0.000009 deg^2,
    ///   z = 0.6 / 0.14145 = 4.2418, ratio 4.2418 / 4.42 = 0.9597 (almost failing);
    /// - with the fallback's 10 ms (timing term 0.3 deg): var = 0.02 + 0.09 = 0.11 deg^2,
    ///   z = 0.6 / 0.33166 = 1.8091, ratio 0.4093: compared, with the larger tolerance stated;
    ///   the fixed limit 6 + 4.42 x 0.3 = 7.326 deg.
    #[test]
    fn a_large_time_sigma_widens_both_detectors_by_rate_times_sigma() {
        let p = CheckParams::default();
        let terms = |sigma_s: f64| VarianceTerms {
            a: (0.1 * DEG).powi(2),
            b: (0.1 * DEG).powi(2),
            rate_radps: 30.0 * DEG,
            timing_sigma_s: sigma_s,
            ..Default::default()
        };
        let pps = compare_axis(&p, Axis::Roll, 0.0, 0.6 * DEG, &terms(1e-4), 4.42, 0.0);
        assert!((pps.stat_ratio - 0.6 / 0.020009f64.sqrt() / 4.42).abs() < 1e-9);
        assert!((pps.stat_ratio - 0.9597).abs() < 1e-4, "{}", pps.stat_ratio);
        let host = compare_axis(&p, Axis::Roll, 0.0, 0.6 * DEG, &terms(0.01), 4.42, 0.0);
        assert!((host.timing_deg - 0.3).abs() < 1e-12);
        assert!((host.var_deg2 - 0.11).abs() < 1e-12);
        assert!(
            (host.stat_ratio - 0.4093).abs() < 1e-4,
            "{}",
            host.stat_ratio
        );
        assert!((host.limit_deg - 7.326).abs() < 1e-9);
        // A real 3 deg disagreement is still caught with the wider tolerance: z = 3 / 0.33166.
        let fault = compare_axis(&p, Axis::Roll, 0.0, 3.0 * DEG, &terms(0.01), 4.42, 0.0);
        assert!(fault.stat_ratio > 2.0, "{}", fault.stat_ratio);
    }

    #[test]
    fn euler_rates_banked_and_pitched_by_hand() {
        // Roll 30 deg, pitch 45 deg, body rates p, q, r = 0.1, 0.2, 0.3 rad/s. 3-2-1 kinematics:
        // q sin(phi) + r cos(phi) = 0.1 + 0.3 x 0.866025 = 0.359808;
        // roll rate  = p + 0.359808 x tan(45 deg) = 0.459808;
        // pitch rate = q cos(phi) - r sin(phi) = 0.173205 - 0.15 = 0.023205;
        // yaw rate   = 0.359808 / cos(45 deg) = 0.359808 x 1.414214 = 0.508845.
        let e = euler_rates([0.1, 0.2, 0.3], 30.0 * DEG, 45.0 * DEG);
        assert!((e[0] - 0.459808).abs() < 1e-6, "{e:?}");
        assert!((e[1] - 0.023205).abs() < 1e-6, "{e:?}");
        assert!((e[2] - 0.508845).abs() < 1e-6, "{e:?}");
        // The same from the rotation itself: the attitude carried 1 ms along with those body
        // rates (q(t + dt) = q(t) exp(w dt), body frame), read back as Euler angles.
        let (phi, theta, psi) = (30.0 * DEG, 45.0 * DEG, 20.0 * DEG);
        let dt = 1e-3;
        let q0 = from_ypr(psi, theta, phi);
        let step = UnitQuaternion::from_scaled_axis(nalgebra::Vector3::new(0.1, 0.2, 0.3) * dt);
        let (y1, p1, r1) = super::super::angles::to_ypr(&(q0 * step));
        let fd = [(r1 - phi) / dt, (p1 - theta) / dt, (y1 - psi) / dt];
        for (got, want) in e.iter().zip(fd) {
            assert!((got - want).abs() < 1e-3, "{e:?} against {fd:?}");
        }
    }

    #[test]
    fn a_pitch_or_roll_mounting_alone_is_removed_too() {
        // A unit mounted pitched up 3 deg on a level aircraft reads pitch 3 deg; one mounted
        // rolled 2 deg reads roll 2 deg. Unmounted, both read the aircraft's level attitude.
        let aircraft = from_ypr(100.0 * DEG, 0.0, 0.0);
        for (pitch_deg, roll_deg) in [(3.0, 0.0), (0.0, 2.0)] {
            let m = Mounting {
                pitch_deg,
                roll_deg,
                ..Default::default()
            };
            let unit = aircraft * from_ypr(0.0, pitch_deg * DEG, roll_deg * DEG);
            let (_, p, r) = super::super::angles::to_ypr(&unit);
            assert!((p - pitch_deg * DEG).abs() < 1e-12 && (r - roll_deg * DEG).abs() < 1e-12);
            let back = unmount(&unit, &m);
            assert!(back.angle_to(&aircraft) < 1e-12, "{m:?}");
        }
    }
}
