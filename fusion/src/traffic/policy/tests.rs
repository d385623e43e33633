//! The fail-safe policy: hand-computed cases from the acceptance points, and a property
//! test over every combination of known / unknown / non-finite / extreme fields.

use nalgebra::Vector2;
use proptest::prelude::*;

use super::*;
use crate::units::{M_PER_FT, M_PER_NM};

const KT: f64 = 1852.0 / 3600.0;

/// A head-on encounter on the north axis: intruder `range_nm` north, both at 100 kt towards
/// each other, same altitude, level.
fn head_on(range_nm: f64) -> Encounter {
    Encounter {
        s_m: Vector2::new(0.0, range_nm * M_PER_NM),
        own_velocity_mps: Some(Vector2::new(0.0, 100.0 * KT)),
        own_vertical_rate_mps: Some(0.0),
        own_max_vertical_rate_mps: 15.0,
        intruder_velocity_mps: Some(Vector2::new(0.0, -100.0 * KT)),
        dz_m: Some(0.0),
        dz_band_m: 0.0,
        intruder_vertical_rate_mps: Some(0.0),
        intruder_max_vertical_rate_mps: 10.0,
        position_margin_m: 0.0,
    }
}

#[test]
fn ownship_velocity_unknown_uses_the_present_separation_only() {
    // The acceptance: co-altitude at 5 NM stays below 2; at 0.3 NM it is at least 2.
    let far = Encounter {
        own_velocity_mps: None,
        ..head_on(5.0)
    };
    let (g, f) = assess(&far).unwrap();
    assert!(f.ownship_velocity_unknown);
    assert_eq!(g.alert_level, 0);
    assert!(!g.well_clear_violated_now);
    assert_eq!(
        (g.tcpa_s, g.hmd_m, g.range_rate_mps, g.tau_mod_s),
        (None, None, None, None)
    );
    assert!((g.horizontal_distance_m - 5.0 * M_PER_NM).abs() < 1e-6);
    let near = Encounter {
        own_velocity_mps: None,
        ..head_on(0.3)
    };
    let (g, _) = assess(&near).unwrap();
    assert!(g.well_clear_violated_now);
    assert_eq!(g.alert_level, 3);
    // Today's bug: NaN velocity made every co-altitude target level 3. NaN is unknown here.
    let nan = Encounter {
        own_velocity_mps: Some(Vector2::new(f64::NAN, f64::NAN)),
        ..head_on(5.0)
    };
    assert_eq!(assess(&nan).unwrap().0.alert_level, 0);
}

#[test]
fn altitude_unknown_is_co_altitude_capped_at_corrective() {
    // Head-on at 2 NM, 200 kt closing: 2 - 0.66 NM = 1.34 NM at 200 kt = 24.1 s to DTHR, so a
    // co-altitude target is level 3 (and an intruder 3000 ft above is 0).
    let known = head_on(2.0);
    assert_eq!(assess(&known).unwrap().0.alert_level, 3);
    let above = Encounter {
        dz_m: Some(3000.0 * M_PER_FT),
        ..head_on(2.0)
    };
    assert_eq!(assess(&above).unwrap().0.alert_level, 0);
    let unknown = Encounter {
        dz_m: None,
        ..head_on(2.0)
    };
    let (g, f) = assess(&unknown).unwrap();
    assert!(f.altitude_unknown);
    assert_eq!(g.alert_level, MAX_LEVEL_ALTITUDE_UNKNOWN);
    assert_eq!(g.vertical_separation_m, None);
    // Inside 0.66 NM: violated now, still 2.
    let inside = Encounter {
        dz_m: None,
        ..head_on(0.5)
    };
    let (g, _) = assess(&inside).unwrap();
    assert!(g.well_clear_violated_now);
    assert_eq!(g.alert_level, 2);
}

#[test]
fn vertical_rate_unknown_covers_the_category_rates() {
    // Intruder 1000 ft above, closing head-on at 2 NM; level flight: no alert (outside ZTHR
    // 450 ft and the preventive 700 ft). With its rate unknown and up to 10 m/s (1969 ft/min),
    // it can descend the 550 ft to ZTHR (167.6 m) in 16.8 s: inside the 25 s warning time.
    let level = Encounter {
        dz_m: Some(1000.0 * M_PER_FT),
        ..head_on(2.0)
    };
    assert_eq!(assess(&level).unwrap().0.alert_level, 0);
    let unknown = Encounter {
        intruder_vertical_rate_mps: None,
        ..level
    };
    let (g, f) = assess(&unknown).unwrap();
    assert!(f.vertical_rate_unknown);
    assert_eq!(g.alert_level, 3);
}

