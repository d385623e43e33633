//! Encounter tests from hand computation of the DO-365 definitions, and a check of the closed-form
//! intervals against a brute-force scan of the volume's definition.

use approx::assert_relative_eq;
use nalgebra::Vector2;

use super::daa::{LOOKAHEAD_S, Thresholds};
use super::*;
use crate::units::{M_PER_FT, M_PER_NM, MPS_PER_FPM, MPS_PER_KT};

const D: f64 = 0.66 * M_PER_NM; // 1222.32 m
const KT100: f64 = 100.0 * MPS_PER_KT; // 51.4444 m/s

fn rel(sx: f64, sy: f64, vx: f64, vy: f64, dz: f64, vz: f64) -> Relative {
    Relative {
        s: Vector2::new(sx, sy),
        v: Vector2::new(vx, vy),
        dz_m: dz,
        vz_mps: vz,
        vz_spread_mps: 0.0,
        dz_spread_m: 0.0,
    }
}

/// Independent check: scan the definition of the volume every 5 ms over the lookahead and return
/// the first interval found.
fn scan_first_interval(r: &Relative, th: &Thresholds) -> Option<(f64, f64)> {
    let step = 0.005;
    let mut start = None;
    let n = (LOOKAHEAD_S / step) as usize;
    for i in 0..=n {
        let t = i as f64 * step;
        let v = r.at(t).violates(th);
        match (start, v) {
            (None, true) => start = Some(t),
            (Some(s), false) => return Some((s, t - step)),
            _ => {}
        }
    }
    start.map(|s| (s, LOOKAHEAD_S))
}

fn assert_interval_matches_scan(r: &Relative) {
    let closed = r.violation_intervals(&Thresholds::DWC, LOOKAHEAD_S).first();
    let scanned = scan_first_interval(r, &Thresholds::DWC);
    match (closed, scanned) {
        (Some(c), Some(s)) => {
            assert!(
                (c.0 - s.0).abs() < 0.011 && (c.1 - s.1).abs() < 0.011,
                "{c:?} vs {s:?}"
            )
        }
        (c, s) => assert_eq!(c.is_some(), s.is_some(), "{c:?} vs {s:?}"),
    }
}

#[test]
fn dthr_is_4010_ft() {
    assert_relative_eq!(Thresholds::DWC.dthr_m, 1222.32, epsilon = 1e-9);
    assert!((Thresholds::DWC.dthr_m / M_PER_FT - 4010.2).abs() < 0.1);
}

#[test]
fn head_on() {
    // Ownship north at 100 kt, intruder 5 NM ahead southbound at 100 kt, co-altitude.
    let r = rel(0.0, 5.0 * M_PER_NM, 0.0, -2.0 * KT100, 0.0, 0.0);
    let g = r.geometry();
    let v = 2.0 * KT100; // 102.889 m/s closing
    let s0 = 5.0 * M_PER_NM; // 9260 m
    assert_relative_eq!(g.horizontal_distance_m, 9260.0);
    assert_relative_eq!(g.range_rate_mps.unwrap(), -v, epsilon = 1e-9);
    assert_relative_eq!(g.tcpa_s.unwrap(), s0 / v, epsilon = 1e-9); // 90.0 s
    assert_relative_eq!(g.tcpa_s.unwrap(), 90.0, epsilon = 1e-9);
    assert_relative_eq!(g.hmd_m.unwrap(), 0.0, epsilon = 1e-9);
    // tau_mod = (D^2 - r^2) / (s.v) = (1222.32^2 - 9260^2) / (9260 x -102.889) = 88.431 s.
    let tau = (D * D - s0 * s0) / (s0 * -v);
    assert_relative_eq!(g.tau_mod_s.unwrap(), tau, epsilon = 1e-9);
    assert!((tau - 88.431).abs() < 0.001);
    // Loss of well-clear starts when tau_mod = 35 s: r^2 - 35 v r - D^2 = 0,
    // r = (35 v + sqrt((35 v)^2 + 4 D^2)) / 2 = 3976.8 m, t = (9260 - r) / v = 51.35 s; it ends when
    // the range opens past DTHR again: t = (9260 + D) / v = 101.88 s.
    let r_start = (35.0 * v + ((35.0 * v).powi(2) + 4.0 * D * D).sqrt()) / 2.0;
    let (a, b) = g.loss_of_well_clear_interval_s.unwrap();
    assert_relative_eq!(a, (s0 - r_start) / v, epsilon = 1e-9);
    assert!((a - 51.35).abs() < 0.01, "{a}");
    assert_relative_eq!(b, (s0 + D) / v, epsilon = 1e-9);
    assert!(!g.well_clear_violated_now);
    // 51.35 s <= 55 s: corrective (2), not yet warning (3).
    assert_eq!(g.alert_level, 2);
    assert_eq!(r.at(30.0).alert_level(), 3);
    assert_interval_matches_scan(&r);
}

