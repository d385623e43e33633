//! MAVLink ADSB_VEHICLE (#246), manual 7.2.1 table 18 "MAVLink ADSB_VEHICLE message description"
//! and 8.2.1 "FLARM MAVLink protocol"; field layout and enums from the MAVLink common dialect
//! (decoded by the `mavlink` crate).
//!
//! Decisions:
//! - The manual's table 18 lists `ver_velocity` as uint16_t but says "positive is up"; the
//!   MAVLink definition (and the crate) has int16_t, which we follow.
//! - `altitude_type` 0 is named "pressure (QNH)" in MAVLink; the module fills `altitude` with the
//!   ADS-B barometric altitude, which is pressure altitude on the 1013.25 hPa datum: mapped to
//!   `alt_pressure_m`. Type 1 (geometric) maps to `alt_geometric_m` (the manual says ASL).
//! - Validity: fields are mapped only when their `ADSB_FLAGS_VALID_*` bit is set. The vertical
//!   rate is taken when `VERTICAL_VELOCITY_VALID` is set, or `VALID_VELOCITY` (senders older than
//!   that flag used `VALID_VELOCITY` for both speeds).
//! - The message carries no address type and no link other than the UAT flag; FLARM targets use
//!   the same message with the FLARM id in `ICAO_address` (manual 8.2.1), so the address type is
//!   [`AddressType::Unknown`] and the link is 1090 MHz unless `ADSB_FLAGS_SOURCE_UAT` is set.

use mavlink::dialects::common::{ADSB_VEHICLE_DATA, AdsbAltitudeType, AdsbEmitterType, AdsbFlags};
use num_traits::FromPrimitive;
use serde::Serialize;

use crate::traffic::{AddressType, Link, Protocol, TrafficFlags, TrafficReport};

/// Message ID of ADSB_VEHICLE.
pub const ID: u32 = 246;

/// `flags` bit: lat/lon valid.
pub const FLAG_VALID_COORDS: u16 = 1;
/// `flags` bit: altitude valid.
pub const FLAG_VALID_ALTITUDE: u16 = 2;
/// `flags` bit: heading (course over ground) valid.
pub const FLAG_VALID_HEADING: u16 = 4;
/// `flags` bit: velocity valid.
pub const FLAG_VALID_VELOCITY: u16 = 8;
/// `flags` bit: callsign valid.
pub const FLAG_VALID_CALLSIGN: u16 = 16;
/// `flags` bit: squawk valid.
pub const FLAG_VALID_SQUAWK: u16 = 32;
/// `flags` bit: simulated target.
pub const FLAG_SIMULATED: u16 = 64;
/// `flags` bit: vertical velocity valid.
pub const FLAG_VERTICAL_VELOCITY_VALID: u16 = 128;
/// `flags` bit: barometric altitude valid.
pub const FLAG_BARO_VALID: u16 = 256;
/// `flags` bit: the target was received over UAT.
pub const FLAG_SOURCE_UAT: u16 = 32768;

/// One ADSB_VEHICLE message, scaled to units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AdsbVehicle {
    /// ICAO address (or FLARM id for FLARM targets), as sent (32 bits).
    pub icao_address: u32,
    /// Latitude, degrees (1e-7 steps).
    pub lat_deg: f64,
    /// Longitude, degrees (1e-7 steps).
    pub lon_deg: f64,
    /// Altitude, m (1 mm steps), kind per `altitude_type`.
    pub altitude_m: f64,
    /// ADSB_ALTITUDE_TYPE: 0 pressure, 1 geometric.
    pub altitude_type: u8,
    /// Course over ground, degrees (0.01 steps).
    pub heading_deg: f64,
    /// Horizontal velocity, m/s (0.01 steps).
    pub hor_velocity_mps: f64,
    /// Vertical velocity, m/s, positive up (0.01 steps).
    pub ver_velocity_mps: f64,
    /// ADSB_FLAGS bit map (see the `FLAG_*` constants).
    pub flags: u16,
    /// Squawk as four octal digits written in decimal (7700 is 7700).
    pub squawk: u16,
    /// Callsign, up to 8 characters, NUL padding removed.
    pub callsign: String,
    /// ADSB_EMITTER_TYPE (0..=19), the DO-260B emitter category.
    pub emitter_type: u8,
    /// Time since last communication, s.
    pub tslc_s: u8,
}

