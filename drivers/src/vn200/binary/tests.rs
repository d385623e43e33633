//! Binary message tests: the ICD's figures, Table 2.2 against each type's fields, hand-built
#![allow(clippy::excessive_precision)] // values transcribed from the ICD figures
//! messages for every type of every group, extension words, variable-length types, and
//! round trips.

use proptest::prelude::*;

use super::*;
use crate::testkit::XorShift;
use wire::Wire;

fn close(a: f32, b: f32) -> bool {
    (a - b).abs() <= 1e-5 * b.abs().max(1.0)
}

#[test]
fn figure_a2_single_group_ypr() {
    let bytes = [
        0xFA, 0x01, 0x08, 0x00, 0x93, 0x50, 0x2E, 0x42, 0x83, 0x3E, 0xF1, 0x3F, 0x48, 0xB5, 0x04,
        0xBB, 0x92, 0x88,
    ];
    let m = BinaryOutput::decode_frame(&bytes).expect("Figure A.2 decodes");
    let ypr = m.common.as_ref().and_then(|c| c.ypr).expect("common ypr");
    assert!(close(ypr.yaw_deg, 43.578686));
    assert!(close(ypr.pitch_deg, 1.884720));
    assert!(close(ypr.roll_deg, -0.002025));
    assert_eq!(m.type_masks(), [0x0008, 0, 0, 0, 0, 0, 0]);
    assert_eq!(
        m.encode(),
        bytes,
        "re-encoding gives the figure's bytes and CRC"
    );
}

#[test]
fn figure_a3_two_groups() {
    let bytes = [
        0xFA, 0x05, 0x08, 0x00, 0x10, 0x00, 0x42, 0x8E, 0xE7, 0xC2, 0x1E, 0x12, 0x11, 0xC1, 0xFF,
        0x49, 0x9C, 0x40, 0xE3, 0x27, 0xC4, 0x41, 0x6A, 0x4E,
    ];
    let m = BinaryOutput::decode_frame(&bytes).expect("Figure A.3 decodes");
    let ypr = m.common.as_ref().and_then(|c| c.ypr).unwrap();
    assert!(close(ypr.yaw_deg, -115.777853));
    assert!(close(ypr.pitch_deg, -9.066923));
    assert!(close(ypr.roll_deg, 4.884033));
    let t = m.imu.as_ref().and_then(|i| i.temperature_c).unwrap();
    assert!(close(t, 24.519476));
    assert_eq!(m.encode(), bytes);
    // The simulator's codec writes the same frame.
    let mut dst = bytes::BytesMut::new();
    tokio_util::codec::Encoder::encode(&mut BinaryEncoder, &m, &mut dst).unwrap();
    assert_eq!(&dst[..], &bytes[..]);
    // A wrong CRC byte is refused, and so is a wrong sync byte under a right CRC.
    let mut bad = bytes;
    bad[23] ^= 1;
    assert!(BinaryOutput::decode_frame(&bad).is_none());
    let mut bad = bytes;
    bad[0] = 0xFB;
    assert!(BinaryOutput::decode_frame(&bad).is_none());
    // Too short for a CRC (the CRC-16 of no bytes is 0, so the length decides), and nothing.
    assert!(BinaryOutput::decode_frame(&[0xFA]).is_none());
    assert!(BinaryOutput::decode_frame(&[0xFA, 0, 0]).is_none());
    assert!(BinaryOutput::decode_frame(&[]).is_none());
}

#[test]
fn group_names_are_the_variant_names_in_lower_case() {
    // The JSON keys of the groups of Table 2.1.
    for g in Group::ALL {
        assert_eq!(g.name(), format!("{g:?}").to_lowercase());
    }
}

