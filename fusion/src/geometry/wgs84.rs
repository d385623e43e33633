//! WGS-84 geodesy for the local tangent plane: geodetic -> ECEF, and East-North-Up frames.
//!
//! Relative geometry is computed in an East-North-Up plane tangent to the WGS-84 ellipsoid at the
//! ownship. NASA DAIDALUS projects onto a sphere instead, so its distances differ from ours by up to
//! about 0.2 %; tests against DAIDALUS-style hand computations allow for that.
//!
//! An intruder's velocity is given over ground in its own local north; it is rotated through ECEF
//! into the ownship's frame, because the two norths differ (about half a degree at 65 deg N and
//! 15 NM east-west, enough to move a predicted miss distance by 150 m).

use nalgebra::{Matrix3, Vector3};

/// WGS-84 semi-major axis, m.
pub const A_M: f64 = 6_378_137.0;
/// WGS-84 flattening.
pub const F: f64 = 1.0 / 298.257_223_563;
/// First eccentricity squared.
pub const E2: f64 = F * (2.0 - F);

/// Earth-centred, earth-fixed position of a geodetic point (latitude and longitude in degrees,
/// height in m), with the sines and cosines it needed (reused for the ENU rotation).
pub fn geodetic_to_ecef(lat_deg: f64, lon_deg: f64, h_m: f64) -> (Vector3<f64>, Matrix3<f64>) {
    let (slat, clat) = lat_deg.to_radians().sin_cos();
    let (slon, clon) = lon_deg.to_radians().sin_cos();
    let n = A_M / (1.0 - E2 * slat * slat).sqrt();
    let p = Vector3::new(
        (n + h_m) * clat * clon,
        (n + h_m) * clat * slon,
        (n * (1.0 - E2) + h_m) * slat,
    );
    // Rows: east, north, up unit vectors in ECEF. ENU = R * ECEF.
    let r = Matrix3::new(
        -slon,
        clon,
        0.0,
        -slat * clon,
        -slat * slon,
        clat,
        clat * clon,
        clat * slon,
        slat,
    );
    (p, r)
}

/// An East-North-Up frame at a geodetic point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnuFrame {
    /// Origin in ECEF, m.
    pub origin_ecef: Vector3<f64>,
    /// Rotation from ECEF to ENU (rows: east, north, up).
    pub ecef_to_enu: Matrix3<f64>,
}

impl EnuFrame {
    /// The frame at a geodetic point (degrees, m).
    pub fn at(lat_deg: f64, lon_deg: f64, h_m: f64) -> Self {
        let (origin_ecef, ecef_to_enu) = geodetic_to_ecef(lat_deg, lon_deg, h_m);
        Self {
            origin_ecef,
            ecef_to_enu,
        }
    }

    /// ENU coordinates (m) of an ECEF position.
    pub fn position(&self, ecef: &Vector3<f64>) -> Vector3<f64> {
        self.ecef_to_enu * (ecef - self.origin_ecef)
    }

    /// ENU components of an ECEF vector (velocity).
    pub fn vector(&self, ecef: &Vector3<f64>) -> Vector3<f64> {
        self.ecef_to_enu * ecef
    }

    /// ECEF vector of ENU components in this frame.
    pub fn to_ecef_vector(&self, enu: &Vector3<f64>) -> Vector3<f64> {
        self.ecef_to_enu.transpose() * enu
    }
}

/// ENU velocity (m/s) from track over ground (deg true), ground speed (m/s) and vertical rate
/// (m/s, up).
pub fn enu_velocity(track_deg: f64, ground_speed_mps: f64, vertical_rate_mps: f64) -> Vector3<f64> {
    let (s, c) = track_deg.to_radians().sin_cos();
    Vector3::new(
        ground_speed_mps * s,
        ground_speed_mps * c,
        vertical_rate_mps,
    )
}

