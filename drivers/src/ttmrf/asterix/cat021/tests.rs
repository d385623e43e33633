//! CAT021 record tests: the real sample (values derived by hand below), hand-built records for
//! every decoded item and for every length rule of the skipped items, errors, and round trips.

use proptest::prelude::*;

use super::super::common::DataSource;
use super::identity::{MopsVersion, OperationalStatus};
use super::kinematics::{
    ANGLE_LSB_DEG, AirSpeed, FL_LSB, GroundVector, HEIGHT_LSB_FT, POS_HR_LSB_DEG, POS_LSB_DEG,
    Position, SPEED_LSB_KT, TAR_LSB_DPS, TrueAirspeed, VRATE_LSB_FPM, VerticalRate,
};
use super::status::{
    DescriptorExt1, DescriptorExt2, QualityExt1, QualityIndicators, TargetReportDescriptor,
    TargetStatus,
};
use super::time::{HP_LSB_S, HighPrecisionTime};
use super::*;
use crate::traffic::{AddressType, Link, Protocol, SourceTime};

/// The two records of `cat21_re.ast` (each block = CAT 0x15, LEN, one record), as derived by hand:
///
/// Block 1 `15 00 2C`: CAT 21, LEN 44. FSPEC `C5 1D 31 01 43 23 04` (7 octets, FX set on all but
/// the last):
/// - C5 = 1100 0101: FRN 1 (I021/010), 2 (040), 6 (130);
/// - 1D = 0001 1101: FRN 11 (080), 12 (073), 13 (074);
/// - 31 = 0011 0001: FRN 17 (090), 18 (210);
/// - 01: none; 43 = 0100 0011: FRN 30 (020), 35 (016);
/// - 23 = 0010 0011: FRN 38 (132), 42 (295); 04 = 0000 0100: FRN 48 (RE), no FX.
///
/// Items: 010 `00 01` SAC 0 SIC 1; 040 `01 40` (FX on the first octet) ATP 0, ARC 0, GBS set;
/// 130 `2B B7 3E FA 65 BA`: lat 2864958 * 180/2^23 = 61.47532939910889, lon -367174 * 180/2^23
/// = -7.87869930267334; 080 `00 00 01`; 073 `38 41 76` = 3686774/128 = 28802.921875 s;
/// 074 `3A DA B9 F5` FSI 0, fraction 987412981 * 2^-30 = 0.9195999996736646 s; 090 `00` NACv 0
/// NIC 0; 210 `02` VNS 0 VN 0 LTT 2 (1090 ES); 020 `00`; 016 `08` = 8 * 0.5 = 4 s; 132 `CB` =
/// -53 dBm; 295 `54 0D 0D 0D` (compound: 0x54 marks subfields 2, 4, 6, one octet each);
/// RE `05 08 F0 01 62` (explicit length 5). 3 + 7 + 34 = 44 octets.
///
/// Block 2 `15 00 2F`: LEN 47, the same FSPEC. 130 `2B B7 3A FA 65 B3`: lat 2864954 counts =
/// 61.47524356842041, lon -367181 counts = -7.878849506378174; 080 `00 00 02`; 073 `38 41 95` =
/// 3686805/128 = 28803.1640625 s; 074 `0A 48 5A 0C` FSI 0, fraction 172513804 * 2^-30 =
/// 0.16066600009799004 s; 020 `15` = 21 (surface service vehicle); 132 `AD` = -83 dBm;
/// 295 `55 01 10 0A 0A 0A FF` (primary subfield of 3 octets: subfields 2, 4, 6, 18);
/// RE `05 08 70 F1 40`.
struct Expected {
    address: u32,
    lat: f64,
    lon: f64,
    tod: f64,
    frac: f64,
    ecat: u8,
    dbm: i8,
}

