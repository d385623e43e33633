//! The error of a configuration value, shared by every section's validation.

/// A configuration value that failed validation, with its key.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{key}: {reason}")]
pub struct ConfigError {
    /// The offending key, e.g. `ports[2].baud`.
    pub key: String,
    /// What is wrong and what is allowed.
    pub reason: String,
}

/// A [`ConfigError`] for `key`.
pub(crate) fn invalid(key: impl Into<String>, reason: impl Into<String>) -> ConfigError {
    ConfigError {
        key: key.into(),
        reason: reason.into(),
    }
}
