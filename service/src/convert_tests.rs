//! Field-by-field checks of the conversions against hand-built inputs; expected values are worked
//! out in the comments (degrees -> radians, track/speed -> north/east, ns -> s).

use std::f64::consts::PI;

use vigil_bus::payload::attitude as att;
use vigil_bus::payload::integrity as integ;
use vigil_bus::payload::ownship as own;
use vigil_bus::payload::traffic as tr;
use vigil_drivers::DecodeStats;
use vigil_drivers::bahrs::{Health, Navigation, NavigationHealth};
use vigil_fusion::attitude::checker::AttitudeChecker;
use vigil_fusion::attitude::gates::GateReason;
use vigil_fusion::attitude::isolation::{Isolation, PairVerdict, Unit};
use vigil_fusion::attitude::params::CheckParams;
use vigil_fusion::attitude::record::{AttitudeRecord, VotedAxis};
use vigil_fusion::attitude::samples::BahrsSample;
use vigil_fusion::geometry::Geometry;
use vigil_fusion::magnetic::Wmm;
use vigil_fusion::ownship::{Ownship, OwnshipSolution, PositionSource};
use vigil_fusion::pipeline::TrafficPicture;
use vigil_fusion::time::aligner::{ClockReport, Device};
use vigil_fusion::time::{AlignedTime, ClockStatus, TimeSource};
use vigil_fusion::traffic::track::{AddressSpace, PlausibilityFlags, TargetKey};
use vigil_fusion::traffic::{AltitudeKind, Origins, Reported, Target, TrafficStats};

use super::*;

const T0: i64 = 1_464_350_418_000_000_000;

/// A real record from the checker (BAHRS only), whose fields the tests then set by hand.
fn record() -> AttitudeRecord {
    let mut c = AttitudeChecker::new(CheckParams::default(), Box::new(Wmm)).unwrap();
    let time = AlignedTime {
        t_gps_ns: T0,
        sigma_ns: 1e5,
        source: TimeSource::PpsDisciplined,
        status: ClockStatus::Locked,
    };
    let nav = Navigation::from_si(
        1,
        500.0,
        0.0,
        0.1,
        0.05,
        1.0,
        NavigationHealth::new(
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
            Health::Safe,
        ),
    );
    let b = BahrsSample::new(&time, &nav, None, None);
    c.compare_at(&b, false)
}

fn axis(value_deg: f64, used: Vec<Unit>, selected: Option<Unit>) -> VotedAxis {
    VotedAxis {
        value_deg,
        used: used.into_iter().collect(),
        selected,
    }
}

