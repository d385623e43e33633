//! Host commands (ICD 1.3) and their echoes: the sensor echoes every valid command after
//! processing it (resetting commands just before the reset), except VNBOM, answered with the
//! binary message itself.

use serde::Serialize;

use super::fields::{AsciiRecord, Fields};
use super::{AsciiError, ChecksumKind, RegisterValue, frame_sentence};
use crate::vn200::binary::{Quaternion, Ypr};

/// Argument of Set Initial Heading (1.3.9): one, three or four floats.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InitialHeading {
    /// Heading only, degrees.
    Heading {
        /// Heading, degrees.
        heading_deg: f32,
    },
    /// Yaw, pitch, roll, degrees.
    Ypr(Ypr),
    /// Quaternion (x, y, z, scalar).
    Quaternion(Quaternion),
}

/// A command sent by the host (and echoed by the sensor).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "command", content = "args", rename_all = "snake_case")]
pub enum Command {
    /// VNRRG: read a register.
    ReadRegister(u8),
    /// VNWRG: write a register (the echo carries the register's contents).
    WriteRegister(RegisterValue),
    /// VNWNV: save the configuration to flash.
    WriteSettings,
    /// VNRFS: restore factory settings (resets).
    RestoreFactorySettings,
    /// VNRST: reset.
    Reset,
    /// VNFWU: enter the bootloader (serial port 1 only).
    FirmwareUpdate,
    /// VNKMD: known magnetic disturbance present (true) or not.
    KnownMagneticDisturbance(bool),
    /// VNKAD: known acceleration disturbance present (true) or not.
    KnownAccelerationDisturbance(bool),
    /// VNSIH: set the initial heading.
    SetInitialHeading(InitialHeading),
    /// VNASY: enable (true) or pause all async outputs on this port.
    AsyncOutputEnable(bool),
    /// VNSFB: copy the filter bias estimates into Register 74.
    SetFilterBias,
    /// VNBOM: poll binary output message 1, 2 or 3 (answered by the binary message).
    PollBinaryOutput(u8),
}

impl Command {
    /// The sentence header.
    pub fn header(&self) -> &'static str {
        match self {
            Self::ReadRegister(_) => "VNRRG",
            Self::WriteRegister(_) => "VNWRG",
            Self::WriteSettings => "VNWNV",
            Self::RestoreFactorySettings => "VNRFS",
            Self::Reset => "VNRST",
            Self::FirmwareUpdate => "VNFWU",
            Self::KnownMagneticDisturbance(_) => "VNKMD",
            Self::KnownAccelerationDisturbance(_) => "VNKAD",
            Self::SetInitialHeading(_) => "VNSIH",
            Self::AsyncOutputEnable(_) => "VNASY",
            Self::SetFilterBias => "VNSFB",
            Self::PollBinaryOutput(_) => "VNBOM",
        }
    }

    /// Whether the sensor echoes this command (all but VNBOM, 1.3.12).
    pub fn is_echoed(&self) -> bool {
        !matches!(self, Self::PollBinaryOutput(_))
    }

    /// The sentence body (between `$` and `*`).
    pub fn body(&self) -> String {
        let mut s = self.header().to_string();
        match self {
            Self::ReadRegister(id) => id.format(&mut s),
            Self::WriteRegister(v) => {
                s.push(',');
                s.push_str(&v.body());
            }
            Self::KnownMagneticDisturbance(b)
            | Self::KnownAccelerationDisturbance(b)
            | Self::AsyncOutputEnable(b) => u8::from(*b).format(&mut s),
            Self::SetInitialHeading(h) => match h {
                InitialHeading::Heading { heading_deg } => heading_deg.format(&mut s),
                InitialHeading::Ypr(v) => v.format(&mut s),
                InitialHeading::Quaternion(q) => q.format(&mut s),
            },
            Self::PollBinaryOutput(n) => n.format(&mut s),
            Self::WriteSettings
            | Self::RestoreFactorySettings
            | Self::Reset
            | Self::FirmwareUpdate
            | Self::SetFilterBias => {}
        }
        s
    }

    /// The framed sentence with the given checksum style.
    pub fn encode(&self, kind: ChecksumKind) -> Vec<u8> {
        frame_sentence(&self.body(), kind)
    }

    /// Parses a command (or echo) other than VNRRG (handled by the caller).
    pub(crate) fn parse(header: &str, f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        fn flag(f: &mut Fields<'_>) -> Result<bool, AsciiError> {
            match f.u8()? {
                0 => Ok(false),
                1 => Ok(true),
                _ => Err(f.bad("state must be 0 or 1")),
            }
        }
        Ok(match header {
            "VNWRG" => {
                let id = f.u8()?;
                Self::WriteRegister(RegisterValue::parse(id, f)?)
            }
            "VNWNV" => Self::WriteSettings,
            "VNRFS" => Self::RestoreFactorySettings,
            "VNRST" => Self::Reset,
            "VNFWU" => Self::FirmwareUpdate,
            "VNSFB" => Self::SetFilterBias,
            "VNKMD" => Self::KnownMagneticDisturbance(flag(f)?),
            "VNKAD" => Self::KnownAccelerationDisturbance(flag(f)?),
            "VNASY" => Self::AsyncOutputEnable(flag(f)?),
            "VNBOM" => Self::PollBinaryOutput(f.u8()?),
            "VNSIH" => Self::SetInitialHeading(match f.remaining() {
                1 => InitialHeading::Heading {
                    heading_deg: f.f32()?,
                },
                3 => InitialHeading::Ypr(Ypr::parse(f)?),
                4 => InitialHeading::Quaternion(Quaternion::parse(f)?),
                _ => return Err(f.bad("VNSIH takes 1, 3 or 4 values")),
            }),
            _ => return Err(AsciiError::UnknownHeader(header.to_string())),
        })
    }
}

/// Encodes commands for a `FramedWrite` (8-bit XOR checksums, the sensor's default).
#[derive(Debug, Clone, Copy, Default)]
pub struct CommandEncoder;

impl tokio_util::codec::Encoder<Command> for CommandEncoder {
    type Error = std::io::Error;

    fn encode(&mut self, item: Command, dst: &mut bytes::BytesMut) -> Result<(), Self::Error> {
        dst.extend_from_slice(&item.encode(ChecksumKind::Xor8));
        Ok(())
    }
}
