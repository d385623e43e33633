//! `vigil/integrity`: per-device link state and decode counters, the clock status, and (issue
//! 25) the set of alerts active now, so a subscriber that starts late learns at once what is
//! raised or latched (`vigil/alerts` carries transitions only).
//!
//! Layout v3 (issue 25 point 4) appends the health cross-check: every BAHRS signal's 2-bit
//! health (`HEALTH_*` codes of [`super::attitude`]), the VN-200 INS status, the age of the newest
//! BAHRS sync pulse, and per compared combination ([`HEALTH_PPS_WITHOUT_FIX`] ..) whether the two
//! units' health agrees, disagrees, or was not compared and why. The rule table behind the
//! combinations (what each state implies, with the document references) is in
//! `vigil_fusion::attitude::health`.
//!
//! Layout v4 (issue 21 point 5) gives one byte of padding a meaning: `line_full`, the devices
//! whose serial line is full, so output the device itself queues and discards is said.

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use super::alerts::REASON_LEN;
use super::attitude::HEALTH_NONE;
use super::{Header, impl_payload, read_text, ser_text};
use crate::names::Topic;

/// Capacity of [`IntegrityPayload::devices`].
pub const MAX_DEVICES: usize = 8;
/// Length of a device name field, bytes.
pub const DEVICE_NAME_LEN: usize = 16;

/// Device kind: BAHRS baro-inertial AHRS.
pub const DEVICE_BAHRS: u8 = 0;
/// Device kind: VN-200 GNSS/INS.
pub const DEVICE_VN200: u8 = 1;
/// Device kind: Watson AHRS-E304.
pub const DEVICE_WATSON: u8 = 2;
/// Device kind: TT-Multi-RF traffic receiver.
pub const DEVICE_TTMRF: u8 = 3;
/// Device kind: other.
pub const DEVICE_OTHER: u8 = 0xFF;

/// Link state: not yet known (just started).
pub const LINK_UNKNOWN: u8 = 0;
/// Link state: port open and messages arriving.
pub const LINK_OK: u8 = 1;
/// Link state: port open but no valid message within the silence limit.
pub const LINK_SILENT: u8 = 2;
/// Link state: port closed or missing; reconnecting with backoff.
pub const LINK_DISCONNECTED: u8 = 3;

/// Clock status: not locked (host clock only).
pub const CLOCK_NOT_LOCKED: u8 = 0;
/// Clock status: GPS time known from messages, no PPS discipline.
pub const CLOCK_GPS_TIME: u8 = 1;
/// Clock status: PPS-disciplined and locked.
pub const CLOCK_PPS_LOCKED: u8 = 2;
/// Clock status: was locked, now holding over.
pub const CLOCK_HOLDOVER: u8 = 3;

// --- issue 25: the active alert set ---
/// Capacity of [`IntegrityPayload::active_alerts`].
pub const MAX_ACTIVE_ALERTS: usize = 32;

/// One alert raised or latched now (the state an [`super::alerts::AlertPayload`] transition
/// left it in).
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.ActiveAlert.v1")]
pub struct ActiveAlert {
    /// The alert's `alert_id` (as on `vigil/alerts`).
    pub alert_id: u32,
    /// `SEVERITY_*` code.
    pub severity: u8,
    /// `STATE_RAISED` or `STATE_LATCHED`.
    pub state: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 2],
    /// GPS time the alert was raised, ns.
    pub raised_gps_ns: i64,
    /// Reason of the newest evaluation that saw the condition, NUL-padded UTF-8.
    #[serde(serialize_with = "ser_text")]
    pub reason: [u8; REASON_LEN],
}

impl Default for ActiveAlert {
    fn default() -> Self {
        Self {
            alert_id: 0,
            severity: 0,
            state: 0,
            reserved: [0; 2],
            raised_gps_ns: 0,
            reason: [0; REASON_LEN],
        }
    }
}

impl ActiveAlert {
    /// The reason text.
    pub fn reason(&self) -> &str {
        read_text(&self.reason)
    }
}

