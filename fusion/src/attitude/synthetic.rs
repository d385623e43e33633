//! Synthetic, time-ordered streams of the three units for the cross-check's tests and benchmark
//! (issue 8, "Done when": the `bahrs-attitude-fault`, `nominal`, magnetic-disturbance and
//! GNSS-loss behaviours), generated from an analytic truth so every expected value is known.
//!
//! Truth: 40 m/s, pitch 2 deg, a 120 s cycle of straight flight, a 30 s right turn at 3 deg/s,
//! straight, a 30 s left turn (turn rate ramped over 3 s, bank coordinated
//! `phi = atan(V psi_dot / g)`, about 12 deg), and a gentle climb/descent (1 m/s amplitude over
//! 100 s). BAHRS at 50 Hz (raw messages through `Navigation::from_si`, so quantised like the
//! wire), VN-200 at 50 Hz offset by 7 ms, Watson at 11.85 Hz rounded to 0.1 deg like its string.
//! Magnetic units report `true - declination`.

use vigil_drivers::bahrs::{
    Accuracy, Health, Inertial, InertialHealth, Navigation, NavigationHealth,
};
use vigil_drivers::vn200::status::InsStatus;

use super::angles::{from_ypr, to_ypr, wrap_2pi};
use super::samples::{BahrsSample, Vn200Sample, WatsonSample};
use crate::time::AlignedTime;
use crate::time::{ClockStatus, TimeSource};

const DEG: f64 = std::f64::consts::PI / 180.0;
const G: f64 = 9.80665;
const SPEED_MPS: f64 = 40.0;
const TURN_RATE: f64 = 3.0 * DEG;
const PITCH: f64 = 2.0 * DEG;

/// What goes wrong, and when (s from the start).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scenario {
    /// Length, s.
    pub duration_s: f64,
    /// Noise seed.
    pub seed: u64,
    /// GPS time of the start, ns.
    pub t0_gps_ns: i64,
    /// Declination the magnetic units see, deg.
    pub declination_deg: f64,
    /// BAHRS roll bias ramp: start, s, and rate, deg/s.
    pub roll_ramp: Option<(f64, f64)>,
    /// BAHRS roll health "integrity risk" from, s.
    pub integrity_risk_from_s: Option<f64>,
    /// Magnetic disturbance on BAHRS and Watson heading: from, s, and offset, deg.
    pub magnetic_disturbance: Option<(f64, f64)>,
    /// VN-200 mode GnssLost (no position) from, s.
    pub gnss_lost_from_s: Option<f64>,
    /// Watson silent from, s.
    pub watson_stops_s: Option<f64>,
    /// Position of the aircraft (lat deg, lon deg, height m), fixed (attitude tests).
    pub lla: [f64; 3],
    /// VN-200 roll error step: from, s, and size, deg.
    pub vn200_roll_step: Option<(f64, f64)>,
    /// Watson pitch error step: from, s, and size, deg.
    pub watson_pitch_step: Option<(f64, f64)>,
    /// BAHRS mounting (yaw, pitch, roll offsets of its body frame), deg.
    pub bahrs_mounting_deg: [f64; 3],
    // --- issue 25 ---
    /// BAHRS times as from a host-clock fallback: each stamp off by a Gaussian error of this
    /// 1-sigma, ns, and the sample's `sigma_ns` saying so (None: PPS-disciplined, 0.1 ms).
    pub bahrs_time_sigma_ns: Option<f64>,
}

impl Default for Scenario {
    fn default() -> Self {
        Self {
            duration_s: 120.0,
            seed: 1,
            // 2026-06-01 10:00:00 UTC (the simulator scenarios' start), GPS = UTC + 18 s.
            t0_gps_ns: (crate::time::gps::days_from_civil(2026, 6, 1) * 86_400 + 36_000
                - crate::time::gps::GPS_EPOCH_UNIX_S
                + 18)
                * 1_000_000_000,
            declination_deg: 3.0,
            roll_ramp: None,
            integrity_risk_from_s: None,
            magnetic_disturbance: None,
            gnss_lost_from_s: None,
            watson_stops_s: None,
            lla: [47.40, 8.50, 600.0],
            vn200_roll_step: None,
            watson_pitch_step: None,
            bahrs_mounting_deg: [0.0; 3],
            bahrs_time_sigma_ns: None,
        }
    }
}

