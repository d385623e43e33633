//! I021/RE, the CAT021 Reserved Expansion Field (EUROCONTROL "ADS-B Target Reports Expansion",
//! ref 1.4): after the explicit length octet, an 8-bit indicator (no FX) marks the subfields
//! BPS, SH, NAV, GAO, SGV, STA, TNH and MES, in that order.
//!
//! ```text
//! BPS 2 octets: 4 spare | barometric pressure setting - 800 hPa, 12 bits, LSB 0.1 hPa
//! SH  2 octets: 4 spare | HDR | STAT | selected heading 10 bits, LSB 45/2^6 deg
//! NAV 1 octet:  AP | VN | AH | AM | 4 spare
//! GAO 1 octet:  GPS antenna offset (raw)
//! SGV 2+ octets: STP | HTS | HTT | HRD | GSS 11 bits, LSB 1/8 kt | FX, then HGT 7 bits,
//!                LSB 45/2^4 deg | FX
//! STA 1+ octets: ES | UAT | 5 spare | FX
//! TNH 2 octets: true north heading, LSB 360/2^16 deg
//! MES compound (FX): SUM 1, PNO 4, EM1 2, XP 1, FOM 1, M2 2 octets
//! ```
//!
//! The record walk never depends on this content (the field's length is explicit). Decoding is
//! best effort: content that does not walk exactly to the field's end is left undecoded.

use serde::Serialize;

use super::super::item::{Rule, item_len};

const MES: &[Option<Rule>] = &[
    Some(Rule::Fixed(1)),
    Some(Rule::Fixed(4)),
    Some(Rule::Fixed(2)),
    Some(Rule::Fixed(1)),
    Some(Rule::Fixed(1)),
    Some(Rule::Fixed(2)),
];

/// Subfield rules in indicator order (bit 8 first).
const SUBFIELDS: [(&str, Rule); 8] = [
    ("BPS", Rule::Fixed(2)),
    ("SH", Rule::Fixed(2)),
    ("NAV", Rule::Fixed(1)),
    ("GAO", Rule::Fixed(1)),
    ("SGV", Rule::Extended { first: 2, ext: 1 }),
    ("STA", Rule::Extended { first: 1, ext: 1 }),
    ("TNH", Rule::Fixed(2)),
    ("MES", Rule::Compound(MES)),
];

/// SGV, the surface ground vector.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct SurfaceGroundVector {
    /// STP: the aircraft has stopped.
    pub stopped: bool,
    /// HTS: the heading/ground track value is valid.
    pub hgt_valid: bool,
    /// HTT: true = ground track, false = heading.
    pub is_ground_track: bool,
    /// HRD: true = magnetic north, false = true north.
    pub magnetic: bool,
    /// GSS ground speed, kt (multiple of 1/8).
    pub ground_speed_kt: f64,
    /// HGT heading or ground track, degrees (multiple of 2.8125); `None` without the extension.
    pub hgt_deg: Option<f64>,
}

/// The decoded content of I021/RE.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct ReservedExpansion {
    /// BPS: barometric pressure setting, hPa (800 + 0.1 * value).
    pub bps_hpa: Option<f64>,
    /// TNH: true north heading, degrees.
    pub true_heading_deg: Option<f64>,
    /// SGV: surface ground vector.
    pub surface_vector: Option<SurfaceGroundVector>,
    /// STA: (1090 ES IN capable, UAT IN capable).
    pub in_capability: Option<(bool, bool)>,
    /// Subfields present but not decoded (SH, NAV, GAO, MES), by name.
    pub undecoded: Vec<&'static str>,
}

