//! Aerobits TT-Multi-RF device model (TT-Multi-RF manual): the RUN / CONFIGURATION /
//! BOOTLOADER states and AT messages (manual 4, 5) through [`SimModule`]; in RUN the decoded
//! traffic protocol (CSV 6.4 / 7.2.1 / 8.2.1 / 10.2.1, JSON 6.6, or the binary MAVLink, GDL90
//! and ASTERIX of 7.2.1 / 8.2.1, see [`super::ttmrf_binary`]), the JSON GNSS section (9.2.2)
//! and raw Mode S frames (7.2.2: HEX with extended fields, HEXd or Beast) for ADS-B targets,
//! every byte encoded by the drivers' encoders.
//!
//! What is sent follows the module's stored settings, as on the device: the scenario's
//! `protocol` and `raw` are written to `ADSB_RX_PROTOCOL_DECODED` / `ADSB_RX_PROTOCOL_RAW` at
//! power-on, and an AT write in CONFIGURATION changes them for the next RUN (the module saves
//! settings on leaving CONFIGURATION, 4.1.3). Decision: the model drives every subsystem's
//! decoded output (ADS-B, UAT, FLARM) from `ADSB_RX_PROTOCOL_DECODED`, limited to the links the
//! protocol carries (GDL90: ADS-B only; ASTERIX: ADS-B and FLARM; the others all), rather than
//! modelling `UAT_DECODED_PROTOCOL` / `FLARM_RX_PROTOCOL_DECODED` apart: one port then carries
//! one decoded protocol. The recording channel's protocol (`ttmrf-text`, `ttmrf-mavlink`,
//! `ttmrf-gdl90`, `ttmrf-asterix`) is the one configured at start.
//!
//! Schedule (all on GPS time, whole milliseconds, so JSON `ts` is exact):
//! - one traffic message per intruder per second, intruder `i` of `n` at `(i + 1) * 1000 /
//!   (n + 1)` ms into each second (spread, like a receiver reporting its table in turn), or
//!   with `list_at_once` all at the whole second after the GNSS output (the list sent at once,
//!   the other reading of the manual's "sending list of aircraft every second"); JSON
//!   sends one target per message, in the array of its link (`adsb`, `uat`, `flarm`); ASTERIX
//!   one record per data block;
//! - at every whole second: with `gnss = true`, the JSON `gnss` section (JSON), or NMEA `$GPGGA`
//!   and `$GPRMC` (CSV; manual 9.2.1), UTC time of day and date; whatever `gnss` says, the GDL90
//!   Heartbeat, Ownship Report and Ownship Geometric Altitude (GDL90) or the CAT023 status
//!   (ASTERIX), which the manual lists as part of those protocols; nothing for MAVLink;
//! - raw frames of each ADS-B target (raw != "off"), at its phase plus: 100 ms even and 600 ms
//!   odd airborne position (TC 11), 350 and 850 ms airborne velocity (TC 19 subtype 1), and
//!   identification (TC 1-4) at 200 ms every 5 s: 2 + 2 + 0.2 frames per second as DO-260B
//!   transmitters. HEX times: TS1s = ns since the last whole second (the PPS), TS24h = ns since
//!   UTC midnight; Beast: the 12 MHz counter = UTC ns of day * 12 / 1000.
//!
//! Values: barometric altitude = the ISA pressure altitude of the truth (whole ft in CSV/JSON,
//! the Mode S encoder quantises to 25 ft); geometric altitude = WGS-84 height; ADS-B/UAT NIC 8,
//! NACp 9, NACv 1, NICbaro 1 (a GNSS-equipped transponder); emitter category as the GDL90 number
//! (A0-A7 = 0-7, B0-B7 = 8-15, C = 16-23, D = 24-31); a `spoof_offset_ned_m` intruder reports
//! its spoofed position (the truth records both). GNSS section: 3-D fix with 2.5 m / 4 m
//! accuracy and matching noise; during a `gnss_outage` fault `fix` = 0 and nothing else.
//!
//! AT commands from the host go to [`SimModule`] at the module's current baud (a pseudo-terminal
//! has no baud; the link keeps the scenario's); the module acts on a command (state changes
//! included) and its answers leave 1 ms after the window that delivered it. Outside RUN no
//! traffic, GNSS or raw output is sent. A `device_reset` fault power-cycles the module
//! (BOOTLOADER then RUN messages).
//!
//! Truth: `type` = "adsb" / "uat" / "flarm" (traffic message, any protocol; `protocol` names
//! it), "gnss", "nmea_gga", "nmea_rmc", "gdl90_heartbeat", "gdl90_ownship",
//! "gdl90_ownship_geo_altitude", "asterix_status", "raw_position", "raw_velocity",
//! "raw_identification", "at"; values: `address`, true `lat_deg`, `lon_deg`, `height_m`,
//! `alt_pressure_m`, `vel_ned_mps`, `track_rad`, the `reported_*` position, `nic`, `nac_p`,
//! `ts_ms` (ownship messages: the true ownship and `fix`).

