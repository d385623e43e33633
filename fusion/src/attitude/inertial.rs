//! The inertial channel (issue 25 point 5): the BAHRS inertial data (protocol 2.0, 3.1, message
//! 0x01: specific force and angular rate per body axis, each with its 2-bit health, section 2.4)
//! against the VN-200's Accel and AngularRate (ICD binary group 1 / IMU group), per axis, in the
//! aircraft body frame.
//!
//! Decisions:
//! - Time: each 0x01 is compared at its own aligned time (from its 0x05), against the VN-200
//!   linearly interpolated between the two samples that bracket it; a 0x01 is compared once
//!   (the checker runs at the BAHRS navigation rate, 50 Hz, and takes the newest 0x01).
//! - Frame: both units' vectors are rotated into the aircraft body frame by their configured
//!   mounting (`[attitude] mounting_*`, the same rotation the attitude comparison removes). The
//!   simulator mounts them aligned (zero rotation). With a rotation, an aircraft axis mixes the
//!   unit's three signals, so one closed gate of a kind (specific force, angular rate) closes
//!   that kind on all three aircraft axes.
//! - Lever arm: none is configured; the units are taken as co-located. A lever arm `r` adds
//!   `w x (w x r) + dw/dt x r` to the specific force difference (0.02 m/s^2 for 0.3 m at
//!   15 deg/s): below the noise for a small UAS, and the simulator has none.
//! - Sign: both are specific force (level at rest: z = -9.81 m/s^2): the BAHRS document says
//!   "specific force"; the VN-200 Accel is the compensated accelerometer output, which is
//!   specific force (ICD: Accel, "compensated acceleration", level reads -g on z).
//! - Limits: statistical only (`|d| / sigma` against the per-axis `k` of the false-alarm
//!   probability, then the persistence and CUSUM of [`super::persistence`]); `sigma` combines
//!   each unit's white noise ([`super::params::InertialParams`], where each number comes from)
//!   with a timing term (the VN-200's rate of change times the two samples' time sigmas). There
//!   is no certified fixed limit for these signals.
//! - Exclusion: a BAHRS signal whose health is not "safe" (00 unavailable, 10 integrity risk,
//!   11 undefined) is not compared; its axis reports the reason (and the payload carries every
//!   signal's health). A VN-200 with IMU error bits or a failed gyro/accelerometer closes all.

use nalgebra::{UnitQuaternion, Vector3};
use serde::Serialize;
use vigil_drivers::bahrs::Health;

use super::angles::from_ypr;
use super::gates::{Gate, GateReason};
use super::isolation::PairVerdict;
use super::params::{CheckParams, Mounting};
use super::persistence::Persistence;
use super::samples::BahrsInertial;

const DEG: f64 = std::f64::consts::PI / 180.0;

/// The VN-200's inertial values at the BAHRS 0x01 time, or why there are none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vn200Inertial {
    /// Specific force x/y/z (VN-200 body), m/s^2.
    pub specific_force_mps2: Option<[f64; 3]>,
    /// Angular rate x/y/z (VN-200 body), rad/s.
    pub angular_rate_radps: Option<[f64; 3]>,
    /// Rate of change of the six values (specific force then angular rate) between the
    /// bracketing samples, per s; zeros without a later sample.
    pub slope_per_s: [f64; 6],
    /// 1-sigma of the VN-200 sample time, ns.
    pub sigma_ns: f64,
    /// Gate of the VN-200 (None: usable).
    pub gate: Gate,
}

/// One comparison of a signal, in the signal's unit (m/s^2 or rad/s, aircraft body frame).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SignalComparison {
    /// BAHRS value.
    pub bahrs: Option<f64>,
    /// VN-200 value at the same time.
    pub vn200: Option<f64>,
    /// Difference BAHRS minus VN-200.
    pub diff: Option<f64>,
    /// Combined 1-sigma of the difference.
    pub sigma: Option<f64>,
    /// Statistical test ratio (1 at the threshold).
    pub stat_ratio: Option<f64>,
    /// Persistent verdict.
    pub verdict: PairVerdict,
    /// Why not compared.
    pub gate: Gate,
}

