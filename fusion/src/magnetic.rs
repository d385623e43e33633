//! Magnetic declination for the heading cross-check (issue 8, "Inputs and references"): the BAHRS
//! and the Watson report magnetic heading, the VN-200 true heading; `true = magnetic + D`, D
//! positive east.
//!
//! The model sits behind [`DeclinationModel`] so that the next WMM epoch (or another model) can be
//! swapped in. [`Wmm`] implements it with the `world_magnetic_model` crate (WMM2025, with its
//! location-dependent declination uncertainty). Near the magnetic poles the horizontal field is
//! weak and compasses unreliable: WMM's caution zone (H < 6000 nT) and blackout zone
//! (H < 2000 nT) are reported so the heading checks can be suppressed there.

use serde::Serialize;
use world_magnetic_model::time::{Date, Month};
use world_magnetic_model::uom::si::angle::{degree, radian};
use world_magnetic_model::uom::si::f32::{Angle, Length};
use world_magnetic_model::uom::si::length::meter;
use world_magnetic_model::uom::si::magnetic_flux_density::nanotesla;
use world_magnetic_model::{GeomagneticField, WarningZone};

use crate::time::gps;

/// Horizontal field below which WMM declares the caution zone, nT.
pub const CAUTION_ZONE_H_NT: f64 = 6000.0;
/// Horizontal field below which WMM declares the blackout zone, nT.
pub const BLACKOUT_ZONE_H_NT: f64 = 2000.0;

/// How trustworthy a compass is at a place.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MagneticZone {
    /// Horizontal field at least 6000 nT.
    Normal,
    /// 2000 nT <= H < 6000 nT: heading checks suppressed.
    Caution,
    /// H < 2000 nT: heading checks suppressed.
    Blackout,
}

impl MagneticZone {
    /// The zone of a horizontal field strength `h_nt`, nT.
    pub fn from_horizontal_nt(h_nt: f64) -> Self {
        if h_nt < BLACKOUT_ZONE_H_NT {
            Self::Blackout
        } else if h_nt < CAUTION_ZONE_H_NT {
            Self::Caution
        } else {
            Self::Normal
        }
    }

    /// Whether magnetic headings may take part in a comparison here.
    pub fn heading_usable(self) -> bool {
        self == Self::Normal
    }
}

/// Declination at one place and date.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Declination {
    /// Declination, rad, positive east (true = magnetic + declination).
    pub declination_rad: f64,
    /// 1-sigma uncertainty of the declination, rad.
    pub sigma_rad: f64,
    /// Horizontal field strength, nT.
    pub horizontal_nt: f64,
    /// Compass zone.
    pub zone: MagneticZone,
}

impl Declination {
    /// True heading from a magnetic one, rad, wrapped to [0, 2 pi).
    pub fn true_from_magnetic(&self, heading_mag_rad: f64) -> f64 {
        crate::attitude::angles::wrap_2pi(heading_mag_rad + self.declination_rad)
    }
}

/// Why no declination could be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MagneticError {
    /// The model rejected the input (date outside its epochs, height or position out of range).
    #[error("magnetic model rejected the query: {0}")]
    Model(String),
    /// The GPS time does not map to a calendar date.
    #[error("gps time {0} ns has no calendar date")]
    BadTime(i64),
}

/// A model of the geomagnetic declination.
pub trait DeclinationModel {
    /// Declination at latitude, longitude (deg, WGS-84), height above the ellipsoid (m) and GPS
    /// time (ns since 1980-01-06).
    fn declination(
        &self,
        lat_deg: f64,
        lon_deg: f64,
        height_m: f64,
        t_gps_ns: i64,
    ) -> Result<Declination, MagneticError>;
}

/// The World Magnetic Model (the epochs bundled in the `world_magnetic_model` crate: WMM2020 and
/// WMM2025, chosen by date).
#[derive(Debug, Clone, Copy, Default)]
pub struct Wmm;

