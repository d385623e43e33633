//! The settings of manual tables 9 (system), 12 (ADS-B), 13 (ASTERIX), 24 (FLARM), 31 (GNSS) and
//! 33 (UAT), as typed values with their ranges.
//!
//! The tables are flattened by the OCR: the Min/Max/Def columns survive only in part. Ranges are
//! taken from the value lists in the Comment column; a default is recorded only where the Def
//! column is legible (otherwise `None`, "not documented").
//!
//! Numbering decision: table 12 lists the ADS-B decoded protocols as None, CSV, Mavlink, JSON,
//! GDL90, ASTERIX, which 5.1.8 (`ADSB_RX_PROTOCOL_DECODED=1` selects CSV) and table 13 ("Visible
//! when ADSB_DECODED_PROTOCOL=5" for ASTERIX) pin as 0..5. Tables 24 and 33 list subsets (FLARM
//! decoded: None, CSV, Mavlink, JSON, ASTERIX; UAT decoded: CSV, JSON, Mavlink; UAT raw: HEX,
//! HEXd) without numbers. The firmware shares one protocol enumeration across subsystems (the
//! statistics settings also use 1 CSV / 2 JSON consistently), so the subsets keep the ADS-B
//! numbers: FLARM ASTERIX = 5, UAT JSON = 3, UAT HEXd = 4. Values outside a subset are rejected.

use std::fmt;

use serde::Serialize;

/// Baud of the UART in CONFIGURATION and BOOTLOADER states (manual 3).
pub const CONFIG_BAUD: u32 = 115_200;

/// Why a setting value was refused.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SettingError {
    /// Name not in the tables this module implements.
    #[error("unknown setting '{0}'")]
    Unknown(String),
    /// Value not an integer.
    #[error("setting {name}: '{value}' is not an integer")]
    NotInteger {
        /// Setting name.
        name: &'static str,
        /// Offending text.
        value: String,
    },
    /// Value outside the documented range or value list.
    #[error("setting {name}: {value} is out of range")]
    OutOfRange {
        /// Setting name.
        name: &'static str,
        /// Offending value.
        value: i64,
    },
}

/// Description of one setting: name, table, allowed values, default.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SettingSpec {
    /// Name as in `AT+NAME=...`.
    pub name: &'static str,
    /// Manual table that documents it.
    pub table: u8,
    /// Smallest value.
    pub min: i64,
    /// Largest value.
    pub max: i64,
    /// The allowed values when not every value of `min..=max` is.
    pub allowed: Option<&'static [i64]>,
    /// Default where the manual's Def column is legible.
    pub default: Option<i64>,
    /// One-line description.
    pub doc: &'static str,
}