use bytes::BytesMut;
use serde_json::{Map, Value, json};
use vigil_drivers::modes::encode::{
    AirbornePositionFields, airborne_position, identification, velocity_ground,
};
use vigil_drivers::ttmrf::csv::{
    AdsbAircraft, AircraftFlags, AircraftState, CsvMessage, FlarmAircraft, NicNac, UatAircraft,
};
use vigil_drivers::ttmrf::json::{AdsbTarget, FlarmTarget, JsonMessage, UatNicNac, UatTarget};
use vigil_drivers::ttmrf::raw::{ModeSFrame, RawFrame, RxMeta, beast, hex};

use vigil_drivers::ttmrf::asterix::common::DataSource;
use vigil_drivers::ttmrf::at::{DecodedProtocol, RawProtocol, SettingId};

use vigil_drivers::protocol::Protocol;

use super::ttmrf_binary::{self, Binary, Target, carries};
use super::{DeviceModel, Emission, FaultSchedule};
use crate::rng::Rng;
use crate::scenario::{Link, TtmrfConfig};
use crate::truth::{IntruderTruth, World};
use crate::ttmrf_module::SimModule;
use crate::units::{GPS_MINUS_UTC_S, NS_PER_S};

const MS: i64 = 1_000_000;
const FT_PER_M: f64 = 1.0 / 0.3048;
const KT_PER_MPS: f64 = 3600.0 / 1852.0;
const FPM_PER_MPS: f64 = 60.0 / 0.3048;
/// Serial number the module reports (`src`).
pub const SERIAL: &str = "TTMRF0001";
/// GNSS horizontal accuracy reported and simulated (1 sigma), m.
pub const GNSS_H_SIGMA_M: f64 = 2.5;
/// GNSS vertical accuracy reported and simulated (1 sigma), m.
pub const GNSS_V_SIGMA_M: f64 = 4.0;

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Event {
    /// The whole second: GNSS section / NMEA, GDL90 heartbeat and ownship, ASTERIX status.
    Second,
    Traffic(usize),
    Position(usize, bool),
    Velocity(usize),
    Ident(usize),
}

/// The GDL90 emitter category number of "A3", "B6", ... (`None` if empty or malformed).
pub fn ecat_number(s: &str) -> Option<u8> {
    let mut c = s.chars();
    let set = match c.next()?.to_ascii_uppercase() {
        'A' => 0,
        'B' => 8,
        'C' => 16,
        'D' => 24,
        _ => return None,
    };
    let d = c.next()?.to_digit(10).filter(|d| *d <= 7)? as u8;
    c.next().is_none().then_some(set + d)
}

/// Milliseconds since UTC midnight of a GPS time.
pub fn utc_ms_of_day(t_gps_ns: i64) -> u32 {
    ((t_gps_ns - GPS_MINUS_UTC_S * NS_PER_S).rem_euclid(86_400 * NS_PER_S) / MS) as u32
}

/// Milliseconds since UTC midnight of a GPS time, rounded to the nearest ms (wrapping at 24 h).
pub fn utc_ms_of_day_rounded(t_gps_ns: i64) -> u32 {
    (((t_gps_ns - GPS_MINUS_UTC_S * NS_PER_S + MS / 2).rem_euclid(86_400 * NS_PER_S)) / MS) as u32
}