// --- issue 25 point 4 (layout v3): the health cross-check ---
/// Number of entries in [`IntegrityPayload::health_checks`].
pub const HEALTH_CHECK_COUNT: usize = 4;
/// Combination: BAHRS sync pulses (0x06) while the VN-200 reports no GNSS fix (its SyncOut
/// GpsPps pulses only with a 3D fix: a miswired sync input or a VN-200 SyncOut not in GpsPps).
pub const HEALTH_PPS_WITHOUT_FIX: usize = 0;
/// Combination: the VN-200 reports a fix but the BAHRS, which had pulses before, gets none.
pub const HEALTH_FIX_WITHOUT_PPS: usize = 1;
/// Combination: VN-200 INS mode Tracking without a GNSS fix for longer than the extended-outage
/// time (60 s by default).
pub const HEALTH_TRACKING_WITHOUT_FIX: usize = 2;
/// Combination: VN-200 INS mode GnssLost with the fix bit set for longer than that time.
pub const HEALTH_GNSS_LOST_WITH_FIX: usize = 3;
/// [`HealthComparison::state`]: compared, consistent.
pub const HEALTH_AGREE: u8 = 0;
/// [`HealthComparison::state`]: compared, the two states contradict each other.
pub const HEALTH_DISAGREE: u8 = 1;
/// [`HealthComparison::state`]: not compared ([`HealthComparison::reason`] says why).
pub const HEALTH_NOT_COMPARED: u8 = 2;
/// [`HealthComparison::reason`]: none (compared).
pub const HEALTH_WHY_NONE: u8 = 0;
/// Not compared: no VN-200 INS status received yet.
pub const HEALTH_WHY_NO_VN200_STATUS: u8 = 1;
/// Not compared: the newest VN-200 INS status is too old.
pub const HEALTH_WHY_VN200_STALE: u8 = 2;
/// Not compared: no BAHRS message recently (a missing pulse is then no evidence).
pub const HEALTH_WHY_BAHRS_SILENT: u8 = 3;
/// Not compared: the BAHRS never reported a sync pulse (input not wired, or none yet).
pub const HEALTH_WHY_NEVER_PULSED: u8 = 4;
/// Not compared: no GPS time to judge at (the service has no clock yet).
pub const HEALTH_WHY_NO_CLOCK: u8 = 5;
/// [`IntegrityPayload::vn200_ins_mode`] / [`IntegrityPayload::vn200_gnss_fix`] when no VN-200
/// status was received.
pub const VN200_STATUS_NONE: u8 = 0xFF;

/// Lower-case name of a `HEALTH_*` combination index (as in the alert reasons).
pub fn health_check_name(i: usize) -> &'static str {
    match i {
        HEALTH_PPS_WITHOUT_FIX => "pps_without_fix",
        HEALTH_FIX_WITHOUT_PPS => "fix_without_pps",
        HEALTH_TRACKING_WITHOUT_FIX => "tracking_without_fix",
        HEALTH_GNSS_LOST_WITH_FIX => "gnss_lost_with_fix",
        _ => "unknown",
    }
}

/// Lower-case name of a `HEALTH_WHY_*` code.
pub fn health_why_name(code: u8) -> &'static str {
    match code {
        HEALTH_WHY_NONE => "none",
        HEALTH_WHY_NO_VN200_STATUS => "no_vn200_status",
        HEALTH_WHY_VN200_STALE => "vn200_stale",
        HEALTH_WHY_BAHRS_SILENT => "bahrs_silent",
        HEALTH_WHY_NEVER_PULSED => "never_pulsed",
        HEALTH_WHY_NO_CLOCK => "no_clock",
        _ => "unknown",
    }
}

/// The verdict on one health combination.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.HealthComparison.v1")]
pub struct HealthComparison {
    /// `HEALTH_AGREE`, `HEALTH_DISAGREE` or `HEALTH_NOT_COMPARED`.
    pub state: u8,
    /// `HEALTH_WHY_*` code when not compared, else `HEALTH_WHY_NONE`.
    pub reason: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 6],
    /// How long the disagreement has lasted at the report time, s; NaN unless `HEALTH_DISAGREE`.
    pub disagree_s: f64,
}

impl Default for HealthComparison {
    /// Not compared: no report.
    fn default() -> Self {
        Self {
            state: HEALTH_NOT_COMPARED,
            reason: HEALTH_WHY_NO_CLOCK,
            reserved: [0; 6],
            disagree_s: f64::NAN,
        }
    }
}

