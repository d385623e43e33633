use vigil_drivers::traffic::{AddressType, Link, Protocol, TrafficReport};

use super::*;
use crate::ownship::{Ownship, PositionSource};
use crate::traffic::track::AddressSpace;
use crate::units::{M_PER_FT, MPS_PER_KT};

const S: i64 = 1_000_000_000;

fn own() -> Ownship {
    Ownship {
        t_gps_ns: 0,
        lat_deg: 47.0,
        lon_deg: 8.0,
        alt_pressure_m: Some(1000.0),
        alt_geometric_m: Some(1050.0),
        track_deg: Some(0.0),
        ground_speed_mps: Some(0.0),
        vertical_rate_mps: Some(0.0),
        heading_deg: Some(90.0),
        position_sigma_m: Some(2.0),
        source: PositionSource::External,
        alt_geometric_band_m: 0.0,
    }
}

fn report(address: u32, lat: f64, lon: f64) -> TrafficReport {
    TrafficReport {
        link: Link::Adsb1090,
        protocol: Protocol::RawModeS,
        address,
        address_type: AddressType::Icao,
        lat_deg: Some(lat),
        lon_deg: Some(lon),
        alt_pressure_m: Some(1000.0),
        track_deg: Some(180.0),
        ground_speed_mps: Some(100.0 * MPS_PER_KT),
        vertical_rate_mps: Some(0.0),
        nac_p: Some(9),
        ..Default::default()
    }
}

#[test]
fn merges_links_and_keeps_address_spaces_apart() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(0, &report(0xABCDEF, 47.1, 8.0));
    let uat = TrafficReport {
        link: Link::Uat978,
        protocol: Protocol::Json,
        ..report(0xABCDEF, 47.1, 8.0)
    };
    m.update(S / 2, &uat);
    let tisb = TrafficReport {
        address_type: AddressType::TisbIcao,
        ..report(0xABCDEF, 47.1, 8.0)
    };
    m.update(S, &tisb);
    // The same number as a FLARM random id is another aircraft.
    let flarm = TrafficReport {
        link: Link::Flarm,
        address_type: AddressType::FlarmRandom,
        ..report(0xABCDEF, 47.2, 8.0)
    };
    m.update(S, &flarm);
    assert_eq!(m.len(), 2);
    let t = m
        .track(&TargetKey {
            space: AddressSpace::Icao,
            address: 0xABCDEF,
        })
        .unwrap();
    assert_eq!(t.sources.len(), 2, "ADS-B (raw, also relayed) and UAT JSON");
    let pic = m.picture(2 * S, &own());
    assert_eq!(pic.len(), 2);
}

#[test]
fn extrapolates_along_velocity() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(0, &report(1, 47.1, 8.0));
    let pic = m.picture(10 * S, &own());
    // 100 kt south for 10 s = 514.4 m; the meridian radius at 47.1 deg is about 6 367 800 m, so
    // 514.4 m is 0.0046284 deg.
    let moved = 47.1 - pic[0].lat_deg;
    assert!(
        (moved - 514.444 / 6_367_800.0f64 * 180.0 / std::f64::consts::PI).abs() < 2e-6,
        "{moved}"
    );
    assert!((pic[0].lon_deg - 8.0).abs() < 1e-12);
    assert!((pic[0].age_s - 10.0).abs() < 1e-12);
    // Its velocity: 100 kt = 51.444 m/s due south, level.
    let v = pic[0].velocity_ne_mps.unwrap();
    assert!((v[0] + 51.444).abs() < 1e-3 && v[1].abs() < 1e-9, "{v:?}");
    assert_eq!(pic[0].vertical_rate_mps, Some(0.0));
}

/// East along the parallel (issue 23: the first test moved only south, so nothing pinned the
/// east step): 100 kt due east for 10 s at 47.1 deg N is 514.444 m on the parallel of radius
/// N cos(lat), N = a / sqrt(1 - e^2 sin^2 lat) = 6 389 624.15 m (WGS-84, worked by hand), so
/// 0.0067767 deg of longitude; the latitude does not move.
#[test]
fn extrapolates_east_along_the_parallel() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(
        0,
        &TrafficReport {
            track_deg: Some(90.0),
            ..report(1, 47.1, 8.0)
        },
    );
    let pic = m.picture(10 * S, &own());
    let moved = pic[0].lon_deg - 8.0;
    assert!((moved - 0.006_776_676).abs() < 1e-8, "{moved}");
    assert!((pic[0].lat_deg - 47.1).abs() < 1e-12);
    // Its velocity: 51.444 m/s east, none north.
    let v = pic[0].velocity_ne_mps.unwrap();
    assert!(v[0].abs() < 1e-9 && (v[1] - 51.444).abs() < 1e-3, "{v:?}");
}

