//! JSON tests: the manual's examples (OCR repaired as noted), hand-built messages for every
//! section and field, ordering/unknown-field/version rules, framing under corruption, splits and
//! random input.

use approx::assert_relative_eq;

use super::*;
use crate::decode_slice;
use crate::testkit::{
    XorShift, assert_split_invariant, assert_survives_random, decode_chunked, flip_bits,
};
use crate::traffic::{AddressType, SourceTime};

/// Manual 7.2.1 ADS-B example. OCR repairs (each restores plain JSON syntax, no value guessed):
/// `""groundState"` -> `"groundState"`, `"updVeloV'"` -> `"updVeloV"`, `"velV": O` -> `0`,
/// `"approach'"` -> `"approach"`, `}l` -> `},`, and `"nav_heading": 151.` / `17,` (split across a
/// page break) -> `151.17,`. The closing `}]}` lost at the page end is restored.
const MANUAL_ADSB: &str = r#"{"src":"33-0000683","ts":69061337,"ver":1,"adsb":[{"icao":"780A3F","flags":{"groundState":false,"updAltBaro":true,"updAltGeo":true,"updPosition":true,"updTrack":true,"updVeloH":true,"updVeloV":true},"sigStr":-67,"sigQ":9,"lat":34.39696,"lon":-85.1055,"altBaro":35000,"geoAlt":36975,"track":143.78,"velH":528,"velV":0,"mag_heading":123.1,"true_heading":125.5,"ias":100,"tas":100,"roll":2.1,"nav_qnh":1013.59,"nav_altitude_mcp":35008,"nav_altitude_fms":35008,"nav_modes":{"althold":false,"approach":false,"autopilot":false,"lnav":false,"tcas":true,"vnav":false},"nav_heading":151.17,"call":"CPA3174","ecat":5,"squawk":"5730","nacp":9,"nacv":1,"nicBaro":1,"nic":8}]}"#;

/// Manual 10.2.1 UAT example. OCR repairs: `'"groundState"` -> `"groundState"`, `"updVeloV'"`,
/// `"acasOperational'`, `"identActive'"` -> plain keys, `} r` / `} !` -> `},`, `"edti"` ->
/// `"cdti"` (table 39: "CDTI Traffic Display Capability"), `"No6lZP"` -> `"N61ZP"` (table 40's
/// example callsign). Closing brackets lost at the page end restored.
const MANUAL_UAT: &str = r#"{"src":"33-0000687","ts":69061337,"ver":1,"uat":[{"icao":"777888","flags":{"groundState":false,"updAltBaro":false,"updPosition":false,"updTrack":false,"updVeloH":false,"updVeloV":false,"updAltGeo":false},"squawk":7232,"call":"N61ZP","lat":90.0000,"lon":180.0000,"altBaro":150,"track":142,"velH":10,"velV":60,"sigStr":0,"sigQ":0,"fps":11,"nicnac":{"nacP":0,"nacv":0,"nicBaro":0},"altGeo":150,"ecat":14,"emergency":0,"uatFlags":{"utcCoupling":false,"cdti":false,"acasOperational":false,"acasActive":false,"identActive":false,"atcActive":false,"headingMagnetic":false,"reservedMS1":0}}]}"#;

/// Manual 8.2.1 FLARM example (no OCR damage).
const MANUAL_FLARM: &str = r#"{"src":"ID-0000001","ts":69061337,"ver":1,"flarm":[{"idType":1,"id":"DABABE","type":13,"danger":1,"lat":53.42854,"lon":14.55281,"alt":1725,"track":72.18,"hvelo":10.5,"vVelo":50,"movMode":5,"stealth":1,"notrack":1}]}"#;

/// Manual 9.2.2 GNSS example. OCR repairs: `"ﬁx" : l'` -> `"fix":1`, `499.¢` -> `499.6` (table
/// 32's example value), `"gndSpeed": | 5.2, 2.1 ]` -> `[5.2,2.1]`, `"acec"` -> `"acc"` (table 32).
const MANUAL_GNSS: &str = r#"{"src":"ID-0000001","ts":69061337,"ver":1,"gnss":{"fix":1,"lat":53.42854,"lon":14.55281,"altWgs84":499.6,"altMsl":508.6,"track":127.3,"hvelo":10.5,"vVelo":25,"gndSpeed":[5.2,2.1],"acc":{"lat":5.2,"lon":2.1,"alt":3.6},"nacp":12,"nacv":2,"nic":12}}"#;

/// Manual 7.2.2 raw example (closing brackets lost at the page end restored).
const MANUAL_RAW: &str =
    r#"{"src":"ID-0000001","ts":69061337,"ver":1,"raw":[["18A9725A4C842D",-78,2,"295CAB573A77"]]}"#;