/// One device's link and decoder counters (counters since start; a consumer takes differences).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.DeviceIntegrity.v2")]
pub struct DeviceIntegrity {
    /// Device name as configured (e.g. the port role), NUL-padded UTF-8.
    #[serde(serialize_with = "ser_text")]
    pub name: [u8; DEVICE_NAME_LEN],
    /// `DEVICE_*` code.
    pub device: u8,
    /// `LINK_*` code.
    pub link_state: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 6],
    /// Time since the last valid message, s; NaN when none was ever received.
    pub last_message_age_s: f64,
    /// Bytes read from the port.
    pub bytes_received: u64,
    /// Bytes the decoder consumed.
    pub bytes_consumed: u64,
    /// Bytes skipped while resynchronising.
    pub bytes_skipped: u64,
    /// Messages decoded.
    pub messages: u64,
    /// Frames rejected by their checksum.
    pub checksum_failures: u64,
    /// Frames of unknown type.
    pub unknown_types: u64,
    /// Frames malformed (bad length or field).
    pub malformed: u64,
    /// Times the port was reopened.
    pub reconnects: u64,
    // --- issue 24 ---
    /// Records dropped alone for an impossible value (latitude beyond 90 deg, negative ground
    /// speed, altitude beyond 130 000 ft, ...), by the decoder or at the fusion's entry; their
    /// neighbours in the same message are kept.
    pub invalid_values: u64,
}

/// Integrity snapshot: every configured device and the clock.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Integrity.v4")]
#[serde(into = "IntegrityJson")]
pub struct IntegrityPayload {
    /// Common header.
    pub header: Header,
    /// Number of valid entries in `devices` (at most [`MAX_DEVICES`]).
    pub device_count: u32,
    /// `CLOCK_*` code.
    pub clock_status: u8,
    /// 1 when the GPS-UTC leap second count is known, 0 otherwise.
    pub leap_seconds_known: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 2],
    /// Estimated offset of the host clock from GPS time, s; NaN when unknown.
    pub clock_offset_s: f64,
    /// 1-sigma uncertainty of the clock offset, s; NaN when unknown.
    pub clock_sigma_s: f64,
    /// Devices; entries from `device_count` on are unspecified.
    pub devices: [DeviceIntegrity; MAX_DEVICES],
    // --- issue 18: clock cross-checks ---
    /// `clock_disagreement`: one bit per `DEVICE_*` code (`1 << code`) whose clock disagrees
    /// with another clock beyond their combined sigmas (e.g. the BAHRS PPS-named time against
    /// the host clock: a wrong edge or second). Its samples are then timed by the other clock
    /// (with that clock's wider sigma) or marked not aligned. 0: every checked clock agrees.
    pub clock_disagreement: u8,
    /// `line_full`: one bit per `DEVICE_*` code (`1 << code`) whose serial line has carried
    /// at least 80 % of its baud rate for at least the last 100 ms of host time: the device's
    /// output may be waiting in its own queue (its times are then widened by that wait) and,
    /// once its buffer is full, lost in the device, where the host cannot count it. Set today
    /// only for the TT-Multi-RF, whose output grows with the traffic it hears (the others send
    /// a fixed configured output, and their lines are not watched).
    /// 0: no line is full. Layout v4: the first byte of v3's `reserved_clock` (the type name
    /// changed with it, so a v3 subscriber never takes v4's bit for padding, nor a v4
    /// subscriber a v3 publisher's 0 for "no line full").
    ///
    /// Alert rule `line_full` (0x10).
    pub line_full: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved_clock: [u8; 6],
    // --- issue 25: the active alert set (the monitor inside `vigil run`) ---
    /// Number of valid entries in `active_alerts`.
    pub active_alert_count: u32,
    /// Alerts active in all; more than `active_alert_count` when the set did not fit (the most
    /// severe, then the oldest, are kept).
    pub active_alert_total: u32,
    /// The alerts raised or latched at `header.gps_time_ns`; entries from `active_alert_count`
    /// on are unspecified.
    pub active_alerts: [ActiveAlert; MAX_ACTIVE_ALERTS],
    // --- issue 25 point 4 (layout v3): signal health and the health cross-check ---
    /// BAHRS health (`HEALTH_*` of [`super::attitude`]: 0 unavailable, 1 safe, 2 integrity risk,
    /// 3 undefined; `HEALTH_NONE` 0xFF before the first message) of its 0x02 signals, in
    /// protocol order: pressure height, downward velocity, roll, pitch, magnetic heading.
    pub bahrs_navigation_health: [u8; 5],
    /// BAHRS health of its 0x01 signals: specific force x/y/z, angular rate x/y/z (the
    /// attitude payload's `INERTIAL_*` order); `HEALTH_NONE` before the first message.
    pub bahrs_inertial_health: [u8; 6],
    /// VN-200 INS mode (InsStatus bits 0-1: 0 NotTracking, 1 Aligning, 2 Tracking, 3 GnssLost);
    /// [`VN200_STATUS_NONE`] when no status was received.
    pub vn200_ins_mode: u8,
    /// VN-200 GNSS fix (InsStatus bit 2): 1 fix, 0 none; [`VN200_STATUS_NONE`] when unknown.
    pub vn200_gnss_fix: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved_health: [u8; 1],
    /// VN-200 InsStatus word as received (reserved bits kept); 0 when none (see
    /// `vn200_ins_mode`).
    pub vn200_ins_status: u16,
    /// Age of that status at `header.gps_time_ns`, s; NaN when none.
    pub vn200_status_age_s: f64,
    /// Time since the newest BAHRS sync pulse report (0x06) reached the fusion, s; NaN when none
    /// came.
    pub bahrs_pulse_age_s: f64,
    /// The health cross-check, per combination (`HEALTH_*` index): agree, disagree (and for how
    /// long) or not compared (and why).
    pub health_checks: [HealthComparison; HEALTH_CHECK_COUNT],
}

