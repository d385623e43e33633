//! Integrity rules over vigil's fused outputs and the alert life cycle (raise, persist, clear,
//! latch). Issue 10, "monitor/".
//!
//! The monitor reads the bus payloads (`vigil_bus::payload`) rather than fusion types, so the same
//! code runs inside `vigil run` (fed in-process with the payloads it publishes) and as the separate
//! process `vigil monitor` (fed by iceoryx2 subscribers). Its clock is the GPS time of the payloads
//! it is given ([`Monitor::poll`]): replaying the same inputs gives the same alerts.
//!
//! API contract: feed every payload as it is published, then call [`Monitor::poll`] with the
//! current GPS time and publish the [`AlertPayload`]s it returns (one per alert state change).
//! Rules are judged on the latest payload of each topic at each poll, so poll after every payload
//! (or at least as often as the fastest rule must react). A condition judged on a topic that has
//! stopped keeps its last value (an alert does not clear because its evidence stopped arriving;
//! the feed-silent rule says that the evidence stopped).
//!
//! ```
//! use vigil_bus::payload::alerts::{SEVERITY_CAUTION, STATE_RAISED};
//! use vigil_bus::payload::attitude::{AttitudePayload, FAULT_HEALTH, UNIT_BAHRS};
//! use vigil_monitor::{Monitor, MonitorParams, Rule};
//!
//! let mut monitor = Monitor::new(MonitorParams::default());
//! let mut att = AttitudePayload { valid: 1, ..AttitudePayload::default() };
//! att.units[usize::from(UNIT_BAHRS)].fault_flags = FAULT_HEALTH; // BAHRS health "integrity risk"
//! monitor.attitude(&att);
//! let alerts = monitor.poll(1_000_000_000);
//! assert_eq!(alerts.len(), 1);
//! assert_eq!(alerts[0].alert_id, Rule::UnitHealth.alert_id(u32::from(UNIT_BAHRS)));
//! assert_eq!((alerts[0].state, alerts[0].severity), (STATE_RAISED, SEVERITY_CAUTION));
//! assert!(alerts[0].reason().starts_with("BAHRS health integrity risk"));
//! ```
//!
//! # Rules
//!
//! Alert ids, codes and subjects are in [`rules`]. Fields read from the payloads:
//!
//! | rule | condition | severity | delay s | hysteresis s |
//! |---|---|---|---|---|
//! | `attitude_miscompare` (per axis) | any pair's `pair_verdicts[pair][axis]` is `VERDICT_FAIL` | caution | 0 | 1 |
//! | `unit_isolated` (per unit) | `isolation == ISOLATION_ISOLATED`, for `isolated_unit` | caution | 0 | 2 |
//! | `unit_health` (per unit) | the unit's `fault_flags` has `FAULT_HEALTH` (BAHRS: health 10 "integrity risk") | caution | 0 | 1 |
//! | `attitude_invalid` | attitude `valid == 0` | warning | 1 | 1 |
//! | `ins_not_tracking` | the VN-200 unit's `fault_flags` has `FAULT_INVALID` | caution | 1 | 2 |
//! | `gnss_lost` | ownship `source == SOURCE_TTMRF_GNSS` (advisory), `valid == 0` or `SOURCE_NONE` (caution), an unknown source (advisory) | advisory/caution | 1 | 2 |
//! | `clock_not_locked` | `CLOCK_NOT_LOCKED` or an unknown code (caution), `CLOCK_HOLDOVER` (advisory), `CLOCK_GPS_TIME` with `clock_require_pps` (advisory) | advisory/caution | 2 | 2 |
//! | `device_silent` (per device) | `LINK_SILENT`, `LINK_DISCONNECTED`, `last_message_age_s > device_silent_s`, or never heard for longer than that | caution | 0 | 1 |
//! | `decode_errors` (per device) | rejected fraction of a `decode_window_s` window over `decode_error_ratio_max` (see [`links`]) | advisory | 0 | 0 |
//! | `feed_silent` (per topic) | no payload of the topic for longer than `feed_silent_s` | caution | 0 | 0 |
//! | `traffic_alert` (per target) | `alert_level`: preventive -> advisory, corrective -> caution, warning (or unknown code) -> warning | by level | 0 | 0 |
//! | `suspected_spoofing` (per target) | `plausibility_flags & spoofing_flags != 0` | caution | 0 | 5 |
//! | `cross_check_unavailable` (per unit) | the unit's `unit_coverage` is not `COVERAGE_COMPARED` (reason: `not_aligned`, `not_wired`, `stale`, `absent`, `invalid`, `no_partner`, `no_check`) | caution | 2 | 1 |
//! | `vertical_miscompare` (per comparison) | `vertical[VERTICAL_*].verdict == VERDICT_FAIL` (BAHRS down velocity or pressure-height rate against the GNSS-aided VN-200; the reason names the unit `vertical_isolated_unit` isolates by the TT-Multi-RF GNSS third opinion, else attributes it to the BAHRS and says why the TT GNSS did not decide) | caution | 0 | 2 |
//! | `inertial_miscompare` (per signal) | `inertial[INERTIAL_*].verdict == VERDICT_FAIL` (a BAHRS specific force or angular rate axis against the VN-200, both usable) | caution | 0 | 2 |
//! | `health_disagreement` (per combination) | integrity `health_checks[HEALTH_*].state == HEALTH_DISAGREE` (BAHRS pulses without a VN-200 fix, a fix without pulses, an INS mode against its fix bit; not compared is never a disagreement) | caution | 3 | 2 |
//! | `clock_disagreement` (per device) | integrity `clock_disagreement & (1 << DEVICE_*) != 0` (the device's own time against the host clock; the reason names the clock and what was done with its samples) | caution | 1 | 2 |
//! | `line_full` (per device) | integrity `line_full & (1 << DEVICE_*) != 0` (the device's messages fill its line: its output waits, and may be lost, in the device; the reason says what to change) | caution | 1 | 2 |
//!
//! No rule latches by default; any can (`[monitor.RULE] latch = true`). Why the delays are 0
//! where they are: the fusion cross-check and the traffic alert filter already apply persistence
//! and hysteresis, the BAHRS "integrity risk" flag must raise at its first sample (issue 8), and
//! the silence limits and error windows are those rules' own persistence.
//!
//! # Parameters ([`MonitorParams`], TOML section `[monitor]`)
//!
//! | key | unit | default | meaning |
//! |---|---|---|---|
//! | `RULE.enabled` | bool | true | the rule is evaluated (`RULE` is a rule name above) |
//! | `RULE.raise_delay_s` | s | see above | the condition must hold this long before the alert raises |
//! | `RULE.clear_hysteresis_s` | s | see above | the condition must stay absent this long before the alert clears |
//! | `RULE.latch` | bool | false | on clearing, go to LATCHED and wait for [`Monitor::acknowledge`] |
//! | `device_silent_s` | s | 2.0 | a device whose last valid message is older is silent |
//! | `feed_silent_s` | s | 2.0 | a topic not received for longer is silent |
//! | `decode_window_s` | s | 10.0 | window of the decode error count |
//! | `decode_error_ratio_max` | fraction | 0.05 | largest rejected fraction of frames in a window |
//! | `decode_min_frames` | frames | 20 | fewest frames for a window to be judged |
//! | `clock_require_pps` | bool | false | a clock with GPS time but no PPS lock is an advisory |
//! | `spoofing_flags` | bits | 0x3F | `PLAUSIBILITY_*` bits that make a target suspect (all six) |
//!
//! # Time
//!
//! Raise delays and hysteresis are judged at the polls (see [`lifecycle`]). A poll time earlier
//! than the previous one (a replay restarting, a publisher's clock stepping back) is taken as the
//! previous one, so the monitor's time never runs backwards. Each transition's payload carries the
//! poll time in `header.gps_time_ns` and a sequence number of the monitor's own in `header.seq`
//! (the bus publisher restamps `seq` per publisher).
#![deny(missing_docs)]