/// A position moved by a ground velocity (track over ground, deg true; ground speed, m/s) for
/// `dt_s` seconds, on the ellipsoid's local radii of curvature at the start (small steps: a
/// second or two of an aircraft's travel). Returns (lat, lon), deg. Used for the traffic
/// reports carried to a picture's time and for the ownship's GNSS fix carried to it.
pub fn dead_reckon(
    lat_deg: f64,
    lon_deg: f64,
    track_deg: f64,
    gs_mps: f64,
    dt_s: f64,
) -> (f64, f64) {
    let (s, c) = track_deg.to_radians().sin_cos();
    let (north, east) = (gs_mps * c * dt_s, gs_mps * s * dt_s);
    let lat = lat_deg.to_radians();
    let w = (1.0 - E2 * lat.sin().powi(2)).sqrt();
    let m = A_M * (1.0 - E2) / (w * w * w);
    let n = A_M / w;
    let dlat = north / m;
    let dlon = east / (n * lat.cos().max(1e-9));
    (lat_deg + dlat.to_degrees(), lon_deg + dlon.to_degrees())
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn ecef_by_hand() {
        // Equator, prime meridian: x = a.
        let (p, _) = geodetic_to_ecef(0.0, 0.0, 0.0);
        assert_relative_eq!(p, Vector3::new(A_M, 0.0, 0.0), epsilon = 1e-6);
        // North pole: z = b = a (1 - f) = 6 356 752.314 m.
        let (p, _) = geodetic_to_ecef(90.0, 0.0, 0.0);
        assert_relative_eq!(p.z, 6_356_752.314_245, epsilon = 1e-3);
        assert!(p.x.abs() < 1e-6);
    }

    #[test]
    fn one_minute_of_latitude_is_about_a_nautical_mile() {
        // At 45 deg the meridian radius of curvature M = a (1-e2) / (1 - e2 sin^2)^1.5
        // = 6 367 381.8 m, so 1' of latitude = M * pi / 10800 = 1852.25 m.
        let f = EnuFrame::at(45.0, 10.0, 0.0);
        let (q, _) = geodetic_to_ecef(45.0 + 1.0 / 60.0, 10.0, 0.0);
        let enu = f.position(&q);
        assert!((enu.y - 1852.25).abs() < 0.1, "{}", enu.y);
        assert!(enu.x.abs() < 1e-6);
    }

    #[test]
    fn norths_differ_at_high_latitude() {
        // 65 deg N, 15 NM apart east-west: the intruder's north is rotated relative to ours by
        // dlon * sin(lat) = (27 780 m / (N cos 65)) * sin 65 = 0.5 deg (meridian convergence).
        let own = EnuFrame::at(65.0, 0.0, 0.0);
        let n = A_M / (1.0 - E2 * 65f64.to_radians().sin().powi(2)).sqrt();
        let dlon_deg = (27_780.0 / (n * 65f64.to_radians().cos())).to_degrees();
        let int = EnuFrame::at(65.0, dlon_deg, 0.0);
        // Due north in the intruder's frame, seen in ours.
        let v = own.vector(&int.to_ecef_vector(&Vector3::new(0.0, 100.0, 0.0)));
        let seen_track = v.x.atan2(v.y).to_degrees();
        let expected = -(dlon_deg * 65f64.to_radians().sin());
        assert!(
            (seen_track - expected).abs() < 0.01,
            "{seen_track} vs {expected}"
        );
        assert!((seen_track.abs() - 0.5).abs() < 0.05);
    }

    /// Up is the ellipsoid normal: a point 100 m above the origin (same latitude and longitude,
    /// geodetic height + 100 m) is at (0, 0, 100) in the frame, wherever the frame is.
    #[test]
    fn up_is_the_ellipsoid_normal() {
        for (lat, lon) in [(47.1, 8.0), (-33.9, 151.2), (65.0, -20.0), (0.0, 0.0)] {
            let f = EnuFrame::at(lat, lon, 500.0);
            let (q, _) = geodetic_to_ecef(lat, lon, 600.0);
            let enu = f.position(&q);
            assert!(
                (enu - Vector3::new(0.0, 0.0, 100.0)).norm() < 1e-6,
                "{lat}, {lon}: {enu:?}"
            );
        }
    }
}
