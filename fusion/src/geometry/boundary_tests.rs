//! Issue 23 point 2: every DO-365 alert threshold tested exactly at, just inside and just outside,
//! in the horizontal and the vertical dimension, against numbers written here from the standard
//! (not read from `Thresholds`): DTHR 0.66 NM = 1222.32 m (1 NM = 1852 m), ZTHR 450 ft =
//! 137.16 m for DWC and 700 ft = 213.36 m for the preventive volume (1 ft = 0.3048 m), TTHR 35 s,
//! alerting times 25 s (warning) and 55 s (corrective, preventive). Each test names the threshold
//! it pins, so a changed constant or a flipped comparison fails a test that says which.
//!
//! "Just inside / outside" is 1 cm (or 1 ms in time), far above f64 rounding at these sizes and
//! far below any distance that matters.

use nalgebra::Vector2;

use super::daa::{Relative, Thresholds};

/// DTHR, m.
const DTHR: f64 = 1222.32;
/// DWC ZTHR, m.
const ZTHR_DWC: f64 = 137.16;
/// Preventive ZTHR, m.
const ZTHR_PREVENTIVE: f64 = 213.36;
/// TTHR, s.
const TTHR: f64 = 35.0;
/// A small step across a boundary, m.
const EPS: f64 = 0.01;

fn rel(sx: f64, sy: f64, vx: f64, vy: f64, dz: f64, vz: f64) -> Relative {
    Relative {
        s: Vector2::new(sx, sy),
        v: Vector2::new(vx, vy),
        dz_m: dz,
        dz_spread_m: 0.0,
        vz_mps: vz,
        vz_spread_mps: 0.0,
    }
}

/// Level and "violated now" of a state.
fn level(r: &Relative) -> (u8, bool) {
    let g = r.geometry();
    assert_eq!(g.alert_level, r.alert_level(), "the two paths agree");
    (g.alert_level, g.well_clear_violated_now)
}

#[test]
fn the_constants_are_the_standards() {
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
    assert!(close(Thresholds::DWC.dthr_m, DTHR));
    assert!(close(Thresholds::DWC.zthr_m, ZTHR_DWC));
    assert!(close(Thresholds::DWC.tthr_s, TTHR));
    assert!(close(Thresholds::PREVENTIVE.dthr_m, DTHR));
    assert!(close(Thresholds::PREVENTIVE.zthr_m, ZTHR_PREVENTIVE));
    assert!(close(Thresholds::PREVENTIVE.tthr_s, TTHR));
}

/// DWC DTHR, horizontal, static (no relative motion, co-altitude): inside DTHR the volume holds
/// now (warning); outside it never does (no closure, so no tau clause).
#[test]
fn dwc_dthr_static() {
    for (r, want) in [
        (DTHR - EPS, (3, true)),
        (DTHR, (3, true)),
        (DTHR + EPS, (0, false)),
    ] {
        assert_eq!(level(&rel(r, 0.0, 0.0, 0.0, 0.0, 0.0)), want, "r = {r}");
        // The same along another bearing.
        let b = 0.7f64;
        assert_eq!(
            level(&rel(r * b.cos(), r * b.sin(), 0.0, 0.0, 0.0, 0.0)),
            want,
            "r = {r}, bearing {b} rad"
        );
    }
}

/// DWC ZTHR (450 ft), vertical, static and horizontally inside: within ZTHR a warning; just above
/// it the DWC volume does not hold but the preventive one (700 ft) does: a preventive alert.
/// Above and below the ownship alike.
#[test]
fn dwc_zthr_static() {
    for sign in [1.0, -1.0] {
        for (dz, want) in [
            (ZTHR_DWC - EPS, (3, true)),
            (ZTHR_DWC, (3, true)),
            (ZTHR_DWC + EPS, (1, false)),
        ] {
            let r = rel(500.0, 0.0, 0.0, 0.0, sign * dz, 0.0);
            assert_eq!(level(&r), want, "dz = {}", sign * dz);
        }
    }
}

