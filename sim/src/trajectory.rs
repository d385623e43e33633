//! Piecewise trajectories: straight legs, coordinated turns and climbs/descents, evaluated in closed
//! form at any time.
//!
//! Within a segment the horizontal speed `v`, the turn rate `omega` and the vertical speed `w` are
//! constant, so the track is a circle arc: `psi(t) = psi0 + omega t`,
//! `n(t) = n0 + v/omega (sin psi(t) - sin psi0)`, `e(t) = e0 + v/omega (cos psi0 - cos psi(t))`.
//! After the last segment the vehicle flies straight and level.
//!
//! Attitude (no wind, no sideslip, no angle of attack): yaw = track, pitch = flight-path angle
//! `atan2(w, v)`, roll from the coordinated-turn condition `tan(roll) = v omega / g` with
//! g = 9.80665 m/s^2. Decision: roll changes as a step at segment boundaries (no roll-in
//! transient); within a segment the body rates are the Euler-rate transform of `psi' = omega`.

use serde::{Deserialize, Serialize};

use crate::units::G0_MPS2;

/// One segment of a trajectory (TOML: `{ kind = "turn", duration_s = 60, rate_dps = 3 }`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Segment {
    /// Straight and level.
    Straight {
        /// Duration, s.
        duration_s: f64,
    },
    /// Coordinated level turn at a constant rate (positive = right, clockwise seen from above).
    Turn {
        /// Duration, s.
        duration_s: f64,
        /// Turn rate, deg/s (3 deg/s is a standard-rate turn).
        rate_dps: f64,
    },
    /// Straight climb (positive) or descent (negative) at a constant vertical speed.
    Climb {
        /// Duration, s.
        duration_s: f64,
        /// Vertical speed, m/s, up positive.
        vertical_speed_mps: f64,
    },
    /// A climbing or descending coordinated turn.
    ClimbingTurn {
        /// Duration, s.
        duration_s: f64,
        /// Turn rate, deg/s.
        rate_dps: f64,
        /// Vertical speed, m/s, up positive.
        vertical_speed_mps: f64,
    },
}

impl Segment {
    /// (duration s, turn rate rad/s, vertical speed m/s).
    pub fn params(&self) -> (f64, f64, f64) {
        match *self {
            Segment::Straight { duration_s } => (duration_s, 0.0, 0.0),
            Segment::Turn {
                duration_s,
                rate_dps,
            } => (duration_s, rate_dps.to_radians(), 0.0),
            Segment::Climb {
                duration_s,
                vertical_speed_mps,
            } => (duration_s, 0.0, vertical_speed_mps),
            Segment::ClimbingTurn {
                duration_s,
                rate_dps,
                vertical_speed_mps,
            } => (duration_s, rate_dps.to_radians(), vertical_speed_mps),
        }
    }
}

/// Kinematic state at one instant, in the local plane of the scenario origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Position north of the origin, m.
    pub north_m: f64,
    /// Position east of the origin, m.
    pub east_m: f64,
    /// Height above the WGS-84 ellipsoid, m.
    pub height_m: f64,
    /// Velocity north, east, down, m/s.
    pub vel_ned_mps: [f64; 3],
    /// Acceleration north, east, down, m/s^2.
    pub accel_ned_mps2: [f64; 3],
    /// Track (= true heading), rad, 0 .. 2 pi.
    pub track_rad: f64,
    /// Turn rate, rad/s.
    pub turn_rate_radps: f64,
    /// Horizontal speed, m/s.
    pub speed_mps: f64,
}

impl Kinematics {
    /// Pitch (flight-path angle), rad.
    pub fn pitch_rad(&self) -> f64 {
        (-self.vel_ned_mps[2]).atan2(self.speed_mps)
    }
    /// Roll of a coordinated turn, rad: `atan(v omega / g)`.
    pub fn roll_rad(&self) -> f64 {
        (self.speed_mps * self.turn_rate_radps / G0_MPS2).atan()
    }
}

#[derive(Debug, Clone, Copy)]
struct Leg {
    t0_s: f64,
    duration_s: f64,
    north_m: f64,
    east_m: f64,
    height_m: f64,
    track_rad: f64,
    omega: f64,
    w: f64,
}

/// Peak roll rate when the bank changes at a segment boundary, deg/s (a gentle manoeuvre for a
/// small aircraft).
pub const ROLL_RATE_DPS: f64 = 15.0;

