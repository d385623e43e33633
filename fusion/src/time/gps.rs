//! GPS time, UTC and leap seconds.
//!
//! GPS time counts SI seconds from 1980-01-06 00:00:00 UTC with no leap seconds, so
//! GPS - UTC grows by one second at every leap second (18 s since 2017-01-01). vigil's timebase is
//! GPS time in nanoseconds since the GPS epoch (`t_gps_ns`, i64: +-292 years).
//!
//! The leap-second table carries its validity date: past it, a new leap second could have been
//! inserted without this table knowing, so [`gps_minus_utc_s`] reports the answer as stale and the
//! caller prefers the VN-200's own GPS-UTC offset (GnssTimeInfo) or widens its uncertainty.

/// Nanoseconds per second.
pub const NS_PER_S: i64 = 1_000_000_000;
/// Seconds per day.
pub const S_PER_DAY: i64 = 86_400;
/// The GPS epoch, 1980-01-06 00:00:00 UTC, in Unix seconds.
pub const GPS_EPOCH_UNIX_S: i64 = 315_964_800;

/// Leap-second table: (Unix time in s at which the offset takes effect, GPS - UTC in s from then).
/// Source: IERS Bulletin C (leap seconds since the GPS epoch).
const LEAP_TABLE: [(i64, i32); 18] = [
    (362_793_600, 1),    // 1981-07-01
    (394_329_600, 2),    // 1982-07-01
    (425_865_600, 3),    // 1983-07-01
    (489_024_000, 4),    // 1985-07-01
    (567_993_600, 5),    // 1988-01-01
    (631_152_000, 6),    // 1990-01-01
    (662_688_000, 7),    // 1991-01-01
    (709_948_800, 8),    // 1992-07-01
    (741_484_800, 9),    // 1993-07-01
    (773_020_800, 10),   // 1994-07-01
    (820_454_400, 11),   // 1996-01-01
    (867_715_200, 12),   // 1997-07-01
    (915_148_800, 13),   // 1999-01-01
    (1_136_073_600, 14), // 2006-01-01
    (1_230_768_000, 15), // 2009-01-01
    (1_341_100_800, 16), // 2012-07-01
    (1_435_708_800, 17), // 2015-07-01
    (1_483_228_800, 18), // 2017-01-01
];

/// The table is known to be complete for UTC instants before this Unix time: 2027-07-01 00:00:00
/// UTC. No leap second was announced through mid-2027 (IERS Bulletin C); the next possible
/// insertion after that is at the end of June 2027 at the earliest announced, so the table stops
/// vouching for times from 2027-07-01.
pub const LEAP_TABLE_VALID_UNTIL_UNIX_S: i64 = 1_814_400_000;

/// GPS - UTC at a UTC instant, and whether the table vouches for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LeapSeconds {
    /// GPS - UTC, s.
    pub gps_minus_utc_s: i32,
    /// False past [`LEAP_TABLE_VALID_UNTIL_UNIX_S`]: the value is the last known one and may be
    /// short by a leap second announced since.
    pub table_valid: bool,
}

/// GPS - UTC in seconds at Unix time `unix_s` (UTC).
pub fn gps_minus_utc_s(unix_s: i64) -> LeapSeconds {
    let n = LEAP_TABLE.iter().take_while(|(t, _)| *t <= unix_s).count();
    let gps_minus_utc_s = if n == 0 { 0 } else { LEAP_TABLE[n - 1].1 };
    LeapSeconds {
        gps_minus_utc_s,
        table_valid: unix_s < LEAP_TABLE_VALID_UNTIL_UNIX_S,
    }
}

/// GPS time (ns) of a UTC instant given as Unix time in ns, with the table's leap seconds.
pub fn gps_ns_from_unix_ns(unix_ns: i64) -> (i64, LeapSeconds) {
    let leap = gps_minus_utc_s(unix_ns.div_euclid(NS_PER_S));
    let t = unix_ns - GPS_EPOCH_UNIX_S * NS_PER_S + i64::from(leap.gps_minus_utc_s) * NS_PER_S;
    (t, leap)
}

/// Unix time (UTC, ns) of a GPS time, given GPS - UTC in seconds.
pub fn unix_ns_from_gps_ns(t_gps_ns: i64, gps_minus_utc_s: i32) -> i64 {
    t_gps_ns + GPS_EPOCH_UNIX_S * NS_PER_S - i64::from(gps_minus_utc_s) * NS_PER_S
}

/// GPS time (ns) from GPS week and time of week (s).
pub fn gps_ns_from_week_tow(week: u16, tow_s: f64) -> i64 {
    i64::from(week) * 7 * S_PER_DAY * NS_PER_S + (tow_s * 1e9).round() as i64
}

