//! Tests of CPR decoding: published examples, hand computations at zone edges and near the
//! poles, and encode/decode round trips.

use super::*;
use crate::modes::{bits, hex_frame, me_of};

fn frame_of(hex: &str) -> CprFrame {
    let (f, _) = hex_frame(hex);
    let me = me_of(&f);
    CprFrame {
        odd: bits(me, 22, 1) == 1,
        lat: bits(me, 23, 17) as u32,
        lon: bits(me, 40, 17) as u32,
    }
}

/// NL from the closed form of DO-260B A.1.7.2, computed independently of the table.
fn nl_closed_form(lat: f64) -> u32 {
    if lat == 0.0 {
        return 59;
    }
    if lat.abs() == 87.0 {
        return 2;
    }
    if lat.abs() > 87.0 {
        return 1;
    }
    let a = 1.0 - (std::f64::consts::PI / 30.0).cos();
    let b = lat.to_radians().cos().powi(2);
    (2.0 * std::f64::consts::PI / (1.0 - a / b).acos()).floor() as u32
}

#[test]
fn table_matches_closed_form() {
    let mut rng = crate::testkit::XorShift::new(3);
    for _ in 0..20_000 {
        let lat = (rng.below(180_000_000) as f64) / 1e6 - 90.0;
        if NL_TRANSITIONS.iter().any(|t| (lat.abs() - t).abs() < 1e-9) {
            continue;
        }
        assert_eq!(nl(lat), nl_closed_form(lat), "{lat}");
    }
}

#[test]
fn nl_edges() {
    assert_eq!(nl(0.0), 59);
    assert_eq!(nl(10.47), 59);
    assert_eq!(nl(10.4705), 58);
    assert_eq!(nl(-10.4705), 58);
    assert_eq!(nl(86.5), 3);
    assert_eq!(nl(86.54), 2);
    assert_eq!(nl(87.0), 2);
    assert_eq!(nl(87.000_001), 1);
    assert_eq!(nl(-90.0), 1);
    assert_eq!(nl(f64::NAN), 1);
}

#[test]
fn riddle_global_pair() {
    // The 1090 MHz Riddle (Sun): even 8D40621D58C382D690C8AC2863A7 (lat 93000, lon 51372), odd
    // 8D40621D58C386435CC412692AD6 (74158, 50194), even newest -> 52.25720 N, 3.91937 E.
    let even = frame_of("8D40621D58C382D690C8AC2863A7");
    let odd = frame_of("8D40621D58C386435CC412692AD6");
    assert_eq!((even.odd, even.lat, even.lon), (false, 93_000, 51_372));
    assert_eq!((odd.odd, odd.lat, odd.lon), (true, 74_158, 50_194));
    let (lat, lon) = global_airborne(even, odd, false).unwrap();
    assert!((lat - 52.257_202_148_437_5).abs() < 1e-9, "{lat}");
    assert!((lon - 3.919_372_558_593_75).abs() < 1e-9, "{lon}");
    // Odd newest: the odd frame's own position, a few hundred metres away.
    let (lat1, lon1) = global_airborne(even, odd, true).unwrap();
    assert!((lat1 - lat).abs() < 0.02 && (lon1 - lon).abs() < 0.03);
    // Arguments in the wrong roles.
    assert_eq!(global_airborne(odd, even, true), Err(CprError::SameFormat));
}

#[test]
fn riddle_local() {
    // The Riddle's local example: reference 52.258 N 3.918 E, even frame above -> the same
    // position as the global decode.
    let even = frame_of("8D40621D58C382D690C8AC2863A7");
    let (lat, lon) = local(even, false, 52.258, 3.918).unwrap();
    assert!((lat - 52.257_202_148_437_5).abs() < 1e-9, "{lat}");
    assert!((lon - 3.919_372_558_593_75).abs() < 1e-9, "{lon}");
}

#[test]
fn hand_computed_zero() {
    // Position 0 N 0 E: every fraction is 0 in both formats. j = floor(0.5) = 0, lat = 0;
    // NL(0) = 59, m = floor(0.5) = 0 -> lon = 0.
    let e = CprFrame {
        odd: false,
        lat: 0,
        lon: 0,
    };
    let o = CprFrame {
        odd: true,
        lat: 0,
        lon: 0,
    };
    assert_eq!(global_airborne(e, o, false), Ok((0.0, 0.0)));
    assert_eq!(encode(0.0, 0.0, false, false), e);
    assert_eq!(encode(0.0, 0.0, true, false), o);
}

#[test]
fn zone_boundary_pair_is_rejected() {
    // An aircraft crossing the NL 59/58 boundary at 10.4705 deg between its two frames: the
    // even frame at 10.46 deg (NL 59), the odd at 10.48 deg (NL 58), 1.2 NM apart. Decoded
    // latitudes land in different NL zones: no position.
    let e = encode(10.46, 20.0, false, false);
    let o = encode(10.48, 20.0, true, false);
    assert_eq!(global_airborne(e, o, true), Err(CprError::ZoneMismatch));
    // Both on the same side: accepted and exact to the CPR resolution (~5 m).
    let e = encode(10.44, 20.0, false, false);
    let o = encode(10.46, 20.0, true, false);
    let (lat, lon) = global_airborne(e, o, true).unwrap();
    assert!((lat - 10.46).abs() < 1e-4 && (lon - 20.0).abs() < 1e-4);
}