/// A trajectory: start state, constant horizontal speed and a list of segments.
#[derive(Debug, Clone)]
pub struct Trajectory {
    speed_mps: f64,
    legs: Vec<Leg>,
}

impl Trajectory {
    /// Builds the trajectory from its start (local plane, m; height m; track deg) and segments.
    pub fn new(
        north_m: f64,
        east_m: f64,
        height_m: f64,
        track_deg: f64,
        speed_mps: f64,
        segments: &[Segment],
    ) -> Self {
        let mut legs = Vec::with_capacity(segments.len() + 1);
        let mut leg = Leg {
            t0_s: 0.0,
            duration_s: 0.0,
            north_m,
            east_m,
            height_m,
            track_rad: track_deg.to_radians(),
            omega: 0.0,
            w: 0.0,
        };
        for s in segments {
            let (duration_s, omega, w) = s.params();
            leg.duration_s = duration_s.max(0.0);
            leg.omega = omega;
            leg.w = w;
            legs.push(leg);
            let k = eval(&leg, speed_mps, leg.duration_s);
            leg = Leg {
                t0_s: leg.t0_s + leg.duration_s,
                duration_s: 0.0,
                north_m: k.north_m,
                east_m: k.east_m,
                height_m: k.height_m,
                track_rad: k.track_rad,
                omega: 0.0,
                w: 0.0,
            };
        }
        // The final straight and level leg, unbounded.
        leg.duration_s = f64::INFINITY;
        legs.push(leg);
        Self { speed_mps, legs }
    }

    /// Roll, rad, and roll rate, rad/s, at `t_s`. Within a segment the roll is that of the
    /// coordinated turn ([`Kinematics::roll_rad`]); at a segment boundary where it changes, the
    /// aircraft rolls from one value to the other in a smooth S-curve (3x^2 - 2x^3) centred on the
    /// boundary, at a mean roll rate of [`ROLL_RATE_DPS`] / 1.5 (peak [`ROLL_RATE_DPS`]).
    ///
    /// Decision: only the attitude rolls smoothly; track and position keep the closed-form
    /// segments (the turn rate still steps). A truth bank that jumped by 12 deg between two
    /// samples could be met by no real aircraft and made every unit's interpolated attitude
    /// disagree for a sample; the small mismatch left between roll and turn rate during the
    /// sub-second roll-in affects no attitude comparison (every unit sees the same truth).
    pub fn roll_at(&self, t_s: f64) -> (f64, f64) {
        let k = self.at(t_s);
        let mut roll = k.roll_rad();
        let mut rate = 0.0;
        let i = self.legs.partition_point(|l| l.t0_s <= t_s);
        // The nearest boundary: the start of the leg at t_s, or of the next one.
        for b in [i.saturating_sub(1), i] {
            let Some(leg) = self.legs.get(b).filter(|_| b > 0) else {
                continue;
            };
            let before = self.at(leg.t0_s - 1e-9).roll_rad();
            let after = self.at(leg.t0_s).roll_rad();
            let d = after - before;
            let span = 1.5 * d.abs() / ROLL_RATE_DPS.to_radians();
            if span <= 0.0 || (t_s - leg.t0_s).abs() >= span / 2.0 {
                continue;
            }
            let x = (t_s - (leg.t0_s - span / 2.0)) / span;
            roll = before + d * x * x * (3.0 - 2.0 * x);
            rate = d * 6.0 * x * (1.0 - x) / span;
            break;
        }
        (roll, rate)
    }

    /// The state `t_s` seconds after the start (times before the start give the start state
    /// extrapolated backwards along the first segment).
    pub fn at(&self, t_s: f64) -> Kinematics {
        let i = self
            .legs
            .partition_point(|l| l.t0_s <= t_s)
            .saturating_sub(1);
        let leg = &self.legs[i.min(self.legs.len() - 1)];
        eval(leg, self.speed_mps, t_s - leg.t0_s)
    }
}