fn utc_ns_of_day(t_gps_ns: i64) -> u64 {
    (t_gps_ns - GPS_MINUS_UTC_S * NS_PER_S).rem_euclid(86_400 * NS_PER_S) as u64
}

/// The scenario name of a decoded protocol (truth `protocol`).
pub fn protocol_name(p: DecodedProtocol) -> &'static str {
    match p {
        DecodedProtocol::None => "none",
        DecodedProtocol::Csv => "csv",
        DecodedProtocol::Mavlink => "mavlink",
        DecodedProtocol::Json => "json",
        DecodedProtocol::Gdl90 => "gdl90",
        DecodedProtocol::Asterix => "asterix",
    }
}

fn obj(v: Value) -> Map<String, Value> {
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

fn round_to(v: f64, step: f64) -> f64 {
    (v / step).round() * step
}

/// The TT-Multi-RF model.
pub struct TtmrfModel {
    cfg: TtmrfConfig,
    module: SimModule,
    noise: Rng,
    n: usize,
    links: Vec<Link>,
    /// Events of the current second, sorted by time, not yet sent.
    queue: Vec<(i64, Event)>,
    next_second: i64,
    answers: Vec<(i64, Vec<u8>)>,
    /// Host bytes and the time the module acts on them.
    inbox: Vec<(i64, Vec<u8>)>,
    resets_ns: Vec<i64>,
    /// The recording channel's protocol (the decoded protocol configured at start).
    channel: &'static str,
    /// MAVLink packet sequence number of the next frame.
    mavlink_seq: u8,
    /// Time-offset faults of its `ts` / TS24h (issue 18 point 4) and the scenario start, ns.
    faults: FaultSchedule,
    start_gps_ns: i64,
}

/// The value of `ADSB_RX_PROTOCOL_DECODED` (manual table 12) for a scenario protocol name.
pub fn decoded_protocol_of(name: &str) -> DecodedProtocol {
    match name {
        "csv" => DecodedProtocol::Csv,
        "mavlink" => DecodedProtocol::Mavlink,
        "json" => DecodedProtocol::Json,
        "gdl90" => DecodedProtocol::Gdl90,
        "asterix" => DecodedProtocol::Asterix,
        _ => DecodedProtocol::None,
    }
}

/// The value of `ADSB_RX_PROTOCOL_RAW` (manual table 12) for a scenario raw name.
pub fn raw_protocol_of(name: &str) -> RawProtocol {
    match name {
        "hex" => RawProtocol::Hex,
        "beast" => RawProtocol::Beast,
        "hexd" => RawProtocol::Hexd,
        _ => RawProtocol::None,
    }
}

/// The recording channel protocol of a port whose decoded protocol is `name` at start.
pub fn channel_protocol(name: &str) -> &'static str {
    match name {
        "mavlink" => Protocol::TtmrfMavlink,
        "gdl90" => Protocol::TtmrfGdl90,
        "asterix" => Protocol::TtmrfAsterix,
        _ => Protocol::TtmrfText,
    }
    .name()
}

impl TtmrfModel {
    /// The JSON `ts` of a message at GPS time `t` (truncated or rounded, as configured).
    pub(crate) fn ts_ms(&self, t: i64) -> u32 {
        let t = self.stamp_time(t);
        if self.cfg.ts_rounded {
            utc_ms_of_day_rounded(t)
        } else {
            utc_ms_of_day(t)
        }
    }

    /// The GPS time the module's `ts` / TS24h name for an event at `t`: `t`, or `t` plus a
    /// [`crate::scenario::Fault::DeviceTimeOffset`] in force.
    fn stamp_time(&self, t: i64) -> i64 {
        let elapsed_s = (t - self.start_gps_ns) as f64 / NS_PER_S as f64;
        t + self.faults.time_offset_ns("ttmrf", elapsed_s)
    }

