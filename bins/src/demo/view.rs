//! The live terminal view of `vigil demo`: what a DAA or integrity consumer sees on the bus,
//! rendered as text. A pure function of the latest payloads (no I/O), so it is tested directly.

use std::collections::VecDeque;
use std::fmt::Write as _;

use vigil_bus::payload::alerts::AlertPayload;
use vigil_bus::payload::attitude::{
    AttitudePayload, FAULT_FROZEN, FAULT_HEALTH, FAULT_INVALID, FAULT_ISOLATED, FAULT_STALE,
    ISOLATION_DETECTED_NOT_ISOLATED, ISOLATION_ISOLATED, ISOLATION_NO_FAULT, PAIR_BAHRS_VN200,
    PAIR_BAHRS_WATSON, PAIR_VN200_WATSON, UNIT_COUNT, VERDICT_FAIL, VERDICT_PASS,
};
use vigil_bus::payload::ownship::{OwnshipPayload, SOURCE_TTMRF_GNSS, SOURCE_VN200_INS};
use vigil_bus::payload::traffic::TrafficPayload;
use vigil_service::json_names::{Code, code_word};

/// Alerts kept in the view's history.
const ALERT_HISTORY: usize = 8;
/// Traffic rows shown.
const TRAFFIC_ROWS: usize = 10;

const UNIT_NAMES: [&str; UNIT_COUNT] = ["BAHRS", "VN-200", "Watson"];
const FT_PER_M: f64 = 1.0 / 0.3048;
const M_PER_NM: f64 = 1852.0;

/// The latest payload of each topic and the recent alert transitions.
#[derive(Debug, Default)]
pub struct View {
    /// Latest attitude.
    pub attitude: Option<AttitudePayload>,
    /// Latest ownship.
    pub ownship: Option<OwnshipPayload>,
    /// Latest traffic picture.
    pub traffic: Option<Box<TrafficPayload>>,
    /// Recent alert transitions, newest last.
    pub alerts: VecDeque<AlertPayload>,
    /// Samples received per topic (attitude, ownship, traffic, alerts).
    pub received: [u64; 4],
}

impl View {
    /// Records an alert transition.
    pub fn alert(&mut self, a: AlertPayload) {
        if self.alerts.len() == ALERT_HISTORY {
            self.alerts.pop_front();
        }
        self.alerts.push_back(a);
        self.received[3] += 1;
    }
}

fn deg(rad: f64) -> f64 {
    rad.to_degrees()
}

fn verdict(v: u8) -> char {
    match v {
        VERDICT_PASS => '.',
        VERDICT_FAIL => 'X',
        _ => '-',
    }
}

fn unit_state(flags: u8, valid: u8) -> String {
    let mut s: Vec<&str> = Vec::new();
    for (bit, name) in [
        (FAULT_ISOLATED, "ISOLATED"),
        (FAULT_HEALTH, "health"),
        (FAULT_INVALID, "invalid"),
        (FAULT_STALE, "stale"),
        (FAULT_FROZEN, "frozen"),
    ] {
        if flags & bit != 0 {
            s.push(name);
        }
    }
    if s.is_empty() {
        if valid != 0 { "ok" } else { "-" }.to_string()
    } else {
        s.join(",")
    }
}

/// The word of a severity (the table of `vigil_service::json_names`), a warning in capitals.
fn severity(s: u8) -> &'static str {
    match code_word(Code::Severity, u64::from(s)) {
        Some("warning") => "WARNING",
        Some(w) => w,
        None => "?",
    }
}

/// The word of a DAA alert level (the table of `vigil_service::json_names`): none as `-`, corrective and
/// warning in capitals.
fn alert_level(l: u8) -> &'static str {
    match code_word(Code::AlertLevel, u64::from(l)) {
        Some("none") => "-",
        Some("corrective") => "CORRECTIVE",
        Some("warning") => "WARNING",
        Some(w) => w,
        None => "?",
    }
}

/// The word of an alert state (the table of `vigil_service::json_names`).
fn state(s: u8) -> &'static str {
    code_word(Code::AlertState, u64::from(s)).unwrap_or("?")
}

