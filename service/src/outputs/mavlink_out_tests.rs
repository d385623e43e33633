use vigil_fusion::traffic::TrafficStats;
use vigil_fusion::traffic::track::{AddressSpace, PlausibilityFlags, TargetKey};

use super::*;

fn target(address: u32) -> Target {
    Target {
        key: TargetKey {
            space: AddressSpace::Icao,
            address,
        },
        callsign: Some("SWR123".to_string()),
        sources: Vec::new(),
        age_s: 1.7,
        lat_deg: 47.4123456,
        lon_deg: -8.5123456,
        alt_m: Some(770.25),
        // 50 m/s south, 50 m/s east: course 135 deg, 70.71 m/s.
        velocity_ne_mps: Some([-50.0, 50.0]),
        vertical_rate_mps: Some(-2.5),
        altitude_kind: AltitudeKind::Pressure,
        position_sigma_m: 10.0,
        bearing_true_deg: 90.0,
        bearing_relative_deg: None,
        geometry: None,
        raw_alert_level: 0,
        alert_level: 0,
        flarm_alarm_level: None,
        flags: PlausibilityFlags::default(),
        fail_safe: Default::default(),
        reported: Default::default(),
    }
}

fn picture(t_s: f64, targets: Vec<Target>) -> TrafficPicture {
    TrafficPicture {
        kind: "traffic",
        t_gps_ns: (t_s * 1e9) as i64,
        targets,
        stats: TrafficStats::default(),
    }
}

fn le_u16(b: &[u8], at: usize) -> u16 {
    u16::from_le_bytes([b[at], b[at + 1]])
}

fn le_i32(b: &[u8], at: usize) -> i32 {
    i32::from_le_bytes(b[at..at + 4].try_into().unwrap())
}

/// The ADSB_VEHICLE frame read by hand from the MAVLink 2 wire format (magic 0xFD, length,
/// flags, sequence, system, component, 24-bit message id, then the payload in the message's
/// wire order: fields sorted by size, largest first; MAVLink 2 trims trailing zero bytes, so
/// the payload is padded back to its 38 bytes here).
#[test]
fn adsb_vehicle_fields_on_the_wire() {
    let mut enc = MavlinkTraffic::new(7, 156);
    let frames = enc.picture(&picture(100.0, vec![target(0x4B1801)]));
    assert_eq!(frames.len(), 2, "heartbeat + one target");
    let f = &frames[1];
    assert_eq!(f[0], 0xFD);
    let len = usize::from(f[1]);
    assert_eq!(
        (f[4], f[5], f[6]),
        (1, 7, 156),
        "sequence 1 (after the heartbeat's 0)"
    );
    assert_eq!(u32::from_le_bytes([f[7], f[8], f[9], 0]), 246);
    let mut p = f[10..10 + len].to_vec();
    p.resize(38, 0);
    // uint32 ICAO_address, int32 lat, int32 lon, int32 altitude, uint16 heading,
    // uint16 hor_velocity, int16 ver_velocity, uint16 flags, uint16 squawk,
    // uint8 altitude_type, char[9] callsign, uint8 emitter_type, uint8 tslc.
    assert_eq!(u32::from_le_bytes(p[0..4].try_into().unwrap()), 0x4B1801);
    assert_eq!(le_i32(&p, 4), 474_123_456);
    assert_eq!(le_i32(&p, 8), -85_123_456);
    assert_eq!(le_i32(&p, 12), 770_250, "mm");
    assert_eq!(le_u16(&p, 16), 13_500, "cdeg");
    assert_eq!(le_u16(&p, 18), 7071, "cm/s: 50 x sqrt(2) = 70.71 m/s");
    assert_eq!(le_u16(&p, 20) as i16, -250, "cm/s, up positive");
    // VALID_COORDS 1 | VALID_ALTITUDE 2 | VALID_HEADING 4 | VALID_VELOCITY 8 |
    // VALID_CALLSIGN 16 | VERTICAL_VELOCITY_VALID 128 | BARO_VALID 256.
    assert_eq!(le_u16(&p, 22), 1 | 2 | 4 | 8 | 16 | 128 | 256);
    assert_eq!(le_u16(&p, 24), 0, "no squawk");
    assert_eq!(p[26], 0, "pressure altitude");
    assert_eq!(&p[27..33], b"SWR123");
    assert_eq!(p[36], 0, "emitter type unknown");
    assert_eq!(p[37], 1, "tslc: 1.7 s in whole seconds");
    // The heartbeat: message id 0, MAV_TYPE_ADSB (27), MAV_AUTOPILOT_INVALID (8), active (4).
    let h = &frames[0];
    assert_eq!((h[0], u32::from_le_bytes([h[7], h[8], h[9], 0])), (0xFD, 0));
    let mut hp = h[10..10 + usize::from(h[1])].to_vec();
    hp.resize(9, 0);
    assert_eq!((hp[4], hp[5], hp[7], hp[8]), (27, 8, 4, 3));
}

