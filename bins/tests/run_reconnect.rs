//! `vigil run` survives a port that disappears: a Watson on a pseudo-terminal created here,
//! reached through a symbolic link; the terminal is closed (the port is reported disconnected in
//! `integrity`), then a new terminal is created and the link re-pointed to it: `vigil run`
//! reopens the port (one reconnect counted) and decodes again.
#![cfg(target_os = "linux")]

mod common;

use std::os::fd::OwnedFd;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use rustix::fs::{Mode, OFlags};
use vigil_bus::payload::integrity::{DeviceIntegrity, LINK_DISCONNECTED, LINK_OK};
use vigil_bus::{Bus, BusConfig, IntegrityPayload, Subscriber};
use vigil_drivers::watson::{Kind, Line};

/// A pseudo-terminal: master (written here) and slave kept open in raw mode.
struct Pty {
    master: OwnedFd,
    _slave: OwnedFd,
    path: PathBuf,
}

fn open_pty() -> Pty {
    use rustix::pty::{OpenptFlags, grantpt, openpt, ptsname, unlockpt};
    let master = openpt(OpenptFlags::RDWR | OpenptFlags::NOCTTY).unwrap();
    grantpt(&master).unwrap();
    unlockpt(&master).unwrap();
    let path = PathBuf::from(
        ptsname(&master, Vec::new())
            .unwrap()
            .to_string_lossy()
            .into_owned(),
    );
    let slave = rustix::fs::open(&path, OFlags::RDWR | OFlags::NOCTTY, Mode::empty()).unwrap();
    let mut t = rustix::termios::tcgetattr(&slave).unwrap();
    t.make_raw();
    rustix::termios::tcsetattr(&slave, rustix::termios::OptionalActions::Now, &t).unwrap();
    rustix::fs::fcntl_setfl(&master, OFlags::NONBLOCK).unwrap();
    // Not inherited by `vigil run` (spawned later): a copy of the master there would keep the
    // terminal alive after this test closes it.
    for fd in [&master, &slave] {
        rustix::io::fcntl_setfd(fd, rustix::io::FdFlags::CLOEXEC).unwrap();
    }
    Pty {
        master,
        _slave: slave,
        path,
    }
}

fn link(link: &Path, pty: &Pty) {
    let _ = std::fs::remove_file(link);
    std::os::unix::fs::symlink(&pty.path, link).unwrap();
}

fn watson_line() -> Vec<u8> {
    Line {
        kind: Kind::Inertial,
        over_range: false,
        bank_deg: 1.0,
        elevation_deg: -2.0,
        heading_deg: 90.0,
        accel_g: [0.0, 0.0, 1.0],
        rate_dps: [0.0; 3],
        velocity_kmh: 100.0,
    }
    .to_bytes()
}

/// Writes Watson lines to `pty` every 50 ms until the newest integrity entry satisfies `done`.
fn feed_until(
    pty: Option<&Pty>,
    sub: &mut Subscriber<IntegrityPayload>,
    what: &str,
    done: impl Fn(&DeviceIntegrity) -> bool,
) -> DeviceIntegrity {
    let deadline = Instant::now() + Duration::from_secs(8);
    let line = watson_line();
    loop {
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        if let Some(p) = pty {
            // A full terminal (nobody reading yet) drops the line: a serial line does too.
            let _ = rustix::io::write(&p.master, &line);
        }
        sub.wait(Duration::from_millis(50)).unwrap();
        let mut last = None;
        while let Some(r) = sub.try_receive().unwrap() {
            last = Some(r.payload().devices[0]);
        }
        if let Some(d) = last
            && done(&d)
        {
            return d;
        }
    }
}

/// Kills the child if the test fails before stopping it.
struct Guard(Option<Child>);

impl Drop for Guard {
    fn drop(&mut self) {
        if let Some(c) = &mut self.0 {
            let _ = c.kill();
            let _ = c.wait();
        }
    }
}

fn stop(mut guard: Guard) {
    let Some(mut child) = guard.0.take() else {
        return;
    };
    common::signal(&child, "TERM");
    common::wait_exit(&mut child, Duration::from_secs(5));
}

