//! [`MonitorParams`]: every threshold and timing of the monitor in one table, with units and
//! defaults (the table is in the crate documentation). Deserialisable from the `[monitor]` section
//! of vigil's TOML configuration; a missing key takes its default, an unknown key is an error, and
//! [`MonitorParams::validate`] names a key whose value is out of range.

use serde::{Deserialize, Deserializer, Serialize};
use vigil_bus::payload::traffic::{
    PLAUSIBILITY_ALTITUDE_JUMP, PLAUSIBILITY_IMPOSSIBLE_SPEED, PLAUSIBILITY_INCONSISTENT_SOURCES,
    PLAUSIBILITY_POSITION_DRIFT, PLAUSIBILITY_POSITION_JUMP, PLAUSIBILITY_RANGE_VS_SIGNAL,
};

use crate::rules::Rule;

/// Life-cycle timing of one rule's alerts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RuleTiming {
    /// The rule is evaluated; when false it never raises (and clears what it had raised).
    pub enabled: bool,
    /// Time the condition must hold before the alert is raised, s (0: at the first evaluation).
    pub raise_delay_s: f64,
    /// Time the condition must stay absent before the alert clears, s (0: at once).
    pub clear_hysteresis_s: f64,
    /// When the condition clears, the alert goes to LATCHED and stays until acknowledged.
    pub latch: bool,
}

impl RuleTiming {
    /// Enabled, not latching, with the given delay and hysteresis, s.
    pub const fn new(raise_delay_s: f64, clear_hysteresis_s: f64) -> Self {
        Self {
            enabled: true,
            raise_delay_s,
            clear_hysteresis_s,
            latch: false,
        }
    }

    /// The default timing of `rule` (see the crate documentation's table for the reasons).
    pub const fn default_for(rule: Rule) -> Self {
        match rule {
            // The fusion cross-check already applies its persistence (about 1 s) before a pair
            // verdict fails or a unit is isolated: no second delay on top.
            Rule::AttitudeMiscompare => Self::new(0.0, 1.0),
            Rule::UnitIsolated => Self::new(0.0, 2.0),
            // Issue 8: the BAHRS "integrity risk" flag raises at the first such sample.
            Rule::UnitHealth => Self::new(0.0, 1.0),
            Rule::AttitudeInvalid => Self::new(1.0, 1.0),
            Rule::InsNotTracking => Self::new(1.0, 2.0),
            Rule::GnssLost => Self::new(1.0, 2.0),
            Rule::ClockNotLocked => Self::new(2.0, 2.0),
            // The silence limit and the counting window are the persistence of these rules.
            Rule::DeviceSilent => Self::new(0.0, 1.0),
            Rule::DecodeErrors => Self::new(0.0, 0.0),
            Rule::FeedSilent => Self::new(0.0, 0.0),
            // The fusion alert filter already applies M-of-N, persistence and hysteresis to the
            // target levels: the monitor passes them through as they are.
            Rule::TrafficAlert => Self::new(0.0, 0.0),
            Rule::SuspectedSpoofing => Self::new(0.0, 5.0),
            // Issue 25: "not compared for longer than a configured time" is the raise delay
            // (2 s: well past a check's normal wait, about 0.25 s at most); comparisons must run
            // again for 1 s before it clears.
            Rule::CrossCheckUnavailable => Self::new(2.0, 1.0),
            // Issue 25 points 5 and 6: the fusion's persistence (filtered ratio for 1 s, or the
            // CUSUM) already stands between a disagreement and a FAIL verdict: no second delay.
            // The verdict itself clears with the same persistence; 2 s more keep a drift that
            // hovers at the limit from raising and clearing in turn.
            Rule::VerticalMiscompare => Self::new(0.0, 2.0),
            Rule::InertialMiscompare => Self::new(0.0, 2.0),
            // Issue 25 point 4: "disagree for longer than a configured time" is the raise delay.
            // 3 s: three 1 Hz sync pulses against a VN-200 without a fix (the fusion already
            // skips pulses reported within 0.5 s of the loss, and waits `pulse_timeout_s` (2.5 s)
            // before calling pulses missing, or `extended_outage_s` (60 s) for an INS mode
            // against its fix bit); 2 s of agreement before it clears, so a pulse train at the
            // edge of a fix does not raise and clear in turn.
            Rule::HealthDisagreement => Self::new(3.0, 2.0),
            // Issue 18 point 4: the bit follows the latest checked time (a BAHRS pulse a second,
            // a VN-200 message every 5 ms); 1 s of it set before raising passes over a single
            // late host read, and 2 s without it (two agreeing BAHRS pulses) clear.
            Rule::ClockDisagreement => Self::new(1.0, 2.0),
            // The bit is judged at each integrity report (1 Hz) over the line's last 100 ms or
            // more: raised when two reports a second apart find it full (one burst of traffic
            // does not raise), cleared after 2 s of reports that do not.
            Rule::LineFull => Self::new(1.0, 2.0),
        }
    }

