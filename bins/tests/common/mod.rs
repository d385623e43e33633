//! Helpers shared by the `vigil` command-line tests.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Runs the `vigil` binary under test with `args`.
pub fn vigil(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(args)
        .output()
        .expect("run vigil")
}

/// A path for a test's file under cargo's per-target temporary directory, in a folder of the
/// test's own (`group`), so test files running in parallel do not collide.
pub fn tmp(group: &str, name: &str) -> PathBuf {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(group);
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}
