//! Physical constants, GPS time and the ISA standard atmosphere.
//!
//! - GPS time counts nanoseconds from 1980-01-06 00:00:00 UTC without leap seconds.
//!   Decision: one leap-second entry, GPS - UTC = 18 s, valid from 2017-01-01 (no new leap second
//!   is announced through mid-2027); earlier scenario start dates are rejected.
//! - ISA (ICAO Doc 7488, troposphere and the isothermal layer to 20 km geopotential): the
//!   pressure altitude is the ISA altitude whose pressure equals the static pressure.

use world_magnetic_model::time::{Date, Duration, Month};

/// Nanoseconds per second.
pub const NS_PER_S: i64 = 1_000_000_000;
/// GPS - UTC, s (valid from 2017-01-01).
pub const GPS_MINUS_UTC_S: i64 = 18;
/// Standard gravity, m/s^2 (also the flat-earth gravity of the simulated world).
pub const G0_MPS2: f64 = 9.80665;

/// ISA sea-level pressure, Pa.
pub const ISA_P0_PA: f64 = 101_325.0;
/// ISA sea-level temperature, K.
pub const ISA_T0_K: f64 = 288.15;
/// ISA temperature lapse rate in the troposphere, K/m.
pub const ISA_LAPSE_K_PER_M: f64 = 0.0065;
/// Specific gas constant of dry air, J/(kg K).
pub const R_AIR: f64 = 287.052_87;
/// Tropopause geopotential altitude, m.
pub const ISA_TROPOPAUSE_M: f64 = 11_000.0;
/// Earth radius used for geopotential altitude, m (ICAO).
pub const EARTH_RADIUS_GEOPOTENTIAL_M: f64 = 6_356_766.0;

/// Exponent g0 / (R L) of the tropospheric pressure law.
fn exponent() -> f64 {
    G0_MPS2 / (R_AIR * ISA_LAPSE_K_PER_M)
}

/// Geopotential altitude of a geometric altitude, m.
pub fn geopotential_m(geometric_m: f64) -> f64 {
    EARTH_RADIUS_GEOPOTENTIAL_M * geometric_m / (EARTH_RADIUS_GEOPOTENTIAL_M + geometric_m)
}

/// ISA pressure at a geopotential altitude for a sea-level pressure `p0_pa`, Pa.
pub fn isa_pressure_pa(geopotential_m: f64, p0_pa: f64) -> f64 {
    let h = geopotential_m.min(20_000.0);
    if h <= ISA_TROPOPAUSE_M {
        p0_pa * (1.0 - ISA_LAPSE_K_PER_M * h / ISA_T0_K).powf(exponent())
    } else {
        let t11 = ISA_T0_K - ISA_LAPSE_K_PER_M * ISA_TROPOPAUSE_M;
        let p11 = isa_pressure_pa(ISA_TROPOPAUSE_M, p0_pa);
        p11 * (-G0_MPS2 * (h - ISA_TROPOPAUSE_M) / (R_AIR * t11)).exp()
    }
}

/// Pressure altitude (standard datum 1013.25 hPa) of a static pressure, m.
pub fn pressure_altitude_m(p_pa: f64) -> f64 {
    let p11 = isa_pressure_pa(ISA_TROPOPAUSE_M, ISA_P0_PA);
    if p_pa >= p11 {
        ISA_T0_K / ISA_LAPSE_K_PER_M * (1.0 - (p_pa / ISA_P0_PA).powf(1.0 / exponent()))
    } else {
        let t11 = ISA_T0_K - ISA_LAPSE_K_PER_M * ISA_TROPOPAUSE_M;
        ISA_TROPOPAUSE_M - R_AIR * t11 / G0_MPS2 * (p_pa / p11).ln()
    }
}

/// Error of a start time.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum TimeError {
    /// Not of the form `YYYY-MM-DDTHH:MM:SSZ`.
    #[error("start_utc {0:?} is not of the form YYYY-MM-DDTHH:MM:SSZ")]
    Format(String),
    /// Before 2017-01-01, where the leap-second table does not hold.
    #[error(
        "start_utc {0:?} is before 2017-01-01, outside the leap-second table (gps - utc = 18 s)"
    )]
    BeforeLeapTable(String),
}

fn gps_epoch_date() -> Date {
    // 1980-01-06 is a valid date; the fallback is never taken.
    Date::from_calendar_date(1980, Month::January, 6).unwrap_or(Date::MIN)
}