#[test]
fn type_masks_by_name() {
    // The benchmark's Common message: TimeGps 1, Ypr 3, Quaternion 4, AngularRate 5, PosLla 6,
    // VelNed 7, Accel 8, InsStatus 12, TimeGpsPps 14 = 0x51FA.
    let names = [
        "time_gps_ns",
        "ypr",
        "quaternion",
        "angular_rate_radps",
        "pos_lla",
        "vel_ned_mps",
        "accel_mps2",
        "ins_status",
        "time_gps_pps_ns",
    ];
    assert_eq!(Group::Common.type_mask(&names), Some(0x51FA));
    // A name given twice still selects its type (a set, not a toggle): Ypr is bit 3.
    assert_eq!(Group::Common.type_mask(&["ypr", "ypr"]), Some(1 << 3));
    assert_eq!(
        Group::Gnss2.type_mask(&["raw_meas", "alt_msl_m"]),
        Some(1 << 16 | 1 << 18)
    );
    assert_eq!(Group::Attitude.type_mask(&["time_gps_ns"]), None);
}

#[test]
fn appendix_a11_header_bytes() {
    // A.1.1: TimeStartup and Ypr from Common, YprU from Attitude: "FA 11 09 00 00 01 ...".
    let m = BinaryOutput {
        common: Some(CommonGroup {
            time_startup_ns: Some(1),
            ypr: Some(Ypr::default()),
            ..Default::default()
        }),
        attitude: Some(AttitudeGroup {
            ypr_u: Some(Ypr::default()),
            ..Default::default()
        }),
        ..Default::default()
    };
    let e = m.encode();
    assert_eq!(&e[..6], &[0xFA, 0x11, 0x09, 0x00, 0x00, 0x01]);
    assert_eq!(e.len(), 6 + 8 + 12 + 12 + 2);
}

#[test]
fn appendix_a12_variable_length_example_header() {
    // A.1.2: GpsTow, GpsWeek, GnssPosLla, GnssVelNed, GnssSatInfo in the GNSS group: group
    // byte 0x08, type word sent as A6 40 (0x40A6), then 46 fixed bytes, then Count*8+2.
    let mask = (1 << 1) | (1 << 2) | (1 << 5) | (1 << 7) | (1 << 14);
    assert_eq!(type_words(mask), (0x40A6, None));
    let fixed: usize = GnssGroup::TYPES
        .iter()
        .filter(|t| mask & (1 << t.0) != 0 && !t.3)
        .map(|t| t.2)
        .sum();
    assert_eq!(fixed, 46);
    let mut body = vec![0x08, 0xA6, 0x40];
    body.extend_from_slice(&[0u8; 46]);
    body.extend_from_slice(&[3, 0]); // Count 3, reserved
    body.extend_from_slice(&[0u8; 24]);
    assert_eq!(
        body_len(&body, 600),
        Ok((parse_header(&body).unwrap(), 3 + 46 + 2 + 24))
    );
    let m = BinaryOutput::decode_body(&body).unwrap();
    assert_eq!(m.gnss.unwrap().sat_info.unwrap().sats.len(), 3);
}

/// Table 2.2 transcribed: (group offset, type offset, size).
const TABLE_2_2: &[(usize, u8, usize)] = &[
    // Common
    (0, 0, 8),
    (0, 1, 8),
    (0, 2, 8),
    (0, 3, 12),
    (0, 4, 16),
    (0, 5, 12),
    (0, 6, 24),
    (0, 7, 12),
    (0, 8, 12),
    (0, 9, 24),
    (0, 10, 20),
    (0, 11, 28),
    (0, 12, 2),
    (0, 13, 4),
    (0, 14, 8),
    // Time
    (1, 0, 8),
    (1, 1, 8),
    (1, 2, 8),
    (1, 3, 2),
    (1, 4, 8),
    (1, 5, 8),
    (1, 6, 8),
    (1, 7, 4),
    (1, 8, 4),
    (1, 9, 1),
    // Imu
    (2, 0, 2),
    (2, 1, 12),
    (2, 2, 12),
    (2, 3, 12),
    (2, 4, 4),
    (2, 5, 4),
    (2, 6, 16),
    (2, 7, 12),
    (2, 8, 12),
    (2, 9, 12),
    (2, 10, 12),
    (2, 11, 2),
    // Gnss
    (3, 0, 8),
    (3, 1, 8),
    (3, 2, 2),
    (3, 3, 1),
    (3, 4, 1),
    (3, 5, 24),
    (3, 6, 24),
    (3, 7, 12),
    (3, 8, 12),
    (3, 9, 12),
    (3, 10, 4),
    (3, 11, 4),
    (3, 12, 2),
    (3, 13, 28),
    (3, 14, 10),
    (3, 16, 40),
    (3, 17, 2),
    (3, 18, 8),
    // Attitude (0 and 9-11 are "-")
    (4, 1, 12),
    (4, 2, 16),
    (4, 3, 36),
    (4, 4, 12),
    (4, 5, 12),
    (4, 6, 12),
    (4, 7, 12),
    (4, 8, 12),
    (4, 12, 12),
    (4, 13, 4),
    // Ins
    (5, 0, 2),
    (5, 1, 24),
    (5, 2, 24),
    (5, 3, 12),
    (5, 4, 12),
    (5, 5, 12),
    (5, 6, 12),
    (5, 7, 12),
    (5, 8, 12),
    (5, 9, 4),
    (5, 10, 4),
    // Gnss2
    (6, 0, 8),
    (6, 1, 8),
    (6, 2, 2),
    (6, 3, 1),
    (6, 4, 1),
    (6, 5, 24),
    (6, 6, 24),
    (6, 7, 12),
    (6, 8, 12),
    (6, 9, 12),
    (6, 10, 4),
    (6, 11, 4),
    (6, 12, 2),
    (6, 13, 28),
    (6, 14, 10),
    (6, 16, 40),
    (6, 17, 2),
    (6, 18, 8),
];

