//! Health cross-check (issue 25 point 4): what the BAHRS signal health and the VN-200 INS status
//! each imply, and which combinations contradict each other.
//!
//! # What each state implies
//!
//! | source | state | implies | document |
//! |---|---|---|---|
//! | BAHRS signal health (per signal of 0x01 and 0x02) | `00` unavailable | no value for this signal | BAHRS protocol 2.0, 2.4 |
//! | | `01` safe | the BAHRS's own fault detection is active and raises no alarm (or isolated it) | 2.4 |
//! | | `10` integrity risk | available, possibly misleading (detection inactive or isolation failed) | 2.4 |
//! | | `11` | not defined; never taken as safe | 2.4 (silent) |
//! | BAHRS 0x06 | a report arrives | a pulse reached the synchronisation input | 3.6 |
//! | VN-200 InsStatus mode | 0 NotTracking | outputs invalid | ICD Table 2.78 |
//! | | 1 Aligning | position and velocity valid, attitude not | Table 2.78 |
//! | | 2 Tracking | attitude, position and velocity valid | Table 2.78 |
//! | | 3 GnssLost | "an extended GNSS outage": attitude valid, position and velocity not | Table 2.78 |
//! | VN-200 InsStatus bit 2 GnssFix | set / clear | the GNSS has / has no valid fix | Table 2.77 |
//! | VN-200 InsStatus bit 6 GnssErr | set | GNSS communication error *or* no valid PPS | Table 2.77 |
//! | VN-200 SyncOut in GpsPps mode | | a pulse each GPS second "when a 3D fix is valid", none otherwise | Table 3.22 |
//!
//! # The combinations compared ([`HealthCombination`])
//!
//! | code | combination | disagrees when | document |
//! |---|---|---|---|
//! | 0 | [`HealthCombination::PpsWithoutFix`] | a BAHRS 0x06 arrives more than 0.5 s (the report's latency allowance) after the VN-200 reported its fix lost, while it still reports none | ICD Table 3.22 with BAHRS 3.6: no 3D fix, no pulse. A pulse then comes from somewhere else: a miswired sync input (another receiver's PPS), a VN-200 SyncOut not in GpsPps mode, or its `alwaysPpsPulse` legacy option (Table 3.44: pulses *before* a first fix) |
//! | 1 | [`HealthCombination::FixWithoutPps`] | the VN-200 has reported a fix for longer than `pulse_timeout_s`, the BAHRS is sending, had pulses before, and none came for `pulse_timeout_s` | Table 3.22: with a 3D fix a pulse comes every second; a BAHRS that stops receiving them has lost its sync wire or edge |
//! | 2 | [`HealthCombination::TrackingWithoutFix`] | INS mode Tracking (position and velocity valid) with no GNSS fix for longer than `extended_outage_s` | Table 2.78 says GnssLost follows "an extended outage" but not after how long (silent): the reading that fails safe is that a minute without a fix (the figure) is extended, so a Tracking claim past it contradicts the fix bit |
//! | 3 | [`HealthCombination::GnssLostWithFix`] | INS mode GnssLost while the fix bit has been set for longer than `extended_outage_s` | the reverse of 2; the ICD is silent on how fast the INS recovers from GnssLost, so the same limit |
//!
//! Decisions where the documents are silent or ambiguous:
//! - InsStatus GnssFix says "a valid fix", not "a 3D fix" (Table 2.77), and the default output
//!   has no GnssFix enumeration (Table 2.41). For combination 0 a clear bit means no 3D fix for
//!   sure (the pulse contradicts it); for combination 1 a set bit is taken as a 3D fix (a 2D-only
//!   fix held for seconds in flight is itself worth the caution: the reading that fails safe).
//! - GnssErr is either a communication error or a missing PPS (Table 2.77): it cannot say which,
//!   so it is published but does not make a disagreement.
//! - A BAHRS that never sent a 0x06 is not compared in combination 1 ([`NotCompared::NeverPulsed`]):
//!   an unwired sync input is a supported configuration (the host-clock fallback, point 3), and
//!   the data cannot tell it from a wire that was never connected.
//! - **Not a disagreement: BAHRS "safe" while the VN-200 reports GnssLost (the example), or
//!   the reverse.** The BAHRS protocol defines "safe" by the BAHRS's own fault detection and
//!   names no GNSS input (the unit is baro-inertial; its only link to the GNSS is the sync input,
//!   compared in 0 and 1); the VN-200's mode speaks of its own position and velocity. A healthy
//!   BAHRS through a true GNSS outage gives exactly this combination, so an alert there would be
//!   false on every long outage (which `gnss_lost` already reports); a BAHRS signal that is not
//!   safe is reported by `unit_health` and the coverage, whatever the VN-200 says.
//!
//! Unknown is never a disagreement: without a VN-200 status (none yet, or older than
//! `status_max_age_s`) or with a silent BAHRS, a combination is [`HealthVerdict::NotCompared`]
//! with its reason. The check is on the fusion's clock (the GPS time of the newest sample): a
//! 0x06 is timed by when it reached the fusion, not by the MCU time it names, so an unaligned
//! BAHRS (no PPS model) is compared too.

