//! The sections of a TT-Multi-RF JSON message: `status` (manual 6.6.1), `adsb` (7.2.1, table 19),
//! `raw` (7.2.2, table 23), `flarm` (8.2.1, table 29), `gnss` (9.2.2, table 32), `uat` (10.2.1,
//! table 40 and the example above it).
//!
//! Field names on the wire follow the manual's examples; where an example and its table spell a
//! name differently (`hvelo` / `hVelo`, `nacv` / `nacV`, `altGeo` / `geoAlt`), both are accepted.
//! Every field is optional ("omitted if unknown"), unknown fields are ignored, and serialisation
//! uses vigil's names with units (`alt_baro_ft`, `velh_kt`).

use serde::{Deserialize, Deserializer, Serialize};

use crate::ttmrf::csv::fields::{parse_hex, parse_squawk, ser_hex24};

/// `status` section.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Status {
    /// Firmware version, same syntax as `AT+FIRMWARE_VERSION`.
    #[serde(default)]
    pub fw: Option<String>,
}

/// `flags` object of `adsb` and `uat` entries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct TargetFlags {
    /// On the ground.
    #[serde(rename(deserialize = "groundState"))]
    pub on_ground: Option<bool>,
    /// Barometric altitude updated during the last second.
    #[serde(rename(deserialize = "updAltBaro"))]
    pub upd_alt_baro: Option<bool>,
    /// Geometric altitude updated.
    #[serde(rename(deserialize = "updAltGeo"))]
    pub upd_alt_geo: Option<bool>,
    /// Position updated.
    #[serde(rename(deserialize = "updPosition"))]
    pub upd_position: Option<bool>,
    /// Track updated.
    #[serde(rename(deserialize = "updTrack"))]
    pub upd_track: Option<bool>,
    /// Horizontal velocity updated.
    #[serde(rename(deserialize = "updVeloH"))]
    pub upd_velo_h: Option<bool>,
    /// Vertical velocity updated.
    #[serde(rename(deserialize = "updVeloV"))]
    pub upd_velo_v: Option<bool>,
}

/// `nav_modes` object of an `adsb` entry (autopilot modes from DO-260B target state).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct NavModes {
    /// Altitude hold.
    pub althold: Option<bool>,
    /// Approach mode.
    pub approach: Option<bool>,
    /// Autopilot engaged.
    pub autopilot: Option<bool>,
    /// LNAV engaged.
    pub lnav: Option<bool>,
    /// TCAS/ACAS operational.
    pub tcas: Option<bool>,
    /// VNAV engaged.
    pub vnav: Option<bool>,
}

/// One entry of the `adsb` array (table 19).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct AdsbTarget {
    /// ICAO address (six hex digits on the wire).
    #[serde(serialize_with = "ser_hex24", deserialize_with = "de_hex24")]
    pub icao: u32,
    /// Flags.
    pub flags: Option<TargetFlags>,
    /// Signal strength, dBm.
    #[serde(rename(deserialize = "sigStr"))]
    pub sig_dbm: Option<f64>,
    /// Signal quality, dB.
    #[serde(rename(deserialize = "sigQ"))]
    pub sig_q_db: Option<f64>,
    /// Raw frames from this aircraft in the last second.
    pub fps: Option<u32>,
    /// Latitude, degrees.
    #[serde(rename(deserialize = "lat"))]
    pub lat_deg: Option<f64>,
    /// Longitude, degrees.
    #[serde(rename(deserialize = "lon"))]
    pub lon_deg: Option<f64>,
    /// Barometric altitude, ft.
    #[serde(rename(deserialize = "altBaro"))]
    pub alt_baro_ft: Option<f64>,
    /// Geometric altitude, ft.
    #[serde(rename(deserialize = "geoAlt"), alias = "altGeo")]
    pub alt_geo_ft: Option<f64>,
    /// Track, degrees.
    #[serde(rename(deserialize = "track"))]
    pub track_deg: Option<f64>,
    /// Horizontal velocity, knots.
    #[serde(rename(deserialize = "velH"))]
    pub velh_kt: Option<f64>,
    /// Vertical velocity, ft/min, positive up.
    #[serde(rename(deserialize = "velV"))]
    pub velv_fpm: Option<f64>,
    /// Magnetic heading, degrees.
    #[serde(rename(deserialize = "mag_heading"))]
    pub mag_heading_deg: Option<f64>,
    /// True heading, degrees.
    #[serde(rename(deserialize = "true_heading"))]
    pub true_heading_deg: Option<f64>,
    /// Indicated airspeed, knots.
    #[serde(rename(deserialize = "ias"))]
    pub ias_kt: Option<f64>,
    /// True airspeed, knots.
    #[serde(rename(deserialize = "tas"))]
    pub tas_kt: Option<f64>,
    /// Roll angle, degrees.
    #[serde(rename(deserialize = "roll"))]
    pub roll_deg: Option<f64>,
    /// Selected QNH, hPa.
    #[serde(rename(deserialize = "nav_qnh"))]
    pub nav_qnh_hpa: Option<f64>,
    /// MCP/FCU selected altitude, ft.
    #[serde(rename(deserialize = "nav_altitude_mcp"))]
    pub nav_altitude_mcp_ft: Option<f64>,
    /// FMS selected altitude, ft.
    #[serde(rename(deserialize = "nav_altitude_fms"))]
    pub nav_altitude_fms_ft: Option<f64>,
    /// Autopilot modes.
    pub nav_modes: Option<NavModes>,
    /// Selected heading, degrees.
    #[serde(rename(deserialize = "nav_heading"))]
    pub nav_heading_deg: Option<f64>,
    /// Callsign.
    #[serde(rename(deserialize = "call"))]
    pub callsign: Option<String>,
    /// Emitter category (table 20, the GDL90 numbering).
    pub ecat: Option<u8>,
    /// Squawk, decimal form of its octal digits (a string on the wire).
    #[serde(default, deserialize_with = "de_squawk")]
    pub squawk: Option<u16>,
    /// NACp (omitted when 0).
    #[serde(rename(deserialize = "nacp"))]
    pub nac_p: Option<u8>,
    /// NACv (omitted when 0).
    #[serde(rename(deserialize = "nacv"))]
    pub nac_v: Option<u8>,
    /// NICbaro (omitted when 0).
    #[serde(rename(deserialize = "nicBaro"))]
    pub nic_baro: Option<u8>,
    /// NIC (omitted when 0).
    pub nic: Option<u8>,
}