#[test]
fn table_2_2_equals_each_types_field_sizes() {
    for g in Group::ALL {
        let ours: Vec<(u8, usize)> = g.types().iter().map(|t| (t.0, t.2)).collect();
        let table: Vec<(u8, usize)> = TABLE_2_2
            .iter()
            .filter(|t| t.0 == g as usize)
            .map(|t| (t.1, t.2))
            .collect();
        assert_eq!(ours, table, "group {}", g.name());
    }
    // The variable types' table sizes are one entry: 2 + 8 and 12 + 28.
    assert_eq!(SatInfoEntry::SIZE, 8);
    assert_eq!(RawMeasEntry::SIZE, 28);
}

/// Builds a body with the given (group, mask) list and a payload of bytes 0, 1, 2, ... so that
/// each field's value shows its offset.
fn sequential_body(groups: &[(usize, u32)], payload_len: usize) -> Vec<u8> {
    let mut gb = 0u8;
    let mut body = vec![0];
    for &(g, m) in groups {
        gb |= 1 << g;
        let (w0, w1) = type_words(m);
        body.extend_from_slice(&w0.to_le_bytes());
        if let Some(w1) = w1 {
            body.extend_from_slice(&w1.to_le_bytes());
        }
    }
    body[0] = gb;
    body.extend((0..payload_len).map(|i| i as u8));
    body
}

// The payload byte at payload offset `o` is `o as u8` (wrapping past 255).
fn le_u64(start: usize) -> u64 {
    u64::from_le_bytes(std::array::from_fn(|i| (start + i) as u8))
}
fn le_f32(start: usize) -> f32 {
    f32::from_le_bytes(std::array::from_fn(|i| (start + i) as u8))
}
fn le_f64(start: usize) -> f64 {
    f64::from_le_bytes(std::array::from_fn(|i| (start + i) as u8))
}
fn le_u16(start: usize) -> u16 {
    u16::from_le_bytes(std::array::from_fn(|i| (start + i) as u8))
}