macro_rules! settings {
    ($( $(#[$m:meta])* $id:ident = $name:literal, $table:literal, $min:literal ..= $max:literal, $allowed:expr, $def:expr, $doc:literal; )*) => {
        /// A setting of tables 9, 12, 13, 24, 31 and 33.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
        pub enum SettingId {
            $( $(#[$m])* $id, )*
        }

        impl SettingId {
            /// Every setting, in table order.
            pub const ALL: &'static [SettingId] = &[$(SettingId::$id,)*];

            /// The setting's description.
            pub const fn spec(self) -> SettingSpec {
                match self {
                    $(SettingId::$id => SettingSpec {
                        name: $name,
                        table: $table,
                        min: $min,
                        max: $max,
                        allowed: $allowed,
                        default: $def,
                        doc: $doc,
                    },)*
                }
            }
        }
    };
}

settings! {
    /// Baud in RUN state: 0 115200, 1 921600, 2 3000000, 3 57600.
    Baudrate = "BAUDRATE", 9, 0..=3, None, None, "Baudrate in RUN state";
    /// System logs: 0 disable, 1 enable.
    SystemLog = "SYSTEM_LOG", 9, 0..=1, None, None, "System logs";
    /// System statistics protocol: 0 none, 1 CSV, 2 JSON.
    SystemStatistics = "SYSTEM_STATISTICS", 9, 0..=2, None, None, "System statistics protocol";
    /// ADS-B decoded protocol, [`DecodedProtocol`].
    AdsbRxProtocolDecoded = "ADSB_RX_PROTOCOL_DECODED", 12, 0..=5, None, Some(1), "ADS-B decoded protocol";
    /// Reporting mode of decoded ADS-B targets, [`ReportingMode`].
    AdsbRxProtocolInc = "ADSB_RX_PROTOCOL_INC", 12, 0..=2, None, None, "Reporting mode of decoded ADS-B targets";
    /// ADS-B raw protocol, [`RawProtocol`].
    AdsbRxProtocolRaw = "ADSB_RX_PROTOCOL_RAW", 12, 0..=4, None, Some(0), "ADS-B raw protocol";
    /// ADS-B statistics protocol: 0 none, 1 CSV, 2 JSON.
    AdsbStatistics = "ADSB_STATISTICS", 12, 0..=2, None, Some(1), "ADS-B statistics protocol";
    /// ASTERIX system area code.
    AsterixSac = "ASTERIX_SAC", 13, 0..=255, None, None, "SAC for ASTERIX protocol";
    /// ASTERIX system identification code.
    AsterixSic = "ASTERIX_SIC", 13, 0..=255, None, Some(129), "SIC for ASTERIX protocol";
    /// FLARM decoded protocol: 0 none, 1 CSV, 2 Mavlink, 3 JSON, 5 ASTERIX.
    FlarmRxProtocolDecoded = "FLARM_RX_PROTOCOL_DECODED", 24, 0..=5, Some(&[0, 1, 2, 3, 5]), Some(0), "FLARM decoded protocol";
    /// FLARM statistics protocol: 0 none, 1 CSV, 2 JSON.
    FlarmStatistics = "FLARM_STATISTICS", 24, 0..=2, None, Some(0), "FLARM statistics protocol";
    /// FLARM transmitter: 0 disable, 1 enable.
    FlarmTx = "FLARM_TX", 24, 0..=1, None, None, "Enable FLARM out";
    /// FLARM aircraft type sent by this module (table 26).
    FlarmTxAircraftType = "FLARM_TX_AIRCRAFT_TYPE", 24, 0..=15, None, Some(13), "FLARM aircraft type";
    /// GNSS raw protocol: 0 none, 5 NMEA.
    GnssRxProtocolRaw = "GNSS_RX_PROTOCOL_RAW", 31, 0..=5, Some(&[0, 5]), Some(0), "GNSS raw protocol";
    /// UAT receiver mode, [`UatMode`].
    UatMode = "UAT_MODE", 33, 0..=3, None, None, "Mode of UAT receiver";
    /// UAT decoded protocol: 1 CSV, 2 Mavlink, 3 JSON.
    UatDecodedProtocol = "UAT_DECODED_PROTOCOL", 33, 1..=3, None, Some(1), "UAT decoded protocol";
    /// UAT raw protocol: 1 HEX, 4 HEXd (dump978).
    UatRawProtocol = "UAT_RAW_PROTOCOL", 33, 1..=4, Some(&[1, 4]), Some(1), "UAT raw protocol";
}

impl SettingId {
    /// The name used in AT commands.
    pub const fn name(self) -> &'static str {
        self.spec().name
    }

    /// Looks a name up, ignoring case (CONFIGURATION state accepts any case, manual 5.1.6).
    pub fn from_name(name: &str) -> Option<SettingId> {
        SettingId::ALL
            .iter()
            .copied()
            .find(|id| id.name().eq_ignore_ascii_case(name))
    }

    /// Whether `value` is allowed.
    pub fn allows(self, value: i64) -> bool {
        let s = self.spec();
        (s.min..=s.max).contains(&value) && s.allowed.is_none_or(|a| a.contains(&value))
    }
}

impl fmt::Display for SettingId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A setting with a value checked against its range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct Setting {
    id: SettingId,
    value: i64,
}

impl Setting {
    /// A setting value, checked.
    pub fn new(id: SettingId, value: i64) -> Result<Self, SettingError> {
        if id.allows(value) {
            Ok(Self { id, value })
        } else {
            Err(SettingError::OutOfRange {
                name: id.name(),
                value,
            })
        }
    }

    /// Parses the value text of `AT+NAME=VALUE` for a setting.
    pub fn parse(id: SettingId, text: &str) -> Result<Self, SettingError> {
        let v = text
            .trim()
            .parse::<i64>()
            .map_err(|_| SettingError::NotInteger {
                name: id.name(),
                value: text.chars().take(32).collect(),
            })?;
        Self::new(id, v)
    }

    /// Which setting.
    pub fn id(&self) -> SettingId {
        self.id
    }

    /// The value as sent on the wire.
    pub fn value(&self) -> i64 {
        self.value
    }

    /// `BAUDRATE`.
    pub fn baudrate(b: Baudrate) -> Self {
        Self {
            id: SettingId::Baudrate,
            value: b as i64,
        }
    }

    /// `ADSB_RX_PROTOCOL_DECODED`.
    pub fn adsb_decoded(p: DecodedProtocol) -> Self {
        Self {
            id: SettingId::AdsbRxProtocolDecoded,
            value: p as i64,
        }
    }

    /// `ADSB_RX_PROTOCOL_RAW`.
    pub fn adsb_raw(p: RawProtocol) -> Self {
        Self {
            id: SettingId::AdsbRxProtocolRaw,
            value: p as i64,
        }
    }

    /// `FLARM_RX_PROTOCOL_DECODED` (GDL90 carries no FLARM targets: refused).
    pub fn flarm_decoded(p: DecodedProtocol) -> Result<Self, SettingError> {
        Self::new(SettingId::FlarmRxProtocolDecoded, p as i64)
    }

    /// `GNSS_RX_PROTOCOL_RAW`: NMEA on or off.
    pub fn gnss_nmea(on: bool) -> Self {
        Self {
            id: SettingId::GnssRxProtocolRaw,
            value: if on { 5 } else { 0 },
        }
    }

    /// `UAT_MODE`.
    pub fn uat_mode(m: UatMode) -> Self {
        Self {
            id: SettingId::UatMode,
            value: m as i64,
        }
    }

    /// `UAT_DECODED_PROTOCOL` (only CSV, Mavlink, JSON).
    pub fn uat_decoded(p: DecodedProtocol) -> Result<Self, SettingError> {
        Self::new(SettingId::UatDecodedProtocol, p as i64)
    }

    /// The baud this setting selects, for `BAUDRATE`.
    pub fn as_baudrate(&self) -> Option<Baudrate> {
        (self.id == SettingId::Baudrate)
            .then(|| Baudrate::from_value(self.value))
            .flatten()
    }
}

/// `BAUDRATE` values (table 9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum Baudrate {
    /// 0: 115200 bps.
    B115200 = 0,
    /// 1: 921600 bps.
    B921600 = 1,
    /// 2: 3000000 bps.
    B3000000 = 2,
    /// 3: 57600 bps.
    B57600 = 3,
}

impl Baudrate {
    /// From the setting value.
    pub fn from_value(v: i64) -> Option<Self> {
        Some(match v {
            0 => Baudrate::B115200,
            1 => Baudrate::B921600,
            2 => Baudrate::B3000000,
            3 => Baudrate::B57600,
            _ => return None,
        })
    }

    /// Bits per second.
    pub const fn bps(self) -> u32 {
        match self {
            Baudrate::B115200 => 115_200,
            Baudrate::B921600 => 921_600,
            Baudrate::B3000000 => 3_000_000,
            Baudrate::B57600 => 57_600,
        }
    }
}

/// Decoded-protocol selector values (table 12; see the module doc for the subsets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum DecodedProtocol {
    /// 0: none.
    None = 0,
    /// 1: CSV.
    Csv = 1,
    /// 2: MAVLink.
    Mavlink = 2,
    /// 3: JSON.
    Json = 3,
    /// 4: GDL90 (ADS-B only).
    Gdl90 = 4,
    /// 5: ASTERIX.
    Asterix = 5,
}

/// Raw-protocol selector values (table 12).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum RawProtocol {
    /// 0: none.
    None = 0,
    /// 1: HEX with extended fields.
    Hex = 1,
    /// 2: Beast.
    Beast = 2,
    /// 3: JSON `raw` section.
    Json = 3,
    /// 4: HEXd (dump1090 / dump978).
    Hexd = 4,
}

