//! Helpers for vigil's end-to-end tests.
#![deny(missing_docs)]

use std::path::PathBuf;

pub use vigil_drivers::testkit::shared_data;

/// The repository root (the workspace directory).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}
