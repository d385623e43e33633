//! `[live_view]`: the optional Foxglove live view of `vigil run` (its runtime is
//! `crate::outputs::live_view`).

use serde::{Deserialize, Serialize};

use super::error::ConfigError;

/// Default TCP port of the WebSocket server (the Foxglove tools' usual port).
pub const DEFAULT_PORT: u16 = 8765;

/// True when this build carries the live view (cargo feature `foxglove`).
pub const AVAILABLE: bool = cfg!(feature = "foxglove");

/// `[live_view]`: the Foxglove WebSocket live view (needs a build with `--features foxglove`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LiveViewSection {
    /// Start the view's WebSocket server (bound to 127.0.0.1 only).
    pub enabled: bool,
    /// Its TCP port, 1 to 65535.
    pub port: u32,
}

impl Default for LiveViewSection {
    fn default() -> Self {
        Self {
            enabled: false,
            port: u32::from(DEFAULT_PORT),
        }
    }
}

impl LiveViewSection {
    /// The commented `[live_view]` section of the example configuration, at the defaults.
    pub const EXAMPLE: &str = r#"[live_view]
# Live view for Foxglove or Lichtblick: a WebSocket server on ws://127.0.0.1:PORT (localhost
# only) showing ownship, traffic, alerts and attitude. Needs a build with
# `--features foxglove`; enabled = true in a build without it is refused at start.
enabled = false
port = 8765

"#;

    /// Checks the section (errors name the key); `available` is whether the build carries the
    /// view ([`AVAILABLE`]; a parameter so both builds' behaviour is testable in either).
    pub fn validate(&self, available: bool) -> Result<(), ConfigError> {
        if self.port == 0 || self.port > u32::from(u16::MAX) {
            return Err(ConfigError {
                key: "live_view.port".into(),
                reason: format!("must be a TCP port, 1 to 65535 (got {})", self.port),
            });
        }
        if self.enabled && !available {
            return Err(ConfigError {
                key: "live_view.enabled".into(),
                reason: "this vigil was built without the live view; rebuild with \
                         `cargo build --release --features foxglove`, or set it to false"
                    .into(),
            });
        }
        Ok(())
    }

    /// The port as a TCP port (a validated section's port always fits; an invalid one gives 0).
    pub fn tcp_port(&self) -> u16 {
        u16::try_from(self.port).unwrap_or(0)
    }
}
