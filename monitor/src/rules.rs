//! The rule table: every alert the monitor can raise, its code, subject and default severity, and
//! how a stable `alert_id` is built from them.
//!
//! `alert_id = (code << 24) | subject`, where `code` is the rule's 8-bit code and `subject` a
//! 24-bit value naming what the alert is about:
//!
//! | rule | code | subject |
//! |---|---|---|
//! | [`Rule::AttitudeMiscompare`] | `0x01` | axis: 0 roll, 1 pitch, 2 heading (`AXIS_*`) |
//! | [`Rule::UnitIsolated`] | `0x02` | unit: 0 BAHRS, 1 VN-200, 2 Watson (`UNIT_*`) |
//! | [`Rule::UnitHealth`] | `0x03` | unit (`UNIT_*`) |
//! | [`Rule::AttitudeInvalid`] | `0x04` | 0 |
//! | [`Rule::InsNotTracking`] | `0x05` | 0 |
//! | [`Rule::GnssLost`] | `0x06` | 0 |
//! | [`Rule::ClockNotLocked`] | `0x07` | 0 |
//! | [`Rule::DeviceSilent`] | `0x08` | `(device kind << 8) \| slot` (`DEVICE_*` code, index in `devices`) |
//! | [`Rule::DecodeErrors`] | `0x09` | `(device kind << 8) \| slot` |
//! | [`Rule::FeedSilent`] | `0x0A` | topic: 0 attitude, 1 ownship, 2 traffic, 3 integrity |
//! | [`Rule::CrossCheckUnavailable`] | `0x0B` | unit (`UNIT_*`) |
//! | [`Rule::VerticalMiscompare`] | `0x0C` | comparison: 0 down velocity, 1 height rate (`VERTICAL_*`) |
//! | [`Rule::InertialMiscompare`] | `0x0D` | signal: 0..2 specific force x/y/z, 3..5 angular rate x/y/z (`INERTIAL_*`) |
//! | [`Rule::HealthDisagreement`] | `0x0E` | combination (integrity `HEALTH_*` index): 0 BAHRS pulses without a VN-200 fix, 1 VN-200 fix without BAHRS pulses, 2 INS Tracking without a fix, 3 INS GnssLost with a fix |
//! | [`Rule::ClockDisagreement`] | `0x0F` | device: `DEVICE_*` code (0 BAHRS, 1 VN-200, 3 TT-Multi-RF) |
//! | [`Rule::TrafficAlert`] | `0x20 + t` | 24-bit target address |
//! | [`Rule::SuspectedSpoofing`] | `0x30 + t` | 24-bit target address |
//!
//! Code `0x0E` is reserved (`health_disagreement`, another change in flight).
//!
//! Per-target alerts: `t` is the target's `ADDRESS_*` type code when it is below 15 and 15
//! otherwise (so `ADDRESS_UNKNOWN` = 0xFF maps to 15). A 24-bit ICAO address and a non-ICAO or
//! TIS-B address with the same 24 bits are different aircraft; folding the address type into the
//! code keeps their alert ids apart. Example: a corrective traffic alert on ICAO `0xABCDEF` has
//! `alert_id = 0x20ABCDEF`, a spoofing suspicion on the same aircraft `0x30ABCDEF`.

use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION, SEVERITY_WARNING};

/// Mask of the subject bits of an `alert_id`.
pub const SUBJECT_MASK: u32 = 0x00FF_FFFF;

