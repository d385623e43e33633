//! The TT-Multi-RF model's binary decoded protocols (manual 7.2.1 "ADS-B MAVLink / ASTERIX /
//! GDL90 protocol", 8.2.1 "FLARM MAVLink / ASTERIX protocol", 10.2.1 UAT), built with the
//! drivers' encoders ([`vigil_drivers::ttmrf::mavlink`], [`gdl90`], [`asterix`]).
//!
//! What each protocol sends (the manual's lists, at its rates):
//! - **MAVLink**: one ADSB_VEHICLE (#246) per target per second, for ADS-B, UAT (flag
//!   `SOURCE_UAT`) and FLARM targets (FLARM id in `ICAO_address`, 8.2.1). The manual names no
//!   heartbeat or ownship message for MAVLink: none is sent. COLLISION (#247) needs FLARM alarms,
//!   which the scenarios do not model.
//! - **GDL90**: one Traffic Report (#20) per ADS-B 1090 target per second; once per second
//!   Heartbeat (#0), Ownship Report (#10) and Ownship Geometric Altitude (#11). FLARM targets are
//!   never sent (manual), nor UAT targets (UAT_DECODED_PROTOCOL offers CSV, JSON, MAVLink only).
//! - **ASTERIX**: one CAT021 ed 2.1 record per ADS-B 1090 and FLARM target per second (FLARM:
//!   SAC 0 / SIC 161, ATP 3, VNS 1, the FLARM emitter numbers as they are, 8.2.1), each in its
//!   own data block; once per second a CAT023 ed 1.2 ground station status record (the
//!   "heartbeat"). SAC/SIC come from the module's `ASTERIX_SAC` / `ASTERIX_SIC` settings. UAT
//!   targets are not sent (UAT_DECODED_PROTOCOL has no ASTERIX).
//!
//! Decisions where the manual is silent:
//! - MAVLink 2 framing, system id 1, component id 156 (MAV_COMP_ID_ADSB), one sequence counter
//!   for the port. ADS-B and UAT altitude = pressure altitude (`altitude_type` 0, the barometric
//!   altitude the target broadcasts); FLARM = GNSS altitude (`altitude_type` 1).
//! - GDL90 Traffic Report altitude = pressure altitude (barometric priority, the GDL90
//!   definition). The Ownship Report carries no pressure altitude (the module has GNSS only: code
//!   0xFFF); its geometric altitude goes in #11 with VFOM 8 m (about 2 sigma of the 4 m GNSS
//!   vertical noise). During a GNSS outage the Ownship Report has lat = lon = 0, NIC 0 (the
//!   specification's "no position"), #11 has VFOM "not available", the Heartbeat clears
//!   "GPS position valid".
//! - Every ASTERIX time item is the report's own GPS time as UTC seconds of day (1/128 s).

use serde_json::{Map, Value, json};
use vigil_drivers::ttmrf::asterix::AsterixMessage;
use vigil_drivers::ttmrf::asterix::cat021::Cat021Record;
use vigil_drivers::ttmrf::asterix::cat021::identity::MopsVersion;
use vigil_drivers::ttmrf::asterix::cat021::kinematics::{GroundVector, Position, VerticalRate};
use vigil_drivers::ttmrf::asterix::cat021::status::{
    DescriptorExt1, QualityExt1, QualityIndicators, TargetReportDescriptor,
};
use vigil_drivers::ttmrf::asterix::cat021::traffic::emitter_to_ecat;
use vigil_drivers::ttmrf::asterix::cat023::{Cat023Record, GroundStationStatus, ServiceType};
use vigil_drivers::ttmrf::asterix::common::DataSource;
use vigil_drivers::ttmrf::gdl90::geo_altitude::{GeoAltitude, Vfom};
use vigil_drivers::ttmrf::gdl90::heartbeat::Heartbeat;
use vigil_drivers::ttmrf::gdl90::report::{
    AddressKind, HorizontalVelocity, TargetReport, TrackType, VerticalVelocity,
};
use vigil_drivers::ttmrf::gdl90::{self, Gdl90Message};
use vigil_drivers::ttmrf::mavlink::adsb_vehicle::{
    FLAG_BARO_VALID, FLAG_SOURCE_UAT, FLAG_VALID_ALTITUDE, FLAG_VALID_CALLSIGN, FLAG_VALID_COORDS,
    FLAG_VALID_HEADING, FLAG_VALID_VELOCITY, FLAG_VERTICAL_VELOCITY_VALID,
};
use vigil_drivers::ttmrf::mavlink::{self, AdsbVehicle, FrameInfo};

