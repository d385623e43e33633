//! `[realtime]`: the optional limit on the CPUs' wake-up latency while `vigil run` runs (its
//! request is made by `crate::runtime::realtime`).

use serde::{Deserialize, Serialize};

use super::error::ConfigError;

/// Largest accepted limit, us (10 s: beyond any idle state's exit latency).
pub const MAX_US: u32 = 10_000_000;

/// `[realtime]`: CPU wake-up latency while `vigil run` runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RealtimeSection {
    /// Limit on the CPUs' idle-state exit latency while running, us (`0`: the CPUs poll when
    /// idle); absent: no request (default).
    pub cpu_wakeup_latency_us: Option<u32>,
}

impl RealtimeSection {
    /// The commented `[realtime]` section of the example configuration, at the default.
    pub const EXAMPLE: &str = r#"[realtime]
# Limit on the CPUs' wake-up latency while vigil run runs, us, through Linux PM QoS
# (/dev/cpu_dma_latency, needs root): 0 keeps idle CPUs polling, so each serial read wakes the
# service sooner and cheaper, at the cost of power. Off when absent (the default).
# cpu_wakeup_latency_us = 0

"#;

    /// Checks the section (errors name the key).
    pub fn validate(&self) -> Result<(), ConfigError> {
        match self.cpu_wakeup_latency_us {
            Some(us) if us > MAX_US => Err(ConfigError {
                key: "realtime.cpu_wakeup_latency_us".into(),
                reason: format!("must be within 0 .. {MAX_US} us (got {us})"),
            }),
            _ => Ok(()),
        }
    }
}
