//! Relative threat geometry (DO-365 well-clear) of intruders against the ownship.
//!
//! - [`wgs84`]: the local tangent plane at the ownship on the WGS-84 ellipsoid;
//! - [`daa`]: CPA, modified tau, the well-clear volume now and predicted, alert levels;
//! - [`AircraftState`] and [`relative`]: from geodetic states to the relative state in the
//!   ownship's plane. [`OwnshipFrame`] and [`IntruderEcef`] cache the trigonometry so that a fusion
//!   step against many intruders costs a few dot products each.

pub mod daa;
pub mod wgs84;

use nalgebra::{Vector2, Vector3};

pub use daa::{Geometry, Relative, Thresholds};
use wgs84::{EnuFrame, enu_velocity, geodetic_to_ecef};

/// An aircraft's state over the earth (SI, angles in degrees as named).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AircraftState {
    /// Latitude, deg (WGS-84).
    pub lat_deg: f64,
    /// Longitude, deg.
    pub lon_deg: f64,
    /// Altitude, m. Compare like with like: pressure altitude with pressure altitude, geometric
    /// with geometric. The horizontal plane is insensitive to which one is used.
    pub alt_m: f64,
    /// Track over ground, deg true, in the aircraft's own local north.
    pub track_deg: f64,
    /// Ground speed, m/s.
    pub ground_speed_mps: f64,
    /// Vertical rate, m/s, up.
    pub vertical_rate_mps: f64,
}

/// The ownship's tangent plane, computed once per fusion step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OwnshipFrame {
    frame: EnuFrame,
    velocity_enu: Vector3<f64>,
    alt_m: f64,
}

impl OwnshipFrame {
    /// The frame at the ownship's state.
    pub fn new(own: &AircraftState) -> Self {
        Self {
            frame: EnuFrame::at(own.lat_deg, own.lon_deg, own.alt_m),
            velocity_enu: enu_velocity(own.track_deg, own.ground_speed_mps, own.vertical_rate_mps),
            alt_m: own.alt_m,
        }
    }

    /// The frame at a position alone (an ownship whose velocity is unknown): its velocity is
    /// taken as zero, so use [`OwnshipFrame::position_of`] and [`OwnshipFrame::velocity_of`]
    /// rather than [`OwnshipFrame::relative`], and let [`crate::traffic::policy`] decide.
    pub fn at_position(lat_deg: f64, lon_deg: f64, alt_m: f64) -> Self {
        Self {
            frame: EnuFrame::at(lat_deg, lon_deg, alt_m),
            velocity_enu: Vector3::zeros(),
            alt_m,
        }
    }

    /// An intruder's position in this plane (east, north, up), m.
    pub fn position_of(&self, intruder: &IntruderEcef) -> Vector3<f64> {
        self.frame.position(&intruder.position_ecef)
    }

    /// An intruder's horizontal velocity over ground in this plane (east, north), m/s.
    pub fn velocity_of(&self, intruder: &IntruderEcef) -> Vector2<f64> {
        let v = self.frame.vector(&intruder.velocity_ecef);
        Vector2::new(v.x, v.y)
    }

    /// The relative state of an intruder.
    pub fn relative(&self, intruder: &IntruderEcef) -> Relative {
        let p = self.frame.position(&intruder.position_ecef);
        let v = self.frame.vector(&intruder.velocity_ecef);
        Relative {
            s: Vector2::new(p.x, p.y),
            v: Vector2::new(v.x - self.velocity_enu.x, v.y - self.velocity_enu.y),
            dz_m: intruder.alt_m - self.alt_m,
            vz_mps: intruder.vertical_rate_mps - self.velocity_enu.z,
            vz_spread_mps: 0.0,
            dz_spread_m: 0.0,
        }
    }
}

/// An intruder's position and velocity in ECEF, computed once per report.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IntruderEcef {
    /// Position, ECEF, m.
    pub position_ecef: Vector3<f64>,
    /// Horizontal velocity (over ground, in its own local plane), ECEF, m/s.
    pub velocity_ecef: Vector3<f64>,
    /// Altitude, m.
    pub alt_m: f64,
    /// Vertical rate, m/s, up.
    pub vertical_rate_mps: f64,
}

impl IntruderEcef {
    /// From the intruder's state: its velocity over ground is rotated from its own local north
    /// into ECEF (see [`wgs84`] on why).
    pub fn new(s: &AircraftState) -> Self {
        let (position_ecef, r) = geodetic_to_ecef(s.lat_deg, s.lon_deg, s.alt_m);
        let v_local = enu_velocity(s.track_deg, s.ground_speed_mps, 0.0);
        Self {
            position_ecef,
            velocity_ecef: r.transpose() * v_local,
            alt_m: s.alt_m,
            vertical_rate_mps: s.vertical_rate_mps,
        }
    }
}

/// The relative state of `intruder` in the ownship's tangent plane.
pub fn relative(own: &AircraftState, intruder: &AircraftState) -> Relative {
    OwnshipFrame::new(own).relative(&IntruderEcef::new(intruder))
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod boundary_tests;
