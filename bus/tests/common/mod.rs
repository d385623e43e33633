//! Shared helpers of the bus integration tests: unique prefixes, known payloads, the child process.

#![allow(dead_code)]

use std::io::{BufRead, BufReader};
use std::process::{Child, ChildStdout, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

use vigil_bus::payload::alerts::{SEVERITY_WARNING, STATE_LATCHED};
use vigil_bus::payload::attitude::{
    FAULT_FROZEN, ISOLATION_ISOLATED, UNIT_WATSON, UnitAttitude, VERDICT_FAIL,
};
use vigil_bus::payload::integrity::{CLOCK_PPS_LOCKED, DEVICE_VN200, LINK_SILENT};
use vigil_bus::payload::traffic::{ALERT_CORRECTIVE, CALLSIGN_LEN};
use vigil_bus::payload::write_text;
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, DeviceIntegrity, IntegrityPayload,
    OwnshipPayload, Payload, Target, TrafficPayload,
};

/// A service prefix no other test (nor another run) uses: process id, a counter and the test name.
pub fn unique_prefix(test: &str) -> String {
    static N: AtomicU32 = AtomicU32::new(0);
    format!(
        "vigil-test-{}-{}-{test}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    )
}

/// A bus under `prefix` that does not touch signal handling (the test harness owns it).
pub fn bus(prefix: &str, node: &str) -> Bus {
    Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: node.to_string(),
        handle_signals: false,
        cleanup_period_s: 0.0,
        lossless_wait_s: None,
    })
    .expect("bus")
}

/// A bus in the lossless regression mode (see `BusConfig::lossless_wait_s`).
pub fn lossless_bus(prefix: &str, node: &str, wait_s: f64) -> Bus {
    Bus::new(&BusConfig {
        prefix: prefix.to_string(),
        node_name: node.to_string(),
        lossless_wait_s: Some(wait_s),
        ..BusConfig::default()
    })
    .expect("bus")
}

/// Debug form of a payload with the publisher-stamped header fields zeroed, to compare content
/// (Debug, not `==`, because unknown quantities are NaN).
pub fn content<T: Payload>(p: &T) -> String {
    let mut c = p.clone();
    let h = c.header_mut();
    h.seq = 0;
    h.send_mono_ns = 0;
    h.schema_version = 0;
    format!("{c:?}")
}

/// An attitude with every field distinct, Watson isolated.
pub fn attitude() -> AttitudePayload {
    let mut p = AttitudePayload {
        roll_rad: 0.1,
        pitch_rad: -0.05,
        heading_rad: 3.0,
        sigma_roll_rad: 0.001,
        sigma_pitch_rad: 0.002,
        sigma_heading_rad: 0.01,
        isolation: ISOLATION_ISOLATED,
        isolated_unit: UNIT_WATSON,
        valid: 1,
        ..Default::default()
    };
    p.header.gps_time_ns = 1_400_000_000_123_456_789;
    for (i, u) in p.units.iter_mut().enumerate() {
        let k = i as f64;
        *u = UnitAttitude {
            t_gps_ns: 1_400_000_000_000_000_000 + i as i64,
            roll_rad: 0.1 + k * 0.01,
            pitch_rad: -0.05 - k * 0.01,
            heading_rad: 3.0 + k * 0.1,
            sigma_roll_rad: f64::NAN,
            sigma_pitch_rad: 0.003,
            sigma_heading_rad: 0.02,
            valid: u8::from(i != 2),
            fault_flags: if i == 2 { FAULT_FROZEN } else { 0 },
            reserved: [0; 6],
        };
    }
    p.pair_verdicts[1][2] = VERDICT_FAIL;
    p.pair_verdicts[2][0] = VERDICT_FAIL;
    p
}

/// An ownship with the geometric altitude unknown.
pub fn ownship() -> OwnshipPayload {
    let mut p = OwnshipPayload {
        lat_deg: 47.3769,
        lon_deg: 8.5417,
        alt_pressure_m: 1234.5,
        vel_north_mps: 30.0,
        vel_east_mps: -4.0,
        vel_up_mps: 1.5,
        ground_speed_mps: 30.265,
        track_deg: 352.4,
        sigma_horizontal_m: 2.5,
        sigma_vertical_m: 4.0,
        sigma_velocity_mps: 0.1,
        source: vigil_bus::payload::ownship::SOURCE_VN200_INS,
        valid: 1,
        ..Default::default()
    };
    p.header.gps_time_ns = 42;
    p
}

