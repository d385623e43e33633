//! Aircraft identification and category, ADS-B TC 1-4 (DO-260B 2.2.3.2.5, BDS 0,8), and the
//! 6-bit character set it shares with Comm-B BDS 2,0.
//!
//! ```text
//! ME bit  1-5   6-8   9-14  15-20 ... 51-56
//!         TC    CA    C1    C2    ... C8      (C = 6-bit IA-5 subset)
//! ```

use serde::Serialize;

use super::bits;

/// The 6-bit character set: `#` marks codes that are not assigned.
const CHARSET: &[u8; 64] = b"#ABCDEFGHIJKLMNOPQRSTUVWXYZ##### ###############0123456789######";

/// An 8-character flight identification, space padded, without allocation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Callsign {
    chars: [u8; 8],
    /// Every character was an assigned code (A-Z, 0-9, space).
    pub valid: bool,
}

impl Callsign {
    /// Decodes the 48 bits of eight 6-bit characters (in the low 48 bits of `v`).
    #[inline]
    pub fn from_bits48(v: u64) -> Self {
        let mut chars = [b' '; 8];
        let mut valid = true;
        for (i, c) in chars.iter_mut().enumerate() {
            let code = ((v >> (42 - 6 * i)) & 0x3F) as usize;
            *c = CHARSET[code];
            valid &= *c != b'#';
        }
        Callsign { chars, valid }
    }

    /// Encodes `s` (up to 8 characters of A-Z, 0-9, space; lower case is upper-cased) as 48
    /// bits. Other characters are refused.
    pub fn encode(s: &str) -> Option<u64> {
        if s.len() > 8 {
            return None;
        }
        let mut v = 0u64;
        let bytes = s.as_bytes();
        for i in 0..8 {
            let c = bytes.get(i).copied().unwrap_or(b' ').to_ascii_uppercase();
            let code = match c {
                b'A'..=b'Z' => c - b'A' + 1,
                b'0'..=b'9' => c - b'0' + 48,
                b' ' => 32,
                _ => return None,
            };
            v = (v << 6) | u64::from(code);
        }
        Some(v)
    }

    /// The callsign with trailing padding removed.
    pub fn as_str(&self) -> &str {
        let end = self
            .chars
            .iter()
            .rposition(|&c| c != b' ')
            .map_or(0, |p| p + 1);
        // Only ASCII from CHARSET is ever stored.
        std::str::from_utf8(&self.chars[..end]).unwrap_or("")
    }

    /// The eight raw characters, padding included.
    pub fn raw(&self) -> &[u8; 8] {
        &self.chars
    }
}

impl Serialize for Callsign {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.as_str())
    }
}

/// TC 1-4: identification and emitter category.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Identification {
    /// Type code 1..4 (4 = set A, 3 = B, 2 = C, 1 = D).
    pub typecode: u8,
    /// Category within the set (CA, 0..7; 0 = no information).
    pub category: u8,
    /// Flight identification.
    pub callsign: Callsign,
}

impl Identification {
    /// Decodes a TC 1-4 ME field.
    #[inline]
    pub fn decode(me: u64) -> Self {
        Identification {
            typecode: bits(me, 1, 5) as u8,
            category: bits(me, 6, 3) as u8,
            callsign: Callsign::from_bits48(me & 0xFFFF_FFFF_FFFF),
        }
    }

    /// The category set letter and number as printed by ground tools, e.g. "A3".
    pub fn category_code(&self) -> [u8; 2] {
        let set = match self.typecode {
            4 => b'A',
            3 => b'B',
            2 => b'C',
            _ => b'D',
        };
        [set, b'0' + (self.category & 7)]
    }

    /// The emitter category in the flat 0..39 numbering of DO-260B/GDL90 (A0-A7 = 0-7,
    /// B0-B7 = 8-15, C0-C7 = 16-23, D0-D7 = 24-31), as `TrafficReport::emitter_category` holds.
    pub fn emitter_category(&self) -> u8 {
        let base = match self.typecode {
            4 => 0,
            3 => 8,
            2 => 16,
            _ => 24,
        };
        base + (self.category & 7)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::{hex_frame, me_of};

    #[test]
    fn klm1023() {
        // The 1090 MHz Riddle: 8D4840D6202CC371C32CE0576098 -> TC 4, "KLM1023 ".
        let (f, _) = hex_frame("8D4840D6202CC371C32CE0576098");
        let id = Identification::decode(me_of(&f));
        assert_eq!(id.typecode, 4);
        assert_eq!(id.category, 0);
        assert_eq!(id.callsign.as_str(), "KLM1023");
        assert!(id.callsign.valid);
        assert_eq!(&id.category_code(), b"A0");
    }

    #[test]
    fn ezy85mh() {
        // pyModeS tests: 8D406B902015A678D4D220AA4BDA -> TC 4, category 0, "EZY85MH".
        let (f, _) = hex_frame("8D406B902015A678D4D220AA4BDA");
        let id = Identification::decode(me_of(&f));
        assert_eq!((id.typecode, id.category), (4, 0));
        assert_eq!(id.callsign.as_str(), "EZY85MH");
    }

    #[test]
    fn encode_round_trip_and_refusals() {
        let v = Callsign::encode("ezy12ab").unwrap();
        assert_eq!(Callsign::from_bits48(v).as_str(), "EZY12AB");
        assert_eq!(Callsign::encode("TOO-LONG1"), None);
        assert_eq!(Callsign::encode("A_B"), None);
        // Unassigned code 0 shows as '#', and the callsign is flagged invalid.
        let c = Callsign::from_bits48(0);
        assert!(!c.valid);
        assert_eq!(c.as_str(), "########");
        assert_eq!(
            Callsign::from_bits48(Callsign::encode("").unwrap()).as_str(),
            ""
        );
        // The raw characters keep the padding that `as_str` trims.
        let ab = Callsign::from_bits48(Callsign::encode("AB").unwrap());
        assert_eq!(ab.raw(), b"AB      ");
    }

    #[test]
    fn category_sets_by_type_code() {
        // DO-260B 2.2.3.2.5.2: TC 4 = set A, 3 = B, 2 = C, 1 = D; the flat numbering (GDL90
        // emitter category, as the doc of `emitter_category` gives it) counts 8 per set.
        for (typecode, category, code, flat) in [
            (4, 3, b"A3", 3),
            (3, 2, b"B2", 10),
            (2, 1, b"C1", 17),
            (1, 7, b"D7", 31),
        ] {
            let id = Identification {
                typecode,
                category,
                callsign: Callsign::from_bits48(0),
            };
            assert_eq!(&id.category_code(), code, "TC {typecode}");
            assert_eq!(id.emitter_category(), flat, "TC {typecode}");
        }
    }
}
