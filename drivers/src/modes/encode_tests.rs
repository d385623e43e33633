//! Encoder tests: fixed frames checked against the literature, and proptest round trips
//! encoder -> frame decoder.

use super::*;
use crate::modes::df::{Content, DecodeOptions, Parity, decode};
use crate::modes::me::Me;
use crate::modes::velocity::VerticalRateSource;
use proptest::prelude::*;

fn me_of_frame(f: &[u8]) -> (u32, Me) {
    let m = decode(f, DecodeOptions::default()).expect("clean frame");
    assert_eq!(m.parity, Parity::Verified);
    let Content::Extended { me, .. } = m.content else {
        panic!("{m:?}")
    };
    (m.icao, me)
}

#[test]
fn klm1023_is_reproduced_bit_for_bit() {
    // 8D4840D6202CC371C32CE0576098: DF17 CA5, 4840D6, TC 4, CA 0, "KLM1023 ".
    let f = identification(0x48_40D6, 4, 0, "KLM1023").unwrap();
    assert_eq!(f, crate::modes::hex_frame("8D4840D6202CC371C32CE0576098").0);
    assert!(identification(1, 5, 0, "X").is_none());
    assert!(identification(1, 4, 8, "X").is_none());
    assert!(identification(1, 4, 0, "bad!").is_none());
}

#[test]
fn riddle_velocity_is_reproduced() {
    // 8D485020994409940838175B284F has E -8 kt, N -159 kt, VR -832 ft/min, IFR 1, NACv 0,
    // bit 36 = 0, dAlt +550 ft: our encoder writes everything but IFR and dAlt, so compare ME
    // bits 11-46 only.
    let f = velocity_ground(0x48_5020, -8, -159, Some(-832), false, 0).unwrap();
    let (_, me) = me_of_frame(&f);
    let Me::Velocity(v) = me else { panic!() };
    assert_eq!(
        (v.v_east_kt, v.v_north_kt, v.vertical_rate_fpm),
        (Some(-8), Some(-159), Some(-832))
    );
    let ours = crate::modes::me_of(&f);
    let theirs = crate::modes::me_of(&crate::modes::hex_frame("8D485020994409940838175B284F").0);
    let mask = ((1u64 << 36) - 1) << 10;
    assert_eq!(ours & mask, theirs & mask);
}

#[test]
fn refusals() {
    let p = AirbornePositionFields {
        typecode: 19,
        surveillance_status: 0,
        nic_b: false,
        altitude_ft: Some(1000),
        lat_deg: 0.0,
        lon_deg: 0.0,
        odd: false,
    };
    assert!(airborne_position(1, &p).is_none());
    assert!(
        airborne_position(
            1,
            &AirbornePositionFields {
                typecode: 11,
                altitude_ft: Some(60_000),
                ..p
            }
        )
        .is_none()
    );
    assert!(
        airborne_position(
            1,
            &AirbornePositionFields {
                typecode: 11,
                lat_deg: 91.0,
                ..p
            }
        )
        .is_none()
    );
    assert!(velocity_ground(1, 5000, 0, None, true, 0).is_none());
    assert!(velocity_ground(1, 0, 0, Some(40_000), true, 0).is_none());
    assert!(
        operational_status(
            1,
            &OperationalStatusFields {
                nac_p: 12,
                ..Default::default()
            }
        )
        .is_none()
    );
    assert!(df11(5, 1, 128).is_none());
}

#[test]
fn surveillance_status_takes_its_two_bits_and_refuses_a_third() {
    // DO-260B 2.2.3.2.3.2: the surveillance status is ME bits 6-7 (2 bits, 0..=3: no condition,
    // permanent alert, temporary alert, SPI). Each value comes back from the decoder; 4 needs a
    // third bit and is refused.
    let p = |surveillance_status| AirbornePositionFields {
        typecode: 11,
        surveillance_status,
        nic_b: false,
        altitude_ft: Some(1000),
        lat_deg: 52.0,
        lon_deg: 4.0,
        odd: false,
    };
    for ss in 0..=3 {
        let f = airborne_position(0x48_40D6, &p(ss)).unwrap();
        let (_, me) = me_of_frame(&f);
        let Me::AirbornePosition(a) = me else {
            panic!("{me:?}")
        };
        assert_eq!((a.surveillance_status, a.typecode), (ss, 11), "status {ss}");
        // ME bits 6-7 are bits 50-49 of the 56-bit ME word (bit 1 is its MSB, bit 56 its LSB).
        assert_eq!((crate::modes::me_of(&f) >> 49) & 0b11, u64::from(ss));
    }
    assert!(airborne_position(0x48_40D6, &p(4)).is_none());
}

