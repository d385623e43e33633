//! One target: the freshest state per source, the merged state, and its plausibility record.

use serde::Serialize;
use vigil_drivers::traffic::{AddressType, Link, Protocol, TrafficReport};

use super::accuracy::{epu_m, rc_m, sigma_from_r95};

/// Which address space an address belongs to: addresses merge only within one space. ICAO
/// addresses relayed by TIS-B/ADS-R, or used by FLARM as its id, are the same aircraft as the
/// ICAO address received directly.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AddressSpace {
    /// 24-bit ICAO.
    Icao,
    /// Non-ICAO ADS-B/UAT address (self-assigned, anonymous).
    NonIcao,
    /// TIS-B track number or other non-ICAO TIS-B address.
    TisbOther,
    /// FLARM random id.
    FlarmRandom,
    /// FLARM fixed id.
    FlarmFixed,
    /// Surface vehicle or beacon.
    Surface,
    /// Address type not given.
    Unknown,
}

impl From<AddressType> for AddressSpace {
    fn from(t: AddressType) -> Self {
        match t {
            AddressType::Icao | AddressType::TisbIcao => AddressSpace::Icao,
            AddressType::NonIcao => AddressSpace::NonIcao,
            AddressType::TisbOther => AddressSpace::TisbOther,
            AddressType::FlarmRandom => AddressSpace::FlarmRandom,
            AddressType::FlarmFixed => AddressSpace::FlarmFixed,
            AddressType::Surface => AddressSpace::Surface,
            AddressType::Unknown => AddressSpace::Unknown,
        }
    }
}

/// The key a target is merged under.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
pub struct TargetKey {
    /// Address space.
    pub space: AddressSpace,
    /// 24-bit address.
    pub address: u32,
}

/// One (link, protocol) that reports a target.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct Source {
    /// Radio link.
    pub link: Link,
    /// Protocol.
    pub protocol: Protocol,
}

/// A value with the GPS time (ns) it refers to.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Timed<T> {
    /// GPS time, ns.
    pub t_gps_ns: i64,
    /// The value.
    pub value: T,
}

/// A position fix: latitude, longitude (deg) and 1-sigma horizontal uncertainty (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Fix {
    /// Latitude, deg.
    pub lat_deg: f64,
    /// Longitude, deg.
    pub lon_deg: f64,
    /// 1-sigma horizontal uncertainty, m.
    pub sigma_m: f64,
    /// Source that gave it.
    pub source: Source,
    /// Its time is the arrival time (the protocol carries no time of applicability), issue 24.
    pub time_from_receipt: bool,
}

/// Plausibility findings on a target, each with the GPS time (ns) it was last seen. A finding
/// stays active until the target's reports have been consistent for
/// [`super::TrafficParams::flag_hold_s`], and never drops the target.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Findings {
    /// Reported ground speed beyond what any aircraft of the traffic picture flies.
    pub impossible_speed: Option<i64>,
    /// A position implying a speed beyond the limit since the previous one.
    pub position_jump: Option<i64>,
    /// An altitude change beyond the vertical-rate limit.
    pub altitude_jump: Option<i64>,
    /// Received signal far stronger than the reported range allows (a nearby transmitter
    /// claiming a distant position).
    pub range_vs_signal: Option<i64>,
    /// Two sources place the same address at positions that disagree beyond their uncertainty
    /// (includes ADS-B against FLARM).
    pub inconsistent_sources: Option<i64>,
    // --- issue 24 ---
    /// Positions that drift away from where the reported velocity takes them, over a window (a
    /// patient spoofer moving a target slower than the jump test sees).
    pub position_drift: Option<i64>,
    /// GPS time (ns) since which every report has been consistent (no finding); `None` while the
    /// last report raised one. Flags clear only after consistent reports for
    /// [`super::TrafficParams::flag_hold_s`].
    pub consistent_since: Option<i64>,
}

/// Active plausibility flags of a target at one time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct PlausibilityFlags {
    /// See [`Findings::impossible_speed`].
    pub impossible_speed: bool,
    /// See [`Findings::position_jump`].
    pub position_jump: bool,
    /// See [`Findings::altitude_jump`].
    pub altitude_jump: bool,
    /// See [`Findings::range_vs_signal`].
    pub range_vs_signal: bool,
    /// See [`Findings::inconsistent_sources`].
    pub inconsistent_sources: bool,
    /// See [`Findings::position_drift`] (issue 24).
    pub position_drift: bool,
}

