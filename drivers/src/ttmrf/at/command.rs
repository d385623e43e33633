//! Commands the host sends (manual 5.1, 5.2), their encoding, and their parsing on the module
//! side (used by the simulator), with the case rules of 5.1.6 and the line endings of 5.1.5.
//!
//! Encoding always uses upper case and `\r\n`, which every state accepts. Parsing accepts the
//! three documented endings (`\n`, `\r`, `\r\n`; the framing is the caller's) and, in
//! CONFIGURATION and RUN state, any case after the `AT+` prefix; in BOOTLOADER state every letter
//! must be upper case.

use bytes::{BufMut, BytesMut};

use super::settings::{Setting, SettingError, SettingId};

/// `AT+CONFIG` values (5.2.2, 5.2.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ConfigMode {
    /// 0: RUN state.
    Run = 0,
    /// 1: CONFIGURATION at 115200 bps.
    Config115200 = 1,
    /// 2: CONFIGURATION at the baud set in `BAUDRATE`.
    ConfigAsSet = 2,
}

impl ConfigMode {
    /// From the wire value.
    pub fn from_value(v: i64) -> Option<Self> {
        Some(match v {
            0 => ConfigMode::Run,
            1 => ConfigMode::Config115200,
            2 => ConfigMode::ConfigAsSet,
            _ => return None,
        })
    }
}

/// A host command.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum AtCommand {
    /// `AT+NAME=VALUE` for a setting of the tables.
    Write(Setting),
    /// `AT+NAME?`.
    Read(SettingId),
    /// `AT+NAME=?`: the setting's description.
    Describe(SettingId),
    /// `AT+SETTINGS?`: list all settings.
    Settings,
    /// `AT+HELP`.
    Help,
    /// `AT+LOCK=0|1`.
    Lock(bool),
    /// `AT+LOCK?`.
    LockQuery,
    /// `AT+BOOT?`.
    BootQuery,
    /// `AT+CONFIG=0|1|2`.
    Config(ConfigMode),
    /// `AT+CONFIG?`.
    ConfigQuery,
    /// `AT+SETTINGS_DEFAULT`.
    SettingsDefault,
    /// `AT+SERIAL_NUMBER?`.
    SerialNumberQuery,
    /// `AT+FIRMWARE_VERSION?`.
    FirmwareVersionQuery,
    /// `AT+REBOOT`.
    Reboot,
    /// `AT+REBOOT_BOOTLOADER` (also sets the lock).
    RebootBootloader,
    /// Any other `AT+...` text (settings outside the tables, such as `ADSB_TX_ICAO`), upper-cased.
    Other(String),
}

/// Why a command line was refused (module side).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum CommandError {
    /// Does not start with `AT+`.
    #[error("command does not start with 'AT+'")]
    NoPrefix,
    /// Lower-case letters in BOOTLOADER state.
    #[error("lower case is not accepted in bootloader state")]
    LowerCase,
    /// A bad value for a known setting or command.
    #[error(transparent)]
    Setting(#[from] SettingError),
    /// A bad value for LOCK or CONFIG.
    #[error("bad value for {0}")]
    BadValue(&'static str),
}

impl AtCommand {
    /// The command text without `AT+` and line ending.
    pub fn body(&self) -> String {
        match self {
            AtCommand::Write(s) => format!("{}={}", s.id().name(), s.value()),
            AtCommand::Read(id) => format!("{}?", id.name()),
            AtCommand::Describe(id) => format!("{}=?", id.name()),
            AtCommand::Settings => "SETTINGS?".into(),
            AtCommand::Help => "HELP".into(),
            AtCommand::Lock(on) => format!("LOCK={}", u8::from(*on)),
            AtCommand::LockQuery => "LOCK?".into(),
            AtCommand::BootQuery => "BOOT?".into(),
            AtCommand::Config(m) => format!("CONFIG={}", *m as u8),
            AtCommand::ConfigQuery => "CONFIG?".into(),
            AtCommand::SettingsDefault => "SETTINGS_DEFAULT".into(),
            AtCommand::SerialNumberQuery => "SERIAL_NUMBER?".into(),
            AtCommand::FirmwareVersionQuery => "FIRMWARE_VERSION?".into(),
            AtCommand::Reboot => "REBOOT".into(),
            AtCommand::RebootBootloader => "REBOOT_BOOTLOADER".into(),
            AtCommand::Other(s) => s.clone(),
        }
    }

    /// The full line: `AT+<body>\r\n`.
    pub fn to_line(&self) -> String {
        format!("AT+{}\r\n", self.body())
    }

    /// Parses a command line (terminator removed) as the module does. `bootloader` selects the
    /// upper-case-only rule of 5.1.6.
    pub fn parse(line: &str, bootloader: bool) -> Result<AtCommand, CommandError> {
        let rest = line
            .trim_end()
            .strip_prefix("AT+")
            .ok_or(CommandError::NoPrefix)?;
        if bootloader && rest.bytes().any(|b| b.is_ascii_lowercase()) {
            return Err(CommandError::LowerCase);
        }
        let up = rest.to_ascii_uppercase();
        let (name, arg) = match up.split_once('=') {
            Some((n, a)) => (n.to_owned(), Some(a.to_owned())),
            None => (up.clone(), None),
        };
        let flag = |a: &str, what: &'static str| match a {
            "0" => Ok(false),
            "1" => Ok(true),
            _ => Err(CommandError::BadValue(what)),
        };
        Ok(match (name.as_str(), arg.as_deref()) {
            ("SETTINGS?", None) => AtCommand::Settings,
            ("HELP", None) => AtCommand::Help,
            ("LOCK?", None) => AtCommand::LockQuery,
            ("LOCK", Some(a)) => AtCommand::Lock(flag(a, "LOCK")?),
            ("BOOT?", None) => AtCommand::BootQuery,
            ("CONFIG?", None) => AtCommand::ConfigQuery,
            ("CONFIG", Some(a)) => AtCommand::Config(
                a.parse::<i64>()
                    .ok()
                    .and_then(ConfigMode::from_value)
                    .ok_or(CommandError::BadValue("CONFIG"))?,
            ),
            ("SETTINGS_DEFAULT", None) => AtCommand::SettingsDefault,
            ("SERIAL_NUMBER?", None) => AtCommand::SerialNumberQuery,
            ("FIRMWARE_VERSION?", None) => AtCommand::FirmwareVersionQuery,
            ("REBOOT", None) => AtCommand::Reboot,
            ("REBOOT_BOOTLOADER", None) => AtCommand::RebootBootloader,
            (n, None) if n.ends_with('?') => match SettingId::from_name(&n[..n.len() - 1]) {
                Some(id) => AtCommand::Read(id),
                None => AtCommand::Other(up),
            },
            (n, Some("?")) => match SettingId::from_name(n) {
                Some(id) => AtCommand::Describe(id),
                None => AtCommand::Other(up),
            },
            (n, Some(v)) => match SettingId::from_name(n) {
                Some(id) => AtCommand::Write(Setting::parse(id, v)?),
                None => AtCommand::Other(up),
            },
            _ => AtCommand::Other(up),
        })
    }
}

/// `tokio_util` encoder of host commands, for a `FramedWrite` over the serial port.
#[derive(Debug, Clone, Copy, Default)]
pub struct AtEncoder;

impl tokio_util::codec::Encoder<AtCommand> for AtEncoder {
    type Error = std::io::Error;

    fn encode(&mut self, item: AtCommand, dst: &mut BytesMut) -> Result<(), Self::Error> {
        dst.put_slice(item.to_line().as_bytes());
        Ok(())
    }
}