#[test]
fn attitude_fields_and_units() {
    let mut r = record();
    r.t_gps_ns = T0;
    r.bahrs.roll_deg = Some(10.0);
    r.bahrs.pitch_deg = Some(-5.0);
    r.bahrs.heading_deg = Some(370.0); // wraps to 10 deg
    r.bahrs.sigma_deg = Some([0.5, 0.25, 2.0]);
    r.bahrs.age_s = None;
    r.bahrs.gates.roll = None;
    r.bahrs.gates.pitch = None;
    r.bahrs.gates.heading = None;
    r.vn200.roll_deg = Some(11.0);
    r.vn200.pitch_deg = Some(-4.0);
    r.vn200.heading_deg = Some(180.0);
    r.vn200.sigma_deg = Some([0.1, 0.1, 0.3]);
    r.vn200.age_s = Some(0.004); // sample 4 ms before the comparison
    r.vn200.gates.roll = None;
    r.vn200.gates.pitch = None;
    r.vn200.gates.heading = Some(GateReason::Frozen);
    r.watson.roll_deg = None;
    r.watson.pitch_deg = None;
    r.watson.heading_deg = None;
    r.watson.sigma_deg = None;
    r.watson.gates.roll = Some(GateReason::Stale);
    r.watson.gates.pitch = Some(GateReason::Stale);
    r.watson.gates.heading = Some(GateReason::Stale);
    r.pairs.bahrs_vn200.roll.verdict = PairVerdict::Pass;
    r.pairs.bahrs_vn200.pitch.verdict = PairVerdict::Fail;
    r.pairs.bahrs_vn200.heading.verdict = PairVerdict::NotCompared;
    r.pairs.vn200_watson.roll.verdict = PairVerdict::NotCompared;
    r.isolated = Some(Unit::Vn200);
    r.fault = true;
    // Roll: median of the three is the VN-200's; pitch: two averaged, no median unit; heading:
    // none.
    r.voted.roll = Some(axis(
        11.0,
        vec![Unit::Bahrs, Unit::Vn200, Unit::Watson],
        Some(Unit::Vn200),
    ));
    r.voted.pitch = Some(axis(-4.5, vec![Unit::Bahrs, Unit::Vn200], None));
    r.voted.heading = None;

    let p = attitude(&r);
    let d = PI / 180.0;
    assert_eq!(p.header.gps_time_ns, T0);
    assert_eq!(p.roll_rad, 11.0 * d);
    assert_eq!(p.pitch_rad, -4.5 * d);
    assert!(p.heading_rad.is_nan());
    // Roll sigma: the selected VN-200's 0.1 deg; pitch: max(0.25, 0.1) deg of the two averaged.
    assert!((p.sigma_roll_rad - 0.1 * d).abs() < 1e-15);
    assert!((p.sigma_pitch_rad - 0.25 * d).abs() < 1e-15);
    assert!(p.sigma_heading_rad.is_nan());
    assert_eq!(p.valid, 0, "no voted heading");

    let b = &p.units[att::UNIT_BAHRS as usize];
    assert_eq!(b.t_gps_ns, T0);
    assert_eq!(b.roll_rad, 10.0 * d);
    assert_eq!(b.pitch_rad, -5.0 * d);
    // 370 deg = 10 deg = 0.174533 rad, inside [0, 2 pi).
    assert!((b.heading_rad - 10.0 * d).abs() < 1e-12);
    assert!((b.sigma_heading_rad - 2.0 * d).abs() < 1e-15);
    assert_eq!(b.valid, 1);
    assert_eq!(b.fault_flags, 0);

    let v = &p.units[att::UNIT_VN200 as usize];
    assert_eq!(v.t_gps_ns, T0 - 4_000_000);
    assert!((v.heading_rad - PI).abs() < 1e-15);
    assert_eq!(v.valid, 0, "heading gate closed");
    assert_eq!(v.fault_flags, att::FAULT_FROZEN | att::FAULT_ISOLATED);

    let w = &p.units[att::UNIT_WATSON as usize];
    assert_eq!(w.t_gps_ns, 0);
    assert!(w.roll_rad.is_nan() && w.sigma_roll_rad.is_nan());
    assert_eq!(w.valid, 0);
    assert_eq!(w.fault_flags, att::FAULT_STALE);

    assert_eq!(
        p.pair_verdicts[att::PAIR_BAHRS_VN200],
        [
            att::VERDICT_PASS,
            att::VERDICT_FAIL,
            att::VERDICT_NOT_COMPARED
        ]
    );
    assert_eq!(
        p.pair_verdicts[att::PAIR_VN200_WATSON][att::AXIS_ROLL],
        att::VERDICT_NOT_COMPARED
    );
    assert_eq!(p.isolation, att::ISOLATION_ISOLATED);
    assert_eq!(p.isolated_unit, att::UNIT_VN200);
}