#[test]
fn every_common_type_at_its_offset() {
    // All 15 types: 8+8+8+12+16+12+24+12+12+24+20+28+2+4+8 = 198 bytes.
    let body = sequential_body(&[(0, 0x7FFF)], 198);
    let m = BinaryOutput::decode_body(&body).unwrap();
    let c = m.common.as_ref().unwrap();
    // Offsets by hand: TimeStartup 0, TimeGps 8, TimeSyncIn 16, Ypr 24, Quaternion 36,
    // AngularRate 52, PosLla 64, VelNed 88, Accel 100, Imu 112, MagPres 136, Deltas 156,
    // InsStatus 184, SyncInCnt 186, TimeGpsPps 190.
    assert_eq!(c.time_startup_ns, Some(le_u64(0)));
    assert_eq!(c.time_gps_ns, Some(le_u64(8)));
    assert_eq!(c.time_sync_in_ns, Some(le_u64(16)));
    assert_eq!(c.ypr.unwrap().yaw_deg.to_bits(), le_f32(24).to_bits());
    assert_eq!(c.quaternion.unwrap().s.to_bits(), le_f32(48).to_bits());
    assert_eq!(
        c.angular_rate_radps.unwrap()[0].to_bits(),
        le_f32(52).to_bits()
    );
    assert_eq!(c.pos_lla.unwrap().alt_m.to_bits(), le_f64(80).to_bits());
    assert_eq!(c.vel_ned_mps.unwrap()[2].to_bits(), le_f32(96).to_bits());
    assert_eq!(c.accel_mps2.unwrap()[0].to_bits(), le_f32(100).to_bits());
    assert_eq!(
        c.imu.unwrap().uncomp_gyro_radps[0].to_bits(),
        le_f32(124).to_bits()
    );
    let mp = c.mag_pres.unwrap();
    assert_eq!(mp.temperature_c.to_bits(), le_f32(148).to_bits());
    assert_eq!(mp.pressure_kpa.to_bits(), le_f32(152).to_bits());
    let d = c.deltas.unwrap();
    assert_eq!(d.theta.delta_time_s.to_bits(), le_f32(156).to_bits());
    assert_eq!(d.delta_vel_mps[0].to_bits(), le_f32(172).to_bits());
    assert_eq!(c.ins_status.unwrap().0, le_u16(184));
    assert_eq!(
        c.sync_in_cnt,
        Some(u32::from_le_bytes([186, 187, 188, 189]))
    );
    assert_eq!(c.time_gps_pps_ns, Some(le_u64(190)));
    let mut out = Vec::new();
    m.encode_body(&mut out);
    assert_eq!(out, body);
}