#[test]
fn offset_head_on_beyond_dthr_is_clear() {
    // Lateral offset 0.7 NM > DTHR: HMD = 1296.4 m, never inside; tau is still defined.
    let r = rel(0.7 * M_PER_NM, 5.0 * M_PER_NM, 0.0, -2.0 * KT100, 0.0, 0.0);
    let g = r.geometry();
    assert_relative_eq!(g.hmd_m.unwrap(), 0.7 * M_PER_NM, epsilon = 1e-6);
    assert!(g.tau_mod_s.is_some());
    assert_eq!(g.loss_of_well_clear_interval_s, None);
    // The 700 ft preventive volume uses the same DTHR, so no alert at all.
    assert_eq!(g.alert_level, 0);
    // Offset 0.5 NM: HMD 926 m < DTHR; entered through the tau clause.
    let r = rel(0.5 * M_PER_NM, 5.0 * M_PER_NM, 0.0, -2.0 * KT100, 0.0, 0.0);
    assert!(r.geometry().loss_of_well_clear_interval_s.is_some());
    assert_interval_matches_scan(&r);
}

#[test]
fn overtaking() {
    // Intruder 1 NM behind, same track, 40 kt faster: closing at 20.58 m/s.
    let closing = 40.0 * MPS_PER_KT;
    let r = rel(0.0, -M_PER_NM, 0.0, closing, 0.0, 0.0);
    let g = r.geometry();
    assert_relative_eq!(g.tcpa_s.unwrap(), M_PER_NM / closing, epsilon = 1e-9); // 90 s
    // Range reaches DTHR at (1852 - 1222.32) / 20.578 = 30.6 s; the tau clause starts earlier:
    // r^2 - 35 c r - D^2 = 0 gives r = 1688.3 m, t = 7.97 s.
    let r_start = (35.0 * closing + ((35.0 * closing).powi(2) + 4.0 * D * D).sqrt()) / 2.0;
    let (a, _) = g.loss_of_well_clear_interval_s.unwrap();
    assert_relative_eq!(a, (M_PER_NM - r_start) / closing, epsilon = 1e-9);
    assert_eq!(g.alert_level, 3);
    assert_interval_matches_scan(&r);
}

#[test]
fn crossing() {
    // Ownship north at 100 kt from the origin; intruder 3 NM east of the crossing point, flying
    // west at 100 kt, starting 3 NM east and 3 NM north: both reach (0, 3 NM) together.
    let s = Vector2::new(3.0 * M_PER_NM, 3.0 * M_PER_NM);
    let r = rel(s.x, s.y, -KT100, -KT100, 0.0, 0.0);
    let g = r.geometry();
    // Relative velocity (-v, -v) aims straight at the ownship: tcpa = |s| / |v_rel| = 3 NM / v.
    assert_relative_eq!(g.tcpa_s.unwrap(), 3.0 * M_PER_NM / KT100, epsilon = 1e-9);
    assert_relative_eq!(g.hmd_m.unwrap(), 0.0, epsilon = 1e-6);
    assert_relative_eq!(
        g.horizontal_distance_m,
        3.0 * M_PER_NM * 2f64.sqrt(),
        epsilon = 1e-9
    );
    assert_interval_matches_scan(&r);
}

