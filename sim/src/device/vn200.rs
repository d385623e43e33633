//! VN-200 device model (VectorNav ICD 24-20006-R1): binary output messages as configured by
//! Registers 75-77 (ICD 3.2.7, chapter 2), and the ASCII command protocol (ICD 1.3-1.5).
//!
//! - Output timing: the IMU runs at 800 Hz on GPS time; binary output `n` is sent on every
//!   `rate_divisor`-th IMU tick (ticks on whole multiples of 1.25 ms of GPS time), so at 200 Hz
//!   (divisor 4) samples fall on whole 5 ms of GPS time. `TimeGps` is the exact sample time.
//! - Default output (Register 75, async mode 1, divisor `800 / rate_hz`): Common TimeGps,
//!   Ypr, Quaternion, AngularRate, PosLla, VelNed, Accel, InsStatus, TimeGpsPps; Time
//!   TimeStatus; Attitude YprU; INS PosU, VelU ([`default_masks`]). Registers 76 and 77 start off.
//! - PPS on every whole GPS second (it drives the BAHRS sync input, modelled there);
//!   `TimeGpsPps` = time since the last whole GPS second.
//! - INS status: Tracking with GNSS fix (0x0006). During a `gnss_outage` fault: mode GnssLost
//!   with the GNSS error bit (0x0043: "GNSS communication error or no valid PPS"), TimeStatus 0
//!   (time of week, date and UTC not valid) and a position uncertainty growing 1 m/s from the
//!   outage start. Attitude stays valid (Table 2.78). An `ins_reset` fault sets the mode to
//!   NotTracking (0) for 1 s, then Aligning (1) for its `aligning_s` (the fix bits unchanged).
//! - Noise: white Gaussian with the sigmas the message reports (YprU, PosU, VelU), so the
//!   reported uncertainties are consistent with the actual errors.
//! - Accel = body specific force (level: z = -9.81 m/s^2), AngularRate = body rates.
//! - ASCII commands (`DeviceModel::receive`): answered 1 ms after the window that delivered them,
//!   always with an 8-bit XOR checksum (Register 30 default). Reads of Registers 1, 3, 4, 5 and
//!   75-77 return their values; writes to 75-77 change the output after the echo; writes and
//!   reads of any other register answer `$VNERR,08` (InvalidRegister: not modelled), a bad
//!   checksum `$VNERR,03`, an unknown command `$VNERR,04`, malformed parameters `$VNERR,07`.
//!   A Register 75-77 configuration selecting a type this model does not produce, or faster than
//!   400 Hz, is refused with `$VNERR,07`. `VNASY` pauses/resumes, `VNWNV` saves, `VNRST` echoes
//!   then resets (restoring the saved configuration, output again after [`BOOT_NS`]), `VNRFS`
//!   restores the defaults, `VNBOM,n` sends output `n` once; other valid commands are echoed.
//!
//! Truth: per binary message `type` = "binary_output" with `output` (1-3), the true values
//! (`yaw_rad` true heading, `pitch_rad`, `roll_rad`, `quat_xyzw`, `lat_deg`, `lon_deg`,
//! `height_m`, `vel_ned_mps`, `angular_rate_body_radps`, `specific_force_body_mps2`), the
//! status words sent and the sigmas; per ASCII answer `type` = "ascii" with `sentence`.

use std::collections::VecDeque;

use serde_json::{Map, Value, json};
use vigil_drivers::vn200::ascii::{
    self, AsciiError, AsciiMessage, BinaryOutputConfig, ChecksumKind, Command, ErrorCode,
    RegisterValue, Scan,
};
use vigil_drivers::vn200::binary::{
    AttitudeGroup, BinaryOutput, CommonGroup, InsGroup, Lla, Quaternion, TimeGroup, Ypr,
};
use vigil_drivers::vn200::status::{InsStatus, TimeStatus};

use vigil_drivers::protocol::Protocol;

use super::{DeviceModel, Emission, FaultSchedule};
use crate::rng::Rng;
use crate::scenario::Vn200Config;
use crate::truth::{OwnshipTruth, World};
use crate::units::NS_PER_S;

/// IMU tick of the VN-200 (800 Hz), ns.
pub const IMU_TICK_NS: i64 = 1_250_000;
/// Boot time after a reset before output resumes, ns.
pub const BOOT_NS: i64 = 1_000_000_000;
/// Delay from receiving a command to the first byte of its answer, ns.
pub const ANSWER_NS: i64 = 1_000_000;
/// Time from a sample to its message being ready, ns.
pub const LATENCY_NS: i64 = 500_000;