/// Manual 6.6.1 status example (closing braces lost at the page end restored).
const MANUAL_STATUS: &str =
    r#"{"src":"ID-0000001","ts":69061337,"ver":1,"status":{"fw":"30903679 (Jan 15 2021)"}}"#;

fn parse(s: &str) -> JsonMessage {
    parse_message(s.as_bytes()).unwrap_or_else(|e| panic!("{e}: {s}"))
}

#[test]
fn manual_adsb_example() {
    let m = parse(MANUAL_ADSB);
    assert_eq!(m.src.as_deref(), Some("33-0000683"));
    // 69061337 ms = 19:11:01.337 (table 10).
    assert_eq!(m.ts_ms, Some(69_061_337));
    assert_eq!(m.ts_ms.unwrap(), ((19 * 60 + 11) * 60 + 1) * 1000 + 337);
    assert_eq!(m.adsb.len(), 1);
    let a = &m.adsb[0];
    assert_eq!(a.icao, 0x780A3F);
    let f = a.flags.unwrap();
    assert_eq!(f.on_ground, Some(false));
    assert_eq!(f.upd_velo_v, Some(true));
    assert_eq!((a.sig_dbm, a.sig_q_db), (Some(-67.0), Some(9.0)));
    assert_eq!((a.lat_deg, a.lon_deg), (Some(34.39696), Some(-85.1055)));
    assert_eq!(
        (a.alt_baro_ft, a.alt_geo_ft),
        (Some(35000.0), Some(36975.0))
    );
    assert_eq!(
        (a.track_deg, a.velh_kt, a.velv_fpm),
        (Some(143.78), Some(528.0), Some(0.0))
    );
    assert_eq!(
        (a.mag_heading_deg, a.true_heading_deg),
        (Some(123.1), Some(125.5))
    );
    assert_eq!(
        (a.ias_kt, a.tas_kt, a.roll_deg),
        (Some(100.0), Some(100.0), Some(2.1))
    );
    assert_eq!(a.nav_qnh_hpa, Some(1013.59));
    assert_eq!(
        (a.nav_altitude_mcp_ft, a.nav_altitude_fms_ft),
        (Some(35008.0), Some(35008.0))
    );
    assert_eq!(a.nav_modes.unwrap().tcas, Some(true));
    assert_eq!(a.nav_modes.unwrap().lnav, Some(false));
    assert_eq!(a.nav_heading_deg, Some(151.17));
    assert_eq!(a.callsign.as_deref(), Some("CPA3174"));
    assert_eq!(a.ecat, Some(5));
    assert_eq!(a.squawk, Some(5730));
    assert_eq!(
        (a.nac_p, a.nac_v, a.nic_baro, a.nic),
        (Some(9), Some(1), Some(1), Some(8))
    );

    let t = &m.traffic_reports()[0];
    assert_eq!(t.address_hex(), "780A3F");
    assert_eq!(t.protocol, Protocol::Json);
    // 35000 ft * 0.3048 = 10668 m; 36975 ft = 11269.98 m; 528 kt = 271.626666... m/s.
    assert_relative_eq!(t.alt_pressure_m.unwrap(), 10668.0, epsilon = 1e-9);
    assert_relative_eq!(t.alt_geometric_m.unwrap(), 11269.98, epsilon = 1e-9);
    assert_relative_eq!(
        t.ground_speed_mps.unwrap(),
        271.626_666_666_666_7,
        epsilon = 1e-9
    );
    assert_eq!(t.vertical_rate_mps, Some(0.0));
    assert_eq!(t.heading_deg, Some(125.5));
    assert_eq!(
        t.source_time,
        Some(SourceTime::MsSinceUtcMidnight(69_061_337))
    );
    assert_eq!((t.nic, t.nac_p, t.nac_v), (Some(8), Some(9), Some(1)));
}

#[test]
fn manual_uat_example() {
    let m = parse(MANUAL_UAT);
    let u = &m.uat[0];
    assert_eq!(u.icao, 0x777888);
    assert_eq!(u.squawk, Some(7232), "a number in this example");
    assert_eq!(u.callsign.as_deref(), Some("N61ZP"));
    assert_eq!((u.lat_deg, u.lon_deg), (Some(90.0), Some(180.0)));
    assert_eq!((u.alt_baro_ft, u.alt_geo_ft), (Some(150.0), Some(150.0)));
    assert_eq!(
        (u.track_deg, u.velh_kt, u.velv_fpm),
        (Some(142.0), Some(10.0), Some(60.0))
    );
    assert_eq!(
        (u.sig_dbm, u.sig_q_errors, u.fps),
        (Some(0.0), Some(0.0), Some(11))
    );
    let nn = u.nicnac.unwrap();
    assert_eq!(
        (nn.nac_p, nn.nac_v, nn.nic_baro),
        (Some(0), Some(0), Some(0))
    );
    assert_eq!((u.ecat, u.emergency), (Some(14), Some(0)));
    let uf = u.uat_flags.unwrap();
    assert_eq!(uf.cdti, Some(false));
    assert_eq!(uf.heading_magnetic, Some(false));
    let t = &m.traffic_reports()[0];
    assert_eq!(t.link, Link::Uat978);
    assert!(!t.flags.emergency);
    // 60 ft/min * 0.00508 = 0.3048 m/s.
    assert_relative_eq!(t.vertical_rate_mps.unwrap(), 0.3048, epsilon = 1e-12);
}

