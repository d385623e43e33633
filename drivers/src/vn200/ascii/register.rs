//! Register contents for `$VNRRG` responses and `$VNWRG` commands (ICD chapters 3 and 4), for the
//! registers vigil uses: 1-8, 30, 32, 33, 55, 57, 58, 59, 63, 64, 67, 72, 73, 75-77, 99, 101,
//! 102 (and every measurement register, see [`Measurement`]). Others are kept as raw fields.

use serde::Serialize;

use super::fields::{AsciiRecord, Fields, ascii_record};
use super::{AsciiError, Measurement};

ascii_record! {
    /// Register 30: communication protocol control (3.2.5), enumerations kept raw.
    pub struct CommProtocolControl {
        /// Counter appended to ASCII outputs (Table 3.12).
        pub ascii_append_count: u8,
        /// Status appended to ASCII outputs (Table 3.13).
        pub ascii_append_status: u8,
        /// Counter appended to SPI outputs.
        pub spi_append_count: u8,
        /// Status appended to SPI outputs.
        pub spi_append_status: u8,
        /// ASCII checksum: 1 = 8-bit XOR, 3 = 16-bit CRC.
        pub ascii_checksum: u8,
        /// SPI checksum: 0 off, 1 XOR, 3 CRC.
        pub spi_checksum: u8,
        /// Error mode: 0 ignore, 1 send, 2 send and ADOR off.
        pub error_mode: u8,
    }
}

ascii_record! {
    /// Register 32: synchronization control (3.2.6).
    pub struct SyncControl {
        /// SyncIn mode (Table 3.20).
        pub sync_in_mode: u8,
        /// SyncIn edge: 0 rising, 1 falling.
        pub sync_in_edge: u8,
        /// SyncIn skip factor.
        pub sync_in_skip_factor: u16,
        /// Reserved (kept).
        pub resv1: u32,
        /// SyncOut mode (Table 3.22).
        pub sync_out_mode: u8,
        /// SyncOut polarity: 0 negative, 1 positive pulse.
        pub sync_out_polarity: u8,
        /// SyncOut skip factor.
        pub sync_out_skip_factor: u16,
        /// SyncOut pulse width, ns.
        pub sync_out_pulse_width_ns: u32,
        /// Reserved (kept).
        pub resv2: u32,
    }
}

ascii_record! {
    /// Register 33: synchronization status (4.2.5).
    pub struct SyncStatus {
        /// SyncIn events.
        pub sync_in_count: u32,
        /// Time since the last SyncIn event, microseconds.
        pub sync_in_time_us: u32,
        /// SyncOut pulses.
        pub sync_out_count: u32,
    }
}

ascii_record! {
    /// Register 55: GNSS basic configuration (3.7.1).
    pub struct GnssBasicConfig {
        /// Receiver enable (Table 3.76).
        pub receiver_enable: u8,
        /// PPS source (Table 3.77).
        pub pps_source: u8,
        /// Measurement rate, Hz.
        pub rate_hz: u8,
        /// Reserved (kept).
        pub resv4: u8,
        /// Reserved (kept).
        pub resv5: u8,
    }
}

ascii_record! {
    /// Register 67: INS basic configuration (3.8.1).
    pub struct InsBasicConfig {
        /// Scenario: 0 AHRS, 1 GNSS/INS with pressure, 2 without.
        pub scenario: u8,
        /// AHRS aiding: 0 off, 1 on.
        pub ahrs_aiding: u8,
        /// Reserved (kept).
        pub resv1: u8,
        /// Reserved (kept).
        pub resv2: u8,
    }
}

/// Register 99: GNSS system configuration (3.7.3). Bitfields are hex on the wire, counts decimal
/// (the example `0013,10,10,16,02,EBF9,003F,0000` has MinCno 10 dB and MaxSats 16).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct GnssSystemConfig {
    /// Enabled constellations (Table 3.81), hex.
    pub systems: u16,
    /// Minimum CN0, dB.
    pub min_cno_db: u8,
    /// Minimum elevation, degrees.
    pub min_elev_deg: u8,
    /// Maximum satellites.
    pub max_sats: u8,
    /// SBAS mode bits (Table 3.82), hex.
    pub sbas_mode: u8,
    /// SBAS PRN masks 120-135, 136-151, 152-158 (hex).
    pub sbas_select: [u16; 3],
}