#[test]
fn every_time_imu_attitude_ins_type_at_its_offset() {
    // Time: 8*3 + 2 + 8*3 + 4 + 4 + 1 = 59; Imu: 2+12*3+4+4+16+12*4+2 = 112;
    // Attitude: 12+16+36+12*5+12+4 = 140; Ins: 2+24+24+12*6+4+4 = 130.
    let att_mask = 0x31FE;
    let body = sequential_body(
        &[(1, 0x03FF), (2, 0x0FFF), (4, att_mask), (5, 0x07FF)],
        59 + 112 + 140 + 130,
    );
    let m = BinaryOutput::decode_body(&body).unwrap();
    let t = m.time.as_ref().unwrap();
    // Time offsets: GpsWeek 24, TimeSyncIn 26, TimeGpsPps 34, TimeUtc 42, SyncInCnt 50,
    // SyncOutCnt 54, TimeStatus 58.
    assert_eq!(t.gps_tow_ns, Some(le_u64(16)));
    assert_eq!(t.gps_week, Some(le_u16(24)));
    assert_eq!(t.time_sync_in_ns, Some(le_u64(26)));
    let utc = t.time_utc.unwrap();
    assert_eq!((utc.year_offset, utc.month, utc.second), (42, 43, 47));
    assert_eq!(utc.frac_ms, i16::from_le_bytes([48, 49]));
    assert_eq!(t.sync_out_cnt, Some(u32::from_le_bytes([54, 55, 56, 57])));
    assert_eq!(t.time_gps_pps_ns, Some(le_u64(34)));
    assert_eq!(t.time_status.unwrap().0, 58);
    // Imu starts at 59: ImuStatus 59, UncompMag 61, Temperature 97, Pressure 101, DeltaTheta
    // 105, DeltaVel 121, Mag 133, Accel 145, AngularRate 157, SensSat 169.
    let i = m.imu.as_ref().unwrap();
    assert_eq!(i.imu_status.unwrap().0, le_u16(59));
    assert_eq!(
        i.uncomp_mag_gauss.unwrap()[0].to_bits(),
        le_f32(61).to_bits()
    );
    assert_eq!(i.temperature_c.unwrap().to_bits(), le_f32(97).to_bits());
    assert_eq!(
        i.delta_theta.unwrap().delta_time_s.to_bits(),
        le_f32(105).to_bits()
    );
    assert_eq!(
        i.angular_rate_radps.unwrap()[0].to_bits(),
        le_f32(157).to_bits()
    );
    assert_eq!(i.sens_sat.unwrap().0, le_u16(169));
    // Attitude starts at 171: Ypr 171, Quaternion 183, Dcm 199, MagNed 235, AccelNed 247,
    // LinBodyAcc 259, LinAccelNed 271, YprU 283, Heave 295, AttU 307.
    let a = m.attitude.as_ref().unwrap();
    assert_eq!(a.ypr.unwrap().yaw_deg.to_bits(), le_f32(171).to_bits());
    assert_eq!(a.dcm.unwrap()[8].to_bits(), le_f32(231).to_bits());
    assert_eq!(a.mag_ned_gauss.unwrap()[0].to_bits(), le_f32(235).to_bits());
    assert_eq!(
        a.lin_accel_ned_mps2.unwrap()[0].to_bits(),
        le_f32(271).to_bits()
    );
    assert_eq!(a.ypr_u.unwrap().roll_deg.to_bits(), le_f32(291).to_bits());
    assert_eq!(a.heave.unwrap().heave_m.to_bits(), le_f32(295).to_bits());
    assert_eq!(a.att_u_deg.unwrap().to_bits(), le_f32(307).to_bits());
    // Ins starts at 311: InsStatus 311, PosLla 313, PosEcef 337, VelBody 361, VelNed 373,
    // VelEcef 385, MagEcef 397, AccelEcef 409, LinAccelEcef 421, PosU 433, VelU 437.
    let n = m.ins.as_ref().unwrap();
    assert_eq!(n.ins_status.unwrap().0, le_u16(311));
    assert_eq!(n.pos_lla.unwrap().lat_deg.to_bits(), le_f64(313).to_bits());
    assert_eq!(n.pos_ecef_m.unwrap()[0].to_bits(), le_f64(337).to_bits());
    assert_eq!(n.vel_ned_mps.unwrap()[0].to_bits(), le_f32(373).to_bits());
    assert_eq!(
        n.lin_accel_ecef_mps2.unwrap()[0].to_bits(),
        le_f32(421).to_bits()
    );
    assert_eq!(n.pos_u_m.unwrap().to_bits(), le_f32(433).to_bits());
    assert_eq!(n.vel_u_mps.unwrap().to_bits(), le_f32(437).to_bits());
    let mut out = Vec::new();
    m.encode_body(&mut out);
    assert_eq!(out, body);
}