    /// Raise delay, ns (negative or NaN taken as 0).
    pub fn raise_delay_ns(&self) -> i64 {
        secs_to_ns(self.raise_delay_s)
    }

    /// Clear hysteresis, ns (negative or NaN taken as 0).
    pub fn clear_hysteresis_ns(&self) -> i64 {
        secs_to_ns(self.clear_hysteresis_s)
    }
}

/// Seconds to ns, saturating; NaN and negative give 0.
pub(crate) fn secs_to_ns(s: f64) -> i64 {
    if s.is_nan() || s <= 0.0 {
        0
    } else {
        // `as` saturates at i64::MAX for huge values.
        (s * 1e9).round() as i64
    }
}

/// A `[monitor.RULE]` table: every key optional, unknown keys rejected; what is missing keeps the
/// rule's own default (not a generic one).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TimingPatch {
    enabled: Option<bool>,
    raise_delay_s: Option<f64>,
    clear_hysteresis_s: Option<f64>,
    latch: Option<bool>,
}

macro_rules! timing_field {
    ($fn_name:ident, $rule:expr) => {
        fn $fn_name<'de, D: Deserializer<'de>>(d: D) -> Result<RuleTiming, D::Error> {
            let p = TimingPatch::deserialize(d)?;
            let t = RuleTiming::default_for($rule);
            Ok(RuleTiming {
                enabled: p.enabled.unwrap_or(t.enabled),
                raise_delay_s: p.raise_delay_s.unwrap_or(t.raise_delay_s),
                clear_hysteresis_s: p.clear_hysteresis_s.unwrap_or(t.clear_hysteresis_s),
                latch: p.latch.unwrap_or(t.latch),
            })
        }
    };
}

timing_field!(de_attitude_miscompare, Rule::AttitudeMiscompare);
timing_field!(de_unit_isolated, Rule::UnitIsolated);
timing_field!(de_unit_health, Rule::UnitHealth);
timing_field!(de_attitude_invalid, Rule::AttitudeInvalid);
timing_field!(de_ins_not_tracking, Rule::InsNotTracking);
timing_field!(de_gnss_lost, Rule::GnssLost);
timing_field!(de_clock_not_locked, Rule::ClockNotLocked);
timing_field!(de_device_silent, Rule::DeviceSilent);
timing_field!(de_decode_errors, Rule::DecodeErrors);
timing_field!(de_feed_silent, Rule::FeedSilent);
timing_field!(de_traffic_alert, Rule::TrafficAlert);
timing_field!(de_suspected_spoofing, Rule::SuspectedSpoofing);
timing_field!(de_cross_check_unavailable, Rule::CrossCheckUnavailable);
timing_field!(de_vertical_miscompare, Rule::VerticalMiscompare);
timing_field!(de_inertial_miscompare, Rule::InertialMiscompare);
timing_field!(de_health_disagreement, Rule::HealthDisagreement);
timing_field!(de_clock_disagreement, Rule::ClockDisagreement);
timing_field!(de_line_full, Rule::LineFull);

