//! The traffic picture: one track per aircraft across links and protocols, extrapolated to the
//! fusion time, with plausibility flags, DO-365 geometry against the ownship, live alert filtering
//! and priority order.
//!
//! - Merge: reports merge by address within one address space ([`track::AddressSpace`]): ICAO
//!   addresses from ADS-B, UAT, TIS-B/ADS-R and FLARM-with-ICAO-id are one aircraft; FLARM random
//!   and fixed ids, and non-ICAO addresses, stay apart. The freshest report per source is kept
//!   with its age; the freshest position, velocity and altitudes form the track's state.
//! - Capacity: bounded (default 1024). When a new target arrives at a full table, the victim is the
//!   track not updated for longest if that is older than `stale_evict_s`; otherwise the one
//!   farthest from the ownship. Every eviction is counted. Targets silent for `timeout_s` are
//!   dropped (counted too).
//! - Altitude: like with like. An intruder's barometric altitude is compared with the ownship's
//!   pressure altitude (BAHRS); only when the intruder has no barometric altitude is geometric
//!   compared with geometric. Each target says which was used.
//! - Plausibility: flagged on the target, never dropped (see [`track::Findings`]).

pub mod accuracy;
pub mod alert_filter;
mod manager;
pub mod plausibility;
pub mod policy;
pub mod track;

pub use manager::{
    AltitudeKind, Origins, Reported, Target, TrackManager, TrafficParams, TrafficStats,
};
