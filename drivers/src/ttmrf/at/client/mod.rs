//! Sans-IO configuration client: brings the module into a wanted configuration and back to RUN.
//!
//! Inputs are the module's bytes ([`ConfigClient::handle_bytes`]) and the passage of time
//! ([`ConfigClient::handle_timeout`]); `now` is any monotonic clock, passed in. Outputs come
//! from [`ConfigClient::poll_output`] in the order they must be applied: bytes to send, baud
//! changes of the host's port, and the final result. [`ConfigClient::poll_timeout`] says when to
//! call `handle_timeout` next.
//!
//! The cycle (manual 4.2, 5.1, 5.2):
//! 1. `AT+CONFIG=1` at the RUN baud; on `AT+RUN_END` (or `AT+OK`) switch to 115200 and wait for
//!    `AT+CONFIG_START`. If nothing arrives, probe with `AT+CONFIG?` at 115200 (the module may
//!    already be in CONFIGURATION, or the state messages were lost), then retry. A module found
//!    in BOOTLOADER (`AT+BOOTLOADER_START`, or `AT+ERROR` to the probe at 115200) is released to
//!    RUN with `AT+LOCK=0` (4.2.1) and the entry retried.
//! 2. Read `SERIAL_NUMBER`, `FIRMWARE_VERSION` and `BAUDRATE` (to know the RUN baud to return to).
//! 3. For each wanted setting: read it; if it differs, write it, then read it back to verify.
//! 4. `AT+LOCK=0`: `AT+CONFIG=1` set the lock (5.2.3), which would hold the module in
//!    CONFIGURATION after its next reset. It is always cleared, also after a failure.
//! 5. `AT+CONFIG=0`; on `AT+CONFIG_END` (or `AT+OK`) switch to the RUN baud and wait for
//!    `AT+RUN_START`. If it does not come, probe at 115200 whether the module is still in
//!    CONFIGURATION and retry the exit.
//!
//! With [`ClientConfig::config_mode`] = `ConfigAsSet` the client sends `AT+CONFIG=2` and every
//! "115200" above reads "the RUN baud" (5.2.2). When the RUN baud is unknown, [`ClientConfig::baud_search`] tries each documented `BAUDRATE`
//! value in turn.
//!
//! Every request has a timeout and a bounded number of retries. Once `AT+CONFIG=1` has been sent,
//! any failure (rejected write, verify mismatch, timeouts, [`ConfigClient::abort`]) runs the same
//! clean-up: `AT+LOCK=0`, `AT+CONFIG=0`, back to the RUN baud. Settings written before the failure
//! are saved by the module on leaving CONFIGURATION (4.1.3); the report lists them.
//!
//! ```
//! use std::time::Duration;
//! use vigil_drivers::ttmrf::at::{ClientConfig, ConfigClient, DecodedProtocol, Output, Setting};
//!
//! let wanted = vec![Setting::adsb_decoded(DecodedProtocol::Json), Setting::gnss_nmea(true)];
//! let mut client = ConfigClient::new(wanted, ClientConfig::default());
//! client.start(Duration::ZERO);
//! // The host loop: apply outputs in order, feed received bytes, honour the deadline.
//! assert_eq!(client.poll_output(), Some(Output::SetBaud(921_600)));
//! assert_eq!(client.poll_output(), Some(Output::Send(b"AT+CONFIG=1\r\n".to_vec())));
//! client.handle_bytes(b"AT+OK\r\nAT+RUN_END\r\n", Duration::from_millis(3));
//! assert_eq!(client.poll_output(), Some(Output::SetBaud(115_200)));
//! assert_eq!(client.poll_timeout(), Some(Duration::from_millis(3003)));
//! ```

use std::collections::VecDeque;
use std::time::Duration;

use bytes::BytesMut;
use serde::Serialize;