/// Preventive ZTHR (700 ft): just inside a preventive alert, just outside none.
#[test]
fn preventive_zthr_static() {
    for sign in [1.0, -1.0] {
        for (dz, want) in [
            (ZTHR_PREVENTIVE - EPS, 1),
            (ZTHR_PREVENTIVE, 1),
            (ZTHR_PREVENTIVE + EPS, 0),
        ] {
            let r = rel(500.0, 0.0, 0.0, 0.0, sign * dz, 0.0);
            assert_eq!(level(&r).0, want, "dz = {}", sign * dz);
        }
    }
}

/// Preventive DTHR (0.66 NM, as DWC): at 600 ft separation (inside the preventive ZTHR only), a
/// static intruder just inside DTHR gives a preventive alert, just outside none.
#[test]
fn preventive_dthr_static() {
    let dz = 600.0 * 0.3048;
    assert_eq!(level(&rel(DTHR - EPS, 0.0, 0.0, 0.0, dz, 0.0)).0, 1);
    assert_eq!(level(&rel(DTHR + EPS, 0.0, 0.0, 0.0, dz, 0.0)).0, 0);
}

/// TTHR (35 s), horizontal: head-on (miss distance 0) at closing speed V, tau_mod =
/// (r^2 - DTHR^2) / (r V), so tau_mod = TTHR at r* = (TTHR V + sqrt((TTHR V)^2 + 4 DTHR^2)) / 2
/// (3884.61 m at 100 m/s). Closer than r* the volume holds now; farther it does not yet.
#[test]
fn tthr_head_on() {
    let v = 100.0;
    let tv = TTHR * v;
    let r_star = (tv + (tv * tv + 4.0 * DTHR * DTHR).sqrt()) / 2.0;
    assert!((r_star - 3884.61).abs() < 0.01, "{r_star}");
    let at = |r: f64| rel(r, 0.0, -v, 0.0, 0.0, 0.0);
    assert!(level(&at(r_star - EPS)).1, "inside TTHR: violated now");
    assert!(!level(&at(r_star + EPS)).1, "outside TTHR: not yet");
    // tau_mod itself, against the formula.
    let tau = at(r_star + 100.0).tau_mod_s(DTHR).unwrap();
    let r = r_star + 100.0;
    assert!((tau - (r * r - DTHR * DTHR) / (r * v)).abs() < 1e-9);
}

/// The horizontal miss distance against DTHR: a head-on with a lateral offset of DTHR - 1 cm
/// (tau_mod 30 s now, within TTHR) is a violation now; with DTHR + 1 cm the intruder never comes
/// within DTHR and the tau clause needs HMD <= DTHR: no alert ever.
#[test]
fn hmd_against_dthr() {
    let v = 100.0;
    let x = 3000.0;
    for (offset, want) in [(DTHR - EPS, (3, true)), (DTHR + EPS, (0, false))] {
        let r = rel(x, offset, -v, 0.0, 0.0, 0.0);
        assert!((r.hmd_m() - offset).abs() < 1e-6);
        assert_eq!(level(&r), want, "offset {offset}");
    }
}

/// Head-on at 100 m/s entering the DWC volume at time T (r0 = r* + 100 T): the warning time
/// (25 s) and the corrective time (55 s) each tested 1 ms either side. Co-altitude, so DWC.
#[test]
fn warning_and_corrective_times_horizontal() {
    let v = 100.0;
    let tv = TTHR * v;
    let r_star = (tv + (tv * tv + 4.0 * DTHR * DTHR).sqrt()) / 2.0;
    let entering_at = |t: f64, dz: f64| rel(r_star + v * t, 0.0, -v, 0.0, dz, 0.0);
    let dt = 0.001;
    assert_eq!(
        level(&entering_at(25.0 - dt, 0.0)).0,
        3,
        "warning: within 25 s"
    );
    assert_eq!(
        level(&entering_at(25.0 + dt, 0.0)).0,
        2,
        "corrective after 25 s"
    );
    assert_eq!(
        level(&entering_at(55.0 - dt, 0.0)).0,
        2,
        "corrective: within 55 s"
    );
    assert_eq!(level(&entering_at(55.0 + dt, 0.0)).0, 0, "none after 55 s");
    // 600 ft apart (preventive volume only): preventive within 55 s, none after.
    let dz = 600.0 * 0.3048;
    assert_eq!(
        level(&entering_at(20.0, dz)).0,
        1,
        "preventive, even when near"
    );
    assert_eq!(
        level(&entering_at(55.0 - dt, dz)).0,
        1,
        "preventive: within 55 s"
    );
    assert_eq!(level(&entering_at(55.0 + dt, dz)).0, 0, "none after 55 s");
    // The predicted interval starts when the hand computation says.
    let g = entering_at(40.0, 0.0).geometry();
    let (t0, _) = g.loss_of_well_clear_interval_s.unwrap();
    assert!((t0 - 40.0).abs() < 1e-6, "{t0}");
}