/// 1-sigma yaw, pitch, roll noise, deg (VN-200 datasheet class: heading 0.2, tilt 0.03).
pub const YPR_SIGMA_DEG: [f64; 3] = [0.2, 0.03, 0.03];
/// 1-sigma position noise with GNSS, m.
pub const POS_SIGMA_M: f64 = 2.5;
/// 1-sigma velocity noise with GNSS, m/s.
pub const VEL_SIGMA_MPS: f64 = 0.05;
/// Growth of the position sigma during a GNSS outage, m/s.
pub const POS_SIGMA_GROWTH_MPS: f64 = 1.0;
/// Growth of the velocity sigma during a GNSS outage, m/s per s.
pub const VEL_SIGMA_GROWTH_MPS2: f64 = 0.05;

/// Types this model fills, per group offset (bit = table offset).
pub const SUPPORTED: [u32; 7] = [
    // Common: TimeStartup, TimeGps, Ypr, Quaternion, AngularRate, PosLla, VelNed, Accel,
    // InsStatus, TimeGpsPps.
    1 | 1 << 1 | 1 << 3 | 1 << 4 | 1 << 5 | 1 << 6 | 1 << 7 | 1 << 8 | 1 << 12 | 1 << 14,
    // Time: TimeStartup, TimeGps, GpsTow, GpsWeek, TimeGpsPps, TimeStatus.
    1 | 1 << 1 | 1 << 2 | 1 << 3 | 1 << 5 | 1 << 9,
    0,
    0,
    // Attitude: Ypr, Quaternion, YprU.
    1 << 1 | 1 << 2 | 1 << 8,
    // INS: InsStatus, PosLla, VelNed, PosU, VelU.
    1 | 1 << 1 | 1 << 4 | 1 << 9 | 1 << 10,
    0,
];

/// The default Register 75 type masks (see the module doc).
pub fn default_masks() -> [u32; 7] {
    [
        1 << 1 | 1 << 3 | 1 << 4 | 1 << 5 | 1 << 6 | 1 << 7 | 1 << 8 | 1 << 12 | 1 << 14,
        1 << 9,
        0,
        0,
        1 << 8,
        1 << 9 | 1 << 10,
        0,
    ]
}

fn on(mask: u32, bit: u8) -> bool {
    mask & (1 << bit) != 0
}

/// The three binary output configurations (Registers 75, 76, 77).
fn default_configs(rate_hz: f64) -> [BinaryOutputConfig; 3] {
    let divisor = (800.0 / rate_hz).round().max(2.0) as u16;
    [
        BinaryOutputConfig::from_masks(1, divisor, default_masks()),
        BinaryOutputConfig::from_masks(0, divisor, [0; 7]),
        BinaryOutputConfig::from_masks(0, divisor, [0; 7]),
    ]
}

/// Whether this model can send `c` (known types only, at most 400 Hz).
fn acceptable(c: &BinaryOutputConfig) -> Option<[u32; 7]> {
    let masks = c.masks()?;
    let ok = masks.iter().zip(SUPPORTED).all(|(m, s)| m & !s == 0)
        && (c.async_mode == 0 || c.rate_divisor >= 2);
    ok.then_some(masks)
}

/// One sample's values, noisy as sent.
struct Sample {
    t_gps_ns: i64,
    truth: OwnshipTruth,
    ypr_deg: [f32; 3],
    quat: [f32; 4],
    rates: [f32; 3],
    lla: [f64; 3],
    vel: [f32; 3],
    accel: [f32; 3],
    ins_status: u16,
    time_status: u8,
    ypr_u_deg: [f32; 3],
    pos_u_m: f32,
    vel_u_mps: f32,
    startup_ns: u64,
    /// What a [`crate::scenario::Fault::DeviceTimeOffset`] adds to the GPS time fields, ns.
    time_offset_ns: i64,
}

/// The VN-200 model.
pub struct Vn200Model {
    cfg: Vn200Config,
    noise: Rng,
    configs: [BinaryOutputConfig; 3],
    masks: [[u32; 7]; 3],
    saved: [BinaryOutputConfig; 3],
    async_enabled: bool,
    boot_gps_ns: i64,
    outputs_from_gps_ns: i64,
    next_tick: i64,
    resets_ns: VecDeque<i64>,
    rx: Vec<u8>,
    inbox: Vec<(i64, Vec<u8>)>,
    answers: VecDeque<(i64, Vec<u8>, Value)>,
    outage_from_ns: Option<i64>,
}