/// One sample of one unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event {
    /// BAHRS.
    Bahrs(BahrsSample),
    /// VN-200.
    Vn200(Vn200Sample),
    /// Watson.
    Watson(WatsonSample),
}

impl Event {
    /// Pushes the sample into `c`; returns its GPS time (ns) and its unit.
    pub fn push_into(
        self,
        c: &mut super::checker::AttitudeChecker,
    ) -> (i64, super::isolation::Unit) {
        match self {
            Event::Bahrs(b) => {
                c.push_bahrs(b);
                (b.t_gps_ns, super::isolation::Unit::Bahrs)
            }
            Event::Vn200(v) => {
                c.push_vn200(v);
                (v.t_gps_ns, super::isolation::Unit::Vn200)
            }
            Event::Watson(w) => {
                c.push_watson(w);
                (w.t_gps_ns, super::isolation::Unit::Watson)
            }
        }
    }
}

/// Truth at `t` s: yaw (true), pitch, roll (rad), body rates p, q, r (rad/s), climb rate (m/s
/// up) and height (m).
pub fn truth(t: f64) -> ([f64; 3], [f64; 3], f64, f64) {
    let cycle = t.rem_euclid(120.0);
    // Normalised turn-rate profile and its integral over one 30 s turn.
    let prof = |tau: f64| -> (f64, f64, f64) {
        if !(0.0..=30.0).contains(&tau) {
            return (0.0, 0.0, if tau > 30.0 { 27.0 } else { 0.0 });
        }
        if tau < 3.0 {
            (tau / 3.0, 1.0 / 3.0, tau * tau / 6.0)
        } else if tau <= 27.0 {
            (1.0, 0.0, 1.5 + (tau - 3.0))
        } else {
            let u = tau - 27.0;
            (1.0 - u / 3.0, -1.0 / 3.0, 25.5 + u - u * u / 6.0)
        }
    };
    let (s1, ds1, i1) = prof(cycle - 30.0);
    let (s2, ds2, i2) = prof(cycle - 90.0);
    let s = s1 - s2;
    let ds = ds1 - ds2;
    let yaw = wrap_2pi(90.0 * DEG + TURN_RATE * (i1 - i2));
    let psi_dot = TURN_RATE * s;
    let k = SPEED_MPS * TURN_RATE / G;
    let roll = (k * s).atan();
    let roll_dot = k * ds / (1.0 + (k * s) * (k * s));
    let (sp, cp) = roll.sin_cos();
    let p = roll_dot - psi_dot * PITCH.sin();
    let q = psi_dot * sp * PITCH.cos();
    let r = psi_dot * cp * PITCH.cos();
    let w = std::f64::consts::TAU / 100.0;
    let climb = (w * t).sin();
    let height = 600.0 - (w * t).cos() / w;
    ([yaw, PITCH, roll], [p, q, r], climb, height)
}

/// A small deterministic Gaussian generator (xorshift64* and Box-Muller).
#[derive(Debug, Clone)]
pub struct Noise(u64);