#[test]
fn times_out_and_evicts_by_policy() {
    let p = TrafficParams {
        capacity: 3,
        ..Default::default()
    };
    let mut m = TrackManager::new(p);
    m.set_ownship(own());
    // Three fresh tracks at 10, 20 and 30 km north.
    for (i, km) in [10.0, 20.0, 30.0].iter().enumerate() {
        m.update(0, &report(i as u32 + 1, 47.0 + km / 111.2, 8.0));
    }
    // A fourth arrives 1 s later: nothing stale, so the farthest (30 km, address 3) goes.
    m.update(S, &report(4, 47.05, 8.0));
    assert_eq!(m.stats().tracks_evicted, 1);
    assert!(
        m.track(&TargetKey {
            space: AddressSpace::Icao,
            address: 3
        })
        .is_none()
    );
    // Refresh 2 and 4; 1 becomes stale (> 5 s); a fifth evicts the stale one, although nearer.
    m.update(7 * S, &report(2, 47.18, 8.0));
    m.update(7 * S, &report(4, 47.05, 8.0));
    m.update(7 * S, &report(5, 47.3, 8.0));
    assert!(
        m.track(&TargetKey {
            space: AddressSpace::Icao,
            address: 1
        })
        .is_none()
    );
    assert_eq!(m.stats().tracks_evicted, 2);
    // Timeout: 20 s after the last report every track goes, counted.
    let pic = m.picture(28 * S, &own());
    assert!(pic.is_empty());
    assert_eq!(m.stats().tracks_timed_out, 3);
}

#[test]
fn altitude_like_with_like() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(0, &report(1, 47.05, 8.0));
    let geo_only = TrafficReport {
        alt_pressure_m: None,
        alt_geometric_m: Some(1100.0),
        ..report(2, 47.06, 8.0)
    };
    m.update(0, &geo_only);
    let none = TrafficReport {
        alt_pressure_m: None,
        ..report(3, 47.07, 8.0)
    };
    m.update(0, &none);
    let pic = m.picture(0, &own());
    let by = |a: u32| pic.iter().find(|t| t.key.address == a).unwrap();
    assert_eq!(by(1).altitude_kind, AltitudeKind::Pressure);
    assert_eq!(by(1).geometry.unwrap().vertical_separation_m, Some(0.0));
    assert_eq!(by(2).altitude_kind, AltitudeKind::Geometric);
    // 1100 m geometric against the ownship's 1050 m geometric, not its 1000 m pressure altitude.
    assert!((by(2).geometry.unwrap().vertical_separation_m.unwrap() - 50.0).abs() < 1e-9);
    assert_eq!(by(3).altitude_kind, AltitudeKind::None);
    // Issue 24: no altitude is co-altitude (horizontal geometry decides), flagged, not "no
    // geometry".
    let g = by(3).geometry.unwrap();
    assert_eq!(g.vertical_separation_m, None);
    assert!(by(3).fail_safe.altitude_unknown);
}

#[test]
fn plausibility_flags() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.set_ownship(own());
    // Impossible speed: 900 kt.
    let fast = TrafficReport {
        ground_speed_mps: Some(900.0 * MPS_PER_KT),
        ..report(1, 47.1, 8.0)
    };
    m.update(0, &fast);
    // Position jump: 20 km in 1 s from the same source.
    m.update(0, &report(2, 47.1, 8.0));
    m.update(S, &report(2, 47.28, 8.0));
    // Two sources 5 km apart at the same time.
    m.update(0, &report(3, 47.1, 8.0));
    let flarm = TrafficReport {
        link: Link::Flarm,
        protocol: Protocol::Csv,
        ..report(3, 47.145, 8.0)
    };
    m.update(0, &flarm);
    // Altitude jump: 3000 ft in 1 s.
    m.update(0, &report(4, 47.1, 8.0));
    m.update(
        S,
        &TrafficReport {
            alt_pressure_m: Some(1000.0 + 3000.0 * M_PER_FT),
            ..report(4, 47.1, 8.0)
        },
    );
    // Spoofing: -30 dBm from a position 200 km away (the free-space maximum there is -82 dBm).
    m.update(
        0,
        &TrafficReport {
            signal_dbm: Some(-30.0),
            ..report(5, 48.8, 8.0)
        },
    );
    // A clean target for contrast, with a plausible signal at 11 km.
    m.update(
        0,
        &TrafficReport {
            signal_dbm: Some(-70.0),
            ..report(6, 47.1, 8.0)
        },
    );
    let pic = m.picture(S, &own());
    let flags = |a: u32| pic.iter().find(|t| t.key.address == a).unwrap().flags;
    assert!(flags(1).impossible_speed);
    assert!(flags(2).position_jump && !flags(2).inconsistent_sources);
    assert!(flags(3).inconsistent_sources);
    assert!(flags(4).altitude_jump);
    assert!(flags(5).range_vs_signal);
    assert!(!flags(6).any());
    // Flags never drop a target.
    assert_eq!(pic.len(), 6);
}

