//! CAT021 ed 2.1 position, altitude and velocity items (EUROCONTROL-SPEC-0149-12 ed 2.1, 5.2):
//!
//! ```text
//! I021/130 lat 24 bits | lon 24 bits, signed, LSB 180/2^23 deg
//! I021/131 lat 32 bits | lon 32 bits, signed, LSB 180/2^30 deg
//! I021/140 geometric height, 16 bits signed, LSB 6.25 ft
//! I021/145 flight level, 16 bits signed, LSB 1/4 FL
//! I021/150 IM | air speed 15 bits: IM=0 IAS LSB 2^-14 NM/s, IM=1 Mach LSB 0.001
//! I021/151 RE | true airspeed 15 bits, LSB 1 kt
//! I021/152 magnetic heading 16 bits, LSB 360/2^16 deg
//! I021/155 RE | barometric vertical rate 15 bits signed, LSB 6.25 ft/min
//! I021/157 RE | geometric vertical rate 15 bits signed, LSB 6.25 ft/min
//! I021/160 RE | ground speed 15 bits, LSB 2^-14 NM/s | track angle 16 bits, LSB 360/2^16 deg
//! I021/165 6 spare bits | track angle rate 10 bits signed, LSB 1/32 deg/s
//! ```
//!
//! RE ("range exceeded") means the true value lies beyond the field's range.

use serde::Serialize;

use super::super::item::{ItemError, be_u64, push_be, sign_extend};

/// Low-resolution latitude/longitude LSB, degrees (180/2^23).
pub const POS_LSB_DEG: f64 = 180.0 / 8_388_608.0;
/// High-resolution latitude/longitude LSB, degrees (180/2^30).
pub const POS_HR_LSB_DEG: f64 = 180.0 / 1_073_741_824.0;
/// Geometric height LSB, ft.
pub const HEIGHT_LSB_FT: f64 = 6.25;
/// Flight level LSB, FL.
pub const FL_LSB: f64 = 0.25;
/// Speed LSB of 2^-14 NM/s expressed in kt (3600 / 16384).
pub const SPEED_LSB_KT: f64 = 3600.0 / 16384.0;
/// Angle LSB of 16-bit angles, degrees (360/2^16).
pub const ANGLE_LSB_DEG: f64 = 360.0 / 65536.0;
/// Vertical rate LSB, ft/min.
pub const VRATE_LSB_FPM: f64 = 6.25;
/// Track angle rate LSB, deg/s.
pub const TAR_LSB_DPS: f64 = 1.0 / 32.0;
/// Mach LSB.
pub const MACH_LSB: f64 = 0.001;

fn fixed<const N: usize>(b: &[u8], name: &'static str) -> Result<[u8; N], ItemError> {
    b.try_into().map_err(|_| ItemError::Malformed(name))
}

fn to_counts(v: f64, lsb: f64, min: i64, max: i64) -> i64 {
    ((v / lsb).round() as i64).clamp(min, max)
}

/// A WGS-84 position (I021/130 or I021/131).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Position {
    /// Latitude, degrees north.
    pub lat_deg: f64,
    /// Longitude, degrees east.
    pub lon_deg: f64,
}

impl Position {
    /// Decodes I021/130 (6 octets).
    pub fn decode_low(b: &[u8]) -> Result<Self, ItemError> {
        let b = fixed::<6>(b, "I021/130")?;
        Ok(Self {
            lat_deg: sign_extend(be_u64(&b[..3]), 24) as f64 * POS_LSB_DEG,
            lon_deg: sign_extend(be_u64(&b[3..]), 24) as f64 * POS_LSB_DEG,
        })
    }

    /// Appends I021/130.
    pub fn encode_low(&self, out: &mut Vec<u8>) {
        for v in [self.lat_deg, self.lon_deg] {
            push_be(
                to_counts(v, POS_LSB_DEG, -(1 << 23), (1 << 23) - 1) as u64,
                3,
                out,
            );
        }
    }

    /// Decodes I021/131 (8 octets).
    pub fn decode_high(b: &[u8]) -> Result<Self, ItemError> {
        let b = fixed::<8>(b, "I021/131")?;
        Ok(Self {
            lat_deg: sign_extend(be_u64(&b[..4]), 32) as f64 * POS_HR_LSB_DEG,
            lon_deg: sign_extend(be_u64(&b[4..]), 32) as f64 * POS_HR_LSB_DEG,
        })
    }

