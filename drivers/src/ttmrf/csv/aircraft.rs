//! `#A` (ADS-B aircraft, manual 7.2.1, tables 14-17) and `#U` (UAT aircraft, manual 10.2.1,
//! tables 34-39) CSV messages.
//!
//! ```text
//! #A:ICAO,FLAGS,CALL,SQ,LAT,LON,ALT_BARO,TRACK,VELH,VELV,SIGS,SIGQ,FPS,NICNAC,ALT_GEO,ECAT,CRC
//! #U:<the same sixteen fields>,U_EMERG,U_FLAGS,CRC
//! ```
//!
//! NIC/NAC bitfield (tables 16 and 36 are flattened by the OCR; the widths follow from the
//! ED-102A value ranges: NIC 0..11 needs 4 bits, NICbaro 1, NACp 0..11 4, NACv 0..4 3):
//!
//! ```text
//! 15..12 reserved | 11..9 NACv | 8..5 NACp | 4 NICbaro | 3..0 NIC
//! ```
//!
//! Check: the manual's `#A` example carries `938`, giving NIC 8, NICbaro 1, NACp 9, the usual
//! values of an airliner (and the JSON example's nacp 9 / nicBaro 1 / nic 8); table 14's `31B`
//! gives NIC 11, NICbaro 1, NACp 8, NACv 1.

use serde::Serialize;

use super::CsvError;
use super::fields::{Fields, push_hex, push_opt, ser_hex24};
use crate::traffic::{AddressType, Link, Protocol, TrafficFlags, TrafficReport};

/// Feet to metres (exact).
pub const FT_TO_M: f64 = 0.3048;
/// Knots to metres per second (exact: 1852 m per 3600 s).
pub const KT_TO_MPS: f64 = 1852.0 / 3600.0;
/// Feet per minute to metres per second (exact).
pub const FPM_TO_MPS: f64 = 0.00508;

/// Number of data fields `#A` has in firmware 2.77.5 (before any future field and the CRC).
pub const ADSB_FIELDS: usize = 16;
/// Number of data fields `#U` has in firmware 2.77.5.
pub const UAT_FIELDS: usize = 18;

/// The FLAGS bitfield of `#A` and `#U` (tables 15 and 35), decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct AircraftFlags {
    /// The raw 16-bit value.
    pub raw: u16,
    /// 0x0001 PLANE_ON_THE_GROUND.
    pub on_ground: bool,
    /// 0x0002 PLANE_IS_MILITARY (always 0 on UAT).
    pub military: bool,
    /// 0x0100 barometric altitude updated during the last second.
    pub upd_alt_baro: bool,
    /// 0x0200 position updated during the last second.
    pub upd_position: bool,
    /// 0x0400 track updated during the last second.
    pub upd_track: bool,
    /// 0x0800 horizontal velocity updated during the last second.
    pub upd_velo_h: bool,
    /// 0x1000 vertical velocity updated during the last second.
    pub upd_velo_v: bool,
    /// 0x2000 geometric altitude updated during the last second.
    pub upd_alt_geo: bool,
}

impl AircraftFlags {
    /// Decodes the raw bitfield.
    pub const fn from_raw(raw: u16) -> Self {
        Self {
            raw,
            on_ground: raw & 0x0001 != 0,
            military: raw & 0x0002 != 0,
            upd_alt_baro: raw & 0x0100 != 0,
            upd_position: raw & 0x0200 != 0,
            upd_track: raw & 0x0400 != 0,
            upd_velo_h: raw & 0x0800 != 0,
            upd_velo_v: raw & 0x1000 != 0,
            upd_alt_geo: raw & 0x2000 != 0,
        }
    }
}

/// The NICNAC bitfield (tables 16 and 36), decoded; see the module doc for the layout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct NicNac {
    /// The raw value.
    pub raw: u16,
    /// Navigation integrity category, bits 3..0.
    pub nic: u8,
    /// NICbaro, bit 4.
    pub nic_baro: u8,
    /// Navigation accuracy category for position, bits 8..5.
    pub nac_p: u8,
    /// Navigation accuracy category for velocity, bits 11..9.
    pub nac_v: u8,
}

impl NicNac {
    /// Decodes the raw bitfield.
    pub const fn from_raw(raw: u16) -> Self {
        Self {
            raw,
            nic: (raw & 0xF) as u8,
            nic_baro: ((raw >> 4) & 1) as u8,
            nac_p: ((raw >> 5) & 0xF) as u8,
            nac_v: ((raw >> 9) & 0x7) as u8,
        }
    }

    /// Packs the four values (each masked to its width) into the raw layout.
    pub const fn pack(nic: u8, nic_baro: u8, nac_p: u8, nac_v: u8) -> u16 {
        (nic as u16 & 0xF)
            | ((nic_baro as u16 & 1) << 4)
            | ((nac_p as u16 & 0xF) << 5)
            | ((nac_v as u16 & 0x7) << 9)
    }
}