#[test]
fn near_the_pole() {
    // At 87.5 deg NL = 1: odd frames use ni = max(1 - 1, 1) = 1 zone, a whole 360 deg.
    for &(lat, lon) in &[(87.5, 45.0), (-87.5, -120.0), (86.9, 179.9), (89.9, -0.1)] {
        let e = encode(lat, lon, false, false);
        let o = encode(lat, lon, true, false);
        for newest_odd in [false, true] {
            let (dl, dn) = global_airborne(e, o, newest_odd).unwrap();
            assert!((dl - lat).abs() < 1e-3, "{lat} {dl}");
            let dlon = (dn - lon + 540.0).rem_euclid(360.0) - 180.0;
            assert!(dlon.abs() < 0.01, "{lon} {dn}");
        }
    }
}

#[test]
fn round_trip_grid() {
    let mut rng = crate::testkit::XorShift::new(11);
    for _ in 0..5_000 {
        let lat = rng.below(17_800_000) as f64 / 1e5 - 89.0;
        let lon = rng.below(36_000_000) as f64 / 1e5 - 180.0;
        let e = encode(lat, lon, false, false);
        let o = encode(lat, lon, true, false);
        let (dl, dn) = match global_airborne(e, o, true) {
            Ok(p) => p,
            // Both frames encode the same point, so only a point within one CPR step of an NL
            // transition can disagree.
            Err(CprError::ZoneMismatch) => {
                assert!(
                    NL_TRANSITIONS.iter().any(|t| (lat.abs() - t).abs() < 1e-3),
                    "{lat}"
                );
                continue;
            }
            Err(e) => panic!("{e} at {lat} {lon}"),
        };
        assert!((dl - lat).abs() < 1e-4, "{lat} {dl}");
        let dlon = (dn - lon + 540.0).rem_euclid(360.0) - 180.0;
        assert!(dlon.abs() < 2e-3, "{lat} {lon} {dn}");
        // Local decoding from a reference 1 deg away gives the same point.
        let (ll, ln) = local(o, false, lat + 0.7, lon - 0.7).unwrap();
        assert!(
            (ll - dl).abs() < 1e-9 && (ln - dn).abs() < 1e-9,
            "{lat} {lon}"
        );
    }
}

#[test]
fn surface_needs_and_uses_the_reference() {
    // Surface frames encode position modulo 90 deg; the reference picks the solution.
    for &(lat, lon, rlat, rlon) in &[
        (52.3206, 4.7347, 51.99, 4.375),
        (-43.4964, 172.5578, -43.5, 172.5),
        (0.05, -0.05, -0.2, 0.3),
        (33.9425, -118.4081, 34.0, -118.0),
    ] {
        let e = encode(lat, lon, false, true);
        let o = encode(lat, lon, true, true);
        let (dl, dn) = global_surface(e, o, false, rlat, rlon).unwrap();
        assert!(
            (dl - lat).abs() < 1e-4 && (dn - lon).abs() < 1e-4,
            "{lat} {lon}: {dl} {dn}"
        );
        let (ll, ln) = local(e, true, rlat, rlon).unwrap();
        assert!(
            (ll - lat).abs() < 1e-4 && (ln - lon).abs() < 1e-4,
            "{lat} {lon}: {ll} {ln}"
        );
    }
}

#[test]
fn local_is_ambiguous_beyond_half_a_zone() {
    // An even airborne zone is 6 deg of latitude: a reference 4 deg away decodes to the wrong
    // zone (2 deg off) - which is why the tracker only uses recent, nearby references.
    let e = encode(50.0, 10.0, false, false);
    let (lat, _) = local(e, false, 54.0, 10.0).unwrap();
    assert!((lat - 56.0).abs() < 1e-3, "{lat}");
}

/// (lat, lon) of a decode, asserted within `tol` degrees of the published value.
fn near(got: (f64, f64), want: (f64, f64), tol: f64) {
    assert!(
        (got.0 - want.0).abs() < tol && (got.1 - want.1).abs() < tol,
        "{got:?} vs {want:?}"
    );
}

