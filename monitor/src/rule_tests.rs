//! Per-rule tests: hand-built payloads fed to a [`Monitor`] on a 100 ms grid, checking which
//! alert rises or clears, when, with which id, severity and reason.

use vigil_bus::payload::alerts::{
    AlertPayload, SEVERITY_ADVISORY, SEVERITY_CAUTION, SEVERITY_WARNING, STATE_CLEARED,
    STATE_LATCHED, STATE_RAISED,
};
use vigil_bus::payload::attitude::{
    AXIS_PITCH, AXIS_ROLL, AttitudePayload, COVERAGE_COMPARED, FAULT_HEALTH, FAULT_INVALID,
    ISOLATION_ISOLATED, ISOLATION_NO_FAULT, PAIR_BAHRS_VN200, PAIR_BAHRS_WATSON, UNIT_BAHRS,
    UNIT_NONE, UNIT_VN200, UnitAttitude, VERDICT_FAIL, VERDICT_PASS,
};
use vigil_bus::payload::integrity::{
    CLOCK_GPS_TIME, CLOCK_HOLDOVER, CLOCK_NOT_LOCKED, CLOCK_PPS_LOCKED, DEVICE_BAHRS, DEVICE_TTMRF,
    DEVICE_VN200, DEVICE_WATSON, DeviceIntegrity, IntegrityPayload, LINK_DISCONNECTED, LINK_OK,
    LINK_SILENT,
};
use vigil_bus::payload::ownship::{
    OwnshipPayload, SOURCE_NONE, SOURCE_TTMRF_GNSS, SOURCE_VN200_INS,
};
use vigil_bus::payload::traffic::{
    ADDRESS_ICAO, ADDRESS_NON_ICAO, ALERT_CORRECTIVE, ALERT_PREVENTIVE, ALERT_WARNING,
    PLAUSIBILITY_IMPOSSIBLE_SPEED, PLAUSIBILITY_POSITION_JUMP, Target, TrafficPayload,
};
use vigil_bus::payload::write_text;

use crate::{Monitor, MonitorParams, Phase, Rule};

const MS: i64 = 1_000_000;
/// A GPS time far from 0, so that nothing depends on starting at 0 (ns).
const T0: i64 = 1_400_000_000 * 1_000_000_000;

/// Nominal payloads of every topic and a monitor fed with them every 100 ms.
struct Rig {
    m: Monitor,
    att: AttitudePayload,
    own: OwnshipPayload,
    traffic: Box<TrafficPayload>,
    integ: IntegrityPayload,
    /// Time of the next step, ms after [`T0`].
    t_ms: i64,
    /// Feed the ownship payload (false: that topic falls silent).
    feed_ownship: bool,
    /// Per-step increments of device slot 0's messages and checksum failures.
    counting: (u64, u64),
}

fn unit(roll_deg: f64) -> UnitAttitude {
    UnitAttitude {
        roll_rad: roll_deg.to_radians(),
        pitch_rad: 2f64.to_radians(),
        heading_rad: 90f64.to_radians(),
        valid: 1,
        ..UnitAttitude::default()
    }
}

fn device(name: &str, kind: u8) -> DeviceIntegrity {
    let mut d = DeviceIntegrity {
        device: kind,
        link_state: LINK_OK,
        last_message_age_s: 0.01,
        ..DeviceIntegrity::default()
    };
    write_text(&mut d.name, name);
    d
}

impl Rig {
    fn new(params: MonitorParams) -> Self {
        let att = AttitudePayload {
            valid: 1,
            units: [unit(3.0), unit(3.0), unit(3.0)],
            pair_verdicts: [[VERDICT_PASS; 3]; 3],
            isolation: ISOLATION_NO_FAULT,
            isolated_unit: UNIT_NONE,
            ..AttitudePayload::default()
        };
        let own = OwnshipPayload {
            source: SOURCE_VN200_INS,
            valid: 1,
            sigma_horizontal_m: 2.5,
            ..OwnshipPayload::default()
        };
        let mut integ = IntegrityPayload {
            clock_status: CLOCK_PPS_LOCKED,
            device_count: 4,
            clock_offset_s: 0.0,
            clock_sigma_s: 1e-6,
            ..IntegrityPayload::default()
        };
        integ.devices[0] = device("bahrs", DEVICE_BAHRS);
        integ.devices[1] = device("vn200", DEVICE_VN200);
        integ.devices[2] = device("watson", DEVICE_WATSON);
        integ.devices[3] = device("ttmrf", DEVICE_TTMRF);
        Self {
            m: Monitor::new(params),
            att,
            own,
            traffic: Box::default(),
            integ,
            t_ms: 0,
            feed_ownship: true,
            counting: (10, 0),
        }
    }

    /// One step: feed every topic, poll at the step's time, advance 100 ms. Returns
    /// (time ms, alerts).
    fn step(&mut self) -> (i64, Vec<AlertPayload>) {
        let t = T0 + self.t_ms * MS;
        self.integ.devices[0].messages += self.counting.0;
        self.integ.devices[0].checksum_failures += self.counting.1;
        self.att.header.gps_time_ns = t;
        self.m.attitude(&self.att);
        if self.feed_ownship {
            self.m.ownship(&self.own);
        }
        self.m.traffic(&self.traffic);
        self.m.integrity(&self.integ);
        let alerts = self.m.poll(t);
        let now = self.t_ms;
        self.t_ms += 100;
        (now, alerts)
    }

    /// Steps for `ms` milliseconds; returns every alert with the time (ms) it was published.
    fn run(&mut self, ms: i64) -> Vec<(i64, AlertPayload)> {
        let end = self.t_ms + ms;
        let mut out = Vec::new();
        while self.t_ms < end {
            let (t, alerts) = self.step();
            out.extend(alerts.into_iter().map(|a| (t, a)));
        }
        out
    }
}

/// The single alert in `alerts`, checked for id, state and severity.
fn only(alerts: &[(i64, AlertPayload)], id: u32, state: u8, severity: u8) -> (i64, AlertPayload) {
    assert_eq!(alerts.len(), 1, "{alerts:#?}");
    let (t, a) = alerts[0];
    assert_eq!(
        (a.alert_id, a.state, a.severity),
        (id, state, severity),
        "{}",
        a.reason()
    );
    assert_eq!(
        a.header.gps_time_ns,
        T0 + t * MS,
        "published at the poll time"
    );
    (t, a)
}

#[test]
fn nominal_payloads_raise_nothing() {
    let mut rig = Rig::new(MonitorParams::default());
    let alerts = rig.run(60_000);
    assert!(alerts.is_empty(), "{alerts:#?}");
}

