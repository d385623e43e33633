//! The one traffic report every TT-Multi-RF protocol maps to, so fusion does not care which
//! protocol (CSV, JSON, MAVLink, GDL90, ASTERIX, raw Mode-S) or link delivered it.
//!
//! Units: SI except where the name says otherwise. Latitude/longitude are in degrees (WGS-84),
//! angles over ground in degrees true. Every field the source did not carry is `None`
//! ("unknown"), never zero.

use serde::Serialize;

/// Radio link a report was received on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Link {
    /// 1090 MHz extended squitter (ADS-B, TIS-B, ADS-R) or other Mode S replies.
    #[default]
    Adsb1090,
    /// 978 MHz Universal Access Transceiver.
    Uat978,
    /// FLARM (868/915 MHz).
    Flarm,
}

/// Protocol that delivered a report (for diagnostics and replay comparisons).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Protocol {
    /// Aerobits CSV ("AERO") lines.
    #[default]
    Csv,
    /// Aerobits JSON.
    Json,
    /// MAVLink ADSB_VEHICLE / COLLISION.
    Mavlink,
    /// GDL90 traffic/ownship reports.
    Gdl90,
    /// ASTERIX CAT021.
    Asterix,
    /// Raw Mode S frames decoded by vigil (HEX, HEXd, Beast).
    RawModeS,
}

/// What kind of address a target's `address` is. Addresses of different kinds never merge.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum AddressType {
    /// 24-bit ICAO aircraft address.
    #[default]
    Icao,
    /// Non-ICAO / self-assigned / anonymous 24-bit address (ADS-B, UAT).
    NonIcao,
    /// TIS-B or ADS-R target with ICAO address.
    TisbIcao,
    /// TIS-B track file number or other non-ICAO TIS-B address.
    TisbOther,
    /// FLARM random / generated id.
    FlarmRandom,
    /// FLARM fixed id (FLARM's own id space).
    FlarmFixed,
    /// Surface vehicle or fixed beacon.
    Surface,
    /// The source gave no address type.
    Unknown,
}

/// Time the source stamped on a report, in the source's own time scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SourceTime {
    /// Milliseconds since UTC midnight (TT-Multi-RF JSON `ts`).
    MsSinceUtcMidnight(u32),
    /// Nanoseconds since UTC midnight (raw Mode S TS24h).
    NsSinceUtcMidnight(u64),
    /// Nanoseconds since the receiver's last PPS (raw Mode S TS1s).
    NsSincePps(u64),
    /// Free-running 12 MHz multilateration counter (Beast), in ticks.
    Mlat12MHz(u64),
    /// Seconds since UTC midnight with fraction (ASTERIX time of applicability), in ns.
    AsterixTodNs(u64),
}

/// Flags carried by a report. All false when the source did not say.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct TrafficFlags {
    /// Target reports being on the ground.
    pub on_ground: bool,
    /// Special position identification (IDENT) active.
    pub ident: bool,
    /// An emergency or priority status is declared (see `emergency`).
    pub emergency: bool,
    /// The report was relayed (TIS-B / ADS-R) rather than received from the aircraft itself.
    pub relayed: bool,
    /// The source marks the position as unreliable (e.g. GDL90 NIC 0, ASTERIX GBS/SIM/TST bits).
    pub degraded: bool,
    /// Simulated or test target (ASTERIX SIM/TST).
    pub test: bool,
}

/// One traffic report, whatever protocol delivered it.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct TrafficReport {
    /// Link the report came on.
    pub link: Link,
    /// Protocol that delivered it.
    pub protocol: Protocol,
    /// 24-bit address (ICAO, non-ICAO or FLARM id, see `address_type`).
    pub address: u32,
    /// What kind of address `address` is.
    pub address_type: AddressType,
    /// Callsign / flight id, trimmed of padding.
    pub callsign: Option<String>,
    /// Mode A code (squawk) as four octal digits packed in decimal form, e.g. 7700.
    pub squawk: Option<u16>,
    /// Emitter category as in DO-260B / GDL90 (0 = no information, 1 = light ... 39); FLARM aircraft
    /// types are mapped to this set.
    pub emitter_category: Option<u8>,
    /// Latitude, degrees north (WGS-84).
    pub lat_deg: Option<f64>,
    /// Longitude, degrees east (WGS-84).
    pub lon_deg: Option<f64>,
    /// Barometric (pressure) altitude, m, referenced to 1013.25 hPa.
    pub alt_pressure_m: Option<f64>,
    /// Geometric altitude, m (above the WGS-84 ellipsoid unless the protocol says MSL).
    pub alt_geometric_m: Option<f64>,
    /// Track over ground, degrees true, 0..360.
    pub track_deg: Option<f64>,
    /// Heading, degrees (true unless the source says magnetic), 0..360.
    pub heading_deg: Option<f64>,
    /// Horizontal speed over ground, m/s.
    pub ground_speed_mps: Option<f64>,
    /// Vertical rate, m/s, positive up.
    pub vertical_rate_mps: Option<f64>,
    /// Navigation integrity category (0..11).
    pub nic: Option<u8>,
    /// Navigation accuracy category for position (0..11).
    pub nac_p: Option<u8>,
    /// Navigation accuracy category for velocity (0..4).
    pub nac_v: Option<u8>,
    /// Source integrity level (0..3).
    pub sil: Option<u8>,
    /// Received signal level, dBm (or the source's own signal unit, see the protocol module).
    pub signal_dbm: Option<f64>,
    /// Emergency / priority code (DO-260B TC 28 values, 0 = none).
    pub emergency_code: Option<u8>,
    /// FLARM alarm level 0..3, where the source is FLARM.
    pub flarm_alarm_level: Option<u8>,
    /// Flags.
    pub flags: TrafficFlags,
    /// Time stamp the source put on the report, if any.
    pub source_time: Option<SourceTime>,
    // --- issue 24: time of applicability ---
    /// How old the report's data were when the message was sent, s, where the protocol says so
    /// (MAVLink `tslc`, ASTERIX time of transmission minus time of applicability of the
    /// position); `None` when it does not.
    pub data_age_s: Option<f64>,
}

