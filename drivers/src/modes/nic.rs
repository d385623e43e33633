//! Navigation integrity category from the position type code and the NIC supplements
//! (DO-260B 2.2.3.2.7.2.6 and Tables 2-14 (airborne) and 2-15 (surface); DO-260A for
//! version 1, where the only supplement is NIC-A, sent as "NIC supplement" in TC 31).
//!
//! Supplements: NIC-A and NIC-C come from operational status (TC 31), NIC-B from ME bit 8 of the
//! airborne position itself (version 2 only). Where a type code admits two NIC values and the
//! supplement is not known yet, the lower value is reported (a DAA consumer must not be told the
//! position is better contained than it is).

/// NIC for a position type code, given the ADS-B version and the supplements known so far.
pub fn nic(typecode: u8, version: u8, nic_a: bool, nic_b: bool, nic_c: bool) -> u8 {
    match typecode {
        5 | 9 | 20 => 11,
        6 | 10 | 21 => 10,
        7 => match version {
            2 if nic_a && !nic_c => 9,
            1 if nic_a => 9,
            _ => 8,
        },
        8 => match version {
            2 if nic_a && nic_c => 7,
            2 if nic_a != nic_c => 6,
            _ => 0,
        },
        11 => match version {
            2 if nic_a && nic_b => 9,
            1 if nic_a => 9,
            _ => 8,
        },
        12 => 7,
        13 => 6,
        14 => 5,
        15 => 4,
        16 => match version {
            2 if nic_a && nic_b => 3,
            1 if nic_a => 3,
            _ => 2,
        },
        17 => 1,
        _ => 0,
    }
}

#[cfg(test)]
mod tests {
    use super::nic;

    #[test]
    fn table_2_14_airborne() {
        assert_eq!(nic(9, 2, false, false, false), 11);
        assert_eq!(nic(10, 2, false, false, false), 10);
        assert_eq!(nic(11, 2, true, true, false), 9);
        assert_eq!(nic(11, 2, true, false, false), 8);
        assert_eq!(nic(11, 2, false, true, false), 8);
        assert_eq!(nic(11, 1, true, false, false), 9);
        assert_eq!(nic(11, 0, true, true, true), 8);
        assert_eq!(nic(12, 2, false, false, false), 7);
        assert_eq!(nic(13, 2, true, true, false), 6);
        assert_eq!(nic(14, 2, false, false, false), 5);
        assert_eq!(nic(15, 2, false, false, false), 4);
        assert_eq!(nic(16, 2, true, true, false), 3);
        assert_eq!(nic(16, 2, false, false, false), 2);
        // One supplement of the two is not the pair the table lists for 3: the lower value.
        assert_eq!(nic(16, 2, true, false, false), 2);
        assert_eq!(nic(16, 2, false, true, false), 2);
        assert_eq!(nic(17, 2, false, false, false), 1);
        assert_eq!(nic(18, 2, true, true, true), 0);
        assert_eq!(nic(20, 2, false, false, false), 11);
        assert_eq!(nic(21, 2, false, false, false), 10);
        assert_eq!(nic(22, 2, false, false, false), 0);
    }

    #[test]
    fn table_2_15_surface() {
        assert_eq!(nic(5, 2, false, false, false), 11);
        assert_eq!(nic(6, 2, false, false, false), 10);
        assert_eq!(nic(7, 2, true, false, false), 9);
        assert_eq!(nic(7, 2, true, false, true), 8);
        assert_eq!(nic(8, 2, true, false, true), 7);
        assert_eq!(nic(8, 2, true, false, false), 6);
        assert_eq!(nic(8, 2, false, false, true), 6);
        assert_eq!(nic(8, 2, false, false, false), 0);
    }

    #[test]
    fn version_1_reads_the_one_supplement() {
        // DO-260A: NIC-A ("NIC supplement") alone lifts TC 7 (surface), 11 and 16 (airborne)
        // to their better containment: 9, 9 and 3 instead of 8, 8 and 2.
        for (tc, with, without) in [(7, 9, 8), (11, 9, 8), (16, 3, 2)] {
            assert_eq!(nic(tc, 1, true, false, false), with, "TC {tc}");
            assert_eq!(nic(tc, 1, false, true, true), without, "TC {tc}");
        }
    }
}
