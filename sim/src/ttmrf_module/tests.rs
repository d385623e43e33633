//! The drivers' configuration client against the simulated module: full cycles, lost lines,
//! stuck settings, aborts, a silent module, and a module already in CONFIGURATION.

use std::time::Duration;

use vigil_drivers::ttmrf::at::client::{
    ClientConfig, ConfigClient, ConfigError, Output, SettingChange,
};
use vigil_drivers::ttmrf::at::settings::{Baudrate, DecodedProtocol, Setting, SettingId};
use vigil_drivers::ttmrf::at::{ConfigFailure, ConfigReport, ModuleState};

use super::*;

type Outcome = Result<ConfigReport, ConfigFailure>;

/// Connects client and module through a virtual serial line: each side only hears the other when
/// both are at the same baud. Returns the outcome, the host's final baud and the virtual time.
fn run(sim: &mut SimModule, client: &mut ConfigClient) -> (Outcome, u32, Duration) {
    client.start(Duration::ZERO);
    run_started(sim, client, Duration::ZERO)
}

fn wanted() -> Vec<Setting> {
    vec![
        Setting::adsb_decoded(DecodedProtocol::Json),
        Setting::flarm_decoded(DecodedProtocol::Json).unwrap(),
        Setting::gnss_nmea(true),
        // Changing the RUN baud makes the client follow it on the way out.
        Setting::baudrate(Baudrate::B115200),
    ]
}

fn module() -> SimModule {
    SimModule::new("22-0000309", "2.77.5.0 (Mar 4 2025)")
}

#[test]
fn full_configure_cycle() {
    let mut sim = module();
    assert_eq!(sim.baud(), 921_600);
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, host_baud, _) = run(&mut sim, &mut client);
    let report = outcome.expect("cycle succeeds");

    assert_eq!(report.serial_number.as_deref(), Some("22-0000309"));
    assert_eq!(
        report.firmware_version.as_deref(),
        Some("2.77.5.0 (Mar 4 2025)")
    );
    // Documented defaults: ADS-B decoded CSV (1), FLARM decoded none (0), GNSS raw none (0);
    // the simulated module runs at BAUDRATE 1.
    assert_eq!(
        report.changed,
        vec![
            SettingChange {
                id: SettingId::AdsbRxProtocolDecoded,
                from: Some("1".into()),
                to: 3
            },
            SettingChange {
                id: SettingId::FlarmRxProtocolDecoded,
                from: Some("0".into()),
                to: 3
            },
            SettingChange {
                id: SettingId::GnssRxProtocolRaw,
                from: Some("0".into()),
                to: 5
            },
            SettingChange {
                id: SettingId::Baudrate,
                from: Some("1".into()),
                to: 0
            },
        ]
    );
    assert!(report.lock_cleared && report.run_confirmed);
    assert_eq!(report.retries, 0);
    assert!(report.warnings.is_empty(), "{:?}", report.warnings);

    // The module saved the settings, is back in RUN, unlocked, at the new baud the host followed.
    assert_eq!(sim.stored("ADSB_RX_PROTOCOL_DECODED"), Some("3"));
    assert_eq!(sim.stored("FLARM_RX_PROTOCOL_DECODED"), Some("3"));
    assert_eq!(sim.stored("GNSS_RX_PROTOCOL_RAW"), Some("5"));
    assert_eq!(sim.state(), ModuleState::Run);
    assert!(!sim.locked());
    assert_eq!(sim.baud(), 115_200);
    assert_eq!(host_baud, 115_200);
    assert_eq!(report.run_baud, 115_200);
    assert_eq!(
        sim.garbled_bytes, 0,
        "the client never spoke at the wrong baud"
    );
    // After a power cycle the module comes up in RUN (it was not left locked).
    sim.power_cycle();
    assert_eq!(sim.state(), ModuleState::Run);
}

#[test]
fn traffic_in_run_state_does_not_disturb_the_client() {
    let mut sim = module();
    let line = "#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE";
    let msg = vigil_drivers::ttmrf::csv::parse_line(line.as_bytes()).unwrap();
    for _ in 0..3 {
        assert!(sim.emit_traffic(&msg));
    }
    let json = vigil_drivers::ttmrf::json::parse_message(
        br#"{"ver":1,"ts":1,"flarm":[{"id":"1600BF","type":13}]}"#,
    )
    .unwrap();
    assert!(sim.emit_line(json.to_wire().as_bytes()));
    assert!(sim.emit_line(b"$GPZDA,201530.00,04,07,2002,00,00*60\r\n"));
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, _, _) = run(&mut sim, &mut client);
    assert_eq!(outcome.unwrap().changed.len(), 4);
    // Back in RUN at the new baud, traffic flows again, byte-identical to the manual's example.
    assert!(sim.emit_traffic(&msg));
    assert_eq!(
        sim.poll_output(),
        Some((115_200, format!("{line}\r\n").into_bytes()))
    );
}

