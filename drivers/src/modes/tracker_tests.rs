//! Tracker tests: CPR pairing rules, local decoding, surface reference, NIC supplements, the
//! address check of AP frames, eviction, and the traffic report.

use super::*;
use crate::modes::df::{DecodeOptions, decode};
use crate::modes::encode::{self, AirbornePositionFields, OperationalStatusFields};
use crate::modes::hex_frame;

fn at(t: f64) -> RxMeta {
    RxMeta {
        ts_utc_ns: Some((t * 1e9) as u64),
        ..RxMeta::default()
    }
}

fn feed(tr: &mut Tracker, f: &[u8], meta: RxMeta) -> Update {
    let m = decode(f, DecodeOptions::default()).expect("valid frame");
    tr.update(&m, &meta)
}

fn pos_frame(icao: u32, tc: u8, lat: f64, lon: f64, odd: bool, nic_b: bool) -> [u8; 14] {
    encode::airborne_position(
        icao,
        &AirbornePositionFields {
            typecode: tc,
            surveillance_status: 0,
            nic_b,
            altitude_ft: Some(10_000),
            lat_deg: lat,
            lon_deg: lon,
            odd,
        },
    )
    .unwrap()
}

/// An even then an odd airborne position frame 0.5 s apart, from `t` s: the odd one's update
/// (the global decode of the pair).
fn pair(tr: &mut Tracker, icao: u32, lat: f64, lon: f64, t: f64) -> Update {
    feed(tr, &pos_frame(icao, 11, lat, lon, false, false), at(t));
    feed(tr, &pos_frame(icao, 11, lat, lon, true, false), at(t + 0.5))
}

/// A DF17 frame sent as DF18 with control field `cf` (its CRC recomputed).
fn as_df18(mut f: [u8; 14], cf: u8) -> [u8; 14] {
    f[0] = (18 << 3) | cf;
    crate::modes::crc::set_parity(&mut f, 0);
    f
}

fn surface_frame(icao: u32, lat: f64, lon: f64, odd: bool) -> [u8; 14] {
    let c = crate::modes::cpr::encode(lat, lon, odd, true);
    let me = (6u64 << 51)
        | (20 << 44)
        | (1 << 43)
        | (64 << 36)
        | (u64::from(odd) << 34)
        | (u64::from(c.lat) << 17)
        | u64::from(c.lon);
    encode::df17(5, icao, me)
}

#[test]
fn riddle_pair_gives_the_published_position() {
    let mut tr = Tracker::new(TrackerConfig::default());
    let (odd, _) = hex_frame("8D40621D58C386435CC412692AD6");
    let (even, _) = hex_frame("8D40621D58C382D690C8AC2863A7");
    let u = feed(&mut tr, &odd, at(100.0));
    assert!(u.accepted && u.position.is_none());
    let u = feed(&mut tr, &even, at(102.0));
    let p = u.position.unwrap();
    assert_eq!(p.method, PositionMethod::Global);
    assert!((p.lat_deg - 52.257_20).abs() < 1e-5 && (p.lon_deg - 3.919_37).abs() < 1e-5);
    // TC 11, version unknown (0): NIC 8.
    assert_eq!(u.nic, Some(8));
    let a = tr.aircraft(0x40_621D).unwrap();
    assert_eq!(a.altitude_baro_ft, Some(38_000));
}