#[test]
fn priority_order_and_relative_bearing() {
    let mut m = TrackManager::new(TrafficParams::default());
    // A far target, a near co-altitude converging one, and one far above.
    m.update(0, &report(1, 47.3, 8.0));
    m.update(0, &report(2, 47.02, 8.0));
    m.update(
        0,
        &TrafficReport {
            alt_pressure_m: Some(3000.0),
            ..report(3, 47.01, 8.0)
        },
    );
    let mut pic = Vec::new();
    for k in 0..3 {
        pic = m.picture(k * S, &own());
    }
    // Target 2 (2.2 km north, closing at 100 kt, co-altitude) alerts at level 3 after 2 of 4.
    assert_eq!(pic[0].key.address, 2);
    assert_eq!(pic[0].alert_level, 3);
    assert!(pic[0].raw_alert_level == 3);
    // Ownship heading 90: a target due north is at -90 relative.
    assert!(
        (pic[0].bearing_true_deg - 0.0).abs() < 1e-6
            || (pic[0].bearing_true_deg - 360.0).abs() < 1e-6
    );
    assert!((pic[0].bearing_relative_deg.unwrap() + 90.0).abs() < 1e-6);
    // Then by range among non-alerting targets.
    assert_eq!(pic[1].key.address, 3);
    assert_eq!(pic[2].key.address, 1);
}

#[test]
fn flarm_alarm_level_is_carried() {
    let mut m = TrackManager::new(TrafficParams::default());
    let r = TrafficReport {
        link: Link::Flarm,
        address_type: AddressType::FlarmFixed,
        flarm_alarm_level: Some(2),
        ..report(9, 47.01, 8.0)
    };
    m.update(0, &r);
    assert_eq!(m.picture(0, &own())[0].flarm_alarm_level, Some(2));
}

/// Issue 24: a report moving south at 100 kt from (47.1, 8.0), at time `t` s, its position
/// shifted east by `drift_m`.
fn moving(t: f64, drift_m: f64) -> TrafficReport {
    let v = 100.0 * MPS_PER_KT;
    let (m_lat, m_lon) = (111_200.0, 111_200.0 * 47.1f64.to_radians().cos());
    report(7, 47.1 - v * t / m_lat, 8.0 + drift_m / m_lon)
}

#[test]
fn regression_24_a_slow_drift_is_flagged_and_held_until_consistent() {
    let mut m = TrackManager::new(TrafficParams::default());
    // Honest for 20 s: no flag (the window integrates the reported velocity).
    for s in 0..20 {
        m.update(s * S, &moving(s as f64, 0.0));
    }
    assert!(!m.picture(20 * S, &own())[0].flags.any());
    // Then 20 m/s east of where its velocity takes it: far below the 350 m/s jump test. NACp 9
    // (sigma 12.2 m): the limit is 5 x 17.3 + 2 m/s x span, about 106 m: crossed after ~6 s.
    let mut first = None;
    for s in 20..40 {
        m.update(s * S, &moving(s as f64, 20.0 * (s - 20) as f64));
        let x = &m.picture(s * S, &own())[0];
        assert!(!x.flags.position_jump);
        if x.flags.position_drift && first.is_none() {
            first = Some(s - 20);
        }
    }
    let first = first.expect("flagged");
    assert!((5..=8).contains(&first), "after {first} s");
    // Silent: stays flagged (only consistent reports clear it), until the track times out.
    assert!(m.picture(50 * S, &own())[0].flags.position_drift);
    // Consistent again (a new, honest chain): cleared after 60 s of it, not before.
    let off = 20.0 * 19.0;
    for s in 51..=115 {
        m.update(s * S, &moving(s as f64, off));
        let x = &m.picture(s * S, &own())[0];
        if s < 105 {
            assert!(x.flags.any(), "cleared too early at {s} s");
        }
    }
    assert!(!m.picture(115 * S, &own())[0].flags.any());
}

#[test]
fn regression_24_a_report_is_placed_at_its_time_of_applicability() {
    let mut m = TrackManager::new(TrafficParams::default());
    // Data 2 s old at arrival (t = 10 s): applicable at 8 s. At the picture (10 s) vigil moves it
    // on by 2 s at 100 kt = 102.9 m south; the age is the data's.
    m.update_at(8 * S, &report(5, 47.1, 8.0), true);
    let x = &m.picture(10 * S, &own())[0];
    let moved_m = (47.1 - x.lat_deg) * 111_200.0;
    assert!((moved_m - 102.9).abs() < 1.0, "{moved_m}");
    assert!((x.age_s - 2.0).abs() < 1e-9);
    assert!(x.fail_safe.time_from_receipt);
    // Older than the ADS-B limit (5 s): no geometry, counted.
    let x = &m.picture(14 * S, &own())[0];
    assert!(x.fail_safe.stale && x.geometry.is_none());
    assert_eq!(m.stats().stale_dropped, 1);
}

#[test]
fn regression_24_unknown_ownship_velocity_is_not_nan() {
    // Today's bug: NaN track and speed put every co-altitude target at level 3.
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(0, &report(1, 47.0 + 5.0 * 1852.0 / 111_200.0, 8.0));
    let o = Ownship {
        track_deg: None,
        ground_speed_mps: None,
        ..own()
    };
    let x = &m.picture(0, &o)[0];
    assert!(x.fail_safe.ownship_velocity_unknown);
    assert_eq!(x.raw_alert_level, 0);
    let g = x.geometry.unwrap();
    assert!((g.horizontal_distance_m - 9260.0).abs() < 20.0);
}