impl AdsbVehicle {
    /// Converts the crate's decoded payload.
    pub fn from_data(d: &ADSB_VEHICLE_DATA) -> Self {
        let cs: &[u8] = &d.callsign[..];
        let end = cs.iter().position(|&b| b == 0).unwrap_or(cs.len());
        let callsign: String = cs[..end].iter().map(|&b| char::from(b)).collect();
        Self {
            icao_address: d.ICAO_address,
            lat_deg: f64::from(d.lat) / 1e7,
            lon_deg: f64::from(d.lon) / 1e7,
            altitude_m: f64::from(d.altitude) / 1e3,
            altitude_type: d.altitude_type as u8,
            heading_deg: f64::from(d.heading) / 100.0,
            hor_velocity_mps: f64::from(d.hor_velocity) / 100.0,
            ver_velocity_mps: f64::from(d.ver_velocity) / 100.0,
            flags: d.flags.bits(),
            squawk: d.squawk,
            callsign,
            emitter_type: d.emitter_type as u8,
            tslc_s: d.tslc,
        }
    }

    /// Converts back to the crate's payload (values rounded to the field resolution and
    /// clamped; an unknown altitude or emitter type becomes 0, a callsign is cut to 8 bytes).
    pub fn to_data(&self) -> ADSB_VEHICLE_DATA {
        fn scaled<T: TryFrom<i64> + Default>(v: f64, per_unit: f64, min: i64, max: i64) -> T {
            let c = ((v * per_unit).round() as i64).clamp(min, max);
            T::try_from(c).unwrap_or_default()
        }
        let mut callsign = [0u8; 9];
        for (dst, src) in callsign.iter_mut().zip(self.callsign.bytes().take(8)) {
            *dst = src;
        }
        ADSB_VEHICLE_DATA {
            ICAO_address: self.icao_address,
            lat: scaled(self.lat_deg, 1e7, i64::from(i32::MIN), i64::from(i32::MAX)),
            lon: scaled(self.lon_deg, 1e7, i64::from(i32::MIN), i64::from(i32::MAX)),
            altitude: scaled(
                self.altitude_m,
                1e3,
                i64::from(i32::MIN),
                i64::from(i32::MAX),
            ),
            heading: scaled(self.heading_deg, 100.0, 0, i64::from(u16::MAX)),
            hor_velocity: scaled(self.hor_velocity_mps, 100.0, 0, i64::from(u16::MAX)),
            ver_velocity: scaled(
                self.ver_velocity_mps,
                100.0,
                i64::from(i16::MIN),
                i64::from(i16::MAX),
            ),
            flags: AdsbFlags::from_bits_retain(self.flags),
            squawk: self.squawk,
            altitude_type: AdsbAltitudeType::from_u8(self.altitude_type).unwrap_or_default(),
            callsign: callsign.into(),
            emitter_type: AdsbEmitterType::from_u8(self.emitter_type).unwrap_or_default(),
            tslc: self.tslc_s,
        }
    }

    fn has(&self, flag: u16) -> bool {
        self.flags & flag != 0
    }

    /// Maps to the common traffic report (see the module doc for the decisions).
    pub fn to_traffic(&self) -> TrafficReport {
        let coords = self.has(FLAG_VALID_COORDS);
        let alt = self.has(FLAG_VALID_ALTITUDE).then_some(self.altitude_m);
        let geometric = self.altitude_type == 1;
        let callsign = self
            .has(FLAG_VALID_CALLSIGN)
            .then(|| self.callsign.trim().to_string())
            .filter(|c| !c.is_empty());
        let link = if self.has(FLAG_SOURCE_UAT) {
            Link::Uat978
        } else {
            Link::Adsb1090
        };
        TrafficReport {
            callsign,
            squawk: self.has(FLAG_VALID_SQUAWK).then_some(self.squawk),
            emitter_category: Some(self.emitter_type),
            lat_deg: coords.then_some(self.lat_deg),
            lon_deg: coords.then_some(self.lon_deg),
            alt_pressure_m: alt.filter(|_| !geometric),
            alt_geometric_m: alt.filter(|_| geometric),
            track_deg: self.has(FLAG_VALID_HEADING).then_some(self.heading_deg),
            ground_speed_mps: self
                .has(FLAG_VALID_VELOCITY)
                .then_some(self.hor_velocity_mps),
            vertical_rate_mps: (self.has(FLAG_VERTICAL_VELOCITY_VALID)
                || self.has(FLAG_VALID_VELOCITY))
            .then_some(self.ver_velocity_mps),
            flags: TrafficFlags {
                test: self.has(FLAG_SIMULATED),
                ..Default::default()
            },
            // Decision (issue 24): `tslc` is whole seconds and the manual does not say whether
            // it is truncated or rounded; it is taken as the age itself (the rounded reading),
            // and the fusion widens the position uncertainty for the half second either way.
            data_age_s: Some(f64::from(self.tslc_s)),
            ..TrafficReport::new(
                link,
                Protocol::Mavlink,
                self.icao_address & 0xFF_FFFF,
                AddressType::Unknown,
            )
        }
    }
}