impl ReservedExpansion {
    /// Decodes the whole item, length octet included; `None` when the content does not walk
    /// exactly to the declared length.
    pub fn decode(item: &[u8]) -> Option<Self> {
        let (&len, rest) = item.split_first()?;
        if usize::from(len) != item.len() {
            return None;
        }
        let (&indicator, mut body) = rest.split_first()?;
        let mut re = Self::default();
        for (bit, (name, rule)) in SUBFIELDS.iter().enumerate() {
            if indicator & (0x80 >> bit) == 0 {
                continue;
            }
            let n = item_len(*rule, body, name).ok()?;
            let sub = &body[..n];
            match *name {
                "BPS" => {
                    let v = u16::from_be_bytes([sub[0], sub[1]]) & 0x0FFF;
                    re.bps_hpa = Some(800.0 + f64::from(v) / 10.0);
                }
                "TNH" => {
                    let v = u16::from_be_bytes([sub[0], sub[1]]);
                    re.true_heading_deg = Some(f64::from(v) * 360.0 / 65536.0);
                }
                "SGV" => {
                    let v = u16::from_be_bytes([sub[0], sub[1]]);
                    re.surface_vector = Some(SurfaceGroundVector {
                        stopped: v & 0x8000 != 0,
                        hgt_valid: v & 0x4000 != 0,
                        is_ground_track: v & 0x2000 != 0,
                        magnetic: v & 0x1000 != 0,
                        ground_speed_kt: f64::from((v >> 1) & 0x07FF) / 8.0,
                        hgt_deg: sub.get(2).map(|&o| f64::from(o >> 1) * 45.0 / 16.0),
                    });
                }
                "STA" => re.in_capability = Some((sub[0] & 0x80 != 0, sub[0] & 0x40 != 0)),
                other => re.undecoded.push(other),
            }
            body = &body[n..];
        }
        body.is_empty().then_some(re)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sample_fields() {
        // Record 1 of cat21_re.ast: RE = 05 08 F0 01 62. Length 5; indicator 0x08 = bit 4 = SGV.
        // F0 01 = 1 1 1 1 00000000000 1: stopped, HGT valid, ground track, magnetic, 0 kt, FX;
        // 62 = 0110001 0: HGT 49 * 45/16 = 137.8125 deg.
        let re = ReservedExpansion::decode(&[0x05, 0x08, 0xF0, 0x01, 0x62]).unwrap();
        assert_eq!(
            re.surface_vector,
            Some(SurfaceGroundVector {
                stopped: true,
                hgt_valid: true,
                is_ground_track: true,
                magnetic: true,
                ground_speed_kt: 0.0,
                hgt_deg: Some(137.8125),
            })
        );
        // Record 2: RE = 05 08 70 F1 40. 70 F1 = 0 1 1 1 00001111000 1: moving, valid, ground
        // track, magnetic, GSS 0x078 = 120 / 8 = 15 kt; 40 = 0100000 0: HGT 32 * 2.8125 = 90.
        let re = ReservedExpansion::decode(&[0x05, 0x08, 0x70, 0xF1, 0x40]).unwrap();
        let v = re.surface_vector.unwrap();
        assert!(!v.stopped && v.hgt_valid && v.is_ground_track && v.magnetic);
        assert_eq!((v.ground_speed_kt, v.hgt_deg), (15.0, Some(90.0)));
    }

    #[test]
    fn every_subfield() {
        // Indicator 0xFF: all eight subfields, 15 octets in all:
        // BPS 0x0D 0x4D: 0xD4D & 0xFFF = 3405 -> 800 + 340.5 = 1140.5 hPa; SH 12 34, NAV 56,
        // GAO 78 (skipped); SGV 00 10 without extension (FX 0): GSS 8 / 8 = 1 kt;
        // STA 0x80: 1090 ES IN capable; TNH 0x40 0x00 = 90 deg; MES primary 0x80 + SUM 0xAA.
        let mut item = [
            0x0F, 0xFF, 0x0D, 0x4D, 0x12, 0x34, 0x56, 0x78, 0x00, 0x10, 0x80, 0x40, 0x00, 0x80,
            0xAA,
        ];
        let re = ReservedExpansion::decode(&item).unwrap();
        assert!((re.bps_hpa.unwrap() - 1140.5).abs() < 1e-9);
        // SGV 00 10 = 0 0 0 0 00000001000 0: every flag clear.
        assert_eq!(
            re.surface_vector,
            Some(SurfaceGroundVector {
                stopped: false,
                hgt_valid: false,
                is_ground_track: false,
                magnetic: false,
                ground_speed_kt: 1.0,
                hgt_deg: None,
            })
        );
        assert_eq!(re.in_capability, Some((true, false)));
        // STA alone (indicator 0x04), 0x40: UAT IN capable, not 1090 ES IN.
        let sta = ReservedExpansion::decode(&[0x03, 0x04, 0x40]).unwrap();
        assert_eq!(sta.in_capability, Some((false, true)));
        assert_eq!(re.true_heading_deg, Some(90.0));
        assert_eq!(re.undecoded, vec!["SH", "NAV", "GAO", "MES"]);
        // A length that does not match the content: not decoded.
        item[0] = 14;
        assert_eq!(ReservedExpansion::decode(&item[..14]), None);
        assert_eq!(ReservedExpansion::decode(&[0x02, 0x08]), None);
        assert_eq!(ReservedExpansion::decode(&[]), None);
    }
}
