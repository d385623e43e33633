//! `vigil decode --device ttmrf --format mavlink|gdl90|asterix`: the TT-Multi-RF binary
//! protocols as JSON Lines.
//!
//! One object per decoded message: the message's own fields (tagged `kind` for MAVLink and
//! GDL90, `cat` for ASTERIX), `format`, and for traffic messages a `traffic` object with the
//! common report. Unknown (null) fields are left out. Every 24-bit address (`address`, `target_address`, `icao_address`, COLLISION
//! `id`) is written as six upper-case hex digits. GDL90 traffic altitudes are read as pressure
//! altitude (the GDL90 definition; see `vigil_drivers::ttmrf::gdl90`).

use std::io::{Read, Write};

use anyhow::{Result, bail};
use serde::Serialize;
use serde_json::{Value, json};
use vigil_drivers::traffic::TrafficReport;
use vigil_drivers::ttmrf::asterix::AsterixDecoder;
use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, TrafficAltitude};
use vigil_drivers::ttmrf::mavlink::MavlinkDecoder;

use super::{JsonLines, Summary, TtFormat, run_decoder};

/// Keys whose integer values are 24-bit addresses.
const ADDRESS_KEYS: [&str; 4] = ["address", "target_address", "icao_address", "id"];

/// Rewrites integer addresses under [`ADDRESS_KEYS`] (at any depth) as upper-case hex, and
/// drops null members (an absent field is unknown).
fn hex_addresses(v: &mut Value) {
    match v {
        Value::Object(map) => {
            map.retain(|_, val| !val.is_null());
            for (k, val) in map.iter_mut() {
                if ADDRESS_KEYS.contains(&k.as_str())
                    && let Some(a) = val.as_u64()
                {
                    *val = Value::String(format!("{:06X}", a & 0xFF_FFFF));
                } else {
                    hex_addresses(val);
                }
            }
        }
        Value::Array(items) => items.iter_mut().for_each(hex_addresses),
        _ => {}
    }
}

/// The JSON line of one message.
fn line<M: Serialize>(format: &str, msg: &M, traffic: Option<TrafficReport>) -> Result<Value> {
    let mut v = serde_json::to_value(msg)?;
    if let Value::Object(map) = &mut v {
        map.insert("format".into(), json!(format));
        if let Some(t) = traffic {
            map.insert("traffic".into(), serde_json::to_value(t)?);
        }
    }
    hex_addresses(&mut v);
    Ok(v)
}

/// Decodes the TT-Multi-RF binary protocols.
pub fn decode<W: Write>(
    format: TtFormat,
    input: &mut dyn Read,
    out: &mut JsonLines<W>,
) -> Result<Summary> {
    let (stats, name) = match format {
        TtFormat::Gdl90 => {
            let mut d = Gdl90Decoder::new(TrafficAltitude::Pressure);
            let alt = d.traffic_altitude();
            let stats = run_decoder(&mut d, input, out, |m, out| {
                out.write(&line("gdl90", &m, m.to_traffic(alt))?)
            })?;
            (stats, "gdl90")
        }
        TtFormat::Asterix => {
            let mut d = AsterixDecoder::default();
            let stats = run_decoder(&mut d, input, out, |m, out| {
                out.write(&line("asterix", &m, m.to_traffic())?)
            })?;
            (stats, "asterix")
        }
        TtFormat::Mavlink => {
            let mut d = MavlinkDecoder::new();
            let stats = run_decoder(&mut d, input, out, |m, out| {
                out.write(&line("mavlink", &m, m.to_traffic())?)
            })?;
            (stats, "mavlink")
        }
        other => bail!("{other:?} is not a TT-Multi-RF binary format"),
    };
    let mut summary = Summary::new("ttmrf", stats);
    summary.extra = json!({ "format": name });
    Ok(summary)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn addresses_become_hex_at_any_depth() {
        let mut v = json!({
            "address": 11_224_393,
            "traffic": { "address": 1, "alt_pressure_m": 1524.0, "callsign": null },
            "target": { "icao_address": 0xDD1234, "id": "not a number" },
            "list": [{ "target_address": 2 }],
            "track_number": 7,
        });
        hex_addresses(&mut v);
        assert_eq!(v["address"], "AB4549");
        assert_eq!(v["traffic"]["address"], "000001");
        assert_eq!(v["traffic"]["alt_pressure_m"], 1524.0);
        assert!(v["traffic"].get("callsign").is_none());
        assert_eq!(v["target"]["icao_address"], "DD1234");
        assert_eq!(v["target"]["id"], "not a number");
        assert_eq!(v["list"][0]["target_address"], "000002");
        assert_eq!(v["track_number"], 7);
    }
}