#[test]
fn reported_state_is_the_newest_of_each_field_moved_to_the_picture_time() {
    let mut m = TrackManager::new(TrafficParams::default());
    // t = 0: ADS-B on 1090, NACp 9, no NIC, light aircraft, climbing 5 m/s.
    m.update(
        0,
        &TrafficReport {
            emitter_category: Some(1),
            vertical_rate_mps: Some(5.0),
            alt_geometric_m: Some(1100.0),
            ..report(0xABCDEF, 47.1, 8.0)
        },
    );
    // t = 0.5 s: the same aircraft on UAT with NIC 7 and NACp 8.
    m.update(
        S / 2,
        &TrafficReport {
            link: Link::Uat978,
            protocol: Protocol::Json,
            nic: Some(7),
            nac_p: Some(8),
            vertical_rate_mps: Some(5.0),
            ..report(0xABCDEF, 47.1, 8.0)
        },
    );
    let pic = m.picture(2 * S, &own());
    let r = pic[0].reported;
    // Pressure altitude last reported at 0.5 s (1000 m), moved on 1.5 s at 5 m/s; geometric
    // last reported at 0 s (1100 m), moved on 2 s.
    assert!((r.alt_pressure_m.unwrap() - 1007.5).abs() < 1e-9, "{r:?}");
    assert!((r.alt_geometric_m.unwrap() - 1110.0).abs() < 1e-9, "{r:?}");
    assert_eq!(r.track_deg, Some(180.0));
    assert!((r.ground_speed_mps.unwrap() - 100.0 * MPS_PER_KT).abs() < 1e-9);
    // The newest report carrying each category gives it: NACp 8 (UAT, newer than 9), NIC 7
    // (only UAT gave one), NACv nobody.
    assert_eq!((r.nic, r.nac_p, r.nac_v), (Some(7), Some(8), None));
    assert_eq!(r.emitter_category, Some(1));
    assert_eq!(
        r.origins,
        Origins {
            adsb: true,
            uat: true,
            flarm: false,
            relayed: false
        }
    );
    // A TIS-B relay of it on 1090: the 1090 source's newest report is now relayed.
    m.update(
        S,
        &TrafficReport {
            address_type: AddressType::TisbIcao,
            ..report(0xABCDEF, 47.1, 8.0)
        },
    );
    let r = m.picture(2 * S, &own())[0].reported;
    assert!(
        r.origins.relayed && r.origins.uat && !r.origins.adsb,
        "{r:?}"
    );
    assert_eq!(
        r.nac_p,
        Some(9),
        "the relay at 1 s is the newest with a NACp"
    );
}

// --- issue 23: what the mutants of manager.rs showed no test pinned ---

/// The counters say what happened: 5 reports of 3 aircraft make 3 tracks; the two not heard for
/// more than `timeout_s` (20 s) are dropped and counted, the one heard again is kept.
#[test]
fn stats_count_reports_tracks_and_timeouts() {
    let mut m = TrackManager::new(TrafficParams::default());
    assert!(m.is_empty());
    m.update(0, &report(1, 47.1, 8.0));
    assert!(!m.is_empty());
    m.update(0, &report(2, 47.2, 8.0));
    m.update(S, &report(1, 47.1, 8.0));
    m.update(S, &report(3, 47.3, 8.0));
    m.update(15 * S, &report(3, 47.3, 8.0));
    let st = m.stats();
    assert_eq!((st.reports, st.tracks_created), (5, 3));
    // At 21.5 s: 1 (last 1 s) and 2 (last 0 s) are over 20 s old; 3 (15 s) is not.
    m.picture(21 * S + S / 2, &own());
    assert_eq!(m.stats().tracks_timed_out, 2);
    assert_eq!(m.len(), 1);
}

/// A report timed by its arrival (no time of its own) may be up to half a second older than
/// that: its position sigma grows by the distance flown in 0.5 s. NACp 9 (EPU 30 m) gives
/// sigma 30 / 2.4477 = 12.256 m; at 100 kt (51.444 m/s) the arrival-timed one is
/// 12.256 + 25.722 = 37.978 m (by hand).
#[test]
fn an_arrival_timed_report_widens_its_position_sigma() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update_at(10 * S, &report(1, 47.1, 8.0), false);
    m.update_at(10 * S, &report(2, 47.2, 8.0), true);
    let pic = m.picture(10 * S, &own());
    let sigma = |address: u32| {
        pic.iter()
            .find(|t| t.key.address == address)
            .map(|t| t.position_sigma_m)
            .unwrap()
    };
    assert!((sigma(1) - 12.256).abs() < 1e-3, "{}", sigma(1));
    assert!((sigma(2) - 37.978).abs() < 1e-3, "{}", sigma(2));
}

