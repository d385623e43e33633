//! `vigil/integrity`: per-device link state and decode counters, and the clock status.

use iceoryx2::prelude::ZeroCopySend;
use serde::Serialize;

use super::{Header, impl_payload, ser_text};
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

/// One device's link and decoder counters (counters since start; a consumer takes differences).
#[repr(C)]
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize)]
#[type_name("vigil.DeviceIntegrity.v1")]
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
#[type_name("vigil.Integrity.v1")]
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
        }
    }
}

impl IntegrityPayload {
    /// The valid device entries (count clamped to the capacity).
    pub fn devices(&self) -> &[DeviceIntegrity] {
        &self.devices[..(self.device_count as usize).min(MAX_DEVICES)]
    }
}

impl_payload!(IntegrityPayload, Topic::Integrity);