use super::command::{AtCommand, ConfigMode};
use super::response::{AtDecoder, AtResponse, StateEvent};
use super::settings::{Baudrate, CONFIG_BAUD, Setting, SettingId};
use super::state::ModuleState;
use crate::DeviceDecoder;

/// Timeouts and retries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClientConfig {
    /// Wait for the answer to a command.
    pub response_timeout: Duration,
    /// Wait for a state change (RUN <-> CONFIGURATION), which includes saving settings.
    pub transition_timeout: Duration,
    /// Attempts per request before giving up.
    pub attempts: u8,
    /// The baud the host's port is at when the client starts (the module's RUN baud, if known).
    pub initial_baud: u32,
    /// When the RUN baud is not known for sure: each entry attempt uses the next `BAUDRATE`
    /// value (`initial_baud` first, then 115200, 921600, 3000000, 57600), with at least four
    /// entry attempts so every documented baud is tried.
    pub baud_search: bool,
    /// How to enter CONFIGURATION: `Config115200` (`AT+CONFIG=1`, the manual's example) or
    /// `ConfigAsSet` (`AT+CONFIG=2`, stays at the RUN baud: for links that cannot change baud).
    /// `Run` is taken as `Config115200`.
    pub config_mode: ConfigMode,
}

impl Default for ClientConfig {
    fn default() -> Self {
        Self {
            response_timeout: Duration::from_millis(500),
            transition_timeout: Duration::from_secs(3),
            attempts: 3,
            initial_baud: Baudrate::B921600.bps(),
            baud_search: false,
            config_mode: ConfigMode::Config115200,
        }
    }
}

/// What the host must do next.
#[derive(Debug, Clone, PartialEq)]
pub enum Output {
    /// Write these bytes to the port at the current baud.
    Send(Vec<u8>),
    /// Switch the host's port to this baud (bytes received before belong to the old baud).
    SetBaud(u32),
    /// The cycle ended.
    Finished(Result<ConfigReport, ConfigFailure>),
}

/// A setting the client changed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SettingChange {
    /// Which setting.
    pub id: SettingId,
    /// Value read before (None when it could not be read or parsed).
    pub from: Option<String>,
    /// Value written and read back.
    pub to: i64,
}

/// What the client found and changed.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct ConfigReport {
    /// `AT+SERIAL_NUMBER?`.
    pub serial_number: Option<String>,
    /// `AT+FIRMWARE_VERSION?`.
    pub firmware_version: Option<String>,
    /// Value of each wanted setting as found (text as sent by the module).
    pub found: Vec<(SettingId, Option<String>)>,
    /// Settings written and verified.
    pub changed: Vec<SettingChange>,
    /// RUN baud the module returned to, bps.
    pub run_baud: u32,
    /// Whether the module acknowledged `AT+LOCK=0`.
    pub lock_cleared: bool,
    /// Whether `AT+RUN_START` was seen at the end.
    pub run_confirmed: bool,
    /// Requests sent again after a timeout.
    pub retries: u32,
    /// Things that did not stop the cycle but deserve a look.
    pub warnings: Vec<String>,
}

/// Why the cycle failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ConfigError {
    /// The module did not enter CONFIGURATION.
    #[error("ttmrf control: module did not enter configuration state after {0} attempts")]
    EnterTimeout(u8),
    /// The module reported BOOTLOADER state.
    #[error("ttmrf control: module is in bootloader state")]
    Bootloader,
    /// A command got no answer.
    #[error("ttmrf control: no answer to {command} after {attempts} attempts")]
    Timeout {
        /// The command.
        command: String,
        /// Attempts made.
        attempts: u8,
    },
    /// The module answered `AT+ERROR`.
    #[error("ttmrf control: {command} rejected: {description}")]
    Rejected {
        /// The command.
        command: String,
        /// The module's description.
        description: String,
    },
    /// The value read back differs from the value written.
    #[error("ttmrf control: {setting} reads back '{read}' after writing {wanted}")]
    VerifyFailed {
        /// The setting.
        setting: SettingId,
        /// Value written.
        wanted: i64,
        /// Value read back.
        read: String,
    },
    /// The host aborted.
    #[error("ttmrf control: aborted")]
    Aborted,
}