/// `nicnac` object of a `uat` entry (table 41).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct UatNicNac {
    /// NACp.
    #[serde(rename(deserialize = "nacP"), alias = "nacp")]
    pub nac_p: Option<u8>,
    /// NACv (the example writes `nacv`, table 41 `nacV`).
    #[serde(rename(deserialize = "nacV"), alias = "nacv")]
    pub nac_v: Option<u8>,
    /// NICbaro.
    #[serde(rename(deserialize = "nicBaro"))]
    pub nic_baro: Option<u8>,
    /// NIC (not in the manual's example; accepted if a firmware sends it).
    pub nic: Option<u8>,
}

/// `uatFlags` object of a `uat` entry (the U_FLAGS bits of table 39).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct UatStatusFlags {
    /// UTC coupling.
    #[serde(rename(deserialize = "utcCoupling"))]
    pub utc_coupling: Option<bool>,
    /// CDTI capability.
    pub cdti: Option<bool>,
    /// ACAS installed and operational.
    #[serde(rename(deserialize = "acasOperational"))]
    pub acas_operational: Option<bool>,
    /// ACAS resolution advisory active.
    #[serde(rename(deserialize = "acasActive"))]
    pub acas_active: Option<bool>,
    /// IDENT active.
    #[serde(rename(deserialize = "identActive"))]
    pub ident_active: Option<bool>,
    /// Receiving ATC services.
    #[serde(rename(deserialize = "atcActive"))]
    pub atc_active: Option<bool>,
    /// Heading referenced to magnetic north.
    #[serde(rename(deserialize = "headingMagnetic"))]
    pub heading_magnetic: Option<bool>,
}

/// One entry of the `uat` array (example in 10.2.1; table 40).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct UatTarget {
    /// Address (six hex digits on the wire).
    #[serde(serialize_with = "ser_hex24", deserialize_with = "de_hex24")]
    pub icao: u32,
    /// Flags.
    pub flags: Option<TargetFlags>,
    /// Squawk, decimal form of its octal digits (a number in the manual's example).
    #[serde(default, deserialize_with = "de_squawk")]
    pub squawk: Option<u16>,
    /// Callsign.
    #[serde(rename(deserialize = "call"))]
    pub callsign: Option<String>,
    /// Latitude, degrees.
    #[serde(rename(deserialize = "lat"))]
    pub lat_deg: Option<f64>,
    /// Longitude, degrees.
    #[serde(rename(deserialize = "lon"))]
    pub lon_deg: Option<f64>,
    /// Barometric altitude, ft.
    #[serde(rename(deserialize = "altBaro"))]
    pub alt_baro_ft: Option<f64>,
    /// Geometric altitude, ft.
    #[serde(rename(deserialize = "altGeo"), alias = "geoAlt")]
    pub alt_geo_ft: Option<f64>,
    /// Track, degrees.
    #[serde(rename(deserialize = "track"))]
    pub track_deg: Option<f64>,
    /// Horizontal velocity, knots.
    #[serde(rename(deserialize = "velH"))]
    pub velh_kt: Option<f64>,
    /// Vertical velocity, ft/min.
    #[serde(rename(deserialize = "velV"))]
    pub velv_fpm: Option<f64>,
    /// Signal strength, dBm.
    #[serde(rename(deserialize = "sigStr"))]
    pub sig_dbm: Option<f64>,
    /// Signal quality: errors corrected, 0 (best) .. 6.
    #[serde(rename(deserialize = "sigQ"))]
    pub sig_q_errors: Option<f64>,
    /// Frames received from this aircraft in the last second.
    pub fps: Option<u32>,
    /// NIC/NAC values.
    pub nicnac: Option<UatNicNac>,
    /// Emitter category.
    pub ecat: Option<u8>,
    /// Emergency status 0..7 (table 38).
    pub emergency: Option<u8>,
    /// Status flags.
    #[serde(rename(deserialize = "uatFlags"))]
    pub uat_flags: Option<UatStatusFlags>,
}

