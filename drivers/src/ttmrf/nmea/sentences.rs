//! The NMEA 0183 sentences vigil uses from the module's GNSS (manual 9.2.1 refers to the
//! receiver's own documentation): GGA, RMC, VTG, GSA, ZDA. Empty fields are unknown (`None`).

use serde::Serialize;

use super::NmeaError;

/// UTC time of day, seconds since midnight (fractional).
pub type SecondsOfDay = f64;

/// GGA: fix data.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Gga {
    /// UTC time of the fix, s since midnight.
    pub time_s: Option<SecondsOfDay>,
    /// Latitude, degrees north.
    pub lat_deg: Option<f64>,
    /// Longitude, degrees east.
    pub lon_deg: Option<f64>,
    /// Fix quality: 0 invalid, 1 GPS, 2 DGPS, 4 RTK fixed, 5 RTK float, 6 dead reckoning.
    pub quality: Option<u8>,
    /// Satellites used.
    pub satellites: Option<u8>,
    /// Horizontal dilution of precision.
    pub hdop: Option<f64>,
    /// Altitude above mean sea level, m.
    pub alt_msl_m: Option<f64>,
    /// Geoid separation (WGS-84 ellipsoid minus MSL), m.
    pub geoid_sep_m: Option<f64>,
    /// Age of differential corrections, s.
    pub dgps_age_s: Option<f64>,
    /// Differential reference station id.
    pub dgps_station: Option<u16>,
}

impl Gga {
    /// Height above the WGS-84 ellipsoid, m (MSL altitude plus geoid separation).
    pub fn alt_wgs84_m(&self) -> Option<f64> {
        Some(self.alt_msl_m? + self.geoid_sep_m?)
    }
}

/// A calendar date (UTC).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Date {
    /// Year, four digits.
    pub year: u16,
    /// Month 1..12.
    pub month: u8,
    /// Day 1..31.
    pub day: u8,
}

/// RMC: recommended minimum data.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Rmc {
    /// UTC time, s since midnight.
    pub time_s: Option<SecondsOfDay>,
    /// Status A (valid) = true, V (warning) = false.
    pub valid: Option<bool>,
    /// Latitude, degrees north.
    pub lat_deg: Option<f64>,
    /// Longitude, degrees east.
    pub lon_deg: Option<f64>,
    /// Speed over ground, knots.
    pub speed_kt: Option<f64>,
    /// Course over ground, degrees true.
    pub course_deg: Option<f64>,
    /// UTC date (two-digit year: 80..99 -> 19xx, 00..79 -> 20xx).
    pub date: Option<Date>,
    /// Magnetic variation, degrees, east positive.
    pub mag_var_deg: Option<f64>,
    /// Mode indicator (NMEA 2.3+): A autonomous, D differential, E estimated, N not valid ...
    pub mode: Option<char>,
}

/// VTG: course and speed over ground.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Vtg {
    /// Course over ground, degrees true.
    pub course_true_deg: Option<f64>,
    /// Course over ground, degrees magnetic.
    pub course_mag_deg: Option<f64>,
    /// Speed, knots.
    pub speed_kt: Option<f64>,
    /// Speed, km/h.
    pub speed_kmh: Option<f64>,
    /// Mode indicator.
    pub mode: Option<char>,
}

/// GSA: DOP and active satellites.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Gsa {
    /// Selection mode: M manual, A automatic.
    pub selection: Option<char>,
    /// Fix type: 1 none, 2 2D, 3 3D.
    pub fix_type: Option<u8>,
    /// PRNs of the satellites used (up to 12).
    pub prns: Vec<u16>,
    /// Position dilution of precision.
    pub pdop: Option<f64>,
    /// Horizontal dilution of precision.
    pub hdop: Option<f64>,
    /// Vertical dilution of precision.
    pub vdop: Option<f64>,
    /// GNSS system id (NMEA 4.1+).
    pub system_id: Option<u8>,
}