impl Vn200Model {
    /// A VN-200 powered on before the scenario start (already tracking).
    pub fn new(cfg: &Vn200Config, world: &World, faults: &FaultSchedule, seed: u64) -> Self {
        let configs = default_configs(cfg.rate_hz);
        let masks = configs.clone().map(|c| c.masks().unwrap_or_default());
        let start = world.start_gps_ns;
        Self {
            cfg: cfg.clone(),
            noise: Rng::stream(seed, "vn200/noise"),
            saved: configs.clone(),
            configs,
            masks,
            async_enabled: true,
            // Powered 60 s before the start (TimeStartup).
            boot_gps_ns: start - 60 * NS_PER_S,
            outputs_from_gps_ns: start,
            next_tick: start.div_euclid(IMU_TICK_NS) + 1,
            resets_ns: faults
                .resets("vn200")
                .into_iter()
                .map(|s| start + (s * 1e9).round() as i64)
                .collect(),
            rx: Vec::new(),
            inbox: Vec::new(),
            answers: VecDeque::new(),
            outage_from_ns: None,
        }
    }

    /// The active configuration of output `n` (1-3).
    pub fn config(&self, n: u8) -> Option<&BinaryOutputConfig> {
        self.configs.get(usize::from(n).wrapping_sub(1))
    }

    fn reset(&mut self, t: i64) {
        self.configs = self.saved.clone();
        self.masks = self.configs.clone().map(|c| c.masks().unwrap_or_default());
        self.async_enabled = true;
        self.boot_gps_ns = t;
        self.outputs_from_gps_ns = t + BOOT_NS;
        self.rx.clear();
    }

    fn sample(&mut self, world: &World, faults: &FaultSchedule, t: i64) -> Sample {
        let o = world.ownship(t);
        let lost = faults.gnss_lost("vn200", world.elapsed_s(t));
        let since = if lost {
            let from = *self.outage_from_ns.get_or_insert(t);
            (t - from) as f64 / 1e9
        } else {
            self.outage_from_ns = None;
            0.0
        };
        let pos_u = POS_SIGMA_M + POS_SIGMA_GROWTH_MPS * since;
        let vel_u = VEL_SIGMA_MPS + VEL_SIGMA_GROWTH_MPS2 * since;
        let n = &mut self.noise;
        let yaw = o.yaw_rad + n.gauss(YPR_SIGMA_DEG[0].to_radians());
        let pitch = o.pitch_rad + n.gauss(YPR_SIGMA_DEG[1].to_radians());
        let roll = o.roll_rad + n.gauss(YPR_SIGMA_DEG[2].to_radians());
        let q = crate::truth::quat_xyzw(yaw, pitch, roll);
        let yaw_deg = yaw.to_degrees().rem_euclid(360.0);
        // ICD 2.6.1: yaw within +-180 deg.
        let yaw_deg = if yaw_deg > 180.0 {
            yaw_deg - 360.0
        } else {
            yaw_deg
        };
        let (dn, de, dd) = (n.gauss(pos_u), n.gauss(pos_u), n.gauss(pos_u));
        // Radii of curvature of the scenario origin (metres per radian north, and east at the
        // origin's latitude): the noise is a few metres, so the origin's radii are exact enough.
        let lat = o.lat_deg + (dn / world.frame.radius_north_m).to_degrees();
        let lon = o.lon_deg + (de / world.frame.radius_east_m).to_degrees();
        let mut vel = o.vel_ned_mps.map(|v| (v + n.gauss(vel_u)) as f32);
        let (drift_h, drift_rate) = faults.vn200_vertical_drift(world.elapsed_s(t));
        vel[2] -= drift_rate as f32;
        Sample {
            t_gps_ns: t,
            truth: o,
            ypr_deg: [
                yaw_deg as f32,
                pitch.to_degrees() as f32,
                roll.to_degrees() as f32,
            ],
            quat: q.map(|v| v as f32),
            rates: o.angular_rate_body_radps.map(|v| v as f32),
            lla: [lat, lon, o.height_m - dd + drift_h],
            vel,
            accel: o.specific_force_body_mps2.map(|v| v as f32),
            // Mode (bits 0-1): Tracking, GnssLost in an outage, or what an INS reset forces;
            // bit 2 GNSS fix, bit 6 GNSS error.
            ins_status: {
                let mode = faults
                    .ins_reset_mode(world.elapsed_s(t))
                    .unwrap_or(if lost { 3 } else { 2 });
                mode | if lost { 0x0040 } else { 0x0004 }
            },
            time_status: if lost { 0 } else { 0b111 },
            ypr_u_deg: YPR_SIGMA_DEG.map(|v| v as f32),
            pos_u_m: pos_u as f32,
            vel_u_mps: vel_u as f32,
            startup_ns: (t - self.boot_gps_ns).max(0) as u64,
            time_offset_ns: faults.time_offset_ns("vn200", world.elapsed_s(t)),
        }
    }