/// One entry of the `flarm` array (table 29).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct FlarmTarget {
    /// Id type: 0 randomised, 1 ICAO, 2 FLARM.
    #[serde(rename(deserialize = "idType"))]
    pub id_type: Option<u8>,
    /// Id (hex on the wire; printed as six upper-case hex digits).
    #[serde(serialize_with = "ser_hex24", deserialize_with = "de_hex32")]
    pub id: u32,
    /// FLARM aircraft type (table 30).
    #[serde(rename(deserialize = "type"))]
    pub aircraft_type: Option<u8>,
    /// Alarm level: `danger` in the manual's example (absent from its table), 0..3.
    #[serde(rename(deserialize = "danger"), alias = "alarmLevel")]
    pub alarm_level: Option<u8>,
    /// Raw frames from this aircraft in the last second.
    pub fps: Option<u32>,
    /// Latitude, degrees.
    #[serde(rename(deserialize = "lat"))]
    pub lat_deg: Option<f64>,
    /// Longitude, degrees.
    #[serde(rename(deserialize = "lon"))]
    pub lon_deg: Option<f64>,
    /// Altitude, m (see the CSV `#ALRM` module for which altitude).
    #[serde(rename(deserialize = "alt"))]
    pub alt_m: Option<f64>,
    /// Track, degrees.
    #[serde(rename(deserialize = "track"))]
    pub track_deg: Option<f64>,
    /// Horizontal velocity, m/s.
    #[serde(rename(deserialize = "hVelo"), alias = "hvelo")]
    pub velh_mps: Option<f64>,
    /// Vertical velocity, m/s, positive up.
    #[serde(rename(deserialize = "vVelo"), alias = "vvelo")]
    pub velv_mps: Option<f64>,
    /// Movement mode: 1 stationary, 4 circling right, 5 flying, 7 circling left.
    #[serde(rename(deserialize = "movMode"))]
    pub move_mode: Option<u8>,
    /// Stealth flag (1 when set, omitted otherwise).
    pub stealth: Option<u8>,
    /// Notrack flag (1 when set, omitted otherwise).
    pub notrack: Option<u8>,
}

/// `acc` object of the `gnss` section: position accuracies (the table's "m/s2" unit line is a
/// copy error; its rows say metres).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct GnssAccuracy {
    /// Latitude accuracy, m.
    #[serde(rename(deserialize = "lat"))]
    pub lat_m: Option<f64>,
    /// Longitude accuracy, m.
    #[serde(rename(deserialize = "lon"))]
    pub lon_m: Option<f64>,
    /// Altitude accuracy, m.
    #[serde(rename(deserialize = "alt"))]
    pub alt_m: Option<f64>,
}

/// `gnss` section (table 32).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct Gnss {
    /// 1 when the receiver has a fix.
    pub fix: Option<u8>,
    /// Last known latitude, degrees.
    #[serde(rename(deserialize = "lat"))]
    pub lat_deg: Option<f64>,
    /// Last known longitude, degrees.
    #[serde(rename(deserialize = "lon"))]
    pub lon_deg: Option<f64>,
    /// Altitude above the WGS-84 ellipsoid, m.
    #[serde(rename(deserialize = "altWgs84"))]
    pub alt_wgs84_m: Option<f64>,
    /// Altitude above mean sea level, m.
    #[serde(rename(deserialize = "altMsl"))]
    pub alt_msl_m: Option<f64>,
    /// Track, degrees true.
    #[serde(rename(deserialize = "track"))]
    pub track_deg: Option<f64>,
    /// Horizontal velocity, knots (table 32).
    #[serde(rename(deserialize = "hVelo"), alias = "hvelo")]
    pub velh_kt: Option<f64>,
    /// Vertical velocity, m/s, positive up.
    #[serde(rename(deserialize = "vVelo"), alias = "vvelo")]
    pub velv_mps: Option<f64>,
    /// Ground speed east and north, knots.
    #[serde(rename(deserialize = "gndSpeed"))]
    pub gnd_speed_en_kt: Option<[f64; 2]>,
    /// Position accuracies.
    pub acc: Option<GnssAccuracy>,
    /// NACp.
    #[serde(rename(deserialize = "nacp"))]
    pub nac_p: Option<u8>,
    /// NACv.
    #[serde(rename(deserialize = "nacv"))]
    pub nac_v: Option<u8>,
    /// NIC.
    pub nic: Option<u8>,
}

