//! `vigil/alerts`: alert events (one sample per state change of one alert).
//!
//! Unlike the state topics, alerts are events: the service never overwrites an unread alert (see
//! [`crate::policy`]); a subscriber that still falls behind sees a gap in `header.seq`, and the
//! publisher counts the failed delivery.

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use super::{Header, impl_payload, ser_text, write_text};
use crate::names::Topic;

/// Length of the reason field, bytes.
pub const REASON_LEN: usize = 160;

/// Severity: advisory (awareness, no action needed).
pub const SEVERITY_ADVISORY: u8 = 0;
/// Severity: caution (action may be needed).
pub const SEVERITY_CAUTION: u8 = 1;
/// Severity: warning (immediate action).
pub const SEVERITY_WARNING: u8 = 2;

/// Transition: the alert condition held for its raise delay; the alert is active.
pub const STATE_RAISED: u8 = 0;
/// Transition: the condition cleared (after hysteresis); the alert is inactive.
pub const STATE_CLEARED: u8 = 1;
/// Transition: the condition cleared but the alert latches until acknowledged.
pub const STATE_LATCHED: u8 = 2;

/// One alert state change.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.Alert.v1")]
pub struct AlertPayload {
    /// Common header; `gps_time_ns` is the time of the transition.
    pub header: Header,
    /// Stable identifier of the alert rule (the monitor's rule table index or code).
    pub alert_id: u32,
    /// `SEVERITY_*` code.
    pub severity: u8,
    /// `STATE_*` code.
    pub state: u8,
    /// Explicit padding; always 0.
    #[serde(skip)]
    pub reserved: [u8; 2],
    /// GPS time the alert was first raised, ns (equal to `header.gps_time_ns` on a raise).
    pub raised_gps_ns: i64,
    /// Human-readable reason, NUL-padded UTF-8.
    #[serde(serialize_with = "ser_text")]
    pub reason: [u8; REASON_LEN],
}

impl Default for AlertPayload {
    fn default() -> Self {
        Self {
            header: Header::default(),
            alert_id: 0,
            severity: SEVERITY_ADVISORY,
            state: STATE_RAISED,
            reserved: [0; 2],
            raised_gps_ns: 0,
            reason: [0; REASON_LEN],
        }
    }
}

impl AlertPayload {
    /// Sets the reason text (truncated to [`REASON_LEN`] bytes at a character boundary).
    pub fn set_reason(&mut self, text: &str) {
        write_text(&mut self.reason, text);
    }

    /// The reason text.
    pub fn reason(&self) -> &str {
        super::read_text(&self.reason)
    }
}

impl_payload!(AlertPayload, Topic::Alerts);