pub mod clock;
mod conditions;
pub mod lifecycle;
pub mod links;
pub mod params;
pub mod rules;

#[cfg(test)]
mod rule_tests;

use std::collections::{BTreeMap, BTreeSet};

use vigil_bus::payload::SCHEMA_VERSION;
use vigil_bus::payload::alerts::AlertPayload;
use vigil_bus::payload::alerts::{STATE_LATCHED, STATE_RAISED};
use vigil_bus::payload::attitude::AttitudePayload;
use vigil_bus::payload::integrity::{ActiveAlert, IntegrityPayload, MAX_ACTIVE_ALERTS};
use vigil_bus::payload::ownship::OwnshipPayload;
use vigil_bus::payload::traffic::TrafficPayload;
use vigil_bus::payload::write_text;

pub use clock::GpsClock;
pub use conditions::{plausibility_names, unit_name};
pub use lifecycle::{Change, Condition, Lifecycle, Phase};
pub use params::{MonitorParams, ParamError, RuleTiming};
pub use rules::{Rule, target_alert_id};

use conditions::TargetSummary;
use links::{Devices, FEED_ATTITUDE, FEED_INTEGRITY, FEED_OWNSHIP, FEED_TRAFFIC, Feeds};

/// The integrity monitor: rule states and alert life cycles.
#[derive(Debug, Clone, Default)]
pub struct Monitor {
    params: MonitorParams,
    attitude: Option<AttitudePayload>,
    ownship: Option<OwnshipPayload>,
    /// Targets of the latest traffic payload that have an alert level or a suspect flag.
    targets: Vec<TargetSummary>,
    integrity: Option<IntegrityPayload>,
    integrity_new: bool,
    devices: Devices,
    feeds: Feeds,
    start_ns: Option<i64>,
    last_t_ns: Option<i64>,
    alerts: BTreeMap<u32, Lifecycle>,
    seq: u64,
}