/// Eviction takes the stalest track only when it is older than `stale_evict_s` (5 s), strictly:
/// at exactly 5 s the farthest goes instead; 1 ns later, the stalest.
#[test]
fn eviction_by_age_starts_strictly_after_stale_evict_s() {
    for (t_new, gone) in [(5 * S, 2), (5 * S + 1, 1)] {
        let p = TrafficParams {
            capacity: 2,
            ..Default::default()
        };
        let mut m = TrackManager::new(p);
        m.set_ownship(own());
        // 1: near (1 km north), heard at 0; 2: far (30 km north), heard at 0.5 s.
        m.update(0, &report(1, 47.0 + 1.0 / 111.2, 8.0));
        m.update(S / 2, &report(2, 47.0 + 30.0 / 111.2, 8.0));
        m.update(t_new, &report(3, 47.0 + 2.0 / 111.2, 8.0));
        let key = |address| TargetKey {
            space: AddressSpace::Icao,
            address,
        };
        assert!(m.track(&key(gone)).is_none(), "at {t_new} ns: {gone} kept");
        assert_eq!(m.len(), 2);
        assert_eq!(m.stats().tracks_evicted, 1);
    }
}

/// Well clear now, in the picture at `t_ns`, against a target reported at 0 straight above or
/// below the ownship `own`.
fn violated_now(
    own: &Ownship,
    r: &TrafficReport,
    t_ns: i64,
) -> (AltitudeKind, Option<f64>, bool, bool) {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(0, r);
    let x = &m.picture(t_ns, own)[0];
    let g = x.geometry.expect("a geometry");
    (
        x.altitude_kind,
        g.vertical_separation_m,
        g.well_clear_violated_now,
        x.fail_safe.altitude_reference_mixed,
    )
}

/// Mixed altitude references (no measured GNSS-baro difference): the separation is taken at
/// face value with a band of 250 m + 10 % of the geometric height (+ the ownship's own
/// geometric band), and well clear (DWC ZTHR 450 ft = 137.16 m) is held as violated while some
/// separation in the band is within ZTHR. Worked by hand, target straight overhead:
/// - intruder pressure altitude only, ownship geometric only (1050 m, band 10 m): band
///   250 + 105 + 10 = 365 m, so violated up to 137.16 + 365 = 502.16 m: 500 m is, 505 m is not;
/// - intruder geometric altitude a only, ownship pressure only (1000 m): band 250 + 0.1 a,
///   violated while (a - 1000) - (250 + 0.1 a) <= 137.16, i.e. a <= 1541.29 m: 1540 m is,
///   1543 m is not.
#[test]
fn mixed_altitude_references_get_the_documented_band() {
    let overhead = report(1, 47.0, 8.0);
    let own_geo = Ownship {
        alt_pressure_m: None,
        alt_geometric_m: Some(1050.0),
        alt_geometric_band_m: 10.0,
        ..own()
    };
    for (dz, violated) in [(500.0, true), (505.0, false)] {
        let r = TrafficReport {
            alt_pressure_m: Some(1050.0 + dz),
            alt_geometric_m: None,
            ..overhead.clone()
        };
        let (kind, sep, v, mixed) = violated_now(&own_geo, &r, 0);
        assert_eq!(kind, AltitudeKind::Mixed);
        assert!(mixed);
        assert!((sep.unwrap() - dz).abs() < 1e-9, "{sep:?}");
        assert_eq!(v, violated, "{dz} m above");
    }
    let own_baro = Ownship {
        alt_pressure_m: Some(1000.0),
        alt_geometric_m: None,
        ..own()
    };
    for (a, violated) in [(1540.0, true), (1543.0, false)] {
        let r = TrafficReport {
            alt_pressure_m: None,
            alt_geometric_m: Some(a),
            ..overhead.clone()
        };
        let (kind, sep, v, mixed) = violated_now(&own_baro, &r, 0);
        assert_eq!(kind, AltitudeKind::Mixed);
        assert!(mixed);
        assert!((sep.unwrap() - (a - 1000.0)).abs() < 1e-9, "{sep:?}");
        assert_eq!(v, violated, "intruder at {a} m");
    }
}

/// An intruder's altitude not moved on (vertical rate unknown) may have changed since its report
/// by what its category can climb: a light aircraft (category 1, 2000 ft/min = 10.16 m/s)
/// reported 2 s before the picture is within a band of 20.32 m, so well clear (ZTHR 137.16 m)
/// is held violated up to 157.48 m of reported separation: 157 m is, 158 m is not.
#[test]
fn an_unknown_vertical_rate_widens_the_band_with_the_reports_age() {
    for (dz, violated) in [(157.0, true), (158.0, false)] {
        let r = TrafficReport {
            alt_pressure_m: Some(1000.0 + dz),
            vertical_rate_mps: None,
            emitter_category: Some(1),
            ..report(1, 47.0, 8.0)
        };
        let (kind, sep, v, _) = violated_now(&own(), &r, 2 * S);
        assert_eq!(kind, AltitudeKind::Pressure);
        assert!((sep.unwrap() - dz).abs() < 1e-9, "{sep:?}");
        assert_eq!(v, violated, "{dz} m above");
    }
}