    /// A module powered on before the scenario start, in RUN.
    pub fn new(cfg: &TtmrfConfig, world: &World, faults: &FaultSchedule, seed: u64) -> Self {
        let n = world.intruder_count();
        let links = (0..n)
            .filter_map(|i| world.intruder(i, world.start_gps_ns).map(|t| t.link))
            .collect();
        let start = world.start_gps_ns;
        let mut module = SimModule::new(SERIAL, "1.0.0");
        module.set_stored(
            SettingId::AdsbRxProtocolDecoded.name(),
            &(decoded_protocol_of(&cfg.protocol) as i64).to_string(),
        );
        module.set_stored(
            SettingId::AdsbRxProtocolRaw.name(),
            &(raw_protocol_of(&cfg.raw) as i64).to_string(),
        );
        Self {
            cfg: cfg.clone(),
            module,
            noise: Rng::stream(seed, "ttmrf/noise"),
            n,
            links,
            queue: Vec::new(),
            next_second: start.div_euclid(NS_PER_S),
            answers: Vec::new(),
            inbox: Vec::new(),
            resets_ns: faults
                .resets("ttmrf")
                .into_iter()
                .rev()
                .map(|s| start + (s * 1e9).round() as i64)
                .collect(),
            channel: channel_protocol(&cfg.protocol),
            mavlink_seq: 0,
            faults: faults.clone(),
            start_gps_ns: start,
        }
    }

    fn setting(&self, id: SettingId) -> Option<i64> {
        self.module
            .stored(id.name())
            .and_then(|v| v.trim().parse().ok())
    }

    /// The decoded protocol the module sends now (its stored `ADSB_RX_PROTOCOL_DECODED`: the
    /// model drives every subsystem's decoded output from it, see the module doc).
    pub fn decoded_protocol(&self) -> DecodedProtocol {
        match self.setting(SettingId::AdsbRxProtocolDecoded) {
            Some(1) => DecodedProtocol::Csv,
            Some(2) => DecodedProtocol::Mavlink,
            Some(3) => DecodedProtocol::Json,
            Some(4) => DecodedProtocol::Gdl90,
            Some(5) => DecodedProtocol::Asterix,
            _ => DecodedProtocol::None,
        }
    }

    /// The raw protocol the module sends now (its stored `ADSB_RX_PROTOCOL_RAW`).
    pub fn raw_protocol(&self) -> RawProtocol {
        match self.setting(SettingId::AdsbRxProtocolRaw) {
            Some(1) => RawProtocol::Hex,
            Some(2) => RawProtocol::Beast,
            Some(3) => RawProtocol::Json,
            Some(4) => RawProtocol::Hexd,
            _ => RawProtocol::None,
        }
    }

    fn asterix_source(&self) -> DataSource {
        let byte = |id| {
            self.setting(id)
                .and_then(|v| u8::try_from(v).ok())
                .unwrap_or(0)
        };
        DataSource {
            sac: byte(SettingId::AsterixSac),
            sic: byte(SettingId::AsterixSic),
        }
    }

    /// The simulated module (state, settings).
    pub fn module(&self) -> &SimModule {
        &self.module
    }

    fn phase_ns(&self, i: usize) -> i64 {
        (i as i64 + 1) * 1000 / (self.n as i64 + 1) * MS
    }

    /// Queues the events of GPS second `s`.
    fn schedule(&mut self, s: i64) {
        let base = s * NS_PER_S;
        self.queue.push((base, Event::Second));
        // JSON raw output (setting 3) is not modelled: nothing is sent for it.
        let raw = matches!(
            self.raw_protocol(),
            RawProtocol::Hex | RawProtocol::Hexd | RawProtocol::Beast
        );
        for i in 0..self.n {
            let p = base + self.phase_ns(i);
            // A list sent at once: at the whole second, after `Event::Second` (the queue pops
            // equal times in event order), in target order.
            let at = if self.cfg.list_at_once { base } else { p };
            self.queue.push((at, Event::Traffic(i)));
            if raw && self.links[i] == Link::Adsb1090 {
                self.queue.push((p + 100 * MS, Event::Position(i, false)));
                self.queue.push((p + 350 * MS, Event::Velocity(i)));
                self.queue.push((p + 600 * MS, Event::Position(i, true)));
                self.queue.push((p + 850 * MS, Event::Velocity(i)));
                if (s + i as i64).rem_euclid(5) == 0 {
                    self.queue.push((p + 200 * MS, Event::Ident(i)));
                }
            }
        }
        // Sorted descending so the next event pops from the end.
        self.queue.sort_by(|a, b| b.cmp(a));
    }

