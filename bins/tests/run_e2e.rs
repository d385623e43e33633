//! `vigil run` end to end: the simulator on pseudo-terminals (`vigil sim --pty-dir`, nominal
//! scenario), `vigil run` on those ports in a second process, and this test as the subscriber in a
//! third; SIGTERM then leaves a complete MCAP file that `vigil replay` reads without damage.
#![cfg(target_os = "linux")]

mod common;

use common::Guard;

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use vigil_bus::payload::integrity::LINK_OK;
use vigil_bus::payload::read_text;
use vigil_bus::{
    AttitudePayload, Bus, BusConfig, IntegrityPayload, OwnshipPayload, TrafficPayload,
};

#[test]
fn run_publishes_fused_outputs_and_sigterm_finalises_the_recording() {
    let dir = common::tmp("run_e2e", "pty");
    let mcap = common::tmp("run_e2e", "run.mcap");
    let _ = std::fs::remove_file(&mcap);
    let prefix = format!("vigil-test-{}-run-e2e", std::process::id());
    let config = common::tmp("run_e2e", "run.toml");
    let mut text = common::run_config(&prefix, &dir);
    text += &format!("[record]\npath = {mcap:?}\n");
    text += "[status]\nintegrity_period_s = 0.25\n";
    std::fs::write(&config, text).unwrap();

    let _sim = Guard(common::start_sim(&dir, "nominal", "30", "5"));
    let bus = Bus::new(&BusConfig {
        prefix: prefix.clone(),
        node_name: "run-e2e-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let mut traffic = bus.traffic_subscriber().unwrap();
    let mut ownship = bus.subscriber::<OwnshipPayload>().unwrap();
    let mut attitude = bus.subscriber::<AttitudePayload>().unwrap();
    let mut integrity = bus.subscriber::<IntegrityPayload>().unwrap();
    let mut run = Guard(common::spawn_run(&config, Stdio::piped()));

    // Collect until a traffic picture holds the scenario's five intruders (the clocks lock
    // within ~2 s, the tracks form at the next 1 s steps).
    let deadline = Instant::now() + Duration::from_secs(15);
    let mut full_picture: Option<TrafficPayload> = None;
    let mut own: Option<OwnshipPayload> = None;
    // Attitude is latest-state-wins with a buffer of 8: count what arrives, and the publisher's
    // sequence number (one per record, at the BAHRS navigation rate of 50 Hz).
    let mut att = 0usize;
    let mut att_valid = 0usize;
    let mut att_seq = 0u64;
    let mut integ: Option<IntegrityPayload> = None;
    // Every picture received: GPS time, (address, horizontal distance m) per target.
    let mut pictures: Vec<(i64, Vec<(u32, f64)>)> = Vec::new();
    while (full_picture.is_none() || pictures.len() < 3) && Instant::now() < deadline {
        traffic.wait(Duration::from_millis(50)).unwrap();
        while let Some(t) = traffic.try_receive().unwrap() {
            if t.targets().len() == 5 {
                full_picture = Some(t.to_payload());
            }
            if !t.targets().is_empty() {
                pictures.push((
                    t.header().gps_time_ns,
                    t.targets()
                        .iter()
                        .map(|x| (x.address, x.horizontal_distance_m))
                        .collect(),
                ));
            }
        }
        while let Some(o) = ownship.try_receive().unwrap() {
            own = Some(*o.payload());
        }
        while let Some(a) = attitude.try_receive().unwrap() {
            att += 1;
            att_valid += usize::from(a.valid == 1);
            att_seq = a.header.seq;
        }
        while let Some(i) = integrity.try_receive().unwrap() {
            integ = Some(*i.payload());
        }
    }
    let t = full_picture.expect("a traffic picture with the five intruders");
    let mut addresses: Vec<u32> = t.targets().iter().map(|x| x.address).collect();
    addresses.sort_unstable();
    // nominal.toml: 4B1801, 4B1802 (ADS-B), A12345 (UAT), 3D0A11 (FLARM), and one more.
    for a in [0x3D0A11, 0x4B1801, 0x4B1802, 0xA12345] {
        assert!(
            addresses.contains(&a),
            "{a:06X} missing from {addresses:06X?}"
        );
    }
    assert_eq!(t.dropped, 0);
    for x in t.targets() {
        // The intruders start 1.5 .. 9 km away; bearing within [0, 360).
        assert!(
            (500.0..20_000.0).contains(&x.horizontal_distance_m),
            "{:06X} at {} m",
            x.address,
            x.horizontal_distance_m
        );
        assert!((0.0..360.0).contains(&x.bearing_deg));
        let r = x.rel_north_m.hypot(x.rel_east_m);
        assert!((r - x.horizontal_distance_m).abs() < 1e-6);
    }
    let o = own.expect("an ownship");
    assert_eq!(o.valid, 1);
    // The scenario starts at 47.40 N 8.50 E and flies 40 m/s.
    assert!((o.lat_deg - 47.40).abs() < 0.05 && (o.lon_deg - 8.50).abs() < 0.05);
    assert!(
        (o.ground_speed_mps - 40.0).abs() < 3.0,
        "{}",
        o.ground_speed_mps
    );
    assert!(
        att > 0 && att_valid > 0 && att_seq > 10,
        "{att} attitude samples, {att_valid} valid, last seq {att_seq}"
    );
    let i = integ.expect("an integrity report");
    assert_eq!(i.device_count, 4);
    for d in i.devices() {
        assert_eq!(d.link_state, LINK_OK, "{}", read_text(&d.name));
    }

    common::signal(&run.0, "TERM");
    let status = common::wait_exit(&mut run.0, Duration::from_secs(5));
    let mut log = String::new();
    std::io::Read::read_to_string(run.0.stderr.as_mut().unwrap(), &mut log).unwrap();
    assert!(status.success(), "vigil run: {status}\n{log}");
    assert!(log.contains("stopping (SIGTERM)"), "{log}");
    assert!(log.contains("recording finalised"), "{log}");

    // The recording is complete (summary written): replay reads it with no damage.
    let out = common::vigil(&["replay", mcap.to_str().unwrap()]);
    assert!(out.status.success());
    // Messages on stdout, the summary on stderr.
    assert!(out.stdout.len() > 1000);
    let stderr = String::from_utf8(out.stderr).unwrap();
    let summary: serde_json::Value = serde_json::from_str(stderr.lines().last().unwrap()).unwrap();
    assert_eq!(summary["kind"], "summary");
    assert!(summary["damage"].is_null(), "{summary}");
    assert!(summary["mcap_messages"].as_u64().unwrap() > 100);
    for d in ["bahrs", "watson", "vn200", "ttmrf"] {
        assert!(
            summary["devices"].get(d).is_some(),
            "{d} missing: {summary}"
        );
    }

    // What was published live is what the recording replays to: the same targets at the same
    // distances at every step both have (the pipeline is a function of the recorded bytes and
    // host times; the recording holds the chunks in the order the service took them).
    let out = common::vigil(&["replay", mcap.to_str().unwrap(), "--emit", "fused"]);
    assert!(out.status.success());
    let replayed: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .filter(|v: &serde_json::Value| v["kind"] == "traffic")
        .collect();
    let mut compared = 0;
    for (t, targets) in &pictures {
        let Some(r) = replayed.iter().find(|v| v["t_gps_ns"].as_i64() == Some(*t)) else {
            continue;
        };
        let r = r["targets"].as_array().unwrap();
        assert_eq!(r.len(), targets.len(), "at {t}");
        for (address, distance) in targets {
            let x = r
                .iter()
                .find(|x| x["key"]["address"] == format!("{address:06X}"))
                .unwrap_or_else(|| panic!("{address:06X} not replayed at {t}"));
            let d = x["geometry"]["horizontal_distance_m"].as_f64().unwrap();
            assert!(
                (d - distance).abs() < 1e-6,
                "{address:06X} at {t}: {d} != {distance}"
            );
        }
        compared += 1;
    }
    assert!(
        compared >= 2,
        "{compared} pictures compared of {}",
        pictures.len()
    );

    // And it matches the simulator's truth: every published range against the true horizontal
    // distance of that intruder at the picture's GPS time (the same scenario and seed give the
    // same world). Tolerance: the position noise of the reports (NACp 9: < 30 m at 95 %) plus what
    // 1 s of extrapolation of a turning target leaves (< 0.5 a t^2 with a = v^2 / r, 2 m for the
    // 6 deg/s glider), and the WGS-84 tangent plane against the simulator's flat earth (0.2 %).
    let sim =
        vigil_sim::Simulator::new(&vigil_sim::scenario::builtin("nominal").unwrap(), 5).unwrap();
    let world = sim.world();
    let mut checked = 0;
    let mut worst = 0.0f64;
    for (t, targets) in &pictures {
        let own = world.ownship(*t);
        for (address, distance) in targets {
            let i = (0..world.intruder_count())
                .find(|&i| {
                    u32::from_str_radix(&world.intruder(i, *t).unwrap().address, 16).ok()
                        == Some(*address)
                })
                .unwrap_or_else(|| panic!("{address:06X} is not in the scenario"));
            let x = world.intruder(i, *t).unwrap();
            let truth = vigil_fusion::traffic::plausibility::horizontal_distance_m(
                own.lat_deg,
                own.lon_deg,
                x.lat_deg,
                x.lon_deg,
            );
            let tol = 40.0 + 0.002 * truth;
            worst = worst.max((distance - truth).abs());
            assert!(
                (distance - truth).abs() < tol,
                "{address:06X} at {t}: published {distance:.1} m, truth {truth:.1} m"
            );
            checked += 1;
        }
    }
    assert!(checked >= 10, "{checked} targets checked against truth");
    println!("{checked} published ranges against truth: largest difference {worst:.1} m");
}

#[test]
fn config_example_is_printed_and_checked() {
    let out = common::vigil(&["config", "--example"]);
    assert!(out.status.success());
    let path = common::tmp("run_config", "example.toml");
    std::fs::write(&path, &out.stdout).unwrap();
    let out = common::vigil(&["config", "--check", path.to_str().unwrap()]);
    assert!(out.status.success());
    let ports = String::from_utf8(out.stdout).unwrap();
    assert_eq!(ports.lines().count(), 4);
    assert!(
        ports.starts_with("bahrs /dev/ttyUSB0 115200 bahrs-2.0\n"),
        "{ports}"
    );

    // A bad value: the error names the key.
    let bad = common::tmp("run_config", "bad.toml");
    std::fs::write(
        &bad,
        "[[ports]]\ndevice = \"vn200\"\npath = \"/dev/x\"\nbaud = 1000\n",
    )
    .unwrap();
    let out = common::vigil(&["run", "--config", bad.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("ports[0].baud: must be one of"), "{err}");
}

#[test]
fn run_configures_the_vn200_and_ttmrf_when_asked_and_keeps_decoding() {
    let dir = common::tmp("run_setup", "pty");
    let prefix = format!("vigil-test-{}-run-setup", std::process::id());
    let config = common::tmp("run_setup", "run.toml");
    let mut text = common::run_config(&prefix, &dir);
    text += "[configure]\nvn200_binary_outputs = true\nvn200_rate_hz = 100\nttmrf_protocol = true\n\
             ttmrf_decoded = \"json\"\n";
    std::fs::write(&config, text).unwrap();
    let _sim = Guard(common::start_sim(&dir, "nominal", "30", "5"));
    let bus = Bus::new(&BusConfig {
        prefix,
        node_name: "run-setup-test".to_string(),
        ..BusConfig::default()
    })
    .unwrap();
    let mut traffic = bus.traffic_subscriber().unwrap();
    let mut run = Guard(common::spawn_run(&config, Stdio::piped()));
    let stderr = run.0.stderr.take().unwrap();
    let (tx, rx) = std::sync::mpsc::channel::<String>();
    std::thread::spawn(move || {
        for l in BufReader::new(stderr).lines().map_while(Result::ok) {
            if tx.send(l).is_err() {
                break;
            }
        }
    });
    // The VN-200 session takes well under a second; the TT-Multi-RF one a few seconds (its
    // CONFIGURATION state transitions).
    let deadline = Instant::now() + Duration::from_secs(15);
    let (mut vn, mut tt) = (false, false);
    let mut log = Vec::new();
    while !(vn && tt) {
        let left = deadline.saturating_duration_since(Instant::now());
        let Ok(l) = rx.recv_timeout(left) else {
            panic!("set-up not reported:\n{}", log.join("\n"));
        };
        vn |= l.contains("vn200: binary output 1 configured at 100 Hz");
        tt |= l.contains("ttmrf: protocols configured");
        assert!(!l.contains("set-up failed"), "{l}");
        log.push(l);
    }
    // The VN-200 model took the write: its Register 75 echo matched.
    assert!(
        log.iter()
            .any(|l| l.contains("VNWRG -> Accepted { echo_matches: true }")),
        "{}",
        log.join("\n")
    );
    // After the set-up the TT-Multi-RF sends JSON: the traffic still comes through (pictures
    // published before now are drained first).
    while traffic.try_receive().unwrap().is_some() {}
    let deadline = Instant::now() + Duration::from_secs(5);
    let mut seen = 0;
    while seen == 0 && Instant::now() < deadline {
        if let Some(t) = traffic.receive_timeout(Duration::from_millis(200)).unwrap()
            && !t.targets().is_empty()
        {
            seen = t.targets().len();
        }
    }
    assert!(seen > 0, "no traffic after the set-up");
    common::signal(&run.0, "TERM");
    assert!(common::wait_exit(&mut run.0, Duration::from_secs(5)).success());
}

#[test]
fn a_missing_port_is_retried_and_duration_ends_the_run() {
    let prefix = format!("vigil-test-{}-run-missing", std::process::id());
    let config = common::tmp("run_missing", "run.toml");
    std::fs::write(
        &config,
        format!(
            "[bus]\nprefix = \"{prefix}\"\n[[ports]]\ndevice = \"vn200\"\n\
             path = \"/nonexistent/ttyVN\"\n[link]\nreconnect_initial_s = 0.05\n"
        ),
    )
    .unwrap();
    let start = Instant::now();
    let out = Command::new(env!("CARGO_BIN_EXE_vigil"))
        .args(["run", "--duration", "1", "--config"])
        .arg(&config)
        .output()
        .unwrap();
    let log = String::from_utf8(out.stderr).unwrap();
    assert!(out.status.success(), "{log}");
    assert!(start.elapsed() < Duration::from_secs(5));
    // Logged once (not at every retry), and the run ends at its duration.
    assert_eq!(log.matches("port vn200: cannot open").count(), 1, "{log}");
    assert!(log.contains("stopping (end of --duration)"), "{log}");
    assert!(log.contains("vn200=disconnected"), "{log}");
}