/// `ADSB_RX_PROTOCOL_INC` values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum ReportingMode {
    /// 0: once per second, always.
    EverySecond = 0,
    /// 1: once per second if data updated.
    EverySecondIfUpdated = 1,
    /// 2: immediately, only after a position update.
    OnPositionUpdate = 2,
}

/// `UAT_MODE` values (table 33).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub enum UatMode {
    /// 0: none.
    None = 0,
    /// 1: raw only.
    RawOnly = 1,
    /// 2: decoded only.
    DecodedOnly = 2,
    /// 3: raw and decoded.
    Both = 3,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_follow_the_tables() {
        assert!(Setting::new(SettingId::SystemStatistics, 2).is_ok());
        // 5.1.3 example: SYSTEM_STATISTICS range 0..2.
        assert!(Setting::new(SettingId::SystemStatistics, 3).is_err());
        assert!(Setting::new(SettingId::AsterixSic, 255).is_ok());
        assert!(Setting::new(SettingId::AsterixSic, 256).is_err());
        assert!(Setting::new(SettingId::FlarmTxAircraftType, 15).is_ok());
        assert!(Setting::new(SettingId::FlarmTxAircraftType, 16).is_err());
        assert!(
            Setting::new(SettingId::GnssRxProtocolRaw, 3).is_err(),
            "only 0 and 5"
        );
        assert!(Setting::flarm_decoded(DecodedProtocol::Gdl90).is_err());
        assert!(Setting::flarm_decoded(DecodedProtocol::Asterix).is_ok());
        assert!(Setting::uat_decoded(DecodedProtocol::None).is_err());
        assert!(Setting::new(SettingId::UatRawProtocol, 2).is_err());
        assert_eq!(SettingId::AsterixSic.spec().default, Some(129));
        assert_eq!(SettingId::FlarmTxAircraftType.spec().default, Some(13));
    }

    #[test]
    fn manual_examples() {
        // 5.1.8: AT+ADSB_RX_PROTOCOL_DECODED=1 switches to CSV.
        assert_eq!(Setting::adsb_decoded(DecodedProtocol::Csv).value(), 1);
        // 5.1.6: names are case-insensitive in CONFIGURATION state.
        assert_eq!(
            SettingId::from_name("sYSTEM_staTISTICS"),
            Some(SettingId::SystemStatistics)
        );
        assert_eq!(
            Setting::parse(SettingId::Baudrate, "1")
                .unwrap()
                .as_baudrate(),
            Some(Baudrate::B921600)
        );
        assert_eq!(Baudrate::B3000000.bps(), 3_000_000);
        assert!(Setting::parse(SettingId::Baudrate, "x").is_err());
        assert!(Setting::parse(SettingId::Baudrate, "4").is_err());
    }
}