/// A target of unknown velocity, seen 2 s ago: its position sigma is the report's (NACp 9:
/// 12.256 m), plus 0.5 m/s^2 t^2 of unknown acceleration (2 m), plus the distance its category
/// may have flown (light aircraft, 250 kt = 128.611 m/s, for 2 s: 257.222 m): 271.478 m, by
/// hand. Each source is listed with its age, 2 s.
#[test]
fn an_unknown_velocity_widens_the_position_sigma_by_the_distance_flown() {
    let mut m = TrackManager::new(TrafficParams::default());
    // Timed by its source (an arrival time would add half a second of flight at the fallback
    // speed, as `an_arrival_timed_report_widens_its_position_sigma` shows).
    m.update_at(
        0,
        &TrafficReport {
            track_deg: None,
            ground_speed_mps: None,
            emitter_category: Some(1),
            ..report(1, 47.1, 8.0)
        },
        false,
    );
    let x = &m.picture(2 * S, &own())[0];
    assert!(x.velocity_ne_mps.is_none());
    assert!(
        (x.position_sigma_m - 271.478).abs() < 1e-3,
        "{}",
        x.position_sigma_m
    );
    assert_eq!(x.sources.len(), 1);
    assert!((x.sources[0].1 - 2.0).abs() < 1e-9, "{:?}", x.sources);
}

/// A 1090 ADS-B position is stale only when older than its 5 s limit, strictly: at exactly 5 s
/// the target still has a geometry; 1 ns later it has none and is flagged stale.
#[test]
fn a_position_is_stale_strictly_after_its_links_limit() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(0, &report(1, 47.1, 8.0));
    let x = &m.picture(5 * S, &own())[0];
    assert!(!x.fail_safe.stale && x.geometry.is_some());
    let x = &m.picture(5 * S + 1, &own())[0];
    assert!(x.fail_safe.stale && x.geometry.is_none());
}

/// Each link has its own staleness limit: with limits of 5 s (1090), 4 s (UAT) and 3 s (FLARM),
/// positions 4.5 s old are fresh from 1090 only, and 3.5 s old from FLARM are stale.
#[test]
fn each_link_has_its_own_staleness_limit() {
    let p = TrafficParams {
        stale_limit_s: [5.0, 4.0, 3.0],
        ..TrafficParams::default()
    };
    let cases = [
        (Link::Adsb1090, AddressType::Icao, 4_500, false),
        (Link::Uat978, AddressType::Icao, 4_500, true),
        (Link::Flarm, AddressType::FlarmRandom, 3_500, true),
        (Link::Flarm, AddressType::FlarmRandom, 2_500, false),
    ];
    for (link, address_type, age_ms, stale) in cases {
        let mut m = TrackManager::new(p);
        m.update(
            0,
            &TrafficReport {
                link,
                address_type,
                ..report(1, 47.1, 8.0)
            },
        );
        let x = &m.picture(age_ms * 1_000_000, &own())[0];
        assert_eq!(x.fail_safe.stale, stale, "{link:?} after {age_ms} ms");
    }
}

/// Degrees of latitude for `d_m` metres north at 47.0-47.1 deg: the WGS-84 meridian radius
/// there, M = a (1 - e^2) / (1 - e^2 sin^2 lat)^1.5 = 6 369 620 m at 47.0 and 6 369 732 m at
/// 47.1 (worked by hand); over a kilometre the arc and the tangent-plane distance differ by
/// micrometres.
fn north_deg(d_m: f64, m_radius: f64) -> f64 {
    (d_m / m_radius).to_degrees()
}

/// Each plausibility test flags only beyond its limit, checked just inside and just outside:
/// - speed: 350 m/s (`max_speed_mps`) is possible, 350.01 is not;
/// - position jump: from NACp 9 (sigma 12.256 m) to NACp 10 (4.085 m) in 2 s, the allowed
///   distance is 350 * 2 + 5 * sqrt(12.256^2 + 4.085^2) = 764.60 m: 763.6 m is not a jump,
///   765.6 m is;
/// - range against signal: at 1000 m the free-space loss at 1090 MHz is 93.196 dB, so 57 dBm
///   EIRP arrives at -36.196 dBm, and with the 10 dB margin a signal above -26.196 dBm is too
///   strong: -26.25 is not, -26.15 is.
#[test]
fn plausibility_limits_flag_just_outside_and_not_just_inside() {
    let speed = |v: f64| {
        let mut m = TrackManager::new(TrafficParams::default());
        m.update(
            0,
            &TrafficReport {
                ground_speed_mps: Some(v),
                ..report(1, 47.1, 8.0)
            },
        );
        m.picture(0, &own())[0].flags.impossible_speed
    };
    assert!(!speed(350.0));
    assert!(speed(350.01));

    let jump = |d_m: f64| {
        // Both timed by their source, so that their sigmas are the NACp's alone.
        let mut m = TrackManager::new(TrafficParams::default());
        m.update_at(0, &report(1, 47.1, 8.0), false);
        let r = TrafficReport {
            nac_p: Some(10),
            ..report(1, 47.1 + north_deg(d_m, 6_369_732.0), 8.0)
        };
        m.update_at(2 * S, &r, false);
        m.picture(2 * S, &own())[0].flags.position_jump
    };
    assert!(!jump(763.6));
    assert!(jump(765.6));

    let strong = |dbm: f64| {
        let mut m = TrackManager::new(TrafficParams::default());
        m.set_ownship(own());
        let r = TrafficReport {
            signal_dbm: Some(dbm),
            ..report(1, 47.0 + north_deg(1000.0, 6_369_620.0), 8.0)
        };
        m.update(0, &r);
        m.picture(0, &own())[0].flags.range_vs_signal
    };
    assert!(!strong(-26.25));
    assert!(strong(-26.15));
}