fn check_sample_record(r: &Cat021Record, e: &Expected) {
    let Expected {
        address,
        lat,
        lon,
        tod,
        frac,
        ecat,
        dbm,
    } = *e;
    assert_eq!(r.data_source, Some(DataSource { sac: 0, sic: 1 }));
    let d = r.descriptor.unwrap();
    assert_eq!((d.atp, d.arc, d.rc, d.rab), (0, 0, false, false));
    let e1 = d.ext1.unwrap();
    assert!(e1.gbs && !e1.sim && !e1.tst && !e1.dcr && !e1.saa);
    assert_eq!(e1.cl, 0);
    let p = r.position.unwrap();
    assert!((p.lat_deg - lat).abs() < 1e-12, "{p:?}");
    assert!((p.lon_deg - lon).abs() < 1e-12, "{p:?}");
    assert_eq!(r.target_address, Some(address));
    assert_eq!(r.time_reception_position_s, Some(tod));
    let hp = r.time_reception_position_hp.unwrap();
    assert_eq!(hp.fsi, 0);
    assert!((hp.fraction_s - frac).abs() < 1e-15);
    let q = r.quality.unwrap();
    assert_eq!((q.nac_v, q.nic, q.ext1), (0, 0, None));
    assert_eq!(
        r.mops,
        Some(MopsVersion {
            vns: false,
            vn: 0,
            ltt: 2
        })
    );
    assert_eq!(r.emitter_category, Some(ecat));
    assert_eq!(r.report_period_s, Some(4.0));
    assert_eq!(r.amplitude_dbm, Some(dbm));
    assert_eq!(r.undecoded, vec!["I021/295"]);
    assert!(r.reserved.as_ref().unwrap().surface_vector.is_some());
    // Absent items stay absent.
    assert_eq!(r.track_number, None);
    assert_eq!(r.flight_level, None);
    assert_eq!(r.target_id, None);
}

#[test]
fn real_sample() {
    let Some(path) = crate::testkit::shared_data("asterix/cat21_re.ast") else {
        return;
    };
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(bytes.len(), 91);
    // Block 1: LEN 44, body from octet 3.
    assert_eq!(&bytes[..3], &[0x15, 0x00, 0x2C]);
    let (r1, len1) = decode_record(&bytes[3..44]).unwrap();
    assert_eq!(len1, 41);
    check_sample_record(
        &r1,
        &Expected {
            address: 0x000001,
            lat: 61.475_329_399_108_89,
            lon: -7.878_699_302_673_34,
            tod: 28_802.921_875,
            frac: 0.919_599_999_673_664_6,
            ecat: 0,
            dbm: -53,
        },
    );
    assert_eq!(&bytes[44..47], &[0x15, 0x00, 0x2F]);
    let (r2, len2) = decode_record(&bytes[47..]).unwrap();
    assert_eq!(len2, 44);
    check_sample_record(
        &r2,
        &Expected {
            address: 0x000002,
            lat: 61.475_243_568_420_41,
            lon: -7.878_849_506_378_174,
            tod: 28_803.164_062_5,
            frac: 0.160_666_000_097_990_04,
            ecat: 21,
            dbm: -83,
        },
    );

    // Traffic mapping of record 1: ADS-B 1090 (SIC 1 is not FLARM, LTT 2), ICAO address
    // 000001, on the ground (GBS), NIC/NACv 0 (no NACp: no 090 extension), -53 dBm,
    // time 28802 + 0.9195999996736646 s = 28802919599999.67 ns -> 28802919600000 ns.
    let t = traffic::to_traffic(&r1);
    assert_eq!(t.link, Link::Adsb1090);
    assert_eq!(t.protocol, Protocol::Asterix);
    assert_eq!(t.address_hex(), "000001");
    assert_eq!(t.address_type, AddressType::Icao);
    assert!(t.flags.on_ground && !t.flags.test && !t.flags.degraded);
    assert_eq!((t.nic, t.nac_v, t.nac_p), (Some(0), Some(0), None));
    assert_eq!(t.signal_dbm, Some(-53.0));
    assert_eq!(t.emitter_category, Some(0));
    assert_eq!(
        t.source_time,
        Some(SourceTime::AsterixTodNs(28_802_919_600_000))
    );
    assert_eq!(t.lat_deg, Some(r1.position.unwrap().lat_deg));
    assert_eq!(t.alt_pressure_m, None);
    // RE/SGV of record 1: stopped, 0 kt; its ground track (137.8125 deg) is magnetic: not
    // mapped.
    let sgv = r1.reserved.as_ref().unwrap().surface_vector.unwrap();
    assert!(sgv.stopped && sgv.magnetic);
    assert_eq!(sgv.hgt_deg, Some(137.8125));
    assert_eq!(t.ground_speed_mps, Some(0.0));
    assert_eq!((t.track_deg, t.heading_deg), (None, None));
    // Record 2: ECAT 21 (surface service vehicle) is emitter category 18 in the DO-260B set;
    // time 28803 + 0.16066600009799004 s -> 28803160666000 ns (0.098 ns rounds down).
    let t2 = traffic::to_traffic(&r2);
    assert_eq!(t2.emitter_category, Some(18));
    // RE/SGV of record 2: moving at 120/8 = 15 kt (7.7166... m/s), magnetic ground track 90 deg.
    let sgv = r2.reserved.as_ref().unwrap().surface_vector.unwrap();
    assert_eq!(
        (sgv.stopped, sgv.ground_speed_kt, sgv.hgt_deg),
        (false, 15.0, Some(90.0))
    );
    assert!((t2.ground_speed_mps.unwrap() - 15.0 * 1852.0 / 3600.0).abs() < 1e-12);
    assert_eq!(t2.track_deg, None);
    assert_eq!(
        t2.source_time,
        Some(SourceTime::AsterixTodNs(28_803_160_666_000))
    );
}

