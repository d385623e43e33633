//! `vigil decode --device vn200`: one JSON object per message.
//!
//! - Binary messages: `"kind": "binary"`, the group byte (`"groups": "14"`), the type word(s) of
//!   each active group as sent (`"types": {"imu": "003E"}`, two words as `"C008 0007"`), then
//!   one object per group with every field present (units in the names where not SI).
//! - ASCII sentences: `"kind": "ascii"`, the sentence kind (`async`, `read_response`, `command`,
//!   `error`) and its fields.
//!
//! The summary on stderr adds the VN-200 counters (`extra`): ASCII/binary counts, false syncs,
//! truncated candidates, foreign sentences, bypassed checksums and split-packet reassembly.

use std::io::{Read, Write};

use anyhow::Result;
use std::collections::BTreeMap;

use serde::Serialize;
use vigil_drivers::vn200::binary::{Group, type_words};
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};

use super::{JsonLines, Summary, run_decoder};

/// One output line: the message, plus the header of binary messages. Serialised directly (not
/// through `serde_json::Value`) so that f32 fields print at f32 precision.
#[derive(Serialize)]
struct Line<'a> {
    #[serde(flatten)]
    message: &'a Vn200Message,
    #[serde(skip_serializing_if = "Option::is_none")]
    groups: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    types: Option<BTreeMap<&'static str, String>>,
}

fn line(msg: &Vn200Message) -> Line<'_> {
    let Vn200Message::Binary(b) = msg else {
        return Line {
            message: msg,
            groups: None,
            types: None,
        };
    };
    let masks = b.type_masks();
    let types = Group::ALL
        .iter()
        .filter(|g| masks[**g as usize] != 0)
        .map(|g| {
            let words = match type_words(masks[*g as usize]) {
                (w0, Some(w1)) => format!("{w0:04X} {w1:04X}"),
                (w0, None) => format!("{w0:04X}"),
            };
            (g.name(), words)
        })
        .collect();
    Line {
        message: msg,
        groups: Some(format!("{:02X}", b.group_byte())),
        types: Some(types),
    }
}

/// Decodes a VN-200 byte stream (binary, split packets and ASCII, interleaved).
pub fn decode<W: Write>(input: &mut dyn Read, out: &mut JsonLines<W>) -> Result<Summary> {
    let mut decoder = Vn200Decoder::new();
    let stats = run_decoder(&mut decoder, input, out, |msg, out| out.write(&line(&msg)))?;
    let mut summary = Summary::new("vn200", stats);
    summary.extra = serde_json::to_value(decoder.counters())?;
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use serde_json::{Value, json};

    use super::*;

    #[test]
    fn binary_and_ascii_json() {
        // Figure A.3 then a $VNERR with hex code 0C and a command echo.
        let mut bytes = vec![
            0xFA, 0x05, 0x08, 0x00, 0x10, 0x00, 0x42, 0x8E, 0xE7, 0xC2, 0x1E, 0x12, 0x11, 0xC1,
            0xFF, 0x49, 0x9C, 0x40, 0xE3, 0x27, 0xC4, 0x41, 0x6A, 0x4E,
        ];
        bytes.extend_from_slice(b"$VNERR,0C*XX\r\n$VNRRG,5*46\r\n$VNKMD,1*47\r\n");
        bytes.extend_from_slice(b"$VNRRG,63,412213.876136,2255,D085,-043.662,+027.311,+003.617,+32.89195471,-096.70376455,+00166.338,-000.025,+000.029,-000.013,49.53,00.56,0.085*1F\r\n");
        let mut out = JsonLines::new(Vec::new());
        let summary = decode(&mut &bytes[..], &mut out).unwrap();
        out.flush().unwrap();
        let text = String::from_utf8(out.out.into_inner().unwrap()).unwrap();
        let lines: Vec<Value> = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        assert_eq!(lines.len(), 5);
        assert_eq!(lines[0]["kind"], "binary");
        assert_eq!(lines[0]["groups"], "05");
        assert_eq!(lines[0]["types"], json!({"common": "0008", "imu": "0010"}));
        // f32 printed at f32 precision: -115.77785 (0xC2E78E42).
        assert_eq!(lines[0]["common"]["ypr"]["yaw_deg"], json!(-115.77785));
        assert!(lines[0]["imu"]["temperature_c"].as_f64().is_some());
        assert_eq!(lines[1]["sentence"], "error");
        assert_eq!(lines[1]["code"], "InsufficientBaudRate");
        assert_eq!(lines[2]["command"]["command"], "read_register");
        assert_eq!(lines[2]["command"]["args"], 5);
        assert_eq!(lines[3]["command"]["args"], true);
        assert_eq!(lines[4]["sentence"], "read_response");
        assert_eq!(lines[4]["value"]["register"], "measurement");
        assert_eq!(lines[4]["value"]["measurement"], "ins_lla");
        assert_eq!(lines[4]["value"]["ins_status"]["mode"], "Aligning");
        assert_eq!(summary.stats.frames_decoded, 5);
        assert_eq!(summary.extra["checksum_bypassed"], 1);
        assert_eq!(summary.extra["split"]["packets"], 0);
    }

    /// Issue 26: a GPS time in the decoded JSON gets its UTC beside it.
    #[test]
    fn gps_time_has_its_utc_beside_it() {
        // Common group (0x01), TimeGps only (type 0x0002): u64 ns since the GPS epoch. GPS week
        // 1899 began 2016-05-29 00:00:00 GPS; GPS - UTC was 17 s; Tuesday 2016-05-31
        // 10:00:01.250 UTC is 2 d + 10 h + 1.25 s + 17 s into the week.
        let t: u64 = (1899 * 604_800 + 172_800 + 36_018) * 1_000_000_000 + 250_000_000;
        let mut bytes = vec![0xFA, 0x01, 0x02, 0x00];
        bytes.extend_from_slice(&t.to_le_bytes());
        let crc = vigil_drivers::vn200::crc::crc16(&bytes[1..]);
        bytes.extend_from_slice(&crc.to_be_bytes());
        let mut out = JsonLines::new(Vec::new());
        decode(&mut &bytes[..], &mut out).unwrap();
        out.flush().unwrap();
        let text = String::from_utf8(out.out.into_inner().unwrap()).unwrap();
        let line: Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
        assert_eq!(line["common"]["time_gps_ns"], t);
        assert_eq!(line["common"]["time_utc"], "2016-05-31T10:00:01.250Z");
    }
}
