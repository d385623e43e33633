//! Integrity rules over vigil's fused outputs and the alert life cycle (raise, persist, clear,
//! latch).
//!
//! The monitor reads the bus payloads (`vigil_bus::payload`) rather than fusion types, so the same
//! code runs inside `vigil run` (fed in-process with the payloads it publishes) and as the separate
//! process `vigil monitor` (fed by iceoryx2 subscribers). Its clock is the GPS time of the payloads
//! it is given ([`Monitor::poll`]): replaying the same inputs gives the same alerts.
//!
//! API contract (stable; the rules behind it are filled in by the service issue):
//! feed every payload as it is published, then call [`Monitor::poll`] with the current GPS time
//! and publish the [`AlertPayload`]s it returns (one per alert state change).
#![deny(missing_docs)]

use vigil_bus::payload::alerts::AlertPayload;
use vigil_bus::payload::attitude::AttitudePayload;
use vigil_bus::payload::integrity::IntegrityPayload;
use vigil_bus::payload::ownship::OwnshipPayload;
use vigil_bus::payload::traffic::TrafficPayload;

/// Thresholds and timings of every rule, with units and defaults.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MonitorParams {}

/// The integrity monitor: rule states and alert life cycles.
#[derive(Debug, Clone, Default)]
pub struct Monitor {
    params: MonitorParams,
}

impl Monitor {
    /// A monitor with the given parameters.
    pub fn new(params: MonitorParams) -> Self {
        Self { params }
    }

    /// The parameters in force.
    pub fn params(&self) -> &MonitorParams {
        &self.params
    }

    /// Takes a published attitude payload.
    pub fn attitude(&mut self, _p: &AttitudePayload) {}

    /// Takes a published ownship payload.
    pub fn ownship(&mut self, _p: &OwnshipPayload) {}

    /// Takes a published traffic payload.
    pub fn traffic(&mut self, _p: &TrafficPayload) {}

    /// Takes a published integrity payload.
    pub fn integrity(&mut self, _p: &IntegrityPayload) {}

    /// Evaluates every rule at GPS time `t_gps_ns` (ns); returns the alert state changes to
    /// publish, in a deterministic order.
    pub fn poll(&mut self, _t_gps_ns: i64) -> Vec<AlertPayload> {
        Vec::new()
    }
}
