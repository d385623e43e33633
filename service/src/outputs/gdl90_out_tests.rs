//! The GDL90 output read back two ways: by an independent decoder written here from the ICD
//! (560-1058-00 Rev A: 2.2 framing and FCS, 3.1 heartbeat, 3.4/3.5 reports, 3.8 geometric
//! altitude), checked first on the ICD's own heartbeat example, and by vigil's GDL90 decoder.

use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, Gdl90Message, TrafficAltitude};
use vigil_drivers::{DeviceDecoder, decode_slice};
use vigil_fusion::ownship::{Ownship, PositionSource};
use vigil_fusion::traffic::track::{AddressSpace, PlausibilityFlags, TargetKey};
use vigil_fusion::traffic::{Reported, TrafficStats};

use super::*;

/// ICD 2.2.3: the FCS as the ICD's C code computes it: a table of CRC-CCITT
/// (x^16 + x^12 + x^5 + 1) values of each byte shifted up 8 bits, then for each message byte
/// `crc = table[crc >> 8] ^ (crc << 8) ^ byte`, starting from 0 (the byte enters after the
/// shift, so this is not the common XMODEM CRC; the ICD's heartbeat example below pins it).
fn crc_ccitt(data: &[u8]) -> u16 {
    let table: Vec<u16> = (0..256u16)
        .map(|i| {
            let mut crc = i << 8;
            for _ in 0..8 {
                crc = (crc << 1) ^ if crc & 0x8000 != 0 { 0x1021 } else { 0 };
            }
            crc
        })
        .collect();
    data.iter().fold(0u16, |crc, &b| {
        table[usize::from(crc >> 8)] ^ (crc << 8) ^ u16::from(b)
    })
}

/// ICD 2.2.1-2.2.2: strips the 0x7E flags, undoes the 0x7D escapes (next byte XOR 0x20), checks
/// the FCS (sent least significant byte first) and returns the clear message.
fn unframe(frame: &[u8]) -> Vec<u8> {
    assert_eq!((frame[0], frame[frame.len() - 1]), (0x7E, 0x7E));
    let mut clear = Vec::new();
    let mut esc = false;
    for &b in &frame[1..frame.len() - 1] {
        if esc {
            clear.push(b ^ 0x20);
            esc = false;
        } else if b == 0x7D {
            esc = true;
        } else {
            assert_ne!(b, 0x7E, "an unescaped flag inside the frame");
            clear.push(b);
        }
    }
    let n = clear.len() - 2;
    let fcs = u16::from(clear[n]) | u16::from(clear[n + 1]) << 8;
    assert_eq!(crc_ccitt(&clear[..n]), fcs, "FCS");
    clear.truncate(n);
    clear
}

fn i24(b: &[u8]) -> i32 {
    (i32::from(b[0]) << 24 | i32::from(b[1]) << 16 | i32::from(b[2]) << 8) >> 8
}

#[test]
fn the_independent_decoder_reads_the_icds_heartbeat_example() {
    let clear = unframe(&[
        0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
    ]);
    assert_eq!(clear, [0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]);
}

fn target() -> Target {
    Target {
        key: TargetKey {
            space: AddressSpace::Icao,
            address: 0xAB7E7D,
        },
        callsign: Some("n825v".to_string()),
        sources: Vec::new(),
        age_s: 0.4,
        lat_deg: 44.907_08,
        lon_deg: -122.995_48,
        alt_m: Some(5000.0 * 0.3048),
        // 123 kt at 45 deg true (north and east components equal).
        velocity_ne_mps: Some([123.0 / (3600.0 / 1852.0) / 2f64.sqrt(); 2]),
        vertical_rate_mps: Some(640.0 * 0.3048 / 60.0),
        altitude_kind: AltitudeKind::Pressure,
        position_sigma_m: 10.0,
        bearing_true_deg: 0.0,
        bearing_relative_deg: None,
        geometry: None,
        raw_alert_level: 2,
        alert_level: 2,
        flarm_alarm_level: None,
        flags: PlausibilityFlags::default(),
        fail_safe: Default::default(),
        // The ICD's traffic report example: NIC 10, NACp 9, emitter category 1 (light).
        reported: Reported {
            nic: Some(10),
            nac_p: Some(9),
            emitter_category: Some(1),
            ..Reported::default()
        },
    }
}