/// The U_FLAGS bitfield of `#U` (table 39), decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct UatFlags {
    /// The raw value (reserved bits kept here).
    pub raw: u16,
    /// 0x0001 UTC coupling.
    pub utc_coupling: bool,
    /// 0x0002 CDTI traffic display capability.
    pub cdti: bool,
    /// 0x0004 TCAS/ACAS installed and operational.
    pub acas_operational: bool,
    /// 0x0008 TCAS/ACAS resolution advisory active.
    pub acas_ra_active: bool,
    /// 0x0010 IDENT switch active.
    pub ident_active: bool,
    /// 0x0020 receiving ATC services.
    pub atc_services: bool,
    /// 0x0040 heading/track referenced to magnetic north (0 = true north).
    pub heading_magnetic: bool,
}

impl UatFlags {
    /// Decodes the raw bitfield.
    pub const fn from_raw(raw: u16) -> Self {
        Self {
            raw,
            utc_coupling: raw & 0x0001 != 0,
            cdti: raw & 0x0002 != 0,
            acas_operational: raw & 0x0004 != 0,
            acas_ra_active: raw & 0x0008 != 0,
            ident_active: raw & 0x0010 != 0,
            atc_services: raw & 0x0020 != 0,
            heading_magnetic: raw & 0x0040 != 0,
        }
    }
}

/// The sixteen fields `#A` and `#U` share, in the device's own units (named).
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct AircraftState {
    /// 24-bit ICAO address (printed as six upper-case hex digits).
    #[serde(serialize_with = "ser_hex24")]
    pub icao: u32,
    /// FLAGS bitfield.
    pub flags: Option<AircraftFlags>,
    /// Callsign.
    pub callsign: Option<String>,
    /// Squawk in decimal form of its four octal digits.
    pub squawk: Option<u16>,
    /// Latitude, degrees.
    pub lat_deg: Option<f64>,
    /// Longitude, degrees.
    pub lon_deg: Option<f64>,
    /// Barometric altitude, feet.
    pub alt_baro_ft: Option<f64>,
    /// Track, degrees 0..360.
    pub track_deg: Option<f64>,
    /// Horizontal velocity, knots.
    pub velh_kt: Option<f64>,
    /// Vertical velocity, ft/min, positive up.
    pub velv_fpm: Option<f64>,
    /// Signal strength, dBm.
    pub sig_dbm: Option<f64>,
    /// Signal quality: dB on 1090 MHz, number of corrected errors (0 best .. 6) on UAT.
    pub sig_q: Option<f64>,
    /// Raw frames received from this aircraft during the last second.
    pub fps: Option<u32>,
    /// NIC/NAC bitfield.
    pub nicnac: Option<NicNac>,
    /// Geometric altitude, feet.
    pub alt_geo_ft: Option<f64>,
    /// Emitter category (table 17: the DO-260B / GDL90 numbering).
    pub ecat: Option<u8>,
}

impl AircraftState {
    /// Parses the sixteen shared fields.
    fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        let icao = f.hex(0, "ICAO", 6)?.ok_or(CsvError::field("ICAO", ""))?;
        Ok(Self {
            icao,
            flags: f
                .hex(1, "FLAGS", 4)?
                .map(|v| AircraftFlags::from_raw(v as u16)),
            callsign: f.text(2),
            squawk: f.squawk(3, "SQ")?,
            lat_deg: f.f64_in(4, "LAT", -90.0, 90.0)?,
            lon_deg: f.f64_in(5, "LON", -180.0, 180.0)?,
            alt_baro_ft: f.f64(6, "ALT_BARO")?,
            track_deg: f.f64_in(7, "TRACK", 0.0, 360.0)?,
            velh_kt: f.f64(8, "VELH")?,
            velv_fpm: f.f64(9, "VELV")?,
            sig_dbm: f.f64(10, "SIGS")?,
            sig_q: f.f64(11, "SIGQ")?,
            fps: f.uint(12, "FPS")?,
            nicnac: f.hex(13, "NICNAC", 4)?.map(|v| NicNac::from_raw(v as u16)),
            alt_geo_ft: f.f64(14, "ALT_GEO")?,
            ecat: f.uint(15, "ECAT")?,
        })
    }

    /// Appends the sixteen fields (each preceded by a comma except the first).
    fn write(&self, line: &mut String) {
        use std::fmt::Write as _;
        let _ = write!(line, "{:06X}", self.icao & 0xFF_FFFF);
        push_hex(line, self.flags.map(|f| u32::from(f.raw)));
        push_opt(line, self.callsign.as_deref());
        push_opt(line, self.squawk.map(|s| format!("{s:04}")));
        push_opt(line, self.lat_deg);
        push_opt(line, self.lon_deg);
        push_opt(line, self.alt_baro_ft);
        push_opt(line, self.track_deg);
        push_opt(line, self.velh_kt);
        push_opt(line, self.velv_fpm);
        push_opt(line, self.sig_dbm);
        push_opt(line, self.sig_q);
        push_opt(line, self.fps);
        push_hex(line, self.nicnac.map(|n| u32::from(n.raw)));
        push_opt(line, self.alt_geo_ft);
        push_opt(line, self.ecat);
    }

    /// The common traffic report (SI units) for these fields.
    fn to_traffic(&self, link: Link) -> TrafficReport {
        TrafficReport {
            callsign: self.callsign.clone(),
            squawk: self.squawk,
            emitter_category: self.ecat,
            lat_deg: self.lat_deg,
            lon_deg: self.lon_deg,
            alt_pressure_m: self.alt_baro_ft.map(|v| v * FT_TO_M),
            alt_geometric_m: self.alt_geo_ft.map(|v| v * FT_TO_M),
            track_deg: self.track_deg,
            ground_speed_mps: self.velh_kt.map(|v| v * KT_TO_MPS),
            vertical_rate_mps: self.velv_fpm.map(|v| v * FPM_TO_MPS),
            nic: self.nicnac.map(|n| n.nic),
            nac_p: self.nicnac.map(|n| n.nac_p),
            nac_v: self.nicnac.map(|n| n.nac_v),
            signal_dbm: self.sig_dbm,
            flags: TrafficFlags {
                on_ground: self.flags.is_some_and(|f| f.on_ground),
                ..Default::default()
            },
            // The CSV message calls the field "ICAO number" and carries no address type. It has
            // no heading and no SIL either: those stay unknown.
            ..TrafficReport::new(link, Protocol::Csv, self.icao, AddressType::Icao)
        }
    }
}

