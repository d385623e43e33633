//! The answer to `AT+NAME=?` (manual 5.1.3): free-text lines `Key: value`.
//!
//! ```text
//! Setting: SYSTEM_STATISTICS
//! Description: System statistics protocol (0:none, 1:CSV, 2:JSON)
//! Access: Read Write
//! Type: Integer decimal
//! Range (min.): 0
//! Range (max.): 2
//! Preserved: 1
//! Requires restart: 0
//! ```

use serde::Serialize;

use super::response::AtResponse;

/// A setting's self-description as the module prints it.
#[derive(Debug, Clone, PartialEq, Eq, Default, Serialize)]
pub struct SettingDescription {
    /// `Setting:`.
    pub name: String,
    /// `Description:`.
    pub description: Option<String>,
    /// `Access:` ("Read Write", ...).
    pub access: Option<String>,
    /// `Type:` ("Integer decimal", ...).
    pub value_type: Option<String>,
    /// `Range (min.):`.
    pub min: Option<i64>,
    /// `Range (max.):`.
    pub max: Option<i64>,
    /// `Preserved:` (kept in non-volatile memory).
    pub preserved: Option<bool>,
    /// `Requires restart:`.
    pub requires_restart: Option<bool>,
}

impl SettingDescription {
    /// Builds the description from the text lines of one answer. `None` without a `Setting:` line.
    /// Unknown keys are ignored; a number that does not parse leaves its field unknown.
    pub fn from_lines<'a>(lines: impl IntoIterator<Item = &'a AtResponse>) -> Option<Self> {
        let mut d = SettingDescription::default();
        let mut named = false;
        for line in lines {
            let AtResponse::Text { text } = line else {
                continue;
            };
            let Some((key, value)) = text.split_once(':') else {
                continue;
            };
            let value = value.trim();
            let flag = |v: &str| match v {
                "0" => Some(false),
                "1" => Some(true),
                _ => None,
            };
            match key.trim() {
                "Setting" => {
                    d.name = value.to_owned();
                    named = true;
                }
                "Description" => d.description = Some(value.to_owned()),
                "Access" => d.access = Some(value.to_owned()),
                "Type" => d.value_type = Some(value.to_owned()),
                "Range (min.)" => d.min = value.parse().ok(),
                "Range (max.)" => d.max = value.parse().ok(),
                "Preserved" => d.preserved = flag(value),
                "Requires restart" => d.requires_restart = flag(value),
                _ => {}
            }
        }
        named.then_some(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ttmrf::at::parse_response;

    #[test]
    fn manual_5_1_3_example() {
        // OCR repairs: "SYSTEM_ STATISTICS" -> "SYSTEM_STATISTICS", "(0O:none" -> "(0:none",
        // "Range (min.): O" -> "0" (the letter O for the digit; the range is 0..2 per 5.1.7).
        let text = "Setting: SYSTEM_STATISTICS\r\nDescription: System statistics protocol (0:none, 1:CSV, 2:JSON)\r\n\
Access: Read Write\r\nType: Integer decimal\r\nRange (min.): 0\r\nRange (max.): 2\r\nPreserved: 1\r\nRequires restart: 0\r\n";
        let lines: Vec<AtResponse> = text
            .split("\r\n")
            .filter(|l| !l.is_empty())
            .map(|l| parse_response(l.as_bytes()).unwrap())
            .collect();
        let d = SettingDescription::from_lines(&lines).unwrap();
        assert_eq!(d.name, "SYSTEM_STATISTICS");
        assert_eq!(
            d.description.as_deref(),
            Some("System statistics protocol (0:none, 1:CSV, 2:JSON)")
        );
        assert_eq!(d.access.as_deref(), Some("Read Write"));
        assert_eq!(d.value_type.as_deref(), Some("Integer decimal"));
        assert_eq!((d.min, d.max), (Some(0), Some(2)));
        assert_eq!((d.preserved, d.requires_restart), (Some(true), Some(false)));
        // The range agrees with the typed table.
        let spec = crate::ttmrf::at::SettingId::SystemStatistics.spec();
        assert_eq!((d.min, d.max), (Some(spec.min), Some(spec.max)));
        assert!(SettingDescription::from_lines(&lines[1..]).is_none());
    }
}
