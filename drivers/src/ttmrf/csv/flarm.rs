//! `#ALRM`: FLARM aircraft (manual 8.2.1, tables 25 and 26).
//!
//! ```text
//! #ALRM:TYPE,ID,ID_TYPE,AIRCRAFT_TYPE,ALARM_LVL,LAT,LON,ALT,TRACK,VELH,VELV,MOVE_MODE,
//!       REL_N,REL_E,REL_DIST_H,REL_DIST_V,NEAR_DIST,DIR,STEALTH,NOTRACK\r\n
//! ```
//!
//! The manual documents this line without a CRC field, so it is parsed as documented: twenty
//! fields, none of them a CRC. Fields after NOTRACK (a later firmware may add some, or a CRC) are
//! kept verbatim in `extra_fields` and not interpreted.
//!
//! Altitude decision: table 25 says "Altitude, in meters", the JSON table 29 calls the same value
//! "Barometric altitude". The FLARM radio protocol carries GNSS altitude, and vigil compares
//! pressure altitudes with the BAHRS: passing a GNSS height off as pressure altitude would be the
//! worse error. So ALT goes to `alt_geometric_m` of the traffic report and is kept as `alt_m` here.

use serde::Serialize;

use super::CsvError;
use super::fields::{Fields, push_opt};
use crate::traffic::{AddressType, Link, Protocol, TrafficReport};
use crate::ttmrf::flarm_category;

/// Number of documented `#ALRM` fields.
pub const FLARM_FIELDS: usize = 20;

/// FLARM id type (ID_TYPE) to the common address type.
pub fn address_type(id_type: Option<u8>) -> AddressType {
    match id_type {
        Some(0) => AddressType::FlarmRandom,
        Some(1) => AddressType::Icao,
        Some(2) => AddressType::FlarmFixed,
        _ => AddressType::Unknown,
    }
}

/// `#ALRM`: one FLARM target, in the device's units (named).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct FlarmAircraft {
    /// TYPE: target type, 0 stationary, 2 regular aircraft.
    pub target_type: Option<u8>,
    /// ID: FLARM, ICAO or random id (printed as six upper-case hex digits).
    #[serde(serialize_with = "super::fields::ser_hex24")]
    pub id: u32,
    /// ID_TYPE: 0 randomised, 1 ICAO, 2 FLARM id.
    pub id_type: Option<u8>,
    /// AIRCRAFT_TYPE, table 26 (0..15).
    pub aircraft_type: Option<u8>,
    /// ALARM_LVL 0 (no danger) .. 3 (high danger).
    pub alarm_level: Option<u8>,
    /// Latitude, degrees (sent in 1e-7 degrees).
    pub lat_deg: Option<f64>,
    /// Longitude, degrees (sent in 1e-7 degrees).
    pub lon_deg: Option<f64>,
    /// Altitude, metres (see the module doc for which altitude).
    pub alt_m: Option<f64>,
    /// Track, degrees.
    pub track_deg: Option<f64>,
    /// Ground speed, m/s.
    pub velh_mps: Option<f64>,
    /// Climb rate, m/s, positive up.
    pub velv_mps: Option<f64>,
    /// MOVE_MODE: 1 stationary, 4 circling right, 5 cruising, 7 circling left.
    pub move_mode: Option<u8>,
    /// REL_N: distance to the target along south-north, m.
    pub rel_north_m: Option<f64>,
    /// REL_E: distance to the target along west-east, m.
    pub rel_east_m: Option<f64>,
    /// REL_DIST_H: horizontal distance, m.
    pub rel_dist_h_m: Option<f64>,
    /// REL_DIST_V: vertical separation, m, positive when the target is higher.
    pub rel_dist_v_m: Option<f64>,
    /// NEAR_DIST: proxy distance for priority sorting, m.
    pub near_dist_m: Option<f64>,
    /// DIR: relative bearing from own track to the target, degrees, -180..180, clockwise.
    pub dir_deg: Option<f64>,
    /// STEALTH (privacy) flag.
    pub stealth: Option<bool>,
    /// NOTRACK flag.
    pub notrack: Option<bool>,
    /// Fields after NOTRACK, kept verbatim.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_fields: Vec<String>,
}