impl AsciiRecord for GnssSystemConfig {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(Self {
            systems: f.hex(4)? as u16,
            min_cno_db: f.u8()?,
            min_elev_deg: f.u8()?,
            max_sats: f.u8()?,
            sbas_mode: f.hex(2)? as u8,
            sbas_select: [f.hex(4)? as u16, f.hex(4)? as u16, f.hex(4)? as u16],
        })
    }
    fn format(&self, out: &mut String) {
        out.push_str(&format!(
            ",{:04X},{},{},{},{:02X},{:04X},{:04X},{:04X}",
            self.systems,
            self.min_cno_db,
            self.min_elev_deg,
            self.max_sats,
            self.sbas_mode,
            self.sbas_select[0],
            self.sbas_select[1],
            self.sbas_select[2]
        ));
    }
}

/// Registers 101 and 102: NMEA output (3.2.10). MsgSelection is hex on the wire.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct NmeaOutputConfig {
    /// Serial port(s): 0 none, 1, 2, 3 both.
    pub port: u8,
    /// Rate, Hz.
    pub rate_hz: u8,
    /// NMEA mode (Table 3.33).
    pub mode: u8,
    /// GNSS source (Table 3.34).
    pub gnss_select: u8,
    /// Message selection bits (Table 3.35), hex.
    pub msg_selection: u32,
}

impl AsciiRecord for NmeaOutputConfig {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(Self {
            port: f.u8()?,
            rate_hz: f.u8()?,
            mode: f.u8()?,
            gnss_select: f.u8()?,
            msg_selection: f.hex(8)?,
        })
    }
    fn format(&self, out: &mut String) {
        out.push_str(&format!(
            ",{},{},{},{},{:08X}",
            self.port, self.rate_hz, self.mode, self.gnss_select, self.msg_selection
        ));
    }
}

/// Registers 75-77: binary output message configuration (3.2.7, Appendix A.1.1, B.1.1).
///
/// On the wire: AsyncMode and RateDivisor in decimal, then the group byte(s) and type word(s)
/// in hex, exactly as in the binary message header (extension bits included).
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct BinaryOutputConfig {
    /// Serial ports the message is sent on at a fixed rate (bit 0 port 1, bit 1 port 2);
    /// 0 turns the output off.
    pub async_mode: u16,
    /// Output rate as a divisor of the IMU rate (800 Hz on the VN-200).
    pub rate_divisor: u16,
    /// Group byte(s), extension bits included.
    pub group_bytes: Vec<u8>,
    /// Type word(s) of the active groups in group order, extension bits included.
    pub type_words: Vec<u16>,
}

impl BinaryOutputConfig {
    /// The configuration for the given type masks (table offsets, indexed by group offset; see
    /// [`crate::vn200::binary::type_words`]).
    pub fn from_masks(async_mode: u16, rate_divisor: u16, masks: [u32; 7]) -> Self {
        let mut group = 0u8;
        let mut words = Vec::new();
        for (g, &m) in masks.iter().enumerate() {
            if m != 0 {
                group |= 1 << g;
                let (w0, w1) = crate::vn200::binary::type_words(m);
                words.push(w0);
                words.extend(w1);
            }
        }
        Self {
            async_mode,
            rate_divisor,
            group_bytes: vec![group],
            type_words: words,
        }
    }

    /// The type masks (table offsets) per group offset 0-6, if the group and type fields are
    /// consistent (one or two words per active group, no groups beyond 6).
    pub fn masks(&self) -> Option<[u32; 7]> {
        let mut masks = [0u32; 7];
        let first = *self.group_bytes.first()?;
        if self.group_bytes.iter().skip(1).any(|b| b & 0x7F != 0) {
            return None;
        }
        let mut words = self.type_words.iter();
        for (g, m) in masks.iter_mut().enumerate() {
            if first & (1 << g) != 0 {
                let w0 = *words.next()?;
                *m = u32::from(w0 & 0x7FFF);
                if w0 & 0x8000 != 0 {
                    *m |= u32::from(*words.next()? & 0x7FFF) << 16;
                }
            }
        }
        words.next().is_none().then_some(masks)
    }
}