/// Vertical closure into a horizontally held volume: the intruder 500 m away, static
/// horizontally, descending at 10 m/s from dz0. It enters DWC ZTHR at (dz0 - 137.16) / 10 and
/// the preventive ZTHR at (dz0 - 213.36) / 10: both alerting times tested 1 ms either side.
#[test]
fn warning_and_corrective_times_vertical() {
    let vz = -10.0;
    let dt = 0.001;
    let entering_dwc_at = |t: f64| rel(500.0, 0.0, 0.0, 0.0, ZTHR_DWC - vz * t, vz);
    assert_eq!(level(&entering_dwc_at(25.0 - dt)).0, 3);
    assert_eq!(level(&entering_dwc_at(25.0 + dt)).0, 2);
    assert_eq!(level(&entering_dwc_at(55.0 - dt)).0, 2);
    // Entering DWC after 55 s, the preventive volume 7.62 s earlier: still within 55 s.
    assert_eq!(level(&entering_dwc_at(55.0 + dt)).0, 1);
    let entering_prev_at = |t: f64| rel(500.0, 0.0, 0.0, 0.0, ZTHR_PREVENTIVE - vz * t, vz);
    assert_eq!(level(&entering_prev_at(55.0 - dt)).0, 1);
    assert_eq!(level(&entering_prev_at(55.0 + dt)).0, 0);
    // Climbing from below behaves the same.
    let from_below = rel(500.0, 0.0, 0.0, 0.0, -(ZTHR_DWC + 10.0 * (25.0 - dt)), 10.0);
    assert_eq!(level(&from_below).0, 3);
    let from_below = rel(500.0, 0.0, 0.0, 0.0, -(ZTHR_DWC + 10.0 * (25.0 + dt)), 10.0);
    assert_eq!(level(&from_below).0, 2);
}

/// Modified tau is defined only while closing (s.v < 0) and outside DMOD (r > DMOD): `None`
/// for a perpendicular pass (s.v = 0, not closing), exactly at DMOD and inside it; outside and
/// closing it is (DMOD^2 - r^2) / (s.v). Found by mutation testing (issue 23): these bounds
/// were not pinned.
#[test]
fn tau_mod_is_undefined_unless_closing_from_outside_dmod() {
    let dmod = 1000.0;
    // Perpendicular: s.v = 0.
    assert_eq!(rel(2000.0, 0.0, 0.0, 10.0, 0.0, 0.0).tau_mod_s(dmod), None);
    // Exactly at DMOD and inside it, closing.
    assert_eq!(rel(1000.0, 0.0, -10.0, 0.0, 0.0, 0.0).tau_mod_s(dmod), None);
    assert_eq!(rel(500.0, 0.0, -10.0, 0.0, 0.0, 0.0).tau_mod_s(dmod), None);
    assert_eq!(rel(30.0, 0.0, -10.0, 0.0, 0.0, 0.0).tau_mod_s(dmod), None);
    // Outside, closing at 10 m/s from 1500 m: (1500^2 - 1000^2) / (1500 x 10) = 83.33 s.
    let tau = rel(1500.0, 0.0, -10.0, 0.0, 0.0, 0.0)
        .tau_mod_s(dmod)
        .unwrap();
    assert!((tau - 1_250_000.0 / 15_000.0).abs() < 1e-9, "{tau}");
    // Diverging: undefined.
    assert_eq!(rel(1500.0, 0.0, 10.0, 0.0, 0.0, 0.0).tau_mod_s(dmod), None);
}