/// A FLARM record with every decoded item except I021/130, 073, 074, 016 and 132, packed by hand.
///
/// FSPEC `FB F3 FB FF C1 80`:
/// - FB = 1111 1011: FRN 1 (010), 2 (040), 3 (161), 4 (015), 5 (071), 7 (131), FX;
/// - F3 = 1111 0011: FRN 8 (072), 9 (150), 10 (151), 11 (080), 14 (075), FX;
/// - FB = 1111 1011: FRN 15 (076), 16 (140), 17 (090), 18 (210), 19 (070), 21 (145), FX;
/// - FF: FRN 22 (152), 23 (200), 24 (155), 25 (157), 26 (160), 27 (165), 28 (077), FX;
/// - C1 = 1100 0001: FRN 29 (170), 30 (020), FX;  80: FRN 36 (008).
pub(crate) const FLARM_RECORD: &[u8] = &[
    0xFB, 0xF3, 0xFB, 0xFF, 0xC1, 0x80, // FSPEC
    0x00, 0xA1, // 010: SAC 0, SIC 161 (FLARM)
    0x61, 0x00, // 040: 011 00 0 0 1 = ATP 3 (not ICAO-based), FX; ext1 all clear
    0x01, 0x23, // 161: track number 0x123 = 291
    0x07, // 015: service id 7
    0x00, 0x00, 0x80, // 071: 128/128 = 1.0 s
    0x10, 0x00, 0x00, 0x00, 0xE0, 0x00, 0x00,
    0x00, // 131: 2^28 and -2^29 * 180/2^30 = 45, -90
    0x00, 0x01, 0x00, // 072: 256/128 = 2.0 s
    0x04, 0x00, // 150: IAS 1024 * 2^-14 NM/s = 225 kt
    0x00, 0xFA, // 151: 250 kt
    0xDD, 0x12, 0x34, // 080: DD1234
    0x00, 0x01, 0x80, // 075: 384/128 = 3.0 s
    0x40, 0x00, 0x00, 0x00, // 076: FSI 1, fraction 0
    0x03, 0x20, // 140: 800 * 6.25 = 5000 ft
    0x51, 0xD2, // 090: 010 1000 1 NACv 2 NIC 8 FX; 1 10 1001 0 NICbaro SIL 2 NACp 9
    0x42, // 210: 0 1 000 010: VNS 1 (FLARM, manual 8.2.1), VN 0, LTT 2
    0x0F, 0xC0, // 070: 111 111 000 000 = 7700
    0x00, 0xC8, // 145: 200/4 = FL 50
    0xC0, 0x00, // 152: 0xC000 * 360/2^16 = 270 deg magnetic
    0x04, // 200: 000 001 00: PS 1 (general emergency)
    0x00, 0xA0, // 155: 160 * 6.25 = 1000 ft/min
    0x7F, 0x60, // 157: 0x7F60 - 2^15 = -160 -> -1000 ft/min
    0x02, 0x00, 0x40, 0x00, // 160: 512 * 3600/16384 = 112.5 kt, 0x4000 -> 90 deg
    0x00, 0x20, // 165: 32/32 = 1 deg/s
    0x00, 0x02, 0x00, // 077: 512/128 = 4.0 s
    0x3B, 0x8C, 0xB5, 0x5A, 0x08, 0x20, // 170: "N825V   " (see identity.rs)
    0x09, // 020: 9 = glider in the manual's table 28 numbering
    0x02, // 008: "not TCAS" only
];