impl PlausibilityFlags {
    /// True when any flag is set: the target is suspect (possible spoofing or a faulty source).
    pub fn any(&self) -> bool {
        self.impossible_speed
            || self.position_jump
            || self.altitude_jump
            || self.range_vs_signal
            || self.inconsistent_sources
            || self.position_drift
    }
}

impl Findings {
    /// The flags at `t_ns`: every finding seen stays active until the reports have been
    /// consistent for `hold_ns` (a silent target keeps its flags until it times out).
    pub fn active(&self, t_ns: i64, hold_ns: i64) -> PlausibilityFlags {
        let cleared = self
            .consistent_since
            .is_some_and(|c| t_ns.saturating_sub(c) >= hold_ns);
        let on = |f: Option<i64>| f.is_some() && !cleared;
        PlausibilityFlags {
            impossible_speed: on(self.impossible_speed),
            position_jump: on(self.position_jump),
            altitude_jump: on(self.altitude_jump),
            range_vs_signal: on(self.range_vs_signal),
            inconsistent_sources: on(self.inconsistent_sources),
            position_drift: on(self.position_drift),
        }
    }

    /// After the tests of one report at `t_ns`: restarts the consistent run when the report
    /// raised a finding, starts it at the first clean report, and forgets findings once the run
    /// is `hold_ns` long.
    pub fn close_report(&mut self, t_ns: i64, hold_ns: i64) {
        let all = [
            self.impossible_speed,
            self.position_jump,
            self.altitude_jump,
            self.range_vs_signal,
            self.inconsistent_sources,
            self.position_drift,
        ];
        if all.contains(&Some(t_ns)) {
            self.consistent_since = None;
        } else if self.consistent_since.is_none() {
            self.consistent_since = Some(t_ns);
        }
        if self
            .consistent_since
            .is_some_and(|c| t_ns.saturating_sub(c) >= hold_ns)
        {
            // Forget the findings, keep the run. (Whether the run is kept makes no difference
            // that can be seen: with no finding left `active` shows nothing, and the next
            // finding restarts the run. Written as an assignment rather than a struct literal
            // with `..Default::default()`: cargo-mutants' exclusions cannot name the field
            // deletion of such a literal, which would be an equivalent mutant.)
            let run = self.consistent_since;
            *self = Findings::default();
            self.consistent_since = run;
        }
    }
}

/// One report in the drift window: time (ns), position (deg), velocity over ground (east, north,
/// m/s) and position sigma (m).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DriftSample {
    /// GPS time, ns.
    pub t_gps_ns: i64,
    /// Latitude, deg.
    pub lat_deg: f64,
    /// Longitude, deg.
    pub lon_deg: f64,
    /// Velocity (east, north), m/s.
    pub velocity_en_mps: [f64; 2],
    /// 1-sigma horizontal position, m.
    pub sigma_m: f64,
}

/// Position-against-velocity consistency over a window (issue 24): the displacement since the
/// oldest report in the window against the reported velocities integrated (trapezoids) over the
/// same reports. A spoofer moving a target's positions at 20 m/s while reporting its true
/// velocity builds a residual of 20 m per second, far below what the jump test sees.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct DriftWindow {
    samples: std::collections::VecDeque<DriftSample>,
}

impl DriftWindow {
    /// Adds a report and returns `(residual_m, span_s, base_sigma_m)` once the window spans at
    /// least a third of `window_ns`; out-of-order reports are ignored.
    pub fn push(&mut self, s: DriftSample, window_ns: i64) -> Option<(f64, f64, f64)> {
        if self
            .samples
            .back()
            .is_some_and(|b| s.t_gps_ns <= b.t_gps_ns)
        {
            return None;
        }
        while self
            .samples
            .front()
            .is_some_and(|f| s.t_gps_ns.saturating_sub(f.t_gps_ns) > window_ns)
        {
            self.samples.pop_front();
        }
        self.samples.push_back(s);
        let base = *self.samples.front()?;
        let span_s = s.t_gps_ns.saturating_sub(base.t_gps_ns) as f64 * 1e-9;
        if span_s * 3e9 < window_ns as f64 {
            return None;
        }
        let mut predicted = [0.0, 0.0];
        for (a, b) in self.samples.iter().zip(self.samples.iter().skip(1)) {
            let dt = b.t_gps_ns.saturating_sub(a.t_gps_ns) as f64 * 1e-9;
            for (k, p) in predicted.iter_mut().enumerate() {
                *p += 0.5 * (a.velocity_en_mps[k] + b.velocity_en_mps[k]) * dt;
            }
        }
        let frame = crate::geometry::wgs84::EnuFrame::at(base.lat_deg, base.lon_deg, 0.0);
        let (p, _) = crate::geometry::wgs84::geodetic_to_ecef(s.lat_deg, s.lon_deg, 0.0);
        let actual = frame.position(&p);
        let residual = (actual.x - predicted[0]).hypot(actual.y - predicted[1]);
        Some((residual, span_s, base.sigma_m))
    }

