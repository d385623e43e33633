//! Every worked example of the GDL 90 Data Interface Specification 560-1058-00 Rev A that
//! concerns the messages decoded here, each checked against the decoders and encoders.

use super::framing::{self, FLAG};
use super::geo_altitude::{GeoAltitude, Vfom};
use super::heartbeat::Heartbeat;
use super::report::{LEN, TargetReport};
use super::{Gdl90Decoder, Gdl90Message};
use crate::testkit::decode_chunked;

/// A traffic report whose latitude, longitude and altitude fields carry the given codes.
fn report_with(lat: [u8; 3], lon: [u8; 3], alt_code: u16) -> TargetReport {
    let mut m = [0u8; LEN];
    m[0] = 20;
    m[5..8].copy_from_slice(&lat);
    m[8..11].copy_from_slice(&lon);
    m[11] = (alt_code >> 4) as u8;
    m[12] = ((alt_code & 0xF) as u8) << 4;
    m[14] = 0xFF;
    m[15] = 0xF8; // h = 0xFFF, v = 0x800
    TargetReport::decode(&m).unwrap()
}

#[test]
fn section_2_2_1_escaping_examples() {
    // "start of message ID #2 with second byte 0x7E: 0x7E 0x02 0x7D 0x5E ..."
    // "start of message ID #3 with second byte 0x7D: 0x7E 0x03 0x7D 0x5D ..."
    let mut out = Vec::new();
    framing::frame(&[0x02, 0x7E], &mut out);
    assert_eq!(&out[..4], &[FLAG, 0x02, 0x7D, 0x5E]);
    out.clear();
    framing::frame(&[0x03, 0x7D], &mut out);
    assert_eq!(&out[..4], &[FLAG, 0x03, 0x7D, 0x5D]);
    // "end of message with CRC value of 0x7D 0x7E: ...0x7D 0x5D 0x7D 0x5E 0x7E": unescaping
    // such an ending gives back the FCS bytes 7D 7E (LSB first: FCS 0x7E7D).
    let mut clear = Vec::new();
    let err = framing::unframe(&[0x00, 0x7D, 0x5D, 0x7D, 0x5E], &mut clear).unwrap_err();
    assert_eq!(
        err,
        framing::FrameError::Fcs {
            computed: 0x0000,
            received: 0x7E7D
        }
    );
}

#[test]
fn section_2_2_1_back_to_back_messages() {
    // "0x7E <message1> 0x7E 0x7E <message2> 0x7E": two heartbeats, no skipped byte.
    let hb = [
        0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
    ];
    let bytes = [hb, hb].concat();
    let (msgs, stats) = decode_chunked(Gdl90Decoder::default(), &bytes, &[bytes.len()]);
    assert_eq!(msgs.len(), 2);
    assert_eq!(stats.bytes_skipped, 0);
}

#[test]
fn section_3_1_4_message_counts() {
    // "If 4 Uplink messages and a total of 567 Basic and Long messages were received in the
    // previous second, the Heartbeat message Byte 6 value will be 0x22, and the Byte 7 value
    // will be 0x37."
    let h = Heartbeat {
        uplink_count: 4,
        basic_long_count: 567,
        ..Default::default()
    };
    let m = h.encode();
    assert_eq!((m[5], m[6]), (0x22, 0x37));
    assert_eq!(Heartbeat::decode(&m).unwrap(), h);
}