/// The UTC calendar date of a GPS time (leap seconds from the table of `time::gps`).
pub fn date_of_gps_ns(t_gps_ns: i64) -> Result<Date, MagneticError> {
    // The leap-second offset is looked up at the GPS time taken as UTC: off by at most 18 s at a
    // leap second, irrelevant for a model that changes over months.
    let approx_unix_s = t_gps_ns
        .div_euclid(gps::NS_PER_S)
        .checked_add(gps::GPS_EPOCH_UNIX_S)
        .ok_or(MagneticError::BadTime(t_gps_ns))?;
    let leap = gps::gps_minus_utc_s(approx_unix_s);
    // Checked: the GPS time is input-derived (same formula as `gps::unix_ns_from_gps_ns`).
    let unix_s = (approx_unix_s).checked_sub(i64::from(leap.gps_minus_utc_s));
    let days = unix_s
        .map(|s| s.div_euclid(gps::S_PER_DAY))
        .ok_or(MagneticError::BadTime(t_gps_ns))?;
    let (y, m, d) = gps::civil_from_days(days);
    let month = u8::try_from(m)
        .ok()
        .and_then(|m| Month::try_from(m).ok())
        .ok_or(MagneticError::BadTime(t_gps_ns))?;
    let day = u8::try_from(d).map_err(|_| MagneticError::BadTime(t_gps_ns))?;
    Date::from_calendar_date(y, month, day).map_err(|_| MagneticError::BadTime(t_gps_ns))
}

impl DeclinationModel for Wmm {
    fn declination(
        &self,
        lat_deg: f64,
        lon_deg: f64,
        height_m: f64,
        t_gps_ns: i64,
    ) -> Result<Declination, MagneticError> {
        let date = date_of_gps_ns(t_gps_ns)?;
        let field = GeomagneticField::new(
            Length::new::<meter>(height_m as f32),
            Angle::new::<degree>(lat_deg as f32),
            Angle::new::<degree>(lon_deg as f32),
            date,
        )
        .map_err(|e| MagneticError::Model(e.to_string()))?;
        let horizontal_nt = f64::from(field.h().get::<nanotesla>());
        // The crate's own zone test and ours (from H) agree by construction; take the crate's and
        // keep H for the record.
        let zone = match field.declination_warning() {
            Some(WarningZone::BlackoutZone) => MagneticZone::Blackout,
            Some(WarningZone::CautionZone) => MagneticZone::Caution,
            None => MagneticZone::Normal,
        };
        Ok(Declination {
            declination_rad: f64::from(field.declination().get::<radian>()),
            sigma_rad: f64::from(field.declination_uncertainty().get::<radian>()),
            horizontal_nt,
            zone,
        })
    }
}

/// A fixed declination (tests, or a configured local value).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixedDeclination(pub Declination);