/// A failed cycle: the error and what had been done.
#[derive(Debug, Clone, PartialEq)]
pub struct ConfigFailure {
    /// The first error.
    pub error: ConfigError,
    /// What was found and changed before it (including the clean-up's lock and RUN flags).
    pub report: ConfigReport,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Phase {
    Idle,
    /// Sent AT+CONFIG=1 at the RUN baud.
    EnterSent,
    /// At 115200, waiting for AT+CONFIG_START.
    EnterWaitStart,
    /// At 115200, sent AT+CONFIG?.
    EnterProbe,
    /// The module is in BOOTLOADER: at 115200, sent AT+LOCK=0 to let it go to RUN.
    BootRelease,
    /// At the RUN baud, waiting for AT+RUN_START after leaving BOOTLOADER.
    BootWaitRun,
    /// Reading identity item `i` (0 serial, 1 firmware, 2 baudrate).
    Identify(usize),
    /// Reading wanted setting `i`.
    Read(usize),
    /// Writing wanted setting `i`.
    Write(usize),
    /// Reading back wanted setting `i`.
    Verify(usize),
    /// Sent AT+LOCK=0.
    Unlock,
    /// Sent AT+CONFIG=0 at 115200.
    ExitSent,
    /// At the RUN baud, waiting for AT+RUN_START.
    ExitWaitRun,
    /// At 115200 again, sent AT+CONFIG? to see whether the exit happened.
    ExitProbe,
    Done,
}

/// The configuration client.
#[derive(Debug)]
pub struct ConfigClient {
    cfg: ClientConfig,
    wanted: Vec<Setting>,
    phase: Phase,
    attempt: u8,
    deadline: Option<Duration>,
    baud: u32,
    run_baud: u32,
    entered: bool,
    cleaning: bool,
    error: Option<ConfigError>,
    report: ConfigReport,
    decoder: AtDecoder,
    rx: BytesMut,
    out: VecDeque<Output>,
}

const IDENTITY: [&str; 3] = ["SERIAL_NUMBER", "FIRMWARE_VERSION", "BAUDRATE"];

impl ConfigClient {
    /// A client that will make the module's settings equal `wanted`.
    pub fn new(wanted: Vec<Setting>, cfg: ClientConfig) -> Self {
        Self {
            cfg,
            wanted,
            phase: Phase::Idle,
            attempt: 0,
            deadline: None,
            baud: cfg.initial_baud,
            run_baud: cfg.initial_baud,
            entered: false,
            cleaning: false,
            error: None,
            report: ConfigReport::default(),
            decoder: AtDecoder::new(),
            rx: BytesMut::new(),
            out: VecDeque::new(),
        }
    }

    /// Starts the cycle.
    pub fn start(&mut self, now: Duration) {
        if self.phase != Phase::Idle {
            return;
        }
        self.attempt = 1;
        self.out.push_back(Output::SetBaud(self.baud));
        self.send_enter(now);
    }

    /// The baud the host's port should be at.
    pub fn baud(&self) -> u32 {
        self.baud
    }

    /// Whether the cycle ended.
    pub fn is_finished(&self) -> bool {
        self.phase == Phase::Done
    }

    /// When to call [`ConfigClient::handle_timeout`] next.
    pub fn poll_timeout(&self) -> Option<Duration> {
        self.deadline
    }

    /// The next thing to do.
    pub fn poll_output(&mut self) -> Option<Output> {
        self.out.pop_front()
    }

    /// Bytes received from the module at the current baud.
    pub fn handle_bytes(&mut self, bytes: &[u8], now: Duration) {
        self.rx.extend_from_slice(bytes);
        while let Some(r) = self.decoder.decode(&mut self.rx) {
            self.handle_response(&r, now);
        }
    }