#[test]
fn already_configured_writes_nothing() {
    let mut sim = module();
    sim.set_stored("ADSB_RX_PROTOCOL_DECODED", "3");
    let mut client = ConfigClient::new(
        vec![Setting::adsb_decoded(DecodedProtocol::Json)],
        ClientConfig::default(),
    );
    let (outcome, host_baud, _) = run(&mut sim, &mut client);
    let report = outcome.unwrap();
    assert!(report.changed.is_empty());
    assert_eq!(
        report.found,
        vec![(SettingId::AdsbRxProtocolDecoded, Some("3".into()))]
    );
    assert_eq!(host_baud, 921_600);
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
}

#[test]
fn lost_state_messages_are_recovered_by_probing() {
    let mut sim = module();
    // AT+OK, AT+RUN_END and AT+CONFIG_START are lost.
    sim.faults.drop_next_lines = 3;
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, _, elapsed) = run(&mut sim, &mut client);
    let report = outcome.unwrap();
    assert_eq!(report.changed.len(), 4);
    assert!(report.run_confirmed);
    // One transition timeout (3 s) was spent before the AT+CONFIG? probe.
    assert!(
        elapsed >= Duration::from_secs(3) && elapsed < Duration::from_secs(4),
        "{elapsed:?}"
    );
    assert!(!sim.locked());
}

#[test]
fn module_already_in_configuration() {
    let mut sim = module();
    sim.receive(b"AT+CONFIG=1\r", 921_600);
    while sim.poll_output().is_some() {}
    assert_eq!(sim.state(), ModuleState::Configuration);
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, _, _) = run(&mut sim, &mut client);
    let report = outcome.unwrap();
    assert_eq!(report.changed.len(), 4);
    // The AT+CONFIG=1 sent at 921600 reached a module listening at 115200 and was garbled.
    assert_eq!(sim.garbled_bytes, "AT+CONFIG=1\r\n".len());
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
}

#[test]
fn stuck_setting_fails_and_still_unlocks_and_returns_to_run() {
    let mut sim = module();
    sim.faults.stuck_setting = Some(SettingId::GnssRxProtocolRaw);
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, host_baud, _) = run(&mut sim, &mut client);
    let failure = outcome.unwrap_err();
    assert_eq!(
        failure.error,
        ConfigError::VerifyFailed {
            setting: SettingId::GnssRxProtocolRaw,
            wanted: 5,
            read: "0".into()
        }
    );
    // Two settings had been changed (and are saved on leaving CONFIGURATION), the third was
    // written three times.
    assert_eq!(failure.report.changed.len(), 2);
    assert_eq!(failure.report.retries, 2);
    assert!(failure.report.lock_cleared && failure.report.run_confirmed);
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
    assert_eq!(sim.stored("ADSB_RX_PROTOCOL_DECODED"), Some("3"));
    assert_eq!(host_baud, sim.baud());
}

#[test]
fn abort_in_configuration_unlocks_and_returns_to_run() {
    let mut sim = module();
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let now = Duration::ZERO;
    let mut host_baud = client.baud();
    client.start(now);
    // Pump until the client has entered CONFIGURATION and read the identity.
    let mut finished = None;
    let mut steps = 0;
    while finished.is_none() && steps < 1000 {
        steps += 1;
        while let Some(o) = client.poll_output() {
            match o {
                Output::Send(b) => sim.receive(&b, host_baud),
                Output::SetBaud(b) => host_baud = b,
                Output::Finished(r) => finished = Some(r),
            }
        }
        if let Some((baud, bytes)) = sim.poll_output()
            && baud == host_baud
        {
            client.handle_bytes(&bytes, now);
        }
        if steps == 12 {
            assert_eq!(sim.state(), ModuleState::Configuration);
            assert!(sim.locked());
            client.abort(now);
        }
    }
    let failure = finished.unwrap().unwrap_err();
    assert_eq!(failure.error, ConfigError::Aborted);
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
}

