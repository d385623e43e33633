//! `vigil decode --device ttmrf --format hex|hexd|beast [--ref LAT,LON]`: raw Mode S frames to
//! JSON Lines, one object per frame that passed its checks (failures only show in the summary
//! counters on stderr).
//!
//! Mode S lines carry `kind: "mode_s"`, `df`, `icao` (upper-case hex), `parity` and, as the
//! frame allows: `typecode`, `callsign`, `category`, `altitude_ft`, `altitude_gnss_ft`,
//! `lat_deg`/`lon_deg`/`position_method` (on the frame that completes a position),
//! `groundspeed_kt` (surface: lower edge of the movement bin, with `groundspeed_max_kt`),
//! `track_deg`, `airspeed_kt`, `airspeed_type`, `heading_deg`, `vertical_rate_fpm`,
//! `vertical_rate_source` (ME bit 36 read as DO-260B: 1 = baro; raw bit in `vr_source_bit`),
//! `gnss_minus_baro_ft`, `squawk`, `emergency`, `nac_p`, `nac_v`, `nic`, `nic_baro`, `sil`,
//! `gva`, `version`, and the receive fields `signal_dbm`, `signal_quality`, `ts_pps_ns`,
//! `ts_utc_ns`, `mlat_ticks`, `rssi_dbfs`. Mode A/C lines: `kind: "mode_ac"`, `code`. UAT
//! lines: `kind: "uat"`, `uplink`, `hex`.

use std::io::{Read, Write};

use anyhow::{Context, Result, bail};
use serde_json::{Map, Value, json};
use vigil_drivers::modes::decoder::{ModesMessage, ModesOutput};
use vigil_drivers::modes::df::{Content, Parity};
use vigil_drivers::modes::me::Me;
use vigil_drivers::modes::{DecodeOptions, ModesDecoder, TrackerConfig};
use vigil_drivers::ttmrf::raw::{RawFrame, RxMeta};
use vigil_drivers::{DeviceDecoder, ttmrf::raw::encode_hex_string};

use super::{JsonLines, Summary, TtFormat, run_decoder};

/// Parses `LAT,LON` in degrees.
fn parse_ref(s: &str) -> Result<(f64, f64)> {
    let (a, b) = s
        .split_once(',')
        .context("--ref must be LAT,LON in degrees")?;
    let lat: f64 = a
        .trim()
        .parse()
        .with_context(|| format!("--ref latitude {a:?}"))?;
    let lon: f64 = b
        .trim()
        .parse()
        .with_context(|| format!("--ref longitude {b:?}"))?;
    if !(-90.0..=90.0).contains(&lat) || !(-180.0..=180.0).contains(&lon) {
        bail!("--ref {s}: latitude must be within +-90 and longitude within +-180 degrees");
    }
    Ok((lat, lon))
}

/// Decodes raw Mode S frames.
pub fn decode<W: Write>(
    format: TtFormat,
    reference: Option<&str>,
    input: &mut dyn Read,
    out: &mut JsonLines<W>,
) -> Result<Summary> {
    let receiver = reference.map(parse_ref).transpose()?;
    let cfg = TrackerConfig {
        receiver,
        emit_reports: false,
        ..TrackerConfig::default()
    };
    let opts = DecodeOptions::default();
    match format {
        TtFormat::Hex | TtFormat::Hexd => run(ModesDecoder::hex(cfg, opts), input, out),
        TtFormat::Beast => run(ModesDecoder::beast(cfg, opts), input, out),
        other => bail!("{other:?} is not a raw Mode S format"),
    }
}

fn run<D, W>(
    mut dec: ModesDecoder<D>,
    input: &mut dyn Read,
    out: &mut JsonLines<W>,
) -> Result<Summary>
where
    D: DeviceDecoder<Message = RawFrame>,
    W: Write,
{
    let stats = run_decoder(&mut dec, input, out, |m, out| out.write(&to_json(&m)))?;
    let mut summary = Summary::new("ttmrf", stats);
    summary.extra = serde_json::to_value(dec.counters())?;
    Ok(summary)
}