impl SignalComparison {
    /// Not compared, for `gate`.
    pub fn not_compared(gate: Gate) -> Self {
        Self {
            bahrs: None,
            vn200: None,
            diff: None,
            sigma: None,
            stat_ratio: None,
            verdict: PairVerdict::NotCompared,
            gate,
        }
    }
}

/// The six inertial comparisons of one check and the BAHRS health of the 0x01 used.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct InertialRecord {
    /// Specific force x/y/z then angular rate x/y/z.
    pub axes: [SignalComparison; 6],
    /// GPS time of the 0x01 compared, ns (`None`: none yet).
    pub t_gps_ns: Option<i64>,
    /// BAHRS health of each signal of that 0x01 (`None`: no 0x01 yet).
    pub bahrs_health: Option<[Health; 6]>,
}

impl InertialRecord {
    /// Nothing compared, for `gate`.
    pub fn none(gate: Gate) -> Self {
        Self {
            axes: [SignalComparison::not_compared(gate); 6],
            t_gps_ns: None,
            bahrs_health: None,
        }
    }
}

/// State of the inertial channel: one persistence per signal and the last 0x01 compared.
#[derive(Debug, Clone, Default)]
pub struct InertialChannel {
    persistence: [Persistence; 6],
    last_t_ns: Option<i64>,
    last: Option<InertialRecord>,
}

fn health_gate(h: Health) -> Gate {
    match h {
        Health::Safe => None,
        Health::Unavailable => Some(GateReason::HealthUnavailable),
        Health::IntegrityRisk => Some(GateReason::HealthIntegrityRisk),
        Health::Undefined => Some(GateReason::HealthUndefined),
    }
}

fn mount_rotation(m: &Mounting) -> Option<UnitQuaternion<f64>> {
    (m.yaw_deg != 0.0 || m.pitch_deg != 0.0 || m.roll_deg != 0.0)
        .then(|| from_ypr(m.yaw_deg * DEG, m.pitch_deg * DEG, m.roll_deg * DEG))
}

/// `v` (unit body frame) in the aircraft body frame: the unit's attitude is the aircraft's
/// times the mounting rotation (see [`super::compare::unmount`]), so `v_aircraft = q_mount v`.
fn to_aircraft(v: [f64; 3], q: Option<&UnitQuaternion<f64>>) -> [f64; 3] {
    match q {
        None => v,
        Some(q) => {
            let r = q * Vector3::new(v[0], v[1], v[2]);
            [r.x, r.y, r.z]
        }
    }
}

/// Per-kind gates after the mounting rotation: per axis without a rotation, else the first
/// closed gate of the kind on every axis.
fn rotated_gates(gates: [Gate; 3], rotated: bool) -> [Gate; 3] {
    if rotated {
        let g = gates.iter().flatten().next().copied();
        [g; 3]
    } else {
        gates
    }
}