#[test]
fn silent_module_gives_up_in_bounded_time() {
    let mut sim = module();
    sim.faults.drop_next_lines = usize::MAX;
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, _, elapsed) = run(&mut sim, &mut client);
    assert_eq!(outcome.unwrap_err().error, ConfigError::EnterTimeout(3));
    // 3 x (3 s + 0.5 s) entering, then the clean-up: 3 x 0.5 s unlock + 3 x 3 s exit.
    assert!(elapsed <= Duration::from_secs(25), "{elapsed:?}");
    // The module heard AT+CONFIG=1 and locked itself; the clean-up's AT+LOCK=0 and AT+CONFIG=0
    // reached it at 115200 even though its answers were lost.
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
}

#[test]
fn module_side_rules() {
    let mut sim = module();
    // In RUN only AT+CONFIG is understood; other commands are ignored silently.
    sim.receive(b"AT+HELP\n", 921_600);
    assert!(sim.poll_output().is_none());
    sim.receive(b"AT+config=1\n", 921_600);
    let lines: Vec<_> = std::iter::from_fn(|| sim.poll_output()).collect();
    assert_eq!(
        lines,
        vec![
            (921_600, b"AT+OK\r\n".to_vec()),
            (921_600, b"AT+RUN_END\r\n".to_vec()),
            (115_200, b"AT+CONFIG_START\r\n".to_vec()),
        ]
    );
    // 5.1.5: a command without "\n", "\r" or "\r\n" is not executed (yet).
    sim.receive(b"AT+CONFIG?", 115_200);
    assert!(sim.poll_output().is_none());
    sim.receive(b"\n", 115_200);
    assert_eq!(
        sim.poll_output(),
        Some((115_200, b"AT+CONFIG=1\r\n".to_vec()))
    );
    // Out-of-range writes are refused with AT+ERROR, reads answer AT+NAME=VALUE.
    sim.receive(b"AT+BAUDRATE=9\r\nAT+asterix_sic?\r\n", 115_200);
    let lines: Vec<_> = std::iter::from_fn(|| sim.poll_output())
        .map(|(_, l)| String::from_utf8(l).unwrap())
        .collect();
    assert!(lines[0].starts_with("AT+ERROR ("), "{lines:?}");
    assert_eq!(lines[1], "AT+ASTERIX_SIC=129\r\n");
    // REBOOT_BOOTLOADER locks; in BOOTLOADER lower case is refused, AT+LOCK=0 releases to RUN.
    sim.receive(b"AT+REBOOT_BOOTLOADER\r", 115_200);
    assert_eq!(sim.state(), ModuleState::Bootloader);
    while sim.poll_output().is_some() {}
    sim.receive(b"AT+lock=0\r", 115_200);
    assert_eq!(sim.state(), ModuleState::Bootloader);
    sim.receive(b"AT+LOCK=0\r", 115_200);
    assert_eq!(sim.state(), ModuleState::Run);
}

#[test]
fn module_locked_in_bootloader_is_released_and_configured() {
    let mut sim = module();
    // Someone entered CONFIGURATION (which sets the lock) and power-cycled the module: it stays
    // in BOOTLOADER.
    sim.receive(b"AT+CONFIG=1\n", 921_600);
    sim.power_cycle();
    while sim.poll_output().is_some() {}
    assert_eq!(sim.state(), ModuleState::Bootloader);
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let (outcome, host_baud, _) = run(&mut sim, &mut client);
    let report = outcome.unwrap();
    assert_eq!(report.changed.len(), 4);
    assert_eq!(report.retries, 1);
    assert!(
        report.warnings[0].contains("bootloader"),
        "{:?}",
        report.warnings
    );
    assert_eq!(sim.state(), ModuleState::Run);
    assert!(!sim.locked());
    assert_eq!(host_baud, 115_200);
}

