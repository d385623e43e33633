//! `vigil/ownship`: the ownship state used for the traffic geometry.

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use super::{Header, impl_payload};
use crate::names::Topic;

/// Position source: none (no valid position).
pub const SOURCE_NONE: u8 = 0;
/// Position source: VN-200 INS in mode Tracking.
pub const SOURCE_VN200_INS: u8 = 1;
/// Position source: the TT-Multi-RF's own GNSS (fallback).
pub const SOURCE_TTMRF_GNSS: u8 = 2;
/// Position source: given directly (tests, replay of a truth file).
pub const SOURCE_EXTERNAL: u8 = 3;

/// The ownship at one GPS time (`header.gps_time_ns`).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Ownship.v2")]
pub struct OwnshipPayload {
    /// Common header; `gps_time_ns` is the time of the state.
    pub header: Header,
    /// Latitude, deg (WGS-84).
    pub lat_deg: f64,
    /// Longitude, deg (WGS-84).
    pub lon_deg: f64,
    /// Pressure altitude (1013.25 hPa datum), m; NaN when unknown.
    pub alt_pressure_m: f64,
    /// Geometric altitude above the WGS-84 ellipsoid, m; NaN when unknown.
    pub alt_geometric_m: f64,
    /// Velocity north, m/s.
    pub vel_north_mps: f64,
    /// Velocity east, m/s.
    pub vel_east_mps: f64,
    /// Velocity up, m/s (climb positive).
    pub vel_up_mps: f64,
    /// Ground speed, m/s.
    pub ground_speed_mps: f64,
    /// Track over ground, deg true.
    pub track_deg: f64,
    /// 1-sigma horizontal position uncertainty, m; NaN when unknown.
    pub sigma_horizontal_m: f64,
    /// 1-sigma vertical position uncertainty, m; NaN when unknown.
    pub sigma_vertical_m: f64,
    /// 1-sigma velocity uncertainty (per axis), m/s; NaN when unknown.
    pub sigma_velocity_mps: f64,
    /// `SOURCE_*` code of the position.
    pub source: u8,
    /// 1 when the state is usable for the traffic geometry, 0 otherwise.
    pub valid: u8,
    // --- issue 24 ---
    /// `FLAG_*` bits: which quantities are unknown (their fields are NaN).
    pub flags: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 5],
}

/// Ownship flag (issue 24): velocity unknown (no track or ground speed); `vel_north_mps`,
/// `vel_east_mps`, `ground_speed_mps` and `track_deg` are NaN, and every target of the same step
/// carries `traffic::FLAG_OWNSHIP_VELOCITY_UNKNOWN`.
pub const FLAG_VELOCITY_UNKNOWN: u8 = 1 << 0;
/// Ownship flag: vertical rate unknown; `vel_up_mps` is NaN.
pub const FLAG_VERTICAL_RATE_UNKNOWN: u8 = 1 << 1;
/// Ownship flag: geometric altitude made from mean-sea-level height without a geoid
/// separation; `sigma_vertical_m` includes the geoid's range.
pub const FLAG_GEOID_UNKNOWN: u8 = 1 << 2;

impl Default for OwnshipPayload {
    /// An invalid state: zeros, unknowns NaN, no source.
    fn default() -> Self {
        Self {
            header: Header::default(),
            lat_deg: 0.0,
            lon_deg: 0.0,
            alt_pressure_m: f64::NAN,
            alt_geometric_m: f64::NAN,
            vel_north_mps: 0.0,
            vel_east_mps: 0.0,
            vel_up_mps: 0.0,
            ground_speed_mps: 0.0,
            track_deg: 0.0,
            sigma_horizontal_m: f64::NAN,
            sigma_vertical_m: f64::NAN,
            sigma_velocity_mps: f64::NAN,
            source: SOURCE_NONE,
            valid: 0,
            flags: 0,
            reserved: [0; 5],
        }
    }
}

impl_payload!(OwnshipPayload, Topic::Ownship);