#[test]
fn attitude_isolation_codes() {
    let mut r = record();
    r.isolated = None;
    r.fault = false;
    r.multiple_fault = false;
    r.isolation.roll = Isolation::NotCompared;
    r.isolation.pitch = Isolation::NotCompared;
    r.isolation.heading = Isolation::NotCompared;
    r.isolation.joint = Isolation::NotCompared;
    let p = attitude(&r);
    assert_eq!(p.isolation, att::ISOLATION_NOT_COMPARED);
    assert_eq!(p.isolated_unit, att::UNIT_NONE);
    r.isolation.roll = Isolation::NoFault;
    assert_eq!(attitude(&r).isolation, att::ISOLATION_NO_FAULT);
    r.fault = true;
    assert_eq!(attitude(&r).isolation, att::ISOLATION_DETECTED_NOT_ISOLATED);
    // A BAHRS with health "integrity risk" on roll is flagged as a health fault.
    r.bahrs.gates.roll = Some(GateReason::HealthIntegrityRisk);
    assert_eq!(
        attitude(&r).units[0].fault_flags & att::FAULT_HEALTH,
        att::FAULT_HEALTH
    );
}

fn ownship_at(t: i64) -> Ownship {
    Ownship {
        t_gps_ns: t,
        lat_deg: 47.4,
        lon_deg: 8.5,
        alt_pressure_m: Some(620.0),
        alt_geometric_m: None,
        track_deg: Some(30.0),
        ground_speed_mps: Some(40.0),
        vertical_rate_mps: Some(-1.5),
        heading_deg: Some(32.0),
        position_sigma_m: Some(2.5),
        source: PositionSource::Vn200Ins,
        alt_geometric_band_m: 0.0,
    }
}

#[test]
fn ownship_fields_and_units() {
    let s = OwnshipSolution {
        kind: "ownship",
        ownship: ownship_at(T0),
        velocity_sigma_mps: Some(0.2),
        nac_p: None,
        roll_deg: Some(1.0),
        pitch_deg: Some(2.0),
        heading_source: "vote",
    };
    let p = ownship(&s);
    assert_eq!(p.header.gps_time_ns, T0);
    assert_eq!((p.lat_deg, p.lon_deg), (47.4, 8.5));
    assert_eq!(p.alt_pressure_m, 620.0);
    assert!(p.alt_geometric_m.is_nan());
    // 40 m/s on track 30 deg: north 40 cos 30 = 34.641 m/s, east 40 sin 30 = 20 m/s.
    assert!((p.vel_north_mps - 34.641_016_151).abs() < 1e-8);
    assert!((p.vel_east_mps - 20.0).abs() < 1e-12);
    assert_eq!(p.vel_up_mps, -1.5);
    assert_eq!(p.ground_speed_mps, 40.0);
    assert_eq!(p.track_deg, 30.0);
    assert_eq!(p.sigma_horizontal_m, 2.5);
    assert!(p.sigma_vertical_m.is_nan());
    assert_eq!(p.sigma_velocity_mps, 0.2);
    assert_eq!(p.source, own::SOURCE_VN200_INS);
    assert_eq!(p.valid, 1);
    let mut s2 = s;
    s2.ownship.source = PositionSource::TtMultiRfGnss;
    s2.velocity_sigma_mps = None;
    let p2 = ownship(&s2);
    assert_eq!(p2.source, own::SOURCE_TTMRF_GNSS);
    assert!(p2.sigma_velocity_mps.is_nan());
}

fn geometry() -> Geometry {
    Geometry {
        horizontal_distance_m: 2000.0,
        vertical_separation_m: Some(150.0),
        range_rate_mps: Some(-60.0),
        tcpa_s: Some(30.0),
        hmd_m: Some(400.0),
        tau_mod_s: Some(20.0),
        well_clear_violated_now: false,
        loss_of_well_clear_interval_s: Some((12.5, 40.0)),
        alert_level: 2,
    }
}

