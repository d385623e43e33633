//! Surface position, ADS-B TC 5-8 (DO-260B 2.2.3.2.4, BDS 0,6).
//!
//! ```text
//! ME bit  1-5  6-12  13  14-20  21  22  23-39    40-56
//!         TC   MOV   S   TRK    T   F   LAT-CPR  LON-CPR
//! ```
//!
//! Movement is a non-linear code of ground-speed *bins* (DO-260B Table 2-13), not a speed: we
//! report the bin's lower and upper edges, never a made-up midpoint.

use serde::Serialize;

use super::bits;
use super::cpr::CprFrame;

/// A ground speed bin from the movement field, knots.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SpeedBin {
    /// Lower edge, kt (inclusive).
    pub min_kt: f64,
    /// Upper edge, kt (exclusive); `None` for "175 kt or more".
    pub max_kt: Option<f64>,
}

/// Decodes a 7-bit movement code: `None` for 0 (no information) and 125-127 (reserved).
pub fn movement(code: u8) -> Option<SpeedBin> {
    let bin = |lo: f64, step: f64, first: u8| {
        let min = lo + step * f64::from(code - first);
        Some(SpeedBin {
            min_kt: min,
            max_kt: Some(min + step),
        })
    };
    match code {
        1 => Some(SpeedBin {
            min_kt: 0.0,
            max_kt: Some(0.125),
        }),
        2..=8 => bin(0.125, 0.125, 2),
        9..=12 => bin(1.0, 0.25, 9),
        13..=38 => bin(2.0, 0.5, 13),
        39..=93 => bin(15.0, 1.0, 39),
        94..=108 => bin(70.0, 2.0, 94),
        109..=123 => bin(100.0, 5.0, 109),
        124 => Some(SpeedBin {
            min_kt: 175.0,
            max_kt: None,
        }),
        _ => None,
    }
}

/// The movement code whose bin holds `speed_kt` (for the encoder and tests).
pub fn movement_code(speed_kt: f64) -> u8 {
    (1u8..=124)
        .rev()
        .find(|&c| movement(c).is_some_and(|b| speed_kt >= b.min_kt))
        .unwrap_or(1)
}

/// A surface position squitter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SurfacePosition {
    /// Type code 5-8.
    pub typecode: u8,
    /// Raw movement code.
    pub movement_code: u8,
    /// Ground speed bin, `None` when not available.
    pub speed: Option<SpeedBin>,
    /// Ground track, degrees true, `None` when the status bit says invalid.
    pub track_deg: Option<f64>,
    /// UTC-synchronised time flag.
    pub utc_sync: bool,
    /// The CPR frame.
    pub cpr: CprFrame,
}

impl SurfacePosition {
    /// Decodes a TC 5-8 ME field.
    #[inline]
    pub fn decode(me: u64) -> Self {
        let movement_code = bits(me, 6, 7) as u8;
        SurfacePosition {
            typecode: bits(me, 1, 5) as u8,
            movement_code,
            speed: movement(movement_code),
            track_deg: (bits(me, 13, 1) == 1).then(|| bits(me, 14, 7) as f64 * 360.0 / 128.0),
            utc_sync: bits(me, 21, 1) == 1,
            cpr: CprFrame::from_me(me),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn movement_bins_by_hand() {
        // DO-260B Table 2-13 edges.
        assert_eq!(movement(0), None);
        assert_eq!(movement(1).unwrap().max_kt, Some(0.125));
        assert_eq!(movement(2).unwrap().min_kt, 0.125);
        assert_eq!(movement(8).unwrap().min_kt, 0.875);
        assert_eq!(movement(9).unwrap().min_kt, 1.0);
        assert_eq!(movement(12).unwrap().min_kt, 1.75);
        assert_eq!(movement(13).unwrap().min_kt, 2.0);
        assert_eq!(movement(38).unwrap().min_kt, 14.5);
        assert_eq!(movement(39).unwrap().min_kt, 15.0);
        assert_eq!(movement(93).unwrap().min_kt, 69.0);
        assert_eq!(movement(94).unwrap().min_kt, 70.0);
        assert_eq!(movement(108).unwrap().min_kt, 98.0);
        assert_eq!(movement(109).unwrap().min_kt, 100.0);
        assert_eq!(movement(123).unwrap().min_kt, 170.0);
        assert_eq!(movement(123).unwrap().max_kt, Some(175.0));
        assert_eq!(movement(124).unwrap().max_kt, None);
        for c in 125..=127 {
            assert_eq!(movement(c), None);
        }
        // Bins tile the axis without gaps.
        for c in 1..123 {
            assert_eq!(
                movement(c).unwrap().max_kt,
                Some(movement(c + 1).unwrap().min_kt)
            );
        }
        assert_eq!(movement_code(17.5), 41);
        assert_eq!(movement_code(0.0), 1);
        assert_eq!(movement_code(500.0), 124);
    }

    #[test]
    fn pymodes_published_movement_codes() {
        // pyModeS tests/test_bds06.py: real surface frames and their ground speeds (bin lower
        // edges; None for code 0). Each frame's parity checks.
        for (hex, want) in [
            ("8C3944F8400002ACB23CDA192B95", None),
            ("903A33FF40100858D34FF3CCE976", Some(0.0)),
            ("8C394C0F389B1667E947DB7BB8BC", Some(1.0)),
            ("8C3461CF398D60597B4EA434C4D7", Some(7.5)),
            ("8C3461CF399D6059814EA81483A9", Some(8.0)),
            ("8C3461CF3A7F3059C94E5BF4E169", Some(15.0)),
            ("8C3950CF3DEDE47BAC304D3B5122", Some(70.0)),
            ("8C3933203EDDE47B9E2FFA5E77B8", Some(100.0)),
            ("8D3933203FCDE2A84E39E1C6C5BC", Some(175.0)),
        ] {
            let (f, _) = crate::modes::hex_frame(hex);
            assert_eq!(crate::modes::crc::syndrome(&f), 0, "{hex}");
            let s = SurfacePosition::decode(crate::modes::me_of(&f));
            assert_eq!(s.speed.map(|b| b.min_kt), want, "{hex}");
        }
    }

    #[test]
    fn hand_built_surface_frame() {
        // TC 7, MOV 41 (17-18 kt), S = 1, TRK 32 -> 90 deg, odd, lat 1234, lon 5678.
        let me =
            (7u64 << 51) | (41 << 44) | (1 << 43) | (32 << 36) | (1 << 34) | (1234 << 17) | 5678;
        let s = SurfacePosition::decode(me);
        assert_eq!(s.typecode, 7);
        assert_eq!(s.speed.unwrap().min_kt, 17.0);
        assert_eq!(s.track_deg, Some(90.0));
        // ME bit 21, the T flag: clear here, set below.
        assert!(!s.utc_sync);
        assert!(SurfacePosition::decode(me | (1 << 35)).utc_sync);
        assert_eq!(
            s.cpr,
            CprFrame {
                odd: true,
                lat: 1234,
                lon: 5678
            }
        );
        // Track status 0: no track.
        let s = SurfacePosition::decode(me & !(1 << 43));
        assert_eq!(s.track_deg, None);
    }
}
