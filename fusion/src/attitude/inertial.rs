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
use super::samples::{BahrsInertial, Vn200Sample};
use vigil_drivers::vn200::status::SensorState;

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
    /// Half the change of each value between the two bracketing samples (zeros without a later
    /// sample): the 1-sigma of the interpolation, which cannot know where between the samples
    /// the signal changed.
    pub step: [f64; 6],
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

/// The VN-200's Accel and AngularRate at `t`, linearly interpolated between the samples
/// that bracket it, `prev` and `next` (held, with the freshness limit `horizon` ns, without a
/// later one).
pub fn vn200_at(
    prev: Option<&Vn200Sample>,
    next: Option<&Vn200Sample>,
    t: i64,
    horizon: i64,
) -> Vn200Inertial {
    let missing = |g| Vn200Inertial {
        specific_force_mps2: None,
        angular_rate_radps: None,
        slope_per_s: [0.0; 6],
        step: [0.0; 6],
        sigma_ns: 0.0,
        gate: Some(g),
    };
    let Some(s0) = prev else {
        return missing(GateReason::NoData);
    };
    let age_ns = t.saturating_sub(s0.t_gps_ns);
    let mut gate = if s0.ins_status.imu_error() {
        Some(GateReason::InsErrorBits)
    } else if s0
        .imu_status
        .is_some_and(|i| i.gyro() == SensorState::Failed || i.accel() == SensorState::Failed)
    {
        Some(GateReason::ImuFailed)
    } else {
        None
    };
    if next.is_none() && age_ns > horizon {
        gate = gate.or(Some(GateReason::Stale));
    }
    let join = |a: Option<[f64; 3]>, b: Option<[f64; 3]>| match (a, b) {
        (Some(a), Some(b)) => Some([a[0], a[1], a[2], b[0], b[1], b[2]]),
        _ => None,
    };
    let v0 = join(s0.accel_mps2, s0.rates_radps);
    let (values, slope, step) = match (v0, next) {
        (Some(v0), Some(s1)) => match join(s1.accel_mps2, s1.rates_radps) {
            Some(v1) => {
                let span_s = s1.t_gps_ns.saturating_sub(s0.t_gps_ns) as f64 * 1e-9;
                let u = if span_s > 0.0 {
                    age_ns as f64 * 1e-9 / span_s
                } else {
                    0.0
                };
                let v: [f64; 6] = std::array::from_fn(|i| v0[i] + (v1[i] - v0[i]) * u);
                let d: [f64; 6] = std::array::from_fn(|i| {
                    if span_s > 0.0 {
                        (v1[i] - v0[i]) / span_s
                    } else {
                        0.0
                    }
                });
                let step: [f64; 6] = std::array::from_fn(|i| (v1[i] - v0[i]).abs() / 2.0);
                (Some(v), d, step)
            }
            None => (Some(v0), [0.0; 6], [0.0; 6]),
        },
        (v0, _) => (v0, [0.0; 6], [0.0; 6]),
    };
    Vn200Inertial {
        specific_force_mps2: values.map(|v| [v[0], v[1], v[2]]),
        angular_rate_radps: values.map(|v| [v[3], v[4], v[5]]),
        slope_per_s: slope,
        step,
        sigma_ns: s0.sigma_ns,
        gate,
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
                    // The interpolation term: the simulator's trajectories change the bank
                    // (and so the specific force) in a step at segment joins; without it, the
                    // nominal 10-minute flight raised two specific-force y alerts, each from
                    // one sample interpolated across a step (78 sigma, enough for the CUSUM
                    // alone). In smooth flight it is half the VN-200's sample-to-sample change.
                    let s_i = vn.step[i];
                    let sigma = (s_b * s_b + s_v * s_v + s_t * s_t + s_i * s_i).sqrt();
                    let j = self.persistence[i].judge((bval, v), sigma, k, dt_s, &p.persistence);
                    SignalComparison {
                        bahrs: Some(bval),
                        vn200: Some(v),
                        diff: Some(j.diff),
                        sigma: Some(sigma),
                        stat_ratio: Some(j.ratio),
                        verdict: j.verdict,
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
            step: [0.0; 6],
            sigma_ns: 1000.0,
            gate: None,
        }
    }

    const SAFE: [Health; 6] = [Health::Safe; 6];

    /// A VN-200 sample at `t_ms` with a z rate `wz` (rad/s) and x specific force `fx` (m/s^2),
    /// level (z force -g).
    fn vn_sample(t_ms: i64, wz: f64, fx: f64) -> Vn200Sample {
        Vn200Sample {
            t_gps_ns: t_ms * 1_000_000,
            sigma_ns: 500.0,
            attitude: nalgebra::UnitQuaternion::identity(),
            ypr_sigma_rad: None,
            ins_status: vigil_drivers::vn200::status::InsStatus(0x0006),
            imu_status: None,
            rates_radps: Some([0.0, 0.0, wz]),
            accel_mps2: Some([fx, 0.0, -G]),
            lla: None,
            vel_ned_mps: None,
            pos_u_m: None,
            vel_u_mps: None,
        }
    }

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
    fn the_vn200_is_interpolated_to_the_bahrs_time_with_its_slope() {
        let mk = |t_ms, wz| vn_sample(t_ms, wz, 0.0);
        let (a, b) = (mk(0, 0.0), mk(10, 0.1));
        // Hand computation: 2.5 ms into a 10 ms span, z rate 0.1 x 0.25 = 0.025 rad/s, slope
        // 0.1 / 0.01 = 10 rad/s^2, interpolation sigma 0.1 / 2 = 0.05 rad/s.
        let v = vn200_at(Some(&a), Some(&b), 2_500_000, 60_000_000);
        assert_eq!(v.gate, None);
        assert!((v.angular_rate_radps.unwrap()[2] - 0.025).abs() < 1e-12);
        assert!((v.slope_per_s[5] - 10.0).abs() < 1e-9);
        assert!((v.step[5] - 0.05).abs() < 1e-12);
        assert_eq!(v.specific_force_mps2, Some([0.0, 0.0, -G]));
        // Without a later sample: held until the freshness limit, then stale.
        let v = vn200_at(Some(&b), None, 50_000_000, 60_000_000);
        assert_eq!((v.gate, v.angular_rate_radps.unwrap()[2]), (None, 0.1));
        let v = vn200_at(Some(&b), None, 80_000_000, 60_000_000);
        assert_eq!(v.gate, Some(GateReason::Stale));
        assert_eq!(vn200_at(None, None, 0, 1).gate, Some(GateReason::NoData));
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

    #[test]
    fn a_pitch_or_roll_mounting_alone_rotates_into_the_aircraft_frame() {
        // A unit pitched up 30 deg: its x axis is the aircraft's (cos 30, 0, -sin 30) (z down);
        // a unit rolled right 30 deg: its y axis is the aircraft's (0, cos 30, sin 30).
        let m = |pitch_deg: f64, roll_deg: f64| Mounting {
            pitch_deg,
            roll_deg,
            ..Default::default()
        };
        let c30 = 3f64.sqrt() / 2.0;
        let close = |a: [f64; 3], b: [f64; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-12);
        let x = to_aircraft([1.0, 0.0, 0.0], mount_rotation(&m(30.0, 0.0)).as_ref());
        assert!(close(x, [c30, 0.0, -0.5]), "{x:?}");
        let y = to_aircraft([0.0, 1.0, 0.0], mount_rotation(&m(0.0, 30.0)).as_ref());
        assert!(close(y, [0.0, c30, 0.5]), "{y:?}");
        assert!(mount_rotation(&Mounting::default()).is_none());
    }

    #[test]
    fn the_vn200_inertial_gate_imu_failures_and_freshness() {
        use vigil_drivers::vn200::status::{ImuStatus, InsStatus};
        let s = Vn200Sample {
            t_gps_ns: 1_000_000_000,
            sigma_ns: 0.0,
            attitude: UnitQuaternion::identity(),
            ypr_sigma_rad: None,
            ins_status: InsStatus(0x0006),
            imu_status: None,
            rates_radps: Some([0.0; 3]),
            accel_mps2: Some([0.0, 0.0, -G]),
            lla: None,
            vel_ned_mps: None,
            pos_u_m: None,
            vel_u_mps: None,
        };
        let horizon = 60_000_000;
        // ImuStatus (Table 2.18): gyro bits 0-1, accelerometer bits 2-3, 3 = failed; 2 is
        // saturated, not failed.
        for (raw, gate) in [
            (0b0000, None),
            (0b1010, None),
            (0b1100, Some(GateReason::ImuFailed)),
            (0b0011, Some(GateReason::ImuFailed)),
        ] {
            let s = Vn200Sample {
                imu_status: Some(ImuStatus(raw)),
                ..s
            };
            let g = vn200_at(Some(&s), None, s.t_gps_ns, horizon).gate;
            assert_eq!(g, gate, "ImuStatus {raw:#06b}");
        }
        // Held without a later sample: fresh up to the horizon (3 periods, 60 ms) exactly.
        let at = |t: i64| vn200_at(Some(&s), None, t, horizon).gate;
        assert_eq!(at(s.t_gps_ns + horizon), None);
        assert_eq!(at(s.t_gps_ns + horizon + 1), Some(GateReason::Stale));
        // Two samples stamped the same time (a zero span): the first one's values and no slope,
        // never a division by zero; the step is half their difference (1 m/s^2 on x, 0.1 rad/s
        // on z: 0.5 and 0.05).
        let s1 = Vn200Sample {
            rates_radps: Some([0.0, 0.0, 0.1]),
            accel_mps2: Some([1.0, 0.0, -G]),
            ..s
        };
        let v = vn200_at(Some(&s), Some(&s1), s.t_gps_ns, horizon);
        assert_eq!(v.specific_force_mps2, s.accel_mps2);
        assert_eq!(v.angular_rate_radps, s.rates_radps);
        assert_eq!(v.slope_per_s, [0.0; 6]);
        assert_eq!(v.step, [0.5, 0.0, 0.0, 0.0, 0.0, 0.05]);
    }

    #[test]
    fn a_bahrs_0x01_is_compared_up_to_exactly_its_horizon() {
        // Freshness limit 60 ms (the horizon passed in): a 0x01 exactly 60 ms before the check
        // is compared; 1 ns older it is stale.
        let p = CheckParams::default();
        let k = p.axis_threshold();
        let b = bahrs(1.0, [0.0; 3], SAFE);
        let horizon = 60_000_000;
        let at =
            |t: i64| InertialChannel::default().update(Some(&b), &vn([0.0; 3]), t, horizon, k, &p);
        let r = at(b.t_gps_ns + horizon);
        assert!(
            r.axes
                .iter()
                .all(|a| a.verdict == PairVerdict::Pass && a.gate.is_none()),
            "{r:?}"
        );
        let r = at(b.t_gps_ns + horizon + 1);
        assert!(
            r.axes.iter().all(|a| a.gate == Some(GateReason::Stale)),
            "{r:?}"
        );
    }

    #[test]
    fn the_vn200_is_interpolated_from_its_earlier_sample_not_from_zero() {
        let mk = vn_sample;
        // Hand computation, 2.5 ms into a 10 ms span: z rate 0.2 -> 0.3 rad/s gives 0.225 rad/s,
        // slope 0.1 / 0.01 = 10 rad/s^2, step 0.1 / 2 = 0.05 rad/s; x force 2 -> 1 m/s^2 gives
        // 1.75, slope -100 m/s^3, step 0.5.
        let v = vn200_at(
            Some(&mk(0, 0.2, 2.0)),
            Some(&mk(10, 0.3, 1.0)),
            2_500_000,
            60_000_000,
        );
        assert!(
            (v.angular_rate_radps.unwrap()[2] - 0.225).abs() < 1e-12,
            "{v:?}"
        );
        assert!(
            (v.specific_force_mps2.unwrap()[0] - 1.75).abs() < 1e-12,
            "{v:?}"
        );
        assert!((v.slope_per_s[5] - 10.0).abs() < 1e-9, "{v:?}");
        assert!((v.slope_per_s[0] + 100.0).abs() < 1e-9, "{v:?}");
        assert!((v.step[5] - 0.05).abs() < 1e-12, "{v:?}");
        assert!((v.step[0] - 0.5).abs() < 1e-12, "{v:?}");
    }

    #[test]
    fn a_vn200_mounting_alone_spreads_a_bahrs_health_gate_over_its_kind() {
        // Rotated vectors mix the unit's axes, so one closed BAHRS axis closes the three of its
        // kind, even when only the VN-200 is rotated on its mount.
        let mut p = CheckParams::default();
        p.mounting_vn200.yaw_deg = 90.0;
        let mut h = SAFE;
        h[1] = Health::Unavailable;
        let b = bahrs(0.0, [0.0; 3], h);
        let r = InertialChannel::default().update(Some(&b), &vn([0.0; 3]), 0, 60_000_000, 4.42, &p);
        for a in 0..3 {
            assert_eq!(
                r.axes[a].gate,
                Some(GateReason::HealthUnavailable),
                "axis {a}"
            );
        }
        for a in 3..6 {
            assert_eq!(r.axes[a].gate, None, "axis {a}");
        }
    }

    #[test]
    fn the_sigma_sums_unit_timing_and_interpolation_terms() {
        let p = CheckParams::default();
        let ip = p.inertial;
        assert_eq!(
            (
                ip.bahrs_angular_rate_sigma_radps,
                ip.vn200_angular_rate_sigma_radps
            ),
            (0.001, 0.0006)
        );
        // Time sigmas 3 and 4 us: 5 us together; times a slope of 200 rad/s^2, 1e-3 rad/s. With
        // the interpolation step 2e-3 rad/s: sigma = sqrt(1 + 0.36 + 1 + 4) e-3 = 2.5219e-3.
        let mut b = bahrs(0.0, [0.0; 3], SAFE);
        b.sigma_ns = 3000.0;
        let mut v = vn([0.0; 3]);
        v.sigma_ns = 4000.0;
        v.slope_per_s[5] = 200.0;
        v.step[5] = 2e-3;
        let r = InertialChannel::default().update(Some(&b), &v, 0, 60_000_000, 4.42, &p);
        let sigma = r.axes[5].sigma.unwrap();
        assert!((sigma - 6.36e-6f64.sqrt()).abs() < 1e-12, "{sigma}");
        assert!((sigma - 2.5219e-3).abs() < 1e-7, "{sigma}");
        // The x rate has neither term: the two units' sigmas alone.
        let sigma = r.axes[3].sigma.unwrap();
        assert!((sigma - 1.36e-6f64.sqrt()).abs() < 1e-12, "{sigma}");
    }

    /// The persistence counts the time between 0x01 records: 1 s of a fault at 10 Hz is the
    /// 11th record (the first counts one nominal period, 20 ms: 0.02 + 10 x 0.1 = 1.02 s); a
    /// time that goes back counts one nominal period too.
    #[test]
    fn persistence_counts_the_time_between_0x01_records() {
        let declared_at = |p: &CheckParams, step_s: f64| {
            let ip = p.inertial;
            let sigma = (ip.bahrs_angular_rate_sigma_radps.powi(2)
                + ip.vn200_angular_rate_sigma_radps.powi(2))
            .sqrt();
            let mut ch = InertialChannel::default();
            (1..=40).find(|&n| {
                // 5 sigma on the z rate: ratio 5 / 4.42 = 1.13, past the threshold at once, and
                // a CUSUM of +3 a record (slack 2), which alone would declare at the 20th.
                let b = bahrs(10.0 + f64::from(n) * step_s, [0.0, 0.0, 5.0 * sigma], SAFE);
                let r = ch.update(Some(&b), &vn([0.0; 3]), b.t_gps_ns, 60_000_000, 4.42, p);
                r.axes[5].verdict == PairVerdict::Fail
            })
        };
        let p = CheckParams::default();
        assert_eq!(p.bahrs_period_s, 0.02);
        assert_eq!(declared_at(&p, 0.1), Some(11));
        // Going back 0.1 s a record with a nominal period of 0.15 s: 0.15 s each, declared at
        // the 7th (1.05 s).
        let p = CheckParams {
            bahrs_period_s: 0.15,
            ..CheckParams::default()
        };
        assert_eq!(declared_at(&p, -0.1), Some(7));
    }
}