#[test]
fn gnss_groups_extension_words_and_variable_types() {
    // GNSS2 (group 6) with NumSats (3), GnssSatInfo (14), GnssRawMeas (16), GnssStatus (17),
    // GnssAltMSL (18): type words 0xC008 (bits 3, 14 and the extension bit 15) and 0x0007
    // (offsets 16, 17, 18 = bits 0, 1, 2 of the second word, as the tables number them).
    let mask = (1 << 3) | (1 << 14) | (1 << 16) | (1 << 17) | (1 << 18);
    assert_eq!(type_words(mask), (0xC008, Some(0x0007)));
    let mut body = vec![0x40, 0x08, 0xC0, 0x07, 0x00];
    body.push(12); // NumSats
    // SatInfo: Count 1, reserved 0xEE, one satellite: GPS sv 7 flags 0x11 cno 45 qi 7
    // el -5 az 271 (0x010F).
    body.extend_from_slice(&[1, 0xEE, 0, 7, 0x11, 45, 7, 0xFB, 0x0F, 0x01]);
    // RawMeas: tow 1.5 s, week 2300 (0x08FC), 2 signals, reserved 0.
    body.extend_from_slice(&1.5f64.to_le_bytes());
    body.extend_from_slice(&2300u16.to_le_bytes());
    body.extend_from_slice(&[2, 0]);
    for k in 0..2u8 {
        body.extend_from_slice(&[6, 10 + k, 1, 1, 0xFE, 40, 0x1F, 0x00]);
        body.extend_from_slice(&(2.0e7f64 + f64::from(k)).to_le_bytes());
        body.extend_from_slice(&(1.0e8f64).to_le_bytes());
        body.extend_from_slice(&(-1234.5f32).to_le_bytes());
    }
    body.extend_from_slice(&0x1913u16.to_le_bytes());
    body.extend_from_slice(&123.25f64.to_le_bytes());
    let (_, n) = body_len(&body, 600).unwrap();
    assert_eq!(n, 5 + 1 + (2 + 8) + (12 + 2 * 28) + 2 + 8);
    assert_eq!(n, body.len());
    // A body exactly at the bound is accepted; one octet over it is too long.
    assert_eq!(body_len(&body, n).map(|(_, l)| l), Ok(n));
    assert_eq!(body_len(&body, n - 1).map(|(_, l)| l), Err(Probe::TooLong));
    let m = BinaryOutput::decode_body(&body).unwrap();
    assert!(m.gnss.is_none());
    let g = m.gnss2.as_ref().unwrap();
    assert_eq!(g.num_sats, Some(12));
    let si = g.sat_info.as_ref().unwrap();
    assert_eq!(si.reserved, 0xEE);
    assert_eq!(
        si.sats,
        vec![SatInfoEntry {
            sys: 0,
            sv_id: 7,
            flags: 0x11,
            cno_dbhz: 45,
            qi: 7,
            elevation_deg: -5,
            azimuth_deg: 271
        }]
    );
    let rm = g.raw_meas.as_ref().unwrap();
    assert_eq!((rm.tow_s, rm.week, rm.meas.len()), (1.5, 2300, 2));
    assert_eq!(rm.meas[1].sv_id, 11);
    assert_eq!(rm.meas[1].slot, -2);
    assert_eq!(rm.meas[1].flags, 0x001F);
    assert_eq!(rm.meas[1].pseudorange, 2.0e7 + 1.0);
    assert_eq!(rm.meas[0].doppler_hz, -1234.5);
    assert!(g.status.unwrap().pps_used_for_time());
    assert_eq!(g.alt_msl_m, Some(123.25));
    let mut out = Vec::new();
    m.encode_body(&mut out);
    assert_eq!(out, body);
    // The same message with zero satellites is 8 + 28 bytes shorter.
    let mut m0 = m.clone();
    if let Some(g) = m0.gnss2.as_mut() {
        g.sat_info.as_mut().unwrap().sats.clear();
        g.raw_meas.as_mut().unwrap().meas.clear();
    }
    let mut out0 = Vec::new();
    m0.encode_body(&mut out0);
    assert_eq!(out0.len(), body.len() - 8 - 2 * 28);
    assert_eq!(BinaryOutput::decode_body(&out0), Some(m0));
}

#[test]
fn every_gnss_type_at_its_offset() {
    // All fixed GNSS types (0-13, 17, 18): 8+8+2+1+1+24+24+12+12+12+4+4+2+28+2+8 = 152.
    let mask = 0x3FFF | (1 << 17) | (1 << 18);
    let body = sequential_body(&[(3, mask)], 152);
    let m = BinaryOutput::decode_body(&body).unwrap();
    let g = m.gnss.as_ref().unwrap();
    // Offsets: TimeUtc 0, GpsTow 8, GpsWeek 16, NumSats 18, Fix 19, PosLla 20, PosEcef 44,
    // VelNed 68, VelEcef 80, PosU 92, VelU 104, TimeU 108, TimeInfo 112, Dop 114, Status 142,
    // AltMSL 144.
    assert_eq!(g.time_utc.unwrap().day, 2);
    assert_eq!(g.gps_tow_ns, Some(le_u64(8)));
    assert_eq!(g.gps_week, Some(le_u16(16)));
    assert_eq!(g.num_sats, Some(18));
    assert_eq!(g.fix, Some(GnssFix(19)));
    assert_eq!(g.pos_lla.unwrap().lat_deg.to_bits(), le_f64(20).to_bits());
    assert_eq!(g.pos_ecef_m.unwrap()[0].to_bits(), le_f64(44).to_bits());
    assert_eq!(g.vel_ned_mps.unwrap()[0].to_bits(), le_f32(68).to_bits());
    assert_eq!(g.vel_ecef_mps.unwrap()[0].to_bits(), le_f32(80).to_bits());
    assert_eq!(g.pos_u_ned_m.unwrap()[0].to_bits(), le_f32(92).to_bits());
    assert_eq!(g.vel_u_mps.unwrap().to_bits(), le_f32(104).to_bits());
    assert_eq!(g.time_u_s.unwrap().to_bits(), le_f32(108).to_bits());
    let ti = g.time_info.unwrap();
    assert_eq!((ti.status.0, ti.leap_seconds), (112, 113));
    assert_eq!(g.dop.unwrap().gdop.to_bits(), le_f32(114).to_bits());
    assert_eq!(g.dop.unwrap().edop.to_bits(), le_f32(138).to_bits());
    assert_eq!(g.status.unwrap().0, le_u16(142));
    assert_eq!(g.alt_msl_m.unwrap().to_bits(), le_f64(144).to_bits());
}

