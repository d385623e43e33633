//! GDL90 Ownship Report, message ID 10 (GDL 90 Data Interface Specification 560-1058-00 Rev A,
//! 3.4): the receiver's own position, in the target report layout of [`super::report`]. The
//! TT-Multi-RF sends it once per second (manual 7.2.1, "ADS-B GDL90 protocol").

pub use super::report::TargetReport as OwnshipReport;

/// Message ID of the Ownship Report.
pub const ID: u8 = 10;

#[cfg(test)]
mod tests {
    use super::super::report::{AddressKind, LEN, TargetReport};
    use super::*;

    #[test]
    fn hand_built() {
        // Ownship at 0x100000 counts = 1048576 * 180/2^23 = 22.5 deg N and
        // 0xF00000 - 2^24 = -1048576 counts = -22.5 deg E; address 0x000001 self-assigned (t=1);
        // altitude code 0x050 = 80 -> 80 * 25 - 1000 = 1000 ft; misc 0x8 airborne, no track;
        // NIC 8 NACp 10; h = 0x00A (10 kt), v = 0xFFE (-2 * 64 = -128 fpm); call sign blank.
        let m: [u8; LEN] = [
            ID, 0x01, 0x00, 0x00, 0x01, 0x10, 0x00, 0x00, 0xF0, 0x00, 0x00, 0x05, 0x08, 0x8A, 0x00,
            0xAF, 0xFE, 0x00, 0x00, b' ', b' ', b' ', b' ', b' ', b' ', b' ', b' ', 0x00,
        ];
        let r = OwnshipReport::decode(&m).unwrap();
        assert_eq!(r.address_type, AddressKind::AdsbSelfAssigned);
        assert_eq!(r.address, 1);
        assert_eq!((r.lat_deg, r.lon_deg), (22.5, -22.5));
        assert_eq!(r.altitude_ft, Some(1000));
        assert!(r.airborne);
        assert_eq!((r.nic, r.nac_p), (8, 10));
        assert_eq!(r.horizontal_velocity.kt(), Some(10));
        assert_eq!(r.vertical_velocity.fpm(), Some(-128));
        assert_eq!(r.callsign_str(), None);
        assert_eq!(TargetReport::encode(&r, ID), m);
    }
}