/// One alert rule.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Rule {
    /// A pair of attitude units disagrees on one axis (pair verdict FAIL after persistence).
    AttitudeMiscompare,
    /// The cross-check isolated one unit as faulty.
    UnitIsolated,
    /// A unit reports an internal health problem (`FAULT_HEALTH`); for the BAHRS this is its health
    /// code 10, "integrity risk": the unit declares its own output possibly misleading.
    UnitHealth,
    /// The voted attitude is not usable (`valid` = 0).
    AttitudeInvalid,
    /// The VN-200 INS gives no valid attitude (`FAULT_INVALID` on its unit: mode NotTracking or
    /// Aligning, or error bits).
    InsNotTracking,
    /// The ownship position is not from the VN-200 INS (advisory while the TT-Multi-RF GNSS
    /// fallback serves, caution with no valid position at all).
    GnssLost,
    /// The GPS-time clock is not locked (caution), or holding over (advisory).
    ClockNotLocked,
    /// A device sends nothing valid for longer than the limit, or its port is gone.
    DeviceSilent,
    /// A device's rejected frames (checksum failures and malformed) exceed the allowed fraction.
    DecodeErrors,
    /// A bus topic has not been received for longer than the limit.
    FeedSilent,
    /// A traffic target's DAA alert level (preventive, corrective, warning).
    TrafficAlert,
    /// A traffic target fails plausibility tests (suspected spoofing).
    SuspectedSpoofing,
    // --- issue 25 ---
    /// An attitude unit has not been cross-checked for longer than the raise delay (its
    /// `unit_coverage` is not `COVERAGE_COMPARED`); the reason names why (not aligned, not
    /// wired, stale, absent, invalid, ...).
    CrossCheckUnavailable,
    /// The BAHRS vertical channel (down velocity, pressure-height rate) disagrees with the
    /// VN-200's (comparison verdict FAIL after the fusion's persistence).
    VerticalMiscompare,
    /// A BAHRS inertial signal (specific force or angular rate on one body axis) disagrees with
    /// the VN-200's while both are usable (comparison verdict FAIL after persistence).
    InertialMiscompare,
    // --- issue 25 point 4 ---
    /// The BAHRS health and sync pulses and the VN-200 INS status contradict each other
    /// (integrity `health_checks[..].state == HEALTH_DISAGREE`; the combinations and the
    /// documents behind them are in `vigil_fusion::attitude::health`). Code 0x0F is kept for
    /// issue 18's `clock_disagreement`.
    HealthDisagreement,
    // --- issue 18 point 4 ---
    /// A device's own clock disagrees with the host clock beyond their combined sigmas (the
    /// integrity payload's `clock_disagreement` bit of its `DEVICE_*` code): its own time is not
    /// used, its samples are timed by another clock or not aligned.
    ClockDisagreement,
    /// A device's serial line is full (the integrity payload's `line_full` bit of its
    /// `DEVICE_*` code): it sends about as much as its baud rate carries, so its output waits in
    /// the device and, once the device's buffer is full, is lost there unseen by the host.
    LineFull,
}

impl Rule {
    /// Every rule, in evaluation order.
    pub const ALL: [Rule; 18] = [
        Rule::AttitudeMiscompare,
        Rule::UnitIsolated,
        Rule::UnitHealth,
        Rule::AttitudeInvalid,
        Rule::InsNotTracking,
        Rule::GnssLost,
        Rule::ClockNotLocked,
        Rule::DeviceSilent,
        Rule::DecodeErrors,
        Rule::FeedSilent,
        Rule::TrafficAlert,
        Rule::SuspectedSpoofing,
        Rule::CrossCheckUnavailable,
        Rule::VerticalMiscompare,
        Rule::InertialMiscompare,
        Rule::HealthDisagreement,
        Rule::ClockDisagreement,
        Rule::LineFull,
    ];

    /// The rule's base code (the top byte of its alert ids; per-target rules add the address
    /// type, 0..=15).
    pub const fn code(self) -> u8 {
        match self {
            Rule::AttitudeMiscompare => 0x01,
            Rule::UnitIsolated => 0x02,
            Rule::UnitHealth => 0x03,
            Rule::AttitudeInvalid => 0x04,
            Rule::InsNotTracking => 0x05,
            Rule::GnssLost => 0x06,
            Rule::ClockNotLocked => 0x07,
            Rule::DeviceSilent => 0x08,
            Rule::DecodeErrors => 0x09,
            Rule::FeedSilent => 0x0A,
            Rule::TrafficAlert => 0x20,
            Rule::SuspectedSpoofing => 0x30,
            Rule::CrossCheckUnavailable => 0x0B,
            Rule::VerticalMiscompare => 0x0C,
            Rule::InertialMiscompare => 0x0D,
            Rule::HealthDisagreement => 0x0E,
            Rule::ClockDisagreement => 0x0F,
            Rule::LineFull => 0x10,
        }
    }

