//! A simulated TT-Multi-RF that answers AT commands (manual 4, 5) well enough to take the
//! drivers' configuration client through a full cycle.
//!
//! Sans-IO like the client: [`SimModule::receive`] takes the host's bytes together with the baud
//! the host sends at; bytes at a baud other than the module's current one arrive garbled and are
//! dropped (counted). [`SimModule::poll_output`] yields each line the module sends with the baud
//! it is sent at, so a test harness can deliver only what the host's port would decode.
//!
//! Modelled: the three states and their messages and bauds (drivers' `at::state`), the case rules
//! (upper case only in BOOTLOADER), the three line endings, range-checked writes
//! (`AT+ERROR (...)`), reads, descriptions, `AT+SETTINGS?`, the lock (set by `AT+CONFIG=1` and
//! `AT+REBOOT_BOOTLOADER`, which holds the module in CONFIGURATION/BOOTLOADER across a power
//! cycle), saving settings to "non-volatile memory" on leaving CONFIGURATION, and faults for
//! tests (lost lines, a setting that does not take a value).

use std::collections::{BTreeMap, VecDeque};

use vigil_drivers::ttmrf::at::state::transition_messages;
use vigil_drivers::ttmrf::at::{
    AtCommand, AtResponse, Baudrate, CONFIG_BAUD, ConfigMode, ModuleState, SettingId,
};
use vigil_drivers::ttmrf::csv::CsvMessage;

/// Faults the simulated module can inject.
#[derive(Debug, Clone, Default)]
pub struct SimFaults {
    /// Drop this many of the next lines the module sends (lost on the wire).
    pub drop_next_lines: usize,
    /// A setting that answers `AT+OK` to a write but keeps its old value.
    pub stuck_setting: Option<SettingId>,
}

/// The simulated module.
#[derive(Debug, Clone)]
pub struct SimModule {
    state: ModuleState,
    config_mode: ConfigMode,
    /// Settings in non-volatile memory.
    stored: BTreeMap<String, String>,
    /// Settings being edited in CONFIGURATION.
    working: BTreeMap<String, String>,
    locked: bool,
    serial: String,
    firmware: String,
    rx: Vec<u8>,
    out: VecDeque<(u32, Vec<u8>)>,
    /// Faults to inject.
    pub faults: SimFaults,
    /// Bytes dropped because the host sent at the wrong baud.
    pub garbled_bytes: usize,
    /// Lines received and understood.
    pub commands_seen: usize,
}

impl SimModule {
    /// A module in RUN state with the documented defaults (undocumented ones as in the 5.2.2
    /// example listing) and RUN baud 921600.
    pub fn new(serial: &str, firmware: &str) -> Self {
        let mut stored = BTreeMap::new();
        for id in SettingId::ALL {
            let v = id.spec().default.unwrap_or(id.spec().min);
            stored.insert(id.name().to_owned(), v.to_string());
        }
        stored.insert("BAUDRATE".into(), (Baudrate::B921600 as i64).to_string());
        stored.insert("ADSB_TX_ICAO".into(), "000000".into());
        Self {
            state: ModuleState::Run,
            config_mode: ConfigMode::Run,
            working: stored.clone(),
            stored,
            locked: false,
            serial: serial.to_owned(),
            firmware: firmware.to_owned(),
            rx: Vec::new(),
            out: VecDeque::new(),
            faults: SimFaults::default(),
            garbled_bytes: 0,
            commands_seen: 0,
        }
    }

    /// Current state.
    pub fn state(&self) -> ModuleState {
        self.state
    }

    /// Whether the lock is set.
    pub fn locked(&self) -> bool {
        self.locked
    }

    /// A setting's stored (non-volatile) value.
    pub fn stored(&self, name: &str) -> Option<&str> {
        self.stored.get(name).map(String::as_str)
    }

    /// Sets a stored value directly (test set-up).
    pub fn set_stored(&mut self, name: &str, value: &str) {
        self.stored.insert(name.to_owned(), value.to_owned());
        self.working = self.stored.clone();
    }

    /// RUN baud from the stored `BAUDRATE`.
    pub fn run_baud(&self) -> u32 {
        self.stored("BAUDRATE")
            .and_then(|v| v.parse().ok())
            .and_then(Baudrate::from_value)
            .unwrap_or(Baudrate::B921600)
            .bps()
    }