    /// Stops the cycle; if the module is in CONFIGURATION, it is unlocked and sent back to RUN.
    pub fn abort(&mut self, now: Duration) {
        if matches!(self.phase, Phase::Idle | Phase::Done) {
            return;
        }
        self.fail(ConfigError::Aborted, now);
    }

    fn set_baud(&mut self, baud: u32) {
        if baud != self.baud {
            self.baud = baud;
            self.out.push_back(Output::SetBaud(baud));
            // Bytes buffered at the old baud are garbage at the new one.
            self.rx.clear();
            self.decoder.reset_framing();
        }
    }

    fn send(&mut self, cmd: &AtCommand, now: Duration, timeout: Duration) {
        self.out.push_back(Output::Send(cmd.to_line().into_bytes()));
        self.deadline = Some(now + timeout);
    }

    /// The `AT+CONFIG` value used to enter CONFIGURATION.
    fn config_mode(&self) -> ConfigMode {
        match self.cfg.config_mode {
            ConfigMode::Run => ConfigMode::Config115200,
            m => m,
        }
    }

    /// The baud of CONFIGURATION state with that mode (5.2.2).
    fn config_baud(&self) -> u32 {
        ModuleState::Configuration.baud(self.config_mode(), self.run_baud)
    }

    /// Attempts at entering CONFIGURATION.
    fn entry_attempts(&self) -> u8 {
        if self.cfg.baud_search {
            self.cfg.attempts.max(4)
        } else {
            self.cfg.attempts
        }
    }

    /// The RUN baud to try on the current entry attempt.
    fn entry_baud(&self) -> u32 {
        if !self.cfg.baud_search {
            return self.run_baud;
        }
        let mut candidates = vec![self.cfg.initial_baud];
        for b in [
            Baudrate::B115200,
            Baudrate::B921600,
            Baudrate::B3000000,
            Baudrate::B57600,
        ] {
            if b.bps() != self.cfg.initial_baud {
                candidates.push(b.bps());
            }
        }
        candidates[usize::from(self.attempt.saturating_sub(1)) % candidates.len()]
    }

    fn send_enter(&mut self, now: Duration) {
        self.run_baud = self.entry_baud();
        self.set_baud(self.run_baud);
        self.entered = true; // from here on the module may be in CONFIGURATION (and locked)
        self.phase = Phase::EnterSent;
        self.send(
            &AtCommand::Config(self.config_mode()),
            now,
            self.cfg.transition_timeout,
        );
    }

    fn request(&mut self, phase: Phase, now: Duration) {
        self.phase = phase;
        let t = self.cfg.response_timeout;
        let cmd = match phase {
            Phase::Identify(i) => AtCommand::Other(format!("{}?", IDENTITY[i])),
            Phase::Read(i) | Phase::Verify(i) => AtCommand::Read(self.wanted[i].id()),
            Phase::Write(i) => AtCommand::Write(self.wanted[i]),
            Phase::Unlock | Phase::BootRelease => AtCommand::Lock(false),
            Phase::EnterProbe | Phase::ExitProbe => AtCommand::ConfigQuery,
            Phase::ExitSent => {
                self.send(
                    &AtCommand::Config(ConfigMode::Run),
                    now,
                    self.cfg.transition_timeout,
                );
                return;
            }
            _ => return,
        };
        self.send(&cmd, now, t);
    }

    /// Moves to `phase` with a fresh attempt counter and sends its request.
    fn next(&mut self, phase: Phase, now: Duration) {
        self.attempt = 1;
        self.request(phase, now);
    }

    fn after_identify(&mut self, now: Duration) {
        if self.wanted.is_empty() {
            self.next(Phase::Unlock, now);
        } else {
            self.next(Phase::Read(0), now);
        }
    }

