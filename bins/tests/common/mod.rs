//! Helpers shared by the `vigil` command-line tests.

// Each test binary uses some of them.
#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Output, Stdio};
use std::time::{Duration, Instant};

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

/// Kills the child process when dropped, so a test that fails early leaves none behind.
pub struct Guard(pub Child);

impl Drop for Guard {
    fn drop(&mut self) {
        if self.0.try_wait().ok().flatten().is_none() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// Starts `vigil sim --pty-dir DIR` on `scenario` for `seconds` with `seed`, and reads its four
/// port lines (all of them: the simulator stops when one cannot be written).
pub fn start_sim(dir: &Path, scenario: &str, seconds: &str, seed: &str) -> Child {
    let mut child = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args([
            "sim",
            "--scenario",
            scenario,
            "--duration",
            seconds,
            "--seed",
            seed,
        ])
        .arg("--pty-dir")
        .arg(dir)
        .stdout(Stdio::piped())
        .spawn()
        .expect("start vigil sim");
    let mut lines = BufReader::new(child.stdout.take().unwrap()).lines();
    for _ in 0..4 {
        lines.next().expect("port line").unwrap();
    }
    child
}

/// The `[bus]` prefix and the four `[[ports]]` of a `vigil run` configuration for the
/// simulator's terminals in `dir`.
pub fn run_config(prefix: &str, dir: &Path) -> String {
    let mut text = format!("[bus]\nprefix = \"{prefix}\"\n");
    for d in ["bahrs", "watson", "vn200", "ttmrf"] {
        text += &format!("[[ports]]\ndevice = \"{d}\"\npath = {:?}\n", dir.join(d));
    }
    text
}

/// Starts `vigil run --config CONFIG` (stdout discarded; stderr as given).
pub fn spawn_run(config: &Path, stderr: Stdio) -> Child {
    Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["run", "--config"])
        .arg(config)
        .stdout(Stdio::null())
        .stderr(stderr)
        .spawn()
        .expect("start vigil run")
}

/// Sends `signal` (`"TERM"`, `"INT"`, ...) to `child` with the `kill` program (no signal API
/// among the tests' dependencies).
pub fn signal(child: &Child, signal: &str) {
    let ok = Command::new("kill")
        .args([&format!("-{signal}"), &child.id().to_string()])
        .status()
        .expect("run kill");
    assert!(ok.success());
}

/// Waits for `child` to exit; kills it and fails the test after `limit`.
pub fn wait_exit(child: &mut Child, limit: Duration) -> ExitStatus {
    let start = Instant::now();
    loop {
        if let Some(s) = child.try_wait().unwrap() {
            return s;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            panic!("process did not exit within {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}