/// The comparisons are strict: a value exactly at its limit is allowed. With no tolerance at
/// all (no speed, no sigmas), the same position again is no jump; a signal exactly at the
/// limit the track manager computes is not too strong.
#[test]
fn plausibility_limits_are_strict() {
    let p = TrafficParams {
        max_speed_mps: 0.0,
        consistency_sigmas: 0.0,
        ..TrafficParams::default()
    };
    let mut m = TrackManager::new(p);
    m.update(0, &report(1, 47.1, 8.0));
    m.update(S, &report(1, 47.1, 8.0));
    assert!(!m.picture(S, &own())[0].flags.position_jump);

    let (lat, lon) = (47.0 + north_deg(1000.0, 6_369_620.0), 8.0);
    let own = own();
    let limit = crate::traffic::plausibility::max_signal_dbm(
        57.0,
        crate::traffic::plausibility::horizontal_distance_m(own.lat_deg, own.lon_deg, lat, lon),
    ) + 10.0;
    let mut m = TrackManager::new(TrafficParams::default());
    m.set_ownship(own);
    m.update(
        0,
        &TrafficReport {
            signal_dbm: Some(limit),
            ..report(1, lat, lon)
        },
    );
    assert!(!m.picture(0, &own)[0].flags.range_vs_signal);
}

/// Reports arrive out of order across sources: an older position is tested but never replaces
/// a newer one. The track keeps the one of 2 s; the one of 1 s (11 km north) is left out.
#[test]
fn an_older_position_does_not_replace_a_newer_one() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update(2 * S, &report(1, 47.1, 8.0));
    m.update(S, &report(1, 47.2, 8.0));
    let x = &m.picture(2 * S, &own())[0];
    assert!((x.lat_deg - 47.1).abs() < 1e-12, "{}", x.lat_deg);
}

/// An altitude jump is a change beyond `max_vertical_rate_mps` (60 m/s) over the time since the
/// track's altitude, plus 50 m: in 2 s, 170 m. 170 m exactly and 169 m are not jumps; 171 m is.
#[test]
fn an_altitude_jump_is_beyond_the_climb_rate_plus_50_m_strictly() {
    let jump = |dz: f64| {
        let mut m = TrackManager::new(TrafficParams::default());
        m.update_at(0, &report(1, 47.1, 8.0), false);
        let r = TrafficReport {
            alt_pressure_m: Some(1000.0 + dz),
            ..report(1, 47.1, 8.0)
        };
        m.update_at(2 * S, &r, false);
        m.picture(2 * S, &own())[0].flags.altitude_jump
    };
    assert!(!jump(169.0));
    assert!(!jump(170.0));
    assert!(jump(171.0));
    assert!(!jump(-170.0));
    assert!(jump(-171.0));
}

/// Velocity, vertical rate and a source's latest report are taken only from a report at least
/// as new as the one held: an older report (here 1 s behind, heading south and descending)
/// changes none of them.
#[test]
fn an_older_report_leaves_the_velocity_rate_and_source_age_alone() {
    let mut m = TrackManager::new(TrafficParams::default());
    m.update_at(
        2 * S,
        &TrafficReport {
            track_deg: Some(90.0),
            vertical_rate_mps: Some(3.0),
            ..report(1, 47.1, 8.0)
        },
        false,
    );
    m.update_at(
        S,
        &TrafficReport {
            vertical_rate_mps: Some(-4.0),
            ..report(1, 47.1, 8.0)
        },
        false,
    );
    let x = &m.picture(2 * S, &own())[0];
    let v = x.velocity_ne_mps.unwrap();
    assert!(v[0].abs() < 1e-9 && (v[1] - 51.444).abs() < 1e-3, "{v:?}");
    assert_eq!(x.vertical_rate_mps, Some(3.0));
    assert_eq!(x.sources.len(), 1);
    assert_eq!(
        x.sources[0].1, 0.0,
        "the source's report of 2 s is the one kept"
    );
}