#[test]
fn headers_that_are_not_messages() {
    // No group.
    assert_eq!(parse_header(&[0x00, 0x08, 0x00]), Err(Probe::Invalid));
    // A group with an empty type word.
    assert_eq!(parse_header(&[0x01, 0x00, 0x00]), Err(Probe::Invalid));
    // A second type word with its extension bit set (only two words allowed).
    assert_eq!(
        parse_header(&[0x08, 0x00, 0x80, 0x00, 0x80]),
        Err(Probe::Invalid)
    );
    // Group 7 via an extension group byte: unknown.
    assert_eq!(parse_header(&[0x81, 0x01, 0x08, 0x00]), Err(Probe::Unknown));
    // Attitude offset 0 (VpeStatus on a VN-100, undefined here): unknown type.
    assert_eq!(body_len(&[0x10, 0x01, 0x00], 600), Err(Probe::Unknown));
    // A redundant zero extension group byte is accepted.
    assert!(parse_header(&[0x81, 0x00, 0x08, 0x00]).is_ok());
    // Too long: GnssSatInfo with Count 255 = 2 + 2040 bytes.
    let mut b = vec![0x08, 0x00, 0x40, 255, 0];
    b.resize(700, 0);
    assert_eq!(body_len(&b, 597), Err(Probe::TooLong));
    // The count byte not yet received: need more.
    assert_eq!(body_len(&[0x08, 0x00, 0x40], 597), Err(Probe::NeedMore));
}