/// Renders the view; `t0_gps_ns` is the GPS time shown as 0 s (the first sample seen).
pub fn render(v: &View, t0_gps_ns: i64) -> String {
    let mut s = String::new();
    let rel = |t: i64| (t - t0_gps_ns) as f64 * 1e-9;
    let _ = writeln!(
        s,
        "vigil demo   received: attitude {}  ownship {}  traffic {}  alerts {}",
        v.received[0], v.received[1], v.received[2], v.received[3]
    );
    s.push_str("\nOWNSHIP\n");
    match &v.ownship {
        Some(o) if o.valid != 0 => {
            let src = match o.source {
                SOURCE_VN200_INS => "VN-200 INS",
                SOURCE_TTMRF_GNSS => "TT-Multi-RF GNSS",
                _ => "other",
            };
            let _ = writeln!(
                s,
                "  t {:8.1} s  {:.5} {:.5}  alt {:6.0} ft (press.)  trk {:5.1}  gs {:5.1} kt  vs {:+5.0} fpm  [{src}, +-{:.0} m]",
                rel(o.header.gps_time_ns),
                o.lat_deg,
                o.lon_deg,
                o.alt_pressure_m * FT_PER_M,
                o.track_deg,
                o.ground_speed_mps / 0.514_444,
                o.vel_up_mps * FT_PER_M * 60.0,
                o.sigma_horizontal_m
            );
        }
        _ => s.push_str("  no position\n"),
    }
    s.push_str("\nATTITUDE        roll   pitch  heading  state\n");
    match &v.attitude {
        Some(a) => {
            for (i, u) in a.units.iter().enumerate() {
                let _ = writeln!(
                    s,
                    "  {:<10} {:+7.2} {:+7.2}  {:7.2}  {}",
                    UNIT_NAMES[i],
                    deg(u.roll_rad),
                    deg(u.pitch_rad),
                    deg(u.heading_rad),
                    unit_state(u.fault_flags, u.valid)
                );
            }
            let _ = writeln!(
                s,
                "  {:<10} {:+7.2} {:+7.2}  {:7.2}  {}",
                "voted",
                deg(a.roll_rad),
                deg(a.pitch_rad),
                deg(a.heading_rad),
                if a.valid != 0 { "ok" } else { "INVALID" }
            );
            let pv =
                |p: usize| -> String { a.pair_verdicts[p].iter().map(|&x| verdict(x)).collect() };
            let iso = match a.isolation {
                ISOLATION_NO_FAULT => "no fault".to_string(),
                ISOLATION_DETECTED_NOT_ISOLATED => "FAULT DETECTED, not isolated".to_string(),
                ISOLATION_ISOLATED => format!(
                    "FAULT: {} isolated",
                    UNIT_NAMES.get(usize::from(a.isolated_unit)).unwrap_or(&"?")
                ),
                _ => "not compared".to_string(),
            };
            let _ = writeln!(
                s,
                "  pairs (roll pitch heading): BAHRS/VN-200 {}  BAHRS/Watson {}  VN-200/Watson {}  -> {iso}",
                pv(PAIR_BAHRS_VN200),
                pv(PAIR_BAHRS_WATSON),
                pv(PAIR_VN200_WATSON)
            );
        }
        None => s.push_str("  no attitude yet\n"),
    }
    s.push_str(
        "\nTRAFFIC   address  callsign  range NM  brg   rel alt ft  time_to_lowc_s  level\n",
    );
    match &v.traffic {
        Some(t) if t.count() > 0 => {
            for x in t.targets().iter().take(TRAFFIC_ROWS) {
                let cs = String::from_utf8_lossy(&x.callsign);
                let cs = cs.trim_end_matches(['\0', ' ']);
                let lowc = if x.time_to_lowc_s.is_finite() {
                    format!("{:14.1}", x.time_to_lowc_s)
                } else {
                    format!("{:>14}", "-")
                };
                let _ = writeln!(
                    s,
                    "          {:06X}   {:<8}  {:8.2}  {:3.0}  {:+10.0}  {lowc}  {}{}",
                    x.address,
                    cs,
                    x.horizontal_distance_m / M_PER_NM,
                    x.bearing_deg,
                    x.vertical_separation_m() * FT_PER_M,
                    alert_level(x.alert_level),
                    if x.plausibility_flags != 0 {
                        "  SUSPECT"
                    } else {
                        ""
                    }
                );
            }
            if t.count() > TRAFFIC_ROWS {
                let _ = writeln!(s, "          ... {} more", t.count() - TRAFFIC_ROWS);
            }
        }
        _ => s.push_str("          no traffic\n"),
    }
    s.push_str("\nALERTS\n");
    if v.alerts.is_empty() {
        s.push_str("  none\n");
    }
    for a in &v.alerts {
        let _ = writeln!(
            s,
            "  {:8.1} s  {:<8} {:<7}  {}",
            rel(a.header.gps_time_ns),
            severity(a.severity),
            state(a.state),
            a.reason()
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_bus::payload::alerts::STATE_RAISED;
    use vigil_bus::payload::traffic::Target;

    #[test]
    fn renders_every_section_with_converted_units() {
        let mut v = View::default();
        let mut o = OwnshipPayload {
            lat_deg: 47.4,
            lon_deg: 8.5,
            alt_pressure_m: 600.0,
            track_deg: 90.0,
            ground_speed_mps: 51.4444,
            vel_up_mps: 2.54,
            source: SOURCE_VN200_INS,
            valid: 1,
            ..Default::default()
        };
        o.header.gps_time_ns = 12_000_000_000;
        v.ownship = Some(o);
        let mut a = AttitudePayload {
            roll_rad: 0.1,
            isolation: ISOLATION_ISOLATED,
            isolated_unit: 0,
            valid: 1,
            ..Default::default()
        };
        a.units[0].fault_flags = FAULT_ISOLATED;
        a.pair_verdicts[PAIR_BAHRS_VN200] = [VERDICT_FAIL, VERDICT_PASS, VERDICT_PASS];
        v.attitude = Some(a);
        let mut t = Box::new(TrafficPayload::default());
        let mut x = Target {
            address: 0x4B1A01,
            alert_level: 3,
            horizontal_distance_m: 3704.0,
            // 100 ft below the ownship.
            rel_down_m: 30.48,
            bearing_deg: 12.0,
            time_to_lowc_s: 8.5,
            ..Target::EMPTY
        };
        x.callsign[..7].copy_from_slice(b"HEADON1");
        t.set_targets(&[x]);
        v.traffic = Some(t);
        let mut al = AlertPayload {
            severity: 2,
            state: STATE_RAISED,
            ..Default::default()
        };
        al.header.gps_time_ns = 14_000_000_000;
        al.set_reason("BAHRS isolated: roll differs by 7.1 deg");
        v.alert(al);
        let text = render(&v, 10_000_000_000);
        // 600 m = 1968.5 ft; 51.4444 m/s = 100.0 kt; 2.54 m/s = +500 fpm; t = 12 - 10 s.
        assert!(
            text.contains("t      2.0 s  47.40000 8.50000  alt   1969 ft"),
            "{text}"
        );
        assert!(
            text.contains("gs 100.0 kt  vs  +500 fpm  [VN-200 INS"),
            "{text}"
        );
        assert!(text.contains("BAHRS/VN-200 X..") && text.contains("FAULT: BAHRS isolated"));
        assert!(text.contains("BAHRS      ") && text.contains("ISOLATED"));
        // 3704 m = 2.00 NM, -30.48 m = -100 ft; the column header is the payload's name.
        assert!(text.contains("rel alt ft  time_to_lowc_s  level"), "{text}");
        assert!(
            text.contains("4B1A01   HEADON1       2.00   12        -100             8.5  WARNING"),
            "{text}"
        );
        assert!(text.contains("4.0 s  WARNING  raised   BAHRS isolated: roll differs by 7.1 deg"));
    }

    #[test]
    fn empty_view_says_what_is_missing_and_history_is_bounded() {
        let mut v = View::default();
        let text = render(&v, 0);
        for want in [
            "no position",
            "no attitude yet",
            "no traffic",
            "ALERTS\n  none",
        ] {
            assert!(text.contains(want), "{want}: {text}");
        }
        for k in 0..20 {
            v.alert(AlertPayload {
                alert_id: k,
                ..Default::default()
            });
        }
        assert_eq!(v.alerts.len(), ALERT_HISTORY);
        assert_eq!(v.alerts.back().unwrap().alert_id, 19);
        assert_eq!(v.received[3], 20);
    }
}