fn ownship() -> Ownship {
    Ownship {
        t_gps_ns: 0,
        lat_deg: 44.9,
        lon_deg: -123.0,
        alt_pressure_m: Some(3000.0 * 0.3048),
        alt_geometric_m: Some(3100.0 * 0.3048),
        track_deg: Some(90.0),
        ground_speed_mps: Some(50.0 * 1852.0 / 3600.0),
        vertical_rate_mps: Some(0.0),
        heading_deg: Some(90.0),
        position_sigma_m: Some(2.0),
        source: PositionSource::Vn200Ins,
        alt_geometric_band_m: 0.0,
    }
}

fn picture(t_gps_ns: i64) -> TrafficPicture {
    TrafficPicture {
        kind: "traffic",
        t_gps_ns,
        targets: vec![target()],
        stats: TrafficStats::default(),
    }
}

/// 2026-11-25 12:34:56 UTC as GPS time (GPS - UTC = 18 s): seconds since 0000Z 45296.
const T_GPS_NS: i64 = (1_795_610_096 - 315_964_800 + 18) * 1_000_000_000;

#[test]
fn every_message_decodes_by_the_icds_tables() {
    let mut enc = Gdl90Traffic::default();
    let frames = enc.picture(&picture(T_GPS_NS), Some(&ownship()));
    let ids: Vec<u8> = frames.iter().map(|f| unframe(f)[0]).collect();
    assert_eq!(ids, [0, 10, 11, 20]);

    // Heartbeat: status 1 bit 7 GPS position valid, bit 0 UAT initialised; status 2 bit 0 UTC
    // OK, bit 7 the timestamp's bit 16; then the timestamp's low 16 bits, LSB first.
    let h = unframe(&frames[0]);
    assert_eq!(h.len(), 7);
    assert_eq!(h[1], 0x81);
    let ts = u32::from(h[3]) | u32::from(h[4]) << 8 | u32::from(h[2] >> 7) << 16;
    assert_eq!(ts, 12 * 3600 + 34 * 60 + 56);
    assert_eq!(h[2] & 1, 1, "UTC OK");

    // Traffic report (3.5.1): the address 0xAB7E7D holds both bytes that must be escaped.
    assert!(frames[3].windows(2).any(|w| w == [0x7D, 0x5E]));
    let m = unframe(&frames[3]);
    assert_eq!(m.len(), 28);
    assert_eq!(
        m[1], 0x10,
        "alert status 1 (corrective), address type 0 (ADS-B ICAO)"
    );
    assert_eq!(&m[2..5], &[0xAB, 0x7E, 0x7D]);
    let lsb = 180.0 / f64::from(1 << 23);
    assert!((f64::from(i24(&m[5..8])) * lsb - 44.907_08).abs() <= lsb / 2.0);
    assert!((f64::from(i24(&m[8..11])) * lsb + 122.995_48).abs() <= lsb / 2.0);
    let alt = (u16::from(m[11]) << 4) | u16::from(m[12] >> 4);
    assert_eq!(i32::from(alt) * 25 - 1000, 5000, "pressure altitude, ft");
    assert_eq!(m[12] & 0x0F, 0b1001, "airborne, updated, true track");
    assert_eq!(
        m[13], 0xA9,
        "NIC 10, NACp 9 (reported 9; from sigma: EPU 2.4477 x 10 m = 24.5 m < 30 m, also 9)"
    );
    assert_eq!(m[18], 1, "emitter category light");
    let hv = (u16::from(m[14]) << 4) | u16::from(m[15] >> 4);
    assert_eq!(hv, 123, "kt");
    let vv = ((i32::from(m[15] & 0x0F) << 8 | i32::from(m[16])) << 20) >> 20;
    assert_eq!(vv * 64, 640, "fpm");
    assert_eq!(m[17], 32, "45 deg in 360/256 steps");
    assert_eq!(&m[19..27], b"N825V   ");

    // Ownship report: address 0, pressure altitude 3000 ft, 50 kt due east (track 64 x 1.40625).
    let o = unframe(&frames[1]);
    assert_eq!(&o[2..5], &[0, 0, 0]);
    let alt = (u16::from(o[11]) << 4) | u16::from(o[12] >> 4);
    assert_eq!(i32::from(alt) * 25 - 1000, 3000);
    assert_eq!((u16::from(o[14]) << 4) | u16::from(o[15] >> 4), 50);
    assert_eq!(o[17], 64);
    assert_eq!(o[13] & 0x0F, 10, "NACp 10: EPU 2.4477 x 2 m = 4.9 m < 10 m");

    // Geometric altitude (3.8): 5 ft steps, signed 16 bits, then VFOM 0x7FFF (not available).
    let g = unframe(&frames[2]);
    assert_eq!(i16::from_be_bytes([g[1], g[2]]), 3100 / 5);
    assert_eq!(u16::from_be_bytes([g[3], g[4]]), 0x7FFF);
}