/// ZDA: UTC date and time.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Zda {
    /// UTC time, s since midnight.
    pub time_s: Option<SecondsOfDay>,
    /// UTC date.
    pub date: Option<Date>,
    /// Local zone hours.
    pub zone_hours: Option<i8>,
    /// Local zone minutes.
    pub zone_minutes: Option<u8>,
}

/// Field access with "empty = unknown".
pub(super) struct F<'a>(pub &'a [&'a str]);

impl F<'_> {
    fn get(&self, i: usize) -> &str {
        self.0.get(i).copied().unwrap_or("")
    }

    fn opt<T: std::str::FromStr>(
        &self,
        i: usize,
        name: &'static str,
    ) -> Result<Option<T>, NmeaError> {
        let s = self.get(i);
        if s.is_empty() {
            return Ok(None);
        }
        s.parse().map(Some).map_err(|_| NmeaError::Field(name))
    }

    fn f64(&self, i: usize, name: &'static str) -> Result<Option<f64>, NmeaError> {
        match self.opt::<f64>(i, name)? {
            Some(v) if !v.is_finite() => Err(NmeaError::Field(name)),
            v => Ok(v),
        }
    }

    fn char(&self, i: usize, name: &'static str) -> Result<Option<char>, NmeaError> {
        let s = self.get(i);
        let mut it = s.chars();
        match (it.next(), it.next()) {
            (None, _) => Ok(None),
            (Some(c), None) => Ok(Some(c)),
            _ => Err(NmeaError::Field(name)),
        }
    }

    /// `hhmmss[.ss]`.
    fn time(&self, i: usize) -> Result<Option<SecondsOfDay>, NmeaError> {
        let s = self.get(i);
        if s.is_empty() {
            return Ok(None);
        }
        let err = NmeaError::Field("time");
        if s.len() < 6 || !s.as_bytes()[..6].iter().all(u8::is_ascii_digit) {
            return Err(err);
        }
        let h: u32 = s[0..2].parse().map_err(|_| err.clone())?;
        let m: u32 = s[2..4].parse().map_err(|_| err.clone())?;
        let sec: f64 = s[4..].parse().map_err(|_| err.clone())?;
        // 60 s is a leap second.
        if h > 23 || m > 59 || !(0.0..61.0).contains(&sec) {
            return Err(err);
        }
        Ok(Some(f64::from(h * 3600 + m * 60) + sec))
    }

    /// `ddmm.mmmm,N` / `dddmm.mmmm,E`.
    fn angle(
        &self,
        i: usize,
        deg_digits: usize,
        name: &'static str,
    ) -> Result<Option<f64>, NmeaError> {
        let (s, hemi) = (self.get(i), self.get(i + 1));
        if s.is_empty() && hemi.is_empty() {
            return Ok(None);
        }
        let err = NmeaError::Field(name);
        if s.len() < deg_digits + 2 || !s.is_char_boundary(deg_digits) {
            return Err(err);
        }
        let deg: f64 = s[..deg_digits].parse().map_err(|_| err.clone())?;
        let min: f64 = s[deg_digits..].parse().map_err(|_| err.clone())?;
        if !(0.0..60.0).contains(&min) || s.starts_with(['-', '+']) {
            return Err(err);
        }
        let v = deg + min / 60.0;
        let (lim, neg) = match (deg_digits, hemi) {
            (2, "N") => (90.0, false),
            (2, "S") => (90.0, true),
            (3, "E") => (180.0, false),
            (3, "W") => (180.0, true),
            _ => return Err(err),
        };
        if v > lim {
            return Err(err);
        }
        Ok(Some(if neg { -v } else { v }))
    }

    /// `ddmmyy` (RMC).
    fn date_ddmmyy(&self, i: usize) -> Result<Option<Date>, NmeaError> {
        let s = self.get(i);
        if s.is_empty() {
            return Ok(None);
        }
        let err = NmeaError::Field("date");
        if s.len() != 6 || !s.bytes().all(|b| b.is_ascii_digit()) {
            return Err(err);
        }
        let d: u8 = s[0..2].parse().map_err(|_| err.clone())?;
        let m: u8 = s[2..4].parse().map_err(|_| err.clone())?;
        let y: u16 = s[4..6].parse().map_err(|_| err.clone())?;
        // Two-digit year: GNSS dates start in 1980, so 80..99 are 19xx and 00..79 are 20xx
        // (valid until 2079).
        let year = if y >= 80 { 1900 + y } else { 2000 + y };
        date(year, m, d).map(Some).ok_or(err)
    }
}

