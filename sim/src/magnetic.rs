//! Magnetic declination behind a small trait, so the next World Magnetic Model (or a test field)
//! can be swapped in. The default is WMM2025 through the `world_magnetic_model` crate.
//!
//! Decision: that crate evaluates the model for a calendar date (no time of day); the secular
//! variation within one day is below 0.001 deg, so the truth uses the UTC date of the GPS time.

use world_magnetic_model::GeomagneticField;
use world_magnetic_model::uom::si::angle::{degree, radian};
use world_magnetic_model::uom::si::f32::{Angle, Length};
use world_magnetic_model::uom::si::length::meter;

use crate::units::gps_ns_to_utc_date;

/// Declination with its 1-sigma uncertainty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Declination {
    /// Declination, rad, east positive (true = magnetic + declination).
    pub declination_rad: f64,
    /// 1-sigma uncertainty of the model, rad.
    pub sigma_rad: f64,
}

/// Why a model could not be evaluated.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("magnetic model: {0}")]
pub struct MagneticError(pub String);

/// A model of the earth's magnetic field that gives the declination.
pub trait MagneticModel: Send + Sync {
    /// Declination at latitude/longitude (rad), height above the WGS-84 ellipsoid (m) and GPS time.
    fn declination(
        &self,
        lat_rad: f64,
        lon_rad: f64,
        height_m: f64,
        t_gps_ns: i64,
    ) -> Result<Declination, MagneticError>;
}

/// World Magnetic Model 2025 (valid 2025-2030; the crate also carries WMM2020 for earlier dates).
#[derive(Debug, Clone, Copy, Default)]
pub struct Wmm2025;

impl MagneticModel for Wmm2025 {
    fn declination(
        &self,
        lat_rad: f64,
        lon_rad: f64,
        height_m: f64,
        t_gps_ns: i64,
    ) -> Result<Declination, MagneticError> {
        let field = GeomagneticField::new(
            Length::new::<meter>(height_m as f32),
            Angle::new::<radian>(lat_rad as f32),
            Angle::new::<radian>(lon_rad as f32),
            gps_ns_to_utc_date(t_gps_ns),
        )
        .map_err(|e| MagneticError(e.to_string()))?;
        Ok(Declination {
            declination_rad: f64::from(field.declination().get::<degree>()).to_radians(),
            sigma_rad: f64::from(field.declination_uncertainty().get::<degree>()).to_radians(),
        })
    }
}

/// A uniform declination everywhere, for tests and synthetic worlds.
#[derive(Debug, Clone, Copy)]
pub struct ConstantDeclination(pub Declination);

impl MagneticModel for ConstantDeclination {
    fn declination(&self, _: f64, _: f64, _: f64, _: i64) -> Result<Declination, MagneticError> {
        Ok(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::units::parse_utc_to_gps_ns;

    #[test]
    fn wmm2025_at_the_crate_documented_point() {
        // The crate's documented example: 100 m, 37.03 N, 7.91 W, 2029-01-15: D = -0.17 +- 0.33 deg.
        let t = parse_utc_to_gps_ns("2029-01-15T12:00:00Z").unwrap();
        let d = Wmm2025
            .declination(37.03f64.to_radians(), (-7.91f64).to_radians(), 100.0, t)
            .unwrap();
        assert!(
            (d.declination_rad.to_degrees() + 0.17).abs() < 0.006,
            "{d:?}"
        );
        assert!((d.sigma_rad.to_degrees() - 0.33).abs() < 0.006, "{d:?}");
    }

    #[test]
    fn out_of_range_is_an_error() {
        assert!(Wmm2025.declination(0.0, 0.0, 1.0e7, 0).is_err());
    }
}