use serde::Serialize;
use vigil_drivers::bahrs::{InertialHealth, NavigationHealth};
use vigil_drivers::vn200::status::{InsMode, InsStatus};

const NS_PER_S: f64 = 1e9;
/// Allowance for a 0x06's report latency, ns: a pulse reported within this of the VN-200's first
/// no-fix status may have fired while the fix was still valid (the last legitimate one). The
/// BAHRS sends 0x06 right after the pulse (milliseconds; protocol 2.0 gives no figure); half the
/// 1 Hz GpsPps period (ICD Table 3.22) keeps the next pulse, a second later, well clear of it.
const PULSE_REPORT_GRACE_NS: i64 = 500_000_000;

/// Parameters of the health cross-check, with units and defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct HealthParams {
    /// With a fix, no pulse for this long is a missing pulse, s (range 1.5 .. 30, default 2.5:
    /// two 1 Hz pulses missed plus the report latency).
    pub pulse_timeout_s: f64,
    /// A VN-200 status older than this is unknown, s (range 0.1 .. 10, default 1).
    pub status_max_age_s: f64,
    /// A mode that contradicts the fix bit for longer than this disagrees, s (range 1 .. 3600,
    /// default 60: the "for a minute"; the ICD gives no figure).
    pub extended_outage_s: f64,
}

impl Default for HealthParams {
    fn default() -> Self {
        Self {
            pulse_timeout_s: 2.5,
            status_max_age_s: 1.0,
            extended_outage_s: 60.0,
        }
    }
}

impl HealthParams {
    /// `(name, value, min, max)` of every parameter, for the range check.
    pub(crate) fn ranges(&self) -> [(&'static str, f64, f64, f64); 3] {
        [
            ("health.pulse_timeout_s", self.pulse_timeout_s, 1.5, 30.0),
            ("health.status_max_age_s", self.status_max_age_s, 0.1, 10.0),
            (
                "health.extended_outage_s",
                self.extended_outage_s,
                1.0,
                3600.0,
            ),
        ]
    }
}

/// A combination of health states that is compared (codes as in the module table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HealthCombination {
    /// BAHRS sync pulses while the VN-200 has no fix.
    PpsWithoutFix = 0,
    /// VN-200 fix while the BAHRS gets no pulse.
    FixWithoutPps = 1,
    /// VN-200 INS Tracking without a fix for an extended time.
    TrackingWithoutFix = 2,
    /// VN-200 INS GnssLost with a fix for an extended time.
    GnssLostWithFix = 3,
}

impl HealthCombination {
    /// Every combination, in code order.
    pub const ALL: [HealthCombination; 4] = [
        HealthCombination::PpsWithoutFix,
        HealthCombination::FixWithoutPps,
        HealthCombination::TrackingWithoutFix,
        HealthCombination::GnssLostWithFix,
    ];
}