fn fusion_target(address: u32, level: u8, geometry: Option<Geometry>) -> Target {
    Target {
        key: TargetKey {
            space: AddressSpace::Icao,
            address,
        },
        callsign: Some("SWR123".to_string()),
        sources: Vec::new(),
        age_s: 0.7,
        lat_deg: 47.41,
        lon_deg: 8.5,
        alt_m: Some(770.0),
        velocity_ne_mps: None,
        vertical_rate_mps: None,
        altitude_kind: AltitudeKind::Pressure,
        position_sigma_m: 10.0,
        bearing_true_deg: 90.0,
        bearing_relative_deg: Some(58.0),
        geometry,
        raw_alert_level: level,
        alert_level: level,
        flarm_alarm_level: None,
        flags: PlausibilityFlags::default(),
        fail_safe: Default::default(),
        reported: Reported {
            alt_pressure_m: Some(770.0),
            alt_geometric_m: None,
            track_deg: Some(270.0),
            ground_speed_mps: Some(50.0),
            nic: Some(8),
            nac_p: Some(9),
            nac_v: None,
            emitter_category: Some(1),
            origins: Origins {
                adsb: true,
                relayed: true,
                ..Origins::default()
            },
        },
    }
}

#[test]
fn target_fields_and_units() {
    let mut t = fusion_target(0x4B1801, 2, Some(geometry()));
    t.flags.position_jump = true;
    t.flags.inconsistent_sources = true;
    let p = target(&t, None);
    assert_eq!(p.address, 0x4B1801);
    assert_eq!(p.address_type, tr::ADDRESS_ICAO);
    assert_eq!(p.alert_level, tr::ALERT_CORRECTIVE);
    assert_eq!(p.altitude_kind, tr::ALTITUDE_PRESSURE);
    assert_eq!(
        p.plausibility_flags,
        tr::PLAUSIBILITY_POSITION_JUMP | tr::PLAUSIBILITY_INCONSISTENT_SOURCES
    );
    assert_eq!(&p.callsign, b"SWR123\0\0");
    // Bearing 90 deg (due east) at 2000 m: north 0, east 2000.
    assert!(p.rel_north_m.abs() < 1e-9);
    assert!((p.rel_east_m - 2000.0).abs() < 1e-9);
    assert!(p.rel_vel_north_mps.is_nan() && p.rel_vel_east_mps.is_nan());
    assert!(p.rel_vel_down_mps.is_nan());
    assert_eq!(p.horizontal_distance_m, 2000.0);
    // 150 m above the ownship is 150 m up: -150 m in the north-east-down frame.
    assert_eq!(p.rel_down_m, -150.0);
    assert_eq!(p.vertical_separation_m(), 150.0);
    // Reported state carried through in the payload's units, unknowns as NaN or NOT_REPORTED.
    assert_eq!((p.lat_deg, p.lon_deg), (47.41, 8.5));
    assert_eq!(p.alt_pressure_m, 770.0);
    assert!(p.alt_geometric_m.is_nan() && p.vertical_rate_mps.is_nan());
    assert_eq!((p.track_deg, p.ground_speed_mps), (270.0, 50.0));
    assert_eq!(p.position_sigma_m, 10.0);
    assert_eq!((p.nic, p.nac_p, p.nac_v), (8, 9, tr::NOT_REPORTED));
    assert_eq!(p.emitter_category, 1);
    assert_eq!(p.sources, tr::SOURCE_ADSB | tr::SOURCE_TISB);
    assert_eq!(p.bearing_deg, 90.0);
    assert_eq!(p.range_rate_mps, -60.0);
    assert_eq!(p.tcpa_s, 30.0);
    assert_eq!(p.hmd_m, 400.0);
    assert_eq!(p.tau_mod_s, 20.0);
    assert_eq!(p.time_to_lowc_s, 12.5, "start of the first loss interval");
    assert_eq!(p.age_s, 0.7);

    // Violated now: time to loss of well-clear 0; undefined tau is NaN.
    let mut g = geometry();
    g.well_clear_violated_now = true;
    g.tau_mod_s = None;
    let p = target(&fusion_target(1, 3, Some(g)), None);
    assert_eq!(p.time_to_lowc_s, 0.0);
    assert!(p.tau_mod_s.is_nan());

    // No geometry: distance from the positions (0.01 deg of latitude north of the ownship at
    // 47.4 deg: about 1112 m; the meridian arc is 111.2 km per degree here), geometry NaN.
    let mut t = fusion_target(2, 0, None);
    t.bearing_true_deg = 0.0;
    t.altitude_kind = AltitudeKind::None;
    t.callsign = None;
    let o = ownship_at(T0);
    let p = target(&t, Some(&o));
    assert!(
        (p.horizontal_distance_m - 1112.0).abs() < 3.0,
        "{}",
        p.horizontal_distance_m
    );
    assert!((p.rel_north_m - p.horizontal_distance_m).abs() < 1e-9);
    assert_eq!(p.altitude_kind, tr::ALTITUDE_UNKNOWN);
    assert!(p.rel_down_m.is_nan() && p.range_rate_mps.is_nan());
    assert!(p.time_to_lowc_s.is_nan());
    assert_eq!(p.callsign, [0; tr::CALLSIGN_LEN]);

    // Relative velocity: intruder (north 0, east -50, down -2: westbound, climbing 2 m/s) minus
    // the ownship (track 30 deg at 40 m/s: north 34.641, east 20.0; vertical rate -1.5 m/s,
    // down +1.5): down -2 - 1.5 = -3.5 m/s.
    let mut t = fusion_target(3, 0, Some(geometry()));
    t.velocity_ne_mps = Some([0.0, -50.0]);
    t.vertical_rate_mps = Some(2.0);
    let p = target(&t, Some(&o));
    assert!((p.rel_vel_north_mps - (0.0 - 34.641_016)).abs() < 1e-6);
    assert!((p.rel_vel_east_mps - (-50.0 - 20.0)).abs() < 1e-9);
    assert!((p.rel_vel_down_mps - (-3.5)).abs() < 1e-9);
    // Without the ownship it is unknown.
    assert!(target(&t, None).rel_vel_north_mps.is_nan());
}