    /// The binary message of output `i` (0-2) for a sample, with its truth values.
    fn message(&self, i: usize, s: &Sample) -> (BinaryOutput, Map<String, Value>) {
        let m = self.masks[i];
        let t = s.t_gps_ns;
        // The GPS time it names (wrong under a time-offset fault); the time since its PPS is
        // measured, and stays right.
        let tg = (t + s.time_offset_ns).max(0) as u64;
        let pps = t.rem_euclid(NS_PER_S) as u64;
        let ypr = Ypr {
            yaw_deg: s.ypr_deg[0],
            pitch_deg: s.ypr_deg[1],
            roll_deg: s.ypr_deg[2],
        };
        let quat = Quaternion {
            x: s.quat[0],
            y: s.quat[1],
            z: s.quat[2],
            s: s.quat[3],
        };
        let lla = Lla {
            lat_deg: s.lla[0],
            lon_deg: s.lla[1],
            alt_m: s.lla[2],
        };
        let b = |g: usize, bit: u8| on(m[g], bit);
        let out = BinaryOutput {
            common: (m[0] != 0).then(|| CommonGroup {
                time_startup_ns: b(0, 0).then_some(s.startup_ns),
                time_gps_ns: b(0, 1).then_some(tg),
                ypr: b(0, 3).then_some(ypr),
                quaternion: b(0, 4).then_some(quat),
                angular_rate_radps: b(0, 5).then_some(s.rates),
                pos_lla: b(0, 6).then_some(lla),
                vel_ned_mps: b(0, 7).then_some(s.vel),
                accel_mps2: b(0, 8).then_some(s.accel),
                ins_status: b(0, 12).then_some(InsStatus(s.ins_status)),
                time_gps_pps_ns: b(0, 14).then_some(pps),
                ..Default::default()
            }),
            time: (m[1] != 0).then(|| TimeGroup {
                time_startup_ns: b(1, 0).then_some(s.startup_ns),
                time_gps_ns: b(1, 1).then_some(tg),
                gps_tow_ns: b(1, 2).then_some(tg % (604_800 * NS_PER_S as u64)),
                gps_week: b(1, 3).then_some((tg / (604_800 * NS_PER_S as u64)) as u16),
                time_gps_pps_ns: b(1, 5).then_some(pps),
                time_status: b(1, 9).then_some(TimeStatus(s.time_status)),
                ..Default::default()
            }),
            attitude: (m[4] != 0).then(|| AttitudeGroup {
                ypr: b(4, 1).then_some(ypr),
                quaternion: b(4, 2).then_some(quat),
                ypr_u: b(4, 8).then_some(Ypr {
                    yaw_deg: s.ypr_u_deg[0],
                    pitch_deg: s.ypr_u_deg[1],
                    roll_deg: s.ypr_u_deg[2],
                }),
                ..Default::default()
            }),
            ins: (m[5] != 0).then(|| InsGroup {
                ins_status: b(5, 0).then_some(InsStatus(s.ins_status)),
                pos_lla: b(5, 1).then_some(lla),
                vel_ned_mps: b(5, 4).then_some(s.vel),
                pos_u_m: b(5, 9).then_some(s.pos_u_m),
                vel_u_mps: b(5, 10).then_some(s.vel_u_mps),
                ..Default::default()
            }),
            ..Default::default()
        };
        let o = &s.truth;
        let v = json!({
            "output": i + 1,
            "yaw_rad": o.yaw_rad,
            "pitch_rad": o.pitch_rad,
            "roll_rad": o.roll_rad,
            "quat_xyzw": o.quat_xyzw,
            "lat_deg": o.lat_deg,
            "lon_deg": o.lon_deg,
            "height_m": o.height_m,
            "vel_ned_mps": o.vel_ned_mps,
            "angular_rate_body_radps": o.angular_rate_body_radps,
            "specific_force_body_mps2": o.specific_force_body_mps2,
            "time_gps_ns": tg,
            "time_gps_pps_ns": pps,
            "ins_status": s.ins_status,
            "time_status": s.time_status,
            "ypr_sigma_deg": s.ypr_u_deg,
            "pos_sigma_m": s.pos_u_m,
            "vel_sigma_mps": s.vel_u_mps,
        });
        let values = match v {
            Value::Object(m) => m,
            _ => Map::new(),
        };
        (out, values)
    }