#[test]
fn intruder_velocity_unknown_is_not_stationary() {
    // Intruder 1 NM away, velocity unknown, report 3 s old at up to 150 m/s: 450 m taken off the
    // 1852 m range leaves 1402 m, outside DTHR (1222 m): level 0. 5 s old (750 m): inside.
    let mut e = Encounter {
        intruder_velocity_mps: None,
        position_margin_m: 450.0,
        ..head_on(1.0)
    };
    let (g, f) = assess(&e).unwrap();
    assert!(f.velocity_unknown);
    assert_eq!(g.alert_level, 0);
    e.position_margin_m = 750.0;
    assert_eq!(assess(&e).unwrap().0.alert_level, 3);
}

#[test]
fn a_band_of_separations_widens_the_vertical_test() {
    // 600 ft above, a 200 m band (pressure against geometric, no measured difference): the
    // separation may be 0, so a co-altitude-violating head-on at 0.5 NM is violated now.
    let e = Encounter {
        dz_m: Some(600.0 * M_PER_FT),
        dz_band_m: 200.0,
        ..head_on(0.5)
    };
    let (g, f) = assess(&e).unwrap();
    assert!(f.altitude_reference_mixed);
    assert!(g.well_clear_violated_now);
    let narrow = Encounter {
        dz_band_m: 0.0,
        ..e
    };
    assert!(!assess(&narrow).unwrap().0.well_clear_violated_now);
}

/// A float that may be ordinary, extreme, or not finite.
fn any_f64(ordinary: std::ops::Range<f64>) -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => ordinary,
        1 => Just(f64::NAN),
        1 => Just(f64::INFINITY),
        1 => Just(f64::NEG_INFINITY),
        1 => Just(1e300),
        1 => Just(-1e300),
        1 => Just(5e-324),
    ]
}

fn maybe(s: impl Strategy<Value = f64>) -> impl Strategy<Value = Option<f64>> {
    prop_oneof![1 => Just(None), 3 => s.prop_map(Some)]
}

fn maybe_vec(r: std::ops::Range<f64>) -> impl Strategy<Value = Option<Vector2<f64>>> {
    maybe(any_f64(r.clone()))
        .prop_flat_map(move |x| (Just(x), any_f64(r.clone())))
        .prop_map(|(x, y)| x.map(|x| Vector2::new(x, y)))
}

prop_compose! {
    fn encounter()(
        sx in any_f64(-20_000.0..20_000.0),
        sy in any_f64(-20_000.0..20_000.0),
        own_v in maybe_vec(-150.0..150.0),
        own_vz in maybe(any_f64(-20.0..20.0)),
        own_vz_max in any_f64(0.0..30.0),
        int_v in maybe_vec(-300.0..300.0),
        dz in maybe(any_f64(-1500.0..1500.0)),
        band in any_f64(0.0..300.0),
        int_vz in maybe(any_f64(-40.0..40.0)),
        int_vz_max in any_f64(0.0..60.0),
        margin in any_f64(0.0..2000.0),
    ) -> Encounter {
        Encounter {
            s_m: Vector2::new(sx, sy),
            own_velocity_mps: own_v,
            own_vertical_rate_mps: own_vz,
            own_max_vertical_rate_mps: own_vz_max,
            intruder_velocity_mps: int_v,
            dz_m: dz,
            dz_band_m: band,
            intruder_vertical_rate_mps: int_vz,
            intruder_max_vertical_rate_mps: int_vz_max,
            position_margin_m: margin,
        }
    }
}

fn finite_or_none(x: Option<f64>) -> bool {
    x.is_none_or(f64::is_finite)
}

/// The level of `e` with every quantity known (the caller fills them in).
fn level(e: &Encounter) -> u8 {
    assess(e).map_or(0, |(g, _)| g.alert_level)
}

