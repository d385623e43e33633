//! The module's states and transitions (manual 3, 4.1, 4.2) and the baud each line travels at.
//!
//! ```text
//!  power on --> BOOTLOADER --(3 s, no lock; or AT+LOCK=0)--> RUN
//!  RUN --AT+CONFIG=1|2--> CONFIGURATION        sends AT+RUN_END (RUN baud), AT+CONFIG_START (config baud)
//!  CONFIGURATION --AT+CONFIG=0--> RUN          sends AT+CONFIG_END (config baud), AT+RUN_START (RUN baud)
//!  CONFIGURATION --AT+REBOOT_BOOTLOADER--> BOOTLOADER (locked)   sends AT+BOOTLOADER_START
//! ```
//!
//! BOOTLOADER and CONFIGURATION run at 115200 bps; RUN at the `BAUDRATE` setting. `AT+CONFIG=2`
//! keeps the RUN baud in CONFIGURATION (5.2.2). Both `AT+CONFIG=1` (5.2.3) and
//! `AT+REBOOT_BOOTLOADER` set the lock, which holds the module in CONFIGURATION/BOOTLOADER; a
//! host must clear it (`AT+LOCK=0`) or the module will not return to RUN by itself.

use serde::Serialize;

use super::command::{AtCommand, ConfigMode};
use super::response::StateEvent;
use super::settings::CONFIG_BAUD;

/// State of the module.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModuleState {
    /// Firmware update possible; 115200 bps, upper-case commands only.
    Bootloader,
    /// Receiving and reporting traffic at the `BAUDRATE` setting.
    Run,
    /// Settings can be changed; 115200 bps (or the RUN baud after `AT+CONFIG=2`).
    Configuration,
}

impl ModuleState {
    /// The baud of the UART in this state.
    pub fn baud(self, config_mode: ConfigMode, run_baud: u32) -> u32 {
        match self {
            ModuleState::Run => run_baud,
            ModuleState::Bootloader => CONFIG_BAUD,
            ModuleState::Configuration => match config_mode {
                ConfigMode::ConfigAsSet => run_baud,
                _ => CONFIG_BAUD,
            },
        }
    }

    /// Whether a command is documented for this state (5.2.1-5.2.3).
    pub fn accepts(self, cmd: &AtCommand) -> bool {
        match self {
            ModuleState::Run => matches!(
                cmd,
                AtCommand::Config(ConfigMode::Config115200 | ConfigMode::ConfigAsSet)
            ),
            ModuleState::Bootloader => {
                matches!(
                    cmd,
                    AtCommand::Lock(_) | AtCommand::LockQuery | AtCommand::BootQuery
                )
            }
            ModuleState::Configuration => true,
        }
    }

    /// Whether commands must be upper case (5.1.6).
    pub fn upper_case_only(self) -> bool {
        self == ModuleState::Bootloader
    }

    /// The state a state message announces.
    pub fn after(event: StateEvent) -> Option<ModuleState> {
        match event {
            StateEvent::RunStart => Some(ModuleState::Run),
            StateEvent::ConfigStart => Some(ModuleState::Configuration),
            StateEvent::BootloaderStart => Some(ModuleState::Bootloader),
            StateEvent::RunEnd | StateEvent::ConfigEnd => None,
        }
    }
}

/// The state messages of a transition, each with the baud it is sent at (4.2).
pub fn transition_messages(
    from: ModuleState,
    to: ModuleState,
    config_mode: ConfigMode,
    run_baud: u32,
) -> Vec<(StateEvent, u32)> {
    let cfg = ModuleState::Configuration.baud(config_mode, run_baud);
    match (from, to) {
        (ModuleState::Run, ModuleState::Configuration) => vec![
            (StateEvent::RunEnd, run_baud),
            (StateEvent::ConfigStart, cfg),
        ],
        (ModuleState::Configuration, ModuleState::Run) => vec![
            (StateEvent::ConfigEnd, cfg),
            (StateEvent::RunStart, run_baud),
        ],
        (_, ModuleState::Bootloader) => vec![(StateEvent::BootloaderStart, CONFIG_BAUD)],
        (ModuleState::Bootloader, ModuleState::Run) => vec![(StateEvent::RunStart, run_baud)],
        _ => Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn baud_rules() {
        let run = 921_600;
        assert_eq!(ModuleState::Run.baud(ConfigMode::Run, run), run);
        assert_eq!(
            ModuleState::Bootloader.baud(ConfigMode::ConfigAsSet, run),
            115_200
        );
        assert_eq!(
            ModuleState::Configuration.baud(ConfigMode::Config115200, run),
            115_200
        );
        assert_eq!(
            ModuleState::Configuration.baud(ConfigMode::ConfigAsSet, run),
            run
        );
    }

    #[test]
    fn transitions_send_documented_messages_at_documented_bauds() {
        // 4.2.2: AT+RUN_END at the settings' baud, AT+CONFIG_START always at 115200.
        assert_eq!(
            transition_messages(
                ModuleState::Run,
                ModuleState::Configuration,
                ConfigMode::Config115200,
                921_600
            ),
            [
                (StateEvent::RunEnd, 921_600),
                (StateEvent::ConfigStart, 115_200)
            ]
        );
        // 4.2.3: AT+CONFIG_END at 115200, AT+RUN_START at the settings' baud.
        assert_eq!(
            transition_messages(
                ModuleState::Configuration,
                ModuleState::Run,
                ConfigMode::Config115200,
                3_000_000
            ),
            [
                (StateEvent::ConfigEnd, 115_200),
                (StateEvent::RunStart, 3_000_000)
            ]
        );
        assert_eq!(
            transition_messages(
                ModuleState::Configuration,
                ModuleState::Bootloader,
                ConfigMode::Config115200,
                57_600
            ),
            [(StateEvent::BootloaderStart, 115_200)]
        );
    }

    #[test]
    fn commands_per_state() {
        assert!(ModuleState::Run.accepts(&AtCommand::Config(ConfigMode::Config115200)));
        assert!(!ModuleState::Run.accepts(&AtCommand::Help));
        assert!(ModuleState::Bootloader.accepts(&AtCommand::Lock(false)));
        assert!(!ModuleState::Bootloader.accepts(&AtCommand::Settings));
        assert!(ModuleState::Bootloader.upper_case_only());
        assert!(!ModuleState::Configuration.upper_case_only());
    }
}