    /// Register contents for a read, or the error.
    fn read_register(&self, id: u8) -> Result<RegisterValue, ErrorCode> {
        Ok(match id {
            1 => RegisterValue::Model {
                model: "VN-200T-CR".into(),
            },
            3 => RegisterValue::SerialNumber { serial: 100_200 },
            4 => RegisterValue::FirmwareVersion {
                version: "2.1.0.0".into(),
            },
            5 => RegisterValue::BaudRate {
                baud: self.cfg.baud,
                port: None,
            },
            75..=77 => RegisterValue::BinaryOutput {
                index: id - 74,
                config: self.configs[usize::from(id - 75)].clone(),
            },
            _ => return Err(ErrorCode::InvalidRegister),
        })
    }

    /// Handles one command; returns the answer sentence.
    fn command(&mut self, t: i64, c: Command) -> Result<Vec<u8>, ErrorCode> {
        let echo = |c: &Command| c.encode(ChecksumKind::Xor8);
        match &c {
            Command::ReadRegister(id) => {
                let value = self.read_register(*id)?;
                Ok(AsciiMessage::ReadResponse { value }.encode(ChecksumKind::Xor8))
            }
            Command::WriteRegister(RegisterValue::BinaryOutput { index, config }) => {
                let masks = acceptable(config).ok_or(ErrorCode::InvalidParameter)?;
                let i = usize::from(*index - 1);
                self.configs[i] = config.clone();
                self.masks[i] = masks;
                Ok(echo(&c))
            }
            Command::WriteRegister(_) => Err(ErrorCode::InvalidRegister),
            Command::AsyncOutputEnable(on) => {
                self.async_enabled = *on;
                Ok(echo(&c))
            }
            Command::WriteSettings => {
                self.saved = self.configs.clone();
                Ok(echo(&c))
            }
            Command::Reset => {
                self.reset(t + ANSWER_NS);
                Ok(echo(&c))
            }
            Command::RestoreFactorySettings => {
                self.saved = default_configs(self.cfg.rate_hz);
                self.reset(t + ANSWER_NS);
                Ok(echo(&c))
            }
            Command::PollBinaryOutput(n) if !(1..=3).contains(n) => {
                Err(ErrorCode::InvalidParameter)
            }
            _ => Ok(echo(&c)),
        }
    }

    /// Parses the buffered host bytes and queues the answers.
    fn process_input(&mut self, t: i64, world: &World, faults: &FaultSchedule) {
        let ready = t + ANSWER_NS;
        loop {
            let Some(start) = self.rx.iter().position(|&b| b == b'$') else {
                self.rx.clear();
                return;
            };
            self.rx.drain(..start);
            let (len, answer) = match ascii::scan(&self.rx) {
                Scan::NeedMore => return,
                Scan::Invalid => (1, None),
                Scan::Foreign { len } => (len, Some(Err(ErrorCode::InvalidCommand))),
                Scan::BadChecksum => {
                    let len = self
                        .rx
                        .iter()
                        .position(|&b| b == b'\n')
                        .map_or(self.rx.len(), |p| p + 1);
                    (len, Some(Err(ErrorCode::InvalidChecksum)))
                }
                Scan::Sentence { body, len, .. } => {
                    let r = match AsciiMessage::parse(body) {
                        Ok(AsciiMessage::Command { command }) => Ok(command),
                        Ok(_) | Err(AsciiError::UnknownHeader(_)) => Err(ErrorCode::InvalidCommand),
                        Err(AsciiError::Malformed { header, .. }) => Err(
                            if matches!(header.as_str(), "VNRRG" | "VNWRG")
                                && body
                                    .split(',')
                                    .nth(1)
                                    .and_then(|id| id.parse::<u8>().ok())
                                    .is_some_and(|id| !matches!(id, 1 | 3 | 4 | 5 | 75..=77))
                            {
                                ErrorCode::InvalidRegister
                            } else {
                                ErrorCode::InvalidParameter
                            },
                        ),
                    };
                    (len, Some(r))
                }
            };
            self.rx.drain(..len.min(self.rx.len()));
            let Some(r) = answer else { continue };
            let poll = matches!(r, Ok(Command::PollBinaryOutput(n)) if (1..=3).contains(&n));
            if let Ok(Command::PollBinaryOutput(n)) = r
                && poll
            {
                let s = self.sample(world, faults, t);
                let (msg, mut v) = self.message(usize::from(n - 1), &s);
                v.insert("polled".into(), json!(true));
                if let Some(bytes) = msg.encode_for_wire(n) {
                    self.answers.push_back((ready, bytes, Value::Object(v)));
                }
                continue;
            }
            let bytes = match r.and_then(|c| self.command(t, c)) {
                Ok(b) => b,
                Err(code) => AsciiMessage::Error { code }.encode(ChecksumKind::Xor8),
            };
            let sentence = String::from_utf8_lossy(&bytes).trim_end().to_string();
            self.answers
                .push_back((ready, bytes, json!({ "sentence": sentence })));
        }
    }
}