#[test]
fn roll_miscompare_raises_at_once_and_clears_after_one_second() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(1000);
    rig.att.units[0] = unit(12.0);
    rig.att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_ROLL] = VERDICT_FAIL;
    rig.att.pair_verdicts[PAIR_BAHRS_WATSON][AXIS_ROLL] = VERDICT_FAIL;
    let id = Rule::AttitudeMiscompare.alert_id(AXIS_ROLL as u32);
    assert_eq!(id, 0x0100_0000);
    let (t, a) = only(&rig.run(3000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 1000);
    assert_eq!(
        a.reason(),
        "roll miscompare (BAHRS/VN-200, BAHRS/Watson fail): BAHRS 12.0, VN-200 3.0, Watson 3.0 deg"
    );
    // Passing again from t = 4.0 s: hysteresis 1 s, cleared at 5.0 s.
    rig.att.pair_verdicts = [[VERDICT_PASS; 3]; 3];
    let (t, a) = only(&rig.run(3000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 5000);
    assert_eq!(a.raised_gps_ns, T0 + 1000 * MS);
    assert!(
        a.reason().starts_with("cleared: roll miscompare"),
        "{}",
        a.reason()
    );
}

#[test]
fn miscompares_on_two_axes_come_out_in_id_order() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_PITCH] = VERDICT_FAIL;
    rig.att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_ROLL] = VERDICT_FAIL;
    let (_, alerts) = rig.step();
    let ids: Vec<u32> = alerts.iter().map(|a| a.alert_id).collect();
    assert_eq!(ids, [0x0100_0000, 0x0100_0001]);
    // The monitor numbers its transitions 1, 2, ...
    let seqs: Vec<u64> = alerts.iter().map(|a| a.header.seq).collect();
    assert_eq!(seqs, [1, 2]);
    assert!(
        alerts
            .iter()
            .all(|a| a.header.schema_version == vigil_bus::payload::SCHEMA_VERSION)
    );
}

#[test]
fn isolated_unit_names_the_unit() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.isolation = ISOLATION_ISOLATED;
    rig.att.isolated_unit = UNIT_VN200;
    rig.att.units[1] = unit(-7.5);
    let (t, a) = only(&rig.run(500), 0x0200_0001, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 0);
    assert!(
        a.reason().starts_with(
            "VN-200 isolated by the cross-check (roll -7.5, pitch 2.0, heading 90.0 deg"
        ),
        "{}",
        a.reason()
    );
    // Hysteresis 2 s.
    rig.att.isolation = ISOLATION_NO_FAULT;
    rig.att.isolated_unit = UNIT_NONE;
    let (t, _) = only(&rig.run(5000), 0x0200_0001, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 2500);
}

/// Issue 25: the BAHRS stops being compared at 1.0 s (its samples arrive unaligned): the
/// alert raises after the 2 s raise delay, at 3.0 s, naming the unit, the reason and the age;
/// comparisons resume at 5.0 s and it clears after the 1 s hysteresis, at 6.0 s.
#[test]
fn cross_check_unavailable_names_the_unit_and_why_and_clears_when_compared_again() {
    use vigil_bus::payload::attitude::{COVERAGE_COMPARED, COVERAGE_NOT_ALIGNED};
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(1000);
    let b = usize::from(UNIT_BAHRS);
    rig.att.unit_coverage[b] = COVERAGE_NOT_ALIGNED;
    rig.att.unit_compared_age_s[b] = 0.6;
    let id = Rule::CrossCheckUnavailable.alert_id(u32::from(UNIT_BAHRS));
    assert_eq!(id, 0x0B00_0000);
    let (t, a) = only(&rig.run(4000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 3000);
    assert_eq!(
        a.reason(),
        "BAHRS not cross-checked: not_aligned (last compared 0.6 s ago)"
    );
    rig.att.unit_coverage[b] = COVERAGE_COMPARED;
    let (t, _) = only(&rig.run(3000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 6000);
    // Never compared at all: the age is NaN and the reason says so.
    rig.att.unit_coverage[b] = vigil_bus::payload::attitude::COVERAGE_NOT_WIRED;
    rig.att.unit_compared_age_s[b] = f64::NAN;
    let (_, a) = only(&rig.run(3000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "BAHRS not cross-checked: not_wired (never compared)"
    );
}

/// Issue 25: the active set as state. An alert raised at 1.0 s is in the set of every report
/// filled from then on (severity, raise time, reason), the most severe first; cleared, it is
/// gone. A pending alert (raise delay not over) is not active.
#[test]
fn the_active_set_holds_raised_alerts_most_severe_first() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(1000);
    rig.att.units[usize::from(UNIT_BAHRS)].fault_flags = FAULT_HEALTH;
    rig.att.valid = 0;
    rig.run(500);
    let mut p = IntegrityPayload::default();
    rig.m.fill_active(&mut p);
    // unit_health raised at 1.0 s; attitude_invalid still pending (1 s delay).
    assert_eq!((p.active_alert_count, p.active_alert_total), (1, 1));
    let a = p.active_alerts()[0];
    assert_eq!((a.alert_id, a.state), (0x0300_0000, STATE_RAISED));
    assert_eq!(a.raised_gps_ns, T0 + 1000 * MS);
    assert!(a.reason().starts_with("BAHRS health integrity risk"));
    rig.run(10_000);
    rig.m.fill_active(&mut p);
    let ids: Vec<(u32, u8)> = p
        .active_alerts()
        .iter()
        .map(|a| (a.alert_id, a.severity))
        .collect();
    assert_eq!(
        ids,
        [
            (0x0400_0000, SEVERITY_WARNING),
            (0x0300_0000, SEVERITY_CAUTION)
        ]
    );
    rig.att.units[usize::from(UNIT_BAHRS)].fault_flags = 0;
    rig.att.valid = 1;
    rig.run(3000);
    rig.m.fill_active(&mut p);
    assert_eq!((p.active_alert_count, p.active_alert_total), (0, 0));
}

#[test]
fn bahrs_integrity_risk_raises_at_the_first_sample() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(700);
    rig.att.units[usize::from(UNIT_BAHRS)].fault_flags = FAULT_HEALTH;
    let (t, a) = only(&rig.run(1000), 0x0300_0000, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 700, "the first sample with the flag");
    assert!(
        a.reason().starts_with("BAHRS health integrity risk"),
        "{}",
        a.reason()
    );
}

#[test]
fn voted_attitude_invalid_is_a_warning_after_one_second() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.valid = 0;
    rig.att.units[0].fault_flags = FAULT_INVALID;
    let (t, a) = only(&rig.run(3000), 0x0400_0000, STATE_RAISED, SEVERITY_WARNING);
    assert_eq!(t, 1000);
    assert_eq!(
        a.reason(),
        "voted attitude unusable; unit fault flags BAHRS 0x01 VN-200 0x00 Watson 0x00"
    );
}

#[test]
fn ins_not_tracking_after_one_second() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(200);
    rig.att.units[usize::from(UNIT_VN200)].fault_flags = FAULT_INVALID;
    rig.att.units[usize::from(UNIT_VN200)].valid = 0;
    let (t, a) = only(&rig.run(3000), 0x0500_0000, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 1200);
    assert_eq!(
        a.reason(),
        "VN-200 INS not tracking: attitude invalid (INS mode or error bits; fault flags 0x01)"
    );
}