fn usable_pos(e: &Encounter) -> bool {
    e.s_m.x.is_finite() && e.s_m.y.is_finite() && e.s_m.norm() <= MAX_RANGE_M
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    /// No panic; every output finite or `None`; the level within 0..=3.
    #[test]
    fn outputs_are_finite_or_unknown(e in encounter()) {
        match assess(&e) {
            None => prop_assert!(!usable_pos(&e)),
            Some((g, f)) => {
                prop_assert!(g.horizontal_distance_m.is_finite());
                prop_assert!(finite_or_none(g.vertical_separation_m));
                prop_assert!(finite_or_none(g.range_rate_mps));
                prop_assert!(finite_or_none(g.tcpa_s));
                prop_assert!(finite_or_none(g.hmd_m));
                prop_assert!(finite_or_none(g.tau_mod_s));
                if let Some(iv) = g.loss_of_well_clear_interval_s {
                    prop_assert!(iv.0.is_finite() && iv.1.is_finite() && iv.0 <= iv.1);
                }
                prop_assert!(g.alert_level <= 3);
                if f.altitude_unknown {
                    prop_assert!(g.alert_level <= MAX_LEVEL_ALTITUDE_UNKNOWN);
                    prop_assert!(g.vertical_separation_m.is_none());
                }
                if f.ownship_velocity_unknown || f.velocity_unknown {
                    // Present separation only: 3, 1 or 0 (2 under the altitude cap).
                    prop_assert!(g.tcpa_s.is_none() && g.loss_of_well_clear_interval_s.is_none());
                }
            }
        }
    }

    /// An unknown altitude never lowers the level below what any known altitude gives (up to the
    /// cap), and gives exactly the capped co-altitude level.
    #[test]
    fn unknown_altitude_is_never_below_a_known_one(e in encounter(), dz in -1500.0..1500.0f64) {
        let unknown = Encounter { dz_m: None, ..e };
        let known = Encounter { dz_m: Some(dz), ..e };
        let co = Encounter { dz_m: Some(0.0), dz_band_m: 0.0, intruder_vertical_rate_mps: Some(0.0),
            own_vertical_rate_mps: Some(0.0), ..e };
        prop_assert!(level(&unknown) >= level(&known).min(MAX_LEVEL_ALTITUDE_UNKNOWN));
        prop_assert_eq!(level(&unknown), level(&co).min(MAX_LEVEL_ALTITUDE_UNKNOWN));
    }

    /// An unknown intruder vertical rate never gives a lower level than any rate the category
    /// allows.
    #[test]
    fn unknown_vertical_rate_covers_every_allowed_rate(e in encounter(), k in -1.0..1.0f64) {
        // A non-finite or out-of-range category limit is tested elsewhere (it widens to the
        // largest rate); here an ordinary one.
        let max = Some(e.intruder_max_vertical_rate_mps)
            .filter(|m| m.is_finite() && (0.0..=MAX_VERTICAL_RATE_MPS).contains(m))
            .unwrap_or(10.0);
        let e = Encounter { intruder_max_vertical_rate_mps: max, ..e };
        let unknown = Encounter { intruder_vertical_rate_mps: None, ..e };
        let known = Encounter { intruder_vertical_rate_mps: Some(k * max), ..e };
        prop_assert!(level(&unknown) >= level(&known));
    }

    /// An unknown velocity (either aircraft) never hides a violation by range that holds now,
    /// whatever the velocity was; and alone it decides nothing about the future (level 2 needs a
    /// prediction, so it never appears without the altitude cap).
    #[test]
    fn unknown_velocity_keeps_present_violations(e in encounter(), vx in -150.0..150.0f64,
        vy in -150.0..150.0f64) {
        let known = Encounter {
            own_velocity_mps: Some(Vector2::new(vx, vy)),
            intruder_velocity_mps: Some(Vector2::zeros()),
            ..e
        };
        let unknown = Encounter { own_velocity_mps: None, ..known };
        let (Some((gk, _)), Some((gu, fu))) = (assess(&known), assess(&unknown)) else {
            return Ok(());
        };
        // (The modified-tau clause of "violated now" needs a velocity; the range clause does not.)
        if gk.well_clear_violated_now && gk.horizontal_distance_m <= Thresholds::DWC.dthr_m {
            prop_assert!(gu.well_clear_violated_now);
        }
        if !fu.altitude_unknown {
            prop_assert!(gu.alert_level != 2);
        }
    }
}

/// `FailSafeFlags::any` is true when any one rule applied, and only then.
#[test]
fn any_fail_safe_flag_alone_counts() {
    assert!(!FailSafeFlags::default().any());
    let each: [fn(&mut FailSafeFlags); 8] = [
        |f| f.ownship_velocity_unknown = true,
        |f| f.ownship_vertical_rate_unknown = true,
        |f| f.altitude_unknown = true,
        |f| f.velocity_unknown = true,
        |f| f.vertical_rate_unknown = true,
        |f| f.altitude_reference_mixed = true,
        |f| f.stale = true,
        |f| f.time_from_receipt = true,
    ];
    for (i, set) in each.iter().enumerate() {
        let mut f = FailSafeFlags::default();
        set(&mut f);
        assert!(f.any(), "flag {i} alone");
    }
}

/// Side by side at the same speed (horizontally inside the volume throughout), the intruder
/// 300 m above: only the vertical decides when well clear is lost.
fn overhead(own_vz: Option<f64>, intruder_vz: Option<f64>) -> Encounter {
    Encounter {
        s_m: Vector2::new(0.0, 0.0),
        own_velocity_mps: Some(Vector2::new(0.0, 100.0 * KT)),
        intruder_velocity_mps: Some(Vector2::new(0.0, 100.0 * KT)),
        dz_m: Some(300.0),
        own_vertical_rate_mps: own_vz,
        intruder_vertical_rate_mps: intruder_vz,
        ..head_on(1.0)
    }
}

