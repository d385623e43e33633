//! A recording through the service's path: every message on GPS time ([`aligned`]), the fused
//! picture and alerts as `vigil run` made them ([`fused`], [`rich`]), on the bus at the recorded
//! pace ([`publish`]), with the configuration the recording was made with ([`config`]).

pub mod aligned;
pub mod config;
pub mod fused;
#[cfg(target_os = "linux")]
pub mod publish;
pub mod rich;

use std::collections::BTreeMap;

use serde::Serialize;
use vigil_drivers::replay::PortSummary;

/// Summary of a replay (written to stderr as JSON).
#[derive(Debug, Serialize)]
pub struct ReplaySummary {
    /// Always "summary".
    pub kind: &'static str,
    /// MCAP messages read.
    pub mcap_messages: u64,
    /// Where reading stopped early (truncated or damaged file).
    pub damage: Option<String>,
    /// Per device: decoder counters, or chunks/bytes for devices without a decoder.
    pub devices: BTreeMap<String, PortSummary>,
}
