//! Plausibility tests on incoming traffic reports. Each test only flags; nothing is dropped.

use crate::geometry::wgs84::{EnuFrame, geodetic_to_ecef};

/// Horizontal distance between two geodetic points (deg), m, in the tangent plane of the first.
/// Exact enough for the few-kilometre distances these tests compare.
pub fn horizontal_distance_m(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> f64 {
    let frame = EnuFrame::at(lat1, lon1, 0.0);
    let (p, _) = geodetic_to_ecef(lat2, lon2, 0.0);
    let enu = frame.position(&p);
    enu.x.hypot(enu.y)
}

/// Free-space path loss at 1090 MHz over `range_m`, dB: 20 log10(4 pi d f / c).
pub fn fspl_1090_db(range_m: f64) -> f64 {
    let f_hz = 1.09e9;
    let c = 299_792_458.0;
    20.0 * (4.0 * std::f64::consts::PI * range_m.max(1.0) * f_hz / c).log10()
}

/// Strongest signal a transmitter of `eirp_dbm` can give at `range_m` in free space, dBm.
pub fn max_signal_dbm(eirp_dbm: f64, range_m: f64) -> f64 {
    eirp_dbm - fspl_1090_db(range_m)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fspl_by_hand() {
        // 20 log10(4 pi / c) = -147.55 dB; 20 log10(1.09e9) = 180.75 dB; at 100 km (100 dB):
        // 100 + 180.75 - 147.55 = 133.2 dB.
        assert!(
            (fspl_1090_db(100_000.0) - 133.2).abs() < 0.01,
            "{}",
            fspl_1090_db(100_000.0)
        );
        // A 500 W (57 dBm) transponder 100 km away arrives at no more than -76.2 dBm.
        assert!((max_signal_dbm(57.0, 100_000.0) + 76.2).abs() < 0.01);
    }

    #[test]
    fn distance_by_hand() {
        // 0.01 deg of longitude at the equator: 0.01 x pi/180 x 6 378 137 = 1113.2 m.
        assert!((horizontal_distance_m(0.0, 0.0, 0.0, 0.01) - 1113.19).abs() < 0.01);
    }
}
