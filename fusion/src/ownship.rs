//! The ownship state the traffic picture is computed against (issue 8, "Ownship").
//!
//! [`Ownship`] is the input contract of the traffic fusion. [`OwnshipBuilder`] fills it:
//! position and velocity from the VN-200 INS while it is Tracking, else from the TT-Multi-RF's own
//! GNSS (JSON `gnss` section or NMEA GGA/RMC), each with its source and uncertainty; pressure
//! altitude from the BAHRS (for comparison with intruders' barometric altitude), geometric
//! altitude from the same source as the position; attitude and heading from the cross-check's
//! vote. The builder lives in [`builder`].

use serde::Serialize;

use crate::geometry::AircraftState;

pub mod builder;
pub use builder::{OwnshipBuilder, OwnshipParams, OwnshipSolution};

/// Where the ownship position came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PositionSource {
    /// VN-200 INS in mode Tracking.
    Vn200Ins,
    /// The TT-Multi-RF's own GNSS (fallback).
    TtMultiRfGnss,
    /// Given directly (tests, the geometry calculator).
    External,
}

/// The ownship at one GPS time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Ownship {
    /// GPS time of the state, ns.
    pub t_gps_ns: i64,
    /// Latitude, deg (WGS-84).
    pub lat_deg: f64,
    /// Longitude, deg.
    pub lon_deg: f64,
    /// Pressure altitude (1013.25 hPa datum), m, from the BAHRS; compared with intruder barometric
    /// altitude.
    pub alt_pressure_m: Option<f64>,
    /// Geometric altitude, m (above the WGS-84 ellipsoid); compared with intruder geometric
    /// altitude when the intruder has no barometric one.
    pub alt_geometric_m: Option<f64>,
    /// Track over ground, deg true.
    pub track_deg: f64,
    /// Ground speed, m/s.
    pub ground_speed_mps: f64,
    /// Vertical rate, m/s, up.
    pub vertical_rate_mps: f64,
    /// True heading, deg (for relative bearings).
    pub heading_deg: f64,
    /// 1-sigma horizontal position uncertainty, m.
    pub position_sigma_m: f64,
    /// Source of the position.
    pub source: PositionSource,
}

impl Ownship {
    /// The state for geometry with the given altitude, m.
    pub fn state(&self, alt_m: f64) -> AircraftState {
        AircraftState {
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_m,
            track_deg: self.track_deg,
            ground_speed_mps: self.ground_speed_mps,
            vertical_rate_mps: self.vertical_rate_mps,
        }
    }
}
