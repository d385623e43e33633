//! Airborne velocity, ADS-B TC 19 (DO-260B 2.2.3.2.6, BDS 0,9), subtypes 1-4.
//!
//! ```text
//! ME bit  1-5  6-8  9   10   11-13  14    15-24  25    26-35  36     37    38-46  47-48  49     50-56
//! ST 1/2: TC   ST   IC  IFR  NACv   S_ew  V_ew   S_ns  V_ns   VrSrc  S_vr  VR     -      S_dif  dAlt
//! ST 3/4: TC   ST   IC  IFR  NACv   SH    HDG    AST   AS     VrSrc  S_vr  VR     -      S_dif  dAlt
//! ```
//!
//! Speeds are coded as value + 1 (0 = not available), in kt (subtypes 1, 3) or 4 kt (supersonic
//! subtypes 2, 4). Vertical rate: 64 ft/min steps, value + 1. The GNSS-baro difference: 25 ft
//! steps, value + 1, sign bit 1 = GNSS below baro.
//!
//! Decision on ME bit 36 (vertical-rate source): public decoders disagree. We read it as
//! DO-260B 2.2.3.2.6.1.10 does, 0 = geometric (GNSS), 1 = barometric, as current readsb and
//! pyModeS do; the dump1090-fa build that decoded our sample capture reads it the other way.
//! The raw bit is kept in [`Velocity::vr_source_bit`].

use serde::Serialize;

use super::bits;

/// Source of the vertical rate, as read from ME bit 36 (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VerticalRateSource {
    /// Bit 36 = 0: geometric (GNSS).
    Gnss,
    /// Bit 36 = 1: barometric.
    Baro,
}

/// An airborne velocity squitter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Velocity {
    /// Subtype 1..4 (1/2 ground speed sub/supersonic, 3/4 air speed sub/supersonic).
    pub subtype: u8,
    /// Intent change flag.
    pub intent_change: bool,
    /// IFR capability flag.
    pub ifr_capability: bool,
    /// Navigation accuracy category for velocity (NACv in v1/v2, NUCr in v0).
    pub nac_v: u8,
    /// East velocity, kt (negative west); subtypes 1/2.
    pub v_east_kt: Option<i32>,
    /// North velocity, kt (negative south); subtypes 1/2.
    pub v_north_kt: Option<i32>,
    /// Ground speed, kt; subtypes 1/2 when both components are available.
    pub groundspeed_kt: Option<f64>,
    /// Track over ground, degrees true 0..360; subtypes 1/2.
    pub track_deg: Option<f64>,
    /// Air speed, kt; subtypes 3/4.
    pub airspeed_kt: Option<u32>,
    /// Air speed is true (TAS) rather than indicated (IAS); subtypes 3/4.
    pub airspeed_true: bool,
    /// Heading, degrees (magnetic or true per the HRD of operational status); subtypes 3/4.
    pub heading_deg: Option<f64>,
    /// Vertical rate, ft/min, positive up.
    pub vertical_rate_fpm: Option<i32>,
    /// Raw ME bit 36.
    pub vr_source_bit: u8,
    /// The reading of bit 36 we chose (DO-260B).
    pub vertical_rate_source: VerticalRateSource,
    /// GNSS height minus barometric altitude, ft.
    pub gnss_minus_baro_ft: Option<i32>,
}