/// A value of a report outside what the protocol can carry or physics allows (issue 24): the
/// report is dropped alone and counted (`invalid_values`), its neighbours kept.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum InvalidValue {
    /// Named field out of its range or not finite.
    #[error("{0} out of range")]
    OutOfRange(&'static str),
}

/// Ranges of [`TrafficReport::check_values`]. Decision: the widest any TT-Multi-RF protocol can
/// encode or any aircraft reach, so a valid report is never dropped; the traffic picture's own
/// plausibility tests (e.g. 350 m/s) only flag. Altitude: -2 000 ft to 130 000 ft (ADS-B and
/// GDL90 encode -1 000 .. 126 750 ft); ground speed 0 to 2 200 m/s (ADS-B supersonic ends at
/// 4 092 kt = 2 105 m/s); vertical rate +-200 m/s (ADS-B ends at 32 608 ft/min = 166 m/s).
pub mod limits {
    /// Lowest altitude, m.
    pub const ALT_MIN_M: f64 = -2_000.0 * 0.3048;
    /// Highest altitude, m.
    pub const ALT_MAX_M: f64 = 130_000.0 * 0.3048;
    /// Fastest ground speed, m/s.
    pub const SPEED_MAX_MPS: f64 = 2_200.0;
    /// Fastest vertical rate either way, m/s.
    pub const VERTICAL_RATE_MAX_MPS: f64 = 200.0;
}

impl TrafficReport {
    /// A report from `link` and `protocol` about `address` (24 bits) of kind `address_type`,
    /// every other value unknown. A decoder that leaves some values to the default builds its
    /// report on this (the others name every field), so where a report came from is always
    /// stated, never left to a default.
    pub fn new(link: Link, protocol: Protocol, address: u32, address_type: AddressType) -> Self {
        Self {
            link,
            protocol,
            address,
            address_type,
            ..Self::default()
        }
    }

    /// Checks every value against the protocol's and physics' ranges (see [`limits`]): latitude
    /// within +-90 deg, longitude within +-180 deg, altitudes, speeds, rates and angles finite
    /// and within their ranges; signal finite. Absent values pass (unknown is not invalid; a
    /// latitude without a longitude is no position to the fusion, not an impossible value).
    pub fn check_values(&self) -> Result<(), InvalidValue> {
        use limits::*;
        let within = |v: Option<f64>, lo: f64, hi: f64, name: &'static str| match v {
            Some(x) if !(x.is_finite() && (lo..=hi).contains(&x)) => {
                Err(InvalidValue::OutOfRange(name))
            }
            _ => Ok(()),
        };
        within(self.lat_deg, -90.0, 90.0, "latitude")?;
        within(self.lon_deg, -180.0, 180.0, "longitude")?;
        within(
            self.alt_pressure_m,
            ALT_MIN_M,
            ALT_MAX_M,
            "pressure altitude",
        )?;
        within(
            self.alt_geometric_m,
            ALT_MIN_M,
            ALT_MAX_M,
            "geometric altitude",
        )?;
        within(self.ground_speed_mps, 0.0, SPEED_MAX_MPS, "ground speed")?;
        let vr = VERTICAL_RATE_MAX_MPS;
        within(self.vertical_rate_mps, -vr, vr, "vertical rate")?;
        // Angles: any finite value within one turn either way (FLARM sends -180 .. 180).
        within(self.track_deg, -360.0, 360.0, "track")?;
        within(self.heading_deg, -360.0, 360.0, "heading")?;
        within(self.signal_dbm, -200.0, 100.0, "signal")?;
        within(self.data_age_s, 0.0, 255.0, "data age")?;
        Ok(())
    }

    /// The address as upper-case hex, six digits (how every tool prints it).
    pub fn address_hex(&self) -> String {
        format!("{:06X}", self.address & 0xFF_FFFF)
    }
}
