//! Aircraft operational status, ADS-B TC 31 (DO-260B 2.2.3.2.7.2, BDS 6,5), subtypes 0
//! (airborne) and 1 (surface).
//!
//! ```text
//! ME bit  1-5 6-8 9-24 (air) / 9-20 CC + 21-24 L/W (surface)   25-40 OM   41-43 VER  44 NIC-A
//!         45-48 NACp  49-50 GVA (air)  51-52 SIL  53 NIC-baro (air) / TRK-HDG (surface)
//!         54 HRD  55 SIL-sup  56 reserved
//! ```
//!
//! In the surface capability class, ME bits 17-19 are NACv and bit 20 is NIC supplement-C.
//! Versions 0 carry only the version number in this layout; for version 0 we report the version
//! and nothing else. Version 1 (DO-260A) has no GVA and no SIL supplement; we report those only
//! for version 2.

use serde::Serialize;

use super::bits;

/// A TC 31 squitter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct OperationalStatus {
    /// 0 airborne, 1 surface.
    pub subtype: u8,
    /// ADS-B version: 0 (DO-260), 1 (DO-260A), 2 (DO-260B).
    pub version: u8,
    /// NIC supplement-A.
    pub nic_a: Option<bool>,
    /// NIC supplement-C (surface).
    pub nic_c: Option<bool>,
    /// NACp.
    pub nac_p: Option<u8>,
    /// NACv (surface only; airborne NACv comes with velocity).
    pub nac_v: Option<u8>,
    /// Geometric vertical accuracy (airborne, v2).
    pub gva: Option<u8>,
    /// Source integrity level.
    pub sil: Option<u8>,
    /// SIL supplement: true = per sample, false = per hour (v2).
    pub sil_per_sample: Option<bool>,
    /// NIC-baro (airborne).
    pub nic_baro: Option<bool>,
    /// Horizontal reference direction: true = magnetic north, false = true north.
    pub hrd_magnetic: Option<bool>,
    /// Capability class bits (16 airborne, 12 surface).
    pub capability_class: u16,
    /// Operational mode bits.
    pub operational_mode: u16,
    /// System design assurance (OM bits 31-32, v2).
    pub sda: Option<u8>,
}

impl OperationalStatus {
    /// Decodes a TC 31 ME field; `None` for subtypes 2-7 (reserved).
    #[inline]
    pub fn decode(me: u64) -> Option<Self> {
        let subtype = bits(me, 6, 3) as u8;
        if subtype > 1 {
            return None;
        }
        let surface = subtype == 1;
        let version = bits(me, 41, 3) as u8;
        let v12 = version >= 1;
        let v2 = version == 2;
        Some(OperationalStatus {
            subtype,
            version,
            nic_a: some(v12, bits(me, 44, 1) == 1),
            nic_c: some(v12 && surface, bits(me, 20, 1) == 1),
            nac_p: some(v12, bits(me, 45, 4) as u8),
            nac_v: some(v12 && surface, bits(me, 17, 3) as u8),
            gva: some(v2 && !surface, bits(me, 49, 2) as u8),
            sil: some(v12, bits(me, 51, 2) as u8),
            sil_per_sample: some(v2, bits(me, 55, 1) == 1),
            nic_baro: some(v12 && !surface, bits(me, 53, 1) == 1),
            hrd_magnetic: some(v12, bits(me, 54, 1) == 1),
            capability_class: if surface {
                bits(me, 9, 12)
            } else {
                bits(me, 9, 16)
            } as u16,
            operational_mode: bits(me, 25, 16) as u16,
            sda: some(v2, bits(me, 31, 2) as u8),
        })
    }
}

/// `Some(v)` when the field exists in this version/subtype.
#[inline]
fn some<T>(exists: bool, v: T) -> Option<T> {
    exists.then_some(v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::{hex_frame, me_of};

    #[test]
    fn capture_frame() {
        // ulss7 capture, dump1090 on ME F82300060049B8: version 2, NACp 9, GVA 2, SIL 3 per
        // hour, NICbaro 1, true north, SDA 2. By hand: byte 6 = 0x49 = 010 0 1001 -> VER 2,
        // NIC-A 0, NACp 9; byte 7 = 0xB8 = 10 11 1 0 0 0 -> GVA 2, SIL 3, NIC-baro 1, HRD 0.
        let (f, _) = hex_frame("8D400159F82300060049B8000000");
        let s = OperationalStatus::decode(me_of(&f)).unwrap();
        assert_eq!(s.version, 2);
        assert_eq!(s.nic_a, Some(false));
        assert_eq!(s.nac_p, Some(9));
        assert_eq!(s.gva, Some(2));
        assert_eq!(s.sil, Some(3));
        assert_eq!(s.sil_per_sample, Some(false));
        assert_eq!(s.nic_baro, Some(true));
        assert_eq!(s.hrd_magnetic, Some(false));
        assert_eq!(s.sda, Some(2));
        // NIC-C and NACv are surface fields.
        assert_eq!((s.nic_c, s.nac_v), (None, None));
    }

    #[test]
    fn surface_and_version_0() {
        // Surface, v2: NACv 2 (bits 17-19), NIC-C 1 (bit 20), NIC-A 1, NACp 8.
        let me =
            (31u64 << 51) | (1 << 48) | (2 << 37) | (1 << 36) | (2 << 13) | (1 << 12) | (8 << 8);
        let s = OperationalStatus::decode(me).unwrap();
        assert_eq!((s.subtype, s.version), (1, 2));
        assert_eq!(
            (s.nac_v, s.nic_c, s.nic_a, s.nac_p),
            (Some(2), Some(true), Some(true), Some(8))
        );
        assert_eq!((s.gva, s.nic_baro), (None, None));
        let s = OperationalStatus::decode(31u64 << 51).unwrap();
        assert_eq!((s.version, s.nac_p, s.sil), (0, None, None));
        assert!(OperationalStatus::decode((31u64 << 51) | (2 << 48)).is_none());
        // Version 0 has no NACv or NIC-C, on the surface too (their bits set).
        let s =
            OperationalStatus::decode((31u64 << 51) | (1 << 48) | (7 << 37) | (1 << 36)).unwrap();
        assert_eq!((s.subtype, s.version, s.nac_v, s.nic_c), (1, 0, None, None));
    }
}
