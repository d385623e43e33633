//! Lines the module sends in answer to AT commands and on state changes (manual 4.2, 5.1, 5.2).
//!
//! ```text
//! AT+OK                      a write or command succeeded (5.1.1)
//! AT+ERROR (DESCRIPTION)     failure, the description is optional (5.1.4)
//! AT+NAME=VALUE              answer to AT+NAME? and the lines of AT+SETTINGS? (5.1.2, 5.2.2)
//! AT+RUN_START ...           state messages (4.2)
//! anything else              free text: AT+NAME=? descriptions, AT+HELP output
//! ```
//!
//! The OCR writes `AT+0K` and `AT+CONF IG_START`; the wire form is `AT+OK` and `AT+CONFIG_START`.

use serde::Serialize;

use crate::DecodeStats;
use crate::ttmrf::text::line::{LineDecoder, LineProtocol};

/// Longest AT line accepted (HELP lines are the longest, about 120 bytes).
pub const MAX_LINE: usize = 1024;

/// A state message (manual 4.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StateEvent {
    /// `AT+RUN_START`: entered RUN (sent at the RUN baud).
    RunStart,
    /// `AT+RUN_END`: leaving RUN (sent at the RUN baud).
    RunEnd,
    /// `AT+CONFIG_START`: entered CONFIGURATION (sent at 115200).
    ConfigStart,
    /// `AT+CONFIG_END`: leaving CONFIGURATION (sent at 115200).
    ConfigEnd,
    /// `AT+BOOTLOADER_START`: entered BOOTLOADER (115200).
    BootloaderStart,
}

impl StateEvent {
    /// The word after `AT+`.
    pub const fn word(self) -> &'static str {
        match self {
            StateEvent::RunStart => "RUN_START",
            StateEvent::RunEnd => "RUN_END",
            StateEvent::ConfigStart => "CONFIG_START",
            StateEvent::ConfigEnd => "CONFIG_END",
            StateEvent::BootloaderStart => "BOOTLOADER_START",
        }
    }

    const ALL: [StateEvent; 5] = [
        StateEvent::RunStart,
        StateEvent::RunEnd,
        StateEvent::ConfigStart,
        StateEvent::ConfigEnd,
        StateEvent::BootloaderStart,
    ];
}

/// One line from the module.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum AtResponse {
    /// `AT+OK`.
    Ok,
    /// `AT+ERROR` with its optional description (without the parentheses).
    Error {
        /// The description, if any.
        description: Option<String>,
    },
    /// A state message.
    State {
        /// Which one.
        event: StateEvent,
    },
    /// `AT+NAME=VALUE` (name as sent; values are kept as text).
    Value {
        /// Setting or property name.
        name: String,
        /// Its value.
        value: String,
    },
    /// Any other printable line.
    Text {
        /// The line.
        text: String,
    },
}

impl AtResponse {
    /// Whether this is `AT+NAME=...` for `name` (case-insensitive).
    pub fn value_of(&self, name: &str) -> Option<&str> {
        match self {
            AtResponse::Value { name: n, value } if n.eq_ignore_ascii_case(name) => Some(value),
            _ => None,
        }
    }

    /// The line as the module sends it, with `\r\n`.
    pub fn to_line(&self) -> String {
        match self {
            AtResponse::Ok => "AT+OK\r\n".into(),
            AtResponse::Error { description: None } => "AT+ERROR\r\n".into(),
            AtResponse::Error {
                description: Some(d),
            } => format!("AT+ERROR ({d})\r\n"),
            AtResponse::State { event } => format!("AT+{}\r\n", event.word()),
            AtResponse::Value { name, value } => format!("AT+{name}={value}\r\n"),
            AtResponse::Text { text } => format!("{text}\r\n"),
        }
    }
}

/// Parses one line (without terminator). `None` for lines that are not printable text.
pub fn parse_response(line: &[u8]) -> Option<AtResponse> {
    let text = std::str::from_utf8(line).ok()?;
    if text.chars().any(|c| c.is_control() && c != '\t') {
        return None;
    }
    let text = text.trim_end();
    let Some(rest) = text.strip_prefix("AT+") else {
        return Some(AtResponse::Text {
            text: text.to_owned(),
        });
    };
    if rest == "OK" {
        return Some(AtResponse::Ok);
    }
    if let Some(desc) = rest.strip_prefix("ERROR") {
        let d = desc.trim();
        let d = d
            .strip_prefix('(')
            .and_then(|d| d.strip_suffix(')'))
            .unwrap_or(d)
            .trim();
        return Some(AtResponse::Error {
            description: (!d.is_empty()).then(|| d.to_owned()),
        });
    }
    if let Some(event) = StateEvent::ALL.iter().find(|e| e.word() == rest) {
        return Some(AtResponse::State { event: *event });
    }
    if let Some((name, value)) = rest.split_once('=')
        && !name.is_empty()
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || b == b'_')
    {
        return Some(AtResponse::Value {
            name: name.to_owned(),
            value: value.to_owned(),
        });
    }
    Some(AtResponse::Text {
        text: text.to_owned(),
    })
}

/// Sans-IO decoder of the module's AT responses and state messages, line by line.
pub type AtDecoder = LineDecoder<AtLines>;

/// The AtLines line protocol for [`LineDecoder`].
#[derive(Debug, Clone, Copy, Default)]
pub struct AtLines;

impl LineProtocol for AtLines {
    type Message = AtResponse;
    const START: Option<u8> = None;
    const MAX_LINE: usize = MAX_LINE;

    fn parse(content: &[u8], stats: &mut DecodeStats) -> Option<AtResponse> {
        // Blank lines between responses are ignored, not malformed.
        if content.iter().all(|b| b.is_ascii_whitespace()) {
            return None;
        }
        let r = parse_response(content);
        if r.is_none() {
            stats.malformed += 1;
        }
        r
    }
}
