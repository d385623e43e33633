//! `vigil decode --device ttmrf --format auto|csv|json|nmea|at`.
//!
//! One JSON object per message; a JSON message with several targets gives one object per target
//! (and per `raw` frame), each carrying the message's `src`, `ts_ms` and `ver`. Field names carry
//! their units where not SI (`alt_baro_ft`, `velh_kt`); addresses are upper-case hex.

use std::io::{Read, Write};

use anyhow::Result;
use serde::Serialize;
use serde_json::{Map, Value, json};
use vigil_drivers::ttmrf::json::JsonMessage;
use vigil_drivers::ttmrf::text::{TextDecoder, TextMessage, TextMode};

use super::{JsonLines, Summary, TtFormat, run_decoder};

/// Decodes the TT-Multi-RF text protocols.
pub fn decode<W: Write>(
    format: TtFormat,
    input: &mut dyn Read,
    out: &mut JsonLines<W>,
) -> Result<Summary> {
    let mode = match format {
        TtFormat::Csv => TextMode::Csv,
        TtFormat::Json => TextMode::Json,
        TtFormat::Nmea => TextMode::Nmea,
        TtFormat::At => TextMode::At,
        _ => TextMode::Auto,
    };
    let mut decoder = TextDecoder::new(mode);
    let stats = run_decoder(&mut decoder, input, out, |m, out| {
        for v in to_json(&m)? {
            out.write(&v)?;
        }
        Ok(())
    })?;
    let mut summary = Summary::new("ttmrf", stats);
    summary.extra = json!({ "format": mode, "per_protocol": decoder.counts() });
    Ok(summary)
}

/// `{"protocol": ..., <key>: <kind>, ...fields}`.
fn object(protocol: &str, fields: impl Serialize, head: &[(&str, Value)]) -> Result<Value> {
    let mut map = Map::new();
    map.insert("protocol".into(), Value::from(protocol));
    for (k, v) in head {
        map.insert((*k).into(), v.clone());
    }
    match serde_json::to_value(fields)? {
        Value::Object(o) => map.extend(o),
        other => {
            map.insert("value".into(), other);
        }
    }
    Ok(Value::Object(map))
}

/// The output objects of one message.
pub fn to_json(m: &TextMessage) -> Result<Vec<Value>> {
    Ok(match m {
        TextMessage::Csv(c) => vec![object("csv", c, &[])?],
        TextMessage::Nmea(n) => vec![object("nmea", n, &[])?],
        TextMessage::At(a) => vec![object("at", a, &[])?],
        TextMessage::Json(j) => json_targets(j)?,
    })
}