#[test]
fn hand_built_flarm_record() {
    let (r, len) = decode_record(FLARM_RECORD).unwrap();
    assert_eq!(len, FLARM_RECORD.len());
    assert!(r.data_source.unwrap().is_flarm());
    assert_eq!(r.descriptor.unwrap().atp, 3);
    assert_eq!(r.track_number, Some(291));
    assert_eq!(r.service_id, Some(7));
    assert_eq!(r.time_applicability_position_s, Some(1.0));
    assert_eq!(
        r.position_high_res,
        Some(Position {
            lat_deg: 45.0,
            lon_deg: -90.0
        })
    );
    assert_eq!(r.time_applicability_velocity_s, Some(2.0));
    assert_eq!(r.air_speed, Some(AirSpeed::IasKt(225.0)));
    assert_eq!(
        r.true_airspeed,
        Some(TrueAirspeed {
            range_exceeded: false,
            kt: 250
        })
    );
    assert_eq!(r.target_address, Some(0xDD1234));
    assert_eq!(r.time_reception_velocity_s, Some(3.0));
    assert_eq!(
        r.time_reception_velocity_hp.unwrap().full_time_s(3.0),
        Some(4.0)
    );
    assert_eq!(r.geometric_height_ft, Some(5000.0));
    let q = r.quality.unwrap();
    assert_eq!((q.nac_v, q.nic), (2, 8));
    assert_eq!(
        q.ext1,
        Some(QualityExt1 {
            nic_baro: true,
            sil: 2,
            nac_p: 9
        })
    );
    assert!(r.mops.unwrap().vns);
    assert_eq!(r.mode3a, Some(7700));
    assert_eq!(r.flight_level, Some(50.0));
    assert_eq!(r.magnetic_heading_deg, Some(270.0));
    assert_eq!(r.target_status.unwrap().ps, 1);
    assert_eq!(r.baro_vertical_rate.unwrap().fpm, 1000.0);
    assert_eq!(r.geo_vertical_rate.unwrap().fpm, -1000.0);
    assert_eq!(
        r.ground_vector,
        Some(GroundVector {
            range_exceeded: false,
            ground_speed_kt: 112.5,
            track_deg: 90.0
        })
    );
    assert_eq!(r.track_angle_rate_dps, Some(1.0));
    assert_eq!(r.time_report_transmission_s, Some(4.0));
    assert_eq!(r.target_id.as_deref(), Some("N825V"));
    assert_eq!(r.emitter_category, Some(9));
    assert!(r.operational_status.unwrap().not_tcas);
    assert!(r.undecoded.is_empty());
    // Encoding reproduces the hand-packed bytes.
    let mut out = Vec::new();
    r.encode(&mut out);
    assert_eq!(out, FLARM_RECORD);

    let t = traffic::to_traffic(&r);
    assert_eq!(t.link, Link::Flarm);
    assert_eq!(t.address_hex(), "DD1234");
    assert_eq!(t.address_type, AddressType::NonIcao);
    assert_eq!(t.callsign.as_deref(), Some("N825V"));
    assert_eq!(t.squawk, Some(7700));
    // FLARM: table 28 value 9 (glider) taken as is; as an ECAT code 9 would be reserved.
    assert_eq!(t.emitter_category, Some(9));
    assert_eq!(traffic::ecat_to_emitter(9), None);
    assert_eq!((t.lat_deg, t.lon_deg), (Some(45.0), Some(-90.0)));
    // FL 50 = 5000 ft = 1524 m; geometric 5000 ft = 1524 m.
    assert!((t.alt_pressure_m.unwrap() - 1524.0).abs() < 1e-9);
    assert!((t.alt_geometric_m.unwrap() - 1524.0).abs() < 1e-9);
    assert_eq!(t.track_deg, Some(90.0));
    assert_eq!(t.heading_deg, None);
    // 112.5 kt * 1852/3600 = 57.875 m/s; baro rate 1000 ft/min * 0.00508 = 5.08 m/s.
    assert!((t.ground_speed_mps.unwrap() - 57.875).abs() < 1e-12);
    assert!((t.vertical_rate_mps.unwrap() - 5.08).abs() < 1e-12);
    assert_eq!(
        (t.nic, t.nac_p, t.nac_v, t.sil),
        (Some(8), Some(9), Some(2), Some(2))
    );
    assert_eq!(t.emergency_code, Some(1));
    assert!(t.flags.emergency && !t.flags.ident && !t.flags.on_ground);
    // Time of applicability for position (071) = 1.0 s.
    assert_eq!(t.source_time, Some(SourceTime::AsterixTodNs(1_000_000_000)));
}