use crate::scenario::Link;

const FT_PER_M: f64 = 1.0 / 0.3048;
const KT_PER_MPS: f64 = 3600.0 / 1852.0;
const FPM_PER_MPS: f64 = 60.0 / 0.3048;

/// MAVLink system id of the module.
pub const MAVLINK_SYSTEM_ID: u8 = 1;
/// MAVLink component id of the module (MAV_COMP_ID_ADSB).
pub const MAVLINK_COMPONENT_ID: u8 = 156;
/// GDL90 Ownship Geometric Altitude VFOM the model reports, m.
pub const GDL90_VFOM_M: u16 = 8;
/// ASTERIX data source of FLARM targets (manual 8.2.1): SAC 0, SIC 161.
pub const FLARM_SOURCE: DataSource = DataSource { sac: 0, sic: 161 };

/// A target as the module reports it (reported position, quantised as the text protocols).
#[derive(Debug, Clone)]
pub struct Target {
    /// Link it was received on.
    pub link: Link,
    /// ICAO address (or FLARM id), 24 bits.
    pub icao: u32,
    /// Reported latitude, degrees.
    pub lat_deg: f64,
    /// Reported longitude, degrees.
    pub lon_deg: f64,
    /// Reported WGS-84 height, m.
    pub height_m: f64,
    /// Pressure altitude, m.
    pub alt_pressure_m: f64,
    /// Velocity north, east, down, m/s.
    pub vel_ned_mps: [f64; 3],
    /// Track over ground, degrees true.
    pub track_deg: f64,
    /// Call sign (may be empty).
    pub callsign: String,
    /// Emitter category, DO-260B / GDL90 numbering.
    pub ecat: Option<u8>,
    // --- issue 24 ---
    /// Age of the reported state, s (MAVLink `tslc`, whole seconds).
    pub age_s: u8,
}

impl Target {
    fn ground_speed_mps(&self) -> f64 {
        self.vel_ned_mps[0].hypot(self.vel_ned_mps[1])
    }

    fn climb_mps(&self) -> f64 {
        -self.vel_ned_mps[2]
    }
}

/// Whether a decoded protocol reports targets of `link` (see the module doc).
pub fn carries(protocol: Binary, link: Link) -> bool {
    match protocol {
        Binary::Mavlink => true,
        Binary::Gdl90 => link == Link::Adsb1090,
        Binary::Asterix => link != Link::Uat978,
    }
}

/// The binary decoded protocols.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binary {
    /// MAVLink 2 ADSB_VEHICLE.
    Mavlink,
    /// GDL90.
    Gdl90,
    /// ASTERIX CAT021 / CAT023.
    Asterix,
}