#[test]
fn vigils_decoder_reads_the_output_back() {
    let mut enc = Gdl90Traffic::default();
    let bytes: Vec<u8> = enc.picture(&picture(T_GPS_NS), Some(&ownship())).concat();
    let mut dec = Gdl90Decoder::new(TrafficAltitude::Pressure);
    let msgs = decode_slice(&mut dec, &bytes);
    assert_eq!(msgs.len(), 4);
    assert_eq!(dec.stats().checksum_failures, 0);
    let Gdl90Message::TrafficReport(r) = msgs[3] else {
        panic!("{:?}", msgs[3]);
    };
    assert_eq!((r.address, r.altitude_ft), (0xAB7E7D, Some(5000)));
    assert_eq!(r.callsign_str().as_deref(), Some("N825V"));
}

#[test]
fn once_a_second_and_unknowns_sent_as_unknown() {
    let mut enc = Gdl90Traffic::default();
    assert_eq!(
        enc.picture(&picture(T_GPS_NS), None).len(),
        2,
        "heartbeat + traffic"
    );
    assert!(
        enc.picture(&picture(T_GPS_NS + 500_000_000), None)
            .is_empty()
    );
    assert_eq!(
        enc.picture(&picture(T_GPS_NS + 1_000_000_000), None).len(),
        2
    );
    // Without an ownship the heartbeat says so.
    let f = enc.picture(&picture(T_GPS_NS + 2_000_000_000), None);
    assert_eq!(unframe(&f[0])[1] & 0x80, 0, "GPS position not valid");
    // A geometric altitude is not a pressure altitude: sent as invalid (0xFFF); no velocity:
    // no track, speed 0xFFF; no vertical rate: 0x800.
    let mut t = target();
    t.altitude_kind = AltitudeKind::Geometric;
    t.velocity_ne_mps = None;
    t.vertical_rate_mps = None;
    t.alert_level = 1;
    let m = traffic_report(&t).encode(20);
    assert_eq!((u16::from(m[11]) << 4) | u16::from(m[12] >> 4), 0xFFF);
    assert_eq!(m[12] & 0x03, 0, "track not valid");
    assert_eq!((u16::from(m[14]) << 4) | u16::from(m[15] >> 4), 0xFFF);
    assert_eq!(u16::from(m[15] & 0x0F) << 8 | u16::from(m[16]), 0x800);
    assert_eq!(m[1] >> 4, 0, "preventive: no traffic alert status");
}

#[test]
fn nacp_follows_the_icds_bounds() {
    // EPU = 2.4477 sigma against the table: < 3 m 11, < 10 m 10, < 30 m 9, < 92.6 m 8, ...
    assert_eq!(nac_p(None), 0);
    assert_eq!(nac_p(Some(1.0)), 11);
    assert_eq!(nac_p(Some(2.0)), 10);
    assert_eq!(nac_p(Some(4.0)), 10);
    assert_eq!(nac_p(Some(10.0)), 9);
    assert_eq!(nac_p(Some(30.0)), 8);
    assert_eq!(nac_p(Some(40.0)), 7, "97.9 m < 0.1 NM");
    assert_eq!(nac_p(Some(10_000.0)), 0);
}

#[test]
fn reported_accuracy_never_claims_more_than_the_extrapolated_position_has() {
    // Reported NACp 11 (EPU < 3 m) but 10 m sigma at the picture's time: NACp 9 goes out.
    let mut t = target();
    t.reported.nac_p = Some(11);
    assert_eq!(traffic_report(&t).nac_p, 9);
    // Reported NACp 7 with a 10 m sigma: the source's own 7 (the worse) goes out.
    t.reported.nac_p = Some(7);
    assert_eq!(traffic_report(&t).nac_p, 7);
    // Nothing reported: NIC 0 and emitter 0 (unknown), NACp from the sigma alone.
    t.reported = Reported::default();
    let r = traffic_report(&t);
    assert_eq!((r.nic, r.nac_p, r.emitter_category), (0, 9, 0));
    // Out of the ICD's tables: not sent.
    t.reported.nic = Some(12);
    t.reported.emitter_category = Some(40);
    let r = traffic_report(&t);
    assert_eq!((r.nic, r.emitter_category), (0, 0));
}