impl InertialChannel {
    /// Compares the newest 0x01 `b` (if any, and not compared before) with the VN-200 at its
    /// time; `horizon_ns` the freshness limit at the check time `t_check_ns`, `k` the per-axis
    /// threshold. A 0x01 already compared gives the previous record again (the checker runs
    /// faster than a slow 0x01 stream, never slower at the defaults).
    pub fn update(
        &mut self,
        b: Option<&BahrsInertial>,
        vn: &Vn200Inertial,
        t_check_ns: i64,
        horizon_ns: i64,
        k: f64,
        p: &CheckParams,
    ) -> InertialRecord {
        let Some(b) = b else {
            return InertialRecord::none(Some(GateReason::NoData));
        };
        if t_check_ns.saturating_sub(b.t_gps_ns) > horizon_ns {
            let mut r = InertialRecord::none(Some(GateReason::Stale));
            r.bahrs_health = Some(b.health);
            r.t_gps_ns = Some(b.t_gps_ns);
            return r;
        }
        if self.last_t_ns == Some(b.t_gps_ns)
            && let Some(r) = self.last
        {
            return r;
        }
        let dt_s = match self.last_t_ns {
            Some(t0) if b.t_gps_ns > t0 => (b.t_gps_ns.saturating_sub(t0) as f64 * 1e-9).min(1.0),
            _ => p.bahrs_period_s,
        };
        self.last_t_ns = Some(b.t_gps_ns);
        let ip = &p.inertial;
        let qb = mount_rotation(&p.mounting_bahrs);
        let qv = mount_rotation(&p.mounting_vn200);
        let rotated = qb.is_some() || qv.is_some();
        let bg = b.health.map(health_gate);
        let gates_f = rotated_gates([bg[0], bg[1], bg[2]], rotated);
        let gates_w = rotated_gates([bg[3], bg[4], bg[5]], rotated);
        let bf = to_aircraft(b.specific_force_mps2, qb.as_ref());
        let bw = to_aircraft(b.angular_rate_radps, qb.as_ref());
        let vf = vn.specific_force_mps2.map(|v| to_aircraft(v, qv.as_ref()));
        let vw = vn.angular_rate_radps.map(|v| to_aircraft(v, qv.as_ref()));
        // Timing: the VN-200's slope times the two time sigmas (the slope's own frame is close
        // enough to the aircraft's for a sigma term).
        let t_sigma_s = (b.sigma_ns.powi(2) + vn.sigma_ns.powi(2)).sqrt() * 1e-9;
        let mut axes = [SignalComparison::not_compared(None); 6];
        for (i, slot) in axes.iter_mut().enumerate() {
            let (bval, vval, gate, s_b, s_v) = if i < 3 {
                (
                    bf[i],
                    vf.map(|v| v[i]),
                    gates_f[i],
                    ip.bahrs_specific_force_sigma_mps2,
                    ip.vn200_specific_force_sigma_mps2,
                )
            } else {
                (
                    bw[i - 3],
                    vw.map(|v| v[i - 3]),
                    gates_w[i - 3],
                    ip.bahrs_angular_rate_sigma_radps,
                    ip.vn200_angular_rate_sigma_radps,
                )
            };
            let gate = gate
                .or(vn.gate)
                .or(vval.is_none().then_some(GateReason::NoData))
                .or((!bval.is_finite()).then_some(GateReason::NotFinite));
            *slot = match (gate, vval) {
                (None, Some(v)) => {
                    let s_t = vn.slope_per_s[i] * t_sigma_s;
                    let sigma = (s_b * s_b + s_v * s_v + s_t * s_t).sqrt();
                    let d = bval - v;
                    let ratio = (d / sigma).abs() / k;
                    let fault = self.persistence[i].update(ratio, d / sigma, dt_s, &p.persistence);
                    SignalComparison {
                        bahrs: Some(bval),
                        vn200: Some(v),
                        diff: Some(d),
                        sigma: Some(sigma),
                        stat_ratio: Some(ratio),
                        verdict: if fault {
                            PairVerdict::Fail
                        } else {
                            PairVerdict::Pass
                        },
                        gate: None,
                    }
                }
                _ => {
                    // An excluded signal starts again from a clean state when it returns.
                    self.persistence[i] = Persistence::default();
                    let mut c = SignalComparison::not_compared(gate);
                    c.bahrs = bval.is_finite().then_some(bval);
                    c.vn200 = vval;
                    c
                }
            };
        }
        let r = InertialRecord {
            axes,
            t_gps_ns: Some(b.t_gps_ns),
            bahrs_health: Some(b.health),
        };
        self.last = Some(r);
        r
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const G: f64 = 9.806_65;

    fn bahrs(t_s: f64, w: [f64; 3], health: [Health; 6]) -> BahrsInertial {
        BahrsInertial {
            t_gps_ns: (t_s * 1e9) as i64,
            sigma_ns: 1000.0,
            specific_force_mps2: [0.0, 0.0, -G],
            angular_rate_radps: w,
            health,
        }
    }

    fn vn(w: [f64; 3]) -> Vn200Inertial {
        Vn200Inertial {
            specific_force_mps2: Some([0.0, 0.0, -G]),
            angular_rate_radps: Some(w),
            slope_per_s: [0.0; 6],
            sigma_ns: 1000.0,
            gate: None,
        }
    }

    const SAFE: [Health; 6] = [Health::Safe; 6];

    #[test]
    fn a_constant_rate_error_of_ten_sigma_fails_on_its_axis_only() {
        let p = CheckParams::default();
        let k = p.axis_threshold();
        let mut ch = InertialChannel::default();
        let ip = p.inertial;
        // Hand computation: sigma = sqrt(0.001^2 + 0.0006^2) rad/s = 1.166e-3 rad/s.
        let sigma = (ip.bahrs_angular_rate_sigma_radps.powi(2)
            + ip.vn200_angular_rate_sigma_radps.powi(2))
        .sqrt();
        assert!((sigma - 1.166e-3).abs() < 1e-6);
        let w = [0.01, -0.02, 0.05];
        let mut first_fail = None;
        for i in 0..200 {
            let t = i as f64 * 0.02;
            // Pitch-rate (y) error of 10 sigma from 1 s.
            let err = if t >= 1.0 { 10.0 * sigma } else { 0.0 };
            let b = bahrs(t, [w[0], w[1] + err, w[2]], SAFE);
            let r = ch.update(Some(&b), &vn(w), b.t_gps_ns, 60_000_000, k, &p);
            for (a, c) in r.axes.iter().enumerate() {
                if a != 4 {
                    assert_eq!(c.verdict, PairVerdict::Pass, "axis {a} at {t}");
                }
            }
            if r.axes[4].verdict == PairVerdict::Fail && first_fail.is_none() {
                first_fail = Some(t);
            }
        }
        // 10 sigma is 2.26 x the threshold (k = 4.42): the low-passed ratio crosses 1 within
        // about 0.4 s, then 1 s of persistence (the CUSUM, +8 a sample, may be faster: 0.16 s).
        let t = first_fail.expect("fails");
        assert!(t > 1.0 && t < 2.5, "{t}");
    }

    #[test]
    fn signals_the_bahrs_does_not_call_safe_are_excluded_with_their_reason() {
        let p = CheckParams::default();
        let mut ch = InertialChannel::default();
        let mut h = SAFE;
        h[0] = Health::IntegrityRisk;
        h[5] = Health::Unavailable;
        // A wild z rate: not compared, so it cannot fail.
        let b = bahrs(0.0, [0.0, 0.0, 5.0], h);
        let r = ch.update(Some(&b), &vn([0.0; 3]), 0, 60_000_000, 4.42, &p);
        assert_eq!(r.axes[0].gate, Some(GateReason::HealthIntegrityRisk));
        assert_eq!(r.axes[5].gate, Some(GateReason::HealthUnavailable));
        assert_eq!(r.axes[5].verdict, PairVerdict::NotCompared);
        assert_eq!(r.axes[1].verdict, PairVerdict::Pass);
        assert_eq!(r.bahrs_health, Some(h));
        // Stale 0x01 (older than the horizon at the check time): nothing compared.
        let r = ch.update(Some(&b), &vn([0.0; 3]), 100_000_000, 60_000_000, 4.42, &p);
        assert!(r.axes.iter().all(|c| c.gate == Some(GateReason::Stale)));
    }

    #[test]
    fn mounting_rotations_are_removed_before_comparing() {
        // BAHRS yawed 90 deg on its mount: its x axis is the aircraft's y. A roll rate of the
        // aircraft (x) reads on the BAHRS as -y (v_unit = q_mount^-1 v_aircraft).
        let mut p = CheckParams::default();
        p.mounting_bahrs.yaw_deg = 90.0;
        let mut ch = InertialChannel::default();
        let mut b = bahrs(0.0, [0.0, -0.3, 0.0], SAFE);
        b.specific_force_mps2 = [0.0, 0.0, -G];
        let r = ch.update(Some(&b), &vn([0.3, 0.0, 0.0]), 0, 60_000_000, 4.42, &p);
        assert!(r.axes[3].diff.unwrap().abs() < 1e-9, "{:?}", r.axes[3]);
        assert!(r.axes[4].diff.unwrap().abs() < 1e-9);
    }
}