    fn after_setting(&mut self, i: usize, now: Duration) {
        if i + 1 < self.wanted.len() {
            self.next(Phase::Read(i + 1), now);
        } else {
            self.next(Phase::Unlock, now);
        }
    }

    fn fail(&mut self, error: ConfigError, now: Duration) {
        if self.error.is_none() {
            self.error = Some(error);
        }
        if self.entered && !self.cleaning {
            self.cleaning = true;
            self.set_baud(self.config_baud());
            self.next(Phase::Unlock, now);
        } else if !self.cleaning || self.phase == Phase::Done {
            self.finish();
        } else {
            // Already cleaning: carry on with the clean-up.
        }
    }

    fn finish(&mut self) {
        self.phase = Phase::Done;
        self.deadline = None;
        self.report.run_baud = self.run_baud;
        let report = self.report.clone();
        let result = match self.error.take() {
            None => Ok(report),
            Some(error) => Err(ConfigFailure { error, report }),
        };
        self.out.push_back(Output::Finished(result));
    }

    fn wanted_name(&self, i: usize) -> &'static str {
        self.wanted[i].id().name()
    }

    /// Handles one line from the module: a `AT+BOOTLOADER_START` whatever the phase, otherwise
    /// the line as an answer in the current phase (the steps of the cycle in the module
    /// documentation: entry, identity, settings, exit). A line a phase does not expect is
    /// ignored; its timeout decides.
    pub fn handle_response(&mut self, r: &AtResponse, now: Duration) {
        if let AtResponse::State {
            event: StateEvent::BootloaderStart,
        } = r
        {
            self.on_bootloader_start(now);
            return;
        }
        match self.phase {
            Phase::Idle | Phase::Done => {}
            Phase::EnterSent
            | Phase::EnterWaitStart
            | Phase::EnterProbe
            | Phase::BootRelease
            | Phase::BootWaitRun => self.on_entry_answer(r, now),
            Phase::Identify(i) => self.on_identity_answer(i, r, now),
            Phase::Read(i) => self.on_read_answer(i, r, now),
            Phase::Write(i) => self.on_write_answer(i, r, now),
            Phase::Verify(i) => self.on_verify_answer(i, r, now),
            Phase::Unlock | Phase::ExitSent | Phase::ExitWaitRun | Phase::ExitProbe => {
                self.on_exit_answer(r, now)
            }
        }
    }

    /// `AT+BOOTLOADER_START`: while entering, the module is released to RUN and the entry
    /// retried; while configuring, the cycle fails (the module left CONFIGURATION for it); while
    /// cleaning up or already handling the bootloader, it changes nothing.
    fn on_bootloader_start(&mut self, now: Duration) {
        match self.phase {
            Phase::EnterSent | Phase::EnterWaitStart | Phase::EnterProbe => {
                self.release_bootloader(now)
            }
            Phase::Idle | Phase::Done | Phase::BootRelease | Phase::BootWaitRun => {}
            _ if !self.cleaning => self.fail(ConfigError::Bootloader, now),
            _ => {}
        }
    }

