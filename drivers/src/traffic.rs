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
}

impl TrafficReport {
    /// The address as upper-case hex, six digits (how every tool prints it).
    pub fn address_hex(&self) -> String {
        format!("{:06X}", self.address & 0xFF_FFFF)
    }
}
