//! Aircraft status, ADS-B TC 28 (DO-260B 2.2.3.2.7.8, BDS 6,1): subtype 1 emergency/priority
//! status with the Mode A code; subtype 2 (ACAS RA broadcast) is recognised, not decoded.
//!
//! ```text
//! ME bit  1-5  6-8  9-11       12-24        25-56
//!         TC   ST   EMERGENCY  MODE A CODE  reserved
//! ```

use serde::Serialize;

use super::bits;
use super::squawk::Squawk;

/// A TC 28 squitter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct AircraftStatus {
    /// Subtype (1 emergency/priority, 2 ACAS RA broadcast).
    pub subtype: u8,
    /// Emergency state (subtype 1): 0 none, 1 general, 2 lifeguard/medical, 3 minimum fuel,
    /// 4 no communications, 5 unlawful interference, 6 downed aircraft, 7 reserved.
    pub emergency: Option<u8>,
    /// Mode A code (subtype 1).
    pub squawk: Option<Squawk>,
}

impl AircraftStatus {
    /// Decodes a TC 28 ME field.
    #[inline]
    pub fn decode(me: u64) -> Self {
        let subtype = bits(me, 6, 3) as u8;
        let one = subtype == 1;
        AircraftStatus {
            subtype,
            emergency: one.then(|| bits(me, 9, 3) as u8),
            squawk: one.then(|| Squawk::from_id13(bits(me, 12, 13) as u16)),
        }
    }

    /// Name of an emergency state.
    pub fn emergency_name(code: u8) -> &'static str {
        match code {
            0 => "none",
            1 => "general",
            2 => "lifeguard",
            3 => "minimum_fuel",
            4 => "no_communications",
            5 => "unlawful_interference",
            6 => "downed_aircraft",
            _ => "reserved",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::{hex_frame, me_of};

    #[test]
    fn capture_frame() {
        // ulss7 capture, dump1090: "*8f400159e1181500000000d94095; ... (28/1) Squawk: 1017".
        let (f, _) = hex_frame("8F400159E1181500000000D94095");
        let s = AircraftStatus::decode(me_of(&f));
        assert_eq!(s.subtype, 1);
        assert_eq!(s.emergency, Some(0));
        assert_eq!(s.squawk.unwrap().to_string(), "1017");
    }

    #[test]
    fn hand_built_7700() {
        let me =
            (28u64 << 51) | (1 << 48) | (1 << 45) | (u64::from(Squawk(0x7700).to_id13()) << 32);
        let s = AircraftStatus::decode(me);
        assert_eq!(s.emergency, Some(1));
        assert_eq!(s.squawk, Some(Squawk(0x7700)));
        // DO-260B Table 2-85: emergency/priority status codes 0-6, 7 reserved.
        let names: Vec<&str> = (0..=7).map(AircraftStatus::emergency_name).collect();
        assert_eq!(
            names,
            [
                "none",
                "general",
                "lifeguard",
                "minimum_fuel",
                "no_communications",
                "unlawful_interference",
                "downed_aircraft",
                "reserved"
            ]
        );
        let s = AircraftStatus::decode((28u64 << 51) | (2 << 48));
        assert_eq!((s.subtype, s.emergency, s.squawk), (2, None, None));
    }
}