impl DeclinationModel for FixedDeclination {
    fn declination(&self, _: f64, _: f64, _: f64, _: i64) -> Result<Declination, MagneticError> {
        Ok(self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEG: f64 = std::f64::consts::PI / 180.0;

    /// GPS ns at a UTC calendar date, 12:00 (leap seconds 18 since 2017).
    fn gps_noon(y: i32, m: u32, d: u32) -> i64 {
        let unix_s = gps::days_from_civil(y, m, d) * 86_400 + 43_200;
        (unix_s - gps::GPS_EPOCH_UNIX_S + 18) * gps::NS_PER_S
    }

    #[test]
    fn date_of_gps_time() {
        let d = date_of_gps_ns(gps_noon(2026, 6, 1)).unwrap();
        assert_eq!((d.year(), d.month() as u8, d.day()), (2026, 6, 1));
        // 00:00:10 UTC on 1 Jan 2026 is 00:00:28 GPS: still 1 Jan, not 31 Dec.
        let t = (gps::days_from_civil(2026, 1, 1) * 86_400 + 10 - gps::GPS_EPOCH_UNIX_S + 18)
            * gps::NS_PER_S;
        let d = date_of_gps_ns(t).unwrap();
        assert_eq!((d.year(), d.month() as u8, d.day()), (2026, 1, 1));
    }

    #[test]
    fn wmm_matches_the_crate_documentation_example() {
        // The crate README: 100 m, 37.03 N, 7.91 W, day 15 of 2029: D = -0.17 +- 0.33 deg.
        let t = gps_noon(2029, 1, 15);
        let d = Wmm.declination(37.03, -7.91, 100.0, t).unwrap();
        assert!(
            (d.declination_rad / DEG + 0.17).abs() < 0.006,
            "{}",
            d.declination_rad / DEG
        );
        assert!((d.sigma_rad / DEG - 0.33).abs() < 0.006);
        assert_eq!(d.zone, MagneticZone::Normal);
    }

    #[test]
    fn zurich_declination_is_small_and_east() {
        // Central Europe in 2026: WMM2025 gives about +3.5 deg (east), sigma ~ 0.3-0.4 deg.
        let d = Wmm
            .declination(47.40, 8.50, 600.0, gps_noon(2026, 6, 1))
            .unwrap();
        let deg = d.declination_rad / DEG;
        assert!((2.5..4.5).contains(&deg), "{deg}");
        assert!(d.horizontal_nt > 15_000.0);
    }

    #[test]
    fn near_the_north_magnetic_pole_the_heading_is_blacked_out() {
        // The north magnetic pole is near 85.8 N 139 E in 2026 (WMM2025): H far below 2000 nT.
        let d = Wmm
            .declination(85.8, 139.0, 0.0, gps_noon(2026, 1, 1))
            .unwrap();
        assert_eq!(d.zone, MagneticZone::Blackout, "H = {}", d.horizontal_nt);
        assert!(!d.zone.heading_usable());
        assert!(d.sigma_rad > 5.0 * DEG);
    }

    #[test]
    fn zones_from_horizontal_field() {
        assert_eq!(
            MagneticZone::from_horizontal_nt(1999.9),
            MagneticZone::Blackout
        );
        assert_eq!(
            MagneticZone::from_horizontal_nt(2000.0),
            MagneticZone::Caution
        );
        assert_eq!(
            MagneticZone::from_horizontal_nt(5999.0),
            MagneticZone::Caution
        );
        assert_eq!(
            MagneticZone::from_horizontal_nt(6000.0),
            MagneticZone::Normal
        );
    }

    #[test]
    fn declination_application_by_hand() {
        // Magnetic 358 deg with D = +3.5 deg (east) is true 1.5 deg (wraps through north);
        // magnetic 10 deg with D = -12 deg (west) is true 358 deg.
        let d = Declination {
            declination_rad: 3.5 * DEG,
            sigma_rad: 0.0,
            horizontal_nt: 20_000.0,
            zone: MagneticZone::Normal,
        };
        assert!((d.true_from_magnetic(358.0 * DEG) - 1.5 * DEG).abs() < 1e-12);
        let d = Declination {
            declination_rad: -12.0 * DEG,
            ..d
        };
        assert!((d.true_from_magnetic(10.0 * DEG) - 358.0 * DEG).abs() < 1e-12);
    }

    #[test]
    fn out_of_range_inputs_are_errors_not_panics() {
        assert!(
            Wmm.declination(95.0, 0.0, 0.0, gps_noon(2026, 1, 1))
                .is_err()
        );
        assert!(
            Wmm.declination(45.0, 0.0, 1e7, gps_noon(2026, 1, 1))
                .is_err()
        );
        assert!(
            Wmm.declination(45.0, 0.0, 0.0, gps_noon(2040, 1, 1))
                .is_err()
        );
        assert!(
            Wmm.declination(f64::NAN, 0.0, 0.0, gps_noon(2026, 1, 1))
                .is_err()
        );
        // Extreme times: no panic; i64::MAX ns is in 2272, outside every bundled epoch.
        assert!(Wmm.declination(45.0, 0.0, 0.0, i64::MAX).is_err());
        assert!(Wmm.declination(45.0, 0.0, 0.0, i64::MIN).is_err());
    }
}