impl Monitor {
    /// A monitor with the given parameters.
    pub fn new(params: MonitorParams) -> Self {
        Self {
            params,
            ..Self::default()
        }
    }

    /// The parameters in force.
    pub fn params(&self) -> &MonitorParams {
        &self.params
    }

    /// Takes a published attitude payload.
    pub fn attitude(&mut self, p: &AttitudePayload) {
        self.attitude = Some(*p);
        self.feeds.seen(FEED_ATTITUDE);
    }

    /// Takes a published ownship payload.
    pub fn ownship(&mut self, p: &OwnshipPayload) {
        self.ownship = Some(*p);
        self.feeds.seen(FEED_OWNSHIP);
    }

    /// Takes a published traffic payload (only the targets with an alert level or a suspect flag
    /// are kept).
    pub fn traffic(&mut self, p: &TrafficPayload) {
        let params = self.params;
        self.targets.clear();
        self.targets.extend(
            p.targets()
                .iter()
                .filter_map(|t| TargetSummary::of(t, &params)),
        );
        self.feeds.seen(FEED_TRAFFIC);
    }

    /// Takes a published integrity payload.
    pub fn integrity(&mut self, p: &IntegrityPayload) {
        self.integrity = Some(*p);
        self.integrity_new = true;
        self.feeds.seen(FEED_INTEGRITY);
    }

    /// Acknowledges a latched alert: it is cleared (a CLEARED payload) at the next poll. Returns
    /// false when `alert_id` is not latched.
    pub fn acknowledge(&mut self, alert_id: u32) -> bool {
        self.alerts
            .get_mut(&alert_id)
            .is_some_and(Lifecycle::acknowledge)
    }