fn json_targets(j: &JsonMessage) -> Result<Vec<Value>> {
    let common = |section: &str| -> Vec<(&'static str, Value)> {
        vec![
            ("section", Value::from(section)),
            ("src", json!(j.src)),
            ("ts_ms", json!(j.ts_ms)),
            ("ver", json!(j.ver)),
        ]
    };
    let mut out = Vec::new();
    if let Some(s) = &j.status {
        out.push(object("json", s, &common("status"))?);
    }
    for a in &j.adsb {
        out.push(object("json", a, &common("adsb"))?);
    }
    for u in &j.uat {
        out.push(object("json", u, &common("uat"))?);
    }
    for f in &j.flarm {
        out.push(object("json", f, &common("flarm"))?);
    }
    if let Some(g) = &j.gnss {
        out.push(object("json", g, &common("gnss"))?);
    }
    for r in &j.raw {
        out.push(object("json", r, &common("raw"))?);
    }
    if out.is_empty() {
        out.push(object("json", json!({}), &common("none"))?);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_drivers::decode_slice;

    fn decode_all(mode: TextMode, bytes: &[u8]) -> Vec<Value> {
        let mut d = TextDecoder::new(mode);
        decode_slice(&mut d, bytes)
            .iter()
            .flat_map(|m| to_json(m).unwrap())
            .collect()
    }

    #[test]
    fn csv_line_output_names_and_hex_address() {
        let v = decode_all(
            TextMode::Auto,
            b"#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE\r\n",
        );
        assert_eq!(v.len(), 1);
        let o = &v[0];
        assert_eq!(o["protocol"], "csv");
        assert_eq!(o["type"], "adsb");
        assert_eq!(o["icao"], "4D240E");
        assert_eq!(o["alt_baro_ft"], 28550.0);
        assert_eq!(o["velh_kt"], 510.0);
        assert_eq!(o["callsign"], Value::Null);
        assert_eq!(o["nicnac"]["nac_p"], 9);
    }

    #[test]
    fn json_message_gives_one_object_per_target() {
        let v = decode_all(
            TextMode::Json,
            br#"{"src":"X","ts":5,"ver":1,"adsb":[{"icao":"00000A"},{"icao":"abcdef","altBaro":100}],"raw":[["5D4B18FFFC710B",-70,2,"1"]]}"#,
        );
        assert_eq!(v.len(), 3);
        assert_eq!(v[0]["section"], "adsb");
        assert_eq!(v[0]["icao"], "00000A");
        assert_eq!(v[1]["icao"], "ABCDEF");
        assert_eq!(v[1]["alt_baro_ft"], 100.0);
        assert_eq!(v[1]["ts_ms"], 5);
        assert_eq!(v[2]["section"], "raw");
        assert_eq!(v[2]["frame_hex"], "5D4B18FFFC710B");
    }

    /// A CONFIGURATION session recorded between the drivers' client and the simulated module
    /// (what a sniffer on the module's TX line at 115200 would capture) decodes line by line.
    #[test]
    fn recorded_configuration_session_decodes_as_at() {
        use std::time::Duration;
        use vigil_drivers::ttmrf::at::{
            ClientConfig, ConfigClient, DecodedProtocol, Output, Setting,
        };
        use vigil_sim::ttmrf_module::SimModule;

        let mut sim = SimModule::new("22-0000309", "2.77.5.0 (Mar 4 2025)");
        let mut client = ConfigClient::new(
            vec![Setting::adsb_decoded(DecodedProtocol::Json)],
            ClientConfig::default(),
        );
        let mut capture = Vec::new();
        let mut host_baud = client.baud();
        client.start(Duration::ZERO);
        'cycle: for _ in 0..1000 {
            while let Some(o) = client.poll_output() {
                match o {
                    Output::Send(b) => sim.receive(&b, host_baud),
                    Output::SetBaud(b) => host_baud = b,
                    Output::Finished(r) => {
                        assert!(r.is_ok());
                        break 'cycle;
                    }
                }
            }
            let (baud, bytes) = sim.poll_output().expect("the module answers");
            if baud == 115_200 {
                capture.extend_from_slice(&bytes);
            }
            if baud == host_baud {
                client.handle_bytes(&bytes, Duration::ZERO);
            }
        }
        let mut d = TextDecoder::new(TextMode::At);
        let v: Vec<Value> = decode_slice(&mut d, &capture)
            .iter()
            .flat_map(|m| to_json(m).unwrap())
            .collect();
        assert_eq!(vigil_drivers::DeviceDecoder::stats(&d).malformed, 0);
        assert_eq!(v.first().unwrap()["event"], "config_start");
        assert_eq!(v.last().unwrap()["event"], "config_end");
        assert!(
            v.iter()
                .any(|o| o["name"] == "SERIAL_NUMBER" && o["value"] == "22-0000309")
        );
        assert!(
            v.iter()
                .any(|o| o["name"] == "ADSB_RX_PROTOCOL_DECODED" && o["value"] == "3")
        );
        // The same capture in auto mode gives the same AT lines.
        let mut a = TextDecoder::new(TextMode::Auto);
        assert_eq!(decode_slice(&mut a, &capture).len(), v.len());
    }

    #[test]
    fn nmea_and_at_output() {
        let v = decode_all(
            TextMode::Auto,
            b"$GPZDA,201530.00,04,07,2002,00,00*60\r\nAT+SERIAL_NUMBER=07-0001337\r\n",
        );
        assert_eq!(v[0]["protocol"], "nmea");
        assert_eq!(v[0]["sentence"], "ZDA");
        assert_eq!(v[0]["date"]["year"], 2002);
        assert_eq!(v[1]["protocol"], "at");
        assert_eq!(v[1]["type"], "value");
        assert_eq!(v[1]["value"], "07-0001337");
    }
}