#[test]
fn the_manual_targets_map_to_whole_traffic_reports() {
    // Every field of the common report, from the manual's ADS-B example (with a climb of
    // -640 fpm instead of 0, so the rate's scale shows) and its UAT example (with a magnetic
    // heading flag off, IDENT on, emergency 1). Units by their definitions: 1 ft = 0.3048 m,
    // 1 kt = 1852 m/h, 1 fpm = 0.00508 m/s.
    let t = SourceTime::MsSinceUtcMidnight(69_061_337);
    let adsb = parse(&MANUAL_ADSB.replace(r#""velV":0"#, r#""velV":-640"#));
    let want = TrafficReport {
        link: Link::Adsb1090,
        protocol: Protocol::Json,
        address: 0x780A3F,
        address_type: AddressType::Icao,
        callsign: Some("CPA3174".into()),
        squawk: Some(5730),
        emitter_category: Some(5),
        lat_deg: Some(34.39696),
        lon_deg: Some(-85.1055),
        alt_pressure_m: Some(35000.0 * 0.3048),
        alt_geometric_m: Some(36975.0 * 0.3048),
        track_deg: Some(143.78),
        heading_deg: Some(125.5),
        ground_speed_mps: Some(528.0 * (1852.0 / 3600.0)),
        vertical_rate_mps: Some(-640.0 * 0.00508),
        nic: Some(8),
        nac_p: Some(9),
        nac_v: Some(1),
        signal_dbm: Some(-67.0),
        source_time: Some(t),
        ..Default::default()
    };
    assert_eq!(adsb.traffic_reports(), vec![want]);

    let uat = parse(
        &MANUAL_UAT
            .replace(r#""identActive":false"#, r#""identActive":true"#)
            .replace(r#""emergency":0"#, r#""emergency":1"#)
            .replace(r#""groundState":false"#, r#""groundState":true"#)
            .replace(r#""sigStr":0"#, r#""sigStr":-71"#)
            .replace(r#""nacP":0"#, r#""nacP":9"#),
    );
    let want = TrafficReport {
        link: Link::Uat978,
        protocol: Protocol::Json,
        address: 0x777888,
        address_type: AddressType::Icao,
        callsign: Some("N61ZP".into()),
        squawk: Some(7232),
        emitter_category: Some(14),
        lat_deg: Some(90.0),
        lon_deg: Some(180.0),
        alt_pressure_m: Some(150.0 * 0.3048),
        alt_geometric_m: Some(150.0 * 0.3048),
        track_deg: Some(142.0),
        ground_speed_mps: Some(10.0 * (1852.0 / 3600.0)),
        vertical_rate_mps: Some(60.0 * 0.00508),
        nac_p: Some(9),
        nac_v: Some(0),
        signal_dbm: Some(-71.0),
        emergency_code: Some(1),
        flags: TrafficFlags {
            on_ground: true,
            ident: true,
            emergency: true,
            ..Default::default()
        },
        source_time: Some(t),
        ..Default::default()
    };
    assert_eq!(uat.traffic_reports(), vec![want]);

    // FLARM: metres and m/s already; type 13 is emitter category 14 (see `flarm_category`).
    let want = TrafficReport {
        link: Link::Flarm,
        protocol: Protocol::Json,
        address: 0xDABABE,
        address_type: AddressType::Icao,
        emitter_category: Some(14),
        lat_deg: Some(53.42854),
        lon_deg: Some(14.55281),
        alt_geometric_m: Some(1725.0),
        track_deg: Some(72.18),
        ground_speed_mps: Some(10.5),
        vertical_rate_mps: Some(50.0),
        flarm_alarm_level: Some(1),
        source_time: Some(t),
        ..Default::default()
    };
    assert_eq!(parse(MANUAL_FLARM).traffic_reports(), vec![want]);
}

#[test]
fn manual_flarm_example() {
    let m = parse(MANUAL_FLARM);
    let f = &m.flarm[0];
    assert_eq!(f.id_type, Some(1));
    assert_eq!(f.id, 0xDABABE);
    assert_eq!(f.aircraft_type, Some(13));
    assert_eq!(f.alarm_level, Some(1));
    assert_eq!((f.lat_deg, f.lon_deg), (Some(53.42854), Some(14.55281)));
    assert_eq!(f.alt_m, Some(1725.0));
    assert_eq!(f.track_deg, Some(72.18));
    assert_eq!(f.velh_mps, Some(10.5), "example spells it 'hvelo'");
    assert_eq!(f.velv_mps, Some(50.0));
    assert_eq!(f.move_mode, Some(5));
    assert_eq!((f.stealth, f.notrack), (Some(1), Some(1)));
    let t = &m.traffic_reports()[0];
    assert_eq!(t.link, Link::Flarm);
    assert_eq!(t.address_type, AddressType::Icao);
    assert_eq!(t.emitter_category, Some(14));
    assert_eq!(t.flarm_alarm_level, Some(1));
    assert_eq!(t.alt_geometric_m, Some(1725.0));
    assert_eq!(t.ground_speed_mps, Some(10.5), "already m/s");
}

#[test]
fn manual_gnss_raw_status_examples() {
    let g = parse(MANUAL_GNSS).gnss.unwrap();
    assert_eq!(g.fix, Some(1));
    assert_eq!((g.alt_wgs84_m, g.alt_msl_m), (Some(499.6), Some(508.6)));
    assert_eq!(
        (g.track_deg, g.velh_kt, g.velv_mps),
        (Some(127.3), Some(10.5), Some(25.0))
    );
    assert_eq!(g.gnd_speed_en_kt, Some([5.2, 2.1]));
    assert_eq!(g.acc.unwrap().alt_m, Some(3.6));
    assert_eq!((g.nac_p, g.nac_v, g.nic), (Some(12), Some(2), Some(12)));

    let r = parse(MANUAL_RAW).raw;
    assert_eq!(r.len(), 1);
    assert_eq!(r[0].frame_hex, "18A9725A4C842D");
    assert_eq!(
        r[0].frame_bytes().unwrap(),
        [0x18, 0xA9, 0x72, 0x5A, 0x4C, 0x84, 0x2D]
    );
    assert_eq!((r[0].sig_dbm, r[0].sig_q_db), (Some(-78.0), Some(2.0)));
    // Table 23: 0x295CAB573A77 ns "translates to 12:37:57.988350583".
    let ns = r[0].ts_ns.unwrap();
    assert_eq!(ns, 0x295C_AB57_3A77);
    assert_eq!(
        ns,
        ((12 * 3600 + 37 * 60 + 57) * 1_000_000_000u64) + 988_350_583
    );
    assert_eq!(
        r[0].source_time(),
        Some(SourceTime::NsSinceUtcMidnight(45_477_988_350_583))
    );
    // The time is hex digits, 64 bits at most (leading zeros are fine); anything else is a
    // malformed entry, not a guess.
    let ts = |t: &str| {
        parse_message(format!(r#"{{"ver":1,"raw":[["18A9725A4C842D",-78,2,"{t}"]]}}"#).as_bytes())
            .map(|m| m.raw[0].ts_ns)
    };
    assert_eq!(ts("0000000000000000001F").unwrap(), Some(31));
    assert_eq!(ts("FFFFFFFFFFFFFFFF").unwrap(), Some(u64::MAX));
    for bad in ["", "+1F", "-1", "1G", "10000000000000000"] {
        assert!(ts(bad).is_err(), "{bad:?}");
    }

    let s = parse(MANUAL_STATUS).status.unwrap();
    assert_eq!(s.fw.as_deref(), Some("30903679 (Jan 15 2021)"));
}

#[test]
fn pretty_printed_manual_layout_parses() {
    // The manual prints messages indented; parse_message accepts any whitespace.
    let pretty = "{\n  \"ver\": 1,\n  \"src\": \"ID-0000001\",\n  \"status\": { \"fw\": \"x\" }\n}";
    assert_eq!(parse(pretty).status.unwrap().fw.as_deref(), Some("x"));
}

#[test]
fn order_free_unknown_ignored_omitted_unknown() {
    let m = parse(
        r#"{"adsb":[{"nic":2,"future":{"x":[1,2]},"icao":"00abcd"}],"ver":1,"newSection":{}}"#,
    );
    assert_eq!(m.src, None);
    assert_eq!(m.ts_ms, None, "ts omitted = unknown");
    let a = &m.adsb[0];
    assert_eq!(a.icao, 0x00ABCD);
    assert_eq!(a.nic, Some(2));
    assert_eq!(a.lat_deg, None);
    assert_eq!(a.squawk, None);
    let t = &m.traffic_reports()[0];
    assert_eq!(t.source_time, None);
    assert_eq!(t.address_hex(), "00ABCD");
    // Padded and empty callsigns.
    let m = parse(r#"{"ver":1,"adsb":[{"icao":"1","call":"SAS1    "},{"icao":"2","call":"   "}]}"#);
    let t = m.traffic_reports();
    assert_eq!(t[0].callsign.as_deref(), Some("SAS1"));
    assert_eq!(t[1].callsign, None);
}

#[test]
fn version_and_range_rules() {
    assert!(matches!(
        parse_message(br#"{"ver":2,"adsb":[]}"#),
        Err(JsonError::Version(2))
    ));
    assert!(matches!(
        parse_message(br#"{"src":"x"}"#),
        Err(JsonError::NoVersion)
    ));
    assert!(matches!(
        parse_message(br#"{"ver":1,"ts":86401000}"#),
        Err(JsonError::Range("ts"))
    ));
    // Issue 24: an impossible target is dropped alone and counted, not the whole message.
    let m =
        parse_message(br#"{"ver":1,"flarm":[{"id":"1","lat":91},{"id":"2","lat":47}]}"#).unwrap();
    assert_eq!(m.flarm.len(), 1);
    assert_eq!(m.flarm[0].id, 2);
    assert_eq!(m.invalid_records, 1);
    assert!(
        parse_message(br#"{"ver":1,"adsb":[{"nic":1}]}"#).is_err(),
        "icao is required"
    );
    assert!(parse_message(br#"{"ver":1,"adsb":[{"icao":"1234567"}]}"#).is_err());
    assert!(parse_message(br#"{"ver":1,"adsb":[{"icao":"1","squawk":"7800"}]}"#).is_err());
    assert!(parse_message(br#"{"ver":1,"raw":[["XYZ",1,2,"1"]]}"#).is_err());
    // A raw entry may grow fields; missing trailing ones are unknown.
    let m = parse(
        r#"{"ver":1,"raw":[["5D4B18FFFC710B",-70],["8D4CA7E858B9838206BA422BBD7B",-71,4,"75BCD15",9]]}"#,
    );
    assert_eq!(m.raw[0].sig_q_db, None);
    assert_eq!(m.raw[1].ts_ns, Some(123_456_789));

    let mut d = JsonDecoder::new();
    let stream = br#"{"ver":2,"adsb":[]}
{"ver":1}
{"src":1}
"#;
    let msgs = decode_slice(&mut d, stream);
    assert_eq!(msgs.len(), 1);
    assert_eq!(d.stats().unsupported_version, 1);
    assert_eq!(d.stats().malformed, 1);
}

#[test]
fn each_impossible_gnss_value_drops_the_gnss_section_alone() {
    // The manual's GNSS example with one value past its limit at a time (latitude 90 deg,
    // longitude 180 deg, altitude 130,000 ft = 39,624 m, speed 2,200 m/s = 4,276.4 kt, track
    // 360 deg, vertical rate 200 m/s): the section is dropped and counted; at the limit it is
    // kept.
    let with = |key: &str, v: &str| {
        let from = MANUAL_GNSS.find(&format!("\"{key}\":")).unwrap() + key.len() + 3;
        let to = from + MANUAL_GNSS[from..].find([',', '}']).unwrap();
        format!("{}{v}{}", &MANUAL_GNSS[..from], &MANUAL_GNSS[to..])
    };
    for (key, limit, past) in [
        ("lat", "-90", "-90.001"),
        ("lon", "180", "180.001"),
        ("altWgs84", "39624", "39624.1"),
        ("hvelo", "4276.4", "4276.5"),
        ("track", "360", "360.1"),
        ("vVelo", "-200", "-200.1"),
    ] {
        let m = parse_message(with(key, limit).as_bytes()).unwrap();
        assert!(m.gnss.is_some() && m.invalid_records == 0, "{key} {limit}");
        let m = parse_message(with(key, past).as_bytes()).unwrap();
        assert!(m.gnss.is_none() && m.invalid_records == 1, "{key} {past}");
    }
}

#[test]
fn impossible_targets_are_counted_across_the_sections() {
    // Two ADS-B targets (one at latitude 91), one UAT target at 91, one FLARM target: two kept
    // (the first ADS-B and the FLARM), two dropped.
    let m = parse_message(
        br#"{"ver":1,"adsb":[{"icao":"A1","lat":47},{"icao":"A2","lat":91}],"uat":[{"icao":"B1","lat":91}],"flarm":[{"id":"1","lat":47}]}"#,
    )
    .unwrap();
    assert_eq!((m.adsb.len(), m.uat.len(), m.flarm.len()), (1, 0, 1));
    assert_eq!(m.invalid_records, 2);
}

#[test]
fn hand_built_every_section_in_one_message() {
    let s = r#"{"src":"22-0000309","ts":1000,"ver":1,"status":{"fw":"2.77.5.0 (Mar 4 2025)"},"adsb":[{"icao":"4D240E","flags":{"groundState":true},"call":"SAS123","squawk":"7700"}],"uat":[{"icao":"A1B2C3","emergency":5,"uatFlags":{"identActive":true},"nicnac":{"nacP":8,"nacV":2,"nicBaro":1,"nic":7}}],"flarm":[{"idType":0,"id":"1600BF","type":1,"danger":3,"alt":300}],"gnss":{"fix":0},"raw":[["0363",-90,1,"2B5792B49315"]]}"#;
    let m = parse(s);
    let t = m.traffic_reports();
    assert_eq!(t.len(), 3);
    assert!(t[0].flags.on_ground);
    assert_eq!(t[0].squawk, Some(7700));
    assert_eq!(t[1].emergency_code, Some(5));
    let m2 = parse(
        r#"{"ver":1,"uat":[{"icao":"1","track":10,"uatFlags":{"headingMagnetic":true}},{"icao":"2","track":10}]}"#,
    );
    let t2 = m2.traffic_reports();
    assert_eq!((t2[0].track_deg, t2[1].track_deg), (None, Some(10.0)));
    assert!(t[1].flags.emergency && t[1].flags.ident);
    assert_eq!(
        (t[1].nac_p, t[1].nac_v, t[1].nic),
        (Some(8), Some(2), Some(7))
    );
    assert_eq!(t[2].address_type, AddressType::FlarmRandom);
    assert_eq!(t[2].emitter_category, Some(9));
    assert_eq!(t[2].flarm_alarm_level, Some(3));
    for r in &t {
        assert_eq!(r.source_time, Some(SourceTime::MsSinceUtcMidnight(1000)));
    }
    assert_eq!(m.gnss.unwrap().fix, Some(0));
    // Table 21: TS24h 2B5792B49315 = 47655.123456789 s.
    assert_eq!(m.raw[0].ts_ns, Some(47_655_123_456_789));
}

fn stream() -> Vec<u8> {
    let mut s = String::new();
    for (i, m) in [
        MANUAL_ADSB,
        MANUAL_UAT,
        MANUAL_FLARM,
        MANUAL_GNSS,
        MANUAL_RAW,
        MANUAL_STATUS,
    ]
    .iter()
    .enumerate()
    {
        s.push_str(["", "\r\n", "xx", "\n", "}", "#A:1,2\r\n"][i]);
        s.push_str(m);
        s.push_str("\r\n");
    }
    // A message cut by a line feed, then one without its line end at the end of the stream.
    s.push_str(&MANUAL_FLARM[..40]);
    s.push_str("\r\n");
    s.push_str(MANUAL_STATUS);
    s.into_bytes()
}

#[test]
fn every_split_point() {
    let bytes = stream();
    assert_split_invariant(JsonDecoder::new, &bytes);
    let mut d = JsonDecoder::new();
    let msgs = decode_slice(&mut d, &bytes);
    assert_eq!(msgs.len(), 7);
    assert_eq!(d.stats().malformed, 1);
}

#[test]
fn random_and_corrupted_input() {
    assert_survives_random(JsonDecoder::new, 0x150, 300, 3000);
    let clean = stream();
    let mut rng = XorShift::new(11);
    for _ in 0..300 {
        let mut bytes = clean.clone();
        flip_bits(&mut bytes, 4, &mut rng);
        let (_, stats) = decode_chunked(JsonDecoder::new(), &bytes, &[1 + rng.below(50) as usize]);
        crate::testkit::assert_accounting(&stats, bytes.len());
    }
    // Random JSON-ish bytes reach serde.
    let alphabet = br#"{}[]":,01a\ver"#;
    for _ in 0..300 {
        let len = rng.below(300) as usize;
        let bytes: Vec<u8> = (0..len)
            .map(|_| alphabet[rng.below(alphabet.len() as u64) as usize])
            .collect();
        let (_, stats) = decode_chunked(JsonDecoder::new(), &bytes, &[7]);
        crate::testkit::assert_accounting(&stats, len);
    }
}

#[test]
fn truncated_messages() {
    for cut in 0..MANUAL_ADSB.len() {
        let mut d = JsonDecoder::new();
        let msgs = decode_slice(&mut d, &MANUAL_ADSB.as_bytes()[..cut]);
        assert!(msgs.is_empty());
        crate::testkit::assert_accounting(d.stats(), cut);
        // A cut object is one malformed message (the `{` is its first byte).
        assert_eq!(d.stats().malformed, u64::from(cut > 0), "{cut}");
    }
}

#[test]
fn a_message_comes_out_as_soon_as_its_object_closes() {
    // No end of stream needed, only the line end; an impossible target in it is counted as it
    // comes out.
    let mut d = JsonDecoder::new();
    let mut buf = BytesMut::from(
        &b"{\"ver\":1,\"flarm\":[{\"id\":\"1\",\"lat\":91},{\"id\":\"2\",\"lat\":47}]}\r\n"[..],
    );
    let m = d.decode(&mut buf).expect("a complete object");
    assert_eq!(m.flarm.len(), 1);
    assert_eq!(d.stats().invalid_values, 1);
    assert!(buf.is_empty());
}

#[test]
fn over_long_object_is_bounded() {
    // The rest of an over-long line is discarded up to its line feed, even a complete object
    // in it; the next line's message comes out, whatever the reads.
    let mut bytes = b"{\"ver\":1,\"pad\":\"".to_vec();
    bytes.extend(std::iter::repeat_n(b'a', framing::MAX_OBJECT + 10));
    bytes.extend_from_slice(b"{\"ver\":1}\"}\r\n");
    let line = bytes.len();
    bytes.extend_from_slice(MANUAL_STATUS.as_bytes());
    let (msgs, stats) = decode_chunked(JsonDecoder::new(), &bytes, &[4096]);
    assert_eq!(msgs.len(), 1);
    assert!(msgs[0].status.is_some());
    assert_eq!((stats.malformed, stats.bytes_skipped), (1, line as u64));
    // A read ending just before the line feed: the discarding goes on into the next read.
    let split = decode_chunked(JsonDecoder::new(), &bytes, &[line - 1, bytes.len()]);
    assert_eq!(split, (msgs, stats));
}

#[test]
fn the_last_object_needs_no_line_end_at_the_end_of_the_stream() {
    // A recording cut right after a closing brace: the object is complete, and at the end of
    // the stream there is nothing more to wait for.
    let wire = parse(MANUAL_STATUS).to_wire();
    let bare = wire.trim_end();
    let (msgs, stats) = decode_chunked(JsonDecoder::new(), bare.as_bytes(), &[4096]);
    assert_eq!(msgs, vec![parse(MANUAL_STATUS)]);
    assert_eq!((stats.malformed, stats.bytes_skipped), (0, 0));
    // A carriage return as the stream's last byte: the object is taken and the lone return
    // skipped.
    let (msgs, stats) = decode_chunked(JsonDecoder::new(), format!("{bare}\r").as_bytes(), &[4096]);
    assert_eq!(msgs, vec![parse(MANUAL_STATUS)]);
    assert_eq!((stats.malformed, stats.bytes_skipped), (0, 1));
    // Before the end of the stream it waits: the next byte may be its line end.
    let mut d = JsonDecoder::new();
    let mut buf = BytesMut::from(bare.as_bytes());
    assert_eq!(d.decode(&mut buf), None);
    assert_eq!(buf.len(), bare.len());
}

#[test]
fn objects_up_to_64_kib_are_taken() {
    // The bound is 64 KiB = 65,536 bytes of object (a message with a few dozen targets is about
    // 20 KiB): an object of exactly that length comes out, one byte more is given up.
    let object = |len: usize| {
        let head = b"{\"ver\":1,\"pad\":\"";
        let mut o = head.to_vec();
        o.extend(std::iter::repeat_n(b'a', len - head.len() - 2));
        o.extend_from_slice(b"\"}");
        assert_eq!(o.len(), len);
        o.extend_from_slice(b"\r\n");
        o
    };
    for (len, taken) in [(20 * 1024, 1), (65_536, 1), (65_537, 0)] {
        let (msgs, stats) = decode_chunked(JsonDecoder::new(), &object(len), &[4096]);
        assert_eq!(
            (msgs.len(), stats.malformed),
            (taken, 1 - taken as u64),
            "{len}"
        );
    }
}

#[test]
fn serialised_names_carry_units() {
    let v = serde_json::to_value(&parse(MANUAL_ADSB).adsb[0]).unwrap();
    assert_eq!(v["icao"], "780A3F");
    assert_eq!(v["alt_baro_ft"], 35000.0);
    assert_eq!(v["velh_kt"], 528.0);
    assert_eq!(v["velv_fpm"], 0.0);
}

#[test]
fn wire_encoding_of_the_manual_examples_round_trips() {
    for example in [
        MANUAL_ADSB,
        MANUAL_UAT,
        MANUAL_FLARM,
        MANUAL_GNSS,
        MANUAL_RAW,
        MANUAL_STATUS,
    ] {
        let m = parse(example);
        let wire = m.to_wire();
        assert!(wire.ends_with("}\r\n") && !wire[..wire.len() - 2].contains('\n'));
        assert_eq!(
            parse_message(wire.trim_end().as_bytes()).unwrap(),
            m,
            "{wire}"
        );
    }
    // Unknown values are omitted, not written as null or 0.
    let wire = parse(r#"{"ver":1,"adsb":[{"icao":"00ABCD"}]}"#).to_wire();
    // (Key order follows serde_json's map; compare as JSON values.)
    assert!(wire.ends_with("}\r\n"));
    let got: serde_json::Value = serde_json::from_str(wire.trim_end()).unwrap();
    assert_eq!(
        got,
        serde_json::json!({"ver": 1, "adsb": [{"icao": "00ABCD"}]})
    );
}

mod round_trip {
    use super::*;
    use proptest::prelude::*;

    fn opt<T: std::fmt::Debug + Clone>(
        s: impl Strategy<Value = T>,
    ) -> impl Strategy<Value = Option<T>> {
        proptest::option::of(s)
    }

    prop_compose! {
        fn adsb_target()(
            icao in 0u32..0x100_0000,
            ground in opt(any::<bool>()),
            lat in opt(-90.0f64..=90.0),
            lon in opt(-180.0f64..=180.0),
            alt in opt(-1000.0f64..60000.0),
            velv in opt(-6000i32..6000),
            call in opt("[A-Z0-9]{1,8}"),
            squawk in opt(0u16..0o10000),
            nic in opt(0u8..12),
            tcas in opt(any::<bool>()),
        ) -> AdsbTarget {
            AdsbTarget {
                icao,
                flags: ground.map(|g| TargetFlags { on_ground: Some(g), ..Default::default() }),
                lat_deg: lat,
                lon_deg: lon,
                alt_baro_ft: alt,
                velv_fpm: velv.map(f64::from),
                callsign: call,
                squawk: squawk.map(|s| format!("{s:o}").parse().unwrap()),
                nic,
                nav_modes: tcas.map(|t| NavModes { tcas: Some(t), ..Default::default() }),
                ..Default::default()
            }
        }
    }

    prop_compose! {
        fn flarm_target()(
            id in 0u32..0x100_0000,
            id_type in opt(0u8..3),
            ty in opt(0u8..16),
            danger in opt(0u8..4),
            alt in opt(-100.0f64..5000.0),
            hvelo in opt(0.0f64..100.0),
            stealth in opt(Just(1u8)),
        ) -> FlarmTarget {
            FlarmTarget { id, id_type, aircraft_type: ty, alarm_level: danger, alt_m: alt, velh_mps: hvelo, stealth, ..Default::default() }
        }
    }

    proptest! {
        #[test]
        fn message_round_trip(
            src in opt("[A-Z0-9-]{1,12}"),
            ts in opt(0u32..86_400_000),
            adsb in proptest::collection::vec(adsb_target(), 0..4),
            flarm in proptest::collection::vec(flarm_target(), 0..3),
            uat_emerg in opt(0u8..8),
            fix in opt(0u8..2),
            raw_ts in opt(0u64..86_400_000_000_000),
        ) {
            let m = JsonMessage {
                src,
                ts_ms: ts,
                ver: Some(1),
                adsb,
                flarm,
                uat: uat_emerg.map(|e| UatTarget { icao: 0x777888, emergency: Some(e), squawk: Some(7232), ..Default::default() }).into_iter().collect(),
                gnss: fix.map(|f| Gnss { fix: Some(f), gnd_speed_en_kt: Some([5.2, -2.1]), ..Default::default() }),
                raw: raw_ts.map(|t| RawFrame { frame_hex: "5D4B18FFFC710B".into(), sig_dbm: None, sig_q_db: Some(2.0), ts_ns: Some(t) }).into_iter().collect(),
                ..Default::default()
            };
            let wire = m.to_wire();
            let mut d = JsonDecoder::new();
            // Issue 24: targets with impossible values come back dropped and counted.
            let expected = super::super::drop_invalid_records(m);
            let dropped = u64::from(expected.invalid_records);
            prop_assert_eq!(decode_slice(&mut d, wire.as_bytes()), vec![expected]);
            prop_assert_eq!(d.stats().invalid_values, dropped);
        }
    }
}

/// The manual's FLARM example exactly as laid out in 8.2.1 (pretty-printed, no OCR damage).
const MANUAL_FLARM_PRETTY: &str = "{\n\"src\": \"ID-0000001\",\n\"ts\": 69061337,\n\"ver\": 1,\n\"flarm\": [\n{\n\"idType\": 1,\n\"id\": \"DABABE\",\n\"type\": 13,\n\"danger\": 1,\n\"lat\": 53.42854,\n\"lon\": 14.55281,\n\"alt\": 1725,\n\"track\": 72.18,\n\"hvelo\": 10.5,\n\"vVelo\": 50,\n\"movMode\": 5,\n\"stealth\": 1,\n\"notrack\": 1\n}\n]\n}\n";

#[test]
fn pretty_printed_input_needs_the_multiline_decoder() {
    let mut strict = JsonDecoder::new();
    assert!(decode_slice(&mut strict, MANUAL_FLARM_PRETTY.as_bytes()).is_empty());
    assert!(strict.stats().malformed > 0);
    let stream = format!("{MANUAL_FLARM_PRETTY}{MANUAL_STATUS}\r\n{MANUAL_FLARM_PRETTY}");
    let mut lenient = JsonDecoder::allowing_newlines();
    let msgs = decode_slice(&mut lenient, stream.as_bytes());
    assert_eq!(msgs.len(), 3);
    assert_eq!(msgs[0], parse(MANUAL_FLARM));
    assert_eq!(lenient.stats().bytes_skipped, 0);
    assert_split_invariant(JsonDecoder::allowing_newlines, stream.as_bytes());
    assert_survives_random(JsonDecoder::allowing_newlines, 8, 200, 2000);
}