#[test]
fn run_reconnects_a_port_that_disappears_and_comes_back() {
    let path = common::tmp("run_reconnect", "watson");
    let prefix = format!("vigil-test-{}-run-reconnect", std::process::id());
    let config = common::tmp("run_reconnect", "run.toml");
    std::fs::write(
        &config,
        format!(
            "[bus]\nprefix = \"{prefix}\"\n[[ports]]\ndevice = \"watson\"\npath = {path:?}\n\
             [link]\nreconnect_initial_s = 0.05\nreconnect_max_s = 0.2\n\
             [status]\nintegrity_period_s = 0.1\n"
        ),
    )
    .unwrap();
    assert!(
        common::vigil(&["config", "--check", config.to_str().unwrap()])
            .status
            .success()
    );
    let pty = open_pty();
    link(&path, &pty);
    let bus = Bus::new(&BusConfig {
        prefix,
        node_name: "run-reconnect-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let mut sub = bus.subscriber::<IntegrityPayload>().unwrap();
    let run = Guard(Some(common::spawn_run(&config, Stdio::null())));

    let before = feed_until(Some(&pty), &mut sub, "messages", |d| {
        d.link_state == LINK_OK && d.messages >= 3
    });
    assert_eq!(before.reconnects, 0);

    // The port disappears: terminal closed, link removed.
    drop(pty);
    let _ = std::fs::remove_file(&path);
    let gone = feed_until(None, &mut sub, "disconnected", |d| {
        d.link_state == LINK_DISCONNECTED
    });
    assert!(gone.messages >= before.messages);

    // It comes back on a new terminal: reopened, one reconnect, messages resume.
    let pty = open_pty();
    link(&path, &pty);
    let back = feed_until(Some(&pty), &mut sub, "resumed messages", |d| {
        d.link_state == LINK_OK && d.messages >= gone.messages + 3
    });
    assert_eq!(back.reconnects, 1);
    assert_eq!(back.checksum_failures, 0);
    stop(run);
}

/// A `vigil run` killed with SIGKILL (no clean shutdown) loses at most the last second of its
/// recording: the file is flushed every second, and `vigil replay` reads it up to the damage.
#[test]
fn a_killed_run_leaves_a_recording_readable_up_to_its_last_flush() {
    let path = common::tmp("run_killed", "watson");
    let mcap = common::tmp("run_killed", "run.mcap");
    let _ = std::fs::remove_file(&mcap);
    let prefix = format!("vigil-test-{}-run-killed", std::process::id());
    let config = common::tmp("run_killed", "run.toml");
    std::fs::write(
        &config,
        format!(
            "[bus]\nprefix = \"{prefix}\"\n[[ports]]\ndevice = \"watson\"\npath = {path:?}\n\
             [record]\npath = {mcap:?}\n[status]\nintegrity_period_s = 0.1\n"
        ),
    )
    .unwrap();
    let pty = open_pty();
    link(&path, &pty);
    let bus = Bus::new(&BusConfig {
        prefix,
        node_name: "run-killed-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let mut sub = bus.subscriber::<IntegrityPayload>().unwrap();
    let mut run = Guard(Some(common::spawn_run(&config, Stdio::null())));
    // Lines for about 2.5 s: at least two flushes have happened by then.
    let first = feed_until(Some(&pty), &mut sub, "messages", |d| d.messages >= 1);
    let start = Instant::now();
    let last = feed_until(Some(&pty), &mut sub, "2.5 s of lines", |_| {
        start.elapsed() > Duration::from_millis(2500)
    });
    assert!(last.messages > first.messages);
    if let Some(c) = run.0.as_mut() {
        c.kill().unwrap(); // SIGKILL
        c.wait().unwrap();
    }
    let out = common::vigil(&["replay", mcap.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stderr = String::from_utf8(out.stderr).unwrap();
    let summary: serde_json::Value = serde_json::from_str(stderr.lines().last().unwrap()).unwrap();
    // Lines decoded from the file: all but at most the last second's (20 lines per second are
    // written here; `last.messages` were decoded live by 2.5 s).
    let replayed = summary["devices"]["watson"]["frames_decoded"]
        .as_u64()
        .unwrap();
    assert!(
        replayed + 25 >= last.messages && replayed > 0,
        "{replayed} replayed, {} live: {summary}",
        last.messages
    );
}

/// A subscriber SIGKILLed in the middle of the stream disturbs neither `vigil run` nor the other
/// subscribers: integrity reports keep arriving here at their period.
#[test]
fn a_killed_subscriber_does_not_disturb_run_or_other_subscribers() {
    let path = common::tmp("run_sub_killed", "watson");
    let prefix = format!("vigil-test-{}-run-sub-killed", std::process::id());
    let config = common::tmp("run_sub_killed", "run.toml");
    std::fs::write(
        &config,
        format!(
            "[bus]\nprefix = \"{prefix}\"\n[[ports]]\ndevice = \"watson\"\npath = {path:?}\n\
             [status]\nintegrity_period_s = 0.05\n"
        ),
    )
    .unwrap();
    let pty = open_pty();
    link(&path, &pty);
    let bus = Bus::new(&BusConfig {
        prefix: prefix.clone(),
        node_name: "run-sub-killed-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let mut sub = bus.subscriber::<IntegrityPayload>().unwrap();
    let run = Guard(Some(common::spawn_run(&config, Stdio::null())));
    feed_until(Some(&pty), &mut sub, "messages", |d| d.messages >= 1);
    // A second-process subscriber (asking for more samples than will come), killed with SIGKILL
    // while subscribed: its ports stay registered until a cleanup finds the dead node.
    let mut other = Guard(Some(
        Command::new(env!("CARGO_BIN_EXE_vigil"))
            .args([
                "listen",
                "integrity",
                "--prefix",
                &prefix,
                "--count",
                "1000000",
            ])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start vigil listen"),
    ));
    feed_until(Some(&pty), &mut sub, "the listener to run", |_| true);
    std::thread::sleep(Duration::from_millis(300));
    if let Some(c) = other.0.as_mut() {
        c.kill().unwrap(); // SIGKILL
        c.wait().unwrap();
    }
    // 20 reports per second are published: here, at least 10 within the next second, and the
    // link still decodes.
    let start = Instant::now();
    let before = sub.received();
    let d = feed_until(Some(&pty), &mut sub, "reports after the kill", |_| {
        start.elapsed() > Duration::from_secs(1)
    });
    let got = sub.received() - before;
    assert!(got >= 10, "{got} integrity reports in 1 s after the kill");
    assert_eq!(d.link_state, LINK_OK);
    stop(run);
}