#[test]
fn gnss_lost_escalates_with_the_position_source() {
    let mut rig = Rig::new(MonitorParams::default());
    let id = 0x0600_0000;
    // TT-Multi-RF fallback from 0: advisory after 1 s.
    rig.own.source = SOURCE_TTMRF_GNSS;
    rig.own.sigma_horizontal_m = 7.0;
    let (t, a) = only(&rig.run(2000), id, STATE_RAISED, SEVERITY_ADVISORY);
    assert_eq!(t, 1000);
    assert_eq!(
        a.reason(),
        "INS GNSS lost: ownship position from the TT-Multi-RF GNSS fallback (sigma_h 7.0 m)"
    );
    // No position at all at 2.0 s: caution at once (a severity change of a raised alert).
    rig.own.source = SOURCE_NONE;
    rig.own.valid = 0;
    let (t, a) = only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 2000);
    assert_eq!(a.raised_gps_ns, T0 + 1000 * MS, "first raise time kept");
    // Back on the INS at 3.0 s: cleared after 2 s.
    rig.own.source = SOURCE_VN200_INS;
    rig.own.valid = 1;
    let (t, _) = only(&rig.run(4000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 5000);
}

#[test]
fn clock_states_and_their_severities() {
    let id = 0x0700_0000;
    let mut rig = Rig::new(MonitorParams::default());
    rig.integ.clock_status = CLOCK_NOT_LOCKED;
    let (t, a) = only(&rig.run(3000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 2000);
    assert!(a.reason().starts_with("clock not locked"), "{}", a.reason());
    rig.integ.clock_status = CLOCK_HOLDOVER;
    only(&rig.run(1000), id, STATE_RAISED, SEVERITY_ADVISORY);
    rig.integ.clock_status = 9;
    let (_, a) = only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert!(a.reason().contains("code 9"), "{}", a.reason());

    // GPS time without PPS: fine unless PPS is required.
    let mut rig = Rig::new(MonitorParams::default());
    rig.integ.clock_status = CLOCK_GPS_TIME;
    assert!(rig.run(5000).is_empty());
    let mut rig = Rig::new(MonitorParams {
        clock_require_pps: true,
        ..MonitorParams::default()
    });
    rig.integ.clock_status = CLOCK_GPS_TIME;
    only(&rig.run(5000), id, STATE_RAISED, SEVERITY_ADVISORY);
}

#[test]
fn device_silent_by_age_by_link_and_never_heard() {
    // VN-200 in slot 1: subject (DEVICE_VN200 << 8) | 1 = 0x101.
    let id = 0x0800_0101;
    let mut rig = Rig::new(MonitorParams::default());
    rig.integ.devices[1].last_message_age_s = 2.0;
    assert!(
        rig.run(1000).is_empty(),
        "2.0 s is not over the 2.0 s limit"
    );
    rig.integ.devices[1].last_message_age_s = 2.5;
    let (_, a) = only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "device vn200 (VN-200) silent: last message 2.5 s ago (limit 2.0 s)"
    );
    rig.integ.devices[1].last_message_age_s = 0.01;
    rig.integ.devices[1].link_state = LINK_DISCONNECTED;
    assert!(rig.run(1000).is_empty(), "still silent: no change");
    // Each link state alone raises it too, with its own reason.
    let mut other = Rig::new(MonitorParams::default());
    other.integ.devices[1].link_state = LINK_DISCONNECTED;
    other.integ.devices[1].reconnects = 3;
    let (_, a) = only(&other.run(100), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "device vn200 (VN-200) disconnected (reconnects 3)"
    );
    let mut other = Rig::new(MonitorParams::default());
    other.integ.devices[1].link_state = LINK_SILENT;
    other.integ.devices[1].last_message_age_s = f64::NAN;
    let (_, a) = only(&other.run(100), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "device vn200 (VN-200) link silent: no message yet"
    );
    rig.integ.devices[1].link_state = LINK_OK;
    let (t, _) = only(&rig.run(2000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 4000, "link OK again at 3.0 s, hysteresis 1 s");

    // A device never heard from (age NaN): silent once it has existed for more than 2 s.
    let mut rig = Rig::new(MonitorParams::default());
    rig.integ.devices[3].last_message_age_s = f64::NAN;
    let (t, a) = only(&rig.run(3000), 0x0800_0303, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 2100);
    assert!(a.reason().contains("no message in 2.1 s"), "{}", a.reason());
}

#[test]
fn decode_error_rate_is_judged_per_window() {
    // Slot 0 (BAHRS): 10 messages and 1 checksum failure per 100 ms step. The baseline is the
    // first payload (t = 0, counters after the first step); the window is judged at t = 10.0 s:
    // 100 steps later, 1000 messages and 100 failures: 100 / 1100 = 9.1 % > 5 %.
    let id = 0x0900_0000;
    let mut rig = Rig::new(MonitorParams::default());
    rig.counting = (10, 1);
    let (t, a) = only(&rig.run(15_000), id, STATE_RAISED, SEVERITY_ADVISORY);
    assert_eq!(t, 10_000);
    assert_eq!(
        a.reason(),
        "device bahrs (BAHRS) decode errors: 100 of 1100 frames rejected in 10.0 s (9.1 %, limit 5.0 %)"
    );
    // Failures stop at 15 s: the window judged at 20 s still has 50 of 1050 (4.8 %): cleared.
    rig.counting = (10, 0);
    let (t, _) = only(&rig.run(10_000), id, STATE_CLEARED, SEVERITY_ADVISORY);
    assert_eq!(t, 20_000);

    // 4 % is under the limit.
    let mut rig = Rig::new(MonitorParams::default());
    rig.counting = (24, 1);
    assert!(rig.run(30_000).is_empty());
    // Too few frames to judge: 2 frames per second, half of them bad.
    let mut rig = Rig::new(MonitorParams {
        decode_window_s: 5.0,
        ..MonitorParams::default()
    });
    rig.counting = (0, 0);
    for _ in 0..50 {
        rig.integ.devices[0].messages += u64::from(rig.t_ms % 1000 == 0);
        rig.integ.devices[0].checksum_failures += u64::from(rig.t_ms % 1000 == 500);
        assert!(rig.step().1.is_empty());
    }
}

#[test]
fn a_counter_reset_starts_a_new_baseline() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.integ.devices[0].messages = 1_000_000;
    rig.run(5000);
    // The publisher restarted: counters from 0. Without a new baseline the difference would
    // wrap; with it, 10 messages per step and no failures raise nothing.
    rig.integ.devices[0].messages = 0;
    assert!(rig.run(30_000).is_empty());
}