fn lowc_start_s(e: &Encounter) -> Option<f64> {
    assess(e)
        .unwrap()
        .0
        .loss_of_well_clear_interval_s
        .map(|iv| iv.0)
}

/// The vertical closure is the intruder's rate less the ownship's, and unknown rates widen it
/// by what each may fly (ZTHR 450 ft = 137.16 m, worked by hand):
/// - the ownship climbing at 5 m/s towards an intruder 300 m above: (300 - 137.16) / 5 =
///   32.57 s; the intruder climbing away as fast: never;
/// - the ownship's rate unknown (up to 15 m/s): 162.84 / 15 = 10.86 s, and the flag says so;
/// - both unknown (15 + 10 m/s): 162.84 / 25 = 6.51 s.
#[test]
fn vertical_closure_is_the_difference_of_the_rates_widened_by_the_unknown_ones() {
    let t = lowc_start_s(&overhead(Some(5.0), Some(0.0))).unwrap();
    assert!((t - 32.568).abs() < 1e-3, "{t}");
    assert_eq!(lowc_start_s(&overhead(Some(5.0), Some(5.0))), None);
    assert_eq!(lowc_start_s(&overhead(Some(0.0), Some(5.0))), None);
    let own_unknown = overhead(None, Some(0.0));
    let (_, f) = assess(&own_unknown).unwrap();
    assert!(f.ownship_vertical_rate_unknown && !f.vertical_rate_unknown);
    let t = lowc_start_s(&own_unknown).unwrap();
    assert!((t - 10.856).abs() < 1e-3, "{t}");
    let t = lowc_start_s(&overhead(None, None)).unwrap();
    assert!((t - 6.5136).abs() < 1e-3, "{t}");
}

/// A value beyond its bound is unknown, not used: an altitude difference of 200 km (over
/// `MAX_DZ_M`) is treated as unknown altitude. The mixed-reference flag needs both a known
/// separation and a band: neither an unknown altitude with a band nor a known one without.
#[test]
fn out_of_bound_values_are_unknown_and_the_mixed_flag_needs_a_band() {
    let far = Encounter {
        dz_m: Some(2.0e5),
        ..head_on(2.0)
    };
    let (g, f) = assess(&far).unwrap();
    assert!(f.altitude_unknown);
    assert_eq!(g.vertical_separation_m, None);
    let unknown_with_band = Encounter {
        dz_m: None,
        dz_band_m: 50.0,
        ..head_on(2.0)
    };
    assert!(
        !assess(&unknown_with_band)
            .unwrap()
            .1
            .altitude_reference_mixed
    );
    assert!(!assess(&head_on(2.0)).unwrap().1.altitude_reference_mixed);
}

/// The per-category limits, each as its decision states it (ft/min or kt), converted by hand
/// (1 ft/min = 0.00508 m/s, 1 kt = 0.514444 m/s); categories the table does not name (0, 6,
/// 8, 11, 13, 15, 16, 22, none) take the fallback.
#[test]
fn category_limits_are_the_stated_ones() {
    let climb = [
        (1, 10.16), // light, 2000 ft/min
        (2, 30.48), // small, 6000 ft/min
        (3, 30.48),
        (4, 30.48),
        (5, 30.48),
        (7, 15.24),  // rotorcraft, 3000 ft/min
        (9, 10.16),  // glider, 2000 ft/min
        (10, 7.62),  // lighter than air, 1500 ft/min
        (12, 10.16), // ultralight, 2000 ft/min
        (14, 15.24), // UAV, 3000 ft/min
        (17, 2.54),  // surface, 500 ft/min
        (21, 2.54),
    ];
    for (c, v) in climb {
        let got = max_vertical_rate_mps(Some(c), 99.0);
        assert!((got - v).abs() < 1e-9, "category {c}: {got}");
    }
    let speed = [
        (1, 128.611), // light, 250 kt
        (7, 92.600),  // rotorcraft, 180 kt
        (9, 82.311),  // glider, 160 kt
        (10, 41.156), // lighter than air, 80 kt
        (12, 41.156), // ultralight, 80 kt
        (14, 77.167), // UAV, 150 kt
        (17, 41.156), // surface, 80 kt
        (21, 41.156),
    ];
    for (c, v) in speed {
        let got = max_speed_mps(Some(c), 999.0);
        assert!((got - v).abs() < 1e-3, "category {c}: {got}");
    }
    for c in [
        None,
        Some(0),
        Some(6),
        Some(8),
        Some(11),
        Some(13),
        Some(15),
        Some(16),
        Some(22),
    ] {
        assert_eq!(max_vertical_rate_mps(c, 99.0), 99.0, "{c:?}");
        assert_eq!(max_speed_mps(c, 999.0), 999.0, "{c:?}");
    }
    for c in 2..=5 {
        assert_eq!(max_speed_mps(Some(c), 999.0), 999.0, "{c}: no stated speed");
    }
}
