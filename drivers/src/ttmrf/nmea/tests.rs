//! NMEA tests: the classic reference sentences (checksums as published, re-derived by XOR), hand
//! built ones for every field, corrupted, truncated, split and random input.

use approx::assert_relative_eq;

use super::*;
use crate::decode_slice;
use crate::testkit::{
    XorShift, assert_split_invariant, assert_survives_random, decode_chunked, flip_bits,
};

const GGA: &str = "$GPGGA,123519,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,*47";
const RMC: &str = "$GPRMC,123519,A,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,W*6A";
const VTG: &str = "$GPVTG,054.7,T,034.4,M,005.5,N,010.2,K*48";
const GSA: &str = "$GPGSA,A,3,04,05,,09,12,,,24,,,,,2.5,1.3,2.1*39";
const ZDA: &str = "$GPZDA,201530.00,04,07,2002,00,00*60";

fn body(s: &str) -> NmeaBody {
    parse_sentence(s.as_bytes())
        .unwrap_or_else(|e| panic!("{e}: {s}"))
        .body
}

#[test]
fn gga() {
    let NmeaBody::Gga(g) = body(GGA) else {
        panic!()
    };
    // 12:35:19 = 45319 s; 48 deg 07.038' = 48.1173 deg; 11 deg 31.000' = 11.516666... deg.
    assert_eq!(g.time_s, Some(45319.0));
    assert_relative_eq!(g.lat_deg.unwrap(), 48.1173, epsilon = 1e-12);
    assert_relative_eq!(g.lon_deg.unwrap(), 11.0 + 31.0 / 60.0, epsilon = 1e-12);
    assert_eq!(
        (g.quality, g.satellites, g.hdop),
        (Some(1), Some(8), Some(0.9))
    );
    assert_eq!((g.alt_msl_m, g.geoid_sep_m), (Some(545.4), Some(46.9)));
    assert_relative_eq!(g.alt_wgs84_m().unwrap(), 592.3, epsilon = 1e-9);
    assert_eq!((g.dgps_age_s, g.dgps_station), (None, None));
}

#[test]
fn rmc() {
    let s = parse_sentence(RMC.as_bytes()).unwrap();
    assert_eq!(s.talker, "GP");
    let NmeaBody::Rmc(r) = s.body else { panic!() };
    assert_eq!(r.valid, Some(true));
    assert_eq!((r.speed_kt, r.course_deg), (Some(22.4), Some(84.4)));
    assert_eq!(
        r.date,
        Some(Date {
            year: 1994,
            month: 3,
            day: 23
        })
    );
    assert_eq!(r.mag_var_deg, Some(-3.1), "west is negative");
    assert_eq!(r.mode, None);
    // A receiver without fix (NMEA 2.3 mode N), just before midnight with a 20xx date.
    let NmeaBody::Rmc(r) = body("$GNRMC,235959.99,V,,,,,,,311226,,,N*67") else {
        panic!()
    };
    assert_eq!(r.valid, Some(false));
    assert_eq!(r.lat_deg, None);
    assert_relative_eq!(r.time_s.unwrap(), 86399.99, epsilon = 1e-9);
    assert_eq!(
        r.date,
        Some(Date {
            year: 2026,
            month: 12,
            day: 31
        })
    );
    assert_eq!(r.mode, Some('N'));
}

