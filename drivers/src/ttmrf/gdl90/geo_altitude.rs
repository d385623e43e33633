//! GDL90 Ownship Geometric Altitude, message ID 11 (GDL 90 Data Interface Specification
//! 560-1058-00 Rev A, 3.8).
//!
//! ```text
//! byte 0    ID = 0x0B
//! bytes 1-2 geometric altitude, 16-bit signed, 5 ft resolution, MS byte first
//! bytes 3-4 vertical metrics, MS byte first: b15 vertical warning, b14..b0 VFOM in metres
//!           (0x7FFF not available, 0x7FFE = 32766 m or more)
//! ```

use serde::Serialize;

/// Message ID of the Ownship Geometric Altitude.
pub const ID: u8 = 11;
/// Length of the clear message, ID included.
pub const LEN: usize = 5;
/// Geometric altitude resolution, ft.
pub const ALT_LSB_FT: i32 = 5;

/// Vertical Figure of Merit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Vfom {
    /// 0x7FFF: not available.
    Unavailable,
    /// 0x7FFE: 32766 m or more.
    AtLeast32766M,
    /// 0..=32765 m.
    Meters(u16),
}

/// Ownship geometric altitude (height above the WGS-84 ellipsoid) and its vertical quality.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct GeoAltitude {
    /// Geometric altitude, ft (multiple of 5).
    pub geo_altitude_ft: i32,
    /// Vertical warning: the vertical protection limit is exceeded.
    pub vertical_warning: bool,
    /// Vertical figure of merit.
    pub vfom: Vfom,
}

impl GeoAltitude {
    /// Decodes the clear message (ID included). `None` when the length is not [`LEN`].
    pub fn decode(m: &[u8]) -> Option<Self> {
        let &[_, a0, a1, v0, v1] = m else {
            return None;
        };
        let metrics = u16::from_be_bytes([v0, v1]);
        let vfom = match metrics & 0x7FFF {
            0x7FFF => Vfom::Unavailable,
            0x7FFE => Vfom::AtLeast32766M,
            m => Vfom::Meters(m),
        };
        Some(Self {
            geo_altitude_ft: i32::from(i16::from_be_bytes([a0, a1])) * ALT_LSB_FT,
            vertical_warning: metrics & 0x8000 != 0,
            vfom,
        })
    }

    /// Encodes the clear message (ID included); the altitude is rounded to 5 ft and clamped, a
    /// VFOM of 32766 m or more becomes the 0x7FFE code.
    pub fn encode(&self) -> [u8; LEN] {
        let units = (f64::from(self.geo_altitude_ft) / f64::from(ALT_LSB_FT)).round() as i64;
        let a = (units.clamp(i64::from(i16::MIN), i64::from(i16::MAX)) as i16).to_be_bytes();
        let vfom = match self.vfom {
            Vfom::Unavailable => 0x7FFF,
            Vfom::AtLeast32766M => 0x7FFE,
            // 32766 m or more is sent as the "at least 32766 m" code (spec 3.8 example:
            // VFOM = 40,000 m -> 0x7FFE).
            Vfom::Meters(m) => m.min(0x7FFE),
        };
        let v = (u16::from(self.vertical_warning) << 15 | vfom).to_be_bytes();
        [ID, a[0], a[1], v[0], v[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_built() {
        // 0x0190 = 400 * 5 ft = 2000 ft; metrics 0x000A: no warning, VFOM 10 m.
        let m = [ID, 0x01, 0x90, 0x00, 0x0A];
        let g = GeoAltitude::decode(&m).unwrap();
        assert_eq!(
            g,
            GeoAltitude {
                geo_altitude_ft: 2000,
                vertical_warning: false,
                vfom: Vfom::Meters(10)
            }
        );
        assert_eq!(g.encode(), m);
        // 0xFF38 = -200 * 5 = -1000 ft; metrics 0xFFFF: warning, VFOM not available.
        let m = [ID, 0xFF, 0x38, 0xFF, 0xFF];
        let g = GeoAltitude::decode(&m).unwrap();
        assert_eq!(g.geo_altitude_ft, -1000);
        assert!(g.vertical_warning);
        assert_eq!(g.vfom, Vfom::Unavailable);
        assert_eq!(g.encode(), m);
        // metrics 0x7FFE: no warning, VFOM >= 32766 m.
        let m = [ID, 0x00, 0x00, 0x7F, 0xFE];
        assert_eq!(GeoAltitude::decode(&m).unwrap().vfom, Vfom::AtLeast32766M);
        assert_eq!(GeoAltitude::decode(&m[..4]), None);
    }
}