/// Every plausibility flag: the default of [`MonitorParams::spoofing_flags`]. (Issue 23: the
/// slow-drift flag of issue 24 was missing here, so a patient spoof never raised
/// `suspected_spoofing` with the defaults; found by mutation testing, pinned by a test.)
pub const ALL_PLAUSIBILITY_FLAGS: u8 = PLAUSIBILITY_IMPOSSIBLE_SPEED
    | PLAUSIBILITY_POSITION_JUMP
    | PLAUSIBILITY_ALTITUDE_JUMP
    | PLAUSIBILITY_RANGE_VS_SIGNAL
    | PLAUSIBILITY_INCONSISTENT_SOURCES
    | PLAUSIBILITY_POSITION_DRIFT;

/// Thresholds and timings of every rule, with units and defaults (the crate documentation has
/// them as one table). In TOML: a `[monitor]` section with the thresholds, and one
/// `[monitor.RULE]` table per rule for its timing, e.g. `[monitor.gnss_lost] latch = true`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MonitorParams {
    /// Timing of [`Rule::AttitudeMiscompare`].
    #[serde(deserialize_with = "de_attitude_miscompare")]
    pub attitude_miscompare: RuleTiming,
    /// Timing of [`Rule::UnitIsolated`].
    #[serde(deserialize_with = "de_unit_isolated")]
    pub unit_isolated: RuleTiming,
    /// Timing of [`Rule::UnitHealth`].
    #[serde(deserialize_with = "de_unit_health")]
    pub unit_health: RuleTiming,
    /// Timing of [`Rule::AttitudeInvalid`].
    #[serde(deserialize_with = "de_attitude_invalid")]
    pub attitude_invalid: RuleTiming,
    /// Timing of [`Rule::InsNotTracking`].
    #[serde(deserialize_with = "de_ins_not_tracking")]
    pub ins_not_tracking: RuleTiming,
    /// Timing of [`Rule::GnssLost`].
    #[serde(deserialize_with = "de_gnss_lost")]
    pub gnss_lost: RuleTiming,
    /// Timing of [`Rule::ClockNotLocked`].
    #[serde(deserialize_with = "de_clock_not_locked")]
    pub clock_not_locked: RuleTiming,
    /// Timing of [`Rule::DeviceSilent`].
    #[serde(deserialize_with = "de_device_silent")]
    pub device_silent: RuleTiming,
    /// Timing of [`Rule::DecodeErrors`].
    #[serde(deserialize_with = "de_decode_errors")]
    pub decode_errors: RuleTiming,
    /// Timing of [`Rule::FeedSilent`].
    #[serde(deserialize_with = "de_feed_silent")]
    pub feed_silent: RuleTiming,
    /// Timing of [`Rule::TrafficAlert`].
    #[serde(deserialize_with = "de_traffic_alert")]
    pub traffic_alert: RuleTiming,
    /// Timing of [`Rule::SuspectedSpoofing`].
    #[serde(deserialize_with = "de_suspected_spoofing")]
    pub suspected_spoofing: RuleTiming,
    // --- issue 25 ---
    /// Timing of [`Rule::CrossCheckUnavailable`].
    #[serde(deserialize_with = "de_cross_check_unavailable")]
    pub cross_check_unavailable: RuleTiming,
    /// Timing of [`Rule::VerticalMiscompare`].
    #[serde(deserialize_with = "de_vertical_miscompare")]
    pub vertical_miscompare: RuleTiming,
    /// Timing of [`Rule::InertialMiscompare`].
    #[serde(deserialize_with = "de_inertial_miscompare")]
    pub inertial_miscompare: RuleTiming,
    /// Timing of [`Rule::HealthDisagreement`].
    #[serde(deserialize_with = "de_health_disagreement")]
    pub health_disagreement: RuleTiming,
    /// Timing of [`Rule::ClockDisagreement`].
    #[serde(deserialize_with = "de_clock_disagreement")]
    pub clock_disagreement: RuleTiming,
    /// Timing of [`Rule::LineFull`].
    #[serde(deserialize_with = "de_line_full")]
    pub line_full: RuleTiming,

    /// A device is silent when its last valid message is older than this, s.
    pub device_silent_s: f64,
    /// A bus topic is silent when no payload arrived for longer than this, s.
    pub feed_silent_s: f64,
    /// Length of the window over which decode errors are counted, s.
    pub decode_window_s: f64,
    /// Largest allowed fraction of rejected frames (checksum failures + malformed) among all
    /// frames (those + messages) in one window, 0..1.
    pub decode_error_ratio_max: f64,
    /// Fewest frames a window needs before its error fraction is judged.
    pub decode_min_frames: u64,
    /// When true, a clock with GPS time but no PPS lock (`CLOCK_GPS_TIME`) raises an advisory.
    pub clock_require_pps: bool,
    /// `PLAUSIBILITY_*` bits that make a target suspect of spoofing.
    pub spoofing_flags: u8,
}