impl FlarmAircraft {
    /// Parses the data fields of an `#ALRM` line.
    pub fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        if f.len() < FLARM_FIELDS {
            return Err(CsvError::FieldCount {
                tag: "ALRM",
                expected: FLARM_FIELDS,
                got: f.len(),
            });
        }
        let deg7 = |i: usize, name: &'static str, lim: f64| -> Result<Option<f64>, CsvError> {
            match f.i64(i, name)? {
                Some(v) => {
                    let d = v as f64 * 1e-7;
                    if d.abs() > lim {
                        Err(CsvError::field(name, f.raw(i)))
                    } else {
                        Ok(Some(d))
                    }
                }
                None => Ok(None),
            }
        };
        Ok(Self {
            target_type: f.uint(0, "TYPE")?,
            id: f.hex(1, "ID", 8)?.ok_or(CsvError::field("ID", ""))?,
            id_type: f.u8_max(2, "ID_TYPE", 2)?,
            aircraft_type: f.u8_max(3, "AIRCRAFT_TYPE", 15)?,
            alarm_level: f.u8_max(4, "ALARM_LVL", 3)?,
            lat_deg: deg7(5, "LAT", 90.0)?,
            lon_deg: deg7(6, "LON", 180.0)?,
            alt_m: f.f64(7, "ALT")?,
            track_deg: f.f64_in(8, "TRACK", 0.0, 360.0)?,
            velh_mps: f.f64(9, "VELH")?,
            velv_mps: f.f64(10, "VELV")?,
            move_mode: f.uint(11, "MOVE_MODE")?,
            rel_north_m: f.f64(12, "REL_N")?,
            rel_east_m: f.f64(13, "REL_E")?,
            rel_dist_h_m: f.f64(14, "REL_DIST_H")?,
            rel_dist_v_m: f.f64(15, "REL_DIST_V")?,
            near_dist_m: f.f64(16, "NEAR_DIST")?,
            dir_deg: f.f64_in(17, "DIR", -180.0, 180.0)?,
            stealth: f.flag(18, "STEALTH")?,
            notrack: f.flag(19, "NOTRACK")?,
            extra_fields: f.rest(FLARM_FIELDS),
        })
    }

    /// Appends the data fields (without tag; `#ALRM` has no CRC).
    pub fn write_fields(&self, line: &mut String) {
        use std::fmt::Write as _;
        if let Some(t) = self.target_type {
            let _ = write!(line, "{t}");
        }
        let _ = write!(line, ",{:06X}", self.id);
        push_opt(line, self.id_type);
        push_opt(line, self.aircraft_type);
        push_opt(line, self.alarm_level);
        push_opt(line, self.lat_deg.map(|v| (v * 1e7).round() as i64));
        push_opt(line, self.lon_deg.map(|v| (v * 1e7).round() as i64));
        push_opt(line, self.alt_m);
        push_opt(line, self.track_deg);
        push_opt(line, self.velh_mps);
        push_opt(line, self.velv_mps);
        push_opt(line, self.move_mode);
        push_opt(line, self.rel_north_m);
        push_opt(line, self.rel_east_m);
        push_opt(line, self.rel_dist_h_m);
        push_opt(line, self.rel_dist_v_m);
        push_opt(line, self.near_dist_m);
        push_opt(line, self.dir_deg);
        push_opt(line, self.stealth.map(u8::from));
        push_opt(line, self.notrack.map(u8::from));
        for x in &self.extra_fields {
            line.push(',');
            line.push_str(x);
        }
    }

    /// The common traffic report (FLARM link; emitter category through table 27).
    pub fn to_traffic(&self) -> TrafficReport {
        TrafficReport {
            emitter_category: self.aircraft_type.map(flarm_category::emitter_category),
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_geometric_m: self.alt_m,
            track_deg: self.track_deg,
            ground_speed_mps: self.velh_mps,
            vertical_rate_mps: self.velv_mps,
            flarm_alarm_level: self.alarm_level,
            ..TrafficReport::new(
                Link::Flarm,
                Protocol::Csv,
                self.id & 0xFF_FFFF,
                address_type(self.id_type),
            )
        }
    }
}