#[test]
fn flarm_privacy_markers_are_not_callsigns() {
    let mut r = decode_record(FLARM_RECORD).unwrap().0;
    for marker in ["STEALTH", "NOTRACK"] {
        r.target_id = Some(marker.to_string());
        let mut bytes = Vec::new();
        r.encode(&mut bytes);
        let back = decode_record(&bytes).unwrap().0;
        assert_eq!(back.target_id.as_deref(), Some(marker));
        assert_eq!(traffic::to_traffic(&back).callsign, None);
    }
    // On an ADS-B target the same text is a call sign.
    r.data_source = Some(DataSource { sac: 0, sic: 1 });
    assert_eq!(traffic::to_traffic(&r).callsign.as_deref(), Some("NOTRACK"));
    // And ECAT 9 of a non-FLARM target is reserved: no category.
    assert_eq!(traffic::to_traffic(&r).emitter_category, None);
}

#[test]
fn mapping_flags_and_fallbacks() {
    let r = Cat021Record {
        data_source: Some(DataSource { sac: 1, sic: 2 }),
        descriptor: Some(TargetReportDescriptor {
            atp: 2,
            ext1: Some(DescriptorExt1 {
                sim: true,
                cl: 1,
                ..Default::default()
            }),
            ..Default::default()
        }),
        mops: Some(MopsVersion {
            vns: false,
            vn: 2,
            ltt: 1,
        }),
        position: Some(Position {
            lat_deg: 1.0,
            lon_deg: 2.0,
        }),
        baro_vertical_rate: Some(VerticalRate {
            range_exceeded: true,
            fpm: 100.0,
        }),
        geo_vertical_rate: Some(VerticalRate {
            range_exceeded: false,
            fpm: -625.0,
        }),
        ground_vector: Some(GroundVector {
            range_exceeded: true,
            ground_speed_kt: 7000.0,
            track_deg: 10.0,
        }),
        geometric_height_ft: Some(f64::from(i16::MAX) * HEIGHT_LSB_FT),
        target_status: Some(TargetStatus {
            ss: 3,
            ..Default::default()
        }),
        time_reception_position_s: Some(10.5),
        ..Default::default()
    };
    let t = traffic::to_traffic(&r);
    assert_eq!(t.link, Link::Uat978);
    // ATP 2 (surface vehicle) but no I021/080: address 0 of unknown type.
    assert_eq!(t.address_type, AddressType::Unknown);
    let mut with_address = r.clone();
    with_address.target_address = Some(0x123456);
    assert_eq!(
        traffic::to_traffic(&with_address).address_type,
        AddressType::Surface
    );
    assert!(t.flags.test && t.flags.degraded && t.flags.ident && !t.flags.emergency);
    assert_eq!((t.lat_deg, t.lon_deg), (Some(1.0), Some(2.0)));
    // Baro rate out of range: the geometric one is used, -625 * 0.00508 = -3.175 m/s.
    assert!((t.vertical_rate_mps.unwrap() + 3.175).abs() < 1e-12);
    assert_eq!((t.ground_speed_mps, t.track_deg), (None, Some(10.0)));
    assert_eq!(t.alt_geometric_m, None);
    assert_eq!(t.address, 0);
    // No 071, no 074: the coarse reception time.
    assert_eq!(
        t.source_time,
        Some(SourceTime::AsterixTodNs(10_500_000_000))
    );
}