impl Default for MonitorParams {
    fn default() -> Self {
        Self {
            attitude_miscompare: RuleTiming::default_for(Rule::AttitudeMiscompare),
            unit_isolated: RuleTiming::default_for(Rule::UnitIsolated),
            unit_health: RuleTiming::default_for(Rule::UnitHealth),
            attitude_invalid: RuleTiming::default_for(Rule::AttitudeInvalid),
            ins_not_tracking: RuleTiming::default_for(Rule::InsNotTracking),
            gnss_lost: RuleTiming::default_for(Rule::GnssLost),
            clock_not_locked: RuleTiming::default_for(Rule::ClockNotLocked),
            device_silent: RuleTiming::default_for(Rule::DeviceSilent),
            decode_errors: RuleTiming::default_for(Rule::DecodeErrors),
            feed_silent: RuleTiming::default_for(Rule::FeedSilent),
            traffic_alert: RuleTiming::default_for(Rule::TrafficAlert),
            suspected_spoofing: RuleTiming::default_for(Rule::SuspectedSpoofing),
            cross_check_unavailable: RuleTiming::default_for(Rule::CrossCheckUnavailable),
            vertical_miscompare: RuleTiming::default_for(Rule::VerticalMiscompare),
            inertial_miscompare: RuleTiming::default_for(Rule::InertialMiscompare),
            health_disagreement: RuleTiming::default_for(Rule::HealthDisagreement),
            clock_disagreement: RuleTiming::default_for(Rule::ClockDisagreement),
            line_full: RuleTiming::default_for(Rule::LineFull),
            device_silent_s: 2.0,
            feed_silent_s: 2.0,
            decode_window_s: 10.0,
            decode_error_ratio_max: 0.05,
            decode_min_frames: 20,
            clock_require_pps: false,
            spoofing_flags: ALL_PLAUSIBILITY_FLAGS,
        }
    }
}

/// A parameter out of its range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("monitor.{key} = {value}: {expected}")]
pub struct ParamError {
    /// The key, e.g. `"gnss_lost.raise_delay_s"`.
    pub key: String,
    /// The rejected value.
    pub value: f64,
    /// What is allowed.
    pub expected: &'static str,
}

impl MonitorParams {
    /// The timing of `rule`.
    pub fn timing(&self, rule: Rule) -> &RuleTiming {
        match rule {
            Rule::AttitudeMiscompare => &self.attitude_miscompare,
            Rule::UnitIsolated => &self.unit_isolated,
            Rule::UnitHealth => &self.unit_health,
            Rule::AttitudeInvalid => &self.attitude_invalid,
            Rule::InsNotTracking => &self.ins_not_tracking,
            Rule::GnssLost => &self.gnss_lost,
            Rule::ClockNotLocked => &self.clock_not_locked,
            Rule::DeviceSilent => &self.device_silent,
            Rule::DecodeErrors => &self.decode_errors,
            Rule::FeedSilent => &self.feed_silent,
            Rule::TrafficAlert => &self.traffic_alert,
            Rule::SuspectedSpoofing => &self.suspected_spoofing,
            Rule::CrossCheckUnavailable => &self.cross_check_unavailable,
            Rule::VerticalMiscompare => &self.vertical_miscompare,
            Rule::InertialMiscompare => &self.inertial_miscompare,
            Rule::HealthDisagreement => &self.health_disagreement,
            Rule::ClockDisagreement => &self.clock_disagreement,
            Rule::LineFull => &self.line_full,
        }
    }