#[test]
fn traffic_keeps_priority_order_bounds_and_counts_dropped() {
    let n = tr::MAX_TARGETS + 3;
    let targets: Vec<Target> = (0..n as u32)
        .map(|i| fusion_target(i, 0, Some(geometry())))
        .collect();
    let pic = TrafficPicture {
        kind: "traffic",
        t_gps_ns: T0,
        targets,
        stats: TrafficStats::default(),
    };
    let mut out = Box::<TrafficPayload>::default();
    out.header.seq = 99;
    traffic(&pic, None, &mut out);
    assert_eq!(out.header.gps_time_ns, T0);
    assert_eq!(out.header.seq, 0, "header reset (the publisher stamps it)");
    assert_eq!(out.count(), tr::MAX_TARGETS);
    assert_eq!(out.dropped, 3);
    // Order kept: slot i holds the picture's i-th target.
    assert_eq!(out.targets[0].address, 0);
    assert_eq!(
        out.targets[tr::MAX_TARGETS - 1].address,
        tr::MAX_TARGETS as u32 - 1
    );
    // A smaller picture afterwards: the count shrinks and nothing is dropped.
    let small = TrafficPicture {
        targets: pic.targets[..2].to_vec(),
        ..pic.clone()
    };
    traffic(&small, None, &mut out);
    assert_eq!((out.count(), out.dropped), (2, 0));
}