#[test]
fn vtg_gsa_zda() {
    let NmeaBody::Vtg(v) = body(VTG) else {
        panic!()
    };
    assert_eq!(
        (v.course_true_deg, v.course_mag_deg),
        (Some(54.7), Some(34.4))
    );
    assert_eq!(
        (v.speed_kt, v.speed_kmh, v.mode),
        (Some(5.5), Some(10.2), None)
    );
    let NmeaBody::Gsa(g) = body(GSA) else {
        panic!()
    };
    assert_eq!((g.selection, g.fix_type), (Some('A'), Some(3)));
    assert_eq!(g.prns, vec![4, 5, 9, 12, 24]);
    assert_eq!(
        (g.pdop, g.hdop, g.vdop, g.system_id),
        (Some(2.5), Some(1.3), Some(2.1), None)
    );
    let NmeaBody::Zda(z) = body(ZDA) else {
        panic!()
    };
    assert_eq!(z.time_s, Some(72930.0));
    assert_eq!(
        z.date,
        Some(Date {
            year: 2002,
            month: 7,
            day: 4
        })
    );
    assert_eq!((z.zone_hours, z.zone_minutes), (Some(0), Some(0)));
}

fn with_cs(body: &str) -> String {
    format!("${body}*{:02X}", checksum(body.as_bytes()))
}

#[test]
fn hand_built_south_west_and_errors() {
    let NmeaBody::Gga(g) = body(&with_cs(
        "GNGGA,000000.5,3345.500,S,07030.250,W,4,12,0.6,-10.0,M,-20.5,M,1.5,0042",
    )) else {
        panic!()
    };
    assert_eq!(g.time_s, Some(0.5));
    assert_relative_eq!(g.lat_deg.unwrap(), -(33.0 + 45.5 / 60.0), epsilon = 1e-12);
    assert_relative_eq!(g.lon_deg.unwrap(), -(70.0 + 30.25 / 60.0), epsilon = 1e-12);
    assert_eq!(
        (g.quality, g.dgps_age_s, g.dgps_station),
        (Some(4), Some(1.5), Some(42))
    );
    // Lower-case checksum digits are accepted; the sentence itself is case-sensitive.
    assert!(parse_sentence(RMC.replace("*6A", "*6a").as_bytes()).is_ok());
    assert!(parse_sentence(RMC.to_lowercase().as_bytes()).is_err());
    // Errors by kind.
    assert!(matches!(
        parse_sentence(GGA.replace("*47", "*48").as_bytes()),
        Err(NmeaError::Checksum { .. })
    ));
    assert!(matches!(
        parse_sentence(b"$GPGSV,3,1,11,03,03,111,00*4A"),
        Err(NmeaError::UnknownType(_))
    ));
    assert!(matches!(
        parse_sentence(with_cs("GPGGA,126019,,,,,0").as_bytes()),
        Err(NmeaError::Field("time"))
    ));
    assert!(matches!(
        parse_sentence(with_cs("GPGGA,,9107.0,N,,,0").as_bytes()),
        Err(NmeaError::Field("lat"))
    ));
    assert!(matches!(
        parse_sentence(with_cs("GPGGA,,4807.0,E,,,0").as_bytes()),
        Err(NmeaError::Field("lat"))
    ));
    assert!(matches!(
        parse_sentence(with_cs("GPGGA,,4860.0,N,,,0").as_bytes()),
        Err(NmeaError::Field("lat"))
    ));
    assert!(matches!(
        parse_sentence(with_cs("GPRMC,,X").as_bytes()),
        Err(NmeaError::Field("status"))
    ));
    assert!(matches!(
        parse_sentence(with_cs("GPZDA,,04,13,2002").as_bytes()),
        Err(NmeaError::Field("date"))
    ));
    assert!(matches!(
        parse_sentence(b"$GPGGA,1"),
        Err(NmeaError::Framing)
    ));
}

