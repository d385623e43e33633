//! Rules with memory of their own: device silent and decode error rate (per device slot of the
//! integrity payload), and feed silent (per bus topic).
//!
//! Decode error rate: the integrity payload carries counters since start. The monitor keeps a
//! baseline per device and, once `decode_window_s` has passed since it, judges the window:
//! `errors = Δchecksum_failures + Δmalformed`, `frames = errors + Δmessages`, and the condition
//! holds when `frames >= decode_min_frames` and `errors / frames > decode_error_ratio_max`. The
//! verdict stands until the next window is judged (tumbling windows, so the window is the rule's
//! persistence). Decision: unknown message types are not errors (a device may send types vigil
//! does not decode, e.g. VN-200 outputs it did not configure) and skipped bytes are not frames;
//! both are already visible in the integrity payload. A counter that goes down (the publisher
//! restarted) starts a new baseline.
//!
//! Device silent: the link state says silent or disconnected, or the last valid message is older
//! than `device_silent_s`, or a device never heard from has existed for longer than that. A slot
//! whose name or device kind changes is a new device.

use vigil_bus::payload::integrity::{
    DEVICE_BAHRS, DEVICE_NAME_LEN, DEVICE_TTMRF, DEVICE_VN200, DEVICE_WATSON, DeviceIntegrity,
    IntegrityPayload, LINK_DISCONNECTED, LINK_SILENT, MAX_DEVICES,
};
use vigil_bus::payload::read_text;

use crate::conditions::Active;
use crate::lifecycle::Condition;
use crate::params::{MonitorParams, secs_to_ns};
use crate::rules::Rule;
use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION};

/// Display name of a `DEVICE_*` code.
pub fn device_kind_name(kind: u8) -> &'static str {
    match kind {
        DEVICE_BAHRS => "BAHRS",
        DEVICE_VN200 => "VN-200",
        DEVICE_WATSON => "Watson",
        DEVICE_TTMRF => "TT-Multi-RF",
        _ => "other",
    }
}

/// A window's verdict on the decode errors.
#[derive(Debug, Clone, Copy, PartialEq)]
struct ErrorWindow {
    errors: u64,
    frames: u64,
    window_s: f64,
}

/// What the monitor remembers of one device slot.
#[derive(Debug, Clone, Copy, PartialEq)]
struct DeviceTrack {
    name: [u8; DEVICE_NAME_LEN],
    kind: u8,
    first_seen_ns: i64,
    base_ns: i64,
    base_messages: u64,
    base_errors: u64,
    /// The last judged window, when its error fraction was over the limit.
    over: Option<ErrorWindow>,
}

fn errors_of(d: &DeviceIntegrity) -> u64 {
    d.checksum_failures.saturating_add(d.malformed)
}

impl DeviceTrack {
    fn new(d: &DeviceIntegrity, t_ns: i64) -> Self {
        Self {
            name: d.name,
            kind: d.device,
            first_seen_ns: t_ns,
            base_ns: t_ns,
            base_messages: d.messages,
            base_errors: errors_of(d),
            over: None,
        }
    }

    fn update(&mut self, d: &DeviceIntegrity, t_ns: i64, params: &MonitorParams) {
        let (messages, errors) = (d.messages, errors_of(d));
        if messages < self.base_messages || errors < self.base_errors {
            // Counters went back: the publisher restarted. Start again from here.
            self.base_ns = t_ns;
            self.base_messages = messages;
            self.base_errors = errors;
            self.over = None;
            return;
        }
        let elapsed_ns = t_ns.saturating_sub(self.base_ns);
        if elapsed_ns < secs_to_ns(params.decode_window_s) {
            return;
        }
        let d_err = errors - self.base_errors;
        let frames = d_err.saturating_add(messages - self.base_messages);
        let ratio = if frames == 0 {
            0.0
        } else {
            d_err as f64 / frames as f64
        };
        self.over = (frames >= params.decode_min_frames && ratio > params.decode_error_ratio_max)
            .then_some(ErrorWindow {
                errors: d_err,
                frames,
                window_s: elapsed_ns as f64 * 1e-9,
            });
        self.base_ns = t_ns;
        self.base_messages = messages;
        self.base_errors = errors;
    }
}

/// Device silent and decode error rate over the integrity payloads.
#[derive(Debug, Clone, Default)]
pub(crate) struct Devices {
    tracks: [Option<DeviceTrack>; MAX_DEVICES],
}

impl Devices {
    /// Takes the latest integrity payload at evaluation time `t_ns`.
    pub fn update(&mut self, p: &IntegrityPayload, t_ns: i64, params: &MonitorParams) {
        let devices = p.devices();
        for (slot, track) in self.tracks.iter_mut().enumerate() {
            let Some(d) = devices.get(slot) else {
                *track = None;
                continue;
            };
            match track {
                Some(tr) if tr.name == d.name && tr.kind == d.device => tr.update(d, t_ns, params),
                _ => *track = Some(DeviceTrack::new(d, t_ns)),
            }
        }
    }