#[test]
fn vertical_rate_field_by_hand() {
    // DO-260B 2.2.3.2.6.1.14: sign bit (1 = down) above 9 bits of 1 + |rate| / 64 ft/min; 0 =
    // no information. Level flight is "up 0" (sign clear): 0b0_000000001.
    assert_eq!(vr_field(None), Some(0));
    assert_eq!(vr_field(Some(0)), Some(1));
    assert_eq!(vr_field(Some(64)), Some(2));
    assert_eq!(vr_field(Some(-64)), Some((1 << 9) | 2));
    // -832 ft/min (Riddle's example): 832 / 64 = 13, raw 14, sign set.
    assert_eq!(vr_field(Some(-832)), Some((1 << 9) | 14));
    // 510 x 64 = 32,640 ft/min is the largest (raw 511); one step more does not fit.
    assert_eq!(vr_field(Some(32_640)), Some(511));
    assert_eq!(vr_field(Some(32_704)), None);
    // The same rule for the velocity components (2.2.3.2.6.1.6-9): standing still is "east 0,
    // north 0", raw 1 in each 10-bit field under a clear direction bit (ME bits 14 and 25, bits
    // 42 and 31 of the 56-bit ME word).
    let me = crate::modes::me_of(&velocity_ground(1, 0, 0, Some(0), false, 0).unwrap());
    assert_eq!((me >> 32) & 0x7FF, 1, "east: direction bit and 10 bits");
    assert_eq!((me >> 21) & 0x7FF, 1, "north: direction bit and 10 bits");
    let me = crate::modes::me_of(&velocity_ground(1, -1, -1, Some(0), false, 0).unwrap());
    assert_eq!(((me >> 32) & 0x7FF, (me >> 21) & 0x7FF), (0x402, 0x402));
}

#[test]
fn airspeed_limits_and_headings_by_hand() {
    // DO-260B 2.2.3.2.6.3.10: subtype 4 (supersonic) air speed is 4 kt x (raw - 1), raw 10
    // bits, 1023 the largest: 4 x 1022 = 4,088 kt. 4,089 kt rounds to it ((4,089 + 2) / 4 =
    // 1,022, raw 1,023); 4,090 kt would need raw 1,024.
    let speed = |kt| {
        let f = velocity_air(1, None, kt, true, None, false)?;
        let (_, me) = me_of_frame(&f);
        let Me::Velocity(v) = me else {
            panic!("{me:?}")
        };
        v.airspeed_kt
    };
    assert_eq!(speed(4_089), Some(4_088));
    assert!(velocity_air(1, None, 4_090, true, None, false).is_none());
    // A heading is a number of degrees or absent; NaN and infinity are neither.
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert!(
            velocity_air(1, Some(bad), 200, true, None, false).is_none(),
            "{bad}"
        );
    }
    assert!(velocity_air(1, Some(359.9), 200, true, None, false).is_some());
    // The vertical rate and its source (ME bit 36: 1 = barometric) as in subtypes 1-2.
    for (baro, source) in [
        (true, VerticalRateSource::Baro),
        (false, VerticalRateSource::Gnss),
    ] {
        let f = velocity_air(1, None, 200, true, Some(-832), baro).unwrap();
        let (_, me) = me_of_frame(&f);
        let Me::Velocity(v) = me else {
            panic!("{me:?}")
        };
        assert_eq!(
            (v.vertical_rate_fpm, v.vertical_rate_source),
            (Some(-832), source)
        );
    }
}

#[test]
fn operational_status_refuses_each_field_too_wide() {
    // Version 0..=2 (3 bits, DO-260B knows three), NACp 0..=11, GVA and SIL 0..=3 (2 bits).
    let ok = OperationalStatusFields::default();
    for version in 0..=2 {
        assert!(operational_status(1, &OperationalStatusFields { version, ..ok }).is_some());
    }
    for bad in [
        OperationalStatusFields { version: 3, ..ok },
        OperationalStatusFields { nac_p: 12, ..ok },
        OperationalStatusFields { gva: 4, ..ok },
        OperationalStatusFields { sil: 4, ..ok },
    ] {
        assert!(operational_status(1, &bad).is_none(), "{bad:?}");
    }
    let widest = OperationalStatusFields {
        version: 2,
        nac_p: 11,
        gva: 3,
        sil: 3,
        ..ok
    };
    assert!(operational_status(1, &widest).is_some());
}