#[test]
fn integrity_fields_and_clock() {
    let stats = DecodeStats {
        bytes_consumed: 1000,
        bytes_skipped: 7,
        frames_decoded: 40,
        checksum_failures: 2,
        unknown_types: 1,
        malformed: 3,
        unsupported_version: 1,
        ..DecodeStats::default()
    };
    let ports = [
        PortReport {
            name: "bahrs",
            protocol: Protocol::Bahrs,
            link_state: integ::LINK_OK,
            last_message_age_s: Some(0.02),
            bytes_received: 1010,
            stats: Some(stats),
            reconnects: 2,
        },
        PortReport {
            name: "tt",
            protocol: Protocol::TtmrfHex,
            link_state: integ::LINK_DISCONNECTED,
            last_message_age_s: None,
            bytes_received: 0,
            stats: None,
            reconnects: 0,
        },
    ];
    let report = |device, status, offset_ns, residual_ns| ClockReport {
        device,
        status,
        offset_ns,
        drift_ppm: None,
        residual_ns,
    };
    let clocks = [
        report(Device::Bahrs, ClockStatus::Locked, Some(5e5), Some(100.0)),
        report(
            Device::Watson,
            ClockStatus::Locked,
            Some(-2.5e6),
            Some(1.5e5),
        ),
        report(Device::Vn200, ClockStatus::Locked, None, None),
        report(
            Device::Ttmrf,
            ClockStatus::Locked,
            Some(-2.5e6),
            Some(1.5e5),
        ),
    ];
    let p = integrity(&ports, &clocks, true, T0);
    assert_eq!(p.header.gps_time_ns, T0);
    assert_eq!(p.device_count, 2);
    assert_eq!(p.clock_status, integ::CLOCK_PPS_LOCKED);
    assert_eq!(p.leap_seconds_known, 1);
    // Host clock minus GPS: -2.5e6 ns = -2.5 ms; sigma 1.5e5 ns = 150 us.
    assert_eq!(p.clock_offset_s, -2.5e-3);
    assert_eq!(p.clock_sigma_s, 1.5e-4);
    let d = &p.devices()[0];
    assert_eq!(vigil_bus::payload::read_text(&d.name), "bahrs");
    assert_eq!(d.device, integ::DEVICE_BAHRS);
    assert_eq!(d.link_state, integ::LINK_OK);
    assert_eq!(d.last_message_age_s, 0.02);
    assert_eq!(d.bytes_received, 1010);
    assert_eq!(
        (d.bytes_consumed, d.bytes_skipped, d.messages),
        (1000, 7, 40)
    );
    assert_eq!((d.checksum_failures, d.unknown_types), (2, 1));
    assert_eq!(d.malformed, 4, "malformed 3 + unsupported version 1");
    assert_eq!(d.reconnects, 2);
    let e = &p.devices()[1];
    assert_eq!(e.device, integ::DEVICE_TTMRF);
    assert_eq!(e.link_state, integ::LINK_DISCONNECTED);
    assert!(e.last_message_age_s.is_nan());
    assert_eq!(e.messages, 0);
}

#[test]
fn clock_status_codes() {
    let r = |device, status| ClockReport {
        device,
        status,
        offset_ns: None,
        drift_ppm: None,
        residual_ns: None,
    };
    use ClockStatus::*;
    let all = |b, w, v| {
        [
            r(Device::Bahrs, b),
            r(Device::Watson, w),
            r(Device::Vn200, v),
        ]
    };
    assert_eq!(
        clock_status(&all(Locked, Unlocked, Unlocked)),
        integ::CLOCK_PPS_LOCKED
    );
    assert_eq!(
        clock_status(&all(Locking, Unlocked, Locked)),
        integ::CLOCK_GPS_TIME
    );
    assert_eq!(
        clock_status(&all(Unlocked, Locked, Unlocked)),
        integ::CLOCK_GPS_TIME
    );
    assert_eq!(
        clock_status(&all(Unlocked, Unlocked, Coasting)),
        integ::CLOCK_HOLDOVER
    );
    assert_eq!(
        clock_status(&all(Unlocked, Locking, Unlocked)),
        integ::CLOCK_NOT_LOCKED
    );
    assert_eq!(clock_status(&[]), integ::CLOCK_NOT_LOCKED);
    let p = integrity(&[], &[], false, 0);
    assert!(p.clock_offset_s.is_nan() && p.clock_sigma_s.is_nan());
    assert_eq!(p.leap_seconds_known, 0);
}

// --- issue 25 point 4 ---