#[test]
fn a_silent_topic_raises_feed_silent_and_its_return_clears_it() {
    let id = 0x0A00_0001;
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(1000);
    // Last ownship at 0.9 s; silent for more than 2 s first at 3.0 s (2.1 s).
    rig.feed_ownship = false;
    let (t, a) = only(&rig.run(4000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 3000);
    assert_eq!(a.reason(), "no ownship payload for 2.1 s (limit 2.0 s)");
    rig.feed_ownship = true;
    let (t, _) = only(&rig.run(1000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 5000);
}

#[test]
fn a_topic_never_received_is_silent_from_the_first_poll() {
    let mut m = Monitor::new(MonitorParams::default());
    let att = AttitudePayload {
        valid: 1,
        ..AttitudePayload::default()
    };
    let mut raised = Vec::new();
    for i in 0..30 {
        m.attitude(&att);
        for a in m.poll(T0 + i * 100 * MS) {
            raised.push((i * 100, a.alert_id));
        }
    }
    // Ownship, traffic, integrity (subjects 1, 2, 3) at 2.1 s; attitude fed, so not subject 0.
    assert_eq!(
        raised,
        [
            (2100, 0x0A00_0001),
            (2100, 0x0A00_0002),
            (2100, 0x0A00_0003)
        ]
    );
}

fn target(address: u32, address_type: u8, level: u8, flags: u8) -> Target {
    let mut t = Target {
        address,
        address_type,
        alert_level: level,
        plausibility_flags: flags,
        horizontal_distance_m: 1234.4,
        // 150 m above the ownship.
        rel_down_m: -150.0,
        time_to_lowc_s: 23.45,
        ..Target::EMPTY
    };
    write_text(&mut t.callsign, "N123AB");
    t
}

#[test]
fn traffic_levels_map_to_severities_per_target() {
    let mut rig = Rig::new(MonitorParams::default());
    let id = 0x20AB_CDEF;
    rig.traffic
        .set_targets(&[target(0xABCDEF, ADDRESS_ICAO, ALERT_PREVENTIVE, 0)]);
    let (t, a) = only(&rig.run(500), id, STATE_RAISED, SEVERITY_ADVISORY);
    assert_eq!(t, 0);
    assert_eq!(
        a.reason(),
        "traffic ABCDEF (N123AB) preventive: range 1234 m, vertical +150 m, time to LoWC 23.4 s"
    );
    rig.traffic
        .set_targets(&[target(0xABCDEF, ADDRESS_ICAO, ALERT_CORRECTIVE, 0)]);
    only(&rig.run(500), id, STATE_RAISED, SEVERITY_CAUTION);
    // A second aircraft with the same 24 bits but a non-ICAO address: its own alert.
    rig.traffic.set_targets(&[
        target(0xABCDEF, ADDRESS_NON_ICAO, ALERT_WARNING, 0),
        target(0xABCDEF, ADDRESS_ICAO, ALERT_CORRECTIVE, 0),
    ]);
    only(&rig.run(500), 0x21AB_CDEF, STATE_RAISED, SEVERITY_WARNING);
    // Both gone from the picture: both cleared (hysteresis 0), in id order.
    rig.traffic.set_targets(&[]);
    let alerts = rig.run(500);
    let got: Vec<(u32, u8)> = alerts.iter().map(|(_, a)| (a.alert_id, a.state)).collect();
    assert_eq!(got, [(id, STATE_CLEARED), (0x21AB_CDEF, STATE_CLEARED)]);
}

#[test]
fn implausible_targets_raise_suspected_spoofing() {
    let id = 0x30AB_CDEF;
    let mut rig = Rig::new(MonitorParams::default());
    let flags = PLAUSIBILITY_IMPOSSIBLE_SPEED | PLAUSIBILITY_POSITION_JUMP;
    rig.traffic
        .set_targets(&[target(0xABCDEF, ADDRESS_ICAO, 0, flags)]);
    let (_, a) = only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "traffic ABCDEF (N123AB) suspected spoofing: impossible speed, position jump (flags 0x03), range 1234 m"
    );
    // Plausible again at 1.0 s: cleared after the 5 s hysteresis.
    rig.traffic
        .set_targets(&[target(0xABCDEF, ADDRESS_ICAO, 0, 0)]);
    let (t, _) = only(&rig.run(7000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 6000);

    // Flags outside `spoofing_flags` are not suspect.
    let mut rig = Rig::new(MonitorParams {
        spoofing_flags: PLAUSIBILITY_POSITION_JUMP,
        ..MonitorParams::default()
    });
    rig.traffic.set_targets(&[target(
        0xABCDEF,
        ADDRESS_ICAO,
        0,
        PLAUSIBILITY_IMPOSSIBLE_SPEED,
    )]);
    assert!(rig.run(2000).is_empty());
}

#[test]
fn a_latched_alert_waits_for_acknowledgement() {
    let mut params = MonitorParams::default();
    params.timing_mut(Rule::UnitIsolated).latch = true;
    let id = 0x0200_0000;
    let mut rig = Rig::new(params);
    rig.att.isolation = ISOLATION_ISOLATED;
    rig.att.isolated_unit = UNIT_BAHRS;
    only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
    rig.att.isolation = ISOLATION_NO_FAULT;
    rig.att.isolated_unit = UNIT_NONE;
    let (t, a) = only(&rig.run(60_000), id, STATE_LATCHED, SEVERITY_CAUTION);
    assert_eq!(t, 3000, "hysteresis 2 s after 1.0 s");
    assert_eq!(a.header.seq, 2);
    assert!(matches!(
        rig.m.active().collect::<Vec<_>>()[..],
        [(0x0200_0000, Phase::Latched { .. })]
    ));
    // The active set says latched too.
    let mut p = IntegrityPayload::default();
    rig.m.fill_active(&mut p);
    let held: Vec<(u32, u8)> = p
        .active_alerts()
        .iter()
        .map(|a| (a.alert_id, a.state))
        .collect();
    assert_eq!(held, [(id, STATE_LATCHED)]);
    assert!(!rig.m.acknowledge(0x0300_0000), "not latched");
    assert!(rig.m.acknowledge(id));
    let (t, a) = only(&rig.run(1000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 61_000, "the next poll");
    assert_eq!(a.header.seq, 3);
    assert_eq!(a.raised_gps_ns, T0);
    assert_eq!(rig.m.active().count(), 0);
}

#[test]
fn a_disabled_rule_raises_nothing() {
    let mut params = MonitorParams::default();
    params.timing_mut(Rule::UnitHealth).enabled = false;
    let mut rig = Rig::new(params);
    rig.att.units[0].fault_flags = FAULT_HEALTH;
    assert!(rig.run(5000).is_empty());
}

#[test]
fn time_never_runs_backwards() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.own.source = SOURCE_TTMRF_GNSS;
    rig.run(500);
    // A poll 10 s in the past is taken as the last poll time (0.4 s): the 1 s delay has not
    // passed and nothing is raised, and the alert's time is never before a previous poll.
    assert!(rig.m.poll(T0 - 10_000 * MS).is_empty());
    let (t, a) = only(&rig.run(1000), 0x0600_0000, STATE_RAISED, SEVERITY_ADVISORY);
    assert_eq!((t, a.raised_gps_ns), (1000, T0 + 1000 * MS));
}

/// A small deterministic generator for the random-input test.
struct XorShift(u64);

impl XorShift {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn one_in(&mut self, n: u64) -> bool {
        self.next().is_multiple_of(n)
    }
    fn byte(&mut self) -> u8 {
        self.next() as u8
    }
    /// A float that is often special: NaN, infinities, huge, negative, or ordinary.
    fn float(&mut self) -> f64 {
        match self.next() % 6 {
            0 => f64::NAN,
            1 => f64::INFINITY,
            2 => -1e300,
            3 => f64::from_bits(self.next()),
            _ => (self.next() % 10_000) as f64 / 100.0,
        }
    }
    /// A small code, mostly valid, sometimes anything.
    fn code(&mut self, valid: u8) -> u8 {
        if self.one_in(8) {
            self.byte()
        } else {
            self.byte() % valid
        }
    }
}

#[test]
fn random_payloads_never_panic_and_transitions_stay_consistent() {
    let mut rng = XorShift(0x9E37_79B9_7F4A_7C15);
    let mut m = Monitor::new(MonitorParams {
        decode_window_s: 0.5,
        ..MonitorParams::default()
    });
    let mut params_latch = MonitorParams::default();
    params_latch.timing_mut(Rule::UnitIsolated).latch = true;
    let mut latching = Monitor::new(params_latch);
    let mut traffic = Box::<TrafficPayload>::default();
    // Per monitor: raised (or latched) ids, last seq, last time.
    let mut state: [(std::collections::BTreeSet<u32>, u64, i64); 2] = Default::default();
    let mut t = T0;
    for step in 0..2_000 {
        // Mostly forward in time, sometimes backwards or a big jump.
        t = match rng.next() % 50 {
            0 => t - 5_000 * MS,
            1 => t + 60_000 * MS,
            _ => t + 50 * MS,
        };
        let mut att = AttitudePayload::default();
        for u in &mut att.units {
            u.roll_rad = rng.float();
            u.valid = rng.code(2);
            u.fault_flags = rng.byte() & 0x1F;
        }
        for row in &mut att.pair_verdicts {
            for v in row {
                *v = rng.code(3);
            }
        }
        att.isolation = rng.code(4);
        att.isolated_unit = rng.code(3);
        att.valid = rng.code(2);
        let own = OwnshipPayload {
            source: rng.code(4),
            valid: rng.code(2),
            sigma_horizontal_m: rng.float(),
            ..OwnshipPayload::default()
        };
        let mut integ = IntegrityPayload {
            device_count: if rng.one_in(10) { u32::MAX } else { 4 },
            clock_status: rng.code(4),
            clock_offset_s: rng.float(),
            ..IntegrityPayload::default()
        };
        for d in &mut integ.devices {
            d.device = rng.code(4);
            d.link_state = rng.code(4);
            d.last_message_age_s = rng.float();
            d.messages = rng.next() % 1000 + step * 10;
            d.checksum_failures = rng.next() % 100;
            d.malformed = if rng.one_in(20) { u64::MAX } else { 0 };
            d.name = [rng.byte(); 16];
        }
        let n = (rng.next() % 40) as usize;
        let targets: Vec<Target> = (0..n)
            .map(|_| Target {
                address: rng.next() as u32,
                address_type: rng.code(6),
                alert_level: rng.code(4),
                plausibility_flags: rng.byte(),
                callsign: [rng.byte(); 8],
                horizontal_distance_m: rng.float(),
                ..Target::EMPTY
            })
            .collect();
        traffic.set_targets(&targets);
        if rng.one_in(7) {
            // Schema 3 holds the targets in a vector (a corrupt wire count is clamped when the
            // sample is read, `TrafficPayload::from_wire`): cut the picture short instead.
            let keep = rng.next() as usize % (traffic.targets.len() + 1);
            traffic.targets.truncate(keep);
        }
        for (k, mon) in [&mut m, &mut latching].into_iter().enumerate() {
            if !rng.one_in(3) {
                mon.attitude(&att);
            }
            if !rng.one_in(3) {
                mon.ownship(&own);
            }
            if rng.one_in(5) {
                mon.traffic(&traffic);
            }
            if rng.one_in(5) {
                mon.integrity(&integ);
            }
            if rng.one_in(50) {
                let ids: Vec<u32> = mon.active().map(|(id, _)| id).collect();
                for id in ids {
                    mon.acknowledge(id);
                }
            }
            let (active, seq, last_t) = &mut state[k];
            for a in mon.poll(t) {
                assert!(Rule::of_alert(a.alert_id).is_some(), "{:08X}", a.alert_id);
                assert_eq!(a.header.seq, *seq + 1, "consecutive sequence numbers");
                *seq = a.header.seq;
                assert!(a.header.gps_time_ns >= *last_t, "time never runs backwards");
                *last_t = a.header.gps_time_ns;
                assert!(a.raised_gps_ns <= a.header.gps_time_ns);
                assert!(a.severity <= SEVERITY_WARNING);
                match a.state {
                    STATE_RAISED => {
                        active.insert(a.alert_id);
                    }
                    STATE_LATCHED => assert!(active.contains(&a.alert_id), "latched unraised"),
                    STATE_CLEARED => assert!(active.remove(&a.alert_id), "cleared unraised"),
                    s => panic!("state {s}"),
                }
            }
            // What the monitor reports active is what its transitions said.
            let now: std::collections::BTreeSet<u32> = mon.active().map(|(id, _)| id).collect();
            assert_eq!(&now, active);
        }
    }
    assert!(
        state[0].1 > 100,
        "the random input raised and cleared alerts"
    );
}

/// The timeline `vigil run` gives for the `bahrs-attitude-fault` scenario, payloads by hand: the
/// BAHRS roll error crosses 6 deg at 72 s and the cross-check isolates the BAHRS about 1 s later
/// (73 s); from 90 s the BAHRS flags its roll "integrity risk", so its roll is no longer compared
/// and the isolation ends. The alerts: miscompare and isolation raised at 73 s, integrity risk
/// raised at 90 s, miscompare cleared at 91 s (1 s hysteresis), isolation at 92 s (2 s).
#[test]
fn regression_10_bahrs_attitude_fault_timeline() {
    use vigil_bus::payload::attitude::VERDICT_NOT_COMPARED;
    let mut rig = Rig::new(MonitorParams::default());
    assert!(rig.run(73_000).is_empty());
    rig.att.units[0] = unit(3.0 + 0.5 * 13.0);
    rig.att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_ROLL] = VERDICT_FAIL;
    rig.att.pair_verdicts[PAIR_BAHRS_WATSON][AXIS_ROLL] = VERDICT_FAIL;
    rig.att.isolation = ISOLATION_ISOLATED;
    rig.att.isolated_unit = UNIT_BAHRS;
    let mut log: Vec<(i64, u32, u8)> = rig
        .run(17_000)
        .into_iter()
        .map(|(t, a)| (t, a.alert_id, a.state))
        .collect();
    rig.att.units[0].fault_flags = FAULT_HEALTH;
    rig.att.units[0].valid = 0;
    rig.att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_ROLL] = VERDICT_NOT_COMPARED;
    rig.att.pair_verdicts[PAIR_BAHRS_WATSON][AXIS_ROLL] = VERDICT_NOT_COMPARED;
    rig.att.isolation = ISOLATION_NO_FAULT;
    rig.att.isolated_unit = UNIT_NONE;
    log.extend(
        rig.run(10_000)
            .into_iter()
            .map(|(t, a)| (t, a.alert_id, a.state)),
    );
    assert_eq!(
        log,
        [
            (73_000, 0x0100_0000, STATE_RAISED),
            (73_000, 0x0200_0000, STATE_RAISED),
            (90_000, 0x0300_0000, STATE_RAISED),
            (91_000, 0x0100_0000, STATE_CLEARED),
            (92_000, 0x0200_0000, STATE_CLEARED),
        ]
    );
}