proptest! {
    #[test]
    fn identification_round_trip(icao in 0u32..0x100_0000, tc in 1u8..=4, cat in 0u8..8, cs in "[A-Z0-9]{0,8}") {
        let f = identification(icao, tc, cat, &cs).unwrap();
        let (a, me) = me_of_frame(&f);
        prop_assert_eq!(a, icao);
        let Me::Identification(id) = me else { panic!() };
        prop_assert_eq!((id.typecode, id.category), (tc, cat));
        prop_assert_eq!(id.callsign.as_str(), cs.as_str());
    }

    #[test]
    fn airborne_position_round_trip(
        icao in 0u32..0x100_0000,
        tc in prop_oneof![9u8..=18, 20u8..=22],
        alt in proptest::option::of(-1000i32..50_000),
        lat in -89.9f64..89.9,
        lon in -180.0f64..180.0,
        nic_b in any::<bool>(),
    ) {
        let mk = |odd| AirbornePositionFields {
            typecode: tc, surveillance_status: 0, nic_b, altitude_ft: alt, lat_deg: lat, lon_deg: lon, odd,
        };
        let fe = airborne_position(icao, &mk(false)).unwrap();
        let fo = airborne_position(icao, &mk(true)).unwrap();
        let (_, e) = me_of_frame(&fe);
        let (_, o) = me_of_frame(&fo);
        let (Me::AirbornePosition(e), Me::AirbornePosition(o)) = (e, o) else { panic!() };
        prop_assert_eq!(e.typecode, tc);
        prop_assert_eq!(e.nic_b, nic_b);
        let want_alt = alt.map(|a| (a + 1000 + 12).div_euclid(25) * 25 - 1000);
        let got_alt = if tc >= 20 { e.altitude_gnss_ft } else { e.altitude_baro_ft };
        prop_assert_eq!(got_alt, want_alt);
        match crate::modes::cpr::global_airborne(e.cpr, o.cpr, true) {
            Ok((dl, dn)) => {
                prop_assert!((dl - lat).abs() < 1e-4, "{} {}", lat, dl);
                let d = (dn - lon + 540.0).rem_euclid(360.0) - 180.0;
                // Half a CPR step of the odd longitude zone (widest near the poles) plus margin.
                let ni = f64::from(crate::modes::cpr::nl(dl).saturating_sub(1).max(1));
                prop_assert!(d.abs() < 0.6 * 360.0 / ni / 131_072.0 + 1e-9, "{} {}", lon, dn);
            }
            // Only a point within one CPR step of an NL transition can straddle it.
            Err(_) => prop_assert!(crate::modes::cpr::nl(lat + 1e-3) != crate::modes::cpr::nl(lat - 1e-3)),
        }
    }

    #[test]
    fn velocity_round_trip(
        ve in -4000i32..4000, vn in -4000i32..4000, vr in proptest::option::of(-32_000i32..32_000),
        baro in any::<bool>(), nacv in 0u8..8,
    ) {
        let f = velocity_ground(0xABCDEF, ve, vn, vr, baro, nacv).unwrap();
        let (_, me) = me_of_frame(&f);
        let Me::Velocity(v) = me else { panic!() };
        let scale = if ve.abs().max(vn.abs()) > 1021 { 4 } else { 1 };
        let q = |x: i32| x.signum() * ((x.abs() + scale / 2) / scale) * scale;
        prop_assert_eq!(v.v_east_kt, Some(q(ve)));
        prop_assert_eq!(v.v_north_kt, Some(q(vn)));
        prop_assert_eq!(v.vertical_rate_fpm, vr.map(|r| r.signum() * ((f64::from(r.abs()) / 64.0).round() as i32) * 64));
        prop_assert_eq!(v.vertical_rate_source, if baro { VerticalRateSource::Baro } else { VerticalRateSource::Gnss });
        prop_assert_eq!(v.nac_v, nacv);
    }

    #[test]
    fn airspeed_round_trip(hdg in proptest::option::of(0.0f64..360.0), as_kt in 0u32..4000, tas in any::<bool>()) {
        let f = velocity_air(0x123456, hdg, as_kt, tas, None, true).unwrap();
        let (_, me) = me_of_frame(&f);
        let Me::Velocity(v) = me else { panic!() };
        let scale = if as_kt > 1021 { 4 } else { 1 };
        prop_assert_eq!(v.airspeed_kt, Some((as_kt + scale / 2) / scale * scale));
        prop_assert_eq!(v.airspeed_true, tas);
        match (hdg, v.heading_deg) {
            (Some(h), Some(d)) => prop_assert!(((d - h + 540.0).rem_euclid(360.0) - 180.0).abs() <= 360.0 / 2048.0 + 1e-9),
            (None, None) => {}
            other => prop_assert!(false, "{:?}", other),
        }
    }

    #[test]
    fn opstatus_round_trip(nic_a in any::<bool>(), nacp in 0u8..12, gva in 0u8..4, sil in 0u8..4, ps in any::<bool>(), nb in any::<bool>(), hrd in any::<bool>()) {
        let s = OperationalStatusFields { version: 2, nic_a, nac_p: nacp, gva, sil, sil_per_sample: ps, nic_baro: nb, hrd_magnetic: hrd };
        let f = operational_status(0x400159, &s).unwrap();
        let (_, me) = me_of_frame(&f);
        let Me::OperationalStatus(o) = me else { panic!() };
        prop_assert_eq!((o.version, o.nic_a, o.nac_p, o.gva, o.sil), (2, Some(nic_a), Some(nacp), Some(gva), Some(sil)));
        prop_assert_eq!((o.sil_per_sample, o.nic_baro, o.hrd_magnetic), (Some(ps), Some(nb), Some(hrd)));
    }

    #[test]
    fn df11_round_trip(icao in 0u32..0x100_0000, ca in 0u8..8, ii in 0u8..128) {
        let f = df11(ca, icao, ii).unwrap();
        let m = decode(&f, DecodeOptions::default()).unwrap();
        prop_assert_eq!(m.icao, icao);
        prop_assert_eq!(m.content, Content::AllCall { capability: ca });
        prop_assert_eq!(m.parity, if ii == 0 { Parity::Verified } else { Parity::Interrogator(ii) });
    }
}
