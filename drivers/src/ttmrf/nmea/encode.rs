//! Encoding sentences (for the simulator's GNSS and the round-trip tests). Angles are written
//! with 5 decimals of minutes (about 2 cm), times with 2 decimals of seconds, other values with
//! Rust's shortest round-trip formatting.

use std::fmt::Write as _;

use super::sentences::{Date, SecondsOfDay};
use super::{NmeaBody, NmeaSentence, checksum};

fn opt<T: std::fmt::Display>(s: &mut String, v: Option<T>) {
    s.push(',');
    if let Some(v) = v {
        let _ = write!(s, "{v}");
    }
}

fn time(s: &mut String, t: Option<SecondsOfDay>) {
    s.push(',');
    if let Some(t) = t {
        let centis = (t * 100.0).round() as u64;
        let (h, rem) = (centis / 360_000, centis % 360_000);
        let (m, c) = (rem / 6000, rem % 6000);
        let _ = write!(s, "{h:02}{m:02}{:02}.{:02}", c / 100, c % 100);
    }
}

fn angle(s: &mut String, v: Option<f64>, deg_digits: usize, pos: char, neg: char) {
    s.push(',');
    match v {
        Some(v) => {
            let a = v.abs();
            let mut deg = a.trunc();
            let mut min = ((a - deg) * 60.0 * 1e5).round() / 1e5;
            if min >= 60.0 {
                deg += 1.0;
                min -= 60.0;
            }
            let _ = write!(
                s,
                "{:0width$}{:08.5},{}",
                deg as u32,
                min,
                if v < 0.0 { neg } else { pos },
                width = deg_digits
            );
        }
        None => s.push(','),
    }
}

fn ddmmyy(s: &mut String, d: Option<Date>) {
    s.push(',');
    if let Some(d) = d {
        let _ = write!(s, "{:02}{:02}{:02}", d.day, d.month, d.year % 100);
    }
}

impl NmeaSentence {
    /// `$TTSSS,...*HH\r\n`.
    pub fn to_line(&self) -> String {
        let mut s = String::with_capacity(96);
        s.push_str(&self.talker);
        match &self.body {
            NmeaBody::Gga(g) => {
                s.push_str("GGA");
                time(&mut s, g.time_s);
                angle(&mut s, g.lat_deg, 2, 'N', 'S');
                angle(&mut s, g.lon_deg, 3, 'E', 'W');
                opt(&mut s, g.quality);
                opt(&mut s, g.satellites.map(|n| format!("{n:02}")));
                opt(&mut s, g.hdop);
                opt(&mut s, g.alt_msl_m);
                s.push_str(",M");
                opt(&mut s, g.geoid_sep_m);
                s.push_str(",M");
                opt(&mut s, g.dgps_age_s);
                opt(&mut s, g.dgps_station.map(|n| format!("{n:04}")));
            }
            NmeaBody::Rmc(r) => {
                s.push_str("RMC");
                time(&mut s, r.time_s);
                opt(&mut s, r.valid.map(|v| if v { 'A' } else { 'V' }));
                angle(&mut s, r.lat_deg, 2, 'N', 'S');
                angle(&mut s, r.lon_deg, 3, 'E', 'W');
                opt(&mut s, r.speed_kt);
                opt(&mut s, r.course_deg);
                ddmmyy(&mut s, r.date);
                opt(&mut s, r.mag_var_deg.map(f64::abs));
                opt(
                    &mut s,
                    r.mag_var_deg.map(|v| if v < 0.0 { 'W' } else { 'E' }),
                );
                opt(&mut s, r.mode);
            }
            NmeaBody::Vtg(v) => {
                s.push_str("VTG");
                opt(&mut s, v.course_true_deg);
                s.push_str(",T");
                opt(&mut s, v.course_mag_deg);
                s.push_str(",M");
                opt(&mut s, v.speed_kt);
                s.push_str(",N");
                opt(&mut s, v.speed_kmh);
                s.push_str(",K");
                opt(&mut s, v.mode);
            }
            NmeaBody::Gsa(g) => {
                s.push_str("GSA");
                opt(&mut s, g.selection);
                opt(&mut s, g.fix_type);
                for i in 0..12 {
                    opt(&mut s, g.prns.get(i).map(|p| format!("{p:02}")));
                }
                opt(&mut s, g.pdop);
                opt(&mut s, g.hdop);
                opt(&mut s, g.vdop);
                if let Some(id) = g.system_id {
                    opt(&mut s, Some(id));
                }
            }
            NmeaBody::Zda(z) => {
                s.push_str("ZDA");
                time(&mut s, z.time_s);
                opt(&mut s, z.date.map(|d| format!("{:02}", d.day)));
                opt(&mut s, z.date.map(|d| format!("{:02}", d.month)));
                opt(&mut s, z.date.map(|d| d.year));
                opt(&mut s, z.zone_hours.map(|h| format!("{h:02}")));
                opt(&mut s, z.zone_minutes.map(|m| format!("{m:02}")));
            }
        }
        let cs = checksum(s.as_bytes());
        format!("${s}*{cs:02X}\r\n")
    }
}