#[test]
fn impossible_values_are_refused_at_their_limits() {
    // Each limit (issue 24) just inside and just past: altitude 130,000 ft = 39,624 m (and
    // -2,000 ft = -609.6 m), geoid separation 200 m, HDOP 0..100, speed 2,200 m/s =
    // 4,276.46 kt, course 0..360 deg. GGA, RMC and VTG each check their own.
    let gga = |alt: &str, sep: &str, hdop: &str| {
        with_cs(&format!(
            "GPGGA,123519,4807.038,N,01131.000,E,1,08,{hdop},{alt},M,{sep},M,,"
        ))
    };
    let rmc = |kt: &str, course: &str| {
        with_cs(&format!(
            "GPRMC,123519,A,4807.038,N,01131.000,E,{kt},{course},230394,003.1,W"
        ))
    };
    let vtg = |course: &str, kt: &str| with_cs(&format!("GPVTG,{course},T,,M,{kt},N,,K"));
    let cases = [
        (gga("39624", "46.9", "0.9"), true),
        (gga("39624.1", "46.9", "0.9"), false),
        (gga("-609.6", "46.9", "0.9"), true),
        (gga("-609.7", "46.9", "0.9"), false),
        (gga("545.4", "-200", "0.9"), true),
        (gga("545.4", "200.1", "0.9"), false),
        (gga("545.4", "46.9", "100"), true),
        (gga("545.4", "46.9", "100.1"), false),
        (rmc("4276.4", "360"), true),
        (rmc("4276.5", "084.4"), false),
        (rmc("022.4", "360.1"), false),
        (vtg("0", "4276.4"), true),
        (vtg("054.7", "4276.5"), false),
        (vtg("360.1", "005.5"), false),
    ];
    for (line, ok) in &cases {
        match parse_sentence(line.as_bytes()) {
            Ok(_) => assert!(ok, "{line}"),
            Err(NmeaError::InvalidValue(_)) => assert!(!ok, "{line}"),
            Err(e) => panic!("{line}: {e:?}"),
        }
    }
    // In a stream, each is dropped alone and counted as an invalid value; a field that does
    // not parse (latitude 91 deg) is malformed instead.
    let mut text = String::new();
    for (line, _) in &cases {
        text.push_str(line);
        text.push_str("\r\n");
    }
    text.push_str(&with_cs("GPGGA,,9107.0,N,,,0"));
    text.push_str("\r\n");
    let mut d = NmeaDecoder::new();
    let out = decode_slice(&mut d, text.as_bytes());
    assert_eq!(out.len(), 6);
    assert_eq!((d.stats().invalid_values, d.stats().malformed), (8, 1));
}

#[test]
fn a_time_too_short_or_a_number_not_finite_is_a_bad_field() {
    // Five digits are not hhmmss; Rust would parse "inf" and "NaN" as numbers.
    assert!(matches!(
        parse_sentence(
            with_cs("GPGGA,12351,4807.038,N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,").as_bytes()
        ),
        Err(NmeaError::Field("time"))
    ));
    for bad in ["inf", "NaN"] {
        let line = with_cs(&format!(
            "GPGGA,123519,4807.038,N,01131.000,E,1,08,{bad},545.4,M,46.9,M,,"
        ));
        assert!(
            matches!(parse_sentence(line.as_bytes()), Err(NmeaError::Field(_))),
            "{line}"
        );
    }
}

#[test]
fn angles_need_whole_minutes_and_their_hemisphere() {
    // ddmm and dddmm without decimals are whole minutes; fewer digits, or a value without its
    // hemisphere (or the reverse), is a bad field.
    let gga = |lat: &str, lon: &str| {
        parse_sentence(
            with_cs(&format!(
                "GPGGA,123519,{lat},{lon},1,08,0.9,545.4,M,46.9,M,,"
            ))
            .as_bytes(),
        )
    };
    let Ok(NmeaSentence {
        body: NmeaBody::Gga(g),
        ..
    }) = gga("4807,N", "01131,E")
    else {
        panic!()
    };
    assert_relative_eq!(g.lat_deg.unwrap(), 48.0 + 7.0 / 60.0, epsilon = 1e-12);
    assert_relative_eq!(g.lon_deg.unwrap(), 11.0 + 31.0 / 60.0, epsilon = 1e-12);
    for (lat, lon) in [
        ("480,N", "01131,E"),
        ("4807,N", "0113,E"),
        ("4807,", "01131,E"),
        (",N", "01131,E"),
        ("4807,N", ",E"),
    ] {
        assert!(
            matches!(gga(lat, lon), Err(NmeaError::Field(_))),
            "{lat} {lon}"
        );
    }
}