/// A record with every skipped item and every length rule, followed by a second record: both
/// decode only if each item is skipped exactly.
///
/// FSPEC `81 01 05 01 3F FF 06`: FRN 1 (010) | - | FRN 20 (230) | - | FRN 31 (220), 32 (146),
/// 33 (148), 34 (110), 35 (016) | FRN 36 (008) .. 42 (295) | FRN 48 (RE), 49 (SP).
pub(crate) const SKIPPING_RECORD: &[u8] = &[
    0x81, 0x01, 0x05, 0x01, 0x3F, 0xFF, 0x06, // FSPEC
    0x00, 0x01, // 010
    0xFF, 0x00, // 230 roll angle (fixed 2)
    0xF0, 0x00, 0x10, 0x00, 0x5A, 0xFF, 0x00, 0x03, // 220 compound: WS 2, WD 2, TMP 2, TRB 1
    0x80, 0x00, // 146 (fixed 2)
    0x00, 0x00, // 148 (fixed 2)
    0xC0, 0x81, 0x00, 0x01, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14,
    15,   // 110 compound: TIS extended (81 00), TID REP 1 x 15 octets
    0x08, // 016: 4 s
    0x02, // 008: not TCAS
    0x03, 0x03, // 271: FX, then an extension whose LSB (part of LW) is set but is not FX
    0xC4, // 132: -60 dBm
    0x02, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, // 250 REP 2 x 8
    1, 2, 3, 4, 5, 6, 7,    // 260 (fixed 7)
    0x01, // 400
    0x81, 0x01, 0x01, 0x40, 0x11,
    0x22, // 295: primary 4 octets (4th: 0x80 = sub 22, 0x40 = sub 23), subfields 1 and 23
    0x03, 0xAA, 0xBB, // RE, explicit length 3
    0x02, 0xCC, // SP, explicit length 2
];

#[test]
fn every_length_rule_is_skipped_exactly() {
    let mut body = SKIPPING_RECORD.to_vec();
    body.extend_from_slice(&[0x80, 0x00, 0x02]); // second record: 010 only
    let (r, len) = decode_record(&body).unwrap();
    assert_eq!(len, SKIPPING_RECORD.len());
    // RE here is 03 AA BB: indicator 0xAA marks BPS, NAV, SGV and TNH but one octet follows:
    // its content does not decode, so RE stays listed as undecoded.
    assert_eq!(r.reserved, None);
    assert_eq!(
        r.undecoded,
        vec![
            "I021/230", "I021/220", "I021/146", "I021/148", "I021/110", "I021/271", "I021/250",
            "I021/260", "I021/400", "I021/295", "I021/RE", "I021/SP"
        ]
    );
    assert_eq!(r.report_period_s, Some(4.0));
    assert!(r.operational_status.unwrap().not_tcas);
    assert_eq!(r.amplitude_dbm, Some(-60));
    let (r2, len2) = decode_record(&body[len..]).unwrap();
    assert_eq!(len2, 3);
    assert_eq!(r2.data_source, Some(DataSource { sac: 0, sic: 2 }));
}