#[test]
fn unknown_quantities_carry_no_validity_flag() {
    let mut t = target(0xABCDEF);
    t.velocity_ne_mps = None;
    t.vertical_rate_mps = None;
    t.callsign = None;
    // Unlike altitudes compared through a band: which kind the target's is, is not known.
    t.altitude_kind = AltitudeKind::Mixed;
    let v = vehicle(&t);
    assert_eq!(v.flags, FLAG_VALID_COORDS);
    t.altitude_kind = AltitudeKind::Geometric;
    let v = vehicle(&t);
    assert_eq!(v.flags, FLAG_VALID_COORDS | FLAG_VALID_ALTITUDE);
    assert_eq!(v.altitude_type, 1);
    t.alt_m = None;
    t.altitude_kind = AltitudeKind::None;
    assert_eq!(vehicle(&t).flags, FLAG_VALID_COORDS);
    // Due north: 0 deg, never 360.
    t.velocity_ne_mps = Some([30.0, -1e-9]);
    assert_eq!(vehicle(&t).heading_deg, 0.0);
    // Emitter category: 14 (UAV) is ADSB_EMITTER_TYPE_UAV (14); 20 (cluster obstacle, GDL90
    // only) has no MAVLink number: 0, no information.
    assert_eq!(vehicle(&t).emitter_type, 0, "not reported");
    t.reported.emitter_category = Some(14);
    assert_eq!(vehicle(&t).emitter_type, 14);
    t.reported.emitter_category = Some(20);
    assert_eq!(vehicle(&t).emitter_type, 0);
}

#[test]
fn each_target_and_the_heartbeat_at_most_once_a_second() {
    let mut enc = MavlinkTraffic::new(1, 156);
    let count = |frames: &[Vec<u8>], id: u32| {
        frames
            .iter()
            .filter(|f| u32::from_le_bytes([f[7], f[8], f[9], 0]) == id)
            .count()
    };
    let two = || vec![target(1), target(2)];
    let f = enc.picture(&picture(10.0, two()));
    assert_eq!((count(&f, 0), count(&f, 246)), (1, 2));
    // Half a second later: nothing is due.
    let f = enc.picture(&picture(10.5, two()));
    assert!(f.is_empty());
    // A new target is sent at once; the others wait for their second.
    let f = enc.picture(&picture(10.6, vec![target(1), target(2), target(3)]));
    assert_eq!((count(&f, 0), count(&f, 246)), (0, 1));
    let f = enc.picture(&picture(11.0, two()));
    assert_eq!((count(&f, 0), count(&f, 246)), (1, 2));
    // Sequence numbers run on across frames: 3 + 0 + 1 + 3 frames before this one.
    let f = enc.picture(&picture(12.0, vec![target(1)]));
    assert_eq!(f[0][4], 7);
}

#[test]
fn the_section_is_off_by_default_and_validated() {
    use crate::config::Config;
    let c = Config::parse("").unwrap();
    assert!(!c.outputs.mavlink.enabled());
    assert_eq!(
        (c.outputs.mavlink.system_id, c.outputs.mavlink.component_id),
        (1, 156)
    );
    let c =
        Config::parse("[outputs.mavlink]\naddress = \"127.0.0.1:14550\"\nsystem_id = 3\n").unwrap();
    assert!(c.outputs.mavlink.enabled() && c.validate().is_ok());
    for (text, key) in [
        (
            "[outputs.mavlink]\naddress = \"ground-station\"\n",
            "outputs.mavlink.address",
        ),
        (
            "[outputs.mavlink]\naddress = \"127.0.0.1\"\n",
            "outputs.mavlink.address",
        ),
        (
            "[outputs.mavlink]\nsystem_id = 0\n",
            "outputs.mavlink.system_id",
        ),
    ] {
        let e = Config::parse(text).unwrap().validate().unwrap_err();
        assert_eq!(e.key, key, "{text}");
    }
}
