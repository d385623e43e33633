//! Aerobits TT-Multi-RF device model (TT-Multi-RF manual): the RUN / CONFIGURATION /
//! BOOTLOADER states and AT messages (manual 4, 5) through [`SimModule`]; in RUN the decoded
//! traffic protocol (CSV 6.4 / 7.2.1 / 8.2.1 / 10.2.1, or JSON 6.6), the JSON GNSS section
//! (9.2.2) and raw Mode S frames (7.2.2: HEX with extended fields, HEXd or Beast) for ADS-B
//! targets, every byte encoded by the drivers' encoders.
//!
//! Schedule (all on GPS time, whole milliseconds, so JSON `ts` is exact):
//! - one traffic message per intruder per second, intruder `i` of `n` at `(i + 1) * 1000 /
//!   (n + 1)` ms into each second (spread, like a receiver reporting its table in turn); JSON
//!   sends one target per message, in the array of its link (`adsb`, `uat`, `flarm`);
//! - with `gnss = true`, at every whole second: the JSON `gnss` section (JSON mode), or NMEA
//!   `$GPGGA` and `$GPRMC` (CSV mode; manual 9.2.1), UTC time of day and date;
//! - raw frames of each ADS-B target (raw != "off"), at its phase plus: 100 ms even and 600 ms
//!   odd airborne position (TC 11), 350 and 850 ms airborne velocity (TC 19 subtype 1), and
//!   identification (TC 1-4) at 200 ms every 5 s: 2 + 2 + 0.2 frames per second as DO-260B
//!   transmitters. HEX times: TS1s = ns since the last whole second (the PPS), TS24h = ns since
//!   UTC midnight; Beast: the 12 MHz counter = UTC ns of day * 12 / 1000.
//!
//! Values: barometric altitude = the ISA pressure altitude of the truth (whole ft, the Mode S
//! encoder quantises to 25 ft); geometric altitude = WGS-84 height; ADS-B/UAT NIC 8, NACp 9,
//! NACv 1, NICbaro 1 (a GNSS-equipped transponder); emitter category as the GDL90 number (A0-A7
//! = 0-7, B0-B7 = 8-15, C = 16-23, D = 24-31); a `spoof_offset_ned_m` intruder reports its
//! spoofed position (the truth records both). GNSS section: 3-D fix with 2.5 m / 4 m accuracy
//! and matching noise; during a `gnss_outage` fault `fix` = 0 and nothing else.
//!
//! AT commands from the host go to [`SimModule`] at the module's current baud (a pseudo-terminal
//! has no baud; the link keeps the scenario's); the module acts on a command (state changes
//! included) and its answers leave 1 ms after the window that delivered it. Outside RUN no traffic, GNSS or raw output is sent. A `device_reset`
//! fault power-cycles the module (BOOTLOADER then RUN messages).
//!
//! Truth: `type` = "adsb" / "uat" / "flarm" (traffic message), "gnss", "nmea_gga", "nmea_rmc",
//! "raw_position",
//! "raw_velocity", "raw_identification", "at"; values: `address`, true `lat_deg`, `lon_deg`,
//! `height_m`, `alt_pressure_m`, `vel_ned_mps`, `track_rad`, the `reported_*` position, `nic`,
//! `nac_p`, `ts_ms`.

use bytes::BytesMut;
use serde_json::{Map, Value, json};
use vigil_drivers::modes::encode::{
    AirbornePositionFields, airborne_position, identification, velocity_ground,
};
use vigil_drivers::ttmrf::csv::{
    AdsbAircraft, AircraftFlags, AircraftState, CsvMessage, FlarmAircraft, NicNac, UatAircraft,
};
use vigil_drivers::ttmrf::json::{
    AdsbTarget, FlarmTarget, Gnss, GnssAccuracy, JsonMessage, UatNicNac, UatTarget,
};
use vigil_drivers::ttmrf::nmea::{Date as NmeaDate, Gga, NmeaBody, NmeaSentence, Rmc};
use vigil_drivers::ttmrf::raw::{ModeSFrame, RawFrame, RxMeta, beast, hex};

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
    Gnss,
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