impl Velocity {
    /// Decodes a TC 19 ME field; `None` for subtypes 0, 5-7 (reserved).
    #[inline]
    pub fn decode(me: u64) -> Option<Self> {
        let subtype = bits(me, 6, 3) as u8;
        if !(1..=4).contains(&subtype) {
            return None;
        }
        let scale = if subtype == 2 || subtype == 4 { 4 } else { 1 };
        let vr_raw = bits(me, 38, 9) as i32;
        let vertical_rate_fpm = (vr_raw != 0).then(|| {
            let v = (vr_raw - 1) * 64;
            if bits(me, 37, 1) == 1 { -v } else { v }
        });
        let dif_raw = bits(me, 50, 7) as i32;
        let gnss_minus_baro_ft = (dif_raw != 0).then(|| {
            let v = (dif_raw - 1) * 25;
            if bits(me, 49, 1) == 1 { -v } else { v }
        });
        let vr_source_bit = bits(me, 36, 1) as u8;
        let mut v = Velocity {
            subtype,
            intent_change: bits(me, 9, 1) == 1,
            ifr_capability: bits(me, 10, 1) == 1,
            nac_v: bits(me, 11, 3) as u8,
            v_east_kt: None,
            v_north_kt: None,
            groundspeed_kt: None,
            track_deg: None,
            airspeed_kt: None,
            airspeed_true: false,
            heading_deg: None,
            vertical_rate_fpm,
            vr_source_bit,
            vertical_rate_source: if vr_source_bit == 1 {
                VerticalRateSource::Baro
            } else {
                VerticalRateSource::Gnss
            },
            gnss_minus_baro_ft,
        };
        if subtype <= 2 {
            let comp = |sign_bit: u32, start: u32| {
                let raw = bits(me, start, 10) as i32;
                (raw != 0).then(|| {
                    let s = (raw - 1) * scale;
                    if bits(me, sign_bit, 1) == 1 { -s } else { s }
                })
            };
            v.v_east_kt = comp(14, 15);
            v.v_north_kt = comp(25, 26);
            if let (Some(e), Some(n)) = (v.v_east_kt, v.v_north_kt) {
                let (e, n) = (f64::from(e), f64::from(n));
                v.groundspeed_kt = Some(e.hypot(n));
                v.track_deg = Some(e.atan2(n).to_degrees().rem_euclid(360.0));
            }
        } else {
            v.heading_deg =
                (bits(me, 14, 1) == 1).then(|| bits(me, 15, 10) as f64 * 360.0 / 1024.0);
            let raw = bits(me, 26, 10) as u32;
            v.airspeed_kt = (raw != 0).then(|| (raw - 1) * scale as u32);
            v.airspeed_true = bits(me, 25, 1) == 1;
        }
        Some(v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::{hex_frame, me_of};

    #[test]
    fn riddle_subtype_1() {
        // 8D485020994409940838175B284F: 159 kt, 182.88 deg, -832 ft/min (The 1090 MHz Riddle).
        // By hand: V_ew = 9 west -> -8 kt, V_ns = 160 south -> -159 kt, VR = 14 down -> -832.
        let (f, _) = hex_frame("8D485020994409940838175B284F");
        let v = Velocity::decode(me_of(&f)).unwrap();
        assert_eq!(v.subtype, 1);
        assert_eq!((v.v_east_kt, v.v_north_kt), (Some(-8), Some(-159)));
        assert!((v.groundspeed_kt.unwrap() - 159.20).abs() < 0.01);
        assert!((v.track_deg.unwrap() - 182.88).abs() < 0.01);
        assert_eq!(v.vertical_rate_fpm, Some(-832));
        assert_eq!(v.vr_source_bit, 0);
        assert_eq!(v.vertical_rate_source, VerticalRateSource::Gnss);
        // dAlt raw 0x17 = 23 -> 22 * 25 = 550 ft, sign 0.
        assert_eq!(v.gnss_minus_baro_ft, Some(550));
    }

    #[test]
    fn riddle_subtype_3() {
        // 8DA05F219B06B6AF189400CBC33F: heading 243.98 deg, 375 kt TAS, -2304 ft/min.
        let (f, _) = hex_frame("8DA05F219B06B6AF189400CBC33F");
        let v = Velocity::decode(me_of(&f)).unwrap();
        assert_eq!(v.subtype, 3);
        assert!((v.heading_deg.unwrap() - 243.984_375).abs() < 1e-9);
        assert_eq!(v.airspeed_kt, Some(375));
        assert!(v.airspeed_true);
        assert_eq!(v.vertical_rate_fpm, Some(-2304));
        assert_eq!(v.vr_source_bit, 1);
        assert_eq!(v.groundspeed_kt, None);
    }

    #[test]
    fn pymodes_published_vectors() {
        // pyModeS tests/test_bds09.py. Subtype 3 with heading 0 (its parity field is zero, so
        // only the ME field is used): 100 kt IAS, heading 0, +1024 ft/min.
        let (f, _) = hex_frame("8D4841409B04000CA04400000000");
        let v = Velocity::decode(me_of(&f)).unwrap();
        assert_eq!((v.airspeed_kt, v.airspeed_true), (Some(100), false));
        assert_eq!(v.heading_deg, Some(0.0));
        assert_eq!(v.vertical_rate_fpm, Some(1024));
        // Vertical-rate sign bits on real frames.
        for (hex, vr) in [
            ("8D3461CF9908388930080F948EA1", 64),
            ("8D3461CF9908558E100C1071EB67", 128),
            ("8D3461CF99085A8F10400F80E6AC", 960),
            ("8D394C0F990C4932780838866883", -64),
        ] {
            let (f, _) = hex_frame(hex);
            assert_eq!(crate::modes::crc::syndrome(&f), 0, "{hex}");
            assert_eq!(
                Velocity::decode(me_of(&f)).unwrap().vertical_rate_fpm,
                Some(vr),
                "{hex}"
            );
        }
    }

    #[test]
    fn supersonic_and_unavailable() {
        // Subtype 2: V_ew raw 101 east -> 400 kt, V_ns raw 0 -> unavailable, VR raw 0.
        let me = (19u64 << 51) | (2 << 48) | (101 << 32);
        let v = Velocity::decode(me).unwrap();
        assert_eq!(v.v_east_kt, Some(400));
        assert_eq!(v.v_north_kt, None);
        assert_eq!(v.groundspeed_kt, None);
        assert_eq!(v.vertical_rate_fpm, None);
        assert_eq!(v.gnss_minus_baro_ft, None);
        // Subtype 4: AS raw 251 -> 1000 kt; SH = 0 -> no heading.
        let me = (19u64 << 51) | (4 << 48) | (251 << 21);
        let v = Velocity::decode(me).unwrap();
        assert_eq!(v.airspeed_kt, Some(1000));
        assert_eq!(v.heading_deg, None);
        // Reserved subtypes.
        assert!(Velocity::decode((19u64 << 51) | (5 << 48)).is_none());
        assert!(Velocity::decode(19u64 << 51).is_none());
    }

    #[test]
    fn intent_change_and_ifr_capability_bits() {
        // DO-260B 2.2.3.2.6.1.2-3: ME bit 9 = intent change, bit 10 = IFR capability.
        let me = crate::modes::me_of(
            &crate::modes::encode::velocity_ground(1, 10, 10, None, false, 0).unwrap(),
        );
        let flags = |me: u64| {
            let v = Velocity::decode(me).unwrap();
            (v.intent_change, v.ifr_capability)
        };
        assert_eq!(flags(me), (false, false));
        assert_eq!(flags(me | 1 << (56 - 9)), (true, false));
        assert_eq!(flags(me | 1 << (56 - 10)), (false, true));
    }
}