#[test]
fn pairing_window_and_times() {
    let mut tr = Tracker::new(TrackerConfig::default());
    let e = pos_frame(1, 11, 45.0, 7.0, false, false);
    let o = pos_frame(1, 11, 45.001, 7.001, true, false);
    feed(&mut tr, &e, at(0.0));
    // 10.5 s later: outside the window, no reference: nothing.
    assert!(feed(&mut tr, &o, at(10.5)).position.is_none());
    // Midnight wrap: 86399.5 and 5.0 s are 5.5 s apart.
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &e, at(86_399.5));
    assert!(feed(&mut tr, &o, at(5.0)).position.is_some());
    // Without times, consecutive frames pair.
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &e, RxMeta::default());
    let p = feed(&mut tr, &o, RxMeta::default()).position.unwrap();
    assert!((p.lat_deg - 45.001).abs() < 1e-4);
    // Then one frame alone decodes locally against the last position.
    let e2 = pos_frame(1, 11, 45.01, 7.01, false, false);
    let mut tr2 = tr.clone();
    let p = feed(&mut tr2, &e2, RxMeta::default()).position.unwrap();
    assert!((p.lat_deg - 45.01).abs() < 1e-4 && (p.lon_deg - 7.01).abs() < 1e-4);
    assert_eq!(
        p.method,
        PositionMethod::Global,
        "a pair is still available"
    );
    let mut tr3 = Tracker::new(TrackerConfig::default());
    feed(&mut tr3, &e, at(0.0));
    feed(&mut tr3, &o, at(1.0));
    let p = feed(&mut tr3, &e2, at(20.0)).position.unwrap();
    assert_eq!(p.method, PositionMethod::LocalAircraft);
    assert!((p.lat_deg - 45.01).abs() < 1e-4);
    // Too old a reference (> 30 s) and no pair: nothing.
    assert!(feed(&mut tr3, &o, at(60.0)).position.is_none());
}

#[test]
fn zone_mismatch_is_rejected_and_counted() {
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(
        &mut tr,
        &pos_frame(2, 11, 10.46, 20.0, false, false),
        at(0.0),
    );
    let u = feed(
        &mut tr,
        &pos_frame(2, 11, 10.48, 20.0, true, false),
        at(1.0),
    );
    assert!(u.position.is_none() && u.cpr_rejected);
    assert_eq!(tr.cpr_rejections, 1);
}

#[test]
fn surface_and_airborne_never_pair() {
    let cfg = TrackerConfig {
        receiver: Some((51.99, 4.375)),
        ..TrackerConfig::default()
    };
    let mut tr = Tracker::new(cfg);
    feed(&mut tr, &pos_frame(3, 11, 52.3, 4.7, false, false), at(0.0));
    // A surface odd frame right after: decoded locally against the receiver, not paired.
    let u = feed(&mut tr, &surface_frame(3, 52.3206, 4.7347, true), at(1.0));
    let p = u.position.unwrap();
    assert_eq!(p.method, PositionMethod::LocalReceiver);
    assert!(p.surface);
    assert!((p.lat_deg - 52.3206).abs() < 1e-4 && (p.lon_deg - 4.7347).abs() < 1e-4);
    // The even surface frame completes a surface pair: global with the receiver reference.
    let p = feed(&mut tr, &surface_frame(3, 52.3207, 4.7348, false), at(2.0))
        .position
        .unwrap();
    assert_eq!(p.method, PositionMethod::Global);
    assert!((p.lat_deg - 52.3207).abs() < 1e-4 && (p.lon_deg - 4.7348).abs() < 1e-4);
    assert!(tr.aircraft(3).unwrap().on_ground);
    // Without a receiver or a previous position, a surface pair cannot be decoded.
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &surface_frame(4, 52.3206, 4.7347, true), at(1.0));
    assert!(
        feed(&mut tr, &surface_frame(4, 52.3206, 4.7347, false), at(2.0))
            .position
            .is_none()
    );
}

#[test]
fn nic_uses_the_supplements() {
    let mut tr = Tracker::new(TrackerConfig::default());
    let e = pos_frame(5, 11, 45.0, 7.0, false, true);
    assert_eq!(feed(&mut tr, &e, at(0.0)).nic, Some(8));
    let os = encode::operational_status(
        5,
        &OperationalStatusFields {
            version: 2,
            nic_a: true,
            nac_p: 9,
            sil: 3,
            ..Default::default()
        },
    )
    .unwrap();
    feed(&mut tr, &os, at(0.5));
    // TC 11, v2, NIC-A 1 (TC 31), NIC-B 1 (ME bit 8): NIC 9 (Rc < 75 m).
    assert_eq!(feed(&mut tr, &e, at(1.0)).nic, Some(9));
    assert_eq!(
        feed(&mut tr, &pos_frame(5, 11, 45.0, 7.0, true, false), at(1.5)).nic,
        Some(8)
    );
    let a = tr.aircraft(5).unwrap();
    assert_eq!((a.version, a.nac_p, a.sil), (Some(2), Some(9), Some(3)));
}