fn utc_ns_of_day(t_gps_ns: i64) -> u64 {
    (t_gps_ns - GPS_MINUS_UTC_S * NS_PER_S).rem_euclid(86_400 * NS_PER_S) as u64
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
}

impl TtmrfModel {
    /// A module powered on before the scenario start, in RUN.
    pub fn new(cfg: &TtmrfConfig, world: &World, faults: &FaultSchedule, seed: u64) -> Self {
        let n = world.intruder_count();
        let links = (0..n)
            .filter_map(|i| world.intruder(i, world.start_gps_ns).map(|t| t.link))
            .collect();
        let start = world.start_gps_ns;
        Self {
            cfg: cfg.clone(),
            module: SimModule::new(SERIAL, "1.0.0"),
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
        if self.cfg.gnss {
            self.queue.push((base, Event::Gnss));
        }
        let raw = self.cfg.raw != "off";
        for i in 0..self.n {
            let p = base + self.phase_ns(i);
            self.queue.push((p, Event::Traffic(i)));
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

    fn traffic(&mut self, t: i64, i: usize, it: &IntruderTruth) -> Option<Emission> {
        let [lat, lon, h] = it
            .reported_position
            .unwrap_or([it.lat_deg, it.lon_deg, it.height_m]);
        let [vn, ve, vd] = it.vel_ned_mps;
        let track_deg = round_to(it.track_rad.to_degrees().rem_euclid(360.0), 0.1) % 360.0;
        let velh_kt = (vn.hypot(ve) * KT_PER_MPS).round();
        let velv_fpm = round_to(-vd * FPM_PER_MPS, 64.0);
        let alt_baro_ft = (it.alt_pressure_m * FT_PER_M).round();
        let alt_geo_ft = (h * FT_PER_M).round();
        let (lat, lon) = (round_to(lat, 1e-6), round_to(lon, 1e-6));
        let icao = u32::from_str_radix(&it.address, 16).unwrap_or(0) & 0xFF_FFFF;
        let ecat = ecat_number(&it.emitter_category);
        let callsign = (!it.callsign.is_empty()).then(|| it.callsign.clone());
        let ts_ms = utc_ms_of_day(t);
        let (kind, line) = match (self.cfg.protocol.as_str(), it.link) {
            ("csv", Link::Flarm) => (
                "flarm",
                CsvMessage::Flarm(FlarmAircraft {
                    id: icao,
                    id_type: Some(1),
                    lat_deg: Some(lat),
                    lon_deg: Some(lon),
                    alt_m: Some(h.round()),
                    track_deg: Some(track_deg),
                    velh_mps: Some(round_to(vn.hypot(ve), 0.1)),
                    velv_mps: Some(round_to(-vd, 0.1)),
                    ..Default::default()
                })
                .to_line(),
            ),
            ("csv", link) => {
                let state = AircraftState {
                    icao,
                    flags: Some(AircraftFlags::from_raw(0x3F00)),
                    callsign,
                    squawk: None,
                    lat_deg: Some(lat),
                    lon_deg: Some(lon),
                    alt_baro_ft: Some(alt_baro_ft),
                    track_deg: Some(track_deg),
                    velh_kt: Some(velh_kt),
                    velv_fpm: Some(velv_fpm),
                    sig_dbm: Some(-70.0),
                    sig_q: Some(10.0),
                    fps: Some(5),
                    nicnac: Some(NicNac::from_raw(NicNac::pack(8, 1, 9, 1))),
                    alt_geo_ft: Some(alt_geo_ft),
                    ecat,
                };
                if link == Link::Uat978 {
                    let m = UatAircraft {
                        state,
                        ..Default::default()
                    };
                    ("uat", CsvMessage::Uat(m).to_line())
                } else {
                    let m = AdsbAircraft {
                        state,
                        ..Default::default()
                    };
                    ("adsb", CsvMessage::Adsb(m).to_line())
                }
            }
            (_, link) => {
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
                            alt_baro_ft: Some(alt_baro_ft),
                            alt_geo_ft: Some(alt_geo_ft),
                            track_deg: Some(track_deg),
                            velh_kt: Some(velh_kt),
                            velv_fpm: Some(velv_fpm),
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
                            alt_baro_ft: Some(alt_baro_ft),
                            alt_geo_ft: Some(alt_geo_ft),
                            track_deg: Some(track_deg),
                            velh_kt: Some(velh_kt),
                            velv_fpm: Some(velv_fpm),
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
                            alt_m: Some(h.round()),
                            track_deg: Some(track_deg),
                            velh_mps: Some(round_to(vn.hypot(ve), 0.1)),
                            velv_mps: Some(round_to(-vd, 0.1)),
                            ..Default::default()
                        });
                        "flarm"
                    }
                };
                (kind, m.to_wire())
            }
        };
        let bytes = self.send_line(line.as_bytes())?;
        let v = json!({
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
            "spoofed": it.reported_position.is_some(),
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

    fn gnss(&mut self, t: i64, world: &World, faults: &FaultSchedule) -> Option<Emission> {
        let lost = faults.gnss_lost("ttmrf", world.elapsed_s(t));
        let o = world.ownship(t);
        let g = if lost {
            Gnss {
                fix: Some(0),
                ..Default::default()
            }
        } else {
            let n = &mut self.noise;
            let (dn, de, dd) = (
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_V_SIGMA_M),
            );
            let [vn, ve, vd] = o.vel_ned_mps;
            let h = round_to(o.height_m - dd, 0.1);
            Gnss {
                fix: Some(1),
                lat_deg: Some(round_to(
                    o.lat_deg + (dn / world.frame.radius_north_m).to_degrees(),
                    1e-7,
                )),
                lon_deg: Some(round_to(
                    o.lon_deg + (de / world.frame.radius_east_m).to_degrees(),
                    1e-7,
                )),
                alt_wgs84_m: Some(h),
                // The simulated geoid is the ellipsoid.
                alt_msl_m: Some(h),
                track_deg: Some(round_to(ve.atan2(vn).to_degrees().rem_euclid(360.0), 0.1) % 360.0),
                velh_kt: Some(round_to(vn.hypot(ve) * KT_PER_MPS, 0.1)),
                velv_mps: Some(round_to(-vd, 0.1)),
                acc: Some(GnssAccuracy {
                    lat_m: Some(GNSS_H_SIGMA_M),
                    lon_m: Some(GNSS_H_SIGMA_M),
                    alt_m: Some(GNSS_V_SIGMA_M),
                }),
                nac_p: Some(9),
                nac_v: Some(1),
                nic: Some(8),
                ..Default::default()
            }
        };
        let ts_ms = utc_ms_of_day(t);
        let m = JsonMessage {
            src: Some(SERIAL.into()),
            ts_ms: Some(ts_ms),
            ver: Some(1),
            gnss: Some(g),
            ..Default::default()
        };
        let bytes = self.send_line(m.to_wire().as_bytes())?;
        let v = json!({
            "fix": !lost,
            "lat_deg": o.lat_deg,
            "lon_deg": o.lon_deg,
            "height_m": o.height_m,
            "vel_ned_mps": o.vel_ned_mps,
            "ts_ms": ts_ms,
        });
        Some(Emission {
            t_ready_gps_ns: t,
            bytes,
            kind: "gnss",
            t_gps_ns: t,
            values: obj(v),
        })
    }

    /// GGA then RMC (manual 9.2.1, NMEA output of the GNSS section) for CSV mode.
    fn nmea(&mut self, t: i64, world: &World, faults: &FaultSchedule, out: &mut Vec<Emission>) {
        let lost = faults.gnss_lost("ttmrf", world.elapsed_s(t));
        let o = world.ownship(t);
        let utc_s = utc_ns_of_day(t) as f64 / 1e9;
        let d = crate::units::gps_ns_to_utc_date(t);
        let date = NmeaDate {
            year: d.year() as u16,
            month: d.month() as u8,
            day: d.day(),
        };
        let [vn, ve, _] = o.vel_ned_mps;
        let (lat, lon, h) = if lost {
            (None, None, None)
        } else {
            let n = &mut self.noise;
            let (dn, de, dd) = (
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_V_SIGMA_M),
            );
            (
                Some(o.lat_deg + (dn / world.frame.radius_north_m).to_degrees()),
                Some(o.lon_deg + (de / world.frame.radius_east_m).to_degrees()),
                Some(round_to(o.height_m - dd, 0.1)),
            )
        };
        let gga = Gga {
            time_s: Some(utc_s),
            lat_deg: lat,
            lon_deg: lon,
            quality: Some(u8::from(!lost)),
            satellites: Some(if lost { 0 } else { 10 }),
            hdop: (!lost).then_some(0.9),
            alt_msl_m: h,
            // The simulated geoid is the ellipsoid.
            geoid_sep_m: (!lost).then_some(0.0),
            ..Default::default()
        };
        let rmc = Rmc {
            time_s: Some(utc_s),
            valid: Some(!lost),
            lat_deg: lat,
            lon_deg: lon,
            speed_kt: (!lost).then(|| round_to(vn.hypot(ve) * KT_PER_MPS, 0.1)),
            course_deg: (!lost)
                .then(|| round_to(ve.atan2(vn).to_degrees().rem_euclid(360.0), 0.1) % 360.0),
            date: Some(date),
            mode: Some(if lost { 'N' } else { 'A' }),
            ..Default::default()
        };
        for (kind, body) in [
            ("nmea_gga", NmeaBody::Gga(gga)),
            ("nmea_rmc", NmeaBody::Rmc(rmc)),
        ] {
            let line = NmeaSentence {
                talker: "GP".into(),
                body,
            }
            .to_line();
            let Some(bytes) = self.send_line(line.as_bytes()) else {
                return;
            };
            let v = json!({
                "fix": !lost,
                "lat_deg": o.lat_deg,
                "lon_deg": o.lon_deg,
                "height_m": o.height_m,
                "vel_ned_mps": o.vel_ned_mps,
                "utc_s_of_day": utc_s,
            });
            out.push(Emission {
                t_ready_gps_ns: t,
                bytes,
                kind,
                t_gps_ns: t,
                values: obj(v),
            });
        }
    }

    fn raw(&mut self, t: i64, e: Event, it: &IntruderTruth) -> Option<Emission> {
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
        let utc_ns = utc_ns_of_day(t);
        let beast_mode = self.cfg.raw == "beast";
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
        match self.cfg.raw.as_str() {
            "beast" => {
                beast::encode_beast(&rf, &mut buf);
            }
            "hexd" => hex::encode_hex(&rf, false, &mut buf),
            _ => hex::encode_hex(&rf, true, &mut buf),
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
        "ttmrf-text"
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
                .unwrap_or((i64::MAX, Event::Gnss));
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
            let em = match e {
                Event::Gnss if self.cfg.protocol == "csv" => {
                    self.nmea(t, world, faults, out);
                    None
                }
                Event::Gnss => self.gnss(t, world, faults),
                Event::Traffic(i) => world.intruder(i, t).and_then(|it| self.traffic(t, i, &it)),
                Event::Position(i, _) | Event::Velocity(i) | Event::Ident(i) => {
                    world.intruder(i, t).and_then(|it| self.raw(t, e, &it))
                }
            };
            out.extend(em);
        }
    }
}

#[cfg(test)]
#[path = "ttmrf_tests.rs"]
mod tests;
