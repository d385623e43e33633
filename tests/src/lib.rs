//! Helpers for vigil's end-to-end tests (`tests/tests/*.rs`): a simulated flight through the
//! service ([`sim_drive`]) or through alignment and fusion alone ([`fuse`]).
#![deny(missing_docs)]

use std::path::PathBuf;

pub mod fuse;
pub mod sim_drive;

pub use vigil_drivers::testkit::shared_data;

/// The repository root (the workspace directory).
pub fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..")
}
