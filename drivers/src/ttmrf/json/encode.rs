//! Encoding a [`JsonMessage`] in the module's wire form (the field names of the manual's
//! examples, unknown fields omitted, compact, one message per line), for the simulator and the
//! round-trip tests that tie it to the decoder.

use serde_json::{Map, Value, json};

use super::JsonMessage;
use super::sections::{
    AdsbTarget, FlarmTarget, Gnss, RawFrame, TargetFlags, UatStatusFlags, UatTarget,
};

fn put<T: Into<Value>>(m: &mut Map<String, Value>, key: &str, v: Option<T>) {
    if let Some(v) = v {
        m.insert(key.to_owned(), v.into());
    }
}

fn flags(f: &TargetFlags) -> Value {
    let mut m = Map::new();
    put(&mut m, "groundState", f.on_ground);
    put(&mut m, "updAltBaro", f.upd_alt_baro);
    put(&mut m, "updAltGeo", f.upd_alt_geo);
    put(&mut m, "updPosition", f.upd_position);
    put(&mut m, "updTrack", f.upd_track);
    put(&mut m, "updVeloH", f.upd_velo_h);
    put(&mut m, "updVeloV", f.upd_velo_v);
    Value::Object(m)
}

fn squawk(s: Option<u16>) -> Option<String> {
    s.map(|s| format!("{s:04}"))
}

fn adsb(a: &AdsbTarget) -> Value {
    let mut m = Map::new();
    m.insert("icao".into(), format!("{:06X}", a.icao & 0xFF_FFFF).into());
    if let Some(f) = &a.flags {
        m.insert("flags".into(), flags(f));
    }
    put(&mut m, "sigStr", a.sig_dbm);
    put(&mut m, "sigQ", a.sig_q_db);
    put(&mut m, "fps", a.fps);
    put(&mut m, "lat", a.lat_deg);
    put(&mut m, "lon", a.lon_deg);
    put(&mut m, "altBaro", a.alt_baro_ft);
    put(&mut m, "geoAlt", a.alt_geo_ft);
    put(&mut m, "track", a.track_deg);
    put(&mut m, "velH", a.velh_kt);
    put(&mut m, "velV", a.velv_fpm);
    put(&mut m, "mag_heading", a.mag_heading_deg);
    put(&mut m, "true_heading", a.true_heading_deg);
    put(&mut m, "ias", a.ias_kt);
    put(&mut m, "tas", a.tas_kt);
    put(&mut m, "roll", a.roll_deg);
    put(&mut m, "nav_qnh", a.nav_qnh_hpa);
    put(&mut m, "nav_altitude_mcp", a.nav_altitude_mcp_ft);
    put(&mut m, "nav_altitude_fms", a.nav_altitude_fms_ft);
    if let Some(n) = &a.nav_modes {
        let mut o = Map::new();
        put(&mut o, "althold", n.althold);
        put(&mut o, "approach", n.approach);
        put(&mut o, "autopilot", n.autopilot);
        put(&mut o, "lnav", n.lnav);
        put(&mut o, "tcas", n.tcas);
        put(&mut o, "vnav", n.vnav);
        m.insert("nav_modes".into(), Value::Object(o));
    }
    put(&mut m, "nav_heading", a.nav_heading_deg);
    put(&mut m, "call", a.callsign.clone());
    put(&mut m, "ecat", a.ecat);
    put(&mut m, "squawk", squawk(a.squawk));
    put(&mut m, "nacp", a.nac_p);
    put(&mut m, "nacv", a.nac_v);
    put(&mut m, "nicBaro", a.nic_baro);
    put(&mut m, "nic", a.nic);
    Value::Object(m)
}

fn uat_flags(f: &UatStatusFlags) -> Value {
    let mut m = Map::new();
    put(&mut m, "utcCoupling", f.utc_coupling);
    put(&mut m, "cdti", f.cdti);
    put(&mut m, "acasOperational", f.acas_operational);
    put(&mut m, "acasActive", f.acas_active);
    put(&mut m, "identActive", f.ident_active);
    put(&mut m, "atcActive", f.atc_active);
    put(&mut m, "headingMagnetic", f.heading_magnetic);
    Value::Object(m)
}