impl DeviceModel for Vn200Model {
    fn name(&self) -> &'static str {
        "vn200"
    }

    fn protocol(&self) -> &'static str {
        Protocol::Vn200.name()
    }

    fn baud(&self) -> u32 {
        self.cfg.baud
    }

    fn receive(&mut self, t_gps_ns: i64, bytes: &[u8]) {
        // Processed by the next `advance`, which has the world for `VNBOM` polls.
        self.inbox.push((t_gps_ns, bytes.to_vec()));
    }

    fn advance(
        &mut self,
        world: &World,
        faults: &FaultSchedule,
        until_gps_ns: i64,
        out: &mut Vec<Emission>,
    ) {
        for (t, bytes) in std::mem::take(&mut self.inbox) {
            self.rx.extend_from_slice(&bytes);
            // The sensor's input buffer holds 256 characters (ICD 1.5, error 02): a longer
            // line without an end is dropped.
            if self.rx.len() > 4096 {
                let cut = self.rx.len() - 4096;
                self.rx.drain(..cut);
            }
            self.process_input(t, world, faults);
        }
        loop {
            let t_tick = self.next_tick * IMU_TICK_NS;
            let t_data = t_tick + LATENCY_NS;
            let answer_first = self.answers.front().is_some_and(|a| a.0 <= t_data);
            if answer_first {
                let Some((ready, bytes, v)) = self.answers.pop_front() else {
                    break;
                };
                if ready >= until_gps_ns {
                    self.answers.push_front((ready, bytes, v));
                    return;
                }
                let values = match v {
                    Value::Object(m) => m,
                    _ => Map::new(),
                };
                let polled = values.contains_key("polled");
                out.push(Emission {
                    t_ready_gps_ns: ready,
                    bytes,
                    kind: if polled { "binary_output" } else { "ascii" },
                    t_gps_ns: ready - ANSWER_NS,
                    values,
                });
                continue;
            }
            if t_data >= until_gps_ns {
                return;
            }
            if let Some(&r) = self.resets_ns.front()
                && r <= t_tick
            {
                self.resets_ns.pop_front();
                self.reset(r);
                continue;
            }
            self.next_tick += 1;
            if !self.async_enabled || t_tick < self.outputs_from_gps_ns {
                continue;
            }
            let tick = t_tick.div_euclid(IMU_TICK_NS);
            let due: Vec<usize> = (0..3)
                .filter(|&i| {
                    let c = &self.configs[i];
                    c.async_mode != 0
                        && self.masks[i] != [0; 7]
                        && c.rate_divisor > 0
                        && tick.rem_euclid(i64::from(c.rate_divisor)) == 0
                })
                .collect();
            if due.is_empty() {
                continue;
            }
            let s = self.sample(world, faults, t_tick);
            for i in due {
                let (msg, values) = self.message(i, &s);
                let Some(bytes) = msg.encode_for_wire(i as u8 + 1) else {
                    continue;
                };
                out.push(Emission {
                    t_ready_gps_ns: t_data,
                    bytes,
                    kind: "binary_output",
                    t_gps_ns: t_tick,
                    values,
                });
            }
        }
    }
}

#[cfg(test)]
#[path = "vn200_tests.rs"]
mod tests;