#[test]
fn rmc_and_zda_optional_fields_and_the_pole() {
    // RMC: an empty status is unknown (not an error); an easterly variation is positive.
    let NmeaBody::Rmc(r) = body(&with_cs(
        "GPRMC,123519,,4807.038,N,01131.000,E,022.4,084.4,230394,003.1,E",
    )) else {
        panic!()
    };
    assert_eq!((r.valid, r.mag_var_deg), (None, Some(3.1)));
    // A six-digit date only; ZDA with no date at all is no date.
    assert!(matches!(
        parse_sentence(with_cs("GPRMC,123519,A,,,,,,,2303940,,").as_bytes()),
        Err(NmeaError::Field("date"))
    ));
    let NmeaBody::Zda(z) = body(&with_cs("GPZDA,201530.00,,,,00,00")) else {
        panic!()
    };
    assert_eq!(z.date, None);
    // The pole itself is a latitude; past it is not.
    let NmeaBody::Gga(g) = body(&with_cs(
        "GPGGA,123519,9000.000,S,18000.000,W,1,08,0.9,545.4,M,46.9,M,,",
    )) else {
        panic!()
    };
    assert_eq!((g.lat_deg, g.lon_deg), (Some(-90.0), Some(-180.0)));
    assert!(matches!(
        parse_sentence(with_cs("GPGGA,123519,9000.001,N,,,1").as_bytes()),
        Err(NmeaError::Field("lat"))
    ));
}

#[test]
fn a_non_ascii_address_is_an_unknown_type_not_a_panic() {
    // Five bytes, but `é` straddles the talker/sentence split at byte 2.
    let line = with_cs("G\u{e9}GA,1");
    assert!(matches!(
        parse_sentence(line.as_bytes()),
        Err(NmeaError::UnknownType(_))
    ));
}

fn stream() -> Vec<u8> {
    let mut s = String::from("junk");
    for line in [GGA, RMC, VTG, GSA, ZDA, "$GPGSV,3,1,11,03,03,111,00*4A"] {
        s.push_str(line);
        s.push_str("\r\n");
    }
    s.push_str("#A:whatever\r\n");
    s.push_str(&GGA.replace("*47", "*00"));
    s.push_str("\r\n");
    s.push_str(ZDA);
    s.into_bytes()
}

#[test]
fn stream_split_random_corrupt_truncated() {
    let bytes = stream();
    let mut d = NmeaDecoder::new();
    let msgs = decode_slice(&mut d, &bytes);
    assert_eq!(msgs.len(), 6);
    assert_eq!(
        (d.stats().unknown_types, d.stats().checksum_failures),
        (1, 1)
    );
    assert_split_invariant(NmeaDecoder::new, &bytes);
    assert_survives_random(NmeaDecoder::new, 77, 300, 1500);
    let mut rng = XorShift::new(9);
    let original = parse_sentence(GGA.as_bytes()).unwrap();
    for _ in 0..2000 {
        let mut b = format!("{GGA}\r\n").into_bytes();
        flip_bits(&mut b, 1, &mut rng);
        let (out, stats) = decode_chunked(NmeaDecoder::new(), &b, &[5]);
        crate::testkit::assert_accounting(&stats, b.len());
        for m in out {
            // XOR detects every single-bit error; only a case flip of a checksum digit survives.
            assert_eq!(m, original);
        }
    }
    for cut in 0..GGA.len() {
        let mut d = NmeaDecoder::new();
        assert!(decode_slice(&mut d, &GGA.as_bytes()[..cut]).is_empty());
    }
}

