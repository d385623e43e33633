//! `vigil/integrity`: per-device link state and decode counters, the clock status, and (issue
//! 25) the set of alerts active now, so a subscriber that starts late learns at once what is
//! raised or latched (`vigil/alerts` carries transitions only).

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use super::alerts::REASON_LEN;
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
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Integrity.v2")]
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
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved_clock: [u8; 7],
    // --- issue 25: the active alert set (the monitor inside `vigil run`) ---
    /// Number of valid entries in `active_alerts`.
    pub active_alert_count: u32,
    /// Alerts active in all; more than `active_alert_count` when the set did not fit (the most
    /// severe, then the oldest, are kept).
    pub active_alert_total: u32,
    /// The alerts raised or latched at `header.gps_time_ns`; entries from `active_alert_count`
    /// on are unspecified.
    pub active_alerts: [ActiveAlert; MAX_ACTIVE_ALERTS],
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
    active_alert_count: u32,
    active_alert_total: u32,
    active_alerts: Vec<ActiveAlert>,
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
            active_alert_count: p.active_alert_count,
            active_alert_total: p.active_alert_total,
            active_alerts: p.active_alerts().to_vec(),
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