    /// Step 1, entering CONFIGURATION (and leaving a BOOTLOADER found on the way): the
    /// acknowledgement of `AT+CONFIG=1` switches to the configuration baud; `AT+CONFIG_START`
    /// (or the probe's `CONFIG=1|2`) means entered; an `AT+ERROR` or `BOOT=1` to the probe
    /// means the BOOTLOADER.
    fn on_entry_answer(&mut self, r: &AtResponse, now: Duration) {
        let state = state_event(r);
        match self.phase {
            Phase::EnterSent => match (r, state) {
                (_, Some(StateEvent::ConfigStart)) => self.entered_config(now),
                (AtResponse::Ok, _) | (_, Some(StateEvent::RunEnd)) => {
                    self.set_baud(self.config_baud());
                    self.phase = Phase::EnterWaitStart;
                    self.deadline = Some(now + self.cfg.transition_timeout);
                }
                _ => {}
            },
            Phase::EnterWaitStart if state == Some(StateEvent::ConfigStart) => {
                self.entered_config(now)
            }
            Phase::EnterProbe => {
                if state == Some(StateEvent::ConfigStart)
                    || r.value_of("CONFIG").is_some_and(|v| v == "1" || v == "2")
                {
                    self.entered_config(now);
                } else if error_description(r).is_some() || r.value_of("BOOT") == Some("1") {
                    // Something at 115200 that refuses AT+CONFIG?: the BOOTLOADER (5.2.1).
                    self.release_bootloader(now);
                }
            }
            Phase::BootRelease if *r == AtResponse::Ok => {
                self.set_baud(self.run_baud);
                self.phase = Phase::BootWaitRun;
                self.deadline = Some(now + self.cfg.transition_timeout);
            }
            Phase::BootWaitRun if state == Some(StateEvent::RunStart) => self.retry_enter(now),
            // Another line in an entry phase, or not an entry phase (see `handle_response`).
            _ => {}
        }
    }

    /// Step 2, identity item `i`: the value is recorded (the `BAUDRATE` becomes the RUN baud to
    /// return to, when it is a documented value); an `AT+ERROR` is only a warning, since the
    /// cycle can go on without it.
    fn on_identity_answer(&mut self, i: usize, r: &AtResponse, now: Duration) {
        if let Some(v) = r.value_of(IDENTITY[i]) {
            let v = v.trim().to_owned();
            match i {
                0 => self.report.serial_number = Some(v),
                1 => self.report.firmware_version = Some(v),
                _ => match v.parse::<i64>().ok().and_then(Baudrate::from_value) {
                    Some(b) => self.run_baud = b.bps(),
                    None => self.report.warnings.push(format!(
                        "BAUDRATE reads '{v}'; keeping {} bps",
                        self.run_baud
                    )),
                },
            }
            self.identify_next(i, now);
        } else if error_description(r).is_some() {
            self.report
                .warnings
                .push(format!("{} not available", IDENTITY[i]));
            self.identify_next(i, now);
        }
    }

    /// Step 3, reading wanted setting `i`: the value found is recorded; equal to the wanted one,
    /// the next setting, else it is written. An `AT+ERROR` fails the cycle.
    fn on_read_answer(&mut self, i: usize, r: &AtResponse, now: Duration) {
        let name = self.wanted_name(i);
        if let Some(v) = r.value_of(name) {
            let v = v.trim().to_owned();
            let want = self.wanted[i];
            self.report.found.push((want.id(), Some(v.clone())));
            if v.parse::<i64>().ok() == Some(want.value()) {
                self.after_setting(i, now);
            } else {
                self.next(Phase::Write(i), now);
            }
        } else if let Some(d) = error_description(r) {
            self.fail(
                ConfigError::Rejected {
                    command: format!("AT+{name}?"),
                    description: d,
                },
                now,
            );
        }
    }

    /// Step 3, writing wanted setting `i`: acknowledged, it is read back; an `AT+ERROR` fails the
    /// cycle.
    fn on_write_answer(&mut self, i: usize, r: &AtResponse, now: Duration) {
        if *r == AtResponse::Ok {
            // Keep the attempt count: write + read back is one attempt.
            self.request(Phase::Verify(i), now);
        } else if let Some(d) = error_description(r) {
            let command = AtCommand::Write(self.wanted[i]).body();
            self.fail(
                ConfigError::Rejected {
                    command: format!("AT+{command}"),
                    description: d,
                },
                now,
            );
        }
    }

