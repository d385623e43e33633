//! Issue 24, "Validate per record, at the edge": for every TT-Multi-RF protocol, a message (or
//! stream) holding one impossible record and one valid one decodes to the valid one, and the
//! impossible one is counted in `invalid_values` rather than dropped silently or passed on. The
//! records are written by the same encoders the simulator uses.

use vigil_drivers::DecodeStats;
use vigil_drivers::modes::decoder::{ModesDecoder, ModesMessage};
use vigil_drivers::modes::df::DecodeOptions;
use vigil_drivers::modes::encode::{self, AirbornePositionFields};
use vigil_drivers::modes::tracker::TrackerConfig;
use vigil_drivers::testkit::decode_chunked;
use vigil_drivers::traffic::TrafficReport;
use vigil_drivers::ttmrf::asterix::{AsterixDecoder, AsterixMessage, encode_block};
use vigil_drivers::ttmrf::csv::{AdsbAircraft, AircraftState, CsvDecoder, CsvMessage};
use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, TrafficAltitude};
use vigil_drivers::ttmrf::json::{AdsbTarget, JsonDecoder, JsonMessage};
use vigil_drivers::ttmrf::mavlink::MavlinkDecoder;
use vigil_drivers::ttmrf::nmea::{Gga, NmeaBody, NmeaDecoder, NmeaSentence};
use vigil_drivers::ttmrf::raw::encode_hex_string;
use vigil_sim::device::ttmrf_binary::{Target, asterix_target, gdl90_traffic, mavlink_vehicle};
use vigil_sim::scenario::Link;

const VALID: u32 = 0x4B2410;
const BAD: u32 = 0x4B2411;

/// A valid target, and one at latitude 95 deg (the example).
fn targets() -> (Target, Target) {
    let good = Target {
        link: Link::Adsb1090,
        icao: VALID,
        lat_deg: 47.4,
        lon_deg: 8.5,
        height_m: 700.0,
        alt_pressure_m: 690.0,
        vel_ned_mps: [50.0, 0.0, 0.0],
        track_deg: 0.0,
        callsign: "GOOD".into(),
        ecat: Some(1),
        age_s: 0,
    };
    let bad = Target {
        icao: BAD,
        lat_deg: 95.0,
        callsign: "BAD".into(),
        ..good.clone()
    };
    (good, bad)
}

fn addresses(reports: &[TrafficReport]) -> Vec<u32> {
    reports.iter().map(|r| r.address).collect()
}

fn check(reports: &[TrafficReport], stats: &DecodeStats, protocol: &str) {
    assert_eq!(
        addresses(reports),
        vec![VALID],
        "{protocol}: the valid record is kept"
    );
    assert_eq!(
        stats.invalid_values, 1,
        "{protocol}: the impossible one is counted"
    );
    assert_eq!(stats.malformed, 0, "{protocol}: and not as malformed");
}

#[test]
fn json_message_keeps_the_valid_target_and_counts_the_impossible_one() {
    let target = |icao, lat| AdsbTarget {
        icao,
        lat_deg: Some(lat),
        lon_deg: Some(8.5),
        alt_baro_ft: Some(2500.0),
        ..Default::default()
    };
    let m = JsonMessage {
        ts_ms: Some(36_000_000),
        ver: Some(1),
        adsb: vec![target(BAD, 95.0), target(VALID, 47.4)],
        ..Default::default()
    };
    let mut bytes = m.to_wire().into_bytes();
    bytes.push(b'\n');
    let (msgs, stats) = decode_chunked(JsonDecoder::new(), &bytes, &[7]);
    let reports: Vec<_> = msgs.iter().flat_map(JsonMessage::traffic_reports).collect();
    check(&reports, &stats, "json");
}

#[test]
fn csv_line_with_a_negative_speed_is_dropped_alone() {
    let line = |icao, velh_kt| {
        CsvMessage::Adsb(AdsbAircraft {
            state: AircraftState {
                icao,
                lat_deg: Some(47.4),
                lon_deg: Some(8.5),
                velh_kt: Some(velh_kt),
                track_deg: Some(10.0),
                ..Default::default()
            },
            ..Default::default()
        })
        .to_line()
    };
    let bytes = format!("{}{}", line(BAD, -120.0), line(VALID, 120.0)).into_bytes();
    let (msgs, stats) = decode_chunked(CsvDecoder::default(), &bytes, &[5]);
    let reports: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            CsvMessage::Adsb(a) => Some(a.to_traffic()),
            _ => None,
        })
        .collect();
    check(&reports, &stats, "csv");
}