    /// Baud of the module's UART now.
    pub fn baud(&self) -> u32 {
        self.state.baud(self.config_mode, self.run_baud())
    }

    /// Power cycle: BOOTLOADER, then RUN unless locked (4.1.1, 4.2.1).
    pub fn power_cycle(&mut self) {
        self.rx.clear();
        self.working = self.stored.clone();
        self.config_mode = ConfigMode::Run;
        self.enter(ModuleState::Bootloader);
        if !self.locked {
            self.enter(ModuleState::Run);
        }
    }

    /// Sends a traffic line (in RUN state only, at the RUN baud), encoded by the drivers' CSV
    /// encoder. Returns whether it was sent.
    pub fn emit_traffic(&mut self, msg: &CsvMessage) -> bool {
        self.emit_line(msg.to_line().as_bytes())
    }

    /// Sends any output line of the RUN state (JSON from `JsonMessage::to_wire`, NMEA from
    /// `NmeaSentence::to_line`, ...) at the RUN baud. Returns whether it was sent.
    pub fn emit_line(&mut self, line: &[u8]) -> bool {
        if self.state != ModuleState::Run {
            return false;
        }
        let baud = self.run_baud();
        self.out.push_back((baud, line.to_vec()));
        true
    }

    /// The next line the module sends, with its baud.
    pub fn poll_output(&mut self) -> Option<(u32, Vec<u8>)> {
        self.out.pop_front()
    }

    /// Bytes from the host, sent at `host_baud`.
    pub fn receive(&mut self, bytes: &[u8], host_baud: u32) {
        if host_baud != self.baud() {
            self.garbled_bytes += bytes.len();
            return;
        }
        for &b in bytes {
            if b == b'\r' || b == b'\n' {
                // "\n", "\r" and "\r\n" all end a command (5.1.5); the empty line between the
                // two bytes of "\r\n" is ignored.
                let line = std::mem::take(&mut self.rx);
                if !line.is_empty() {
                    self.command(&line);
                }
            } else if self.rx.len() < 256 {
                self.rx.push(b);
            }
        }
    }

    fn send(&mut self, r: AtResponse) {
        let baud = self.baud();
        self.send_at(r, baud);
    }

    fn send_at(&mut self, r: AtResponse, baud: u32) {
        if self.faults.drop_next_lines > 0 {
            self.faults.drop_next_lines -= 1;
            return;
        }
        self.out.push_back((baud, r.to_line().into_bytes()));
    }

    fn error(&mut self, why: &str) {
        self.send(AtResponse::Error {
            description: Some(why.to_owned()),
        });
    }

    fn value(&mut self, name: &str, value: String) {
        self.send(AtResponse::Value {
            name: name.to_owned(),
            value,
        });
    }

    fn enter(&mut self, to: ModuleState) {
        // Each state message goes out at the baud the manual gives for it (4.2).
        for (event, baud) in transition_messages(self.state, to, self.config_mode, self.run_baud())
        {
            self.send_at(AtResponse::State { event }, baud);
        }
        self.state = to;
    }

    /// One line from the host: parsed, counted, checked against the state, then executed. A line
    /// it cannot take is ignored in RUN and answered with `AT+ERROR` in the other states.
    fn command(&mut self, line: &[u8]) {
        let Ok(text) = std::str::from_utf8(line) else {
            return;
        };
        let cmd = match AtCommand::parse(text, self.state.upper_case_only()) {
            Ok(c) => c,
            Err(e) => {
                if self.state != ModuleState::Run {
                    self.error(&e.to_string());
                }
                return;
            }
        };
        self.commands_seen += 1;
        if !self.state.accepts(&cmd) {
            if self.state != ModuleState::Run {
                self.error("Command not available in this state");
            }
            return;
        }
        self.execute(cmd);
    }