fn meta_json(meta: &RxMeta, o: &mut Map<String, Value>) {
    let mut put = |k: &str, v: Value| {
        if !v.is_null() {
            o.insert(k.to_string(), v);
        }
    };
    put("signal_dbm", json!(meta.signal_dbm));
    put("signal_quality", json!(meta.signal_quality));
    put("ts_pps_ns", json!(meta.ts_pps_ns));
    put("ts_utc_ns", json!(meta.ts_utc_ns));
    put("mlat_ticks", json!(meta.mlat_ticks));
    put(
        "rssi_dbfs",
        json!(meta.signal_dbfs().map(|d| (d * 10.0).round() / 10.0)),
    );
}

/// The JSON object of one decoded message.
pub fn to_json(m: &ModesMessage) -> Value {
    let mut o = Map::new();
    match m {
        ModesMessage::ModeS(x) => mode_s_json(x, &mut o),
        ModesMessage::ModeAc(a) => {
            o.insert("kind".into(), json!("mode_ac"));
            o.insert("code".into(), json!(a.code.to_string()));
            meta_json(&a.meta, &mut o);
        }
        ModesMessage::Uat(u) => {
            o.insert("kind".into(), json!("uat"));
            o.insert("uplink".into(), json!(u.uplink));
            o.insert("hex".into(), json!(encode_hex_string(&u.bytes)));
            meta_json(&u.meta, &mut o);
        }
    }
    Value::Object(o)
}

fn mode_s_json(x: &ModesOutput, o: &mut Map<String, Value>) {
    let mut put = |k: &str, v: Value| {
        if !v.is_null() {
            o.insert(k.to_string(), v);
        }
    };
    let m = &x.msg;
    put("kind", json!("mode_s"));
    put("df", json!(m.df));
    put("icao", json!(format!("{:06X}", m.icao)));
    put("hex", json!(encode_hex_string(x.frame.data())));
    let parity = match m.parity {
        Parity::Verified => "verified",
        Parity::Interrogator(_) => "interrogator",
        Parity::Corrected(_) => "corrected",
        Parity::AddressParity => "address_parity",
    };
    put("parity", json!(parity));
    if let Parity::Interrogator(ii) = m.parity {
        put("interrogator_code", json!(ii));
    }
    match m.content {
        Content::AllCall { capability } => put("capability", json!(capability)),
        Content::Surveillance {
            status,
            altitude_ft,
            squawk,
            mb,
            callsign,
        } => {
            put(
                if matches!(m.df, 0 | 16) {
                    "vertical_status"
                } else {
                    "flight_status"
                },
                json!(status),
            );
            put("altitude_ft", json!(altitude_ft));
            put("squawk", json!(squawk.map(|s| s.to_string())));
            put("mb", json!(mb.map(|v| format!("{v:014X}"))));
            put("callsign", json!(callsign.map(|c| c.as_str().to_string())));
        }
        Content::Extended { ca_cf, me, .. } => {
            put(if m.df == 17 { "capability" } else { "cf" }, json!(ca_cf));
            put("typecode", json!(me.typecode()));
            me_json(&me, &mut put);
        }
        Content::NotDecoded => {}
    }
    if let Some(p) = x.position {
        put("lat_deg", json!(p.lat_deg));
        put("lon_deg", json!(p.lon_deg));
        put("position_method", json!(p.method));
        put("surface", json!(p.surface));
    }
    put("nic", json!(x.nic));
    meta_json(&x.frame.meta, o);
}