    /// The alerts raised or latched now, `(alert_id, phase)`, by id.
    pub fn active(&self) -> impl Iterator<Item = (u32, Phase)> + '_ {
        self.alerts
            .iter()
            .filter(|(_, lc)| lc.is_active())
            .map(|(&id, lc)| (id, lc.phase()))
    }

    // --- issue 25: the active set as state ---
    /// Fills `p`'s active-alert set with the alerts raised or latched now: the most severe
    /// first, then the oldest, then by id; as many as fit, `active_alert_total` counting all.
    pub fn fill_active(&self, p: &mut IntegrityPayload) {
        let mut all: Vec<ActiveAlert> = self
            .alerts
            .iter()
            .filter_map(|(&alert_id, lc)| {
                let (state, raised_gps_ns, severity) = match lc.phase() {
                    Phase::Raised {
                        raised_ns,
                        severity,
                        ..
                    } => (STATE_RAISED, raised_ns, severity),
                    Phase::Latched {
                        raised_ns,
                        severity,
                        ..
                    } => (STATE_LATCHED, raised_ns, severity),
                    Phase::Inactive | Phase::Pending { .. } => return None,
                };
                let mut a = ActiveAlert {
                    alert_id,
                    severity,
                    state,
                    raised_gps_ns,
                    ..ActiveAlert::default()
                };
                write_text(&mut a.reason, lc.reason());
                Some(a)
            })
            .collect();
        all.sort_by_key(|a| (core::cmp::Reverse(a.severity), a.raised_gps_ns, a.alert_id));
        p.active_alert_total = all.len() as u32;
        let n = all.len().min(MAX_ACTIVE_ALERTS);
        p.active_alerts[..n].copy_from_slice(&all[..n]);
        p.active_alert_count = n as u32;
    }

    /// Evaluates every rule at GPS time `t_gps_ns` (ns); returns the alert state changes to
    /// publish, in a deterministic order (by `alert_id`).
    pub fn poll(&mut self, t_gps_ns: i64) -> Vec<AlertPayload> {
        let t = self.last_t_ns.map_or(t_gps_ns, |last| t_gps_ns.max(last));
        self.last_t_ns = Some(t);
        let start = *self.start_ns.get_or_insert(t);
        let params = self.params;

        let mut active = Vec::new();
        if let Some(p) = &self.attitude {
            conditions::attitude(p, &params, &mut active);
            conditions::coverage(p, &params, &mut active);
            conditions::vertical(p, &params, &mut active);
            conditions::inertial(p, &params, &mut active);
        }
        if let Some(p) = &self.ownship {
            conditions::ownship(p, &params, &mut active);
        }
        conditions::traffic(&self.targets, &params, &mut active);
        if let Some(p) = &self.integrity {
            if core::mem::take(&mut self.integrity_new) {
                self.devices.update(p, t, &params);
            }
            conditions::clock(p, &params, &mut active);
            conditions::health(p, &params, &mut active);
            conditions::clock_disagreement(p, &params, &mut active);
            conditions::line_full(p, &params, &mut active);
            self.devices.conditions(p, t, &params, &mut active);
        }
        self.feeds.conditions(t, start, &params, &mut active);

        // Two targets could in principle share an id (same address and type twice in one
        // payload): the first, most urgent by the payload's order, wins.
        let mut conds: BTreeMap<u32, Condition> = BTreeMap::new();
        for (id, c) in active {
            conds.entry(id).or_insert(c);
        }
        let ids: BTreeSet<u32> = conds.keys().chain(self.alerts.keys()).copied().collect();
        let mut out = Vec::new();
        for id in ids {
            let Some(rule) = Rule::of_alert(id) else {
                continue;
            };
            let timing = params.timing(rule);
            let lc = self.alerts.entry(id).or_default();
            if let Some(change) = lc.step(t, conds.get(&id), timing) {
                self.seq += 1;
                let mut a = AlertPayload {
                    alert_id: id,
                    severity: change.severity,
                    state: change.state,
                    raised_gps_ns: change.raised_gps_ns,
                    ..AlertPayload::default()
                };
                a.header.schema_version = SCHEMA_VERSION;
                a.header.seq = self.seq;
                a.header.gps_time_ns = t;
                a.set_reason(&change.reason);
                out.push(a);
            }
            if lc.is_idle() {
                self.alerts.remove(&id);
            }
        }
        out
    }
}