#[test]
fn climb_into_an_intruder() {
    // Intruder 1000 ft above and 2 NM ahead (head-on 200 kt closure); the ownship climbs at
    // 1500 ft/min. Vertical separation reaches 450 ft at (1000 - 450) / 1500 min = 22 s.
    let vz = -1500.0 * MPS_PER_FPM;
    let r = rel(
        0.0,
        2.0 * M_PER_NM,
        0.0,
        -2.0 * KT100,
        1000.0 * M_PER_FT,
        vz,
    );
    let g = r.geometry();
    let (a, _) = g.loss_of_well_clear_interval_s.unwrap();
    assert_relative_eq!(a, 550.0 * M_PER_FT / (1500.0 * MPS_PER_FPM), epsilon = 1e-9);
    assert_relative_eq!(a, 22.0, epsilon = 1e-9);
    assert!(!g.well_clear_violated_now);
    assert_eq!(g.alert_level, 3);
    assert_interval_matches_scan(&r);
}

#[test]
fn diverging() {
    let r = rel(0.0, 2.0 * M_PER_NM, 0.0, KT100, 0.0, 0.0);
    let g = r.geometry();
    assert_eq!(g.tcpa_s.unwrap(), 0.0);
    assert_eq!(g.tau_mod_s, None);
    assert_relative_eq!(g.hmd_m.unwrap(), 2.0 * M_PER_NM);
    assert!(g.range_rate_mps.unwrap() > 0.0);
    assert_eq!(g.loss_of_well_clear_interval_s, None);
    assert_eq!(g.alert_level, 0);
}

#[test]
fn parallel_co_altitude_inside_dthr() {
    // Side by side 0.5 NM apart at the same speed: inside DTHR now and for the whole lookahead;
    // tau is undefined (not closing, and inside DMOD).
    let r = rel(0.5 * M_PER_NM, 0.0, 0.0, 0.0, 100.0 * M_PER_FT, 0.0);
    let g = r.geometry();
    assert!(g.well_clear_violated_now);
    assert_eq!(g.tau_mod_s, None);
    assert_eq!(g.loss_of_well_clear_interval_s, Some((0.0, LOOKAHEAD_S)));
    assert_eq!(g.alert_level, 3);
    // 600 ft apart vertically: outside DWC (450 ft) but inside the preventive 700 ft volume.
    let r = rel(0.5 * M_PER_NM, 0.0, 0.0, 0.0, 600.0 * M_PER_FT, 0.0);
    assert!(!r.geometry().well_clear_violated_now);
    assert_eq!(r.alert_level(), 1);
}

#[test]
fn hovering_ownship() {
    // A hovering ownship and an intruder approaching at 60 kt from 2 NM, 200 ft above.
    let own = AircraftState {
        lat_deg: 47.0,
        lon_deg: 8.0,
        alt_m: 500.0,
        track_deg: 0.0,
        ground_speed_mps: 0.0,
        vertical_rate_mps: 0.0,
    };
    // 2 NM due north along the meridian (1' of latitude is about 1852 m at 47 deg: 1852.4 m).
    let intruder = AircraftState {
        lat_deg: 47.0 + 2.0 / 60.0,
        track_deg: 180.0,
        ground_speed_mps: 60.0 * MPS_PER_KT,
        alt_m: 500.0 + 200.0 * M_PER_FT,
        ..own
    };
    let g = relative(&own, &intruder).geometry();
    assert!(
        (g.horizontal_distance_m - 2.0 * 1852.4).abs() < 2.0,
        "{}",
        g.horizontal_distance_m
    );
    assert!((g.range_rate_mps.unwrap() + 60.0 * MPS_PER_KT).abs() < 1e-3);
    assert!(g.hmd_m.unwrap() < 1.0);
    assert_relative_eq!(
        g.vertical_separation_m.unwrap(),
        200.0 * M_PER_FT,
        epsilon = 1e-9
    );
}