#[test]
fn pymodes_published_airborne_vectors() {
    // pyModeS tests/test_cpr.py (values given to 1e-3 there, to 5 decimals).
    let e = frame_of("8D40058B58C901375147EFD09357");
    let o = frame_of("8D40058B58C904A87F402D3B8C59");
    near(
        global_airborne(e, o, true).unwrap(),
        (49.81755, 6.08442),
        1e-5,
    );
    near(
        global_airborne(e, o, false).unwrap(),
        (49.82410, 6.06785),
        1e-5,
    );
    near(
        local(e, false, 49.0, 6.0).unwrap(),
        (49.82410, 6.06785),
        1e-5,
    );
    near(
        local(o, false, 49.0, 6.0).unwrap(),
        (49.81755, 6.08442),
        1e-5,
    );
    // "Numerical challenge": a reference right on a zone boundary.
    let f = frame_of("8D06A15358BF17FF7D4A84B47B95");
    near(
        local(f, false, 30.508_474_576_271_183, 7.2 * 5.0 + 3e-15).unwrap(),
        (30.50540, 33.44787),
        1e-5,
    );
    // A pair whose latitudes fall in NL 23 and 24: rejected.
    let e = CprFrame {
        odd: false,
        lat: 8192,
        lon: 0,
    };
    let o = CprFrame {
        odd: true,
        lat: 114_688,
        lon: 0,
    };
    assert_eq!(global_airborne(e, o, false), Err(CprError::ZoneMismatch));
}

#[test]
fn pymodes_published_surface_vectors() {
    // pyModeS tests/test_cpr.py: real DF18 surface pair of 3A23FF at Toulouse (LFBO).
    let e = frame_of("903A23FF426A38565950432EBF95");
    let o = frame_of("903A23FF426A4E65F7487A775D17");
    near(
        global_surface(e, o, true, 43.63, 1.37).unwrap(),
        (43.62646, 1.37476),
        1e-5,
    );
    near(
        global_surface(e, o, false, 43.63, 1.37).unwrap(),
        (43.62648, 1.37462),
        1e-5,
    );
    near(
        local(o, true, 43.63, 1.37).unwrap(),
        (43.62646, 1.37476),
        1e-5,
    );
    // The reference picks the hemisphere and the 90-degree quadrant.
    near(
        global_surface(e, o, true, -43.5, 1.37).unwrap(),
        (-46.37354, 1.44350),
        1e-5,
    );
    near(
        global_surface(e, o, true, 43.63, -178.63).unwrap(),
        (43.62646, -178.62524),
        1e-5,
    );
    near(
        global_surface(e, o, true, 43.63, 91.37).unwrap(),
        (43.62646, 91.37476),
        1e-5,
    );
    // Sao Paulo pair (southern hemisphere, west), odd newer: within 0.05 deg of the receiver.
    let e = frame_of("8FE48C033A9FA184B934E744C6FD");
    let o = frame_of("8FE48C033A9FA68F7C3D39B1C2F0");
    near(
        global_surface(e, o, true, -23.426_544_8, -46.481_625_8).unwrap(),
        (-23.4265, -46.4816),
        0.05,
    );
    // Synthetic pair straddling NL 54/53: rejected.
    let e = CprFrame {
        odd: false,
        lat: 28_672,
        lon: 0,
    };
    let o = CprFrame {
        odd: true,
        lat: 122_880,
        lon: 0,
    };
    assert_eq!(
        global_surface(e, o, false, 50.0, 0.0),
        Err(CprError::ZoneMismatch)
    );
}

#[test]
fn a_pair_of_one_format_is_refused_whichever_format() {
    // Each decode needs one even and one odd frame: two of either format is an error, not a
    // position (the wrong-roles case is in riddle_global_pair).
    let e = CprFrame {
        odd: false,
        lat: 93_000,
        lon: 51_372,
    };
    let o = CprFrame { odd: true, ..e };
    for (a, b) in [(e, e), (o, o)] {
        assert_eq!(global_airborne(a, b, false), Err(CprError::SameFormat));
        assert_eq!(
            global_surface(a, b, false, 52.0, 4.0),
            Err(CprError::SameFormat)
        );
    }
}

#[test]
fn one_latitude_just_beyond_the_pole_refuses_the_pair() {
    // By hand: even lat 130 810, odd 98 305 (of 2^17): j = floor(59 x 0.998001 - 60 x 0.750008
    // + 0.5) = floor(14.38) = 14; even 6 x (14 + 0.998001) = 89.988 deg, odd 360/59 x (14 +
    // 0.750008) = 90.00005 deg: the odd one is not a latitude, so neither is the pair.
    let even = CprFrame {
        odd: false,
        lat: 130_810,
        lon: 0,
    };
    let odd = CprFrame {
        odd: true,
        lat: 98_305,
        lon: 0,
    };
    assert_eq!(
        global_airborne(even, odd, false),
        Err(CprError::LatitudeOutOfRange)
    );
}

#[test]
fn encode_gives_back_the_riddle_frames() {
    // Each Riddle frame's decoded position lies on its own CPR grid, so encoding it gives the
    // frame's fields exactly (to the LSB: encode rounds to the nearest step).
    let even = frame_of("8D40621D58C382D690C8AC2863A7");
    let odd = frame_of("8D40621D58C386435CC412692AD6");
    let (lat, lon) = global_airborne(even, odd, false).unwrap();
    assert_eq!(encode(lat, lon, false, false), even);
    let (lat, lon) = global_airborne(even, odd, true).unwrap();
    assert_eq!(encode(lat, lon, true, false), odd);
}