    /// Step 3, reading back wanted setting `i`: equal to the value written, the change is
    /// recorded (a new `BAUDRATE` becomes the RUN baud to return to); different, the write is
    /// repeated while attempts remain, then the cycle fails.
    fn on_verify_answer(&mut self, i: usize, r: &AtResponse, now: Duration) {
        let Some(v) = r.value_of(self.wanted_name(i)) else {
            return;
        };
        let v = v.trim().to_owned();
        let want = self.wanted[i];
        if v.parse::<i64>().ok() == Some(want.value()) {
            self.record_change(want);
            self.after_setting(i, now);
        } else if self.attempt < self.cfg.attempts {
            self.attempt += 1;
            self.report.retries += 1;
            self.request(Phase::Write(i), now);
        } else {
            self.fail(
                ConfigError::VerifyFailed {
                    setting: want.id(),
                    wanted: want.value(),
                    read: v,
                },
                now,
            );
        }
    }

    /// Records the verified write of `want`, with the value found before it.
    fn record_change(&mut self, want: Setting) {
        let from = self
            .report
            .found
            .iter()
            .rev()
            .find(|(id, _)| *id == want.id())
            .and_then(|(_, v)| v.clone());
        self.report.changed.push(SettingChange {
            id: want.id(),
            from,
            to: want.value(),
        });
        if let Some(b) = want.as_baudrate() {
            self.run_baud = b.bps();
        }
    }

    /// Steps 4 and 5, unlocking and leaving CONFIGURATION: `AT+LOCK=0` answered either way leads
    /// to the exit (an `AT+ERROR` is a warning); the exit's acknowledgement switches to the RUN
    /// baud; `AT+RUN_START` ends the cycle; a probe still reading `CONFIG=1|2` retries the exit.
    fn on_exit_answer(&mut self, r: &AtResponse, now: Duration) {
        let state = state_event(r);
        match self.phase {
            Phase::Unlock => {
                if *r == AtResponse::Ok {
                    self.report.lock_cleared = true;
                    self.next(Phase::ExitSent, now);
                } else if error_description(r).is_some() {
                    self.report
                        .warnings
                        .push("AT+LOCK=0 answered AT+ERROR".into());
                    self.next(Phase::ExitSent, now);
                }
            }
            Phase::ExitSent => {
                if *r == AtResponse::Ok || state == Some(StateEvent::ConfigEnd) {
                    self.set_baud(self.run_baud);
                    self.phase = Phase::ExitWaitRun;
                    self.deadline = Some(now + self.cfg.transition_timeout);
                } else if state == Some(StateEvent::RunStart) {
                    self.run_started();
                }
            }
            Phase::ExitWaitRun if state == Some(StateEvent::RunStart) => self.run_started(),
            // Still in CONFIGURATION: try the exit again.
            Phase::ExitProbe if r.value_of("CONFIG").is_some_and(|v| v == "1" || v == "2") => {
                if self.attempt < self.cfg.attempts {
                    self.attempt += 1;
                    self.report.retries += 1;
                    self.request(Phase::ExitSent, now);
                } else {
                    self.give_up_exit("module stays in configuration state");
                }
            }
            // Another line in an exit phase, or not an exit phase (see `handle_response`).
            _ => {}
        }
    }

    /// The module is in BOOTLOADER (possibly locked there): release it to RUN with `AT+LOCK=0`
    /// (4.2.1), then enter CONFIGURATION again. Counts as an attempt.
    fn release_bootloader(&mut self, now: Duration) {
        self.report
            .warnings
            .push("module found in bootloader state; released it with AT+LOCK=0".into());
        self.set_baud(CONFIG_BAUD);
        self.request(Phase::BootRelease, now);
    }

    /// Another attempt at entering CONFIGURATION, or the failure when attempts are used up.
    fn retry_enter(&mut self, now: Duration) {
        if self.attempt < self.entry_attempts() {
            self.attempt += 1;
            self.report.retries += 1;
            self.send_enter(now);
        } else {
            let n = self.attempt;
            self.fail(ConfigError::EnterTimeout(n), now);
        }
    }

