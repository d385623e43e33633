//! WGS-84 geometry of the simulated world.
//!
//! Trajectories are computed in a local north/east plane centred on the scenario origin (the
//! ownship's start) and mapped to latitude/longitude with the meridian and prime-vertical radii of
//! curvature at the origin (an equirectangular projection). Decision: this keeps every truth
//! velocity the exact time derivative of the local-plane position; the mapping's distortion grows
//! as (distance / earth radius)^2, about 1e-4 at 60 km, so a fusion layer computing velocity from
//! successive latitudes with local radii sees errors of millimetres per second.

/// WGS-84 semi-major axis, m.
pub const WGS84_A_M: f64 = 6_378_137.0;
/// WGS-84 flattening.
pub const WGS84_F: f64 = 1.0 / 298.257_223_563;

/// The local tangent plane at the scenario origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocalFrame {
    /// Origin latitude, rad.
    pub lat0_rad: f64,
    /// Origin longitude, rad.
    pub lon0_rad: f64,
    /// Meridian radius of curvature at the origin, m.
    pub radius_north_m: f64,
    /// Prime-vertical radius of curvature times cos(latitude) at the origin, m.
    pub radius_east_m: f64,
}

impl LocalFrame {
    /// The frame at (`lat_deg`, `lon_deg`).
    pub fn new(lat_deg: f64, lon_deg: f64) -> Self {
        let lat = lat_deg.to_radians();
        let e2 = WGS84_F * (2.0 - WGS84_F);
        let s2 = lat.sin().powi(2);
        let n = WGS84_A_M / (1.0 - e2 * s2).sqrt();
        let m = WGS84_A_M * (1.0 - e2) / (1.0 - e2 * s2).powf(1.5);
        Self {
            lat0_rad: lat,
            lon0_rad: lon_deg.to_radians(),
            radius_north_m: m,
            radius_east_m: n * lat.cos(),
        }
    }

    /// Latitude and longitude (rad) of a local-plane point (m north, m east of the origin).
    pub fn to_geodetic_rad(&self, north_m: f64, east_m: f64) -> (f64, f64) {
        let lat = self.lat0_rad + north_m / self.radius_north_m;
        let mut lon = self.lon0_rad + east_m / self.radius_east_m;
        // Keep longitude in -pi .. pi.
        lon = (lon + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI;
        (lat, lon)
    }

    /// Local-plane point (m north, m east) of a latitude/longitude in degrees.
    pub fn to_local_m(&self, lat_deg: f64, lon_deg: f64) -> (f64, f64) {
        let dlon = (lon_deg.to_radians() - self.lon0_rad + std::f64::consts::PI)
            .rem_euclid(std::f64::consts::TAU)
            - std::f64::consts::PI;
        (
            (lat_deg.to_radians() - self.lat0_rad) * self.radius_north_m,
            dlon * self.radius_east_m,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_at_45_deg_by_hand() {
        // e^2 = 0.00669437999; at 45 deg, 1 - e^2/2 = 0.99665281;
        // N = 6378137 / sqrt(0.99665281) = 6388838.3 m; M = N (1 - e^2) / (1 - e^2/2) = 6367381.8 m.
        let f = LocalFrame::new(45.0, 10.0);
        assert!(
            (f.radius_north_m - 6_367_381.8).abs() < 0.5,
            "{}",
            f.radius_north_m
        );
        assert!((f.radius_east_m - 6_388_838.3 * 0.5f64.sqrt()).abs() < 0.5);
        let (n, e) = f.to_local_m(45.01, 10.02);
        let (lat, lon) = f.to_geodetic_rad(n, e);
        assert!(
            (lat.to_degrees() - 45.01).abs() < 1e-12 && (lon.to_degrees() - 10.02).abs() < 1e-12
        );
    }
}
