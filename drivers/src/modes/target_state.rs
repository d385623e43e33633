//! Target state and status, ADS-B TC 29 subtype 1 (DO-260B 2.2.3.2.7.1, version 2 layout).
//! Subtype 0 (DO-260A) is recognised, not decoded.
//!
//! ```text
//! ME bit  1-5 6-7 8       9        10-20    21-29  30  31   32-39  40-43 44      45-46 47 48 49   50  51 52  53   54   55-56
//!         TC  ST  SILsup  ALTtype  SEL ALT  BARO   HS  HSgn HDG    NACp  NICbaro SIL   MS AP VNAV ALT -  APP ACAS LNAV -
//! ```

use serde::Serialize;

use super::bits;

/// A TC 29 subtype 1 squitter.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TargetState {
    /// Subtype (1 = DO-260B; 0 = DO-260A, whose fields are not decoded).
    pub subtype: u8,
    /// Selected altitude, ft (`None` = no data).
    pub selected_altitude_ft: Option<i32>,
    /// The selected altitude comes from the FMS (true) or the MCP/FCU (false).
    pub selected_altitude_fms: bool,
    /// Barometric pressure setting, hPa (`None` = no data).
    pub baro_setting_hpa: Option<f64>,
    /// Selected heading, degrees (`None` = not valid).
    pub selected_heading_deg: Option<f64>,
    /// NACp.
    pub nac_p: u8,
    /// NIC-baro.
    pub nic_baro: bool,
    /// SIL.
    pub sil: u8,
    /// SIL supplement (true = per sample, false = per hour).
    pub sil_per_sample: bool,
    /// Autopilot, VNAV, altitude hold, approach, LNAV engaged (valid when `modes_valid`).
    pub autopilot: bool,
    /// VNAV mode engaged.
    pub vnav: bool,
    /// Altitude hold mode engaged.
    pub alt_hold: bool,
    /// Approach mode engaged.
    pub approach: bool,
    /// LNAV mode engaged.
    pub lnav: bool,
    /// The mode bits above are valid (ME bit 47).
    pub modes_valid: bool,
    /// ACAS operational.
    pub acas_operational: bool,
}

impl TargetState {
    /// Decodes a TC 29 ME field; `None` for subtypes other than 1.
    #[inline]
    pub fn decode(me: u64) -> Option<Self> {
        let subtype = bits(me, 6, 2) as u8;
        if subtype != 1 {
            return None;
        }
        let alt = bits(me, 10, 11) as i32;
        let baro = bits(me, 21, 9) as f64;
        let hdg = bits(me, 31, 9) as f64;
        Some(TargetState {
            subtype,
            sil_per_sample: bits(me, 8, 1) == 1,
            selected_altitude_fms: bits(me, 9, 1) == 1,
            selected_altitude_ft: (alt != 0).then(|| (alt - 1) * 32),
            baro_setting_hpa: (baro != 0.0).then_some(800.0 + (baro - 1.0) * 0.8),
            selected_heading_deg: (bits(me, 30, 1) == 1).then(|| hdg * 180.0 / 256.0),
            nac_p: bits(me, 40, 4) as u8,
            nic_baro: bits(me, 44, 1) == 1,
            sil: bits(me, 45, 2) as u8,
            modes_valid: bits(me, 47, 1) == 1,
            autopilot: bits(me, 48, 1) == 1,
            vnav: bits(me, 49, 1) == 1,
            alt_hold: bits(me, 50, 1) == 1,
            approach: bits(me, 52, 1) == 1,
            acas_operational: bits(me, 53, 1) == 1,
            lnav: bits(me, 54, 1) == 1,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_built() {
        // Selected altitude 35 008 ft -> raw 35008/32 + 1 = 1095; baro 1013.6 hPa -> raw
        // (1013.6 - 800)/0.8 + 1 = 268; heading 49.2 deg -> raw 49.21875*256/180 = 70;
        // NACp 10, NIC-baro 1, SIL 3, ACAS.
        let me = (29u64 << 51)
            | (1 << 49)
            | (1 << 48)
            | (1095 << 36)
            | (268 << 27)
            | (1 << 26)
            | (70 << 17)
            | (10 << 13)
            | (1 << 12)
            | (3 << 10)
            | (1 << 3);
        let t = TargetState::decode(me).unwrap();
        assert_eq!(t.selected_altitude_ft, Some(35_008));
        assert!((t.baro_setting_hpa.unwrap() - 1013.6).abs() < 1e-9);
        assert!((t.selected_heading_deg.unwrap() - 49.218_75).abs() < 1e-9);
        assert_eq!((t.nac_p, t.nic_baro, t.sil), (10, true, 3));
        assert!(t.acas_operational && t.sil_per_sample && !t.autopilot);
        assert!(TargetState::decode(29u64 << 51).is_none());
        // All "no data".
        let t = TargetState::decode((29u64 << 51) | (1 << 49)).unwrap();
        assert_eq!(
            (
                t.selected_altitude_ft,
                t.baro_setting_hpa,
                t.selected_heading_deg
            ),
            (None, None, None)
        );
    }

    #[test]
    fn each_mode_flag_at_its_me_bit() {
        // DO-260B 2.2.3.2.7.1.3: ME bit 8 SIL supplement, 9 selected altitude from the FMS,
        // 44 NIC-baro, 47 mode bits valid, 48 autopilot, 49 VNAV, 50 altitude hold,
        // 52 approach, 53 ACAS operational, 54 LNAV (bit 1 is the ME's first, 56 its last).
        let flags = |t: &TargetState| {
            [
                t.sil_per_sample,
                t.selected_altitude_fms,
                t.nic_baro,
                t.modes_valid,
                t.autopilot,
                t.vnav,
                t.alt_hold,
                t.approach,
                t.acas_operational,
                t.lnav,
            ]
        };
        let base = (29u64 << 51) | (1 << 49);
        assert_eq!(flags(&TargetState::decode(base).unwrap()), [false; 10]);
        for (i, bit) in [8, 9, 44, 47, 48, 49, 50, 52, 53, 54]
            .into_iter()
            .enumerate()
        {
            let t = TargetState::decode(base | (1 << (56 - bit))).unwrap();
            let mut want = [false; 10];
            want[i] = true;
            assert_eq!(flags(&t), want, "ME bit {bit}");
        }
    }
}