#[test]
fn high_latitude_norths() {
    // 65 deg N, intruder 15 NM east, flying "north" in its own frame at 150 kt, ownship still.
    // In the ownship's plane its track is about -0.5 deg (meridian convergence), so over 600 s it
    // drifts 0.5 deg x 600 x 77 m/s = 400 m west, not 0: the miss distance is 15 NM minus that.
    let own = AircraftState {
        lat_deg: 65.0,
        lon_deg: 10.0,
        alt_m: 1000.0,
        track_deg: 0.0,
        ground_speed_mps: 0.0,
        vertical_rate_mps: 0.0,
    };
    let n = wgs84::A_M / (1.0 - wgs84::E2 * 65f64.to_radians().sin().powi(2)).sqrt();
    let dlon = (15.0 * M_PER_NM / (n * 65f64.to_radians().cos())).to_degrees();
    let intruder = AircraftState {
        lon_deg: 10.0 + dlon,
        ground_speed_mps: 150.0 * MPS_PER_KT,
        ..own
    };
    let r = relative(&own, &intruder);
    let seen_track = r.v.x.atan2(r.v.y).to_degrees();
    assert!(
        (seen_track + dlon * 65f64.to_radians().sin()).abs() < 0.01,
        "{seen_track}"
    );
    // Closing in the ownship's frame (the intruder's north leans toward us), so a CPA exists.
    assert!(r.tcpa_s() > 0.0);
}

#[test]
fn date_line() {
    // Ownship at 179.99 E heading east, intruder at 179.99 W heading west: 0.02 deg of longitude
    // apart at the equator = 0.02 x pi/180 x 6 378 137 m = 2226.4 m, closing at 200 kt.
    let own = AircraftState {
        lat_deg: 0.0,
        lon_deg: 179.99,
        alt_m: 3000.0,
        track_deg: 90.0,
        ground_speed_mps: KT100,
        vertical_rate_mps: 0.0,
    };
    let intruder = AircraftState {
        lon_deg: -179.99,
        track_deg: 270.0,
        ..own
    };
    let g = relative(&own, &intruder).geometry();
    let expected = 0.02f64.to_radians() * (wgs84::A_M + 3000.0);
    assert!(
        (g.horizontal_distance_m - expected).abs() < 0.01,
        "{}",
        g.horizontal_distance_m
    );
    // The two easts differ by 0.02 deg about the polar axis: cos(0.02 deg) = 1 - 6e-8.
    assert!((g.range_rate_mps.unwrap() + 2.0 * KT100).abs() < 1e-4);
    // 2226 m > DTHR, but closing head-on with tau_mod = (D^2 - r^2) / (-r v) = 15.1 s <= 35 s
    // and HMD 0: inside the DWC volume now.
    let tau = (D * D - expected * expected) / (-expected * 2.0 * KT100);
    assert!((g.tau_mod_s.unwrap() - tau).abs() < 1e-3 && (tau - 15.1).abs() < 0.1);
    assert!(g.well_clear_violated_now);
    assert_eq!(g.alert_level, 3);
}

#[test]
fn closed_form_matches_a_scan_over_many_encounters() {
    // Deterministic spread of encounters: the closed form and the scanned definition agree.
    let mut x = 12345u64;
    let mut next = || {
        x = x
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..200 {
        let r = rel(
            (next() - 0.5) * 20_000.0,
            (next() - 0.5) * 20_000.0,
            (next() - 0.5) * 300.0,
            (next() - 0.5) * 300.0,
            (next() - 0.5) * 600.0,
            (next() - 0.5) * 20.0,
        );
        assert_interval_matches_scan(&r);
    }
}

/// The relative state is the intruder's less the ownship's, on every axis: the ownship flying
/// north at 50 m/s and climbing 3 m/s, an intruder 200 m straight above flying east at 40 m/s
/// and descending 2 m/s: relative velocity (40, -50) m/s east/north, 200 m above, closing
/// vertically at -5 m/s (by hand; both at the same point, so no rotation between their norths).
#[test]
fn relative_state_is_the_intruder_less_the_ownship() {
    let own = AircraftState {
        lat_deg: 47.0,
        lon_deg: 8.0,
        alt_m: 1000.0,
        track_deg: 0.0,
        ground_speed_mps: 50.0,
        vertical_rate_mps: 3.0,
    };
    let intruder = AircraftState {
        alt_m: 1200.0,
        track_deg: 90.0,
        ground_speed_mps: 40.0,
        vertical_rate_mps: -2.0,
        ..own
    };
    let r = relative(&own, &intruder);
    assert!(r.s.norm() < 1e-6, "{:?}", r.s);
    assert!((r.v - Vector2::new(40.0, -50.0)).norm() < 1e-9, "{:?}", r.v);
    assert_relative_eq!(r.dz_m, 200.0, epsilon = 1e-9);
    assert_relative_eq!(r.vz_mps, -5.0, epsilon = 1e-12);
}