/// The integrity payload's health fields: each BAHRS signal's health in protocol order, the
/// VN-200 status decoded by hand from the ICD's bit layout, and the verdicts with their codes.
#[test]
fn integrity_health_fields_from_the_health_check() {
    use vigil_drivers::bahrs::InertialHealth;
    use vigil_drivers::vn200::status::InsStatus;
    use vigil_fusion::attitude::health::{HealthCheck, HealthParams};
    const S: i64 = 1_000_000_000;
    // Nothing known: every field says so.
    let mut p = integrity(&[], &[], false, 0);
    health(&mut p, &HealthCheck::new(HealthParams::default()), None);
    assert_eq!(p.bahrs_navigation_health, [att::HEALTH_NONE; 5]);
    assert_eq!(p.bahrs_inertial_health, [att::HEALTH_NONE; 6]);
    assert_eq!(
        (p.vn200_ins_mode, p.vn200_gnss_fix),
        (integ::VN200_STATUS_NONE, integ::VN200_STATUS_NONE)
    );
    assert!(p.vn200_status_age_s.is_nan() && p.bahrs_pulse_age_s.is_nan());
    for c in p.health_checks {
        assert_eq!(
            (c.state, c.reason),
            (integ::HEALTH_NOT_COMPARED, integ::HEALTH_WHY_NO_CLOCK)
        );
    }
    // Pressure height unavailable, velocity down integrity risk, the rest safe; angular rate z
    // undefined. VN-200 0x0043: mode 3 (GnssLost), fix bit 2 clear, GnssErr bit 6 set.
    let mut h = HealthCheck::new(HealthParams::default());
    h.vn200_status(10 * S, InsStatus(0x0043));
    h.bahrs_navigation(NavigationHealth::new(
        Health::Unavailable,
        Health::IntegrityRisk,
        Health::Safe,
        Health::Safe,
        Health::Safe,
    ));
    h.bahrs_inertial(InertialHealth::new(
        [Health::Safe; 3],
        [Health::Safe, Health::Safe, Health::Undefined],
    ));
    h.bahrs_pulse();
    let mut p = integrity(&[], &[], false, 0);
    health(&mut p, &h, Some(10 * S + S / 2));
    assert_eq!(
        p.bahrs_navigation_health,
        [
            att::HEALTH_UNAVAILABLE,
            att::HEALTH_INTEGRITY_RISK,
            att::HEALTH_SAFE,
            att::HEALTH_SAFE,
            att::HEALTH_SAFE
        ]
    );
    assert_eq!(
        p.bahrs_inertial_health,
        [1, 1, 1, 1, 1, att::HEALTH_UNDEFINED]
    );
    assert_eq!((p.vn200_ins_mode, p.vn200_gnss_fix), (3, 0));
    assert_eq!(p.vn200_ins_status, 0x0043);
    assert!((p.vn200_status_age_s - 0.5).abs() < 1e-9);
    assert!((p.bahrs_pulse_age_s - 0.5).abs() < 1e-9);
    // The pulse came with the loss itself (within one PPS period): agreement; the BAHRS did
    // pulse, so "fix without pulses" is compared and agrees (no fix).
    assert!(
        p.health_checks
            .iter()
            .all(|c| c.state == integ::HEALTH_AGREE)
    );
    // The status 2 s old: not compared, stale.
    health(&mut p, &h, Some(12 * S));
    assert!(p.health_checks.iter().all(|c| {
        (c.state, c.reason) == (integ::HEALTH_NOT_COMPARED, integ::HEALTH_WHY_VN200_STALE)
    }));
    // A pulse 2 s after the loss with no fix: disagreement, lasting 0.25 s at the report.
    h.vn200_status(12 * S, InsStatus(0x0043));
    h.bahrs_pulse();
    health(&mut p, &h, Some(12 * S + S / 4));
    let c = p.health_checks[integ::HEALTH_PPS_WITHOUT_FIX];
    assert_eq!(
        (c.state, c.reason),
        (integ::HEALTH_DISAGREE, integ::HEALTH_WHY_NONE)
    );
    assert!((c.disagree_s - 0.25).abs() < 1e-9, "{c:?}");
}
