//! Position integrity and accuracy of ADS-B reports (DO-260B, 2.2.3.2.7.2 tables): NIC to the
//! containment radius Rc, and NACp to the estimated position uncertainty EPU (95 % bound).

use crate::units::M_PER_NM;

/// Containment radius Rc, m, for a NIC value (0 or unknown: `None`).
///
/// NIC 6 has two radii in DO-260B (0.6 NM, or 0.3 NM with NIC supplement A); this takes the
/// conservative 0.6 NM unless the caller knows the supplements (see [`rc_m_with_supplement`]).
pub fn rc_m(nic: u8) -> Option<f64> {
    let nm = match nic {
        1 => 20.0,
        2 => 8.0,
        3 => 4.0,
        4 => 2.0,
        5 => 1.0,
        6 => 0.6,
        7 => 0.2,
        8 => 0.1,
        9 => return Some(75.0),
        10 => return Some(25.0),
        11 => return Some(7.5),
        _ => return None,
    };
    Some(nm * M_PER_NM)
}

/// Containment radius for NIC 6 with supplement A set (0.3 NM); other values as [`rc_m`].
pub fn rc_m_with_supplement(nic: u8, supplement_a: bool) -> Option<f64> {
    if nic == 6 && supplement_a {
        Some(0.3 * M_PER_NM)
    } else {
        rc_m(nic)
    }
}

/// Estimated position uncertainty (95 % horizontal bound), m, for a NACp value (0: `None`).
pub fn epu_m(nac_p: u8) -> Option<f64> {
    let nm = match nac_p {
        1 => 10.0,
        2 => 4.0,
        3 => 2.0,
        4 => 1.0,
        5 => 0.5,
        6 => 0.3,
        7 => 0.1,
        8 => 0.05,
        9 => return Some(30.0),
        10 => return Some(10.0),
        11 => return Some(3.0),
        _ => return None,
    };
    Some(nm * M_PER_NM)
}

/// 1-sigma horizontal position uncertainty, m, from a 95 % horizontal radius: for a circular
/// 2-D Gaussian, P(r <= k sigma) = 1 - exp(-k^2/2) = 0.95 gives k = sqrt(-2 ln 0.05) = 2.4477.
pub fn sigma_from_r95(r95_m: f64) -> f64 {
    r95_m / (-2.0 * 0.05f64.ln()).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-9)
    }

    #[test]
    fn tables_by_hand() {
        assert!(close(epu_m(8), 92.6)); // 0.05 NM
        assert!(close(epu_m(9), 30.0));
        assert_eq!(epu_m(0), None);
        assert!(close(rc_m(7), 370.4)); // 0.2 NM
        assert!(close(rc_m(6), 1111.2));
        assert!(close(rc_m_with_supplement(6, true), 555.6));
        assert_eq!(rc_m(12), None);
        assert!((sigma_from_r95(2.447_746_830_680_816) - 1.0).abs() < 1e-12);
    }

    /// Every row of the two DO-260B tables, as the standard gives them (NM rows converted at
    /// 1852 m per NM by hand), and `None` past them.
    #[test]
    fn every_row_of_the_nic_and_nacp_tables() {
        let nic_rc_m = [
            (1, 37_040.0), // 20 NM
            (2, 14_816.0), // 8 NM
            (3, 7_408.0),  // 4 NM
            (4, 3_704.0),  // 2 NM
            (5, 1_852.0),  // 1 NM
            (6, 1_111.2),  // 0.6 NM (no supplement)
            (7, 370.4),    // 0.2 NM
            (8, 185.2),    // 0.1 NM
            (9, 75.0),
            (10, 25.0),
            (11, 7.5),
        ];
        for (nic, rc) in nic_rc_m {
            assert!(close(rc_m(nic), rc), "NIC {nic}");
            // Supplement A changes NIC 6 only (0.3 NM); without it, NIC 6 is 0.6 NM.
            let with_a = if nic == 6 { 555.6 } else { rc };
            assert!(
                close(rc_m_with_supplement(nic, true), with_a),
                "NIC {nic}, A"
            );
            assert!(close(rc_m_with_supplement(nic, false), rc), "NIC {nic}");
        }
        let nacp_epu_m = [
            (1, 18_520.0), // 10 NM
            (2, 7_408.0),  // 4 NM
            (3, 3_704.0),  // 2 NM
            (4, 1_852.0),  // 1 NM
            (5, 926.0),    // 0.5 NM
            (6, 555.6),    // 0.3 NM
            (7, 185.2),    // 0.1 NM
            (8, 92.6),     // 0.05 NM
            (9, 30.0),
            (10, 10.0),
            (11, 3.0),
        ];
        for (nac_p, epu) in nacp_epu_m {
            assert!(close(epu_m(nac_p), epu), "NACp {nac_p}");
        }
        for code in [0, 12, 15, 255] {
            assert_eq!(rc_m(code), None);
            assert_eq!(rc_m_with_supplement(code, true), None);
            assert_eq!(epu_m(code), None);
        }
    }
}