#[test]
fn address_parity_needs_a_known_address() {
    let mut tr = Tracker::new(TrackerConfig::default());
    let (df5, _) = hex_frame("282018154A9D59"); // AP -> 400159, squawk 1017
    assert!(!feed(&mut tr, &df5[..7], at(0.0)).accepted);
    let (df11, _) = hex_frame("5F4001594B0FBB"); // DF11 400159
    assert!(feed(&mut tr, &df11[..7], at(0.1)).accepted);
    assert!(feed(&mut tr, &df5[..7], at(0.2)).accepted);
    assert_eq!(
        tr.aircraft(0x40_0159).unwrap().squawk.unwrap().to_string(),
        "1017"
    );
}

#[test]
fn bounded_table_evicts_the_least_recently_heard() {
    let mut tr = Tracker::new(TrackerConfig {
        capacity: 2,
        ..TrackerConfig::default()
    });
    let f = |a| encode::df11(5, a, 0).unwrap();
    feed(&mut tr, &f(1), at(0.0));
    feed(&mut tr, &f(2), at(1.0));
    feed(&mut tr, &f(1), at(2.0)); // 1 heard again: 2 is now the oldest
    feed(&mut tr, &f(3), at(3.0));
    assert_eq!(tr.len(), 2);
    assert_eq!(tr.evictions, 1);
    assert!(tr.aircraft(1).is_some() && tr.aircraft(3).is_some() && tr.aircraft(2).is_none());
}

#[test]
fn traffic_report_once_located() {
    let mut tr = Tracker::new(TrackerConfig::default());
    let id = encode::identification(6, 4, 3, "TEST12").unwrap();
    feed(&mut tr, &id, at(0.0));
    let v = encode::velocity_ground(6, 0, 100, Some(-1024), true, 2).unwrap();
    // Velocity before any position: no report.
    assert!(feed(&mut tr, &v, at(0.1)).report.is_none());
    feed(&mut tr, &pos_frame(6, 11, 45.0, 7.0, false, false), at(0.2));
    let r = feed(&mut tr, &pos_frame(6, 11, 45.0, 7.0, true, false), at(0.3))
        .report
        .unwrap();
    assert_eq!(r.protocol, crate::traffic::Protocol::RawModeS);
    assert_eq!(r.address_hex(), "000006");
    assert_eq!(r.callsign.as_deref(), Some("TEST12"));
    assert_eq!(r.emitter_category, Some(3));
    assert!((r.lat_deg.unwrap() - 45.0).abs() < 1e-4);
    assert!((r.alt_pressure_m.unwrap() - 3048.0).abs() < 1e-9);
    assert!((r.ground_speed_mps.unwrap() - 100.0 * 1852.0 / 3600.0).abs() < 1e-9);
    assert!((r.vertical_rate_mps.unwrap() + 1024.0 * 0.00508).abs() < 1e-9);
    assert_eq!(r.track_deg, Some(0.0));
    assert_eq!(r.nac_v, Some(2));
    assert_eq!(
        r.source_time,
        Some(crate::traffic::SourceTime::NsSinceUtcMidnight(300_000_000))
    );
}