/// Parses `YYYY-MM-DDTHH:MM:SSZ` (UTC) into GPS nanoseconds.
pub fn parse_utc_to_gps_ns(s: &str) -> Result<i64, TimeError> {
    let err = || TimeError::Format(s.to_string());
    let b = s.trim_end_matches('Z').as_bytes();
    if b.len() != 19
        || b[4] != b'-'
        || b[7] != b'-'
        || b[10] != b'T'
        || b[13] != b':'
        || b[16] != b':'
    {
        return Err(err());
    }
    let num = |r: std::ops::Range<usize>| -> Result<i64, TimeError> {
        std::str::from_utf8(&b[r])
            .ok()
            .and_then(|t| t.parse().ok())
            .ok_or_else(err)
    };
    let (y, mo, d) = (num(0..4)?, num(5..7)?, num(8..10)?);
    let (h, mi, sec) = (num(11..13)?, num(14..16)?, num(17..19)?);
    let month = Month::try_from(u8::try_from(mo).map_err(|_| err())?).map_err(|_| err())?;
    let date = Date::from_calendar_date(y as i32, month, u8::try_from(d).map_err(|_| err())?)
        .map_err(|_| err())?;
    if h > 23 || mi > 59 || sec > 59 {
        return Err(err());
    }
    if y < 2017 {
        return Err(TimeError::BeforeLeapTable(s.to_string()));
    }
    let days = (date - gps_epoch_date()).whole_days();
    let utc_s = days * 86_400 + h * 3600 + mi * 60 + sec;
    Ok((utc_s + GPS_MINUS_UTC_S) * NS_PER_S)
}

/// The UTC date of a GPS time (for the magnetic model, which takes a date).
pub fn gps_ns_to_utc_date(t_gps_ns: i64) -> Date {
    let utc_s = t_gps_ns.div_euclid(NS_PER_S) - GPS_MINUS_UTC_S;
    gps_epoch_date()
        .checked_add(Duration::days(utc_s.div_euclid(86_400)))
        .unwrap_or(Date::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isa_table_values() {
        // ICAO standard atmosphere table (geopotential altitude -> pressure):
        // 1000 m: 89 874.6 Pa, 5000 m: 54 019.9 Pa, 11 000 m: 22 632.1 Pa.
        for (h, p) in [
            (0.0, 101_325.0),
            (1000.0, 89_874.6),
            (5000.0, 54_019.9),
            (11_000.0, 22_632.1),
        ] {
            let got = isa_pressure_pa(h, ISA_P0_PA);
            assert!((got - p).abs() < 0.6, "h {h}: {got} vs {p}");
            // And back: the pressure altitude of the ISA pressure is the altitude itself.
            assert!((pressure_altitude_m(got) - h).abs() < 1e-6);
        }
        // Above the tropopause (isothermal, 216.65 K): 15 000 m: 12 044.6 Pa.
        assert!((isa_pressure_pa(15_000.0, ISA_P0_PA) - 12_044.6).abs() < 1.0);
        assert!((pressure_altitude_m(12_044.6) - 15_000.0).abs() < 1.0);
    }

    #[test]
    fn qnh_shifts_pressure_altitude_about_8_m_per_hpa() {
        // At sea level with QNH 1023.25 hPa the pressure altitude is
        // 44330.77 x (1 - (102325/101325)^(1/5.25588)) = -82.91 m (about 8.3 m per hPa).
        let p = isa_pressure_pa(0.0, 102_325.0);
        let pa = pressure_altitude_m(p);
        assert!((pa + 82.91).abs() < 0.02, "{pa}");
    }

    #[test]
    fn gps_time_of_a_date() {
        // 2026-01-01T00:00:00Z: 1980-01-01 .. 2026-01-01 is 46 x 365 days plus 12 leap days
        // (1980, 1984, ..., 2024) = 16 802 days; minus the 5 days to 1980-01-06: 16 797 days,
        // plus 18 leap seconds.
        let t = parse_utc_to_gps_ns("2026-01-01T00:00:00Z").unwrap();
        assert_eq!(t, (16_797 * 86_400 + 18) * NS_PER_S);
        assert_eq!(
            gps_ns_to_utc_date(t),
            Date::from_calendar_date(2026, Month::January, 1).unwrap()
        );
        // 17 s of GPS time after midnight UTC is still the previous UTC day.
        assert_eq!(
            gps_ns_to_utc_date(t - NS_PER_S),
            Date::from_calendar_date(2025, Month::December, 31).unwrap()
        );
        assert!(parse_utc_to_gps_ns("2016-12-31T23:59:59Z").is_err());
        assert!(parse_utc_to_gps_ns("2026-13-01T00:00:00Z").is_err());
    }
}