/// One ADSB_VEHICLE frame for `t`, with sequence number `seq`.
pub fn mavlink_vehicle(seq: u8, t: &Target) -> Vec<u8> {
    let flarm = t.link == Link::Flarm;
    let mut flags = FLAG_VALID_COORDS
        | FLAG_VALID_ALTITUDE
        | FLAG_VALID_HEADING
        | FLAG_VALID_VELOCITY
        | FLAG_VERTICAL_VELOCITY_VALID;
    if !flarm {
        flags |= FLAG_BARO_VALID;
    }
    if t.link == Link::Uat978 {
        flags |= FLAG_SOURCE_UAT;
    }
    if !t.callsign.is_empty() {
        flags |= FLAG_VALID_CALLSIGN;
    }
    let v = AdsbVehicle {
        icao_address: t.icao,
        lat_deg: t.lat_deg,
        lon_deg: t.lon_deg,
        altitude_m: if flarm { t.height_m } else { t.alt_pressure_m },
        altitude_type: u8::from(flarm),
        heading_deg: t.track_deg,
        hor_velocity_mps: t.ground_speed_mps(),
        ver_velocity_mps: t.climb_mps(),
        flags,
        squawk: 0,
        callsign: t.callsign.clone(),
        // ADSB_EMITTER_TYPE is the DO-260B numbering up to 19.
        emitter_type: t.ecat.filter(|&e| e <= 19).unwrap_or(0),
        tslc_s: t.age_s,
    };
    let frame = FrameInfo {
        version: 2,
        sequence: seq,
        system_id: MAVLINK_SYSTEM_ID,
        component_id: MAVLINK_COMPONENT_ID,
        signed: false,
    };
    let mut out = Vec::with_capacity(mavlink::MAX_FRAME_LEN);
    mavlink::encode_adsb_vehicle(&frame, &v, &mut out);
    out
}

fn callsign8(s: &str) -> [u8; 8] {
    let mut c = *b"        ";
    for (d, b) in c.iter_mut().zip(s.bytes()) {
        *d = b;
    }
    c
}

fn frame(m: &Gdl90Message) -> Vec<u8> {
    let mut out = Vec::with_capacity(64);
    gdl90::encode_frame(m, &mut out);
    out
}

/// One GDL90 Traffic Report (#20) frame for `t`.
pub fn gdl90_traffic(t: &Target) -> Vec<u8> {
    let r = TargetReport {
        address_type: AddressKind::AdsbIcao,
        address: t.icao,
        lat_deg: t.lat_deg,
        lon_deg: t.lon_deg,
        altitude_ft: Some((t.alt_pressure_m * FT_PER_M).round() as i32),
        airborne: true,
        track_type: TrackType::TrueTrack,
        track_deg: t.track_deg,
        nic: 8,
        nac_p: 9,
        horizontal_velocity: HorizontalVelocity::Kt(
            (t.ground_speed_mps() * KT_PER_MPS)
                .round()
                .clamp(0.0, 4094.0) as u16,
        ),
        vertical_velocity: VerticalVelocity::Fpm((t.climb_mps() * FPM_PER_MPS).round() as i32),
        emitter_category: t.ecat.unwrap_or(0),
        callsign: callsign8(&t.callsign),
        ..Default::default()
    };
    frame(&Gdl90Message::TrafficReport(r))
}

/// The ownship as the module's GNSS gives it (noisy), or `None` without a fix.
#[derive(Debug, Clone, Copy)]
pub struct OwnFix {
    /// Latitude, degrees.
    pub lat_deg: f64,
    /// Longitude, degrees.
    pub lon_deg: f64,
    /// WGS-84 height, m.
    pub height_m: f64,
    /// Velocity north, east, down, m/s.
    pub vel_ned_mps: [f64; 3],
}