/// A random valid body: random type masks over the known types, random payload bytes, small
/// counts for the variable types.
fn random_body(masks: [u32; 7], seed: u64) -> Vec<u8> {
    let mut rng = XorShift::new(seed);
    let mut groups = Vec::new();
    for g in Group::ALL {
        let known = g.types().iter().fold(0u32, |a, t| a | 1 << t.0);
        let m = masks[g as usize] & known;
        if m != 0 {
            groups.push((g, m));
        }
    }
    if groups.is_empty() {
        groups.push((Group::Common, 1 << 3));
    }
    let mut body = vec![groups.iter().fold(0u8, |a, (g, _)| a | 1 << *g as u8)];
    for (_, m) in &groups {
        let (w0, w1) = type_words(*m);
        body.extend_from_slice(&w0.to_le_bytes());
        if let Some(w1) = w1 {
            body.extend_from_slice(&w1.to_le_bytes());
        }
    }
    for (g, m) in &groups {
        for &(off, name, size, variable) in g.types() {
            if m & (1 << off) == 0 {
                continue;
            }
            if variable {
                let count = rng.below(4) as u8;
                if name == "sat_info" {
                    body.extend_from_slice(&[count, rng.next_u64() as u8]);
                    let mut e = vec![0u8; 8 * usize::from(count)];
                    rng.fill(&mut e);
                    body.extend_from_slice(&e);
                } else {
                    let mut h = [0u8; 12];
                    rng.fill(&mut h);
                    h[10] = count;
                    body.extend_from_slice(&h);
                    let mut e = vec![0u8; 28 * usize::from(count)];
                    rng.fill(&mut e);
                    body.extend_from_slice(&e);
                }
            } else {
                let mut e = vec![0u8; size];
                rng.fill(&mut e);
                body.extend_from_slice(&e);
            }
        }
    }
    body
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// decode(encode(x)) == x, taken bitwise: every decodable body re-encodes to its own bytes,
    /// and decoding that again gives the same message (compared by its encoding, since random
    /// float bits include NaN, which is not equal to itself).
    #[test]
    fn prop_round_trip(masks in proptest::array::uniform7(any::<u32>()), seed in any::<u64>()) {
        let body = random_body(masks, seed);
        let (_, n) = body_len(&body, usize::MAX).unwrap();
        prop_assert_eq!(n, body.len());
        let m = BinaryOutput::decode_body(&body).unwrap();
        let mut out = Vec::new();
        m.encode_body(&mut out);
        prop_assert_eq!(&out, &body);
        let framed = m.encode();
        let again = BinaryOutput::decode_frame(&framed).unwrap();
        prop_assert_eq!(again.encode(), framed);
        // Truncating the body by one byte never decodes.
        prop_assert!(BinaryOutput::decode_body(&body[..body.len() - 1]).is_none());
    }

    /// With finite floats, plain equality holds too.
    #[test]
    fn prop_round_trip_finite(yaw in -180f32..180.0, lat in -90f64..90.0, t in any::<u64>(), st in any::<u16>()) {
        let m = BinaryOutput {
            common: Some(CommonGroup {
                time_gps_ns: Some(t),
                ypr: Some(Ypr { yaw_deg: yaw, pitch_deg: -yaw / 2.0, roll_deg: 1.0 }),
                pos_lla: Some(Lla { lat_deg: lat, lon_deg: -lat, alt_m: 100.5 }),
                ins_status: Some(crate::vn200::status::InsStatus(st)),
                ..Default::default()
            }),
            ..Default::default()
        };
        prop_assert_eq!(BinaryOutput::decode_frame(&m.encode()), Some(m));
    }
}

/// The in-place decode (issue 21) accepts a payload only when it holds exactly the types its
/// header selects, as `decode_payload` does: the same message from the whole payload, `false`
/// with one byte missing or one byte too many.
#[test]
fn in_place_decoding_needs_exactly_the_selected_bytes() {
    for (i, masks) in [
        [u32::MAX; 7],
        [0x0000_0FFF, 0, 0, 0, 0, 0, 0],
        [0, 0x3F, 0, 0x1F, 0, 0, 0],
    ]
    .into_iter()
    .enumerate()
    {
        let body = random_body(masks, i as u64);
        let header = parse_header(&body).unwrap();
        let payload = &body[header.len..];
        let whole = BinaryOutput::decode_payload(&header, payload).unwrap();
        let mut out = BinaryOutput::default();
        assert!(out.decode_payload_into(&header, payload), "masks {i}");
        assert_eq!(out.encode(), whole.encode(), "masks {i}");
        let short = &payload[..payload.len() - 1];
        assert!(
            !BinaryOutput::default().decode_payload_into(&header, short),
            "masks {i}"
        );
        let mut long = payload.to_vec();
        long.push(0);
        assert!(
            !BinaryOutput::default().decode_payload_into(&header, &long),
            "masks {i}"
        );
    }
}

#[test]
fn gnss_fix_values_are_table_2_41() {
    // ICD Table 2.41: 0-4, 7 and 8 are documented; 5, 6 and 9.. are not (None, not a guess).
    let table = [
        (0, Some(GnssFixKind::NoFix)),
        (1, Some(GnssFixKind::TimeOnly)),
        (2, Some(GnssFixKind::Fix2D)),
        (3, Some(GnssFixKind::Fix3D)),
        (4, Some(GnssFixKind::Sbas)),
        (5, None),
        (6, None),
        (7, Some(GnssFixKind::RtkFloat)),
        (8, Some(GnssFixKind::RtkFix)),
        (9, None),
        (255, None),
    ];
    for (v, kind) in table {
        assert_eq!(GnssFix(v).kind(), kind, "{v}");
    }
}
