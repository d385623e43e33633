//! Airborne position, ADS-B TC 9-18 (barometric altitude) and TC 20-22 (GNSS height)
//! (DO-260B 2.2.3.2.3, BDS 0,5).
//!
//! ```text
//! ME bit  1-5  6-7  8          9-20  21  22  23-39    40-56
//!         TC   SS   NIC-B/SAF  ALT   T   F   LAT-CPR  LON-CPR
//! ```
//!
//! Decision on TC 20-22: DO-260B codes the GNSS height (HAE) in the same 12-bit form as the
//! barometric altitude (25 ft with Q = 1), as readsb reads it; pyModeS reads it as metres. We
//! follow DO-260B and report it as `altitude_gnss_ft`.

use serde::Serialize;

use super::altitude::decode_ac12;
use super::bits;
use super::cpr::CprFrame;

/// An airborne position squitter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AirbornePosition {
    /// Type code (9-18, 20-22).
    pub typecode: u8,
    /// Surveillance status (0 none, 1 permanent alert, 2 temporary alert, 3 SPI).
    pub surveillance_status: u8,
    /// ME bit 8: NIC supplement-B in version 2, single antenna flag in versions 0/1.
    pub nic_b: bool,
    /// Barometric altitude, ft (TC 9-18), `None` when not available.
    pub altitude_baro_ft: Option<i32>,
    /// GNSS height above the ellipsoid, ft (TC 20-22), `None` when not available.
    pub altitude_gnss_ft: Option<i32>,
    /// UTC-synchronised time flag (T).
    pub utc_sync: bool,
    /// The CPR frame.
    pub cpr: CprFrame,
}

impl AirbornePosition {
    /// Decodes a TC 9-18 / 20-22 ME field.
    #[inline]
    pub fn decode(me: u64) -> Self {
        let typecode = bits(me, 1, 5) as u8;
        let alt = decode_ac12(bits(me, 9, 12) as u16);
        let gnss = typecode >= 20;
        AirbornePosition {
            typecode,
            surveillance_status: bits(me, 6, 2) as u8,
            nic_b: bits(me, 8, 1) == 1,
            altitude_baro_ft: if gnss { None } else { alt },
            altitude_gnss_ft: if gnss { alt } else { None },
            utc_sync: bits(me, 21, 1) == 1,
            cpr: CprFrame::from_me(me),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::{hex_frame, me_of};

    #[test]
    fn riddle_even_frame() {
        // 8D40621D58C382D690C8AC2863A7: TC 11, ALT 0xC38 -> 38 000 ft, even, 93000/51372.
        let (f, _) = hex_frame("8D40621D58C382D690C8AC2863A7");
        let p = AirbornePosition::decode(me_of(&f));
        assert_eq!(p.typecode, 11);
        assert_eq!(p.altitude_baro_ft, Some(38_000));
        assert_eq!(p.altitude_gnss_ft, None);
        assert_eq!(
            p.cpr,
            CprFrame {
                odd: false,
                lat: 93_000,
                lon: 51_372
            }
        );
        assert_eq!(p.surveillance_status, 0);
        assert!(!p.nic_b);
        // ME bit 21, the T flag (DO-260B 2.2.3.2.3.5): 0 in this frame; set, the time is
        // UTC-synchronised.
        assert!(!p.utc_sync);
        assert!(AirbornePosition::decode(me_of(&f) | (1 << 35)).utc_sync);
    }

    #[test]
    fn gnss_height_and_unavailable_altitude() {
        // Hand-built ME: TC 20, ALT = 0 (unavailable), odd.
        let me = (20u64 << 51) | (1 << 34);
        let p = AirbornePosition::decode(me);
        assert_eq!(p.altitude_gnss_ft, None);
        assert_eq!(p.altitude_baro_ft, None);
        assert!(p.cpr.odd);
        // TC 21 with Q = 1, N = 1040 -> 25 000 ft of GNSS height. N = 0b100_0001_0000:
        // AC12 = 0b1000001 << 5 | 1 << 4 | 0 = 0x830.
        let me = (21u64 << 51) | (0x830u64 << 36);
        let p = AirbornePosition::decode(me);
        assert_eq!(p.altitude_gnss_ft, Some(25_000));
    }
}