    /// Short lower-case name, as used in the `[monitor]` configuration table and in logs.
    pub const fn name(self) -> &'static str {
        match self {
            Rule::AttitudeMiscompare => "attitude_miscompare",
            Rule::UnitIsolated => "unit_isolated",
            Rule::UnitHealth => "unit_health",
            Rule::AttitudeInvalid => "attitude_invalid",
            Rule::InsNotTracking => "ins_not_tracking",
            Rule::GnssLost => "gnss_lost",
            Rule::ClockNotLocked => "clock_not_locked",
            Rule::DeviceSilent => "device_silent",
            Rule::DecodeErrors => "decode_errors",
            Rule::FeedSilent => "feed_silent",
            Rule::TrafficAlert => "traffic_alert",
            Rule::SuspectedSpoofing => "suspected_spoofing",
            Rule::CrossCheckUnavailable => "cross_check_unavailable",
            Rule::VerticalMiscompare => "vertical_miscompare",
            Rule::InertialMiscompare => "inertial_miscompare",
            Rule::HealthDisagreement => "health_disagreement",
            Rule::ClockDisagreement => "clock_disagreement",
            Rule::LineFull => "line_full",
        }
    }

    /// The rule's usual severity (`SEVERITY_*`). Rules whose severity depends on the value
    /// ([`Rule::GnssLost`], [`Rule::ClockNotLocked`], [`Rule::TrafficAlert`]) give their highest.
    pub const fn severity(self) -> u8 {
        match self {
            Rule::AttitudeInvalid => SEVERITY_WARNING,
            Rule::TrafficAlert => SEVERITY_WARNING,
            Rule::DecodeErrors => SEVERITY_ADVISORY,
            _ => SEVERITY_CAUTION,
        }
    }

    /// The rule an `alert_id` belongs to, or `None` for an id no rule makes.
    pub const fn of_alert(alert_id: u32) -> Option<Rule> {
        let code = (alert_id >> 24) as u8;
        Some(match code {
            0x01 => Rule::AttitudeMiscompare,
            0x02 => Rule::UnitIsolated,
            0x03 => Rule::UnitHealth,
            0x04 => Rule::AttitudeInvalid,
            0x05 => Rule::InsNotTracking,
            0x06 => Rule::GnssLost,
            0x07 => Rule::ClockNotLocked,
            0x08 => Rule::DeviceSilent,
            0x09 => Rule::DecodeErrors,
            0x0A => Rule::FeedSilent,
            0x0B => Rule::CrossCheckUnavailable,
            0x0C => Rule::VerticalMiscompare,
            0x0D => Rule::InertialMiscompare,
            0x0E => Rule::HealthDisagreement,
            0x0F => Rule::ClockDisagreement,
            0x10 => Rule::LineFull,
            0x20..=0x2F => Rule::TrafficAlert,
            0x30..=0x3F => Rule::SuspectedSpoofing,
            _ => return None,
        })
    }

    /// The alert id of this rule about `subject` (only its low 24 bits are used).
    pub const fn alert_id(self, subject: u32) -> u32 {
        ((self.code() as u32) << 24) | (subject & SUBJECT_MASK)
    }
}

