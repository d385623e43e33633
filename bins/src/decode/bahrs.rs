//! `vigil decode --device bahrs`: one JSON object per BAHRS message, SI values, health as words.

use std::io::{Read, Write};

use anyhow::Result;
use serde_json::{Value, json};
use vigil_drivers::bahrs::{Decoder, Health, Message};

use super::{JsonLines, Summary, run_decoder};

/// Decodes a BAHRS byte stream.
pub fn decode<W: Write>(input: &mut dyn Read, out: &mut JsonLines<W>) -> Result<Summary> {
    let mut decoder = Decoder::new();
    let stats = run_decoder(&mut decoder, input, out, |m, out| out.write(&to_json(&m)))?;
    Ok(Summary::new("bahrs", stats))
}

/// The word for a health code.
fn word(h: Health) -> &'static str {
    match h {
        Health::Unavailable => "unavailable",
        Health::Safe => "safe",
        Health::IntegrityRisk => "integrity_risk",
        Health::Undefined => "undefined",
    }
}

/// The JSON form of one message: `type` (name), `type_id`, `seq` where the message has one, then
/// its fields.
pub fn to_json(m: &Message) -> Value {
    let mut v = match m {
        Message::Inertial(i) => {
            let h = i.health;
            json!({
                "type": "inertial",
                "specific_force_mps2": i.specific_force_mps2(),
                "angular_rate_radps": i.angular_rate_radps(),
                "health": {
                    "specific_force_x": word(h.specific_force(0)),
                    "specific_force_y": word(h.specific_force(1)),
                    "specific_force_z": word(h.specific_force(2)),
                    "angular_rate_x": word(h.angular_rate(0)),
                    "angular_rate_y": word(h.angular_rate(1)),
                    "angular_rate_z": word(h.angular_rate(2)),
                    "reserved_bits": h.reserved(),
                },
            })
        }
        Message::Navigation(n) => {
            let h = n.health;
            json!({
                "type": "navigation",
                "pressure_height_m": n.pressure_height_m(),
                "velocity_down_mps": n.velocity_down_mps(),
                "roll_rad": n.roll_rad(),
                "pitch_rad": n.pitch_rad(),
                "heading_mag_rad": n.heading_mag_rad(),
                "health": {
                    "pressure_height": word(h.pressure_height()),
                    "velocity_down": word(h.velocity_down()),
                    "roll": word(h.roll()),
                    "pitch": word(h.pitch()),
                    "heading": word(h.heading()),
                    "reserved_bits": h.reserved(),
                },
            })
        }
        Message::Accuracy(a) => json!({
            "type": "accuracy",
            "std_north_rad": a.std_north_rad(),
            "std_east_rad": a.std_east_rad(),
            "std_heading_rad": a.std_heading_rad(),
            "mcu_time_us": a.mcu_time_us,
        }),
        Message::NavigationTime(t) | Message::InertialTime(t) => json!({
            "type": if matches!(m, Message::NavigationTime(_)) { "navigation_time" } else { "inertial_time" },
            "data_seq": t.data_seq,
            "mcu_time_us": t.mcu_time_us,
            "valid": t.is_valid(),
        }),
        Message::SyncPulseTime(t) => json!({
            "type": "sync_pulse_time",
            "mcu_time_us": t.mcu_time_us,
        }),
        Message::SoftwareVersion(s) => json!({
            "type": "software_version",
            "project_code": s.project_code_str(),
            "major": s.major,
            "minor": s.minor,
        }),
        Message::HardwareVersion(h) => json!({
            "type": "hardware_version",
            "mcu_id": h.mcu_id,
            "unique_id": h.unique_id.map(|w| format!("{w:08X}")),
        }),
        Message::EnterDiagnostics => json!({ "type": "enter_diagnostics" }),
        Message::ExitDiagnostics => json!({ "type": "exit_diagnostics" }),
        Message::ReadNvmPage { page } => json!({ "type": "read_nvm_page", "page": page }),
        Message::NvmPage(p) => json!({
            "type": "nvm_page",
            "page": p.page,
            "data_hex": p.data.iter().map(|b| format!("{b:02X}")).collect::<String>(),
        }),
        Message::Ack(a) => json!({
            "type": "ack",
            "acked_type": a.acked_type,
            "status": a.status,
            "ok": a.status == 0,
        }),
    };
    // Lead with the type, its id and the sequence counter, then the fields.
    let mut map = serde_json::Map::new();
    if let Value::Object(fields) = &mut v {
        if let Some(name) = fields.shift_remove("type") {
            map.insert("type".into(), name);
        }
        map.insert("type_id".into(), json!(m.type_id()));
        if let Some(seq) = m.seq() {
            map.insert("seq".into(), json!(seq));
        }
        map.append(fields);
    }
    Value::Object(map)
}