    /// The timing of `rule`, mutable.
    pub fn timing_mut(&mut self, rule: Rule) -> &mut RuleTiming {
        match rule {
            Rule::AttitudeMiscompare => &mut self.attitude_miscompare,
            Rule::UnitIsolated => &mut self.unit_isolated,
            Rule::UnitHealth => &mut self.unit_health,
            Rule::AttitudeInvalid => &mut self.attitude_invalid,
            Rule::InsNotTracking => &mut self.ins_not_tracking,
            Rule::GnssLost => &mut self.gnss_lost,
            Rule::ClockNotLocked => &mut self.clock_not_locked,
            Rule::DeviceSilent => &mut self.device_silent,
            Rule::DecodeErrors => &mut self.decode_errors,
            Rule::FeedSilent => &mut self.feed_silent,
            Rule::TrafficAlert => &mut self.traffic_alert,
            Rule::SuspectedSpoofing => &mut self.suspected_spoofing,
            Rule::CrossCheckUnavailable => &mut self.cross_check_unavailable,
            Rule::VerticalMiscompare => &mut self.vertical_miscompare,
            Rule::InertialMiscompare => &mut self.inertial_miscompare,
            Rule::HealthDisagreement => &mut self.health_disagreement,
            Rule::ClockDisagreement => &mut self.clock_disagreement,
            Rule::LineFull => &mut self.line_full,
        }
    }

    /// Checks every value's range; the error names the first bad key.
    pub fn validate(&self) -> Result<(), ParamError> {
        let bad = |key: String, value: f64, expected| {
            Err(ParamError {
                key,
                value,
                expected,
            })
        };
        const SECONDS: &str = "expected a finite number of seconds >= 0";
        for rule in Rule::ALL {
            let t = self.timing(rule);
            for (what, v) in [
                ("raise_delay_s", t.raise_delay_s),
                ("clear_hysteresis_s", t.clear_hysteresis_s),
            ] {
                if !(v.is_finite() && v >= 0.0) {
                    return bad(format!("{}.{what}", rule.name()), v, SECONDS);
                }
            }
        }
        for (key, v) in [
            ("device_silent_s", self.device_silent_s),
            ("feed_silent_s", self.feed_silent_s),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(key.to_string(), v, SECONDS);
            }
        }
        if !(self.decode_window_s.is_finite() && self.decode_window_s > 0.0) {
            return bad(
                "decode_window_s".into(),
                self.decode_window_s,
                "expected a finite number of seconds > 0",
            );
        }
        if !(0.0..=1.0).contains(&self.decode_error_ratio_max) {
            return bad(
                "decode_error_ratio_max".into(),
                self.decode_error_ratio_max,
                "expected a fraction in 0..=1",
            );
        }
        Ok(())
    }
}

/// One-line meaning of each rule, for the commented example.
fn rule_doc(rule: Rule) -> &'static str {
    match rule {
        Rule::AttitudeMiscompare => "A pair of attitude units disagrees on an axis",
        Rule::UnitIsolated => "The cross-check isolated a unit",
        Rule::UnitHealth => "A unit reports a health problem (BAHRS: integrity risk)",
        Rule::AttitudeInvalid => "No usable voted attitude",
        Rule::InsNotTracking => "The VN-200 INS gives no valid attitude",
        Rule::GnssLost => "Ownship position not from the VN-200 INS",
        Rule::ClockNotLocked => "GPS-time clock not locked or holding over",
        Rule::DeviceSilent => "A device sends nothing valid",
        Rule::DecodeErrors => "Too many rejected frames from a device",
        Rule::FeedSilent => "A bus topic is not received",
        Rule::TrafficAlert => "A traffic target's DAA alert level",
        Rule::SuspectedSpoofing => "A traffic target fails plausibility tests",
        Rule::CrossCheckUnavailable => "An attitude unit is not cross-checked (and why)",
        Rule::VerticalMiscompare => "The BAHRS vertical channel disagrees with the VN-200",
        Rule::InertialMiscompare => "A BAHRS inertial signal disagrees with the VN-200 on one axis",
        Rule::HealthDisagreement => {
            "The BAHRS health or sync pulses contradict the VN-200 INS status"
        }
        Rule::ClockDisagreement => "A device's own clock disagrees with the host clock",
        Rule::LineFull => "A device sends about as much as its serial line carries",
    }
}