/// The once-per-second GDL90 messages: Heartbeat, Ownship Report, Ownship Geometric Altitude,
/// each as (truth type, frame).
pub fn gdl90_second(
    utc_s_of_day: u32,
    own_address: u32,
    own_ecat: u8,
    fix: Option<OwnFix>,
) -> [(&'static str, Vec<u8>); 3] {
    let hb = Heartbeat {
        gps_pos_valid: fix.is_some(),
        uat_initialized: true,
        utc_ok: true,
        timestamp_s: utc_s_of_day,
        ..Default::default()
    };
    let mut own = TargetReport {
        address_type: AddressKind::AdsbIcao,
        address: own_address,
        altitude_ft: None,
        airborne: true,
        emitter_category: own_ecat,
        ..Default::default()
    };
    let geo = match fix {
        Some(f) => {
            let [vn, ve, vd] = f.vel_ned_mps;
            own.lat_deg = f.lat_deg;
            own.lon_deg = f.lon_deg;
            own.nic = 8;
            own.nac_p = 9;
            own.track_type = TrackType::TrueTrack;
            own.track_deg = ve.atan2(vn).to_degrees().rem_euclid(360.0);
            own.horizontal_velocity =
                HorizontalVelocity::Kt((vn.hypot(ve) * KT_PER_MPS).round().min(4094.0) as u16);
            own.vertical_velocity = VerticalVelocity::Fpm((-vd * FPM_PER_MPS).round() as i32);
            GeoAltitude {
                // 5 ft steps.
                geo_altitude_ft: ((f.height_m * FT_PER_M) / 5.0).round() as i32 * 5,
                vertical_warning: false,
                vfom: Vfom::Meters(GDL90_VFOM_M),
            }
        }
        None => GeoAltitude {
            geo_altitude_ft: 0,
            vertical_warning: false,
            vfom: Vfom::Unavailable,
        },
    };
    [
        ("gdl90_heartbeat", frame(&Gdl90Message::Heartbeat(hb))),
        ("gdl90_ownship", frame(&Gdl90Message::OwnshipReport(own))),
        (
            "gdl90_ownship_geo_altitude",
            frame(&Gdl90Message::OwnshipGeoAltitude(geo)),
        ),
    ]
}

/// One CAT021 data block for `t` (ADS-B 1090 or FLARM), reported at `tod_s` (UTC s of day).
pub fn asterix_target(t: &Target, tod_s: f64, source: DataSource, track_number: u16) -> Vec<u8> {
    let flarm = t.link == Link::Flarm;
    let ecat = if flarm {
        // Manual table 28: the FLARM numbers are the DO-260B ones, sent as they are.
        t.ecat
    } else {
        t.ecat.and_then(emitter_to_ecat)
    };
    let r = Cat021Record {
        data_source: Some(if flarm { FLARM_SOURCE } else { source }),
        descriptor: Some(TargetReportDescriptor {
            atp: if flarm { 3 } else { 0 },
            arc: if flarm { 2 } else { 0 },
            ext1: Some(DescriptorExt1::default()),
            ..Default::default()
        }),
        track_number: Some(track_number),
        time_applicability_position_s: Some(tod_s),
        position_high_res: Some(Position {
            lat_deg: t.lat_deg,
            lon_deg: t.lon_deg,
        }),
        time_applicability_velocity_s: Some(tod_s),
        target_address: Some(t.icao),
        time_reception_position_s: Some(tod_s),
        geometric_height_ft: Some(t.height_m * FT_PER_M),
        quality: Some(QualityIndicators {
            nac_v: 1,
            nic: 8,
            ext1: Some(QualityExt1 {
                nic_baro: !flarm,
                sil: 3,
                nac_p: 9,
            }),
            ..Default::default()
        }),
        mops: Some(MopsVersion {
            vns: flarm,
            vn: 2,
            ltt: 2,
        }),
        flight_level: (!flarm).then(|| t.alt_pressure_m * FT_PER_M / 100.0),
        baro_vertical_rate: (!flarm).then(|| VerticalRate {
            range_exceeded: false,
            fpm: t.climb_mps() * FPM_PER_MPS,
        }),
        geo_vertical_rate: flarm.then(|| VerticalRate {
            range_exceeded: false,
            fpm: t.climb_mps() * FPM_PER_MPS,
        }),
        ground_vector: Some(GroundVector {
            range_exceeded: false,
            ground_speed_kt: t.ground_speed_mps() * KT_PER_MPS,
            track_deg: t.track_deg,
        }),
        time_report_transmission_s: Some(tod_s),
        target_id: (!t.callsign.is_empty()).then(|| t.callsign.clone()),
        emitter_category: ecat,
        ..Default::default()
    };
    let mut out = Vec::with_capacity(64);
    AsterixMessage::Cat021(Box::new(r)).encode_block(&mut out);
    out
}

/// The once-per-second CAT023 ground station status block (the ASTERIX "heartbeat").
pub fn asterix_status(tod_s: f64, source: DataSource) -> Vec<u8> {
    let r = Cat023Record {
        data_source: Some(source),
        // 1: ground station status.
        report_type: Some(1),
        // SID 0, STYP 2: ADS-B Extended Squitter.
        service: Some(ServiceType { sid: 0, styp: 2 }),
        time_of_day_s: Some(tod_s),
        ground_station_status: Some(GroundStationStatus::default()),
        ..Default::default()
    };
    let mut out = Vec::with_capacity(16);
    AsterixMessage::Cat023(Box::new(r)).encode_block(&mut out);
    out
}

/// Truth values of a once-per-second ownship message.
pub fn ownship_values(fix: bool, lat: f64, lon: f64, h: f64, vel: [f64; 3]) -> Map<String, Value> {
    match json!({
        "fix": fix,
        "lat_deg": lat,
        "lon_deg": lon,
        "height_m": h,
        "vel_ned_mps": vel,
    }) {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_drivers::decode_slice;
    use vigil_drivers::ttmrf::asterix::AsterixDecoder;
    use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, TrafficAltitude};
    use vigil_drivers::ttmrf::mavlink::{MavlinkDecoder, MavlinkMessage};

    fn target(link: Link) -> Target {
        Target {
            link,
            icao: 0x4B1B01,
            lat_deg: 47.5,
            lon_deg: 8.25,
            height_m: 1524.0,
            // FL 50 = 5000 ft = 1524 m.
            alt_pressure_m: 1524.0,
            // 100 kt north, 500 ft/min climb: 100 * 1852 / 3600 m/s, 500 * 0.00508 m/s.
            vel_ned_mps: [100.0 * 1852.0 / 3600.0, 0.0, -2.54],
            track_deg: 0.0,
            callsign: "SPOOF1".into(),
            ecat: Some(14),
            age_s: 0,
        }
    }

    #[test]
    fn mavlink_frames_decode_to_the_target() {
        let bytes = mavlink_vehicle(7, &target(Link::Uat978));
        let m = decode_slice(&mut MavlinkDecoder::new(), &bytes);
        let MavlinkMessage::AdsbVehicle { frame, vehicle } = &m[0] else {
            panic!("{m:?}")
        };
        assert_eq!(
            (frame.version, frame.sequence, frame.component_id),
            (2, 7, 156)
        );
        let r = vehicle.to_traffic();
        assert_eq!(r.address_hex(), "4B1B01");
        assert_eq!(r.link, vigil_drivers::traffic::Link::Uat978);
        assert_eq!(r.alt_pressure_m, Some(1524.0));
        // 51.444... m/s at 1 cm/s resolution; 2.54 m/s up.
        assert!((r.ground_speed_mps.unwrap() - 51.44).abs() < 0.006);
        assert_eq!(r.vertical_rate_mps, Some(2.54));
        assert_eq!(r.callsign.as_deref(), Some("SPOOF1"));
        assert_eq!(r.emitter_category, Some(14));
        // FLARM: GNSS altitude, geometric type.
        let bytes = mavlink_vehicle(8, &target(Link::Flarm));
        let m = decode_slice(&mut MavlinkDecoder::new(), &bytes);
        let r = m[0].to_traffic().unwrap();
        assert_eq!((r.alt_geometric_m, r.alt_pressure_m), (Some(1524.0), None));
    }

    #[test]
    fn gdl90_traffic_and_ownship_decode() {
        let bytes = gdl90_traffic(&target(Link::Adsb1090));
        let m = decode_slice(&mut Gdl90Decoder::new(TrafficAltitude::Pressure), &bytes);
        let r = m[0].to_traffic(TrafficAltitude::Pressure).unwrap();
        // 5000 ft in 25 ft steps; 100 kt; 500 fpm -> 512 (8 x 64 fpm).
        assert_eq!(r.alt_pressure_m, Some(5000.0 * 0.3048));
        assert!((r.ground_speed_mps.unwrap() - 100.0 * 1852.0 / 3600.0).abs() < 1e-9);
        assert!((r.vertical_rate_mps.unwrap() - 512.0 * 0.00508).abs() < 1e-9);
        let fix = OwnFix {
            lat_deg: 47.5,
            lon_deg: 8.25,
            height_m: 1000.0,
            vel_ned_mps: [0.0, 10.0, 0.0],
        };
        let msgs: Vec<_> = gdl90_second(36_000, 0xABCDEF, 14, Some(fix))
            .iter()
            .flat_map(|(_, b)| decode_slice(&mut Gdl90Decoder::default(), b))
            .collect();
        let Gdl90Message::Heartbeat(h) = msgs[0] else {
            panic!()
        };
        assert!(h.gps_pos_valid && h.utc_ok);
        assert_eq!(h.timestamp_s, 36_000);
        let Gdl90Message::OwnshipReport(o) = msgs[1] else {
            panic!()
        };
        // East at 10 m/s: track 90 deg, 19.4 kt -> 19.
        assert_eq!((o.track_deg, o.horizontal_velocity.kt()), (90.0, Some(19)));
        assert_eq!(o.altitude_ft, None);
        let Gdl90Message::OwnshipGeoAltitude(g) = msgs[2] else {
            panic!()
        };
        // 1000 m = 3280.84 ft -> 3280 ft (5 ft steps).
        assert_eq!(g.geo_altitude_ft, 3280);
        let lost: Vec<_> = gdl90_second(36_000, 0xABCDEF, 14, None)
            .iter()
            .flat_map(|(_, b)| decode_slice(&mut Gdl90Decoder::default(), b))
            .collect();
        let Gdl90Message::OwnshipReport(o) = lost[1] else {
            panic!()
        };
        assert!(!o.has_position());
    }

    #[test]
    fn asterix_blocks_decode() {
        let src = DataSource { sac: 1, sic: 129 };
        let mut bytes = asterix_target(&target(Link::Adsb1090), 36_000.5, src, 3);
        bytes.extend(asterix_target(&target(Link::Flarm), 36_000.5, src, 4));
        bytes.extend(asterix_status(36_001.0, src));
        let m = decode_slice(&mut AsterixDecoder::default(), &bytes);
        assert_eq!(m.len(), 3);
        let a = m[0].to_traffic().unwrap();
        assert_eq!(a.link, vigil_drivers::traffic::Link::Adsb1090);
        // FL 50.
        assert!((a.alt_pressure_m.unwrap() - 1524.0).abs() < 1e-9);
        // UAV: DO-260B 14 is ECAT 13 on the wire, 14 again in the report.
        assert_eq!(a.emitter_category, Some(14));
        let AsterixMessage::Cat021(r) = &m[0] else {
            panic!()
        };
        assert_eq!(r.emitter_category, Some(13));
        let f = m[1].to_traffic().unwrap();
        assert_eq!(f.link, vigil_drivers::traffic::Link::Flarm);
        let AsterixMessage::Cat023(s) = &m[2] else {
            panic!()
        };
        assert_eq!(s.data_source, Some(src));
        assert_eq!(s.time_of_day_s, Some(36_001.0));
    }

    #[test]
    fn which_protocol_carries_which_link() {
        assert!(carries(Binary::Mavlink, Link::Flarm));
        assert!(!carries(Binary::Gdl90, Link::Flarm));
        assert!(!carries(Binary::Gdl90, Link::Uat978));
        assert!(carries(Binary::Asterix, Link::Flarm));
        assert!(!carries(Binary::Asterix, Link::Uat978));
    }
}