/// The alert id of a per-target rule ([`Rule::TrafficAlert`], [`Rule::SuspectedSpoofing`]) for a
/// target with `address` (24 bits used) and `ADDRESS_*` type `address_type`.
pub const fn target_alert_id(rule: Rule, address: u32, address_type: u8) -> u32 {
    let t = if address_type < 15 { address_type } else { 15 };
    (((rule.code() + t) as u32) << 24) | (address & SUBJECT_MASK)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_bus::payload::traffic::{ADDRESS_ICAO, ADDRESS_NON_ICAO, ADDRESS_UNKNOWN};

    #[test]
    fn each_rule_has_the_severity_of_the_documented_table() {
        use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION, SEVERITY_WARNING};
        // The crate documentation's rule table (lib.rs): warning for an invalid attitude and
        // traffic (its highest), advisory for decode errors, caution for every other rule.
        for rule in Rule::ALL {
            let want = match rule.name() {
                "attitude_invalid" | "traffic_alert" => SEVERITY_WARNING,
                "decode_errors" => SEVERITY_ADVISORY,
                _ => SEVERITY_CAUTION,
            };
            assert_eq!(rule.severity(), want, "{rule:?}");
        }
    }

    #[test]
    fn per_target_ids_keep_the_address_type_in_the_rule_code() {
        // Codes 0x20..=0x2F: TrafficAlert + address type, type 15 and above share 0x2F.
        let icao = target_alert_id(Rule::TrafficAlert, 0xAB_CDEF, ADDRESS_ICAO);
        assert_eq!(icao, 0x20AB_CDEF);
        assert_eq!(
            target_alert_id(Rule::TrafficAlert, 0xAB_CDEF, 1),
            0x21AB_CDEF
        );
        assert_eq!(target_alert_id(Rule::TrafficAlert, 1, 14), 0x2E00_0001);
        assert_eq!(target_alert_id(Rule::TrafficAlert, 1, 15), 0x2F00_0001);
        assert_eq!(
            target_alert_id(Rule::TrafficAlert, 1, ADDRESS_UNKNOWN),
            0x2F00_0001
        );
        // Only the low 24 bits of the address are kept.
        assert_eq!(
            target_alert_id(Rule::SuspectedSpoofing, 0xFF12_3456, 0),
            0x3012_3456
        );
        assert_eq!(Rule::DeviceSilent.alert_id(0xFF00_0003), 0x0800_0003);
    }

    #[test]
    fn alert_ids_round_trip_to_their_rule() {
        for rule in Rule::ALL {
            let id = rule.alert_id(0x12_3456);
            assert_eq!(id & SUBJECT_MASK, 0x12_3456);
            assert_eq!(Rule::of_alert(id), Some(rule), "{rule:?}");
        }
        assert_eq!(Rule::of_alert(0xFF00_0000), None);
        assert_eq!(Rule::of_alert(0), None);
    }

    #[test]
    fn target_ids_keep_address_types_apart() {
        // The documented examples.
        assert_eq!(
            target_alert_id(Rule::TrafficAlert, 0xABCDEF, ADDRESS_ICAO),
            0x20AB_CDEF
        );
        assert_eq!(
            target_alert_id(Rule::SuspectedSpoofing, 0xABCDEF, ADDRESS_ICAO),
            0x30AB_CDEF
        );
        // Same 24 bits, another address type: another id. Unknown (0xFF) maps to 15.
        assert_eq!(
            target_alert_id(Rule::TrafficAlert, 0xABCDEF, ADDRESS_NON_ICAO),
            0x21AB_CDEF
        );
        assert_eq!(
            target_alert_id(Rule::TrafficAlert, 0xABCDEF, ADDRESS_UNKNOWN),
            0x2FAB_CDEF
        );
        // Bits above 24 in the address field are ignored.
        assert_eq!(
            target_alert_id(Rule::TrafficAlert, 0xFFAB_CDEF, ADDRESS_ICAO),
            0x20AB_CDEF
        );
        assert_eq!(
            Rule::of_alert(0x2FAB_CDEF),
            Some(Rule::TrafficAlert),
            "unknown address type stays a traffic alert"
        );
    }
}