impl Default for IntegrityPayload {
    /// No device, clock unknown, no active alert, no health known.
    fn default() -> Self {
        Self {
            header: Header::default(),
            device_count: 0,
            clock_status: 0,
            leap_seconds_known: 0,
            reserved: [0; 2],
            clock_offset_s: 0.0,
            clock_sigma_s: 0.0,
            devices: [DeviceIntegrity::default(); MAX_DEVICES],
            clock_disagreement: 0,
            line_full: 0,
            reserved_clock: [0; 6],
            active_alert_count: 0,
            active_alert_total: 0,
            active_alerts: [ActiveAlert::default(); MAX_ACTIVE_ALERTS],
            bahrs_navigation_health: [HEALTH_NONE; 5],
            bahrs_inertial_health: [HEALTH_NONE; 6],
            vn200_ins_mode: VN200_STATUS_NONE,
            vn200_gnss_fix: VN200_STATUS_NONE,
            reserved_health: [0; 1],
            vn200_ins_status: 0,
            vn200_status_age_s: f64::NAN,
            bahrs_pulse_age_s: f64::NAN,
            health_checks: [HealthComparison::default(); HEALTH_CHECK_COUNT],
        }
    }
}

/// JSON form of [`IntegrityPayload`]: only the valid device entries.
#[derive(Serialize)]
struct IntegrityJson {
    header: Header,
    device_count: u32,
    clock_status: u8,
    leap_seconds_known: u8,
    clock_offset_s: f64,
    clock_sigma_s: f64,
    devices: Vec<DeviceIntegrity>,
    clock_disagreement: u8,
    line_full: u8,
    active_alert_count: u32,
    active_alert_total: u32,
    active_alerts: Vec<ActiveAlert>,
    bahrs_navigation_health: [u8; 5],
    bahrs_inertial_health: [u8; 6],
    vn200_ins_mode: u8,
    vn200_gnss_fix: u8,
    vn200_ins_status: u16,
    vn200_status_age_s: f64,
    bahrs_pulse_age_s: f64,
    health_checks: [HealthComparison; HEALTH_CHECK_COUNT],
}

impl From<IntegrityPayload> for IntegrityJson {
    fn from(p: IntegrityPayload) -> Self {
        Self {
            header: p.header,
            device_count: p.device_count,
            clock_status: p.clock_status,
            leap_seconds_known: p.leap_seconds_known,
            clock_offset_s: p.clock_offset_s,
            clock_sigma_s: p.clock_sigma_s,
            devices: p.devices().to_vec(),
            clock_disagreement: p.clock_disagreement,
            line_full: p.line_full,
            active_alert_count: p.active_alert_count,
            active_alert_total: p.active_alert_total,
            active_alerts: p.active_alerts().to_vec(),
            bahrs_navigation_health: p.bahrs_navigation_health,
            bahrs_inertial_health: p.bahrs_inertial_health,
            vn200_ins_mode: p.vn200_ins_mode,
            vn200_gnss_fix: p.vn200_gnss_fix,
            vn200_ins_status: p.vn200_ins_status,
            vn200_status_age_s: p.vn200_status_age_s,
            bahrs_pulse_age_s: p.bahrs_pulse_age_s,
            health_checks: p.health_checks,
        }
    }
}

impl IntegrityPayload {
    /// The valid device entries (count clamped to the capacity).
    pub fn devices(&self) -> &[DeviceIntegrity] {
        &self.devices[..(self.device_count as usize).min(MAX_DEVICES)]
    }

    /// The valid active-alert entries (count clamped to the capacity).
    pub fn active_alerts(&self) -> &[ActiveAlert] {
        &self.active_alerts[..(self.active_alert_count as usize).min(MAX_ACTIVE_ALERTS)]
    }
}

impl_payload!(IntegrityPayload, Topic::Integrity);