#[test]
fn record_errors() {
    use super::super::item::ItemError;
    // FRN 43 (unused in the UAP): 7th FSPEC octet 0x80.
    let b = [0x81, 0x01, 0x01, 0x01, 0x01, 0x01, 0x80, 0x00, 0x01];
    assert_eq!(decode_record(&b), Err(ItemError::UndefinedFrn(43)));
    // FSPEC running off the end.
    assert_eq!(decode_record(&[0x81]), Err(ItemError::Truncated("fspec")));
    // 295 marking subfield 24 (undefined): primary 01 01 01 20 (4th octet: 0x80 = subfield 22,
    // 0x40 = 23, 0x20 = 24).
    let b = [
        0x81, 0x01, 0x01, 0x01, 0x01, 0x02, 0x00, 0x01, 0x01, 0x01, 0x01, 0x20, 0x00,
    ];
    assert_eq!(
        decode_record(&b),
        Err(ItemError::UndefinedSubfield("I021/295", 24))
    );
    // Item cut short: 080 (FRN 11: second octet 0x10) needs 3 octets.
    let b = [0x81, 0x10, 0x00, 0x01, 0xAB, 0xCD];
    assert_eq!(decode_record(&b), Err(ItemError::Truncated("I021/080")));
    // No data source.
    let b = [0x01, 0x20, 0xAB, 0xCD, 0xEF];
    assert_eq!(
        decode_record(&b),
        Err(ItemError::Malformed("I021/010 missing"))
    );
    // Every truncation of the full records fails cleanly (or parses a shorter valid record).
    for rec in [FLARM_RECORD, SKIPPING_RECORD] {
        for cut in 0..rec.len() {
            assert!(decode_record(&rec[..cut]).is_err(), "cut {cut}");
        }
    }
}

fn opt<T: std::fmt::Debug + Clone + 'static>(
    s: impl Strategy<Value = T> + 'static,
) -> impl Strategy<Value = Option<T>> {
    proptest::option::of(s)
}

fn tod() -> impl Strategy<Value = f64> {
    (0u32..0x100_0000).prop_map(|c| f64::from(c) / 128.0)
}

fn hp() -> impl Strategy<Value = HighPrecisionTime> {
    (0u8..4, 0u32..0x4000_0000).prop_map(|(fsi, c)| HighPrecisionTime {
        fsi,
        fraction_s: f64::from(c) * HP_LSB_S,
    })
}

fn descriptor() -> impl Strategy<Value = TargetReportDescriptor> {
    (any::<[u8; 3]>(), 0usize..3).prop_map(|(o, n)| {
        // Decode of arbitrary octets gives every field value; extensions are prefix-closed.
        TargetReportDescriptor::decode(&o[..=n]).unwrap()
    })
}

fn quality() -> impl Strategy<Value = QualityIndicators> {
    (any::<[u8; 4]>(), 0usize..4).prop_map(|(o, n)| {
        let q = QualityIndicators::decode(&o[..=n]).unwrap();
        QualityIndicators {
            ext1: (n >= 1).then(|| q.ext1.unwrap_or_default()),
            ext2: (n >= 2).then(|| q.ext2.unwrap_or_default()),
            pic: (n >= 3).then(|| q.pic.unwrap_or(0)),
            ..q
        }
    })
}

fn vrate() -> impl Strategy<Value = VerticalRate> {
    (any::<bool>(), -(1i32 << 14)..(1 << 14)).prop_map(|(re, c)| VerticalRate {
        range_exceeded: re,
        fpm: f64::from(c) * VRATE_LSB_FPM,
    })
}