    /// Appends I021/131.
    pub fn encode_high(&self, out: &mut Vec<u8>) {
        for v in [self.lat_deg, self.lon_deg] {
            let c = to_counts(v, POS_HR_LSB_DEG, i64::from(i32::MIN), i64::from(i32::MAX));
            push_be(c as u64, 4, out);
        }
    }
}

/// Decodes a 16-bit signed item scaled by `lsb` (I021/140 ft, I021/145 FL).
pub fn decode_i16(b: &[u8], lsb: f64, name: &'static str) -> Result<f64, ItemError> {
    Ok(f64::from(i16::from_be_bytes(fixed::<2>(b, name)?)) * lsb)
}

/// Appends a 16-bit signed item scaled by `lsb`.
pub fn encode_i16(v: f64, lsb: f64, out: &mut Vec<u8>) {
    let c = to_counts(v, lsb, i64::from(i16::MIN), i64::from(i16::MAX)) as i16;
    out.extend_from_slice(&c.to_be_bytes());
}

/// Decodes a 16-bit unsigned angle (I021/152), degrees.
pub fn decode_angle(b: &[u8], name: &'static str) -> Result<f64, ItemError> {
    Ok(f64::from(u16::from_be_bytes(fixed::<2>(b, name)?)) * ANGLE_LSB_DEG)
}

fn angle_counts(deg: f64) -> u16 {
    // A value that rounds up to 360 deg (65,536 counts) is 0: the cast to u16 keeps the count
    // modulo 2^16.
    (deg.rem_euclid(360.0) / ANGLE_LSB_DEG).round() as u32 as u16
}

/// Appends a 16-bit unsigned angle.
pub fn encode_angle(deg: f64, out: &mut Vec<u8>) {
    out.extend_from_slice(&angle_counts(deg).to_be_bytes());
}

/// I021/150 Air Speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AirSpeed {
    /// Indicated airspeed, kt (multiple of 3600/16384).
    IasKt(f64),
    /// Mach number (multiple of 0.001).
    Mach(f64),
}

impl AirSpeed {
    /// Decodes the two-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        let v = u16::from_be_bytes(fixed::<2>(b, "I021/150")?);
        let value = f64::from(v & 0x7FFF);
        Ok(if v & 0x8000 != 0 {
            Self::Mach(value / 1000.0)
        } else {
            Self::IasKt(value * SPEED_LSB_KT)
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let v = match *self {
            Self::IasKt(kt) => to_counts(kt, SPEED_LSB_KT, 0, 0x7FFF) as u16,
            Self::Mach(m) => 0x8000 | to_counts(m, MACH_LSB, 0, 0x7FFF) as u16,
        };
        out.extend_from_slice(&v.to_be_bytes());
    }
}

/// I021/151 True Airspeed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct TrueAirspeed {
    /// RE: the speed exceeds the field's range.
    pub range_exceeded: bool,
    /// True airspeed, kt (15 bits).
    pub kt: u16,
}

impl TrueAirspeed {
    /// Decodes the two-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        let v = u16::from_be_bytes(fixed::<2>(b, "I021/151")?);
        Ok(Self {
            range_exceeded: v & 0x8000 != 0,
            kt: v & 0x7FFF,
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let v = u16::from(self.range_exceeded) << 15 | (self.kt & 0x7FFF);
        out.extend_from_slice(&v.to_be_bytes());
    }
}

/// I021/155 Barometric or I021/157 Geometric Vertical Rate.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct VerticalRate {
    /// RE: the rate exceeds the field's range (its magnitude is larger than `fpm`).
    pub range_exceeded: bool,
    /// Vertical rate, ft/min, positive up (multiple of 6.25).
    pub fpm: f64,
}

