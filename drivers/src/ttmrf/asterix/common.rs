//! Items that CAT021 and CAT023 share: Data Source Identifier (I021/010, I023/010) and the
//! three-octet time of day in 1/128 s (I021/071..077 whole-second forms, I023/070).

use serde::Serialize;

use super::item::{ItemError, be_u64, push_be};

/// SAC/SIC of the TT-Multi-RF's FLARM targets (manual 8.2.1 "FLARM ASTERIX protocol").
pub const FLARM_SOURCE: DataSource = DataSource { sac: 0, sic: 161 };

/// Data Source Identifier: System Area Code and System Identification Code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct DataSource {
    /// System Area Code.
    pub sac: u8,
    /// System Identification Code.
    pub sic: u8,
}

impl DataSource {
    /// Decodes the two-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        match *b {
            [sac, sic] => Ok(Self { sac, sic }),
            _ => Err(ItemError::Malformed("data source identifier")),
        }
    }

    /// Appends the two-octet item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        out.extend_from_slice(&[self.sac, self.sic]);
    }

    /// Whether this is the source the TT-Multi-RF uses for FLARM targets (SAC 0, SIC 161).
    pub fn is_flarm(&self) -> bool {
        *self == FLARM_SOURCE
    }
}

/// Seconds per count of the three-octet time of day.
pub const TOD_LSB_S: f64 = 1.0 / 128.0;

/// Decodes a three-octet time of day (1/128 s since midnight UTC), seconds.
pub fn decode_tod(b: &[u8]) -> Result<f64, ItemError> {
    if b.len() != 3 {
        return Err(ItemError::Malformed("time of day"));
    }
    Ok(be_u64(b) as f64 * TOD_LSB_S)
}

/// Appends a three-octet time of day, rounded to 1/128 s and wrapped into 24 bits.
pub fn encode_tod(seconds: f64, out: &mut Vec<u8>) {
    let counts = (seconds / TOD_LSB_S).round().max(0.0) as u64;
    push_be(counts & 0xFF_FFFF, 3, out);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tod() {
        // 0x384176 = 3686774 counts / 128 = 28802.921875 s.
        assert_eq!(decode_tod(&[0x38, 0x41, 0x76]), Ok(28_802.921_875));
        let mut out = Vec::new();
        encode_tod(28_802.921_875, &mut out);
        assert_eq!(out, [0x38, 0x41, 0x76]);
        assert!(decode_tod(&[1, 2]).is_err());
    }

    #[test]
    fn source() {
        assert!(DataSource::decode(&[0, 161]).unwrap().is_flarm());
        assert!(!DataSource::decode(&[0, 1]).unwrap().is_flarm());
        assert!(DataSource::decode(&[0]).is_err());
    }
}