#[test]
fn mavlink_gdl90_and_asterix_keep_the_valid_record() {
    let (good, bad) = targets();
    // MAVLink: one ADSB_VEHICLE per frame; the impossible frame first.
    let mut bytes = mavlink_vehicle(0, &bad);
    bytes.extend(mavlink_vehicle(1, &good));
    let (msgs, stats) = decode_chunked(MavlinkDecoder::default(), &bytes, &[3]);
    let reports: Vec<_> = msgs.iter().filter_map(|m| m.to_traffic()).collect();
    check(&reports, &stats, "mavlink");
    // GDL90: one Traffic Report per frame.
    let mut bytes = gdl90_traffic(&bad);
    bytes.extend(gdl90_traffic(&good));
    let (msgs, stats) = decode_chunked(Gdl90Decoder::new(TrafficAltitude::Pressure), &bytes, &[4]);
    let reports: Vec<_> = msgs
        .iter()
        .filter_map(|m| m.to_traffic(TrafficAltitude::Pressure))
        .collect();
    check(&reports, &stats, "gdl90");
    // ASTERIX: both records in one CAT021 data block (each encoder block is CAT, LEN(2), record).
    let source = Default::default();
    let a = asterix_target(&bad, 36_000.0, source, 1);
    let b = asterix_target(&good, 36_000.0, source, 2);
    let mut records = a[3..].to_vec();
    records.extend_from_slice(&b[3..]);
    let mut block = Vec::new();
    encode_block(21, &records, &mut block);
    let (msgs, stats) = decode_chunked(AsterixDecoder::default(), &block, &[6]);
    let reports: Vec<_> = msgs
        .iter()
        .filter_map(|m| match m {
            AsterixMessage::Cat021(r) => Some(
                vigil_drivers::ttmrf::asterix::cat021::traffic::to_traffic(r),
            ),
            _ => None,
        })
        .collect();
    check(&reports, &stats, "asterix");
}

#[test]
fn nmea_fix_with_an_impossible_altitude_is_dropped_alone() {
    let gga = |alt| {
        NmeaSentence {
            talker: "GP".into(),
            body: NmeaBody::Gga(Gga {
                lat_deg: Some(47.4),
                lon_deg: Some(8.5),
                quality: Some(1),
                hdop: Some(0.9),
                alt_msl_m: Some(alt),
                ..Default::default()
            }),
        }
        .to_line()
    };
    // 1e9 ft above sea level, then an ordinary fix.
    let bytes = format!("{}{}", gga(3.048e8), gga(600.0)).into_bytes();
    let (msgs, stats) = decode_chunked(NmeaDecoder::default(), &bytes, &[9]);
    assert_eq!(msgs.len(), 1);
    assert!(matches!(&msgs[0].body, NmeaBody::Gga(g) if g.alt_msl_m == Some(600.0)));
    assert_eq!(stats.invalid_values, 1);
    assert_eq!(stats.malformed, 0);
}

/// Raw Mode S: a frame's fields cannot leave their encoded ranges, so the impossible record is a
/// position that cannot be true. Here the bad aircraft's even and odd frames decode to latitude
/// zones that differ (10.46 and 10.48 deg straddle the NL boundary near 10.47 deg: the pair
/// describes no single position); the good aircraft's pair is at 47.4 N 8.5 E.
#[test]
fn raw_mode_s_keeps_the_valid_aircraft_and_counts_the_impossible_position() {
    let frame = |icao, lat: f64, lon: f64, odd| {
        let f = encode::airborne_position(
            icao,
            &AirbornePositionFields {
                typecode: 11,
                surveillance_status: 0,
                nic_b: false,
                altitude_ft: Some(2_500),
                lat_deg: lat,
                lon_deg: lon,
                odd,
            },
        )
        .unwrap();
        format!("*{};\n", encode_hex_string(&f))
    };
    let lines = [
        frame(BAD, 10.46, 20.0, false),
        frame(VALID, 47.4, 8.5, false),
        frame(BAD, 10.48, 20.0, true),
        frame(VALID, 47.4, 8.5, true),
    ]
    .concat();
    let (msgs, stats) = decode_chunked(
        ModesDecoder::hex(TrackerConfig::default(), DecodeOptions::default()),
        lines.as_bytes(),
        &[9],
    );
    let reports: Vec<TrafficReport> = msgs
        .iter()
        .filter_map(|m| match m {
            ModesMessage::ModeS(o) => o.report.clone(),
            _ => None,
        })
        .filter(|r| r.lat_deg.is_some())
        .collect();
    check(&reports, &stats, "raw mode s");
    let r = &reports[0];
    assert!((r.lat_deg.unwrap() - 47.4).abs() < 1e-3 && (r.lon_deg.unwrap() - 8.5).abs() < 1e-3);
}