    fn send_line(&mut self, line: &[u8]) -> Option<Vec<u8>> {
        if !self.module.emit_line(line) {
            return None;
        }
        self.module.poll_output().map(|(_, b)| b)
    }

    /// One traffic message of intruder `i` at `t`: `it` is its truth at `t`, `rep` the state its
    /// report carries (its truth `report_age_s` earlier, issue 24; else `it` again).
    fn traffic(
        &mut self,
        t: i64,
        i: usize,
        it: &IntruderTruth,
        rep: &IntruderTruth,
    ) -> Option<Emission> {
        if it.silent {
            return None;
        }
        let [lat, lon, h] =
            rep.reported_position
                .unwrap_or([rep.lat_deg, rep.lon_deg, rep.height_m]);
        let [vn, ve, vd] = rep.vel_ned_mps;
        let track_deg = round_to(rep.track_rad.to_degrees().rem_euclid(360.0), 0.1) % 360.0;
        let velh_kt = (vn.hypot(ve) * KT_PER_MPS).round();
        let velv_fpm = round_to(-vd * FPM_PER_MPS, 64.0);
        let alt_baro_ft = (rep.alt_pressure_m * FT_PER_M).round();
        let alt_geo_ft = (h * FT_PER_M).round();
        // Issue 24: the fields the scenario leaves out (JSON and CSV output).
        let (no_alt, no_vel, no_vs) = (
            it.omits("altitude"),
            it.omits("velocity"),
            it.omits("vertical_rate"),
        );
        let keep = |omit: bool, v: f64| (!omit).then_some(v);
        let (lat, lon) = (round_to(lat, 1e-6), round_to(lon, 1e-6));
        let icao = u32::from_str_radix(&it.address, 16).unwrap_or(0) & 0xFF_FFFF;
        let ecat = ecat_number(&it.emitter_category);
        let callsign = (!it.callsign.is_empty()).then(|| it.callsign.clone());
        let ts_ms = self.ts_ms(t);
        let protocol = self.decoded_protocol();
        let binary = match protocol {
            DecodedProtocol::None => return None,
            DecodedProtocol::Mavlink => Some(Binary::Mavlink),
            DecodedProtocol::Gdl90 => Some(Binary::Gdl90),
            DecodedProtocol::Asterix => Some(Binary::Asterix),
            DecodedProtocol::Csv | DecodedProtocol::Json => None,
        };
        let kind = match it.link {
            Link::Adsb1090 => "adsb",
            Link::Uat978 => "uat",
            Link::Flarm => "flarm",
        };
        let (kind, line) = match (protocol, it.link, binary) {
            (_, _, Some(b)) => {
                if !carries(b, it.link) {
                    return None;
                }
                let target = Target {
                    link: it.link,
                    icao,
                    lat_deg: lat,
                    lon_deg: lon,
                    height_m: h,
                    alt_pressure_m: rep.alt_pressure_m,
                    vel_ned_mps: rep.vel_ned_mps,
                    track_deg,
                    callsign: it.callsign.clone(),
                    ecat,
                    age_s: it.report_age_s.round().clamp(0.0, 255.0) as u8,
                };
                let bytes = match b {
                    Binary::Mavlink => {
                        let seq = self.mavlink_seq;
                        self.mavlink_seq = seq.wrapping_add(1);
                        ttmrf_binary::mavlink_vehicle(seq, &target)
                    }
                    Binary::Gdl90 => ttmrf_binary::gdl90_traffic(&target),
                    Binary::Asterix => ttmrf_binary::asterix_target(
                        &target,
                        utc_ns_of_day(t) as f64 / 1e9,
                        self.asterix_source(),
                        // Track numbers 1.. by intruder (12 bits).
                        ((i + 1) % 4096) as u16,
                    ),
                };
                (kind, bytes)
            }
            (DecodedProtocol::Csv, Link::Flarm, _) => (
                "flarm",
                CsvMessage::Flarm(FlarmAircraft {
                    id: icao,
                    id_type: Some(1),
                    lat_deg: Some(lat),
                    lon_deg: Some(lon),
                    alt_m: keep(no_alt, h.round()),
                    track_deg: keep(no_vel, track_deg),
                    velh_mps: keep(no_vel, round_to(vn.hypot(ve), 0.1)),
                    velv_mps: keep(no_vs, round_to(-vd, 0.1)),
                    ..Default::default()
                })
                .to_line()
                .into_bytes(),
            ),
            (DecodedProtocol::Csv, link, _) => {
                let state = AircraftState {
                    icao,
                    flags: Some(AircraftFlags::from_raw(0x3F00)),
                    callsign,
                    squawk: None,
                    lat_deg: Some(lat),
                    lon_deg: Some(lon),
                    alt_baro_ft: keep(no_alt, alt_baro_ft),
                    track_deg: keep(no_vel, track_deg),
                    velh_kt: keep(no_vel, velh_kt),
                    velv_fpm: keep(no_vs, velv_fpm),
                    sig_dbm: Some(-70.0),
                    sig_q: Some(10.0),
                    fps: Some(5),
                    nicnac: Some(NicNac::from_raw(NicNac::pack(8, 1, 9, 1))),
                    alt_geo_ft: keep(no_alt, alt_geo_ft),
                    ecat,
                };
                if link == Link::Uat978 {
                    let m = UatAircraft {
                        state,
                        ..Default::default()
                    };
                    ("uat", CsvMessage::Uat(m).to_line().into_bytes())
                } else {
                    let m = AdsbAircraft {
                        state,
                        ..Default::default()
                    };
                    ("adsb", CsvMessage::Adsb(m).to_line().into_bytes())
                }
            }
            (_, link, _) => {
                let mut m = JsonMessage {
                    src: Some(SERIAL.into()),
                    ts_ms: Some(ts_ms),
                    ver: Some(1),
                    ..Default::default()
                };
                let kind = match link {
                    Link::Adsb1090 => {
                        m.adsb.push(AdsbTarget {
                            icao,
                            sig_dbm: Some(-70.0),
                            fps: Some(5),
                            lat_deg: Some(lat),
                            lon_deg: Some(lon),
                            alt_baro_ft: keep(no_alt, alt_baro_ft),
                            alt_geo_ft: keep(no_alt, alt_geo_ft),
                            track_deg: keep(no_vel, track_deg),
                            velh_kt: keep(no_vel, velh_kt),
                            velv_fpm: keep(no_vs, velv_fpm),
                            callsign,
                            ecat,
                            nac_p: Some(9),
                            nac_v: Some(1),
                            nic_baro: Some(1),
                            nic: Some(8),
                            ..Default::default()
                        });
                        "adsb"
                    }
                    Link::Uat978 => {
                        m.uat.push(UatTarget {
                            icao,
                            callsign,
                            lat_deg: Some(lat),
                            lon_deg: Some(lon),
                            alt_baro_ft: keep(no_alt, alt_baro_ft),
                            alt_geo_ft: keep(no_alt, alt_geo_ft),
                            track_deg: keep(no_vel, track_deg),
                            velh_kt: keep(no_vel, velh_kt),
                            velv_fpm: keep(no_vs, velv_fpm),
                            sig_dbm: Some(-75.0),
                            fps: Some(1),
                            nicnac: Some(UatNicNac {
                                nac_p: Some(9),
                                nac_v: Some(1),
                                nic_baro: Some(1),
                                nic: Some(8),
                            }),
                            ecat,
                            ..Default::default()
                        });
                        "uat"
                    }
                    Link::Flarm => {
                        m.flarm.push(FlarmTarget {
                            id_type: Some(1),
                            id: icao,
                            fps: Some(1),
                            lat_deg: Some(lat),
                            lon_deg: Some(lon),
                            alt_m: keep(no_alt, h.round()),
                            track_deg: keep(no_vel, track_deg),
                            velh_mps: keep(no_vel, round_to(vn.hypot(ve), 0.1)),
                            velv_mps: keep(no_vs, round_to(-vd, 0.1)),
                            ..Default::default()
                        });
                        "flarm"
                    }
                };
                (kind, m.to_wire().into_bytes())
            }
        };
        let bytes = self.send_line(&line)?;
        let v = json!({
            "protocol": protocol_name(protocol),
            "intruder": i,
            "address": it.address,
            "callsign": it.callsign,
            "lat_deg": it.lat_deg,
            "lon_deg": it.lon_deg,
            "height_m": it.height_m,
            "alt_pressure_m": it.alt_pressure_m,
            "vel_ned_mps": it.vel_ned_mps,
            "track_rad": it.track_rad,
            "reported_lat_deg": lat,
            "reported_lon_deg": lon,
            "reported_height_m": h,
            "spoofed": rep.reported_position.is_some(),
            "report_age_s": it.report_age_s,
            "nic": 8,
            "nac_p": 9,
            "ts_ms": ts_ms,
        });
        Some(Emission {
            t_ready_gps_ns: t,
            bytes,
            kind,
            t_gps_ns: t,
            values: obj(v),
        })
    }