fn me_json(me: &Me, put: &mut impl FnMut(&str, Value)) {
    match me {
        Me::Identification(id) => {
            put("callsign", json!(id.callsign.as_str()));
            put(
                "category",
                json!(String::from_utf8_lossy(&id.category_code())),
            );
        }
        Me::SurfacePosition(s) => {
            put("groundspeed_kt", json!(s.speed.map(|b| b.min_kt)));
            put("groundspeed_max_kt", json!(s.speed.and_then(|b| b.max_kt)));
            put("track_deg", json!(s.track_deg));
            put("cpr_odd", json!(s.cpr.odd));
        }
        Me::AirbornePosition(p) => {
            put("altitude_ft", json!(p.altitude_baro_ft));
            put("altitude_gnss_ft", json!(p.altitude_gnss_ft));
            put("surveillance_status", json!(p.surveillance_status));
            put("cpr_odd", json!(p.cpr.odd));
        }
        Me::Velocity(v) => {
            put("subtype", json!(v.subtype));
            put("groundspeed_kt", json!(v.groundspeed_kt));
            put("track_deg", json!(v.track_deg));
            put("airspeed_kt", json!(v.airspeed_kt));
            if v.airspeed_kt.is_some() {
                put(
                    "airspeed_type",
                    json!(if v.airspeed_true { "tas" } else { "ias" }),
                );
            }
            put("heading_deg", json!(v.heading_deg));
            put("vertical_rate_fpm", json!(v.vertical_rate_fpm));
            put("vertical_rate_source", json!(v.vertical_rate_source));
            put("vr_source_bit", json!(v.vr_source_bit));
            put("gnss_minus_baro_ft", json!(v.gnss_minus_baro_ft));
            put("nac_v", json!(v.nac_v));
        }
        Me::Status(s) => {
            put("subtype", json!(s.subtype));
            put("emergency", json!(s.emergency));
            put("squawk", json!(s.squawk.map(|q| q.to_string())));
        }
        Me::TargetState(t) => {
            put("selected_altitude_ft", json!(t.selected_altitude_ft));
            put("baro_setting_hpa", json!(t.baro_setting_hpa));
            put("selected_heading_deg", json!(t.selected_heading_deg));
            put("nac_p", json!(t.nac_p));
            put("nic_baro", json!(u8::from(t.nic_baro)));
            put("sil", json!(t.sil));
        }
        Me::OperationalStatus(s) => {
            put("subtype", json!(s.subtype));
            put("version", json!(s.version));
            put("nic_a", json!(s.nic_a));
            put("nic_c", json!(s.nic_c));
            put("nac_p", json!(s.nac_p));
            put("nac_v", json!(s.nac_v));
            put("gva", json!(s.gva));
            put("sil", json!(s.sil));
            put("nic_baro", json!(s.nic_baro.map(u8::from)));
            put(
                "hrd",
                json!(s.hrd_magnetic.map(|m| if m { "magnetic" } else { "true" })),
            );
        }
        Me::Other { subtype, .. } => put("subtype", json!(subtype)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_parsing() {
        assert_eq!(parse_ref("52.3, 4.7").unwrap(), (52.3, 4.7));
        assert!(parse_ref("52.3").is_err());
        assert!(parse_ref("91,0").is_err());
        assert!(parse_ref("a,b").is_err());
    }

    #[test]
    fn json_of_the_riddle_frames() {
        let text = b"*8D4840D6202CC371C32CE0576098; (-70,3,75BCD15,2B5792B49315)\r\n\
*8D40621D58C386435CC412692AD6;\n*8D40621D58C382D690C8AC2863A7;\n*8D485020994409940838175B284F;\n*7700;\n";
        let mut d = ModesDecoder::hex(TrackerConfig::default(), DecodeOptions::default());
        let v: Vec<Value> = vigil_drivers::decode_slice(&mut d, text)
            .iter()
            .map(to_json)
            .collect();
        assert_eq!(v.len(), 5);
        assert_eq!(v[0]["icao"], "4840D6");
        assert_eq!(v[0]["callsign"], "KLM1023");
        assert_eq!(v[0]["typecode"], 4);
        assert_eq!(v[0]["signal_dbm"], -70);
        assert_eq!(v[0]["ts_utc_ns"], 47_655_123_456_789u64);
        assert!(v[1].get("lat_deg").is_none());
        assert_eq!(v[2]["altitude_ft"], 38_000);
        assert!((v[2]["lat_deg"].as_f64().unwrap() - 52.2572).abs() < 1e-4);
        assert!((v[2]["lon_deg"].as_f64().unwrap() - 3.9194).abs() < 1e-4);
        assert_eq!(v[3]["vertical_rate_fpm"], -832);
        assert!((v[3]["groundspeed_kt"].as_f64().unwrap() - 159.2).abs() < 0.01);
        assert_eq!(v[4]["kind"], "mode_ac");
        assert_eq!(v[4]["code"], "7700");
    }
}