    /// Pushes the device-silent and decode-error conditions holding at `t_ns`, judged on the
    /// latest integrity payload `p`.
    pub fn conditions(
        &self,
        p: &IntegrityPayload,
        t_ns: i64,
        params: &MonitorParams,
        out: &mut Active,
    ) {
        let limit_s = params.device_silent_s;
        for (slot, (d, track)) in p.devices().iter().zip(&self.tracks).enumerate() {
            let Some(track) = track else { continue };
            let subject = (u32::from(d.device) << 8) | slot as u32;
            let who = format!(
                "device {} ({})",
                read_text(&d.name),
                device_kind_name(d.device)
            );
            let age = d.last_message_age_s;
            let since_start_s = t_ns.saturating_sub(track.first_seen_ns) as f64 * 1e-9;
            let silent = if d.link_state == LINK_DISCONNECTED {
                Some(format!("{who} disconnected (reconnects {})", d.reconnects))
            } else if d.link_state == LINK_SILENT {
                Some(if age.is_nan() {
                    format!("{who} link silent: no message yet")
                } else {
                    format!("{who} link silent: last message {age:.1} s ago")
                })
            } else if age.is_finite() && age > limit_s {
                Some(format!(
                    "{who} silent: last message {age:.1} s ago (limit {limit_s:.1} s)"
                ))
            } else if age.is_nan() && since_start_s > limit_s {
                Some(format!(
                    "{who} silent: no message in {since_start_s:.1} s (limit {limit_s:.1} s)"
                ))
            } else {
                None
            };
            if let Some(reason) = silent
                && params.device_silent.enabled
            {
                out.push((
                    Rule::DeviceSilent.alert_id(subject),
                    Condition {
                        severity: SEVERITY_CAUTION,
                        reason,
                    },
                ));
            }
            if let Some(w) = track.over
                && params.decode_errors.enabled
            {
                out.push((
                    Rule::DecodeErrors.alert_id(subject),
                    Condition {
                        severity: SEVERITY_ADVISORY,
                        reason: format!(
                            "{who} decode errors: {} of {} frames rejected in {:.1} s ({:.1} %, \
                             limit {:.1} %)",
                            w.errors,
                            w.frames,
                            w.window_s,
                            100.0 * w.errors as f64 / w.frames as f64,
                            100.0 * params.decode_error_ratio_max
                        ),
                    },
                ));
            }
        }
    }
}

/// Index of a topic in the feed-silent rule's subjects.
pub const FEED_ATTITUDE: usize = 0;
/// Ownship topic index.
pub const FEED_OWNSHIP: usize = 1;
/// Traffic topic index.
pub const FEED_TRAFFIC: usize = 2;
/// Integrity topic index.
pub const FEED_INTEGRITY: usize = 3;
const FEED_NAMES: [&str; 4] = ["attitude", "ownship", "traffic", "integrity"];

/// When each topic was last received (in evaluation time).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Feeds {
    seen_since_poll: [bool; 4],
    last_seen_ns: [Option<i64>; 4],
}

impl Feeds {
    /// A payload of topic `feed` arrived.
    pub fn seen(&mut self, feed: usize) {
        if let Some(s) = self.seen_since_poll.get_mut(feed) {
            *s = true;
        }
    }

    /// Pushes the feed-silent conditions at `t_ns`; `start_ns` is the first evaluation.
    pub fn conditions(
        &mut self,
        t_ns: i64,
        start_ns: i64,
        params: &MonitorParams,
        out: &mut Active,
    ) {
        let limit_ns = secs_to_ns(params.feed_silent_s);
        for (feed, name) in FEED_NAMES.iter().enumerate() {
            if core::mem::take(&mut self.seen_since_poll[feed]) {
                self.last_seen_ns[feed] = Some(t_ns);
            }
            let since = self.last_seen_ns[feed].unwrap_or(start_ns);
            let silent_ns = t_ns.saturating_sub(since);
            if silent_ns <= limit_ns || !params.feed_silent.enabled {
                continue;
            }
            let what = if self.last_seen_ns[feed].is_some() {
                "for"
            } else {
                "since start,"
            };
            out.push((
                Rule::FeedSilent.alert_id(feed as u32),
                Condition {
                    severity: SEVERITY_CAUTION,
                    reason: format!(
                        "no {} payload {what} {:.1} s (limit {:.1} s)",
                        name,
                        silent_ns as f64 * 1e-9,
                        params.feed_silent_s
                    ),
                },
            ));
        }
    }
}