#[test]
fn random_valid_squitters_never_panic() {
    // Arbitrary ME fields with correct parity exercise every register decoder, CPR and the
    // tracker on values no real transmitter sends; a tiny table forces evictions too.
    let mut rng = crate::testkit::XorShift::new(77);
    let cfg = TrackerConfig {
        capacity: 8,
        receiver: Some((10.0, 20.0)),
        ..TrackerConfig::default()
    };
    let mut tr = Tracker::new(cfg);
    for i in 0..50_000u32 {
        let icao = (rng.below(16) as u32) * 0x1_0101;
        let me = rng.next_u64() & 0xFF_FFFF_FFFF_FFFF;
        let f = encode::df17((rng.below(8)) as u8, icao, me);
        let meta = if i % 3 == 0 {
            RxMeta::default()
        } else {
            at(f64::from(i) * 0.01)
        };
        let u = feed(&mut tr, &f, meta);
        assert!(u.accepted);
        if let Some(p) = u.position {
            assert!(
                (-90.0..=90.0).contains(&p.lat_deg) && (-180.0..180.0).contains(&p.lon_deg),
                "{p:?}"
            );
        }
    }
    assert!(tr.len() <= 8);
    assert!(tr.evictions > 0);
}

#[test]
fn implausible_positions_are_rejected() {
    // A fix at 45 N 7 E, then 2 s later a pair whose decode lands 2 deg (222 km) away: not
    // reachable at 1000 m/s in 2 s.
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(pair(&mut tr, 7, 45.0, 7.0, 0.0).position.is_some());
    let u = pair(&mut tr, 7, 47.0, 7.0, 2.0);
    assert!(u.position.is_none() && u.cpr_rejected);
    // Out of range of the receiver (about 890 km away).
    let cfg = TrackerConfig {
        receiver: Some((52.0, 4.0)),
        ..TrackerConfig::default()
    };
    let mut tr = Tracker::new(cfg);
    assert!(pair(&mut tr, 8, 45.0, 7.0, 0.0).position.is_none());
    assert_eq!(tr.cpr_rejections, 1);
    // Within range: accepted. Hand check of the distance: 1 deg of latitude = 111.2 km.
    assert!(pair(&mut tr, 9, 51.0, 4.0, 0.0).position.is_some());
    assert!((distance_m((51.0, 4.0), (52.0, 4.0)) - 111_195.0).abs() < 10.0);
}

#[test]
fn fast_distance_check_agrees_with_the_exact_one() {
    let mut rng = crate::testkit::XorShift::new(12);
    for _ in 0..20_000 {
        let a = (
            rng.below(1_780_000) as f64 / 1e4 - 89.0,
            rng.below(3_600_000) as f64 / 1e4 - 180.0,
        );
        let b = (
            (a.0 + (rng.below(2000) as f64 - 1000.0) / 1e3).clamp(-90.0, 90.0),
            a.1 + (rng.below(2000) as f64 - 1000.0) / 1e3,
        );
        let limit = rng.below(200_000) as f64;
        assert_eq!(
            within_distance(a, b, limit),
            distance_m(a, b) <= limit,
            "{a:?} {b:?} {limit}"
        );
    }
    // Cases the random pairs (within 1 deg of each other, limits in metres to 200 km) never
    // reach: longitudes 200 deg apart the short way round (160 deg, 17,800 km), and a limit
    // under 2 m (1.2 m apart, 1 m allowed), where squaring the limit shrinks it.
    assert!(!within_distance((0.0, 100.0), (0.0, -100.0), 1_000_000.0));
    assert!(within_distance((0.0, 170.0), (0.0, -170.0), 2_300_000.0));
    assert!(!within_distance((0.0, 0.0), (1.2 / 111_195.08, 0.0), 1.0));
    assert!(within_distance((0.0, 0.0), (0.8 / 111_195.08, 0.0), 1.0));
    assert!(!within_distance((0.0, 0.0), (0.8 / 111_195.08, 0.0), 0.5));
}