impl AsciiRecord for BinaryOutputConfig {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        let async_mode = f.u16()?;
        let rate_divisor = f.u16()?;
        let mut group_bytes = Vec::new();
        loop {
            let b = f.hex(2)? as u8;
            group_bytes.push(b);
            if b & 0x80 == 0 {
                break;
            }
            if group_bytes.len() == 4 {
                return Err(f.bad("more than four group bytes"));
            }
        }
        let mut type_words = Vec::new();
        while !f.is_empty() {
            type_words.push(f.hex(4)? as u16);
        }
        Ok(Self {
            async_mode,
            rate_divisor,
            group_bytes,
            type_words,
        })
    }
    fn format(&self, out: &mut String) {
        out.push_str(&format!(",{},{}", self.async_mode, self.rate_divisor));
        for b in &self.group_bytes {
            out.push_str(&format!(",{b:02X}"));
        }
        for w in &self.type_words {
            out.push_str(&format!(",{w:04X}"));
        }
    }
}

/// The contents of one register.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "register", rename_all = "snake_case")]
pub enum RegisterValue {
    /// Register 1: product model string.
    Model {
        /// Model, up to 24 characters.
        model: String,
    },
    /// Register 2: hardware version.
    HardwareVersion {
        /// Version number.
        version: u32,
    },
    /// Register 3: serial number.
    SerialNumber {
        /// Serial number.
        serial: u32,
    },
    /// Register 4: firmware version string.
    FirmwareVersion {
        /// Version, e.g. `2.1.0.0`.
        version: String,
    },
    /// Register 5: baud rate, with the optional serial port.
    BaudRate {
        /// Baud rate, bit/s.
        baud: u32,
        /// Serial port (0 active, 1, 2) if given.
        #[serde(skip_serializing_if = "Option::is_none")]
        port: Option<u8>,
    },
    /// Register 6: async data output type (ADOR, Table 3.6), with the optional port.
    AsyncOutputType {
        /// ADOR value (0 off, 1 YPR, ... 22 INS).
        ador: u32,
        /// Serial port if given.
        #[serde(skip_serializing_if = "Option::is_none")]
        port: Option<u8>,
    },
    /// Register 7: async data output frequency, with the optional port.
    AsyncOutputFreq {
        /// Output rate, Hz.
        rate_hz: u32,
        /// Serial port if given.
        #[serde(skip_serializing_if = "Option::is_none")]
        port: Option<u8>,
    },
    /// Register 30.
    CommProtocol(CommProtocolControl),
    /// Register 32.
    SyncControl(SyncControl),
    /// Register 33.
    SyncStatus(SyncStatus),
    /// Register 55.
    GnssBasic(GnssBasicConfig),
    /// Register 57: GNSS A antenna offset in the body frame, m.
    GnssAntennaOffset {
        /// x, y, z, m.
        position_m: [f32; 3],
    },
    /// Register 67.
    InsBasic(InsBasicConfig),
    /// Registers 75, 76, 77.
    BinaryOutput {
        /// Which configuration: 1 (Register 75), 2 (76) or 3 (77).
        index: u8,
        /// The configuration.
        config: BinaryOutputConfig,
    },
    /// Register 99.
    GnssSystem(GnssSystemConfig),
    /// Registers 101 and 102.
    NmeaOutput {
        /// 1 (Register 101) or 2 (Register 102).
        index: u8,
        /// The configuration.
        config: NmeaOutputConfig,
    },
    /// A measurement register (8, 9, 15, 17-20, 27, 54, 58, 59, 63, 64, 72, 73, 80, 115, 239,
    /// 240).
    Measurement(Measurement),
    /// Any other register, fields kept as text.
    Other {
        /// Register id.
        id: u8,
        /// The fields as sent.
        fields: Vec<String>,
    },
}