/// Why a combination was not compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NotCompared {
    /// No VN-200 InsStatus received yet.
    NoVn200Status,
    /// The newest VN-200 InsStatus is older than `status_max_age_s`.
    Vn200Stale,
    /// No BAHRS message within `pulse_timeout_s`: no pulse is no evidence.
    BahrsSilent,
    /// The BAHRS never reported a pulse (sync input not wired, or none yet).
    NeverPulsed,
}

/// The verdict on one combination.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HealthVerdict {
    /// The two states are consistent.
    Agree,
    /// They contradict each other; `since_ns` is the GPS time the contradiction began, ns.
    Disagree {
        /// GPS time the contradiction began, ns.
        since_ns: i64,
    },
    /// Not compared, and why.
    NotCompared(NotCompared),
}

/// The newest VN-200 status and since when its parts hold.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Vn200State {
    t_ns: i64,
    status: InsStatus,
    mode_since_ns: i64,
    fix_since_ns: i64,
}

/// The health cross-check state (see the module documentation).
#[derive(Debug, Clone, Default)]
pub struct HealthCheck {
    params: HealthParams,
    now_ns: Option<i64>,
    vn: Option<Vn200State>,
    last_bahrs_ns: Option<i64>,
    last_pulse_ns: Option<i64>,
    /// First pulse that contradicted the current no-fix period.
    pulse_without_fix_ns: Option<i64>,
    navigation: Option<NavigationHealth>,
    inertial: Option<InertialHealth>,
}

impl HealthCheck {
    /// A check with the given parameters.
    pub fn new(params: HealthParams) -> Self {
        Self {
            params,
            ..Self::default()
        }
    }

    /// The fusion's clock moved to `t_ns` (GPS time of a sample used, ns).
    pub fn observe_time(&mut self, t_ns: i64) {
        self.now_ns = Some(self.now_ns.map_or(t_ns, |n| n.max(t_ns)));
    }

    /// A VN-200 InsStatus at GPS time `t_ns`.
    pub fn vn200_status(&mut self, t_ns: i64, status: InsStatus) {
        self.observe_time(t_ns);
        let (mode_since_ns, fix_since_ns) = match self.vn {
            Some(v) => (
                if v.status.mode() == status.mode() {
                    v.mode_since_ns
                } else {
                    t_ns
                },
                if v.status.gnss_fix() == status.gnss_fix() {
                    v.fix_since_ns
                } else {
                    t_ns
                },
            ),
            None => (t_ns, t_ns),
        };
        if status.gnss_fix() {
            self.pulse_without_fix_ns = None;
        }
        self.vn = Some(Vn200State {
            t_ns,
            status,
            mode_since_ns,
            fix_since_ns,
        });
    }

    /// Any BAHRS message reached the fusion (aligned or not).
    pub fn bahrs_message(&mut self) {
        self.last_bahrs_ns = self.now_ns.or(self.last_bahrs_ns);
    }

    /// A BAHRS 0x06 (sync pulse report) reached the fusion (aligned or not).
    pub fn bahrs_pulse(&mut self) {
        self.bahrs_message();
        let Some(now) = self.now_ns else {
            return;
        };
        self.last_pulse_ns = Some(now);
        if let Some(v) = self.vn
            && !v.status.gnss_fix()
            && now > v.fix_since_ns.saturating_add(PULSE_REPORT_GRACE_NS)
            && self.pulse_without_fix_ns.is_none()
        {
            self.pulse_without_fix_ns = Some(now);
        }
    }

    /// The BAHRS navigation health (0x02) as received.
    pub fn bahrs_navigation(&mut self, h: NavigationHealth) {
        self.bahrs_message();
        self.navigation = Some(h);
    }

    /// The BAHRS inertial health (0x01) as received.
    pub fn bahrs_inertial(&mut self, h: InertialHealth) {
        self.bahrs_message();
        self.inertial = Some(h);
    }