#[test]
fn report_flags_ground_emergency_and_relay() {
    // Airborne DF17 pair: none of the flags.
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &pos_frame(7, 11, 45.0, 7.0, false, false), at(0.0));
    let r = feed(&mut tr, &pos_frame(7, 11, 45.0, 7.0, true, false), at(0.5))
        .report
        .unwrap();
    assert!(!r.flags.on_ground && !r.flags.emergency && !r.flags.relayed);
    // TC 28 subtype 1 with emergency code 1 (general emergency; ME bits 6-8 subtype, 9-11
    // code), then a position: the emergency flag and the code.
    let me = (28u64 << 51) | (1 << 48) | (1 << 45);
    feed(&mut tr, &encode::df17(5, 7, me), at(0.6));
    let r = feed(&mut tr, &pos_frame(7, 11, 45.0, 7.0, false, false), at(1.0))
        .report
        .unwrap();
    assert!(r.flags.emergency && !r.flags.on_ground && !r.flags.relayed);
    assert_eq!(r.emergency_code, Some(1));
    // Code 0 is "no emergency".
    feed(
        &mut tr,
        &encode::df17(5, 7, (28u64 << 51) | (1 << 48)),
        at(1.1),
    );
    let r = feed(&mut tr, &pos_frame(7, 11, 45.0, 7.0, true, false), at(1.5))
        .report
        .unwrap();
    assert!(!r.flags.emergency);
    // The same pair as DF18 with CF 6 (ADS-R, DO-260B 2.2.18): relayed.
    let df18 = |f| as_df18(f, 6);
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(
        &mut tr,
        &df18(pos_frame(8, 11, 45.0, 7.0, false, false)),
        at(0.0),
    );
    let r = feed(
        &mut tr,
        &df18(pos_frame(8, 11, 45.0, 7.0, true, false)),
        at(0.5),
    )
    .report
    .unwrap();
    assert!(r.flags.relayed && !r.flags.on_ground);
    // A surface pair (with the receiver's position): on the ground.
    let cfg = TrackerConfig {
        receiver: Some((51.99, 4.375)),
        ..TrackerConfig::default()
    };
    let mut tr = Tracker::new(cfg);
    feed(&mut tr, &surface_frame(9, 52.3206, 4.7347, true), at(0.0));
    let r = feed(&mut tr, &surface_frame(9, 52.3207, 4.7348, false), at(1.0))
        .report
        .unwrap();
    assert!(r.flags.on_ground && !r.flags.relayed && !r.flags.emergency);
}

#[test]
fn the_configuration_is_the_one_given() {
    let cfg = TrackerConfig {
        capacity: 17,
        ..TrackerConfig::default()
    };
    assert_eq!(Tracker::new(cfg).config(), &cfg);
}

#[test]
fn coarse_tis_b_and_management_frames_are_accepted_but_not_tracked() {
    // DF18 CF 3 (coarse TIS-B) and CF 4 (management): their address field may be a track
    // number, so they vouch for no one and start no track (DO-260B 2.2.3.2.1.1). CF 0 (ADS-B
    // from a non-transponder device) is tracked.
    let with_cf = |cf| as_df18(pos_frame(9, 11, 45.0, 7.0, false, false), cf);
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(tr.is_empty());
    for cf in [3, 4] {
        let up = feed(&mut tr, &with_cf(cf), at(0.0));
        assert!(up.accepted, "CF {cf}");
        assert!(tr.is_empty(), "CF {cf}");
    }
    assert!(feed(&mut tr, &with_cf(0), at(0.1)).accepted);
    assert!(!tr.is_empty());
    assert_eq!(tr.len(), 1);
}

#[test]
fn a_last_position_older_than_30_s_does_not_gate_a_jump() {
    // The jump of `implausible_positions_are_rejected` (2 deg, 222 km), 40 s after the last fix
    // instead of 2 s: the last position is older than `local_max_age_s` (30 s), too old to
    // vouch against a new global decode, which stands on its own.
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(pair(&mut tr, 7, 45.0, 7.0, 0.0).position.is_some());
    feed(
        &mut tr,
        &pos_frame(7, 11, 47.0, 7.0, false, false),
        at(40.0),
    );
    let u = feed(&mut tr, &pos_frame(7, 11, 47.0, 7.0, true, false), at(40.5));
    assert!(u.position.is_some() && !u.cpr_rejected);
}

