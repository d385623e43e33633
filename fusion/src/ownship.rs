//! The ownship state the traffic picture is computed against (issue 8, "Ownship").
//!
//! [`Ownship`] is the input contract of the traffic fusion. [`OwnshipBuilder`] fills it:
//! position and velocity from the VN-200 INS while it is Tracking, else from the TT-Multi-RF's own
//! GNSS (JSON `gnss` section or NMEA GGA/RMC), each with its source and uncertainty; pressure
//! altitude from the BAHRS (for comparison with intruders' barometric altitude), geometric
//! altitude from the same source as the position; attitude and heading from the cross-check's
//! vote. The builder lives in [`builder`].

use serde::Serialize;

use crate::geometry::{AircraftState, OwnshipFrame};

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
    /// Track over ground, deg true; `None` when the source gave none (a GNSS report without
    /// track or ground speed): the traffic geometry is then position-only (see
    /// [`crate::traffic::policy`]).
    pub track_deg: Option<f64>,
    /// Ground speed, m/s; `None` when unknown (as `track_deg`).
    pub ground_speed_mps: Option<f64>,
    /// Vertical rate, m/s, up; `None` when unknown.
    pub vertical_rate_mps: Option<f64>,
    /// True heading, deg (for relative bearings); `None` without a vote, a VN-200 attitude or a
    /// track.
    pub heading_deg: Option<f64>,
    /// 1-sigma horizontal position uncertainty, m; `None` when the source gave none.
    pub position_sigma_m: Option<f64>,
    /// Source of the position.
    pub source: PositionSource,
    // --- issue 24: altitude reference ---
    /// Half-width of the band the geometric altitude lies in beyond its noise, m: 0 normally;
    /// the geoid's worldwide range when the source gave mean-sea-level height without the geoid
    /// separation (see [`builder::GEOID_UNKNOWN_HALF_RANGE_M`]).
    pub alt_geometric_band_m: f64,
}

impl Ownship {
    /// The horizontal velocity over ground (east, north), m/s, when track and speed are known and
    /// finite.
    pub fn velocity_en_mps(&self) -> Option<[f64; 2]> {
        let (t, v) = (self.track_deg?, self.ground_speed_mps?);
        if !(t.is_finite() && v.is_finite()) {
            return None;
        }
        let (s, c) = t.to_radians().sin_cos();
        Some([v * s, v * c])
    }

    /// The state for geometry with the given altitude, m, when the velocity is known (an unknown
    /// vertical rate is 0 here; [`crate::traffic::policy`] widens the vertical test for it).
    pub fn state(&self, alt_m: f64) -> Option<AircraftState> {
        self.velocity_en_mps()?;
        Some(AircraftState {
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_m,
            track_deg: self.track_deg?,
            ground_speed_mps: self.ground_speed_mps?,
            vertical_rate_mps: self
                .vertical_rate_mps
                .filter(|v| v.is_finite())
                .unwrap_or(0.0),
        })
    }

    /// The ownship's tangent plane at the given altitude, m: with its velocity when known, else
    /// at its position alone.
    pub fn frame(&self, alt_m: f64) -> OwnshipFrame {
        match self.state(alt_m) {
            Some(s) => OwnshipFrame::new(&s),
            None => OwnshipFrame::at_position(self.lat_deg, self.lon_deg, alt_m),
        }
    }
}