    fn raw(&mut self, t: i64, e: Event, it: &IntruderTruth) -> Option<Emission> {
        if it.silent {
            return None;
        }
        let icao = u32::from_str_radix(&it.address, 16).ok()? & 0xFF_FFFF;
        let [lat, lon, _] = it
            .reported_position
            .unwrap_or([it.lat_deg, it.lon_deg, it.height_m]);
        let (kind, frame, extra) = match e {
            Event::Position(_, odd) => {
                let alt_ft = (it.alt_pressure_m * FT_PER_M).round() as i32;
                let f = airborne_position(
                    icao,
                    &AirbornePositionFields {
                        typecode: 11,
                        surveillance_status: 0,
                        nic_b: false,
                        altitude_ft: Some(alt_ft),
                        lat_deg: lat,
                        lon_deg: lon,
                        odd,
                    },
                )?;
                (
                    "raw_position",
                    f,
                    json!({ "odd": odd, "altitude_ft": alt_ft }),
                )
            }
            Event::Velocity(_) => {
                let [vn, ve, vd] = it.vel_ned_mps;
                let f = velocity_ground(
                    icao,
                    (ve * KT_PER_MPS).round() as i32,
                    (vn * KT_PER_MPS).round() as i32,
                    Some((-vd * FPM_PER_MPS).round() as i32),
                    true,
                    1,
                )?;
                ("raw_velocity", f, json!({}))
            }
            Event::Ident(_) => {
                let cat = ecat_number(&it.emitter_category).unwrap_or(0);
                // Set A..D = type code 4..1, category = the digit.
                let tc = 4 - cat / 8;
                let f = identification(icao, tc, cat % 8, &it.callsign)?;
                ("raw_identification", f, json!({ "typecode": tc }))
            }
            _ => return None,
        };
        let utc_ns = utc_ns_of_day(self.stamp_time(t));
        let raw_protocol = self.raw_protocol();
        let beast_mode = raw_protocol == RawProtocol::Beast;
        let meta = RxMeta {
            signal_dbm: (!beast_mode).then_some(-70),
            signal_quality: (!beast_mode).then_some(12),
            ts_pps_ns: (!beast_mode).then_some(t.rem_euclid(NS_PER_S) as u64),
            ts_utc_ns: (!beast_mode).then_some(utc_ns),
            mlat_ticks: beast_mode.then_some(utc_ns * 12 / 1000),
            rssi: beast_mode.then_some(128),
        };
        let rf = RawFrame::ModeS(ModeSFrame {
            bytes: frame,
            len: 14,
            meta,
        });
        let mut buf = BytesMut::with_capacity(96);
        match raw_protocol {
            RawProtocol::Beast => {
                beast::encode_beast(&rf, &mut buf);
            }
            RawProtocol::Hexd => hex::encode_hex(&rf, false, &mut buf),
            RawProtocol::Hex => hex::encode_hex(&rf, true, &mut buf),
            // Switched off (or to the unmodelled JSON raw section) since it was scheduled.
            RawProtocol::None | RawProtocol::Json => return None,
        }
        let bytes = self.send_line(&buf)?;
        let mut v = obj(json!({
            "address": it.address,
            "lat_deg": it.lat_deg,
            "lon_deg": it.lon_deg,
            "alt_pressure_m": it.alt_pressure_m,
            "vel_ned_mps": it.vel_ned_mps,
            "reported_lat_deg": lat,
            "reported_lon_deg": lon,
            "ts_utc_ns": utc_ns,
        }));
        v.extend(obj(extra));
        Some(Emission {
            t_ready_gps_ns: t,
            bytes,
            kind,
            t_gps_ns: t,
            values: v,
        })
    }