    /// Executes a command the current state accepts.
    fn execute(&mut self, cmd: AtCommand) {
        match cmd {
            AtCommand::Config(mode) => self.config(mode),
            AtCommand::ConfigQuery => {
                let v = if self.state == ModuleState::Configuration {
                    self.config_mode as u8
                } else {
                    0
                };
                self.value("CONFIG", v.to_string());
            }
            AtCommand::Lock(on) => {
                self.locked = on;
                self.send(AtResponse::Ok);
                if !on && self.state == ModuleState::Bootloader {
                    self.enter(ModuleState::Run);
                }
            }
            AtCommand::LockQuery => self.value("LOCK", u8::from(self.locked).to_string()),
            AtCommand::BootQuery => {
                let v = u8::from(self.state == ModuleState::Bootloader);
                self.value("BOOT", v.to_string());
            }
            AtCommand::SerialNumberQuery => self.value("SERIAL_NUMBER", self.serial.clone()),
            AtCommand::FirmwareVersionQuery => {
                self.value("FIRMWARE_VERSION", self.firmware.clone())
            }
            AtCommand::Settings => self.list_settings(),
            AtCommand::Help => self.help(),
            AtCommand::SettingsDefault => {
                for id in SettingId::ALL {
                    if let Some(d) = id.spec().default {
                        self.working.insert(id.name().to_owned(), d.to_string());
                    }
                }
                self.send(AtResponse::Ok);
            }
            AtCommand::Read(id) => {
                let v = self.working.get(id.name()).cloned().unwrap_or_default();
                self.value(id.name(), v);
            }
            AtCommand::Describe(id) => self.describe(id),
            AtCommand::Write(setting) => {
                if self.faults.stuck_setting != Some(setting.id()) {
                    self.working
                        .insert(setting.id().name().to_owned(), setting.value().to_string());
                }
                self.send(AtResponse::Ok);
            }
            AtCommand::Other(body) => self.other(&body),
            AtCommand::Reboot => {
                self.stored = self.working.clone();
                self.power_cycle();
            }
            AtCommand::RebootBootloader => {
                self.locked = true;
                self.config_mode = ConfigMode::Run;
                self.enter(ModuleState::Bootloader);
            }
        }
    }

    /// `AT+CONFIG=n`. `AT+CONFIG=0` saves the working settings and returns to RUN. From RUN,
    /// 1 or 2 enters CONFIGURATION with the stored settings and sets the lock (5.2.3: "This
    /// command also sets lock."); in CONFIGURATION it only changes the mode.
    fn config(&mut self, mode: ConfigMode) {
        if mode == ConfigMode::Run {
            self.send(AtResponse::Ok);
            self.stored = self.working.clone();
            self.enter(ModuleState::Run);
            self.config_mode = ConfigMode::Run;
        } else if self.state == ModuleState::Run {
            self.send(AtResponse::Ok);
            self.locked = true; // 5.2.3: "This command also sets lock."
            self.config_mode = mode;
            self.working = self.stored.clone();
            self.enter(ModuleState::Configuration);
        } else {
            self.config_mode = mode;
            self.send(AtResponse::Ok);
        }
    }

    /// `AT+SETTINGS?`: every working setting as `AT+NAME=value`.
    fn list_settings(&mut self) {
        let lines: Vec<_> = self
            .working
            .iter()
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect();
        for (k, v) in lines {
            self.value(&k, v);
        }
    }

    /// `AT+HELP`: one line per documented setting, with its value and description.
    fn help(&mut self) {
        for id in SettingId::ALL {
            let line = format!(
                "AT+{}={} [{}]",
                id.name(),
                self.working[id.name()],
                id.spec().doc
            );
            self.send(AtResponse::Text { text: line });
        }
    }

    /// `AT+NAME=?`: the setting's description block.
    fn describe(&mut self, id: SettingId) {
        let s = id.spec();
        for line in [
            format!("Setting: {}", s.name),
            format!("Description: {}", s.doc),
            "Access: Read Write".to_owned(),
            "Type: Integer decimal".to_owned(),
            format!("Range (min.): {}", s.min),
            format!("Range (max.): {}", s.max),
        ] {
            self.send(AtResponse::Text { text: line });
        }
    }

    /// Any other `AT+...` text: a write or a read of a setting outside the tables that the
    /// module holds (such as `ADSB_TX_ICAO`), taken without a range check; anything else is an
    /// unknown command.
    fn other(&mut self, body: &str) {
        match body.split_once('=') {
            Some((name, v)) if self.working.contains_key(name) => {
                self.working.insert(name.to_owned(), v.to_owned());
                self.send(AtResponse::Ok);
            }
            _ => match body.strip_suffix('?') {
                Some(name) if self.working.contains_key(name) => {
                    let v = self.working[name].clone();
                    self.value(name, v);
                }
                _ => self.error("Unknown command"),
            },
        }
    }
}

/// Baud helper for harnesses: the configuration baud.
pub const SIM_CONFIG_BAUD: u32 = CONFIG_BAUD;

#[cfg(test)]
mod tests;
