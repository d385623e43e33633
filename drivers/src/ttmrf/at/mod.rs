//! TT-Multi-RF AT control (manual 3 "UART configuration", 4 "Principle of operation",
//! 5 "System configuration").
//!
//! - [`state`]: BOOTLOADER / RUN / CONFIGURATION, transitions, the messages each transition sends
//!   and the baud they travel at.
//! - [`command`]: host commands `AT+X=V`, `AT+X?`, `AT+X=?` and the named commands, their
//!   encoding (upper case, `\r\n`) and the module-side parsing with the case rules.
//! - [`response`]: what the module answers (`AT+OK`, `AT+ERROR (...)`, `AT+X=V`, state messages,
//!   free text) and a line decoder for it.
//! - [`describe`]: the answer to `AT+NAME=?`.
//! - [`settings`]: the settings of tables 9, 12, 13, 24, 31 and 33 as typed, range-checked values.
//! - [`client`]: the sans-IO client that brings the module into a wanted configuration.

pub mod client;
pub mod command;
pub mod describe;
pub mod response;
pub mod settings;
pub mod state;

pub use client::{ClientConfig, ConfigClient, ConfigError, ConfigFailure, ConfigReport, Output};
pub use command::{AtCommand, AtEncoder, CommandError, ConfigMode};
pub use describe::SettingDescription;
pub use response::{AtDecoder, AtResponse, StateEvent, parse_response};
pub use settings::{Baudrate, CONFIG_BAUD, DecodedProtocol, RawProtocol, Setting, SettingId};
pub use state::ModuleState;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::decode_slice;
    use crate::testkit::{assert_split_invariant, assert_survives_random};

    #[test]
    fn manual_write_read_describe_examples() {
        // 5.1.1: AT+SYSTEM_STATISTICS=1, response AT+OK (printed "AT+0K" by the OCR).
        let w = AtCommand::Write(Setting::new(SettingId::SystemStatistics, 1).unwrap());
        assert_eq!(w.to_line(), "AT+SYSTEM_STATISTICS=1\r\n");
        assert_eq!(parse_response(b"AT+OK"), Some(AtResponse::Ok));
        // 5.1.2: AT+SYSTEM_STATISTICS? -> AT+SYSTEM_STATISTICS=1.
        assert_eq!(
            AtCommand::Read(SettingId::SystemStatistics).to_line(),
            "AT+SYSTEM_STATISTICS?\r\n"
        );
        let r = parse_response(b"AT+SYSTEM_STATISTICS=1").unwrap();
        assert_eq!(r.value_of("SYSTEM_STATISTICS"), Some("1"));
        // 5.1.3: AT+SYSTEM_STATISTICS=? and its free-text description lines.
        assert_eq!(
            AtCommand::Describe(SettingId::SystemStatistics).to_line(),
            "AT+SYSTEM_STATISTICS=?\r\n"
        );
        assert_eq!(
            parse_response(b"Range (max.): 2"),
            Some(AtResponse::Text {
                text: "Range (max.): 2".into()
            })
        );
        // 5.1.4: errors with and without description.
        assert_eq!(
            parse_response(b"AT+ERROR (Settings missing, loaded default)"),
            Some(AtResponse::Error {
                description: Some("Settings missing, loaded default".into())
            })
        );
        assert_eq!(
            parse_response(b"AT+ERROR"),
            Some(AtResponse::Error { description: None })
        );
        // 5.2.2 examples of values.
        assert_eq!(
            parse_response(b"AT+FIRMWARE_VERSION=2.73.1.0 (Jun 27 2024)")
                .unwrap()
                .value_of("FIRMWARE_VERSION"),
            Some("2.73.1.0 (Jun 27 2024)")
        );
        assert_eq!(
            parse_response(b"AT+SERIAL_NUMBER=07-0001337")
                .unwrap()
                .value_of("serial_number"),
            Some("07-0001337")
        );
        // 4.2: state messages (the OCR's "AT+CONF IG_START" has a stray space).
        for (line, event) in [
            ("AT+RUN_START", StateEvent::RunStart),
            ("AT+RUN_END", StateEvent::RunEnd),
            ("AT+CONFIG_START", StateEvent::ConfigStart),
            ("AT+CONFIG_END", StateEvent::ConfigEnd),
            ("AT+BOOTLOADER_START", StateEvent::BootloaderStart),
        ] {
            assert_eq!(
                parse_response(line.as_bytes()),
                Some(AtResponse::State { event })
            );
            assert_eq!(AtResponse::State { event }.to_line(), format!("{line}\r\n"));
        }
    }

    #[test]
    fn manual_5_1_8_switch_to_csv_sequence() {
        let cmds = [
            AtCommand::Config(ConfigMode::Config115200),
            AtCommand::Write(Setting::adsb_decoded(DecodedProtocol::Csv)),
            AtCommand::Config(ConfigMode::Run),
        ];
        let text: String = cmds.iter().map(AtCommand::to_line).collect();
        assert_eq!(
            text,
            "AT+CONFIG=1\r\nAT+ADSB_RX_PROTOCOL_DECODED=1\r\nAT+CONFIG=0\r\n"
        );
    }

    #[test]
    fn command_parsing_case_rules_and_values() {
        // 5.1.6: any case after AT+ in CONFIGURATION, upper case only in BOOTLOADER.
        assert_eq!(
            AtCommand::parse("AT+sYSTEM_staTISTICS?", false),
            Ok(AtCommand::Read(SettingId::SystemStatistics))
        );
        assert_eq!(
            AtCommand::parse("AT+lock=0", true),
            Err(CommandError::LowerCase)
        );
        assert_eq!(
            AtCommand::parse("AT+LOCK=0", true),
            Ok(AtCommand::Lock(false))
        );
        assert_eq!(
            AtCommand::parse("at+LOCK=0", false),
            Err(CommandError::NoPrefix)
        );
        assert_eq!(
            AtCommand::parse("AT+CONFIG=2", false),
            Ok(AtCommand::Config(ConfigMode::ConfigAsSet))
        );
        assert!(AtCommand::parse("AT+CONFIG=3", false).is_err());
        assert!(AtCommand::parse("AT+BAUDRATE=4", false).is_err());
        assert_eq!(
            AtCommand::parse("AT+ASTERIX_SIC=?", false),
            Ok(AtCommand::Describe(SettingId::AsterixSic))
        );
        assert_eq!(
            AtCommand::parse("AT+ADSB_TX_ICAO=ABC123", false),
            Ok(AtCommand::Other("ADSB_TX_ICAO=ABC123".into()))
        );
        for cmd in [
            AtCommand::Settings,
            AtCommand::Help,
            AtCommand::Lock(true),
            AtCommand::LockQuery,
            AtCommand::BootQuery,
            AtCommand::ConfigQuery,
            AtCommand::SettingsDefault,
            AtCommand::SerialNumberQuery,
            AtCommand::FirmwareVersionQuery,
            AtCommand::Reboot,
            AtCommand::RebootBootloader,
            AtCommand::Write(Setting::gnss_nmea(true)),
            AtCommand::Describe(SettingId::UatMode),
        ] {
            let line = cmd.to_line();
            assert!(line.ends_with("\r\n") && line.starts_with("AT+"));
            assert_eq!(AtCommand::parse(line.trim_end(), true), Ok(cmd));
        }
    }

    fn settings_listing() -> Vec<u8> {
        // Part of the 5.2.2 AT+SETTINGS? example (OCR spaces inside names removed), a HELP line,
        // garbage and a line without terminator.
        b"AT+BAUDRATE=0\r\nAT+BOOT=0\r\nAT+CONFIG=1\r\nAT+DEVICE=TR-1F\r\n\
AT+FIRMWARE_VERSION=2.72.1.0 (Jun 17 2024)\r\nAT+LOCK=0\r\nAT+SERIAL_NUMBER=22-0000309\r\n\
\x00\xff\r\n\r\nAT+SYSTEM_LOG=0 [System logs (0:disable, 1:enable)]\r\nAT+ASTERIX_SIC=129\r\nAT+OK"
            .to_vec()
    }

    #[test]
    fn decoder_on_a_settings_listing() {
        let bytes = settings_listing();
        let mut d = AtDecoder::new();
        let out = decode_slice(&mut d, &bytes);
        // Seven values, then (garbage, empty line skipped) SYSTEM_LOG, ASTERIX_SIC and AT+OK.
        assert_eq!(out.len(), 10);
        assert_eq!(out[3].value_of("DEVICE"), Some("TR-1F"));
        assert_eq!(out[8].value_of("ASTERIX_SIC"), Some("129"));
        assert_eq!(out[9], AtResponse::Ok);
        assert_eq!(d.stats().malformed, 1);
        assert_split_invariant(AtDecoder::new, &bytes);
        assert_survives_random(AtDecoder::new, 3, 200, 1500);
    }

    proptest::proptest! {
        #[test]
        fn response_round_trip(kind in 0u8..5, ev in 0usize..5, name in "[A-Z][A-Z0-9_]{0,20}", value in "[ -~]{0,30}") {
            let r = match kind {
                0 => AtResponse::Ok,
                1 => AtResponse::Error { description: None },
                2 => AtResponse::Error { description: Some(value.trim().to_owned()).filter(|d| !d.is_empty() && !d.starts_with('(')) },
                3 => AtResponse::State { event: [StateEvent::RunStart, StateEvent::RunEnd, StateEvent::ConfigStart, StateEvent::ConfigEnd, StateEvent::BootloaderStart][ev] },
                _ => AtResponse::Value { name, value: value.trim_end().to_owned() },
            };
            let line = r.to_line();
            proptest::prop_assert_eq!(parse_response(line.trim_end_matches(['\r', '\n']).as_bytes()), Some(r));
        }

        #[test]
        fn write_command_round_trip(idx in 0usize..SettingId::ALL.len(), raw in -5i64..300) {
            let id = SettingId::ALL[idx];
            if let Ok(setting) = Setting::new(id, raw) {
                let cmd = AtCommand::Write(setting);
                // Upper case passes in every state, lower case only outside BOOTLOADER.
                proptest::prop_assert_eq!(AtCommand::parse(cmd.to_line().trim_end(), true), Ok(cmd.clone()));
                let lower = cmd.to_line().to_ascii_lowercase().replacen("at+", "AT+", 1);
                proptest::prop_assert_eq!(AtCommand::parse(lower.trim_end(), false), Ok(cmd));
            } else {
                let line = format!("AT+{}={raw}", id.name());
                proptest::prop_assert!(AtCommand::parse(&line, false).is_err());
            }
        }
    }
}