#[test]
fn on_ground_from_the_df17_ca_and_the_all_call_capability() {
    // CA / capability 4 = "level 2+ transponder, on ground", 5 = "airborne" (ICAO Annex 10
    // Vol IV 3.1.2.5.2.2.1). DF18 has CF in that field, which says nothing of the ground.
    let id = encode::df17(4, 0x00AB_CDEF, (4u64 << 51) | (1 << 48));
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &id, at(0.0));
    assert!(tr.aircraft(0x00AB_CDEF).unwrap().on_ground);
    feed(&mut tr, &as_df18(id, 0), at(0.1));
    assert!(tr.aircraft(0x00AB_CDEF).unwrap().on_ground);
    feed(
        &mut tr,
        &encode::df17(5, 0x00AB_CDEF, (4u64 << 51) | (1 << 48)),
        at(0.2),
    );
    assert!(!tr.aircraft(0x00AB_CDEF).unwrap().on_ground);
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &encode::df11(4, 0x00AB_CDEF, 0).unwrap(), at(0.0));
    assert!(tr.aircraft(0x00AB_CDEF).unwrap().on_ground);
    feed(&mut tr, &encode::df11(5, 0x00AB_CDEF, 0).unwrap(), at(0.1));
    assert!(!tr.aircraft(0x00AB_CDEF).unwrap().on_ground);
}

#[test]
fn reachability_counts_time_across_midnight() {
    // Receive times are UTC seconds of the day: the last fix at 23:59:50 and a frame at
    // 00:00:15 are 25 s apart, not 86,375 s.
    let fix = |tr: &mut Tracker, lat: f64, t: f64| pair(tr, 7, lat, 7.0, t);
    // 0.27 deg of latitude (30.0 km) in 25 s: within 1000 m/s x 25 s + 5 NM.
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(fix(&mut tr, 45.0, 86_389.5).position.is_some());
    let p = fix(&mut tr, 45.27, 15.0).position.unwrap();
    assert!((p.lat_deg - 45.27).abs() < 1e-3, "{p:?}");
    // 2 deg (222 km) in 2 s across midnight: not reachable.
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(fix(&mut tr, 45.0, 86_399.0).position.is_some());
    let u = fix(&mut tr, 47.0, 1.5);
    assert!(u.position.is_none() && u.cpr_rejected);
    // The same jump in 2 s late in the day (no wrap): not reachable either.
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(fix(&mut tr, 45.0, 1_000.0).position.is_some());
    let u = fix(&mut tr, 47.0, 1_002.0);
    assert!(u.position.is_none() && u.cpr_rejected);
}

#[test]
fn df18_address_types_never_merge_with_the_icao_aircraft_of_that_number() {
    // DO-260B 2.2.3.2.1.1: DF18 CF 1 = non-ICAO address, CF 2 = TIS-B with an ICAO address,
    // CF 5 = fine TIS-B with another address (a track file number): four table keys for one
    // 24-bit number.
    let id = |cf: Option<u8>| {
        let f = encode::df17(5, 0x00AB_CDEF, (4u64 << 51) | (1 << 48));
        cf.map_or(f, |cf| as_df18(f, cf))
    };
    let mut tr = Tracker::new(TrackerConfig::default());
    for cf in [None, Some(0), Some(1), Some(2), Some(6), Some(5)] {
        feed(&mut tr, &id(cf), at(0.0));
    }
    // (CF 0 is the ICAO aircraft itself; CF 6 = ADS-R of an ICAO address, relayed as CF 2.)
    assert_eq!(tr.len(), 4);
    for (key, kind) in [
        (0x00AB_CDEF, AddressType::Icao),
        (0x01AB_CDEF, AddressType::NonIcao),
        (0x02AB_CDEF, AddressType::TisbIcao),
        (0x03AB_CDEF, AddressType::TisbOther),
    ] {
        assert_eq!(
            tr.aircraft(key).map(|a| a.address_type),
            Some(kind),
            "{key:#x}"
        );
    }
    // A CF 0 frame alone is the ICAO aircraft.
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &id(Some(0)), at(0.0));
    assert_eq!(
        tr.aircraft(0x00AB_CDEF).map(|a| a.address_type),
        Some(AddressType::Icao)
    );
}