prop_compose! {
    fn record()(
        a in (opt(any::<(u8, u8)>()), opt(descriptor()), opt(0u16..0x1000), opt(any::<u8>()),
              opt(tod()), opt(any::<(i32, i32)>()), opt(tod())),
        b in (opt(any::<(bool, u16)>()), opt(any::<(bool, u16)>()), opt(0u32..0x100_0000),
              opt(tod()), opt(hp()), opt(tod()), opt(hp())),
        c in (opt(any::<i16>()), opt(quality()), opt(any::<u8>()), opt(0u16..0o10000),
              opt(any::<i16>()), opt(any::<u16>()), opt(any::<u8>())),
        d in (opt(vrate()), opt(vrate()), opt(any::<(bool, u16, u16)>()), opt(-512i32..512),
              opt(tod()), opt("[A-Z0-9]{0,8}"), opt(any::<u8>())),
        e in (opt(any::<u8>()), opt(any::<u8>()), opt(any::<i8>()), opt(any::<[u8; 8]>().prop_map(|v| (v, ())))),
        pos_low in opt((-(1i32 << 23)..(1 << 23), -(1i32 << 23)..(1 << 23))),
    ) -> Cat021Record {
        let (src, desc, tn, sid, t071, pos_hr, t072) = a;
        let (air, tas, addr, t073, t074, t075, t076) = b;
        let (gh, q, mops, m3a, fl, mh, ts) = c;
        let (bvr, gvr, gv, tar, t077, id, ecat) = d;
        let (rp, ops, amp, _) = e;
        // Mode 3/A as decimal digits of the octal code.
        let squawk = m3a.map(|v| (v >> 9) * 1000 + ((v >> 6) & 7) * 100 + ((v >> 3) & 7) * 10 + (v & 7));
        Cat021Record {
            data_source: Some(src.map(|(sac, sic)| DataSource { sac, sic }).unwrap_or_default()),
            descriptor: desc,
            track_number: tn,
            service_id: sid,
            time_applicability_position_s: t071,
            position: pos_low.map(|(la, lo)| Position {
                lat_deg: f64::from(la) * POS_LSB_DEG,
                lon_deg: f64::from(lo) * POS_LSB_DEG,
            }),
            position_high_res: pos_hr.map(|(la, lo)| Position {
                lat_deg: f64::from(la) * POS_HR_LSB_DEG,
                lon_deg: f64::from(lo) * POS_HR_LSB_DEG,
            }),
            time_applicability_velocity_s: t072,
            air_speed: air.map(|(mach, v)| {
                let v = f64::from(v & 0x7FFF);
                if mach { AirSpeed::Mach(v / 1000.0) } else { AirSpeed::IasKt(v * SPEED_LSB_KT) }
            }),
            true_airspeed: tas.map(|(re, kt)| TrueAirspeed { range_exceeded: re, kt: kt & 0x7FFF }),
            target_address: addr,
            time_reception_position_s: t073,
            time_reception_position_hp: t074,
            time_reception_velocity_s: t075,
            time_reception_velocity_hp: t076,
            geometric_height_ft: gh.map(|h| f64::from(h) * HEIGHT_LSB_FT),
            quality: q,
            mops: mops.map(|o| MopsVersion::decode(&[o]).unwrap()),
            mode3a: squawk,
            flight_level: fl.map(|f| f64::from(f) * FL_LSB),
            magnetic_heading_deg: mh.map(|h| f64::from(h) * ANGLE_LSB_DEG),
            target_status: ts.map(|o| TargetStatus::decode(&[o]).unwrap()),
            baro_vertical_rate: bvr,
            geo_vertical_rate: gvr,
            ground_vector: gv.map(|(re, gs, trk)| GroundVector {
                range_exceeded: re,
                ground_speed_kt: f64::from(gs & 0x7FFF) * SPEED_LSB_KT,
                track_deg: f64::from(trk) * ANGLE_LSB_DEG,
            }),
            track_angle_rate_dps: tar.map(|c| f64::from(c) * TAR_LSB_DPS),
            time_report_transmission_s: t077,
            target_id: id.map(|s| s.trim_end().to_string()),
            emitter_category: ecat,
            report_period_s: rp.map(|c| f64::from(c) * 0.5),
            operational_status: ops.map(|o| OperationalStatus::decode(&[o]).unwrap()),
            amplitude_dbm: amp,
            reserved: None,
            undecoded: Vec::new(),
        }
    }
}

proptest! {
    #[test]
    fn record_round_trip(r in record()) {
        let mut bytes = Vec::new();
        r.encode(&mut bytes);
        let (back, len) = decode_record(&bytes).unwrap();
        prop_assert_eq!(len, bytes.len());
        prop_assert_eq!(back, r);
    }

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        if let Ok((r, len)) = decode_record(&bytes) {
            prop_assert!(len <= bytes.len());
            let _ = traffic::to_traffic(&r);
        }
    }
}

#[test]
fn unused_descriptor_ext_defaults() {
    // DescriptorExt2 default is all clear (used by the encoder for missing extensions).
    assert_eq!(
        DescriptorExt2::default(),
        DescriptorExt2 {
            ipc: false,
            nogo: false,
            cpr: false,
            ldpj: false,
            rcf: false
        }
    );
}