    fn identify_next(&mut self, i: usize, now: Duration) {
        if i + 1 < IDENTITY.len() {
            self.next(Phase::Identify(i + 1), now);
        } else {
            self.after_identify(now);
        }
    }

    fn entered_config(&mut self, now: Duration) {
        if self.cleaning {
            return;
        }
        self.next(Phase::Identify(0), now);
    }

    fn run_started(&mut self) {
        self.report.run_confirmed = true;
        self.finish();
    }

    fn give_up_exit(&mut self, why: &str) {
        self.report.warnings.push(why.to_owned());
        if self.error.is_none() {
            self.error = Some(ConfigError::Timeout {
                command: "AT+CONFIG=0".into(),
                attempts: self.attempt,
            });
        }
        self.set_baud(self.run_baud);
        self.finish();
    }

    /// Advances the timers; call at or after [`ConfigClient::poll_timeout`].
    pub fn handle_timeout(&mut self, now: Duration) {
        let Some(deadline) = self.deadline else {
            return;
        };
        if now < deadline {
            return;
        }
        self.deadline = None;
        let retry = self.attempt < self.cfg.attempts;
        match self.phase {
            Phase::Idle | Phase::Done => {}
            Phase::EnterSent | Phase::EnterWaitStart => {
                // The state messages may have been lost: ask at 115200.
                self.set_baud(self.config_baud());
                self.request(Phase::EnterProbe, now);
            }
            Phase::EnterProbe | Phase::BootRelease | Phase::BootWaitRun => self.retry_enter(now),
            Phase::Identify(i) => {
                if retry {
                    self.attempt += 1;
                    self.report.retries += 1;
                    self.request(Phase::Identify(i), now);
                } else {
                    self.report
                        .warnings
                        .push(format!("no answer to AT+{}?", IDENTITY[i]));
                    self.identify_next(i, now);
                }
            }
            Phase::Read(_) | Phase::Write(_) | Phase::Verify(_) | Phase::Unlock => {
                if retry {
                    self.attempt += 1;
                    self.report.retries += 1;
                    self.request(self.phase, now);
                } else if self.phase == Phase::Unlock {
                    self.report.warnings.push("no answer to AT+LOCK=0".into());
                    self.next(Phase::ExitSent, now);
                } else {
                    let command = match self.phase {
                        Phase::Write(i) => {
                            format!("AT+{}", AtCommand::Write(self.wanted[i]).body())
                        }
                        Phase::Read(i) | Phase::Verify(i) => format!("AT+{}?", self.wanted_name(i)),
                        _ => String::new(),
                    };
                    let attempts = self.attempt;
                    self.fail(ConfigError::Timeout { command, attempts }, now);
                }
            }
            Phase::ExitSent => {
                if retry {
                    self.attempt += 1;
                    self.report.retries += 1;
                    self.request(Phase::ExitSent, now);
                } else {
                    self.give_up_exit("no answer to AT+CONFIG=0");
                }
            }
            Phase::ExitWaitRun => {
                // No AT+RUN_START: check at 115200 whether the module is still configuring.
                self.set_baud(self.config_baud());
                self.request(Phase::ExitProbe, now);
            }
            Phase::ExitProbe => {
                // No answer at 115200: the module left CONFIGURATION (its RUN_START was lost).
                self.report
                    .warnings
                    .push("AT+RUN_START not seen; module no longer answers at 115200".into());
                self.set_baud(self.run_baud);
                self.finish();
            }
        }
    }
}

/// The description of an `AT+ERROR` line (empty when it has none); `None` for any other line.
fn error_description(r: &AtResponse) -> Option<String> {
    match r {
        AtResponse::Error { description } => Some(description.clone().unwrap_or_default()),
        _ => None,
    }
}

/// The state event of a state line, `None` for any other line.
fn state_event(r: &AtResponse) -> Option<StateEvent> {
    match r {
        AtResponse::State { event } => Some(*event),
        _ => None,
    }
}

#[cfg(test)]
mod tests;