fn eval(leg: &Leg, v: f64, tau: f64) -> Kinematics {
    let psi0 = leg.track_rad;
    let w = leg.omega;
    let psi = psi0 + w * tau;
    let (dn, de) = if w.abs() < 1e-12 {
        (v * tau * psi0.cos(), v * tau * psi0.sin())
    } else {
        (
            v / w * (psi.sin() - psi0.sin()),
            v / w * (psi0.cos() - psi.cos()),
        )
    };
    Kinematics {
        north_m: leg.north_m + dn,
        east_m: leg.east_m + de,
        height_m: leg.height_m + leg.w * tau,
        vel_ned_mps: [v * psi.cos(), v * psi.sin(), -leg.w],
        accel_ned_mps2: [-v * w * psi.sin(), v * w * psi.cos(), 0.0],
        track_rad: psi.rem_euclid(std::f64::consts::TAU),
        turn_rate_radps: w,
        speed_mps: v,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roll_changes_smoothly_across_a_segment_boundary() {
        // 40 m/s, straight 10 s then a 3 deg/s turn: bank atan(40 x 0.05236 / 9.80665) = 12.055
        // deg, rolled in over 1.5 x 12.055 / 15 = 1.2055 s centred on t = 10 s.
        let t = Trajectory::new(
            0.0,
            0.0,
            0.0,
            0.0,
            40.0,
            &[
                Segment::Straight { duration_s: 10.0 },
                Segment::Turn {
                    duration_s: 30.0,
                    rate_dps: 3.0,
                },
            ],
        );
        let bank = (40.0 * 3f64.to_radians() / G0_MPS2).atan();
        assert!((bank.to_degrees() - 12.055).abs() < 1e-3);
        let span = 1.5 * bank.to_degrees() / ROLL_RATE_DPS;
        assert_eq!(t.roll_at(5.0), (0.0, 0.0));
        assert_eq!(t.roll_at(10.0 - span / 2.0 - 1e-6).0, 0.0);
        // Half-way at the boundary, at the peak rate.
        let (r, p) = t.roll_at(10.0);
        assert!((r - bank / 2.0).abs() < 1e-9);
        assert!(
            (p.to_degrees() - ROLL_RATE_DPS).abs() < 1e-6,
            "{}",
            p.to_degrees()
        );
        assert!((t.roll_at(10.0 + span / 2.0 + 1e-6).0 - bank).abs() < 1e-12);
        // Monotonic, and never a step bigger than the peak rate allows.
        let mut prev = t.roll_at(9.0).0;
        for k in 1..=200 {
            let r = t.roll_at(9.0 + k as f64 * 0.01).0;
            assert!(r >= prev && r - prev <= ROLL_RATE_DPS.to_radians() * 0.01 + 1e-12);
            prev = r;
        }
    }

    #[test]
    fn full_circle_returns_to_start_and_bank_by_hand() {
        // 3 deg/s for 120 s is 360 deg: back at the start. Radius v / omega = 50 / 0.05236 = 954.9 m.
        let t = Trajectory::new(
            0.0,
            0.0,
            500.0,
            0.0,
            50.0,
            &[Segment::Turn {
                duration_s: 120.0,
                rate_dps: 3.0,
            }],
        );
        let end = t.at(120.0);
        assert!(end.north_m.abs() < 1e-6 && end.east_m.abs() < 1e-6);
        // After a quarter turn (30 s) heading east, one radius north and one radius east.
        let q = t.at(30.0);
        let r = 50.0 / 3f64.to_radians();
        assert!((q.north_m - r).abs() < 1e-6 && (q.east_m - r).abs() < 1e-6);
        assert!((q.track_rad - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        // Bank: tan(phi) = 50 x 0.0523599 / 9.80665 = 0.266961 -> phi = 14.9472 deg.
        assert!(
            (q.roll_rad().to_degrees() - 14.9472).abs() < 0.0001,
            "{}",
            q.roll_rad().to_degrees()
        );
        // Centripetal acceleration v omega = 2.618 m/s^2 towards the centre (south at t = 30 s).
        assert!((q.accel_ned_mps2[0] + 2.617_994).abs() < 1e-5);
    }

    #[test]
    fn climb_then_straight_and_level_forever() {
        let t = Trajectory::new(
            0.0,
            0.0,
            100.0,
            90.0,
            40.0,
            &[Segment::Climb {
                duration_s: 10.0,
                vertical_speed_mps: 5.0,
            }],
        );
        let k = t.at(5.0);
        assert!((k.height_m - 125.0).abs() < 1e-9);
        assert!((k.pitch_rad() - (5.0f64 / 40.0).atan()).abs() < 1e-12);
        let k = t.at(110.0);
        assert!((k.height_m - 150.0).abs() < 1e-9);
        assert!((k.east_m - 40.0 * 110.0).abs() < 1e-6);
        assert_eq!(k.vel_ned_mps[2], 0.0);
    }
}