impl MonitorParams {
    /// A commented `[monitor]` section with every key at its default value (for `vigil config
    /// --example`); it parses back to [`MonitorParams::default`].
    pub fn example_toml() -> String {
        use core::fmt::Write as _;
        let d = Self::default();
        let mut s = String::from(
            "[monitor]\n\
             # Integrity monitor thresholds (every key optional; defaults shown).\n",
        );
        let _ = write!(
            s,
            "# A device whose last valid message is older is silent, s.\n\
             device_silent_s = {:?}\n\
             # A bus topic not received for longer is silent, s.\n\
             feed_silent_s = {:?}\n\
             # Window of the decode error count, s.\n\
             decode_window_s = {:?}\n\
             # Largest fraction of rejected frames (checksum + malformed) in a window, 0..1.\n\
             decode_error_ratio_max = {:?}\n\
             # Fewest frames for a window to be judged.\n\
             decode_min_frames = {}\n\
             # Raise an advisory when the clock has GPS time but no PPS lock.\n\
             clock_require_pps = {}\n\
             # PLAUSIBILITY_* bits that make a target suspect of spoofing (0x3F: all six).\n\
             spoofing_flags = {}\n",
            d.device_silent_s,
            d.feed_silent_s,
            d.decode_window_s,
            d.decode_error_ratio_max,
            d.decode_min_frames,
            d.clock_require_pps,
            d.spoofing_flags,
        );
        s.push_str(
            "# Per rule: enabled, raise_delay_s (condition must hold this long), \
             clear_hysteresis_s\n\
             # (must stay absent this long), latch (stay LATCHED until acknowledged).\n",
        );
        for rule in Rule::ALL {
            let t = d.timing(rule);
            let _ = write!(
                s,
                "\n[monitor.{}]\n# {}.\nenabled = {}\nraise_delay_s = {:?}\n\
                 clear_hysteresis_s = {:?}\nlatch = {}\n",
                rule.name(),
                rule_doc(rule),
                t.enabled,
                t.raise_delay_s,
                t.clear_hysteresis_s,
                t.latch
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<MonitorParams, toml::de::Error> {
        toml::from_str(text)
    }

    #[test]
    fn every_plausibility_flag_makes_a_target_suspect_by_default() {
        // The six PLAUSIBILITY_* bits of vigil-bus are 1 << 0 .. 1 << 5 (0x3F): each one alone
        // is in the default set, and nothing else is.
        for bit in 0..6 {
            assert_ne!(
                MonitorParams::default().spoofing_flags & (1 << bit),
                0,
                "plausibility bit {bit} would never raise suspected_spoofing"
            );
        }
        assert_eq!(ALL_PLAUSIBILITY_FLAGS, 0x3F);
        assert_eq!(PLAUSIBILITY_POSITION_DRIFT, 1 << 5);
        // And each has a name in the alert's reason.
        for bit in 0..6 {
            assert_eq!(
                crate::conditions::plausibility_names(1 << bit).len(),
                1,
                "bit {bit}"
            );
        }
    }

    #[test]
    fn silence_limits_must_be_finite_and_not_negative() {
        for text in [
            "device_silent_s = -1.0",
            "feed_silent_s = -0.5",
            "device_silent_s = inf",
            "feed_silent_s = nan",
        ] {
            let e = parse(text).unwrap().validate().unwrap_err();
            assert!(
                e.to_string().contains(text.split(' ').next().unwrap()),
                "{text}: {e}"
            );
        }
        parse("device_silent_s = 0.0").unwrap().validate().unwrap();
    }

    #[test]
    fn empty_table_gives_the_defaults() {
        assert_eq!(parse("").unwrap(), MonitorParams::default());
        MonitorParams::default().validate().unwrap();
    }

    #[test]
    fn a_partial_rule_table_keeps_that_rules_own_defaults() {
        let p = parse(
            "feed_silent_s = 5.0\n\
             [gnss_lost]\nlatch = true\n\
             [unit_isolated]\nraise_delay_s = 0.25\n",
        )
        .unwrap();
        assert_eq!(p.feed_silent_s, 5.0);
        // gnss_lost: latch changed; delay 1 s and hysteresis 2 s are gnss_lost's defaults.
        assert_eq!(
            p.gnss_lost,
            RuleTiming {
                enabled: true,
                raise_delay_s: 1.0,
                clear_hysteresis_s: 2.0,
                latch: true
            }
        );
        // unit_isolated: delay changed; its hysteresis stays 2 s.
        assert_eq!(p.unit_isolated.raise_delay_s, 0.25);
        assert_eq!(p.unit_isolated.clear_hysteresis_s, 2.0);
        // Untouched rules are the defaults.
        assert_eq!(p.clock_not_locked, RuleTiming::new(2.0, 2.0));
    }

    #[test]
    fn unknown_keys_are_rejected_with_their_name() {
        let e = parse("feed_silence_s = 1.0\n").unwrap_err().to_string();
        assert!(e.contains("feed_silence_s"), "{e}");
        let e = parse("[gnss_lost]\ndelay = 1.0\n").unwrap_err().to_string();
        assert!(e.contains("delay"), "{e}");
    }

    #[test]
    fn validate_names_the_bad_key() {
        let mut p = MonitorParams::default();
        p.gnss_lost.raise_delay_s = -1.0;
        let e = p.validate().unwrap_err();
        assert_eq!(e.key, "gnss_lost.raise_delay_s");
        assert!(
            e.to_string()
                .starts_with("monitor.gnss_lost.raise_delay_s = -1")
        );
        let p = MonitorParams {
            decode_error_ratio_max: 1.5,
            ..MonitorParams::default()
        };
        assert_eq!(p.validate().unwrap_err().key, "decode_error_ratio_max");
        let p = MonitorParams {
            decode_window_s: 0.0,
            ..MonitorParams::default()
        };
        assert_eq!(p.validate().unwrap_err().key, "decode_window_s");
    }

    #[test]
    fn the_commented_example_parses_back_to_the_defaults() {
        let text = MonitorParams::example_toml();
        let mut doc: toml::Table = toml::from_str(&text).unwrap();
        let section = doc.remove("monitor").expect("a [monitor] section");
        assert!(doc.is_empty());
        let p: MonitorParams = section.try_into().unwrap();
        assert_eq!(p, MonitorParams::default());
        // Every rule has its table, named as in the rule table.
        for rule in Rule::ALL {
            assert!(
                text.contains(&format!("[monitor.{}]", rule.name())),
                "{rule:?}"
            );
        }
    }

    #[test]
    fn serialises_to_toml_that_parses_back() {
        let mut p = MonitorParams::default();
        p.gnss_lost.latch = true;
        p.feed_silent_s = 3.5;
        let text = toml::to_string(&p).unwrap();
        assert_eq!(parse(&text).unwrap(), p);
    }

    #[test]
    fn seconds_convert_to_ns() {
        assert_eq!(secs_to_ns(1.5), 1_500_000_000);
        assert_eq!(secs_to_ns(-2.0), 0);
        assert_eq!(secs_to_ns(f64::NAN), 0);
        assert_eq!(secs_to_ns(1e300), i64::MAX);
    }
}