/// One raw Mode S frame of the `raw` section (table 23): `[frame hex, dBm, dB, time hex]`.
///
/// The frame stays a hex string: the Mode S decoder (raw module) takes it from here.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct RawFrame {
    /// Frame bytes as upper-case hex (14 digits short, 28 long).
    pub frame_hex: String,
    /// Signal strength, dBm.
    pub sig_dbm: Option<f64>,
    /// Signal quality, dB.
    pub sig_q_db: Option<f64>,
    /// UTC-calibrated reception time, ns since UTC midnight (hex on the wire).
    pub ts_ns: Option<u64>,
}

impl RawFrame {
    /// The reception time as the common source time: nanoseconds since UTC midnight (table 23's
    /// example 0x295CAB573A77 "translates to 12:37:57.988350583").
    pub fn source_time(&self) -> Option<crate::traffic::SourceTime> {
        self.ts_ns
            .map(crate::traffic::SourceTime::NsSinceUtcMidnight)
    }

    /// The frame bytes, if the hex is well formed.
    pub fn frame_bytes(&self) -> Option<Vec<u8>> {
        let s = self.frame_hex.as_bytes();
        if !s.len().is_multiple_of(2) {
            return None;
        }
        s.chunks(2)
            .map(|p| {
                let hi = (p[0] as char).to_digit(16)?;
                let lo = (p[1] as char).to_digit(16)?;
                Some((hi * 16 + lo) as u8)
            })
            .collect()
    }
}

impl<'de> Deserialize<'de> for RawFrame {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let v: Vec<serde_json::Value> = Vec::deserialize(d)?;
        let frame_hex = v
            .first()
            .and_then(|x| x.as_str())
            .filter(|s| !s.is_empty() && s.len() <= 64 && s.bytes().all(|b| b.is_ascii_hexdigit()))
            .ok_or_else(|| D::Error::custom("raw frame: first element must be a hex string"))?
            .to_ascii_uppercase();
        let num = |i: usize| -> Result<Option<f64>, D::Error> {
            match v.get(i) {
                None | Some(serde_json::Value::Null) => Ok(None),
                Some(x) => x
                    .as_f64()
                    .map(Some)
                    .ok_or_else(|| D::Error::custom("raw frame: signal must be a number")),
            }
        };
        let ts_ns = match v.get(3) {
            None | Some(serde_json::Value::Null) => None,
            Some(x) => Some(
                // Hex digits only (`from_str_radix` alone would take a leading `+`); an empty
                // string or more than 64 bits is refused by the parse itself.
                x.as_str()
                    .filter(|s| s.bytes().all(|b| b.is_ascii_hexdigit()))
                    .and_then(|s| u64::from_str_radix(s, 16).ok())
                    .ok_or_else(|| D::Error::custom("raw frame: time must be hex"))?,
            ),
        };
        Ok(RawFrame {
            frame_hex,
            sig_dbm: num(1)?,
            sig_q_db: num(2)?,
            ts_ns,
        })
    }
}

fn de_hex(s: &str, digits: usize) -> Option<u32> {
    parse_hex(s, digits)
}

fn de_hex24<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let s = String::deserialize(d)?;
    de_hex(&s, 6).ok_or_else(|| serde::de::Error::custom("address must be 1-6 hex digits"))
}

fn de_hex32<'de, D: Deserializer<'de>>(d: D) -> Result<u32, D::Error> {
    let s = String::deserialize(d)?;
    de_hex(&s, 8).ok_or_else(|| serde::de::Error::custom("id must be 1-8 hex digits"))
}

/// A squawk as a string ("5730", adsb) or a number (7232, the uat example): octal digits.
fn de_squawk<'de, D: Deserializer<'de>>(d: D) -> Result<Option<u16>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Sq {
        Text(String),
        Number(u64),
    }
    let text = match Option::<Sq>::deserialize(d)? {
        None => return Ok(None),
        Some(Sq::Text(s)) => s,
        Some(Sq::Number(n)) => format!("{n:04}"),
    };
    parse_squawk(&text)
        .map(Some)
        .ok_or_else(|| serde::de::Error::custom("squawk must be up to four octal digits"))
}