// --- issue 25 points 5 and 6 ---
#[test]
fn inertial_miscompare_names_the_axis_and_health_and_clears_after_two_seconds() {
    use vigil_bus::payload::attitude::{
        ChannelComparison, HEALTH_SAFE, INERTIAL_ANGULAR_RATE_X, INERTIAL_COUNT,
    };
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.bahrs_inertial_health = [HEALTH_SAFE; INERTIAL_COUNT];
    rig.run(1000);
    // Angular rate z: BAHRS 0.02 rad/s, VN-200 0.01 rad/s (1.146 and 0.573 deg/s).
    let z = INERTIAL_ANGULAR_RATE_X + 2;
    rig.att.inertial[z] = ChannelComparison {
        bahrs: 0.02,
        vn200: 0.01,
        diff: 0.01,
        sigma: 0.001,
        stat_ratio: 2.26,
        verdict: VERDICT_FAIL,
        coverage: COVERAGE_COMPARED,
        ..ChannelComparison::default()
    };
    let id = Rule::InertialMiscompare.alert_id(z as u32);
    assert_eq!(id, 0x0D00_0005);
    let (t, a) = only(&rig.run(2000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 1000);
    assert_eq!(
        a.reason(),
        "inertial angular rate z miscompare (BAHRS health safe): BAHRS 1.146, VN-200 0.573 \
         deg/s, difference 0.573 (sigma 0.057)"
    );
    // Passing again from t = 3.0 s: hysteresis 2 s, cleared at 5.0 s.
    rig.att.inertial[z].verdict = VERDICT_PASS;
    let (t, _) = only(&rig.run(3000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 5000);
}

#[test]
fn vertical_miscompare_names_the_comparison_and_the_bahrs_as_suspect() {
    use vigil_bus::payload::attitude::{
        COVERAGE_ABSENT, ChannelComparison, VERTICAL_VELOCITY_DOWN,
    };
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.vertical[VERTICAL_VELOCITY_DOWN] = ChannelComparison {
        bahrs: 0.0,
        vn200: -2.0,
        diff: 2.0,
        sigma: 0.5,
        verdict: VERDICT_FAIL,
        coverage: COVERAGE_COMPARED,
        ..ChannelComparison::default()
    };
    let id = Rule::VerticalMiscompare.alert_id(0);
    assert_eq!(id, 0x0C00_0000);
    // Without a third opinion (TT GNSS absent): the premise-based attribution, with why.
    rig.att.vertical_tt_coverage = COVERAGE_ABSENT;
    rig.att.vertical_isolated_unit = UNIT_NONE;
    let (_, a) = only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "vertical down velocity miscompare, BAHRS suspected (VN-200 GNSS-aided; TT GNSS absent): \
         BAHRS 0.00, VN-200 -2.00 m/s, difference 2.00 (sigma 0.50)"
    );
}

/// Issue 25 point 6: with the third opinion compared, the reason names the unit it isolates
/// (only when the two third-opinion verdicts carry it: BAHRS-TT fail and VN-200-TT pass, or the
/// reverse), else says it is undecided.
#[test]
fn vertical_miscompare_names_the_unit_the_tt_gnss_isolates() {
    use vigil_bus::payload::attitude::{
        ChannelComparison, VERTICAL_HEIGHT_RATE, VERTICAL_TT_BAHRS, VERTICAL_TT_VN200,
    };
    let fail = ChannelComparison {
        verdict: VERDICT_FAIL,
        coverage: COVERAGE_COMPARED,
        ..ChannelComparison::default()
    };
    let pass = ChannelComparison {
        verdict: VERDICT_PASS,
        ..fail
    };
    let id = Rule::VerticalMiscompare.alert_id(VERTICAL_HEIGHT_RATE as u32);
    let cases = [
        (
            UNIT_BAHRS,
            fail,
            pass,
            "BAHRS isolated (TT GNSS agrees with VN-200)",
        ),
        (
            UNIT_VN200,
            pass,
            fail,
            "VN-200 isolated (TT GNSS agrees with BAHRS)",
        ),
        (
            UNIT_NONE,
            fail,
            fail,
            "BAHRS suspected (VN-200 GNSS-aided; TT GNSS undecided)",
        ),
        // A unit the verdicts do not carry is not believed.
        (
            UNIT_BAHRS,
            pass,
            pass,
            "BAHRS suspected (VN-200 GNSS-aided; TT GNSS undecided)",
        ),
    ];
    for (unit, b, v, expect) in cases {
        let mut rig = Rig::new(MonitorParams::default());
        rig.att.vertical[VERTICAL_HEIGHT_RATE] = fail;
        rig.att.vertical_tt_coverage = COVERAGE_COMPARED;
        rig.att.vertical_isolated_unit = unit;
        rig.att.vertical_tt[VERTICAL_TT_BAHRS] = b;
        rig.att.vertical_tt[VERTICAL_TT_VN200] = v;
        let (_, a) = only(&rig.run(1000), id, STATE_RAISED, SEVERITY_CAUTION);
        assert!(
            a.reason()
                .starts_with(&format!("vertical height rate miscompare, {expect}: ")),
            "{}",
            a.reason()
        );
    }
}

// --- issue 25 point 4 ---
/// A disagreement of the health cross-check raises after the 3 s raise delay with the
/// combination in the subject and the VN-200 status in the reason, clears 2 s after agreement
/// returns; "not compared" (unknown) never raises.
#[test]
fn health_disagreement_raises_after_three_seconds_and_never_on_unknown() {
    use vigil_bus::payload::integrity::{
        HEALTH_AGREE, HEALTH_DISAGREE, HEALTH_NOT_COMPARED, HEALTH_PPS_WITHOUT_FIX,
        HEALTH_WHY_VN200_STALE, HealthComparison,
    };
    let mut rig = Rig::new(MonitorParams::default());
    // Unknown for 10 s: nothing.
    rig.integ.health_checks = [HealthComparison {
        state: HEALTH_NOT_COMPARED,
        reason: HEALTH_WHY_VN200_STALE,
        ..HealthComparison::default()
    }; 4];
    assert!(rig.run(10_000).is_empty());
    // From 10.0 s: BAHRS pulses while the VN-200 (InsStatus 0x0043: GnssLost, no fix) has none.
    rig.integ.health_checks = [HealthComparison {
        state: HEALTH_AGREE,
        ..HealthComparison::default()
    }; 4];
    rig.integ.health_checks[HEALTH_PPS_WITHOUT_FIX] = HealthComparison {
        state: HEALTH_DISAGREE,
        disagree_s: 0.5,
        ..HealthComparison::default()
    };
    rig.integ.vn200_ins_mode = 3;
    rig.integ.vn200_gnss_fix = 0;
    rig.integ.vn200_ins_status = 0x0043;
    rig.integ.bahrs_pulse_age_s = 0.3;
    let id = Rule::HealthDisagreement.alert_id(HEALTH_PPS_WITHOUT_FIX as u32);
    assert_eq!(id, 0x0E00_0000);
    let (t, a) = only(&rig.run(5000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 13_000);
    assert_eq!(
        a.reason(),
        "health disagreement: BAHRS sync pulses without a VN-200 GNSS fix (miswired sync?) for \
         0.5 s; INS GnssLost, status 0x0043, last pulse 0.3 s ago"
    );
    // Agreement again from 15.0 s: cleared at 17.0 s.
    rig.integ.health_checks[HEALTH_PPS_WITHOUT_FIX].state = HEALTH_AGREE;
    let (t, _) = only(&rig.run(5000), id, STATE_CLEARED, SEVERITY_CAUTION);
    assert_eq!(t, 17_000);
}

// --- issue 18 point 4 ---
#[test]
fn clock_disagreement_per_device_bit_after_one_second_clears_after_two() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(1000);
    // The BAHRS (bit 0) and the TT-Multi-RF (bit 3) disagree from t = 1.0 s.
    rig.integ.clock_disagreement = (1 << DEVICE_BAHRS) | (1 << DEVICE_TTMRF);
    // A bit set for less than the 1 s delay raises nothing.
    assert!(rig.run(900).is_empty());
    let out = rig.run(300);
    let ids: Vec<u32> = out.iter().map(|(_, a)| a.alert_id).collect();
    // Subject: the DEVICE_* code; ids in order, both raised at 2.0 s, caution.
    assert_eq!(ids, vec![0x0F00_0000, 0x0F00_0003]);
    for (t, a) in &out {
        assert_eq!(
            (*t, a.state, a.severity),
            (2000, STATE_RAISED, SEVERITY_CAUTION)
        );
    }
    assert!(
        out[0]
            .1
            .reason()
            .starts_with("BAHRS PPS-named time disagrees")
    );
    assert!(
        out[1]
            .1
            .reason()
            .starts_with("TT-Multi-RF ts / TS24h disagrees")
    );
    // The TT agrees again from 2.2 s: cleared 2 s (hysteresis) later; the BAHRS stays.
    rig.integ.clock_disagreement = 1 << DEVICE_BAHRS;
    let (t, _) = only(
        &rig.run(3000),
        Rule::ClockDisagreement.alert_id(u32::from(DEVICE_TTMRF)),
        STATE_CLEARED,
        SEVERITY_CAUTION,
    );
    assert_eq!(t, 4200);
}

// --- a full serial line (issue 21 point 5: output lost in the device is said) ---
#[test]
fn line_full_per_device_bit_after_one_second_clears_after_two() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.run(1000);
    // The TT-Multi-RF's line (bit 3) is full from t = 1.0 s; a device code no device has
    // (bit 6) is reported by its number, not dropped.
    rig.integ.line_full = (1 << DEVICE_TTMRF) | (1 << 6);
    // Set for less than the 1 s delay: nothing.
    assert!(rig.run(900).is_empty());
    let out = rig.run(300);
    let ids: Vec<u32> = out.iter().map(|(_, a)| a.alert_id).collect();
    // Rule code 0x10, subject the DEVICE_* code; both raised at 2.0 s, caution.
    assert_eq!(ids, vec![0x1000_0003, 0x1000_0006]);
    for (t, a) in &out {
        assert_eq!(
            (*t, a.state, a.severity),
            (2000, STATE_RAISED, SEVERITY_CAUTION)
        );
    }
    let tt = out[0].1.reason();
    assert!(
        tt.starts_with("TT-Multi-RF output fills its serial line"),
        "{tt}"
    );
    // The reason is whole: it ends with the advice, inside the 160-byte field.
    assert!(tt.ends_with("raise the baud"), "{tt}");
    assert_eq!(
        out[1].1.reason(),
        "device code 6: output fills its serial line"
    );
    // The clock rule, which shares the payload, raises nothing for these bits.
    assert!(out.iter().all(|(_, a)| a.alert_id >> 24 == 0x10));
    // The TT's line empties from 2.2 s: cleared 2 s (hysteresis) later; bit 6 stays.
    rig.integ.line_full = 1 << 6;
    let (t, _) = only(
        &rig.run(3000),
        Rule::LineFull.alert_id(u32::from(DEVICE_TTMRF)),
        STATE_CLEARED,
        SEVERITY_CAUTION,
    );
    assert_eq!(t, 4200);
}

