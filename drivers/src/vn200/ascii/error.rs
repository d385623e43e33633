//! `$VNERR` system error codes (ICD 1.5, Table 1.6). The code is hexadecimal on the wire
//! (`0A`, `0B`, `0C`, `FF`): `$VNERR,0C` is InsufficientBaudRate (12), not 0 or an error.

use serde::Serialize;

/// A `$VNERR` code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ErrorCode {
    /// 01: firmware hard fault; streaming disabled until reset.
    HardFault,
    /// 02: serial input buffer overflow (256 characters).
    SerialBufferOverflow,
    /// 03: the command's checksum was invalid.
    InvalidChecksum,
    /// 04: invalid command.
    InvalidCommand,
    /// 05: not enough parameters.
    NotEnoughParameters,
    /// 06: too many parameters.
    TooManyParameters,
    /// 07: invalid parameter.
    InvalidParameter,
    /// 08: invalid register.
    InvalidRegister,
    /// 09: unauthorized access (e.g. writing a read-only register).
    UnauthorizedAccess,
    /// 0A: watchdog reset occurred.
    WatchdogReset,
    /// 0B: output buffer overflow (2048 characters).
    OutputBufferOverflow,
    /// 0C: baud rate too low for the requested output.
    InsufficientBaudRate,
    /// FF: system error buffer overflow.
    ErrorBufferOverflow,
    /// Any other code (kept).
    Other(u8),
}

impl ErrorCode {
    /// The code from its wire value.
    pub fn from_code(code: u8) -> Self {
        match code {
            0x01 => Self::HardFault,
            0x02 => Self::SerialBufferOverflow,
            0x03 => Self::InvalidChecksum,
            0x04 => Self::InvalidCommand,
            0x05 => Self::NotEnoughParameters,
            0x06 => Self::TooManyParameters,
            0x07 => Self::InvalidParameter,
            0x08 => Self::InvalidRegister,
            0x09 => Self::UnauthorizedAccess,
            0x0A => Self::WatchdogReset,
            0x0B => Self::OutputBufferOverflow,
            0x0C => Self::InsufficientBaudRate,
            0xFF => Self::ErrorBufferOverflow,
            c => Self::Other(c),
        }
    }

    /// Parses the hexadecimal wire field (one or two hex digits).
    pub fn from_hex(s: &str) -> Option<Self> {
        super::fields::parse_hex(s, 2).map(|c| Self::from_code(c as u8))
    }

    /// The wire value.
    pub fn code(self) -> u8 {
        match self {
            Self::HardFault => 0x01,
            Self::SerialBufferOverflow => 0x02,
            Self::InvalidChecksum => 0x03,
            Self::InvalidCommand => 0x04,
            Self::NotEnoughParameters => 0x05,
            Self::TooManyParameters => 0x06,
            Self::InvalidParameter => 0x07,
            Self::InvalidRegister => 0x08,
            Self::UnauthorizedAccess => 0x09,
            Self::WatchdogReset => 0x0A,
            Self::OutputBufferOverflow => 0x0B,
            Self::InsufficientBaudRate => 0x0C,
            Self::ErrorBufferOverflow => 0xFF,
            Self::Other(c) => c,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_are_hexadecimal() {
        // One or two hex digits only: not empty, not three digits even when the value fits a
        // byte, no sign or other character that `from_str_radix` would take.
        for bad in ["", "0FF", "001", "+1", "G", "1 "] {
            assert_eq!(ErrorCode::from_hex(bad), None, "{bad:?}");
        }
        assert_eq!(ErrorCode::from_hex("1"), Some(ErrorCode::HardFault));
        assert_eq!(ErrorCode::from_hex("0A"), Some(ErrorCode::WatchdogReset));
        assert_eq!(
            ErrorCode::from_hex("0B"),
            Some(ErrorCode::OutputBufferOverflow)
        );
        assert_eq!(
            ErrorCode::from_hex("0C"),
            Some(ErrorCode::InsufficientBaudRate)
        );
        assert_eq!(
            ErrorCode::from_hex("FF"),
            Some(ErrorCode::ErrorBufferOverflow)
        );
        assert_eq!(
            ErrorCode::from_hex("ff"),
            Some(ErrorCode::ErrorBufferOverflow)
        );
        // "10" is 0x10 = 16, an undocumented code, not ten.
        assert_eq!(ErrorCode::from_hex("10"), Some(ErrorCode::Other(0x10)));
        assert_eq!(ErrorCode::from_hex("0G"), None);
        assert_eq!(ErrorCode::from_hex("123"), None);
        for c in 0..=255u8 {
            assert_eq!(ErrorCode::from_code(c).code(), c);
        }
    }
}