fn date(year: u16, month: u8, day: u8) -> Option<Date> {
    ((1..=12).contains(&month) && (1..=31).contains(&day)).then_some(Date { year, month, day })
}

impl Gga {
    pub(super) fn parse(f: &F<'_>) -> Result<Self, NmeaError> {
        Ok(Self {
            time_s: f.time(0)?,
            lat_deg: f.angle(1, 2, "lat")?,
            lon_deg: f.angle(3, 3, "lon")?,
            quality: f.opt(5, "quality")?,
            satellites: f.opt(6, "satellites")?,
            hdop: f.f64(7, "hdop")?,
            alt_msl_m: f.f64(8, "altitude")?,
            geoid_sep_m: f.f64(10, "geoid separation")?,
            dgps_age_s: f.f64(12, "dgps age")?,
            dgps_station: f.opt(13, "dgps station")?,
        })
    }
}

impl Rmc {
    pub(super) fn parse(f: &F<'_>) -> Result<Self, NmeaError> {
        let valid = match f.get(1) {
            "" => None,
            "A" => Some(true),
            "V" => Some(false),
            _ => return Err(NmeaError::Field("status")),
        };
        let mag_var_deg = match (f.f64(9, "magnetic variation")?, f.get(10)) {
            (None, _) => None,
            (Some(v), "E") => Some(v),
            (Some(v), "W") => Some(-v),
            _ => return Err(NmeaError::Field("magnetic variation")),
        };
        Ok(Self {
            time_s: f.time(0)?,
            valid,
            lat_deg: f.angle(2, 2, "lat")?,
            lon_deg: f.angle(4, 3, "lon")?,
            speed_kt: f.f64(6, "speed")?,
            course_deg: f.f64(7, "course")?,
            date: f.date_ddmmyy(8)?,
            mag_var_deg,
            mode: f.char(11, "mode")?,
        })
    }
}

impl Vtg {
    pub(super) fn parse(f: &F<'_>) -> Result<Self, NmeaError> {
        Ok(Self {
            course_true_deg: f.f64(0, "course true")?,
            course_mag_deg: f.f64(2, "course magnetic")?,
            speed_kt: f.f64(4, "speed kt")?,
            speed_kmh: f.f64(6, "speed km/h")?,
            mode: f.char(8, "mode")?,
        })
    }
}

impl Gsa {
    pub(super) fn parse(f: &F<'_>) -> Result<Self, NmeaError> {
        let mut prns = Vec::new();
        for i in 2..14 {
            if let Some(p) = f.opt::<u16>(i, "prn")? {
                prns.push(p);
            }
        }
        Ok(Self {
            selection: f.char(0, "selection")?,
            fix_type: f.opt(1, "fix type")?,
            prns,
            pdop: f.f64(14, "pdop")?,
            hdop: f.f64(15, "hdop")?,
            vdop: f.f64(16, "vdop")?,
            system_id: f.opt(17, "system id")?,
        })
    }
}

impl Zda {
    pub(super) fn parse(f: &F<'_>) -> Result<Self, NmeaError> {
        let day: Option<u8> = f.opt(1, "day")?;
        let month: Option<u8> = f.opt(2, "month")?;
        let year: Option<u16> = f.opt(3, "year")?;
        let date = match (year, month, day) {
            (Some(y), Some(m), Some(d)) => Some(date(y, m, d).ok_or(NmeaError::Field("date"))?),
            (None, None, None) => None,
            _ => return Err(NmeaError::Field("date")),
        };
        Ok(Self {
            time_s: f.time(0)?,
            date,
            zone_hours: f.opt(4, "zone hours")?,
            zone_minutes: f.opt(5, "zone minutes")?,
        })
    }
}
