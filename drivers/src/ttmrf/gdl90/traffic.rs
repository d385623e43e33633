//! GDL90 Traffic Report, message ID 20 (GDL 90 Data Interface Specification 560-1058-00 Rev A,
//! 3.5): one target, in the layout of [`super::report`].
//!
//! The TT-Multi-RF sends one Traffic Report per ADS-B target once per second (manual 7.2.1,
//! "ADS-B GDL90 protocol"); FLARM targets are not reported over GDL90.

pub use super::report::TargetReport as TrafficReport;

/// Message ID of the Traffic Report.
pub const ID: u8 = 20;

#[cfg(test)]
mod tests {
    use super::super::report::{
        AddressKind, HorizontalVelocity, LEN, TargetReport, TrackType, VerticalVelocity,
    };
    use super::*;

    /// The GDL 90 specification's Traffic Report example (3.5.4): ID 0x14, no alert, ADS-B ICAO
    /// address AB4549, lat 44.90708 N, lon 122.99488 W, 5000 ft, airborne, true track 45 deg,
    /// NIC 10, NACp 9, 123 kt, climbing 64 fpm, light aircraft, call sign "N825V", no emergency.
    pub(crate) const SPEC_EXAMPLE: [u8; LEN] = [
        0x14, 0x00, 0xAB, 0x45, 0x49, 0x1F, 0xEF, 0x15, 0xA8, 0x89, 0x78, 0x0F, 0x09, 0xA9, 0x07,
        0xB0, 0x01, 0x20, 0x01, 0x4E, 0x38, 0x32, 0x35, 0x56, 0x20, 0x20, 0x20, 0x00,
    ];

    #[test]
    fn spec_example() {
        let r = TargetReport::decode(&SPEC_EXAMPLE).unwrap();
        assert_eq!(r.alert_status, 0);
        assert_eq!(r.address_type, AddressKind::AdsbIcao);
        assert_eq!(r.address, 0xAB4549);
        // lat 0x1FEF15 = 2092821 counts * 180/2^23 = 44.907066822052 deg.
        assert!((r.lat_deg - 44.907_066_822_052).abs() < 1e-12);
        // lon 0xA88978 - 2^24 = -5731976 counts * 180/2^23 = -122.994861602783 deg.
        assert!((r.lon_deg + 122.994_861_602_783_2).abs() < 1e-12);
        // alt code 0x0F0 = 240: 240 * 25 - 1000 = 5000 ft.
        assert_eq!(r.altitude_ft, Some(5000));
        // misc 0x9 = 0b1001: airborne, updated, true track.
        assert!(r.airborne && !r.extrapolated);
        assert_eq!(r.track_type, TrackType::TrueTrack);
        assert_eq!((r.nic, r.nac_p), (10, 9));
        // h 0x07B = 123 kt; v 0x001 = 64 fpm.
        assert_eq!(r.horizontal_velocity, HorizontalVelocity::Kt(123));
        assert_eq!(r.vertical_velocity, VerticalVelocity::Fpm(64));
        // track 0x20 = 32 * 1.40625 = 45 deg.
        assert_eq!(r.track_deg, 45.0);
        assert_eq!(r.emitter_category, 1);
        assert_eq!(r.callsign_str().as_deref(), Some("N825V"));
        assert_eq!((r.emergency_code, r.spare), (0, 0));
        assert_eq!(r.encode(ID), SPEC_EXAMPLE);
    }

    #[test]
    fn hand_built_every_field() {
        // Hand-packed report:
        // byte 1 = 0x13: alert status 1 (traffic alert), address type 3 (TIS-B track file);
        // address 0xFEDCBA;
        // lat 0xC00000 = -4194304 counts = -90 deg; lon 0x400000 = 4194304 counts = +90 deg;
        // alt code 0xFFF (invalid) with misc 0x6 = 0b0110 (on ground, extrapolated, magnetic
        // heading): bytes FF F6;
        // NIC 0, NACp 11: 0x0B;
        // h = 0xFFE (>= 4094 kt), v = 0xE02 (descent over 32576 fpm): FF EE 02;
        // heading 0xFF = 255 * 1.40625 = 358.59375 deg; emitter 14 (UAV);
        // call sign "AB12    "; emergency 5 (unlawful interference), spare 0xA: 0x5A.
        let m: [u8; LEN] = [
            ID, 0x13, 0xFE, 0xDC, 0xBA, 0xC0, 0x00, 0x00, 0x40, 0x00, 0x00, 0xFF, 0xF6, 0x0B, 0xFF,
            0xEE, 0x02, 0xFF, 14, b'A', b'B', b'1', b'2', b' ', b' ', b' ', b' ', 0x5A,
        ];
        let r = TargetReport::decode(&m).unwrap();
        assert_eq!(r.alert_status, 1);
        assert_eq!(r.address_type, AddressKind::TisbTrackFile);
        assert_eq!(r.address, 0xFEDCBA);
        assert_eq!((r.lat_deg, r.lon_deg), (-90.0, 90.0));
        assert_eq!(r.altitude_ft, None);
        assert!(!r.airborne && r.extrapolated);
        assert_eq!(r.track_type, TrackType::MagneticHeading);
        assert_eq!(r.track_deg, 358.59375);
        assert_eq!((r.nic, r.nac_p), (0, 11));
        assert_eq!(r.horizontal_velocity, HorizontalVelocity::AtLeast4094Kt);
        assert_eq!(r.vertical_velocity, VerticalVelocity::DescentOver32576Fpm);
        assert_eq!(r.emitter_category, 14);
        assert_eq!(r.callsign_str().as_deref(), Some("AB12"));
        assert_eq!((r.emergency_code, r.spare), (5, 0xA));
        assert!(r.has_position());
        assert_eq!(r.encode(ID), m);

        // Altitude extremes: code 0 = -1000 ft, code 0xFFE = 0xFFE * 25 - 1000 = 101350 ft;
        // misc 0xB = airborne, updated, true heading. v 0x1FE, h 0.
        let mut m2 = m;
        m2[11] = 0x00;
        m2[12] = 0x0B;
        m2[14] = 0x00;
        m2[15] = 0x01;
        m2[16] = 0xFE;
        let r2 = TargetReport::decode(&m2).unwrap();
        assert_eq!(r2.altitude_ft, Some(-1000));
        assert_eq!(r2.track_type, TrackType::TrueHeading);
        assert!(r2.airborne && !r2.extrapolated);
        assert_eq!(r2.horizontal_velocity, HorizontalVelocity::Kt(0));
        assert_eq!(r2.vertical_velocity, VerticalVelocity::ClimbOver32576Fpm);
        m2[11] = 0xFF;
        m2[12] = 0xE0;
        assert_eq!(
            TargetReport::decode(&m2).unwrap().altitude_ft,
            Some(101_350)
        );
    }

    #[test]
    fn no_position_convention() {
        let r = TargetReport {
            nic: 0,
            ..Default::default()
        };
        assert!(!r.has_position());
        let r = TargetReport {
            nic: 1,
            ..Default::default()
        };
        assert!(r.has_position());
    }

    #[test]
    fn wrong_length() {
        assert_eq!(TargetReport::decode(&SPEC_EXAMPLE[..27]), None);
    }
}