#[test]
fn encoder_reproduces_reference_sentences() {
    // Re-encoding gives the same values (formatting may differ: 5 decimals of minutes).
    for line in [GGA, RMC, VTG, GSA, ZDA] {
        let s = parse_sentence(line.as_bytes()).unwrap();
        let again = s.to_line();
        assert_eq!(
            parse_sentence(again.trim_end().as_bytes()).unwrap(),
            s,
            "{again}"
        );
    }
    // Fields are written in order with the unit letters in place.
    let vtg = parse_sentence(VTG.as_bytes()).unwrap().to_line();
    assert!(
        vtg.starts_with("$GPVTG,54.7,T,34.4,M,5.5,N,10.2,K,*"),
        "{vtg}"
    );
}

#[test]
fn minutes_that_round_up_to_60_carry_into_the_degrees() {
    // 47.9999999999 deg is 47 deg 59.999999994 min; at 5 decimals that is 60.00000 min, written
    // as 48 deg 00.00000 min (and never as "4760.00000"). The same for a westerly longitude
    // with three degree digits; a value that does not round up is left alone.
    let gga = |lat: f64, lon: f64| {
        NmeaSentence {
            talker: "GP".into(),
            body: NmeaBody::Gga(Gga {
                lat_deg: Some(lat),
                lon_deg: Some(lon),
                ..Default::default()
            }),
        }
        .to_line()
    };
    let line = gga(47.9999999999, -11.9999999999);
    assert!(
        line.starts_with("$GPGGA,,4800.00000,N,01200.00000,W,"),
        "{line}"
    );
    // 47.99999 deg = 47 deg 59.9994 min.
    let line = gga(47.99999, -0.5);
    assert!(
        line.starts_with("$GPGGA,,4759.99940,N,00030.00000,W,"),
        "{line}"
    );
}

mod round_trip {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn gga_rmc_round_trip(
            t in 0u32..8_640_000,
            lat in -90_000_000i64..=90_000_000,
            lon in -180_000_000i64..=180_000_000,
            alt in -500i32..9000,
            sats in 0u8..40,
            day in 1u8..29, month in 1u8..13, year in 1980u16..2080,
        ) {
            let time_s = Some(f64::from(t) / 100.0);
            let (lat_deg, lon_deg) = (Some(lat as f64 / 1e6), Some(lon as f64 / 1e6));
            let gga = NmeaSentence {
                talker: "GN".into(),
                body: NmeaBody::Gga(Gga { time_s, lat_deg, lon_deg, quality: Some(1), satellites: Some(sats), alt_msl_m: Some(f64::from(alt)), ..Default::default() }),
            };
            let back = parse_sentence(gga.to_line().trim_end().as_bytes()).unwrap();
            let (NmeaBody::Gga(a), NmeaBody::Gga(b)) = (&back.body, &gga.body) else { unreachable!() };
            // 1e-5 minutes = 1.7e-7 degrees.
            prop_assert!((a.lat_deg.unwrap() - b.lat_deg.unwrap()).abs() < 2e-7);
            prop_assert!((a.lon_deg.unwrap() - b.lon_deg.unwrap()).abs() < 2e-7);
            prop_assert!((a.time_s.unwrap() - b.time_s.unwrap()).abs() < 1e-6);
            prop_assert_eq!((a.satellites, a.alt_msl_m, a.quality), (b.satellites, b.alt_msl_m, b.quality));
            let rmc = NmeaSentence {
                talker: "GP".into(),
                body: NmeaBody::Rmc(Rmc { time_s, valid: Some(true), date: Some(Date { year, month, day }), mag_var_deg: Some(-3.5), ..Default::default() }),
            };
            let back = parse_sentence(rmc.to_line().trim_end().as_bytes()).unwrap();
            let NmeaBody::Rmc(r) = back.body else { unreachable!() };
            prop_assert_eq!(r.date, Some(Date { year, month, day }));
            prop_assert_eq!(r.mag_var_deg, Some(-3.5));
        }
    }
}