    fn drain_module(&mut self, t: i64) {
        while let Some((_, b)) = self.module.poll_output() {
            self.answers.push((t, b));
        }
    }
}

impl DeviceModel for TtmrfModel {
    fn name(&self) -> &'static str {
        "ttmrf"
    }

    fn protocol(&self) -> &'static str {
        self.channel
    }

    fn baud(&self) -> u32 {
        self.cfg.baud
    }

    fn receive(&mut self, t_gps_ns: i64, bytes: &[u8]) {
        // The module acts on the command (state change included) 1 ms after it arrives, when
        // its answer leaves.
        self.inbox.push((t_gps_ns + MS, bytes.to_vec()));
    }

    fn advance(
        &mut self,
        world: &World,
        faults: &FaultSchedule,
        until_gps_ns: i64,
        out: &mut Vec<Emission>,
    ) {
        loop {
            // Every event before the first unscheduled second is queued: schedule seconds until
            // the earliest queued event lies before the next second (raw frames of a second
            // reach 1.85 s past its start, so seconds overlap).
            while self.next_second * NS_PER_S < until_gps_ns
                && self
                    .queue
                    .last()
                    .is_none_or(|e| e.0 >= self.next_second * NS_PER_S)
            {
                let s = self.next_second;
                self.next_second += 1;
                self.schedule(s);
            }
            let (t, e) = self
                .queue
                .last()
                .copied()
                .unwrap_or((i64::MAX, Event::Second));
            // Host commands, resets and AT answers that come first.
            if let Some(&(ti, _)) = self.inbox.first()
                && ti <= t
                && ti < until_gps_ns
            {
                let (ti, bytes) = self.inbox.remove(0);
                let baud = self.module.baud();
                self.module.receive(&bytes, baud);
                self.drain_module(ti);
                continue;
            }
            if let Some(&r) = self.resets_ns.last()
                && r <= t
                && r < until_gps_ns
            {
                self.resets_ns.pop();
                self.module.power_cycle();
                self.drain_module(r);
                continue;
            }
            if let Some(&(ta, _)) = self.answers.first()
                && ta <= t
                && ta < until_gps_ns
            {
                let (ta, bytes) = self.answers.remove(0);
                let line = String::from_utf8_lossy(&bytes).trim_end().to_string();
                out.push(Emission {
                    t_ready_gps_ns: ta,
                    bytes,
                    kind: "at",
                    t_gps_ns: ta,
                    values: obj(json!({ "line": line })),
                });
                continue;
            }
            if t >= until_gps_ns {
                return;
            }
            self.queue.pop();
            if t < world.start_gps_ns {
                continue;
            }
            let em = match (e, self.decoded_protocol()) {
                (Event::Second, DecodedProtocol::Csv) if self.cfg.gnss => {
                    self.nmea(t, world, faults, out);
                    None
                }
                (Event::Second, DecodedProtocol::Json) if self.cfg.gnss => {
                    self.gnss(t, world, faults)
                }
                (Event::Second, DecodedProtocol::Gdl90) => {
                    self.gdl90_second(t, world, faults, out);
                    None
                }
                (Event::Second, DecodedProtocol::Asterix) => self.asterix_status(t),
                (Event::Second, _) => None,
                (Event::Traffic(i), _) => world.intruder(i, t).and_then(|it| {
                    let age_ns = (it.report_age_s * 1e9) as i64;
                    let rep = if age_ns > 0 {
                        world.intruder(i, t - age_ns)
                    } else {
                        None
                    };
                    self.traffic(t, i, &it, rep.as_ref().unwrap_or(&it))
                }),
                (Event::Position(i, _) | Event::Velocity(i) | Event::Ident(i), _) => {
                    world.intruder(i, t).and_then(|it| self.raw(t, e, &it))
                }
            };
            out.extend(em);
        }
    }
}

#[path = "ttmrf_second.rs"]
mod second;

#[cfg(test)]
#[path = "ttmrf_tests.rs"]
mod tests;