#[test]
fn bootloader_start_seen_while_entering() {
    let mut sim = module();
    sim.receive(b"AT+CONFIG=1\n", 921_600);
    while sim.poll_output().is_some() {}
    // Power cycle while locked: the module announces BOOTLOADER (at 115200) and stays there.
    sim.power_cycle();
    let mut client = ConfigClient::new(wanted(), ClientConfig::default());
    let now = Duration::ZERO;
    client.start(now);
    // The client's AT+CONFIG=1 at 921600 is lost on a module at 115200; the host hears
    // AT+BOOTLOADER_START (a host listening at 115200 during power-up, as here by construction).
    while client.poll_output().is_some() {}
    let (baud, line) = sim.poll_output().unwrap();
    assert_eq!(
        (baud, line.as_slice()),
        (115_200, &b"AT+BOOTLOADER_START\r\n"[..])
    );
    client.handle_bytes(&line, now);
    let (outcome, _, elapsed) = run_started(&mut sim, &mut client, now);
    let report = outcome.unwrap();
    assert_eq!(report.changed.len(), 4);
    // No timeout was needed: the state message triggered the release at once.
    assert!(elapsed < Duration::from_millis(500), "{elapsed:?}");
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
}

/// The harness of [`run`] for a client that was already started.
fn run_started(
    sim: &mut SimModule,
    client: &mut ConfigClient,
    mut now: Duration,
) -> (Outcome, u32, Duration) {
    let mut host_baud = client.baud();
    for _ in 0..10_000 {
        while let Some(o) = client.poll_output() {
            match o {
                Output::Send(bytes) => sim.receive(&bytes, host_baud),
                Output::SetBaud(b) => host_baud = b,
                Output::Finished(r) => return (r, host_baud, now),
            }
        }
        if let Some((baud, bytes)) = sim.poll_output() {
            now += Duration::from_millis(1);
            if baud == host_baud {
                client.handle_bytes(&bytes, now);
            }
            continue;
        }
        let t = client
            .poll_timeout()
            .expect("a waiting client always has a deadline");
        now = now.max(t);
        client.handle_timeout(now);
    }
    panic!("the cycle did not end");
}

#[test]
fn unknown_run_baud_is_found_by_baud_search() {
    let mut sim = module();
    sim.set_stored("BAUDRATE", "2");
    assert_eq!(sim.baud(), 3_000_000);
    let cfg = ClientConfig {
        baud_search: true,
        ..Default::default()
    };
    let mut client = ConfigClient::new(vec![Setting::gnss_nmea(true)], cfg);
    let (outcome, host_baud, _) = run(&mut sim, &mut client);
    let report = outcome.unwrap();
    // 921600 (the initial guess) and 115200 fail, 3000000 answers.
    assert_eq!(report.retries, 2);
    assert_eq!(report.run_baud, 3_000_000);
    assert_eq!(host_baud, 3_000_000);
    assert_eq!(sim.stored("GNSS_RX_PROTOCOL_RAW"), Some("5"));
    assert!(!sim.locked());

    // Without the search, the wrong guess is a clean failure.
    let mut sim2 = module();
    sim2.set_stored("BAUDRATE", "2");
    let mut client = ConfigClient::new(vec![Setting::gnss_nmea(true)], ClientConfig::default());
    let (outcome, _, _) = run(&mut sim2, &mut client);
    assert_eq!(outcome.unwrap_err().error, ConfigError::EnterTimeout(3));
    assert_eq!(sim2.state(), ModuleState::Run);
    assert!(!sim2.locked());
}

#[test]
fn config_as_set_keeps_the_run_baud() {
    use vigil_drivers::ttmrf::at::ConfigMode;
    let mut sim = module();
    let cfg = ClientConfig {
        config_mode: ConfigMode::ConfigAsSet,
        ..Default::default()
    };
    let mut client = ConfigClient::new(vec![Setting::gnss_nmea(true)], cfg);
    client.start(Duration::ZERO);
    let mut bauds = Vec::new();
    let mut host_baud = 0;
    let mut result = None;
    for _ in 0..1000 {
        while let Some(o) = client.poll_output() {
            match o {
                Output::Send(b) => sim.receive(&b, host_baud),
                Output::SetBaud(b) => {
                    host_baud = b;
                    bauds.push(b);
                }
                Output::Finished(r) => result = Some(r),
            }
        }
        match sim.poll_output() {
            Some((baud, bytes)) if baud == host_baud => client.handle_bytes(&bytes, Duration::ZERO),
            Some(_) => panic!("the module spoke at a baud the host was not at"),
            None => break,
        }
    }
    let report = result.unwrap().unwrap();
    // 5.2.2: AT+CONFIG=2 keeps the RUN baud, so the host never switches.
    assert_eq!(bauds, [921_600]);
    assert_eq!(report.retries, 0);
    assert_eq!(sim.stored("GNSS_RX_PROTOCOL_RAW"), Some("5"));
    assert!(!sim.locked());
    assert_eq!(sim.state(), ModuleState::Run);
}
