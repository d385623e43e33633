//! Time alignment: every sample on one timebase, GPS time in nanoseconds, with a 1-sigma
//! uncertainty and the source of its time.
//!
//! Building blocks (the per-device aligners that use them arrive with the time-alignment issue):
//! - [`gps`]: GPS time, UTC, the leap-second table with its validity date, and placing a UTC time
//!   of day (TT-Multi-RF `ts`, TS24h) on the right day;
//! - [`pps`]: a device clock disciplined by PPS pulses (the BAHRS MCU clock through 0x06);
//! - [`host`]: the host clock model (lower envelope of receive time minus GPS time);
//! - [`bahrs`]: the BAHRS aligner built from them;
//! - [`seq`]: pairing data messages with their time messages by wrapping sequence counters.

pub mod bahrs;
pub mod gps;
pub mod host;
pub mod pps;
pub mod seq;
#[cfg(test)]
mod testrng;

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