#[test]
fn a_gnss_height_position_reports_its_geometric_altitude_in_metres() {
    // TC 20 (GNSS height): 3,000 ft encoded in 25 ft steps; 3,000 x 0.3048 = 914.4 m.
    let gnss = |odd| {
        encode::airborne_position(
            7,
            &AirbornePositionFields {
                typecode: 20,
                surveillance_status: 0,
                nic_b: false,
                altitude_ft: Some(3_000),
                lat_deg: 45.0,
                lon_deg: 7.0,
                odd,
            },
        )
        .unwrap()
    };
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(&mut tr, &gnss(false), at(0.0));
    let r = feed(&mut tr, &gnss(true), at(0.5)).report.unwrap();
    assert!((r.alt_geometric_m.unwrap() - 914.4).abs() < 1e-9);
    assert_eq!(r.alt_pressure_m, None);
}

#[test]
fn the_last_position_gates_only_positions_of_its_kind_and_age() {
    // An airborne fix 57 km north of the receiver, then 2 s later a surface pair at the
    // receiver: not reachable in 2 s, but an airborne position says nothing about where the
    // aircraft stands on the ground (and a surface decode is local to the receiver anyway).
    let cfg = TrackerConfig {
        receiver: Some((51.99, 4.375)),
        ..TrackerConfig::default()
    };
    let mut tr = Tracker::new(cfg);
    assert!(pair(&mut tr, 7, 52.5, 4.4, 0.0).position.is_some());
    feed(&mut tr, &surface_frame(7, 51.99, 4.375, false), at(2.0));
    let u = feed(&mut tr, &surface_frame(7, 51.99, 4.375, true), at(2.5));
    assert!(u.position.is_some_and(|p| p.surface), "{u:?}");
    // Across midnight a last fix 200 s old (23:58:20 to 00:01:40) is too old to gate a 2 deg
    // jump: accepted.
    let mut tr = Tracker::new(TrackerConfig::default());
    feed(
        &mut tr,
        &pos_frame(8, 11, 45.0, 7.0, false, false),
        at(86_299.5),
    );
    assert!(
        feed(
            &mut tr,
            &pos_frame(8, 11, 45.0, 7.0, true, false),
            at(86_300.0)
        )
        .position
        .is_some()
    );
    feed(
        &mut tr,
        &pos_frame(8, 11, 47.0, 7.0, false, false),
        at(100.0),
    );
    let u = feed(
        &mut tr,
        &pos_frame(8, 11, 47.0, 7.0, true, false),
        at(100.5),
    );
    assert!(u.position.is_some() && !u.cpr_rejected);
}

#[test]
fn a_refused_global_decode_frees_the_other_frame_for_a_local_decode() {
    // A fix at 45 N 7 E; 2 s later a pair placing the aircraft at 47 N (222 km away, not
    // reachable): refused, and its even frame forgotten. The next odd frame, at the true
    // position, then decodes locally against the last fix instead of pairing again with the
    // refused even frame (which would be refused again).
    let mut tr = Tracker::new(TrackerConfig::default());
    assert!(pair(&mut tr, 7, 45.0, 7.0, 0.0).position.is_some());
    let u = pair(&mut tr, 7, 47.0, 7.0, 2.0);
    assert!(u.position.is_none() && u.cpr_rejected);
    let u = feed(
        &mut tr,
        &pos_frame(7, 11, 45.001, 7.0, true, false),
        at(3.0),
    );
    let p = u.position.expect("a local decode");
    assert_eq!(p.method, PositionMethod::LocalAircraft);
    // Within the CPR quantum of the encoded position (about 5 m).
    assert!(
        (p.lat_deg - 45.001).abs() < 1e-4 && (p.lon_deg - 7.0).abs() < 1e-4,
        "{p:?}"
    );
}
