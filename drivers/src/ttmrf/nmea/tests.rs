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