/// Position against velocity (issue 24): a target flying east at 50 m/s, reported at 0 and 4 s,
/// is predicted 200 m east; its second position is also D north. With NACp 9 on both (12.256 m)
/// the allowed residual is 5 * sqrt(2) * 12.256 + 2 m/s * 4 s = 94.66 m: D = 93.7 m is not a
/// drift, 95.7 m is.
#[test]
fn drift_is_a_residual_beyond_the_sigmas_and_the_velocity_allowance() {
    let drift = |d_m: f64| {
        let mut m = TrackManager::new(TrafficParams::default());
        let east = |lat: f64, lon: f64| TrafficReport {
            track_deg: Some(90.0),
            ground_speed_mps: Some(50.0),
            ..report(1, lat, lon)
        };
        m.update_at(0, &east(47.1, 8.0), false);
        // 200 m east on the parallel of radius N cos(lat) = 6 389 624.15 m * cos(47.1 deg).
        let dlon = (200.0 / (6_389_624.15 * 47.1f64.to_radians().cos())).to_degrees();
        let r = east(47.1 + north_deg(d_m, 6_369_732.0), 8.0 + dlon);
        m.update_at(4 * S, &r, false);
        m.picture(4 * S, &own())[0].flags.position_drift
    };
    assert!(!drift(93.7));
    assert!(drift(95.7));

    // Strict: with no allowance at all, a stationary target at the same place is no drift.
    let p = TrafficParams {
        consistency_sigmas: 0.0,
        drift_velocity_error_mps: 0.0,
        ..TrafficParams::default()
    };
    let mut m = TrackManager::new(p);
    let still = TrafficReport {
        ground_speed_mps: Some(0.0),
        ..report(1, 47.1, 8.0)
    };
    m.update_at(0, &still, false);
    m.update_at(4 * S, &still, false);
    assert!(!m.picture(4 * S, &own())[0].flags.position_drift);
}

/// A stationary target (velocity 0), `d_north_m` north of 47.1 N.
fn still_at(d_north_m: f64) -> TrafficReport {
    TrafficReport {
        ground_speed_mps: Some(0.0),
        ..report(1, 47.1 + north_deg(d_north_m, 6_369_732.0), 8.0)
    }
}

fn drift_after(p: TrafficParams, reports: &[(i64, TrafficReport)]) -> bool {
    let mut m = TrackManager::new(p);
    for (t_ms, r) in reports {
        m.update_at(t_ms * 1_000_000, r, false);
    }
    let t_last = reports.last().unwrap().0 * 1_000_000;
    m.picture(t_last, &own())[0].flags.position_drift
}

/// The drift window's edges (window 9 s, so a third is 3 s exactly; NACp 9 everywhere, so
/// 5 sigmas of two reports are 86.66 m, and the velocity allowance is 2 m/s of the span):
/// - a window is judged from exactly a third of its length: a 100 m residual over 3 s (allowed
///   92.66 m) is a drift;
/// - a report exactly one window older than the newest stays the base: reports at 0, 3 and 9 s,
///   100 m off at 9 s, are judged over 9 s (allowed 104.66 m: no drift), not over 6 s
///   (98.66 m);
/// - a report without velocity breaks the chain: 150 m off at 5 s after a break at 2 s is no
///   drift (the window restarts), although it would be over 0..5 s (allowed 96.66 m).
#[test]
fn drift_window_edges() {
    let p = TrafficParams {
        drift_window_s: 9.0,
        ..TrafficParams::default()
    };
    assert!(drift_after(
        p,
        &[(0, still_at(0.0)), (3_000, still_at(100.0))]
    ));
    assert!(!drift_after(
        p,
        &[
            (0, still_at(0.0)),
            (3_000, still_at(0.0)),
            (9_000, still_at(100.0))
        ]
    ));
    let no_velocity = TrafficReport {
        track_deg: None,
        ground_speed_mps: None,
        ..still_at(0.0)
    };
    assert!(!drift_after(
        TrafficParams::default(),
        &[
            (0, still_at(0.0)),
            (2_000, no_velocity),
            (5_000, still_at(150.0))
        ]
    ));
    assert!(drift_after(
        TrafficParams::default(),
        &[(0, still_at(0.0)), (5_000, still_at(150.0))]
    ));
}

/// A FLARM position without NACp or NIC is taken at 10 m (the other aircraft's own GNSS); any
/// other link's at 100 m.
#[test]
fn a_flarm_position_without_accuracy_is_taken_at_10_m() {
    for (link, address_type, sigma) in [
        (Link::Flarm, AddressType::FlarmRandom, 10.0),
        (Link::Adsb1090, AddressType::Icao, 100.0),
    ] {
        let mut m = TrackManager::new(TrafficParams::default());
        let r = TrafficReport {
            link,
            address_type,
            nac_p: None,
            nic: None,
            ..report(1, 47.1, 8.0)
        };
        m.update_at(0, &r, false);
        assert_eq!(m.picture(0, &own())[0].position_sigma_m, sigma, "{link:?}");
    }
}