// --- issue 23: tests for the mutants the first cargo-mutants run over links.rs and
// conditions.rs left alive. Each names the behaviour it pins; the expected words come from the
// device documents (BAHRS 2-bit health, VN-200 InsStatus mode) or from hand computation.

/// The pitch miscompare reports the units' pitch, not another axis (units at pitch 2.0 deg, the
/// BAHRS at 9.5 deg; their roll 3.0 and heading 90.0 deg appear nowhere in the reason).
#[test]
fn pitch_miscompare_gives_the_units_pitch() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.units[usize::from(UNIT_BAHRS)].pitch_rad = 9.5f64.to_radians();
    rig.att.pair_verdicts[PAIR_BAHRS_VN200][AXIS_PITCH] = VERDICT_FAIL;
    let id = Rule::AttitudeMiscompare.alert_id(AXIS_PITCH as u32);
    let (_, a) = only(&rig.run(100), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        "pitch miscompare (BAHRS/VN-200 fail): BAHRS 9.5, VN-200 2.0, Watson 2.0 deg"
    );
}

/// A unit code past the three units (a newer publisher) is named as a code, not given a unit's
/// name; code 3 is the first such code.
#[test]
fn an_isolated_unit_code_past_the_units_is_named_as_a_code() {
    let mut rig = Rig::new(MonitorParams::default());
    rig.att.isolation = ISOLATION_ISOLATED;
    rig.att.isolated_unit = 3;
    let (_, a) = only(&rig.run(100), 0x0200_0003, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(a.reason(), "unit code 3 isolated by the cross-check");
}

/// Each BAHRS 2-bit health code has the document's meaning in the reason (00 signal
/// unavailable, 01 safe, 10 integrity risk; 11 is not defined), and "unknown" before the first
/// message (the payload's `HEALTH_NONE`).
#[test]
fn inertial_miscompare_gives_each_bahrs_health_its_document_name() {
    use vigil_bus::payload::attitude::{
        ChannelComparison, HEALTH_INTEGRITY_RISK, HEALTH_NONE, HEALTH_SAFE, HEALTH_UNAVAILABLE,
        INERTIAL_COUNT,
    };
    for (code, name) in [
        (HEALTH_UNAVAILABLE, "unavailable"),
        (HEALTH_SAFE, "safe"),
        (HEALTH_INTEGRITY_RISK, "integrity risk"),
        (3, "undefined"),
        (HEALTH_NONE, "unknown"),
    ] {
        let mut rig = Rig::new(MonitorParams::default());
        rig.att.bahrs_inertial_health = [code; INERTIAL_COUNT];
        rig.att.inertial[0] = ChannelComparison {
            verdict: VERDICT_FAIL,
            coverage: COVERAGE_COMPARED,
            ..ChannelComparison::default()
        };
        let id = Rule::InertialMiscompare.alert_id(0);
        let (_, a) = only(&rig.run(100), id, STATE_RAISED, SEVERITY_CAUTION);
        let want = format!("(BAHRS health {name})");
        assert!(a.reason().contains(&want), "{code}: {}", a.reason());
    }
}

/// An ownship payload marked invalid is "no valid position" whatever source it names; a valid
/// position from an external source (`SOURCE_EXTERNAL`, supplied by the integrator) is not a
/// GNSS loss.
#[test]
fn an_invalid_ownship_is_a_caution_whatever_its_source_and_an_external_one_is_fine() {
    use vigil_bus::payload::ownship::SOURCE_EXTERNAL;
    let id = Rule::GnssLost.alert_id(0);
    let mut rig = Rig::new(MonitorParams::default());
    rig.own.valid = 0;
    let (_, a) = only(&rig.run(2000), id, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(
        a.reason(),
        format!("no valid ownship position (source code {SOURCE_VN200_INS}, valid 0)")
    );
    let mut rig = Rig::new(MonitorParams::default());
    rig.own.source = SOURCE_EXTERNAL;
    assert!(rig.run(5000).is_empty());
}

/// The health reason names the VN-200 INS mode by the document's InsStatus mode enumeration
/// (0 NotTracking, 1 Aligning, 2 Tracking, 3 GnssLost), "unknown" before any status, and each
/// compared combination by what disagrees.
#[test]
fn health_disagreement_names_the_ins_mode_and_each_combination() {
    use vigil_bus::payload::integrity::{
        HEALTH_AGREE, HEALTH_DISAGREE, HEALTH_FIX_WITHOUT_PPS, HEALTH_GNSS_LOST_WITH_FIX,
        HEALTH_PPS_WITHOUT_FIX, HEALTH_TRACKING_WITHOUT_FIX, HealthComparison, VN200_STATUS_NONE,
    };
    let modes = [
        (0, "INS NotTracking,"),
        (1, "INS Aligning,"),
        (2, "INS Tracking,"),
        (3, "INS GnssLost,"),
        (4, "INS undefined,"),
        (VN200_STATUS_NONE, "INS unknown,"),
    ];
    let combinations = [
        (
            HEALTH_PPS_WITHOUT_FIX,
            "BAHRS sync pulses without a VN-200 GNSS fix",
        ),
        (
            HEALTH_FIX_WITHOUT_PPS,
            "VN-200 GNSS fix without BAHRS sync pulses",
        ),
        (
            HEALTH_TRACKING_WITHOUT_FIX,
            "VN-200 INS Tracking without a GNSS fix",
        ),
        (
            HEALTH_GNSS_LOST_WITH_FIX,
            "VN-200 INS GnssLost with a GNSS fix",
        ),
    ];
    for (mode, mode_text) in modes {
        for (which, what) in combinations {
            let mut rig = Rig::new(MonitorParams::default());
            rig.integ.health_checks = [HealthComparison {
                state: HEALTH_AGREE,
                ..HealthComparison::default()
            }; 4];
            rig.integ.health_checks[which].state = HEALTH_DISAGREE;
            rig.integ.vn200_ins_mode = mode;
            let id = Rule::HealthDisagreement.alert_id(which as u32);
            let (_, a) = only(&rig.run(4000), id, STATE_RAISED, SEVERITY_CAUTION);
            let r = a.reason();
            assert!(
                r.starts_with(&format!("health disagreement: {what}")),
                "{r}"
            );
            assert!(r.contains(mode_text), "{mode}: {r}");
        }
    }
}

/// Each device kind has its name in a device reason (the Watson in slot 2, the TT-Multi-RF in
/// slot 3).
#[test]
fn device_reasons_name_the_watson_and_the_tt_multi_rf() {
    for (slot, kind, name) in [
        (2, DEVICE_WATSON, "device watson (Watson)"),
        (3, DEVICE_TTMRF, "device ttmrf (TT-Multi-RF)"),
    ] {
        let mut rig = Rig::new(MonitorParams::default());
        rig.integ.devices[slot].link_state = LINK_DISCONNECTED;
        let id = Rule::DeviceSilent.alert_id((u32::from(kind) << 8) | slot as u32);
        let (_, a) = only(&rig.run(100), id, STATE_RAISED, SEVERITY_CAUTION);
        assert!(a.reason().starts_with(name), "{}", a.reason());
    }
}

/// A device whose every frame is rejected (its message count stands still while its checksum
/// failures rise) is the worst decode error rate, not a pause: 100 of 100 frames in the 10 s
/// window, raised when the window closes.
#[test]
fn a_device_whose_every_frame_fails_raises_decode_errors() {
    let id = Rule::DecodeErrors.alert_id(0);
    let mut rig = Rig::new(MonitorParams::default());
    rig.counting = (0, 1);
    let (t, a) = only(&rig.run(15_000), id, STATE_RAISED, SEVERITY_ADVISORY);
    assert_eq!(t, 10_000);
    assert_eq!(
        a.reason(),
        "device bahrs (BAHRS) decode errors: 100 of 100 frames rejected in 10.0 s (100.0 %, limit 5.0 %)"
    );
}

/// Windows follow each other every `decode_window_s` from the first payload, whether or not
/// errors came: errors from 5.0 s give 50 of 1050 frames (4.8 %) in the window judged at
/// 10.0 s, so nothing; the next window, judged at 20.0 s, has 100 of 1100 (9.1 %) and raises.
#[test]
fn decode_windows_keep_their_cadence_through_a_clean_spell() {
    let id = Rule::DecodeErrors.alert_id(0);
    let mut rig = Rig::new(MonitorParams::default());
    rig.counting = (10, 0);
    assert!(rig.run(5000).is_empty());
    rig.counting = (10, 1);
    let (t, a) = only(&rig.run(20_000), id, STATE_RAISED, SEVERITY_ADVISORY);
    assert_eq!(t, 20_000);
    assert!(
        a.reason().contains("100 of 1100 frames rejected in 10.0 s"),
        "{}",
        a.reason()
    );
}

/// `decode_error_ratio_max` is the largest fraction allowed: exactly 5 % (1 of every 20 frames;
/// 1/20 and 0.05 are the same double) raises nothing.
#[test]
fn a_decode_error_ratio_exactly_at_the_limit_is_allowed() {
    let mut rig = Rig::new(MonitorParams::default());
    assert_eq!(1.0 / 20.0, rig.m.params().decode_error_ratio_max);
    rig.counting = (19, 1);
    assert!(rig.run(40_000).is_empty());
}

/// A slot whose device changes (a new name, same kind) is a new device: its never-heard time
/// counts from when it appeared (at 5.0 s), so it is silent after more than 2 s of that, at
/// 7.1 s, not at once.
#[test]
fn a_new_device_in_a_slot_starts_its_own_history() {
    let mut rig = Rig::new(MonitorParams::default());
    assert!(rig.run(5000).is_empty());
    write_text(&mut rig.integ.devices[3].name, "ttmrf2");
    rig.integ.devices[3].last_message_age_s = f64::NAN;
    let (t, a) = only(&rig.run(3000), 0x0800_0303, STATE_RAISED, SEVERITY_CAUTION);
    assert_eq!(t, 7100);
    assert!(a.reason().contains("no message in 2.1 s"), "{}", a.reason());
}

/// `Monitor::params` gives back the parameters the monitor was made with.
#[test]
fn params_are_the_ones_given() {
    let p = MonitorParams {
        decode_window_s: 7.5,
        clock_require_pps: true,
        ..MonitorParams::default()
    };
    assert_eq!(*Monitor::new(p).params(), p);
}
