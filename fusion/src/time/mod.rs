//! Time alignment: every sample on one timebase, GPS time in nanoseconds, with a 1-sigma
//! uncertainty and the source of its time.
//!
//! Building blocks and the per-device aligners built from them (issue 7):
//! - [`gps`]: GPS time, UTC, the leap-second table with its validity date, and placing a UTC time
//!   of day (TT-Multi-RF `ts`, TS24h) on the right day;
//! - [`pps`]: a device clock disciplined by PPS pulses (the BAHRS MCU clock through 0x06), and
//!   the VN-200's PPS times that name each pulse's GPS second;
//! - [`host`]: the host clock model (lower envelope of receive time minus GPS time);
//! - [`bahrs`]: the BAHRS aligner built from them;
//! - [`mcu_host`]: the BAHRS MCU clock against host time (pulse naming, cross-check, fallback);
//! - [`seq`]: pairing data messages with their time messages by wrapping sequence counters;
//! - [`host_timed`]: transmission times at a baud rate, and samples placed by the host clock;
//! - [`vn200`]: the VN-200 aligner (native GPS time, its start-up clock while GNSS time is
//!   invalid, the host clock references and GPS - UTC);
//! - [`ttmrf`]: TT-Multi-RF JSON `ts`, raw TS24h / TS1s and host-timed outputs;
//! - [`cross_check`]: a device's own time (VN-200 GPS time, TT-Multi-RF `ts` / TS24h) against
//!   the host clock (issue 18 point 4);
//! - [`aligner`]: one deterministic object for every device, with per-device clock status.

pub mod aligner;
pub mod bahrs;
pub mod cross_check;
pub mod gps;
pub mod host;
pub mod host_timed;
pub mod line_load;
pub mod mcu_host;
pub mod pps;
pub mod seq;
#[cfg(test)]
mod testrng;
pub mod ttmrf;
pub mod vn200;

use serde::Serialize;

/// State of a device clock model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ClockStatus {
    /// No usable model: samples are not aligned.
    Unlocked,
    /// A model from too few references: times are given, with a wide uncertainty.
    Locking,
    /// A model from enough recent references.
    Locked,
    /// References stopped recently: times are extrapolated with a growing uncertainty.
    Coasting,
}

/// Where a sample's GPS time came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TimeSource {
    /// The device reports GPS time itself (VN-200 TimeGps).
    NativeGps,
    /// The device's own clock, disciplined by PPS pulses.
    PpsDisciplined,
    /// A UTC time of day from the device, placed on the right day.
    UtcTimeOfDay,
    /// The host receive time, mapped through the host-clock model.
    HostClock,
    /// The device's free-running clock (VN-200 TimeStartup), extrapolated from its last valid GPS
    /// time while the device says its GPS time is invalid.
    DeviceClock,
    // --- issue 18 / issue 25 point 3 ---
    /// The device's own clock (BAHRS MCU time) fitted to host time and mapped through the
    /// host-clock model: no usable synchronisation pulse (never wired, lost, GNSS outage, or
    /// pulses disagreeing with the host clock). Its sigma is the host clock's and more
    /// (about 1 ms); a cross-check widens its tolerance by it.
    DeviceClockViaHost,
}

/// Why a sample has no GPS time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum NotAligned {
    /// The device clock model is unlocked (no reference yet, or lost).
    ClockUnlocked,
    /// The sample's time message never arrived.
    NoTimeMessage,
    /// The sample lies outside the current clock epoch (e.g. from before a device reset).
    OutsideClockEpoch,
    /// The host clock model is not established.
    HostClockUnknown,
    /// The device flags its time invalid and no model of its clock exists yet.
    DeviceTimeInvalid,
    /// The device's time stamp is out of range (e.g. a time of day past 24 h).
    BadTimeStamp,
    /// The device's own time disagrees with the host clock beyond their combined sigmas
    /// ([`cross_check`], issue 18 point 4) and no other clock could place the sample.
    ClockDisagreement,
    /// The device's line is full and its own times came earlier than their arrival by more
    /// than the queue limit: its messages wait in its buffer longer than the limit (or its
    /// clock is wrong), so how long a message without a time of its own waited is unknown
    /// (TT-Multi-RF; [`line_load`]).
    LineFull,
}

/// How a message reached the host: the inputs of every receive-time computation.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rx {
    /// Host monotonic receive time of the read that delivered the message's LAST byte, ns.
    /// Decision: the issue speaks of the first byte, but a read returns a chunk only after its last
    /// byte arrived, so the time of the chunk holding the first byte is late by a random share of
    /// the chunk (up to 64 bytes: 67 ms at 9600 baud). A message ends at a line idle or at the end
    /// of a chunk; the read that completes it is its arrival, and subtracting its own transmission
    /// time ([`host_timed::tx_ns`]) gives the host time its first byte left the device (plus the
    /// link latency the host-clock model measures).
    pub host_ns: i64,
    /// Length of the message on the wire, bytes.
    pub wire_len: usize,
    /// How the host's reads split the message, where the reader knows it (`None`: unknown; a
    /// live port or replay gives it through [`host_timed::ChunkClock`]). Issue 18 point 1: the
    /// delay of a message's last read depends on whether earlier reads of the same message
    /// could hold it back.
    pub reads: Option<Reads>,
}

/// How the host's reads delivered one message (issue 18 point 1, link delay per port).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reads {
    /// Host monotonic time of the read holding the message's FIRST byte, ns.
    pub first_host_ns: i64,
    /// The message's bytes in that read (== `wire_len` when one read held all of it).
    pub first_bytes: usize,
    /// The message's bytes in the read holding its last byte.
    pub last_bytes: usize,
    /// The bytes that read returned after the message's last one (the start of the next
    /// message, on a line that sends them back to back): they took at least their line time
    /// after the message's end, so that read came at least that much after it
    /// ([`host_timed::first_byte_host_ns`]).
    pub after_bytes: usize,
}

impl Rx {
    /// A receive with no knowledge of how the reads split the message.
    pub fn new(host_ns: i64, wire_len: usize) -> Self {
        Self {
            host_ns,
            wire_len,
            reads: None,
        }
    }
}

/// A sample on the GPS timebase, or marked as not aligned (never silently dropped).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Aligned<T> {
    /// The sample.
    pub message: T,
    /// GPS time of the sample, ns since 1980-01-06, or why there is none.
    pub time: Result<AlignedTime, NotAligned>,
}

/// A GPS time with its uncertainty and provenance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AlignedTime {
    /// GPS time, ns since 1980-01-06 00:00:00 UTC.
    pub t_gps_ns: i64,
    /// 1-sigma uncertainty, ns.
    pub sigma_ns: f64,
    /// Where the time came from.
    pub source: TimeSource,
    /// State of the clock model when the time was given.
    pub status: ClockStatus,
}