/// Days since 1970-01-01 of a proleptic Gregorian civil date (Howard Hinnant's algorithm,
/// re-derived: shift the year to start in March so the leap day is last).
pub fn days_from_civil(year: i32, month: u32, day: u32) -> i64 {
    let y = i64::from(year) - i64::from(month <= 2);
    let era = y.div_euclid(400);
    let yoe = y - era * 400;
    let m = i64::from(month);
    let doy = (153 * (if m > 2 { m - 3 } else { m + 9 }) + 2) / 5 + i64::from(day) - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// The civil date (year, month, day) of a count of days since 1970-01-01.
pub fn civil_from_days(days: i64) -> (i32, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let month = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let year = (yoe + era * 400 + i64::from(month <= 2)) as i32;
    (year, month, day)
}

/// Why a time of day could not be placed on the GPS timebase.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum TimeOfDayError {
    /// The time of day is not within one UTC day (a leap-second day has 86 401 s).
    #[error("time of day {0} ns is outside a UTC day")]
    OutOfRange(i64),
}

/// Places a UTC time of day (ns since UTC midnight, e.g. TT-Multi-RF `ts` x 1e6 or TS24h) on the
/// GPS timebase, choosing the day whose instant is nearest to `reference_gps_ns` (a full GPS time
/// known to within a few hours, e.g. from the VN-200). Around midnight this picks the right day on
/// either side: a 23:59:59.9 stamp received just after midnight belongs to the day before.
///
/// `gps_minus_utc_s` is the offset in force (from [`gps_minus_utc_s`] or the VN-200).
pub fn resolve_time_of_day(
    ns_since_utc_midnight: i64,
    reference_gps_ns: i64,
    gps_minus_utc_s: i32,
) -> Result<i64, TimeOfDayError> {
    if !(0..(S_PER_DAY + 1) * NS_PER_S).contains(&ns_since_utc_midnight) {
        return Err(TimeOfDayError::OutOfRange(ns_since_utc_midnight));
    }
    let ref_unix_ns = unix_ns_from_gps_ns(reference_gps_ns, gps_minus_utc_s);
    let day_ns = S_PER_DAY * NS_PER_S;
    let midnight = ref_unix_ns.div_euclid(day_ns) * day_ns;
    let candidates =
        [midnight - day_ns, midnight, midnight + day_ns].map(|m| m + ns_since_utc_midnight);
    // Of three candidates there is always a nearest; the fallback (the reference's own day) is
    // never taken, and is written without arithmetic so that it holds no mutant to survive.
    let best = candidates
        .into_iter()
        .min_by_key(|t| (t - ref_unix_ns).abs())
        .unwrap_or(candidates[1]);
    Ok(best - GPS_EPOCH_UNIX_S * NS_PER_S + i64::from(gps_minus_utc_s) * NS_PER_S)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn epoch_and_civil_dates_by_hand() {
        // 1980-01-06 is 3657 days after 1970-01-01: 10 years with 2 leap days (1972, 1976) is
        // 3652 days to 1980-01-01, plus 5.
        assert_eq!(days_from_civil(1980, 1, 6), 3657);
        assert_eq!(days_from_civil(1980, 1, 6) * S_PER_DAY, GPS_EPOCH_UNIX_S);
        assert_eq!(days_from_civil(1970, 1, 1), 0);
        assert_eq!(days_from_civil(2000, 3, 1), 11_017);
        assert_eq!(civil_from_days(11_017), (2000, 3, 1));
        assert_eq!(civil_from_days(days_from_civil(2024, 2, 29)), (2024, 2, 29));
        assert_eq!(civil_from_days(-1), (1969, 12, 31));
        for d in [-800_000, -1, 0, 59, 60, 10_000, 20_000, 2_000_000] {
            let (y, m, dd) = civil_from_days(d);
            assert_eq!(days_from_civil(y, m, dd), d);
        }
        // The table's dates are what the comments say.
        assert_eq!(LEAP_TABLE[17].0, days_from_civil(2017, 1, 1) * S_PER_DAY);
        assert_eq!(LEAP_TABLE[0].0, days_from_civil(1981, 7, 1) * S_PER_DAY);
        assert_eq!(
            LEAP_TABLE_VALID_UNTIL_UNIX_S,
            days_from_civil(2027, 7, 1) * S_PER_DAY
        );
    }

    #[test]
    fn leap_second_table_boundaries() {
        let t2017 = days_from_civil(2017, 1, 1) * S_PER_DAY;
        assert_eq!(gps_minus_utc_s(t2017 - 1).gps_minus_utc_s, 17);
        assert_eq!(gps_minus_utc_s(t2017).gps_minus_utc_s, 18);
        assert_eq!(gps_minus_utc_s(GPS_EPOCH_UNIX_S).gps_minus_utc_s, 0);
        let today = days_from_civil(2026, 11, 22) * S_PER_DAY;
        assert_eq!(
            gps_minus_utc_s(today),
            LeapSeconds {
                gps_minus_utc_s: 18,
                table_valid: true
            }
        );
        let later = days_from_civil(2027, 7, 1) * S_PER_DAY;
        assert!(gps_minus_utc_s(later - 1).table_valid);
        assert!(!gps_minus_utc_s(later).table_valid);
        assert_eq!(gps_minus_utc_s(later).gps_minus_utc_s, 18);
    }

    #[test]
    fn gps_week_by_hand() {
        // 2026-11-22 00:00:00 UTC is 17 122 days after 1980-01-06 (checked with a calendar):
        // 2446 whole weeks, and a Sunday like the GPS epoch, so the start of GPS week 2446 in UTC.
        let days = days_from_civil(2026, 11, 22) - days_from_civil(1980, 1, 6);
        assert_eq!(days, 17_122);
        assert_eq!(days / 7, 2446);
        assert_eq!(days % 7, 0); // a Sunday, like the GPS epoch
        let (t, _) = gps_ns_from_unix_ns(days_from_civil(2026, 11, 22) * S_PER_DAY * NS_PER_S);
        // GPS runs 18 s ahead of UTC.
        assert_eq!(t, gps_ns_from_week_tow(2446, 18.0));
        assert_eq!(
            unix_ns_from_gps_ns(t, 18),
            days_from_civil(2026, 11, 22) * S_PER_DAY * NS_PER_S
        );
    }

    #[test]
    fn time_of_day_rolls_over_midnight() {
        let day = days_from_civil(2026, 11, 22) * S_PER_DAY * NS_PER_S;
        let gps = |unix_ns: i64| gps_ns_from_unix_ns(unix_ns).0;
        // A stamp of 23:59:59.900 received (reference) at 00:00:00.200 the next day belongs to the
        // day before.
        let stamp = (S_PER_DAY * 1000 - 100) * 1_000_000;
        let reference = gps(day + 200_000_000);
        assert_eq!(
            resolve_time_of_day(stamp, reference, 18),
            Ok(gps(day - 100_000_000))
        );
        // A stamp of 00:00:00.050 with a reference still at 23:59:59.990 belongs to the next day.
        let reference = gps(day - 10_000_000);
        assert_eq!(
            resolve_time_of_day(50_000_000, reference, 18),
            Ok(gps(day + 50_000_000))
        );
        // Midday: the same day, whatever the reference's error of a few hours.
        let noon = 12 * 3600 * NS_PER_S;
        let reference = gps(day + noon + 3 * 3600 * NS_PER_S);
        assert_eq!(
            resolve_time_of_day(noon, reference, 18),
            Ok(gps(day + noon))
        );
        assert!(resolve_time_of_day(-1, reference, 18).is_err());
        assert!(resolve_time_of_day(86_401 * NS_PER_S, reference, 18).is_err());
    }

    #[test]
    fn civil_from_days_at_the_ends_of_a_400_year_era() {
        // 2000-01-01 is day 10 957 (30 years of 365 days + 7 leap days since 1970).
        assert_eq!(civil_from_days(0), (1970, 1, 1));
        assert_eq!(civil_from_days(10_957), (2000, 1, 1));
        // + 31 (January) + 28: 2000-02-29, the last day of the era that began 1600-03-01 (a
        // century year divisible by 400 is a leap year); the next is the era's first day.
        assert_eq!(civil_from_days(11_016), (2000, 2, 29));
        assert_eq!(civil_from_days(11_017), (2000, 3, 1));
        // 2100 is a century year not divisible by 400: no Feb 29. 2100-03-01 is 36 524 days
        // (100 years, 24 leap days) after 2000-03-01.
        assert_eq!(civil_from_days(11_017 + 36_524), (2100, 3, 1));
        assert_eq!(civil_from_days(11_017 + 36_523), (2100, 2, 28));
    }

    #[test]
    fn a_leap_second_stamp_is_within_the_day() {
        // 23:59:60.500 (86 400.5 s since midnight) exists on a leap-second day: placed, counted
        // on from that day's midnight with the offset given (the one in force before the leap).
        let day = days_from_civil(2026, 11, 22) * S_PER_DAY * NS_PER_S;
        let gps = |unix_ns: i64| gps_ns_from_unix_ns(unix_ns).0;
        let reference = gps(day - 10_000_000);
        assert_eq!(
            resolve_time_of_day(86_400_500_000_000, reference, 18),
            Ok(gps(day + 500_000_000))
        );
    }
}
