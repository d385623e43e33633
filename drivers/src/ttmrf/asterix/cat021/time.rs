//! CAT021 ed 2.1 time items (EUROCONTROL-SPEC-0149-12 ed 2.1, 5.2): I021/071, 072, 073, 075 and
//! 077 are three-octet times of day in 1/128 s (see [`super::super::common::decode_tod`]);
//! I021/074 and I021/076 are the high-precision forms decoded here.
//!
//! ```text
//! I021/074, I021/076: b32..b31 FSI | b30..b1 fractional part of the second, LSB 2^-30 s
//! FSI: 00 whole seconds as in I021/073 (or 075), 01 one more, 10 one less, 11 reserved
//! ```

use serde::Serialize;

use super::super::item::ItemError;

/// Seconds per count of the high-precision fraction (2^-30 s).
pub const HP_LSB_S: f64 = 1.0 / 1_073_741_824.0;

/// I021/074 or I021/076: the fractional second of a message reception time.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct HighPrecisionTime {
    /// Full Second Indication, 0..=3 (3 reserved).
    pub fsi: u8,
    /// Fraction of the second, s (multiple of 2^-30, below 1).
    pub fraction_s: f64,
}

impl HighPrecisionTime {
    /// Decodes the four-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        let b: [u8; 4] = b.try_into().map_err(|_| ItemError::Malformed("I021/074"))?;
        let v = u32::from_be_bytes(b);
        Ok(Self {
            fsi: (v >> 30) as u8,
            fraction_s: f64::from(v & 0x3FFF_FFFF) * HP_LSB_S,
        })
    }

    /// Appends the item (fraction rounded to 2^-30 s and kept below one second).
    pub fn encode(&self, out: &mut Vec<u8>) {
        let raw = (self.fraction_s / HP_LSB_S)
            .round()
            .clamp(0.0, f64::from(0x3FFF_FFFFu32));
        let v = u32::from(self.fsi & 3) << 30 | raw as u32;
        out.extend_from_slice(&v.to_be_bytes());
    }

    /// The full time of day, s, from the whole-second item it refines (I021/073 for 074,
    /// I021/075 for 076). `None` for the reserved FSI 3. Wraps into 0..86400 s.
    pub fn full_time_s(&self, coarse_s: f64) -> Option<f64> {
        let adjust = match self.fsi {
            0 => 0.0,
            1 => 1.0,
            2 => -1.0,
            _ => return None,
        };
        Some((coarse_s.floor() + adjust + self.fraction_s).rem_euclid(86_400.0))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_values() {
        // CAT021 sample record 1: I021/073 = 38 41 76 = 3686774 / 128 = 28802.921875 s;
        // I021/074 = 3A DA B9 F5: FSI = 00, fraction = 0x3ADAB9F5 = 987412981 * 2^-30
        // = 0.91959999967... s; full time = 28802 + 0.9196 = 28802.9196 s.
        let t = HighPrecisionTime::decode(&[0x3A, 0xDA, 0xB9, 0xF5]).unwrap();
        assert_eq!(t.fsi, 0);
        assert!((t.fraction_s - 0.919_599_999_673_664_6).abs() < 1e-15);
        let full = t.full_time_s(28_802.921_875).unwrap();
        assert!((full - 28_802.919_6).abs() < 1e-6);
        let mut out = Vec::new();
        t.encode(&mut out);
        assert_eq!(out, [0x3A, 0xDA, 0xB9, 0xF5]);
    }

    #[test]
    fn fsi() {
        // 0x40000000: FSI 01, fraction 0 -> whole seconds + 1.
        let t = HighPrecisionTime::decode(&[0x40, 0, 0, 0]).unwrap();
        assert_eq!(t.full_time_s(100.99), Some(101.0));
        // 0xA0000000: FSI 10, fraction 0x20000000 * 2^-30 = 0.5 -> whole seconds - 1 + 0.5.
        let t = HighPrecisionTime::decode(&[0xA0, 0, 0, 0]).unwrap();
        assert_eq!(t.full_time_s(100.01), Some(99.5));
        // Wrap at midnight: 0 s with FSI 10 is the previous day's last second.
        assert_eq!(t.full_time_s(0.2), Some(86_399.5));
        let t = HighPrecisionTime::decode(&[0xC0, 0, 0, 0]).unwrap();
        assert_eq!(t.full_time_s(1.0), None);
    }
}