/// A full traffic picture: 1024 distinct targets (the capacity), tau_mod NaN on odd ones.
pub fn traffic() -> TrafficPayload {
    let mut p = TrafficPayload::default();
    let targets: Vec<Target> = (0..vigil_bus::MAX_TARGETS)
        .map(|i| {
            let k = i as f64;
            let mut callsign = [0u8; CALLSIGN_LEN];
            write_text(&mut callsign, &format!("T{i:05}"));
            Target {
                address: 0x40_0000 + i as u32,
                address_type: (i % 6) as u8,
                alert_level: if i == 0 { ALERT_CORRECTIVE } else { 0 },
                altitude_kind: (i % 3) as u8,
                plausibility_flags: (i % 32) as u8,
                callsign,
                lat_deg: 47.0 + k * 1e-4,
                lon_deg: 8.0 - k * 1e-4,
                alt_pressure_m: 1500.0 + k,
                alt_geometric_m: if i % 2 == 0 { f64::NAN } else { 1550.0 + k },
                track_deg: (k * 0.7) % 360.0,
                ground_speed_mps: 60.0 + k / 100.0,
                vertical_rate_mps: -1.5,
                position_sigma_m: 9.0,
                nic: (i % 12) as u8,
                nac_p: 10,
                nac_v: vigil_bus::payload::traffic::NOT_REPORTED,
                emitter_category: (i % 20) as u8,
                sources: (i % 16) as u8,
                reserved: [0; 3],
                rel_north_m: 100.0 + k,
                rel_east_m: -50.0 - k,
                rel_down_m: k - 30.0,
                rel_vel_north_mps: -10.0,
                rel_vel_east_mps: 2.0 + k / 1000.0,
                rel_vel_down_mps: -0.5,
                horizontal_distance_m: 111.8 + k,
                bearing_deg: (k * 0.35) % 360.0,
                range_rate_mps: -9.0,
                tcpa_s: 12.0 + k,
                hmd_m: 40.0 + k,
                tau_mod_s: if i % 2 == 1 { f64::NAN } else { 20.0 + k },
                time_to_lowc_s: if i == 0 { 0.0 } else { f64::NAN },
                age_s: 0.25,
                flags: vigil_bus::payload::traffic::FLAG_VERTICAL_RATE_UNKNOWN,
            }
        })
        .collect();
    p.set_targets(&targets);
    p.header.gps_time_ns = 7;
    p
}

/// An integrity snapshot with three devices.
pub fn integrity() -> IntegrityPayload {
    let mut p = IntegrityPayload {
        device_count: 3,
        clock_status: CLOCK_PPS_LOCKED,
        leap_seconds_known: 1,
        clock_offset_s: 1.5e-6,
        clock_sigma_s: 2.0e-7,
        ..Default::default()
    };
    for (i, d) in p.devices.iter_mut().take(3).enumerate() {
        let k = i as u64;
        *d = DeviceIntegrity {
            device: if i == 1 { DEVICE_VN200 } else { i as u8 },
            link_state: if i == 2 { LINK_SILENT } else { 1 },
            last_message_age_s: if i == 2 {
                f64::NAN
            } else {
                0.01 * (k as f64 + 1.0)
            },
            bytes_received: 1000 + k,
            bytes_consumed: 990 + k,
            bytes_skipped: 10,
            messages: 50 + k,
            checksum_failures: k,
            unknown_types: 2 * k,
            malformed: 3 * k,
            reconnects: 4 * k,
            ..Default::default()
        };
        write_text(&mut d.name, ["bahrs", "vn200", "watson"][i]);
    }
    p
}

/// A latched warning with a non-ASCII reason.
pub fn alert() -> AlertPayload {
    let mut p = AlertPayload {
        alert_id: 17,
        severity: SEVERITY_WARNING,
        state: STATE_LATCHED,
        raised_gps_ns: 1_400_000_000_000_000_000,
        ..Default::default()
    };
    p.header.gps_time_ns = 1_400_000_001_000_000_000;
    p.set_reason("attitude miscompare: Watson roll 2.1° off BAHRS/VN-200 for 1.0 s");
    p
}

/// Name of the test function that hosts the child roles (see `child_main`).
pub const CHILD_TEST: &str = "child_process_entry";
/// Environment variable naming the child role.
pub const ROLE_VAR: &str = "VIGIL_BUS_CHILD_ROLE";
/// Environment variable carrying the child's service prefix.
pub const PREFIX_VAR: &str = "VIGIL_BUS_CHILD_PREFIX";
/// Line the child prints once its ports exist.
pub const READY: &str = "VIGIL-BUS-CHILD-READY";

/// This test binary run again as a child process in `role`, stdin and stdout piped.
pub fn spawn_child(role: &str, prefix: &str) -> (Child, BufReader<ChildStdout>) {
    let exe = std::env::current_exe().expect("test binary path");
    let mut child = Command::new(exe)
        .args([CHILD_TEST, "--exact", "--nocapture", "--test-threads=1"])
        .env(ROLE_VAR, role)
        .env(PREFIX_VAR, prefix)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .spawn()
        .expect("spawn child");
    let stdout = BufReader::new(child.stdout.take().expect("child stdout"));
    (child, stdout)
}

/// Reads the child's output until its ready line (panics if it ends first).
pub fn wait_ready(out: &mut BufReader<ChildStdout>) {
    let mut line = String::new();
    loop {
        line.clear();
        let n = out.read_line(&mut line).expect("read child stdout");
        assert!(n > 0, "child exited before it was ready");
        if line.contains(READY) {
            return;
        }
    }
}

/// True until the parent closes the child's stdin (checked by a reader thread), or 30 s pass.
pub fn parent_alive_flag() -> std::sync::Arc<std::sync::atomic::AtomicBool> {
    let alive = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(true));
    let flag = alive.clone();
    std::thread::spawn(move || {
        let mut s = String::new();
        let _ = std::io::stdin().read_line(&mut s);
        flag.store(false, Ordering::Relaxed);
    });
    let flag = alive.clone();
    let start = Instant::now();
    std::thread::spawn(move || {
        while start.elapsed() < Duration::from_secs(30) {
            std::thread::sleep(Duration::from_millis(100));
        }
        flag.store(false, Ordering::Relaxed);
    });
    alive
}