/// `#A`: ADS-B aircraft state vector, sent once per second per aircraft.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct AdsbAircraft {
    /// The sixteen documented fields.
    #[serde(flatten)]
    pub state: AircraftState,
    /// Fields after ECAT and before the CRC (added by later firmware), kept verbatim.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_fields: Vec<String>,
}

impl AdsbAircraft {
    /// Parses the data fields of a `#A` line.
    pub fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        if f.len() < ADSB_FIELDS {
            return Err(CsvError::FieldCount {
                tag: "A",
                expected: ADSB_FIELDS,
                got: f.len(),
            });
        }
        Ok(Self {
            state: AircraftState::parse(f)?,
            extra_fields: f.rest(ADSB_FIELDS),
        })
    }

    /// Appends the data fields (without tag and CRC).
    pub fn write_fields(&self, line: &mut String) {
        self.state.write(line);
        for x in &self.extra_fields {
            line.push(',');
            line.push_str(x);
        }
    }

    /// The common traffic report.
    pub fn to_traffic(&self) -> TrafficReport {
        self.state.to_traffic(Link::Adsb1090)
    }
}

/// `#U`: UAT aircraft state vector, sent once per second per aircraft.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct UatAircraft {
    /// The sixteen fields shared with `#A`.
    #[serde(flatten)]
    pub state: AircraftState,
    /// U_EMERG: emergency/priority status 0..7 (table 38).
    pub emergency: Option<u8>,
    /// U_FLAGS (table 39).
    pub uat_flags: Option<UatFlags>,
    /// Fields after U_FLAGS and before the CRC, kept verbatim.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub extra_fields: Vec<String>,
}

impl UatAircraft {
    /// Parses the data fields of a `#U` line.
    pub fn parse(f: &Fields<'_>) -> Result<Self, CsvError> {
        if f.len() < UAT_FIELDS {
            return Err(CsvError::FieldCount {
                tag: "U",
                expected: UAT_FIELDS,
                got: f.len(),
            });
        }
        Ok(Self {
            state: AircraftState::parse(f)?,
            emergency: f.u8_max(16, "U_EMERG", 7)?,
            uat_flags: f
                .hex(17, "U_FLAGS", 4)?
                .map(|v| UatFlags::from_raw(v as u16)),
            extra_fields: f.rest(UAT_FIELDS),
        })
    }

    /// Appends the data fields (without tag and CRC).
    pub fn write_fields(&self, line: &mut String) {
        self.state.write(line);
        push_opt(line, self.emergency);
        push_hex(line, self.uat_flags.map(|f| u32::from(f.raw)));
        for x in &self.extra_fields {
            line.push(',');
            line.push_str(x);
        }
    }

    /// The common traffic report: adds the emergency code and the IDENT flag.
    ///
    /// Decision: U_FLAGS 0x0040 says the direction is referenced to magnetic north. The report's
    /// `track_deg` is true, and no declination is known here, so a magnetic direction is not
    /// passed on (`None`); the message keeps it in `state.track_deg`.
    pub fn to_traffic(&self) -> TrafficReport {
        let mut r = self.state.to_traffic(Link::Uat978);
        if self.uat_flags.is_some_and(|f| f.heading_magnetic) {
            r.track_deg = None;
        }
        r.emergency_code = self.emergency;
        r.flags.emergency = self.emergency.is_some_and(|e| e != 0);
        r.flags.ident = self.uat_flags.is_some_and(|f| f.ident_active);
        r
    }
}
