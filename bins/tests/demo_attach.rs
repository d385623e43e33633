//! Issue 26: `vigil demo` as a person meets it. It prints the command that attaches a second
//! terminal, and that command receives traffic. A SIGKILLed demo leaves nothing behind once the
//! next vigil has started: its children get SIGTERM when it dies (and shut down cleanly), its
//! temporary directory is swept, and its bus services are gone.
#![cfg(target_os = "linux")]

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use vigil_bus::{Bus, BusConfig};

/// The PIDs of the processes whose parent is `pid` (from /proc/*/stat).
fn children_of(pid: u32) -> Vec<u32> {
    let mut out = Vec::new();
    for e in std::fs::read_dir("/proc").unwrap().flatten() {
        let Some(child) = e.file_name().to_str().and_then(|n| n.parse::<u32>().ok()) else {
            continue;
        };
        let Ok(stat) = std::fs::read_to_string(e.path().join("stat")) else {
            continue;
        };
        // "PID (COMM) STATE PPID ...": COMM may hold spaces, so split after its closing ')'.
        let ppid = stat
            .rsplit_once(')')
            .and_then(|(_, rest)| rest.split_whitespace().nth(1))
            .and_then(|p| p.parse::<u32>().ok());
        if ppid == Some(pid) {
            out.push(child);
        }
    }
    out
}

fn alive(pid: u32) -> bool {
    // A zombie (exited, not yet reaped by init) counts as gone.
    std::fs::read_to_string(format!("/proc/{pid}/stat")).is_ok_and(|s| {
        s.rsplit_once(')')
            .is_some_and(|(_, r)| !r.trim_start().starts_with('Z'))
    })
}

#[test]
fn a_second_terminal_attaches_and_a_killed_demo_leaves_nothing() {
    let vigil = env!("CARGO_BIN_EXE_vigil");
    let mut demo = Command::new(vigil)
        .args(["demo", "--duration", "120"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let demo_pid = demo.id();
    let mut lines = BufReader::new(demo.stdout.take().unwrap()).lines();
    // The first line names the command to attach with.
    let first = lines.next().expect("a first line").unwrap();
    let command = first
        .split_once("attach from another terminal: ")
        .map(|(_, c)| c.split("   ").next().unwrap().to_string())
        .unwrap_or_else(|| panic!("no attach command in {first:?}"));
    let prefix = format!("demo{demo_pid}");
    assert_eq!(command, format!("vigil listen traffic --prefix {prefix}"));
    // Keep reading the demo's view so it never blocks on a full pipe.
    std::thread::spawn(move || for _ in lines.by_ref() {});

    // The printed command, as a person would type it, receives traffic.
    let args: Vec<&str> = command.split_whitespace().skip(1).collect();
    let out = Command::new(vigil)
        .args(&args)
        .args(["--count", "1", "--duration", "60"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    let line: serde_json::Value =
        serde_json::from_str(text.lines().next().expect("a traffic line")).unwrap();
    assert_eq!(line["topic"], "traffic");

    let children = children_of(demo_pid);
    assert_eq!(children.len(), 2, "vigil sim and vigil run: {children:?}");
    let dir = std::env::temp_dir().join(format!("vigil-demo-{demo_pid}"));
    assert!(dir.exists());

    demo.kill().unwrap(); // SIGKILL: no handler runs, no Drop.
    demo.wait().unwrap();
    let until = Instant::now() + Duration::from_secs(15);
    while children.iter().any(|&c| alive(c)) && Instant::now() < until {
        std::thread::sleep(Duration::from_millis(100));
    }
    let left: Vec<u32> = children.iter().copied().filter(|&c| alive(c)).collect();
    assert!(left.is_empty(), "children still running: {left:?}");

    // The next vigil (any command) sweeps the directory; its bus node reclaims the dead
    // demo's bus resources.
    let next = Command::new(vigil)
        .args(["listen", "alerts", "--duration", "0.1", "--prefix", &prefix])
        .output()
        .unwrap();
    assert!(next.status.success());
    assert!(!dir.exists(), "{} left behind", dir.display());
    let bus = Bus::new(&BusConfig {
        node_name: "demo-attach-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let prefixes = bus.prefixes_in_use().unwrap();
    assert!(
        !prefixes.contains(&prefix),
        "services under {prefix} remain: {prefixes:?}"
    );
}