    /// Forgets the window (a report without velocity breaks the chain).
    pub fn clear(&mut self) {
        self.samples.clear();
    }
}

/// A target's merged state.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Track {
    /// Merge key.
    pub key: TargetKey,
    /// Address type as last reported.
    pub address_type: AddressType,
    /// Latest report per source with its GPS time.
    pub sources: Vec<Timed<(Source, TrafficReport)>>,
    /// Freshest position fix.
    pub position: Option<Timed<Fix>>,
    /// Freshest horizontal velocity: track over ground (deg true) and ground speed (m/s).
    pub velocity: Option<Timed<(f64, f64)>>,
    /// Freshest vertical rate, m/s.
    pub vertical_rate: Option<Timed<f64>>,
    /// Freshest barometric altitude, m.
    pub alt_pressure: Option<Timed<f64>>,
    /// Freshest geometric altitude, m.
    pub alt_geometric: Option<Timed<f64>>,
    /// Callsign, latest known.
    pub callsign: Option<String>,
    /// Emitter category, latest known.
    pub emitter_category: Option<u8>,
    /// Squawk, latest known.
    pub squawk: Option<u16>,
    /// FLARM alarm level (0-3), latest known from FLARM.
    pub flarm_alarm_level: Option<u8>,
    /// Latest received signal level, dBm.
    pub signal_dbm: Option<f64>,
    /// GPS time of the latest report, ns.
    pub last_update_ns: i64,
    /// Plausibility findings.
    pub findings: Findings,
    /// Live alert filter state.
    pub alert: super::alert_filter::AlertFilter,
    /// Position-against-velocity window (issue 24).
    pub drift: DriftWindow,
}

/// 1-sigma horizontal uncertainty of a report's position, m: from NACp (EPU) when given, else from
/// NIC (containment radius, a looser bound), else a default for FLARM/unknown.
pub fn report_sigma_m(r: &TrafficReport) -> f64 {
    r.nac_p
        .and_then(epu_m)
        .or_else(|| r.nic.and_then(rc_m))
        .map(sigma_from_r95)
        .unwrap_or(match r.link {
            // FLARM positions come from the other aircraft's own GNSS: ~10 m class.
            Link::Flarm => 10.0,
            _ => 100.0,
        })
}

impl Track {
    /// A new, empty track for a key.
    pub fn new(key: TargetKey, address_type: AddressType, t_gps_ns: i64) -> Self {
        Self {
            key,
            address_type,
            sources: Vec::with_capacity(2),
            position: None,
            velocity: None,
            vertical_rate: None,
            alt_pressure: None,
            alt_geometric: None,
            callsign: None,
            emitter_category: None,
            squawk: None,
            flarm_alarm_level: None,
            signal_dbm: None,
            last_update_ns: t_gps_ns,
            findings: Findings::default(),
            alert: Default::default(),
            drift: DriftWindow::default(),
        }
    }

    /// Age of the latest report at `t_ns`, s.
    pub fn age_s(&self, t_ns: i64) -> f64 {
        t_ns.saturating_sub(self.last_update_ns) as f64 * 1e-9
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `PlausibilityFlags::any` (a target is suspect) is true when any one flag is set, and
    /// only then.
    #[test]
    fn any_plausibility_flag_alone_makes_the_target_suspect() {
        assert!(!PlausibilityFlags::default().any());
        let each: [fn(&mut PlausibilityFlags); 6] = [
            |f| f.impossible_speed = true,
            |f| f.position_jump = true,
            |f| f.altitude_jump = true,
            |f| f.range_vs_signal = true,
            |f| f.inconsistent_sources = true,
            |f| f.position_drift = true,
        ];
        for (i, set) in each.iter().enumerate() {
            let mut f = PlausibilityFlags::default();
            set(&mut f);
            assert!(f.any(), "flag {i} alone");
        }
    }
}