impl RegisterValue {
    /// The register id.
    pub fn id(&self) -> u8 {
        match self {
            Self::Model { .. } => 1,
            Self::HardwareVersion { .. } => 2,
            Self::SerialNumber { .. } => 3,
            Self::FirmwareVersion { .. } => 4,
            Self::BaudRate { .. } => 5,
            Self::AsyncOutputType { .. } => 6,
            Self::AsyncOutputFreq { .. } => 7,
            Self::CommProtocol(_) => 30,
            Self::SyncControl(_) => 32,
            Self::SyncStatus(_) => 33,
            Self::GnssBasic(_) => 55,
            Self::GnssAntennaOffset { .. } => 57,
            Self::InsBasic(_) => 67,
            Self::BinaryOutput { index, .. } => 74 + index,
            Self::GnssSystem(_) => 99,
            Self::NmeaOutput { index, .. } => 100 + index,
            Self::Measurement(m) => m.register_id(),
            Self::Other { id, .. } => *id,
        }
    }

    /// Parses the fields after the register id.
    pub(crate) fn parse(id: u8, f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        fn opt_port(f: &mut Fields<'_>) -> Result<Option<u8>, AsciiError> {
            if f.is_empty() {
                Ok(None)
            } else {
                f.u8().map(Some)
            }
        }
        Ok(match id {
            1 => Self::Model {
                model: f.rest().join(","),
            },
            2 => Self::HardwareVersion { version: f.u32()? },
            3 => Self::SerialNumber { serial: f.u32()? },
            4 => Self::FirmwareVersion {
                version: f.rest().join(","),
            },
            5 => Self::BaudRate {
                baud: f.u32()?,
                port: opt_port(f)?,
            },
            6 => Self::AsyncOutputType {
                ador: f.u32()?,
                port: opt_port(f)?,
            },
            7 => Self::AsyncOutputFreq {
                rate_hz: f.u32()?,
                port: opt_port(f)?,
            },
            30 => Self::CommProtocol(CommProtocolControl::parse(f)?),
            32 => Self::SyncControl(SyncControl::parse(f)?),
            33 => Self::SyncStatus(SyncStatus::parse(f)?),
            55 => Self::GnssBasic(GnssBasicConfig::parse(f)?),
            57 => Self::GnssAntennaOffset {
                position_m: <[f32; 3]>::parse(f)?,
            },
            67 => Self::InsBasic(InsBasicConfig::parse(f)?),
            75..=77 => Self::BinaryOutput {
                index: id - 74,
                config: BinaryOutputConfig::parse(f)?,
            },
            99 => Self::GnssSystem(GnssSystemConfig::parse(f)?),
            101 | 102 => Self::NmeaOutput {
                index: id - 100,
                config: NmeaOutputConfig::parse(f)?,
            },
            _ if Measurement::is_measurement_register(id) => {
                Self::Measurement(Measurement::parse_register(id, f)?)
            }
            _ => Self::Other {
                id,
                fields: f.rest().iter().map(|s| s.to_string()).collect(),
            },
        })
    }

    /// The fields as written after the command header: `<id>,<fields...>`.
    pub fn body(&self) -> String {
        let mut s = self.id().to_string();
        match self {
            Self::Model { model: v } | Self::FirmwareVersion { version: v } => {
                s.push(',');
                s.push_str(v);
            }
            Self::HardwareVersion { version: v } | Self::SerialNumber { serial: v } => {
                v.format(&mut s)
            }
            Self::BaudRate { baud: v, port }
            | Self::AsyncOutputType { ador: v, port }
            | Self::AsyncOutputFreq { rate_hz: v, port } => {
                v.format(&mut s);
                if let Some(p) = port {
                    p.format(&mut s);
                }
            }
            Self::CommProtocol(v) => v.format(&mut s),
            Self::SyncControl(v) => v.format(&mut s),
            Self::SyncStatus(v) => v.format(&mut s),
            Self::GnssBasic(v) => v.format(&mut s),
            Self::GnssAntennaOffset { position_m } => position_m.format(&mut s),
            Self::InsBasic(v) => v.format(&mut s),
            Self::BinaryOutput { config, .. } => config.format(&mut s),
            Self::GnssSystem(v) => v.format(&mut s),
            Self::NmeaOutput { config, .. } => config.format(&mut s),
            Self::Measurement(m) => m.format(&mut s),
            Self::Other { fields, .. } => {
                for x in fields {
                    s.push(',');
                    s.push_str(x);
                }
            }
        }
        s
    }
}