impl Noise {
    /// Seeded generator.
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    fn unit(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        ((self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    }
    /// A standard normal value.
    pub fn gauss(&mut self) -> f64 {
        let (u1, u2) = (self.unit(), self.unit());
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }
    /// A normal value of mean `mean` and standard deviation `sigma` (same unit): how every
    /// simulated measurement gets its noise.
    pub fn around(&mut self, mean: f64, sigma: f64) -> f64 {
        mean + sigma * self.gauss()
    }
}

/// The time-ordered stream of a scenario.
pub struct Stream {
    sc: Scenario,
    noise: Noise,
    k: [u64; 3],
    seq: u8,
}

/// Stream periods, ns: BAHRS, VN-200, Watson.
const PERIOD_NS: [f64; 3] = [20e6, 20e6, 1e9 / 11.85];
/// Offsets of the first sample, ns.
const OFFSET_NS: [f64; 3] = [0.0, 7e6, 3e6];

impl Stream {
    /// The stream of `sc`.
    pub fn new(sc: Scenario) -> Self {
        Self {
            noise: Noise::new(sc.seed),
            sc,
            k: [0; 3],
            seq: 0,
        }
    }

    fn time(&self, t_rel_ns: f64, sigma_ns: f64, source: TimeSource) -> AlignedTime {
        AlignedTime {
            t_gps_ns: self.sc.t0_gps_ns + t_rel_ns as i64,
            sigma_ns,
            source,
            status: ClockStatus::Locked,
        }
    }

    fn bahrs(&mut self, t: f64, t_ns: f64) -> BahrsSample {
        let ([yaw, pitch, roll], rates, climb, height) = truth(t);
        let sc = self.sc;
        let n = &mut self.noise;
        let bias = sc
            .roll_ramp
            .map(|(from, rate)| ((t - from).max(0.0)) * rate * DEG)
            .unwrap_or(0.0);
        let dist = sc
            .magnetic_disturbance
            .filter(|(from, _)| t >= *from)
            .map(|(_, d)| d * DEG)
            .unwrap_or(0.0);
        let roll_health = match sc.integrity_risk_from_s {
            Some(from) if t >= from => Health::IntegrityRisk,
            _ => Health::Safe,
        };
        let health = NavigationHealth::new(
            Health::Safe,
            Health::Safe,
            roll_health,
            Health::Safe,
            Health::Safe,
        );
        self.seq = self.seq.wrapping_add(1);
        // The unit's frame is the aircraft's rotated by the mounting: q_unit = q_aircraft q_mount.
        let [my, mp, mr] = sc.bahrs_mounting_deg.map(|d| d * DEG);
        let (yaw, pitch, roll) = to_ypr(&(from_ypr(yaw, pitch, roll) * from_ypr(my, mp, mr)));
        let nav = Navigation::from_si(
            self.seq,
            n.around(height - 40.0, 0.3),
            n.around(-climb, 0.1),
            n.around(roll + bias, 0.15 * DEG),
            n.around(pitch, 0.15 * DEG),
            n.around(yaw - sc.declination_deg * DEG + dist, 0.5 * DEG),
            health,
        );
        // Reported accuracy: 0.3 deg tilt, 1.0 deg heading (raw LSB 2 pi / 65536).
        let lsb = std::f64::consts::TAU / 65536.0;
        let acc = Accuracy {
            seq: self.seq,
            std_north_raw: (0.3 * DEG / lsb).round() as u16,
            std_east_raw: (0.3 * DEG / lsb).round() as u16,
            std_heading_raw: (1.0 * DEG / lsb).round() as u16,
            mcu_time_us: 0,
        };
        let safe = [Health::Safe; 3];
        let inertial = Inertial::from_si(
            self.seq,
            [0.0, 0.0, -G],
            rates,
            InertialHealth::new(safe, safe),
        );
        let time = match sc.bahrs_time_sigma_ns {
            // The value is the truth at t; its stamp is off by the clock error.
            Some(sigma) => {
                let stamp_ns = n.around(t_ns, sigma);
                self.time(stamp_ns, sigma, TimeSource::HostClock)
            }
            None => self.time(t_ns, 1e5, TimeSource::PpsDisciplined),
        };
        BahrsSample::new(&time, &nav, Some(&acc), Some(&inertial))
    }

    fn vn200(&mut self, t: f64, t_ns: f64) -> Vn200Sample {
        let ([yaw, pitch, roll], rates, climb, height) = truth(t);
        let sc = self.sc;
        let n = &mut self.noise;
        let lost = sc.gnss_lost_from_s.is_some_and(|from| t >= from);
        // 0x0006 Tracking + fix; 0x0043 GnssLost with the GNSS error bit.
        let ins = InsStatus(if lost { 0x0043 } else { 0x0006 });
        let step = sc
            .vn200_roll_step
            .filter(|(from, _)| t >= *from)
            .map(|(_, d)| d * DEG)
            .unwrap_or(0.0);
        let attitude = from_ypr(
            n.around(yaw, 0.2 * DEG),
            n.around(pitch, 0.05 * DEG),
            n.around(roll + step, 0.05 * DEG),
        );
        Vn200Sample {
            t_gps_ns: sc.t0_gps_ns + t_ns as i64,
            sigma_ns: 1e3,
            attitude,
            ypr_sigma_rad: Some([0.5 * DEG, 0.1 * DEG, 0.1 * DEG]),
            ins_status: ins,
            imu_status: None,
            rates_radps: Some(rates),
            accel_mps2: None,
            lla: Some([sc.lla[0], sc.lla[1], n.around(height, 0.5)]),
            vel_ned_mps: Some([0.0, SPEED_MPS, n.around(-climb, 0.05)]),
            pos_u_m: Some(if lost { 50.0 } else { 2.0 }),
            vel_u_mps: Some(0.1),
        }
    }

    fn watson(&mut self, t: f64, t_ns: f64) -> WatsonSample {
        let ([yaw, pitch, roll], rates, _, _) = truth(t);
        let sc = self.sc;
        let n = &mut self.noise;
        let dist = sc
            .magnetic_disturbance
            .filter(|(from, _)| t >= *from)
            .map(|(_, d)| d * DEG)
            .unwrap_or(0.0);
        let pstep = sc
            .watson_pitch_step
            .filter(|(from, _)| t >= *from)
            .map(|(_, d)| d * DEG)
            .unwrap_or(0.0);
        let q01 = |rad: f64| (rad / DEG * 10.0).round() / 10.0 * DEG;
        WatsonSample {
            t_gps_ns: sc.t0_gps_ns + t_ns as i64,
            sigma_ns: 2e6,
            roll_rad: q01(n.around(roll, 0.3 * DEG)),
            pitch_rad: q01(n.around(pitch + pstep, 0.3 * DEG)),
            heading_mag_rad: q01(wrap_2pi(
                n.around(yaw - sc.declination_deg * DEG + dist, 0.8 * DEG),
            )),
            over_range: false,
            rates_radps: rates.map(q01),
        }
    }
}

impl Iterator for Stream {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        loop {
            let times: [f64; 3] =
                std::array::from_fn(|i| OFFSET_NS[i] + self.k[i] as f64 * PERIOD_NS[i]);
            let i = (0..3).min_by(|&a, &b| times[a].total_cmp(&times[b]))?;
            let t_ns = times[i];
            let t = t_ns * 1e-9;
            if t >= self.sc.duration_s {
                return None;
            }
            self.k[i] += 1;
            return Some(match i {
                0 => Event::Bahrs(self.bahrs(t, t_ns)),
                1 => Event::Vn200(self.vn200(t, t_ns)),
                _ => {
                    if self.sc.watson_stops_s.is_some_and(|s| t >= s) {
                        continue;
                    }
                    Event::Watson(self.watson(t, t_ns))
                }
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn truth_turns_are_coordinated_and_return_to_the_start_heading() {
        // A full 30 s turn at 3 deg/s with 3 s ramps turns 27 x 3 = 81 deg.
        let (a, _, _, _) = truth(29.0);
        let (b, _, _, _) = truth(61.0);
        assert!(((b[0] - a[0]) / DEG - 81.0).abs() < 1e-9);
        let (c, _, _, _) = truth(120.0);
        assert!((c[0] - 90.0 * DEG).abs() < 1e-9);
        // Mid-turn bank: atan(40 x 0.05236 / 9.80665) = 12.05 deg.
        let (m, r, _, _) = truth(45.0);
        assert!((m[2] / DEG - 12.05).abs() < 0.01, "{}", m[2] / DEG);
        // Body yaw rate r = psi_dot cos(phi) cos(theta).
        assert!((r[2] - TURN_RATE * m[2].cos() * PITCH.cos()).abs() < 1e-12);
    }

    /// The times where the turn-rate profile has a corner (cycle s): the derivative checks keep
    /// away from them.
    fn near_a_corner(t: f64) -> bool {
        let c = t.rem_euclid(120.0);
        [0.0, 30.0, 33.0, 57.0, 60.0, 90.0, 93.0, 117.0, 120.0]
            .iter()
            .any(|k| (c - k).abs() < 1e-3)
    }

    #[test]
    fn truth_rates_are_the_derivatives_of_its_attitude_and_height() {
        // Central differences over +-h, independent of the formulas for the rates: the yaw
        // rate from the heading, the body rates from the rotation between the two attitudes
        // (its rotation vector over 2h), the climb from the height.
        let h = 1e-4;
        let mut t = 0.05;
        let mut checked = 0;
        while t < 240.0 {
            if !near_a_corner(t) {
                let ([y0, p0, r0], _, _, h0) = truth(t - h);
                let ([y1, p1, r1], _, _, h1) = truth(t + h);
                let (_, w_mid, climb_mid, _) = truth(t);
                let dq = from_ypr(y0, p0, r0).inverse() * from_ypr(y1, p1, r1);
                let v = dq.scaled_axis() / (2.0 * h);
                for a in 0..3 {
                    assert!(
                        (v[a] - w_mid[a]).abs() < 1e-7,
                        "t {t} axis {a}: {v} {w_mid:?}"
                    );
                }
                assert!(((h1 - h0) / (2.0 * h) - climb_mid).abs() < 1e-7, "t {t}");
                checked += 1;
            }
            t += 0.37;
        }
        assert!(checked > 600, "{checked}");
    }

    #[test]
    fn truth_by_hand_on_the_ramp_the_left_turn_and_the_climb() {
        // 1.5 s into the right turn's 3 s ramp: turn rate 1.5 deg/s; heading 90 + 3 x 1.5^2 / 6
        // = 91.125 deg; at the ramp's end 90 + 3 x 1.5 = 94.5 deg.
        let ([yaw, pitch, _], _, _, _) = truth(31.5);
        assert!((yaw / DEG - 91.125).abs() < 1e-9, "{}", yaw / DEG);
        assert!((pitch / DEG - 2.0).abs() < 1e-12);
        let ([yaw, ..], _, _, _) = truth(33.0);
        assert!((yaw / DEG - 94.5).abs() < 1e-9, "{}", yaw / DEG);
        // 2.5 s into the right turn's ramp-out (tau 29.5): rate 3 x (1 - 2.5 / 3) = 0.5 deg/s;
        // heading 90 + 3 x (25.5 + 2.5 - 2.5^2 / 6) = 90 + 80.875 deg.
        let ([yaw, ..], _, _, _) = truth(59.5);
        assert!((yaw / DEG - 170.875).abs() < 1e-9, "{}", yaw / DEG);
        // Mid left turn: bank -atan(40 x 3 deg/s / g) = -12.05 deg, yaw rate about the body
        // z negative; back on the start heading after it.
        let ([yaw, _, roll], w, _, _) = truth(105.0);
        assert!((roll / DEG + 12.05).abs() < 0.01, "{}", roll / DEG);
        assert!(w[2] < -0.05, "{w:?}");
        assert!(
            (yaw / DEG - (171.0 - 3.0 * 13.5)).abs() < 1e-9,
            "{}",
            yaw / DEG
        );
        // Climb: 1 m/s amplitude over 100 s, 0 at t = 0, +1 at 25 s, -1 at 75 s; height 600 m -
        // cos(wt)/w, w = 2 pi / 100 s.
        let w = std::f64::consts::TAU / 100.0;
        for (t, c) in [(0.0, 0.0), (25.0, 1.0), (75.0, -1.0)] {
            let (_, _, climb, height) = truth(t);
            assert!((climb - c).abs() < 1e-12, "{t}");
            assert!((height - (600.0 - (w * t).cos() / w)).abs() < 1e-9, "{t}");
        }
        // Straight flight: level wings, no rates.
        let ([yaw, _, roll], w, _, _) = truth(10.0);
        assert_eq!((yaw, roll, w), (90.0 * DEG, 0.0, [0.0; 3]));
    }

    #[test]
    fn noise_is_xorshift64_star_and_box_muller() {
        // The published xorshift64* (shifts 12, 25, 27; multiplier 0x2545F4914F6CDD1D), state
        // seed x 0x9E3779B97F4A7C15 | 1, top 53 bits plus a half over 2^53: the first values
        // for seed 1, computed apart with Python's integers.
        let mut n = Noise::new(1);
        let u: [f64; 4] = std::array::from_fn(|_| n.unit());
        assert_eq!(
            u,
            [
                0.05279087335850824,
                0.3311202810018536,
                0.657317355741249,
                0.4899604040060455
            ]
        );
        // Box-Muller on those pairs: sqrt(-2 ln u1) cos(2 pi u2).
        let mut n = Noise::new(1);
        assert!((n.gauss() + 1.1834038310489554).abs() < 1e-12);
        assert!((n.gauss() + 0.9142438849714214).abs() < 1e-12);
        // And standard normal: mean 0 and variance 1 within 4 standard errors on 100 000.
        let mut n = Noise::new(7);
        let x: Vec<f64> = (0..100_000).map(|_| n.gauss()).collect();
        let mean = x.iter().sum::<f64>() / 1e5;
        let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / 1e5;
        assert!(mean.abs() < 4.0 / 1e5f64.sqrt(), "{mean}");
        assert!(
            (var - 1.0).abs() < 4.0 * 2f64.sqrt() / 1e5f64.sqrt(),
            "{var}"
        );
    }

    /// Mean and standard deviation.
    fn stats(v: &[f64]) -> (f64, f64) {
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        (
            m,
            (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / n).sqrt(),
        )
    }

    /// `v`'s mean is `mean` within 4 standard errors and its standard deviation `sd` within
    /// `tol` (relative); `sd` includes the uniform quantisation of a step `lsb` (lsb^2 / 12).
    fn assert_noise(what: &str, v: &[f64], mean: f64, sd: f64, lsb: f64, tol: f64) {
        let sd = (sd * sd + lsb * lsb / 12.0).sqrt();
        let (m, s) = stats(v);
        let se = sd / (v.len() as f64).sqrt();
        assert!(
            (m - mean).abs() < 4.0 * se,
            "{what}: mean {m} for {mean} (se {se})"
        );
        assert!((s / sd - 1.0).abs() < tol, "{what}: sd {s} for {sd}");
    }

    #[test]
    fn each_unit_reports_the_truth_with_its_documented_offsets_and_noise() {
        use super::super::angles::wrap_pi;
        use vigil_drivers::bahrs::{
            ANGLE_RAD_PER_LSB, ANGULAR_RATE_RADPS_PER_LSB, HEIGHT_M_PER_LSB, VELOCITY_MPS_PER_LSB,
        };
        let sc = Scenario::default();
        let (t0, decl) = (sc.t0_gps_ns, sc.declination_deg * DEG);
        let mut b: [Vec<f64>; 5] = Default::default();
        let mut v: [Vec<f64>; 5] = Default::default();
        let mut w: [Vec<f64>; 3] = Default::default();
        let mut n = [0usize; 3];
        let mut last = i64::MIN;
        for e in Stream::new(sc) {
            let t_ns = match e {
                Event::Bahrs(s) => s.t_gps_ns,
                Event::Vn200(s) => s.t_gps_ns,
                Event::Watson(s) => s.t_gps_ns,
            };
            assert!(t_ns >= last, "time-ordered");
            last = t_ns;
            let t = (t_ns - t0) as f64 * 1e-9;
            let ([yaw, pitch, roll], rates, climb, height) = truth(t);
            match e {
                Event::Bahrs(s) => {
                    // 50 Hz from 0.
                    assert_eq!(t_ns - t0, n[0] as i64 * 20_000_000);
                    n[0] += 1;
                    assert_eq!((s.sigma_ns, s.health.roll()), (1e5, Health::Safe));
                    b[0].push(s.pressure_height_m - height);
                    b[1].push(s.velocity_down_mps + climb);
                    b[2].push(s.roll_rad - roll);
                    b[3].push(s.pitch_rad - pitch);
                    b[4].push(wrap_pi(s.heading_mag_rad - (yaw - decl)));
                    // Reported accuracy 0.3, 0.3 and 1 deg, to the LSB (2 pi / 65536).
                    let acc = s.accuracy_rad.unwrap().map(Option::unwrap);
                    for (a, want) in acc.iter().zip([0.3, 0.3, 1.0]) {
                        assert!((a - want * DEG).abs() <= ANGLE_RAD_PER_LSB / 2.0, "{acc:?}");
                    }
                    let r = s.rates_radps.unwrap();
                    for (got, want) in r.iter().zip(rates) {
                        assert!((got - want).abs() <= ANGULAR_RATE_RADPS_PER_LSB / 2.0);
                    }
                }
                Event::Vn200(s) => {
                    // 50 Hz from 7 ms.
                    assert_eq!(t_ns - t0, 7_000_000 + n[1] as i64 * 20_000_000);
                    n[1] += 1;
                    assert_eq!(s.ins_status, InsStatus(0x0006));
                    assert_eq!((s.sigma_ns, s.pos_u_m), (1e3, Some(2.0)));
                    let (y, p, r) = to_ypr(&s.attitude);
                    v[0].push(wrap_pi(y - yaw));
                    v[1].push(p - pitch);
                    v[2].push(r - roll);
                    v[3].push(s.lla.unwrap()[2] - height);
                    let vel = s.vel_ned_mps.unwrap();
                    assert_eq!(vel[..2], [0.0, SPEED_MPS]);
                    v[4].push(vel[2] + climb);
                    assert_eq!(s.rates_radps, Some(rates));
                }
                Event::Watson(s) => {
                    // 11.85 Hz from 3 ms.
                    let want = 3e6 + n[2] as f64 * 1e9 / 11.85;
                    assert!(((t_ns - t0) as f64 - want).abs() <= 1.0, "{t_ns}");
                    n[2] += 1;
                    assert_eq!(s.sigma_ns, 2e6);
                    w[0].push(s.roll_rad - roll);
                    w[1].push(s.pitch_rad - pitch);
                    w[2].push(wrap_pi(s.heading_mag_rad - (yaw - decl)));
                    // Rates rounded to 0.1 deg/s.
                    for (got, want) in s.rates_radps.iter().zip(rates) {
                        assert!((got - want).abs() <= 0.05 * DEG + 1e-12);
                    }
                }
            }
        }
        // 120 s: 6000 BAHRS and VN-200 samples, and Watson at 0.003 + k / 11.85 < 120 s,
        // k = 0 ..= 1421.
        assert_eq!(n, [6000, 6000, 1422]);
        let a = ANGLE_RAD_PER_LSB;
        assert_noise("BAHRS height", &b[0], -40.0, 0.3, HEIGHT_M_PER_LSB, 0.05);
        assert_noise("BAHRS v down", &b[1], 0.0, 0.1, VELOCITY_MPS_PER_LSB, 0.05);
        assert_noise("BAHRS roll", &b[2], 0.0, 0.15 * DEG, a, 0.05);
        assert_noise("BAHRS pitch", &b[3], 0.0, 0.15 * DEG, a, 0.05);
        assert_noise("BAHRS heading", &b[4], 0.0, 0.5 * DEG, a, 0.05);
        assert_noise("VN-200 yaw", &v[0], 0.0, 0.2 * DEG, 0.0, 0.05);
        assert_noise("VN-200 pitch", &v[1], 0.0, 0.05 * DEG, 0.0, 0.05);
        assert_noise("VN-200 roll", &v[2], 0.0, 0.05 * DEG, 0.0, 0.05);
        assert_noise("VN-200 height", &v[3], 0.0, 0.5, 0.0, 0.05);
        assert_noise("VN-200 v down", &v[4], 0.0, 0.05, 0.0, 0.05);
        // Watson: rounded to 0.1 deg.
        assert_noise("Watson roll", &w[0], 0.0, 0.3 * DEG, 0.1 * DEG, 0.08);
        assert_noise("Watson pitch", &w[1], 0.0, 0.3 * DEG, 0.1 * DEG, 0.08);
        assert_noise("Watson heading", &w[2], 0.0, 0.8 * DEG, 0.1 * DEG, 0.08);
    }

    #[test]
    fn a_host_clock_bahrs_is_stamped_with_its_time_error() {
        // 1 ms of clock error: the stamps scatter about the true times with that sigma, and
        // say so.
        let sc = Scenario {
            bahrs_time_sigma_ns: Some(1e6),
            duration_s: 60.0,
            ..Scenario::default()
        };
        let mut err = Vec::new();
        for e in Stream::new(sc) {
            if let Event::Bahrs(s) = e {
                assert_eq!(s.sigma_ns, 1e6);
                err.push((s.t_gps_ns - sc.t0_gps_ns) as f64 - err.len() as f64 * 20e6);
            }
        }
        assert_eq!(err.len(), 3000);
        assert_noise("stamp error", &err, 0.0, 1e6, 1.0, 0.05);
    }

    #[test]
    fn injected_errors_add_with_their_sign() {
        // From 10 s: a BAHRS roll ramp of +0.5 deg/s, a VN-200 roll step of +2 deg and a Watson
        // pitch step of +3 deg. Each unit's error, less the injected one, is its noise about
        // zero (0.15, 0.05 and 0.3 deg; Watson rounded to 0.1 deg), before and after.
        let sc = Scenario {
            roll_ramp: Some((10.0, 0.5)),
            vn200_roll_step: Some((10.0, 2.0)),
            watson_pitch_step: Some((10.0, 3.0)),
            duration_s: 20.0,
            ..Scenario::default()
        };
        let mut err: [Vec<f64>; 6] = Default::default();
        for e in Stream::new(sc) {
            let t_ns = match e {
                Event::Bahrs(s) => s.t_gps_ns,
                Event::Vn200(s) => s.t_gps_ns,
                Event::Watson(s) => s.t_gps_ns,
            };
            let t = (t_ns - sc.t0_gps_ns) as f64 * 1e-9;
            let ([_, pitch, roll], ..) = truth(t);
            let on = usize::from(t >= 10.0);
            match e {
                Event::Bahrs(s) => {
                    let injected = 0.5 * (t - 10.0).max(0.0) * DEG;
                    err[on].push(s.roll_rad - roll - injected);
                }
                Event::Vn200(s) => {
                    let injected = if t >= 10.0 { 2.0 * DEG } else { 0.0 };
                    err[2 + on].push(to_ypr(&s.attitude).2 - roll - injected);
                }
                Event::Watson(s) => {
                    let injected = if t >= 10.0 { 3.0 * DEG } else { 0.0 };
                    err[4 + on].push(s.pitch_rad - pitch - injected);
                }
            }
        }
        let a = vigil_drivers::bahrs::ANGLE_RAD_PER_LSB;
        for k in 0..2 {
            assert_noise("BAHRS roll", &err[k], 0.0, 0.15 * DEG, a, 0.1);
            assert_noise("VN-200 roll", &err[2 + k], 0.0, 0.05 * DEG, 0.0, 0.1);
            assert_noise("Watson pitch", &err[4 + k], 0.0, 0.3 * DEG, 0.1 * DEG, 0.15);
        }
    }
}
