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

/// Keys whose integer values are 24-bit addresses: the usual ones and MAVLink COLLISION's `id`.
const ADDRESS_KEYS: [&str; 5] = ["address", "icao", "icao_address", "target_address", "id"];

/// Drops null members (an absent field is unknown) at any depth, then applies the JSON names
/// (`vigil_service::json_names`: addresses as hex, codes as words, UTC beside GPS times).
fn hex_addresses(v: &mut Value) {
    fn drop_nulls(v: &mut Value) {
        match v {
            Value::Object(map) => {
                map.retain(|_, val| !val.is_null());
                map.values_mut().for_each(drop_nulls);
            }
            Value::Array(items) => items.iter_mut().for_each(drop_nulls),
            _ => {}
        }
    }
    drop_nulls(v);
    vigil_service::json_names::normalise_with(v, &ADDRESS_KEYS);
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

    fn run(format: TtFormat, bytes: &[u8]) -> (Vec<Value>, Summary) {
        let mut out = JsonLines::new(Vec::new());
        let summary = decode(format, &mut std::io::Cursor::new(bytes.to_vec()), &mut out).unwrap();
        let text = String::from_utf8(out.out.into_inner().unwrap()).unwrap();
        let lines = text
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        (lines, summary)
    }

    #[test]
    fn gdl90_spec_heartbeat() {
        // GDL 90 spec 2.2.4 heartbeat, after two garbage bytes.
        let bytes = [
            0x00, 0x01, 0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E,
        ];
        let (lines, summary) = run(TtFormat::Gdl90, &bytes);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0]["kind"], "heartbeat");
        assert_eq!(lines[0]["format"], "gdl90");
        assert_eq!(lines[0]["timestamp_s"], 53467);
        assert!(lines[0].get("traffic").is_none());
        assert_eq!(summary.stats.bytes_skipped, 2);
        assert_eq!(summary.extra["format"], "gdl90");
    }

    #[test]
    fn asterix_sample() {
        let Some(path) = vigil_drivers::testkit::shared_data("asterix/cat21_re.ast") else {
            return;
        };
        let (lines, summary) = run(TtFormat::Asterix, &std::fs::read(path).unwrap());
        assert_eq!(lines.len(), 2);
        assert_eq!(lines[0]["cat"], "cat021");
        assert_eq!(lines[0]["target_address"], "000001");
        assert_eq!(lines[1]["traffic"]["address"], "000002");
        // ECAT 21 (surface service vehicle) -> emitter category 18.
        assert_eq!(lines[1]["traffic"]["emitter_category"], 18);
        assert_eq!(summary.stats.frames_decoded, 2);
    }

    #[test]
    fn mavlink_vehicle_line() {
        use vigil_drivers::ttmrf::mavlink::{AdsbVehicle, FrameInfo, encode_adsb_vehicle};
        let frame = FrameInfo {
            version: 2,
            sequence: 7,
            system_id: 1,
            component_id: 156,
            signed: false,
        };
        let v = AdsbVehicle {
            icao_address: 0x00AB_4549,
            lat_deg: 44.9,
            lon_deg: -123.0,
            altitude_m: 1524.0,
            altitude_type: 0,
            heading_deg: 45.0,
            hor_velocity_mps: 63.28,
            ver_velocity_mps: 0.0,
            flags: 0x0001 | 0x0002 | 0x0010,
            squawk: 0,
            callsign: "N825V".into(),
            emitter_type: 1,
            tslc_s: 1,
        };
        let mut bytes = Vec::new();
        encode_adsb_vehicle(&frame, &v, &mut bytes);
        let (lines, summary) = run(TtFormat::Mavlink, &bytes);
        assert_eq!(lines.len(), 1);
        assert_eq!(lines[0]["kind"], "adsb_vehicle");
        assert_eq!(lines[0]["vehicle"]["icao_address"], "AB4549");
        assert_eq!(lines[0]["traffic"]["address"], "AB4549");
        assert_eq!(lines[0]["traffic"]["callsign"], "N825V");
        assert_eq!(lines[0]["traffic"]["alt_pressure_m"], 1524.0);
        // Velocity flag not set: no speed in the report (absent, not null).
        assert!(lines[0]["traffic"].get("ground_speed_mps").is_none());
        assert_eq!(summary.stats.frames_decoded, 1);
    }

    #[test]
    fn mavlink_empty_and_wrong_format() {
        let (lines, summary) = run(TtFormat::Mavlink, b"no frames here");
        assert!(lines.is_empty());
        assert_eq!(summary.stats.bytes_skipped, 14);
        let mut out = JsonLines::new(Vec::new());
        assert!(decode(TtFormat::Csv, &mut std::io::Cursor::new(vec![]), &mut out).is_err());
    }

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