impl VerticalRate {
    /// Decodes the two-octet item.
    pub fn decode(b: &[u8], name: &'static str) -> Result<Self, ItemError> {
        let v = u16::from_be_bytes(fixed::<2>(b, name)?);
        Ok(Self {
            range_exceeded: v & 0x8000 != 0,
            fpm: sign_extend(u64::from(v & 0x7FFF), 15) as f64 * VRATE_LSB_FPM,
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let c = to_counts(self.fpm, VRATE_LSB_FPM, -(1 << 14), (1 << 14) - 1) as u16 & 0x7FFF;
        let v = u16::from(self.range_exceeded) << 15 | c;
        out.extend_from_slice(&v.to_be_bytes());
    }
}

/// I021/160 Airborne Ground Vector.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct GroundVector {
    /// RE: the ground speed exceeds the field's range.
    pub range_exceeded: bool,
    /// Ground speed, kt (multiple of 3600/16384).
    pub ground_speed_kt: f64,
    /// Track angle, degrees true (multiple of 360/2^16).
    pub track_deg: f64,
}

impl GroundVector {
    /// Decodes the four-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        let b = fixed::<4>(b, "I021/160")?;
        let gs = u16::from_be_bytes([b[0], b[1]]);
        Ok(Self {
            range_exceeded: gs & 0x8000 != 0,
            ground_speed_kt: f64::from(gs & 0x7FFF) * SPEED_LSB_KT,
            track_deg: f64::from(u16::from_be_bytes([b[2], b[3]])) * ANGLE_LSB_DEG,
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let gs = u16::from(self.range_exceeded) << 15
            | to_counts(self.ground_speed_kt, SPEED_LSB_KT, 0, 0x7FFF) as u16;
        out.extend_from_slice(&gs.to_be_bytes());
        out.extend_from_slice(&angle_counts(self.track_deg).to_be_bytes());
    }
}

/// Decodes I021/165 Track Angle Rate, deg/s (positive turning right).
pub fn decode_track_angle_rate(b: &[u8]) -> Result<f64, ItemError> {
    let v = u16::from_be_bytes(fixed::<2>(b, "I021/165")?);
    Ok(sign_extend(u64::from(v & 0x03FF), 10) as f64 * TAR_LSB_DPS)
}

/// Appends I021/165.
pub fn encode_track_angle_rate(dps: f64, out: &mut Vec<u8>) {
    let c = to_counts(dps, TAR_LSB_DPS, -512, 511) as u16 & 0x03FF;
    out.extend_from_slice(&c.to_be_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions() {
        // Sample record 1, I021/130 = 2B B7 3E FA 65 BA:
        // lat 0x2BB73E = 2864958 * 180/2^23 = 61.47532939910889 deg;
        // lon 0xFA65BA - 2^24 = -367174 * 180/2^23 = -7.87869930267334 deg.
        let p = Position::decode_low(&[0x2B, 0xB7, 0x3E, 0xFA, 0x65, 0xBA]).unwrap();
        assert!((p.lat_deg - 61.475_329_399_108_89).abs() < 1e-12);
        assert!((p.lon_deg + 7.878_699_302_673_34).abs() < 1e-12);
        let mut out = Vec::new();
        p.encode_low(&mut out);
        assert_eq!(out, [0x2B, 0xB7, 0x3E, 0xFA, 0x65, 0xBA]);
        // I021/131: 0x20000000 = 2^29 * 180/2^30 = 90 deg; 0xC0000000 = -2^30 -> -180 deg.
        let p = Position::decode_high(&[0x20, 0, 0, 0, 0xC0, 0, 0, 0]).unwrap();
        assert_eq!((p.lat_deg, p.lon_deg), (90.0, -180.0));
        let mut out = Vec::new();
        p.encode_high(&mut out);
        assert_eq!(out, [0x20, 0, 0, 0, 0xC0, 0, 0, 0]);
        // Beyond the field's range a value saturates at its extreme count and never wraps to
        // the other sign: 200 deg is 0x7FFFFF (2^23 - 1 counts) and -200 deg 0x800000 (-2^23).
        let mut out = Vec::new();
        Position {
            lat_deg: 200.0,
            lon_deg: -200.0,
        }
        .encode_low(&mut out);
        assert_eq!(out, [0x7F, 0xFF, 0xFF, 0x80, 0x00, 0x00]);
    }

    #[test]
    fn angles_wrap_at_360_degrees() {
        // 360/2^16 deg a count: 90 deg is 0x4000, -90 deg is 270 deg = 0xC000, and a value
        // within half a count of 360 deg rounds to 65,536 counts, which is 0.
        for (deg, counts) in [
            (90.0, 0x4000),
            (-90.0, 0xC000),
            (359.999, 0),
            (360.0, 0),
            (720.0 + ANGLE_LSB_DEG, 1),
        ] {
            let mut out = Vec::new();
            encode_angle(deg, &mut out);
            assert_eq!(out, u16::to_be_bytes(counts), "{deg}");
        }
    }

    #[test]
    fn heights() {
        // I021/140 0x0320 = 800 * 6.25 = 5000 ft; 0xFFF0 = -16 * 6.25 = -100 ft.
        assert_eq!(
            decode_i16(&[0x03, 0x20], HEIGHT_LSB_FT, "h").unwrap(),
            5000.0
        );
        assert_eq!(
            decode_i16(&[0xFF, 0xF0], HEIGHT_LSB_FT, "h").unwrap(),
            -100.0
        );
        // I021/145 0x00C8 = 200 / 4 = FL 50.
        assert_eq!(decode_i16(&[0x00, 0xC8], FL_LSB, "fl").unwrap(), 50.0);
    }

    #[test]
    fn speeds() {
        // I021/150 0x0400 = 1024 * 2^-14 NM/s = 0.0625 NM/s = 225 kt IAS.
        assert_eq!(
            AirSpeed::decode(&[0x04, 0x00]).unwrap(),
            AirSpeed::IasKt(225.0)
        );
        // 0x8320 = Mach, 800 * 0.001 = 0.8.
        let AirSpeed::Mach(m) = AirSpeed::decode(&[0x83, 0x20]).unwrap() else {
            panic!()
        };
        assert!((m - 0.8).abs() < 1e-12);
        let mut out = Vec::new();
        AirSpeed::Mach(m).encode(&mut out);
        assert_eq!(out, [0x83, 0x20]);
        // I021/151 0x81F4: RE, 500 kt.
        assert_eq!(
            TrueAirspeed::decode(&[0x81, 0xF4]).unwrap(),
            TrueAirspeed {
                range_exceeded: true,
                kt: 500
            }
        );
        // I021/160 0x0200 4000: 512 * 3600/16384 = 112.5 kt; 0x4000 * 360/2^16 = 90 deg.
        let g = GroundVector::decode(&[0x02, 0x00, 0x40, 0x00]).unwrap();
        assert_eq!(
            (g.range_exceeded, g.ground_speed_kt, g.track_deg),
            (false, 112.5, 90.0)
        );
        let mut out = Vec::new();
        g.encode(&mut out);
        assert_eq!(out, [0x02, 0x00, 0x40, 0x00]);
        // I021/152 0xC000 = 270 deg.
        assert_eq!(decode_angle(&[0xC0, 0x00], "h").unwrap(), 270.0);
    }

    #[test]
    fn rates() {
        // I021/155 0x00A0 = 160 * 6.25 = 1000 ft/min; 0x7F60 = 15 bits 0x7F60 - 2^15 = -160
        // -> -1000 ft/min; 0xC000 = RE with 0x4000 - 2^15 = -16384 -> -102400 ft/min.
        assert_eq!(
            VerticalRate::decode(&[0x00, 0xA0], "v").unwrap().fpm,
            1000.0
        );
        assert_eq!(
            VerticalRate::decode(&[0x7F, 0x60], "v").unwrap().fpm,
            -1000.0
        );
        let v = VerticalRate::decode(&[0xC0, 0x00], "v").unwrap();
        assert!(v.range_exceeded);
        assert_eq!(v.fpm, -102_400.0);
        let mut out = Vec::new();
        v.encode(&mut out);
        assert_eq!(out, [0xC0, 0x00]);
        // A rate past the field's range saturates at its extreme count and keeps its sign:
        // +200,000 ft/min is 0x3FFF (2^14 - 1 counts = 102,393.75 ft/min), never a count that
        // reads back negative.
        let mut out = Vec::new();
        VerticalRate {
            range_exceeded: true,
            fpm: 200_000.0,
        }
        .encode(&mut out);
        assert_eq!(out, [0xBF, 0xFF]);
        assert_eq!(VerticalRate::decode(&out, "v").unwrap().fpm, 102_393.75);
        // I021/165 0xFC20: spare bits ignored, 10 bits 0x020 = 32 / 32 = 1 deg/s;
        // 0x03E0 = 0x3E0 - 1024 = -32 -> -1 deg/s.
        assert_eq!(decode_track_angle_rate(&[0xFC, 0x20]).unwrap(), 1.0);
        assert_eq!(decode_track_angle_rate(&[0x03, 0xE0]).unwrap(), -1.0);
    }
}