#[test]
fn section_3_5_1_3_latitude_longitude_examples() {
    let lsb = 180.0 / 8_388_608.0;
    let cases: [([u8; 3], f64); 8] = [
        ([0x00, 0x00, 0x00], 0.0),
        ([0x00, 0x00, 0x01], lsb),
        ([0xFF, 0xFF, 0xFF], -lsb),
        ([0x20, 0x00, 0x00], 45.0),
        ([0xE0, 0x00, 0x00], -45.0),
        ([0x40, 0x00, 0x00], 90.0),
        ([0x80, 0x00, 0x00], -180.0),
        ([0x7F, 0xFF, 0xFF], 180.0 - lsb),
    ];
    for (code, deg) in cases {
        let r = report_with(code, code, 0xFFF);
        assert_eq!((r.lat_deg, r.lon_deg), (deg, deg), "{code:02X?}");
        let m = r.encode(20);
        assert_eq!(&m[5..8], &code);
        assert_eq!(&m[8..11], &code);
    }
}

#[test]
fn section_3_5_1_4_altitude_examples() {
    for (code, ft) in [
        (0x000, Some(-1000)),
        (0x028, Some(0)),
        (0x050, Some(1000)),
        (0xFFE, Some(101_350)),
        (0xFFF, None),
    ] {
        let r = report_with([0; 3], [0; 3], code);
        assert_eq!(r.altitude_ft, ft, "{code:#05x}");
        let m = r.encode(20);
        assert_eq!(u16::from(m[11]) << 4 | u16::from(m[12] >> 4), code);
    }
}

#[test]
fn section_3_5_1_8_vertical_velocity_examples() {
    use super::report::VerticalVelocity as V;
    for (code, v) in [
        (0x000u16, V::Fpm(0)),
        (0x001, V::Fpm(64)),
        (0xFFF, V::Fpm(-64)),
        (0x1FD, V::Fpm(32_576)),
        (0x1FE, V::ClimbOver32576Fpm),
        (0xE03, V::Fpm(-32_576)),
        (0xE02, V::DescentOver32576Fpm),
        (0x800, V::Unavailable),
    ] {
        let mut m = [0u8; LEN];
        m[0] = 20;
        m[15] = (code >> 8) as u8;
        m[16] = code as u8;
        let r = TargetReport::decode(&m).unwrap();
        assert_eq!(r.vertical_velocity, v, "{code:#05x}");
        assert_eq!(r.encode(20), m);
    }
}

#[test]
fn section_3_5_1_10_emitter_example() {
    // "ee = 0x11 -> Surface Emergency Vehicle" (17 in the set TrafficReport uses).
    let mut m = [0u8; LEN];
    m[0] = 20;
    m[18] = 0x11;
    let r = TargetReport::decode(&m).unwrap();
    let t = Gdl90Message::TrafficReport(r)
        .to_traffic(super::TrafficAltitude::Pressure)
        .unwrap();
    assert_eq!(t.emitter_category, Some(17));
}

#[test]
fn section_3_8_geometric_altitude_examples() {
    for (bytes, ft) in [
        ([0xFF, 0x38], -1000),
        ([0x00, 0x00], 0),
        ([0x00, 0xC8], 1000),
    ] {
        let m = [11, bytes[0], bytes[1], 0x7F, 0xFF];
        let g = GeoAltitude::decode(&m).unwrap();
        assert_eq!(g.geo_altitude_ft, ft);
        assert_eq!(g.encode(), m);
    }
    for (metrics, warning, vfom) in [
        (0xFFFFu16, true, Vfom::Unavailable),
        (0x7FFE, false, Vfom::AtLeast32766M),
        (0x000A, false, Vfom::Meters(10)),
        (0x8032, true, Vfom::Meters(50)),
    ] {
        let v = metrics.to_be_bytes();
        let g = GeoAltitude::decode(&[11, 0, 0, v[0], v[1]]).unwrap();
        assert_eq!(
            (g.vertical_warning, g.vfom),
            (warning, vfom),
            "{metrics:#06x}"
        );
    }
    // "No Vertical Warning, VFOM = 40,000 meters: 0x7FFE".
    let g = GeoAltitude {
        geo_altitude_ft: 0,
        vertical_warning: false,
        vfom: Vfom::Meters(40_000),
    };
    assert_eq!(&g.encode()[3..], &[0x7F, 0xFE]);
}