fn uat(u: &UatTarget) -> Value {
    let mut m = Map::new();
    m.insert("icao".into(), format!("{:06X}", u.icao & 0xFF_FFFF).into());
    if let Some(f) = &u.flags {
        m.insert("flags".into(), flags(f));
    }
    // The manual's UAT example sends the squawk as a number.
    put(&mut m, "squawk", u.squawk);
    put(&mut m, "call", u.callsign.clone());
    put(&mut m, "lat", u.lat_deg);
    put(&mut m, "lon", u.lon_deg);
    put(&mut m, "altBaro", u.alt_baro_ft);
    put(&mut m, "track", u.track_deg);
    put(&mut m, "velH", u.velh_kt);
    put(&mut m, "velV", u.velv_fpm);
    put(&mut m, "sigStr", u.sig_dbm);
    put(&mut m, "sigQ", u.sig_q_errors);
    put(&mut m, "fps", u.fps);
    if let Some(n) = &u.nicnac {
        let mut o = Map::new();
        put(&mut o, "nacP", n.nac_p);
        put(&mut o, "nacv", n.nac_v);
        put(&mut o, "nicBaro", n.nic_baro);
        put(&mut o, "nic", n.nic);
        m.insert("nicnac".into(), Value::Object(o));
    }
    put(&mut m, "altGeo", u.alt_geo_ft);
    put(&mut m, "ecat", u.ecat);
    put(&mut m, "emergency", u.emergency);
    if let Some(f) = &u.uat_flags {
        m.insert("uatFlags".into(), uat_flags(f));
    }
    Value::Object(m)
}

fn flarm(f: &FlarmTarget) -> Value {
    let mut m = Map::new();
    put(&mut m, "idType", f.id_type);
    m.insert("id".into(), format!("{:06X}", f.id).into());
    put(&mut m, "type", f.aircraft_type);
    put(&mut m, "danger", f.alarm_level);
    put(&mut m, "fps", f.fps);
    put(&mut m, "lat", f.lat_deg);
    put(&mut m, "lon", f.lon_deg);
    put(&mut m, "alt", f.alt_m);
    put(&mut m, "track", f.track_deg);
    put(&mut m, "hVelo", f.velh_mps);
    put(&mut m, "vVelo", f.velv_mps);
    put(&mut m, "movMode", f.move_mode);
    put(&mut m, "stealth", f.stealth);
    put(&mut m, "notrack", f.notrack);
    Value::Object(m)
}

fn gnss(g: &Gnss) -> Value {
    let mut m = Map::new();
    put(&mut m, "fix", g.fix);
    put(&mut m, "lat", g.lat_deg);
    put(&mut m, "lon", g.lon_deg);
    put(&mut m, "altWgs84", g.alt_wgs84_m);
    put(&mut m, "altMsl", g.alt_msl_m);
    put(&mut m, "track", g.track_deg);
    put(&mut m, "hVelo", g.velh_kt);
    put(&mut m, "vVelo", g.velv_mps);
    if let Some([e, n]) = g.gnd_speed_en_kt {
        m.insert("gndSpeed".into(), json!([e, n]));
    }
    if let Some(a) = &g.acc {
        let mut o = Map::new();
        put(&mut o, "lat", a.lat_m);
        put(&mut o, "lon", a.lon_m);
        put(&mut o, "alt", a.alt_m);
        m.insert("acc".into(), Value::Object(o));
    }
    put(&mut m, "nacp", g.nac_p);
    put(&mut m, "nacv", g.nac_v);
    put(&mut m, "nic", g.nic);
    Value::Object(m)
}

fn raw(r: &RawFrame) -> Value {
    json!([
        r.frame_hex,
        r.sig_dbm,
        r.sig_q_db,
        r.ts_ns.map(|t| format!("{t:X}")),
    ])
}

impl JsonMessage {
    /// The message as the module sends it: compact JSON with the manual's field names, fields
    /// that are `None` omitted, followed by `\r\n`.
    pub fn to_wire(&self) -> String {
        let mut m = Map::new();
        put(&mut m, "src", self.src.clone());
        put(&mut m, "ts", self.ts_ms);
        put(&mut m, "ver", self.ver);
        if let Some(s) = &self.status {
            let mut o = Map::new();
            put(&mut o, "fw", s.fw.clone());
            m.insert("status".into(), Value::Object(o));
        }
        if !self.adsb.is_empty() {
            m.insert("adsb".into(), self.adsb.iter().map(adsb).collect());
        }
        if !self.uat.is_empty() {
            m.insert("uat".into(), self.uat.iter().map(uat).collect());
        }
        if !self.flarm.is_empty() {
            m.insert("flarm".into(), self.flarm.iter().map(flarm).collect());
        }
        if let Some(g) = &self.gnss {
            m.insert("gnss".into(), gnss(g));
        }
        if !self.raw.is_empty() {
            m.insert("raw".into(), self.raw.iter().map(raw).collect());
        }
        let mut s = Value::Object(m).to_string();
        s.push_str("\r\n");
        s
    }
}