    /// The newest BAHRS navigation health, if any.
    pub fn navigation_health(&self) -> Option<NavigationHealth> {
        self.navigation
    }

    /// The newest BAHRS inertial health, if any.
    pub fn inertial_health(&self) -> Option<InertialHealth> {
        self.inertial
    }

    /// The newest VN-200 InsStatus and its age at `now_ns` (s), if any.
    pub fn vn200(&self, now_ns: i64) -> Option<(InsStatus, f64)> {
        self.vn
            .map(|v| (v.status, (now_ns - v.t_ns).max(0) as f64 / NS_PER_S))
    }

    /// Time since the newest BAHRS pulse report at `now_ns`, s; `None` when none came.
    pub fn pulse_age_s(&self, now_ns: i64) -> Option<f64> {
        self.last_pulse_ns
            .map(|t| (now_ns - t).max(0) as f64 / NS_PER_S)
    }

    /// The verdict on every combination at GPS time `now_ns` (ns), in [`HealthCombination::ALL`]
    /// order.
    pub fn verdicts(&self, now_ns: i64) -> [HealthVerdict; 4] {
        HealthCombination::ALL.map(|c| self.verdict(c, now_ns))
    }

    /// The verdict on `c` at GPS time `now_ns` (ns).
    pub fn verdict(&self, c: HealthCombination, now_ns: i64) -> HealthVerdict {
        let secs = |s: f64| (s * NS_PER_S) as i64;
        let Some(v) = self.vn else {
            return HealthVerdict::NotCompared(NotCompared::NoVn200Status);
        };
        if now_ns - v.t_ns > secs(self.params.status_max_age_s) {
            return HealthVerdict::NotCompared(NotCompared::Vn200Stale);
        }
        let fix = v.status.gnss_fix();
        let timeout = secs(self.params.pulse_timeout_s);
        let extended = secs(self.params.extended_outage_s);
        let bahrs_alive = self.last_bahrs_ns.is_some_and(|t| now_ns - t <= timeout);
        let disagree_from = |since_ns: i64| {
            if now_ns >= since_ns {
                HealthVerdict::Disagree { since_ns }
            } else {
                HealthVerdict::Agree
            }
        };
        match c {
            HealthCombination::PpsWithoutFix => {
                if !bahrs_alive {
                    return HealthVerdict::NotCompared(NotCompared::BahrsSilent);
                }
                match (fix, self.pulse_without_fix_ns, self.last_pulse_ns) {
                    // The contradiction lasts while pulses keep coming.
                    (false, Some(first), Some(last)) if now_ns - last <= timeout => {
                        disagree_from(first)
                    }
                    _ => HealthVerdict::Agree,
                }
            }
            HealthCombination::FixWithoutPps => {
                if !bahrs_alive {
                    return HealthVerdict::NotCompared(NotCompared::BahrsSilent);
                }
                let Some(last) = self.last_pulse_ns else {
                    return HealthVerdict::NotCompared(NotCompared::NeverPulsed);
                };
                if !fix {
                    return HealthVerdict::Agree;
                }
                disagree_from(last.max(v.fix_since_ns).saturating_add(timeout))
            }
            HealthCombination::TrackingWithoutFix => {
                if v.status.mode() != InsMode::Tracking || fix {
                    return HealthVerdict::Agree;
                }
                disagree_from(v.mode_since_ns.max(v.fix_since_ns).saturating_add(extended))
            }
            HealthCombination::GnssLostWithFix => {
                if v.status.mode() != InsMode::GnssLost || !fix {
                    return HealthVerdict::Agree;
                }
                disagree_from(v.mode_since_ns.max(v.fix_since_ns).saturating_add(extended))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: i64 = 1_000_000_000;
    /// Tracking with a fix (ICD Table 2.77: mode 2 in bits 0-1, GnssFix bit 2).
    const TRACKING_FIX: InsStatus = InsStatus(0x0006);
    /// GnssLost (3), no fix, GnssErr (bit 6): what the VN-200 reports in an outage.
    const LOST_NO_FIX: InsStatus = InsStatus(0x0043);
    /// Tracking (2), no fix.
    const TRACKING_NO_FIX: InsStatus = InsStatus(0x0002);
    /// GnssLost (3) with the fix bit set.
    const LOST_FIX: InsStatus = InsStatus(0x0007);

    /// Runs `seconds` of 50 Hz VN-200 status `status(t)` and, each whole second where
    /// `pulse(t)`, a BAHRS 0x06 20 ms after the second, with a BAHRS 0x02 every 20 ms.
    fn fly(
        h: &mut HealthCheck,
        from_s: i64,
        to_s: i64,
        status: impl Fn(i64) -> InsStatus,
        pulse: impl Fn(i64) -> bool,
    ) {
        for k in from_s * 50..to_s * 50 {
            let t = k * S / 50;
            h.vn200_status(t, status(t));
            h.bahrs_navigation(NavigationHealth(0x155));
            if t % S == 20_000_000 && pulse(t) {
                h.bahrs_pulse();
            }
        }
    }

    fn disagree(v: HealthVerdict) -> Option<i64> {
        match v {
            HealthVerdict::Disagree { since_ns } => Some(since_ns),
            _ => None,
        }
    }

    #[test]
    fn nominal_flight_and_a_true_outage_agree_everywhere() {
        // A GNSS outage from 10 s to 80 s (longer than a minute, VN-200 in GnssLost at once, as
        // the simulator and Table 2.78 have it) in which the PPS stops too (Table 3.22).
        let outage = |t: i64| (10 * S..80 * S).contains(&t);
        let mut h = HealthCheck::new(HealthParams::default());
        for s in 0..100 {
            fly(
                &mut h,
                s,
                s + 1,
                |t| if outage(t) { LOST_NO_FIX } else { TRACKING_FIX },
                |t| !outage(t),
            );
            let now = (s + 1) * S - S / 50;
            assert!(
                h.verdicts(now).iter().all(|v| *v == HealthVerdict::Agree),
                "{s} s: {:?}",
                h.verdicts(now)
            );
        }
    }

    #[test]
    fn pulses_without_a_fix_disagree_from_the_first_pulse_a_period_after_the_loss() {
        // The fix is lost at 10 s but the pulses go on (a miswired sync input).
        let mut h = HealthCheck::new(HealthParams::default());
        let lost = |t: i64| t >= 10 * S;
        fly(
            &mut h,
            0,
            30,
            |t| if lost(t) { LOST_NO_FIX } else { TRACKING_FIX },
            |_| true,
        );
        // Status first seen clear at 10.00 s; the pulse reported at 10.02 s is within the 0.5 s
        // report allowance and not counted; the one at 11.02 s is the first contradiction.
        let now = 30 * S - S / 50;
        let v = h.verdict(HealthCombination::PpsWithoutFix, now);
        assert_eq!(disagree(v), Some(11 * S + 20_000_000), "{v:?}");
        // Fix back at 30 s: agreement at once.
        fly(&mut h, 30, 31, |_| TRACKING_FIX, |_| true);
        assert_eq!(
            h.verdict(HealthCombination::PpsWithoutFix, 31 * S - S / 50),
            HealthVerdict::Agree
        );
    }

    #[test]
    fn a_fix_without_pulses_disagrees_after_the_timeout_unless_never_wired() {
        let mut h = HealthCheck::new(HealthParams::default());
        // Never a pulse: not compared (an unwired sync input is supported).
        fly(&mut h, 0, 5, |_| TRACKING_FIX, |_| false);
        assert_eq!(
            h.verdict(HealthCombination::FixWithoutPps, 5 * S - S / 50),
            HealthVerdict::NotCompared(NotCompared::NeverPulsed)
        );
        // Pulses from 5 s to 10 s (last at 9.02 s), then none while the fix holds.
        fly(&mut h, 5, 10, |_| TRACKING_FIX, |_| true);
        fly(&mut h, 10, 20, |_| TRACKING_FIX, |_| false);
        let v = h.verdict(HealthCombination::FixWithoutPps, 20 * S - S / 50);
        assert_eq!(disagree(v), Some(9 * S + 20_000_000 + 2_500_000_000));
        // The BAHRS falls silent: no pulse is no evidence.
        assert_eq!(
            h.verdict(HealthCombination::FixWithoutPps, 20 * S + 3 * S),
            HealthVerdict::NotCompared(NotCompared::Vn200Stale)
        );
        let mut g = h.clone();
        for k in 0..200 {
            g.vn200_status(20 * S + k * S / 50, TRACKING_FIX);
        }
        assert_eq!(
            g.verdict(HealthCombination::FixWithoutPps, 24 * S - S / 50),
            HealthVerdict::NotCompared(NotCompared::BahrsSilent)
        );
    }

    #[test]
    fn ins_mode_against_the_fix_bit_after_the_extended_outage_time() {
        let p = HealthParams {
            extended_outage_s: 5.0,
            ..HealthParams::default()
        };
        let mut h = HealthCheck::new(p);
        fly(&mut h, 0, 2, |_| TRACKING_FIX, |_| true);
        // Tracking without a fix from 2 s: disagrees from 7 s.
        fly(&mut h, 2, 6, |_| TRACKING_NO_FIX, |_| false);
        let c = HealthCombination::TrackingWithoutFix;
        assert_eq!(h.verdict(c, 6 * S - S / 50), HealthVerdict::Agree);
        fly(&mut h, 6, 8, |_| TRACKING_NO_FIX, |_| false);
        assert_eq!(disagree(h.verdict(c, 8 * S - S / 50)), Some(7 * S));
        // GnssLost with the fix bit set from 8 s: disagrees from 13 s.
        fly(&mut h, 8, 14, |_| LOST_FIX, |_| true);
        let c = HealthCombination::GnssLostWithFix;
        assert_eq!(disagree(h.verdict(c, 14 * S - S / 50)), Some(13 * S));
        assert_eq!(
            h.verdict(HealthCombination::TrackingWithoutFix, 14 * S - S / 50),
            HealthVerdict::Agree
        );
    }

    #[test]
    fn unknown_is_never_a_disagreement() {
        let h = HealthCheck::new(HealthParams::default());
        assert!(
            h.verdicts(S)
                .iter()
                .all(|v| *v == HealthVerdict::NotCompared(NotCompared::NoVn200Status))
        );
    }

    #[test]
    fn defaults_are_in_range() {
        for (name, v, lo, hi) in HealthParams::default().ranges() {
            assert!((lo..=hi).contains(&v), "{name}");
        }
    }

    #[test]
    fn each_health_parameter_is_range_checked_at_its_documented_bounds() {
        use crate::attitude::params::CheckParams;
        // The ranges of the parameter docs: pulse_timeout_s 1.5 .. 30, status_max_age_s
        // 0.1 .. 10, extended_outage_s 1 .. 3600. Each bound is accepted, just outside is not,
        // and the error names the parameter.
        let set = |which: usize, v: f64| {
            let mut p = CheckParams::default();
            let h = &mut p.health;
            *[
                &mut h.pulse_timeout_s,
                &mut h.status_max_age_s,
                &mut h.extended_outage_s,
            ][which] = v;
            p.validate()
        };
        let table = [
            ("health.pulse_timeout_s", 1.5, 30.0),
            ("health.status_max_age_s", 0.1, 10.0),
            ("health.extended_outage_s", 1.0, 3600.0),
        ];
        for (i, (name, min, max)) in table.into_iter().enumerate() {
            assert_eq!(set(i, min), Ok(()), "{name}");
            assert_eq!(set(i, max), Ok(()), "{name}");
            for bad in [min * 0.99, max * 1.01, f64::NAN] {
                let e = set(i, bad).unwrap_err();
                assert_eq!((e.name, e.min, e.max), (name, min, max));
            }
        }
    }

    #[test]
    fn the_newest_reports_are_kept_with_their_ages() {
        let mut h = HealthCheck::new(HealthParams::default());
        assert_eq!((h.navigation_health(), h.inertial_health()), (None, None));
        assert_eq!((h.vn200(0), h.pulse_age_s(0)), (None, None));
        h.vn200_status(10 * S, TRACKING_FIX);
        h.bahrs_navigation(NavigationHealth(0x155));
        h.bahrs_inertial(InertialHealth(0x0fff));
        h.bahrs_pulse();
        // 2.5 s later: the status and the pulse (both at 10 s) are 2.5 s old.
        let now = 12 * S + S / 2;
        assert_eq!(h.vn200(now), Some((TRACKING_FIX, 2.5)));
        assert_eq!(h.pulse_age_s(now), Some(2.5));
        // Asked about an earlier time: age 0, never negative.
        assert_eq!(h.vn200(9 * S), Some((TRACKING_FIX, 0.0)));
        assert_eq!(h.navigation_health(), Some(NavigationHealth(0x155)));
        assert_eq!(h.inertial_health(), Some(InertialHealth(0x0fff)));
    }

    #[test]
    fn a_pulse_within_the_report_grace_of_the_fix_loss_is_not_a_contradiction() {
        // Fix lost at 10 s: a pulse reported exactly 500 ms later may have fired with the fix
        // still valid; one reported 1 ns after that is the first contradicting pulse.
        let mut h = HealthCheck::new(HealthParams::default());
        h.vn200_status(0, TRACKING_FIX);
        h.vn200_status(10 * S, LOST_NO_FIX);
        let grace_end = 10 * S + 500_000_000;
        h.observe_time(grace_end);
        h.bahrs_pulse();
        let c = HealthCombination::PpsWithoutFix;
        assert_eq!(h.verdict(c, grace_end), HealthVerdict::Agree);
        h.observe_time(grace_end + 1);
        h.bahrs_pulse();
        assert_eq!(disagree(h.verdict(c, grace_end + 1)), Some(grace_end + 1));
    }

    #[test]
    fn a_status_is_known_up_to_status_max_age_s_old() {
        // status_max_age_s = 1 s: a status exactly 1 s old is used, 1 s + 1 ns is unknown.
        let mut h = HealthCheck::new(HealthParams::default());
        h.vn200_status(0, TRACKING_FIX);
        let c = HealthCombination::TrackingWithoutFix;
        assert_eq!(h.verdict(c, S), HealthVerdict::Agree);
        assert_eq!(
            h.verdict(c, S + 1),
            HealthVerdict::NotCompared(NotCompared::Vn200Stale)
        );
    }

    #[test]
    fn pulses_without_a_fix_disagree_only_while_they_keep_coming() {
        // No fix from 10 s, one pulse at 11 s, then none; the BAHRS keeps talking (0x02) and the
        // VN-200 keeps reporting. pulse_timeout_s = 2.5 s: the contradiction holds until 13.5 s
        // and is over 1 ns later.
        let mut h = HealthCheck::new(HealthParams::default());
        h.vn200_status(0, TRACKING_FIX);
        h.vn200_status(10 * S, LOST_NO_FIX);
        h.observe_time(11 * S);
        h.bahrs_pulse();
        let c = HealthCombination::PpsWithoutFix;
        for (now, want) in [(13 * S + S / 2, Some(11 * S)), (13 * S + S / 2 + 1, None)] {
            h.vn200_status(now, LOST_NO_FIX);
            h.bahrs_navigation(NavigationHealth(0x155));
            let v = h.verdict(c, now);
            assert_eq!(disagree(v), want, "{v:?} at {now} ns");
            if want.is_none() {
                assert_eq!(v, HealthVerdict::Agree);
            }
        }
    }
}
