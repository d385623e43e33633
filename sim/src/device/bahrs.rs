//! BAHRS device model (BAHRS serial protocol 2.0, section 3): 0x01 + 0x05 and 0x02 + 0x04 at their
//! rates, 0x03 at 1 Hz, 0x06 after every synchronisation pulse, 0x0F and 0x1F at start.
//!
//! - MCU clock: microseconds, `mcu_us = mcu0_us + (t_gps - boot) (1 + drift)`, with a random start
//!   value (0 .. 10 s) and a drift drawn within +-`clock_drift_ppm_max`. Samples are taken on the
//!   MCU's own clock (every `1e6 / rate` us of MCU time, integer us), so their GPS times carry the
//!   drift. A reset stops the output for 300 ms, restarts the MCU clock at 0 and every sequence
//!   counter at 0, and sends the versions again.
//! - Synchronisation: the sync input is wired to the VN-200 PPS (on every whole GPS second when a
//!   VN-200 with `pps = true` is present, has a 3D fix (VN-200 ICD: SyncOut GpsPps only with a
//!   valid fix, so no pulses in a VN-200 GNSS outage, unless a `bahrs_sync_miswired` fault says
//!   the input follows another pulse) and no PPS loss is scheduled); 0x06 carries
//!   the MCU time of the pulse (truncated to the us) and is ready `latency_us` after it. The
//!   `sync` options model what the document leaves open (issue 18): the report sent late or
//!   repeated, the wrong edge captured, a software capture's latency.
//! - Every message of a sample is ready `latency_us` after the sample; 0x05 follows its 0x01 and
//!   0x04 its 0x02 immediately, or, with `time_message_lag = n`, after the n-th later data message
//!   of its stream (the time message arrives late; its truth `t_gps_ns` stays the data's). Each message type has its own sequence counter (wrapping at 256).
//! - Noise: white Gaussian on every signal (sigmas in the configuration); the attitude biases and
//!   health words of the fault schedule; the magnetic disturbance adds to the heading.
//!
//! Truth values are the true (noise- and fault-free) quantities in SI, plus `mcu_time_us` where the
//! message carries one and `attitude_fault_rad` (roll, pitch, heading error injected by faults).

use std::collections::VecDeque;

use serde_json::{Map, Value, json};
use vigil_drivers::bahrs::{
    ANGLE_RAD_PER_LSB, Accuracy, DataTime, HardwareVersion, Health, Inertial, InertialHealth,
    Message, Navigation, NavigationHealth, SoftwareVersion, SyncPulseTime,
};

use vigil_drivers::protocol::Protocol;

use super::{DeviceModel, Emission, FaultSchedule};
use crate::rng::Rng;
use crate::scenario::{Axis, BahrsConfig, HealthSignal};
use crate::truth::World;
use crate::units::NS_PER_S;

/// Boot time after power-on or reset before the first output, ns.
pub const BOOT_NS: i64 = 300_000_000;

fn obj(v: Value) -> Map<String, Value> {
    match v {
        Value::Object(m) => m,
        _ => Map::new(),
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
enum Event {
    Reset,
    Versions,
    SyncReport,
    Pps,
    Inertial,
    Navigation,
    Accuracy,
}

/// A queued 0x06 report.
struct Report {
    ready: i64,
    /// Truth: GPS time of the instant whose MCU time it carries.
    t: i64,
    m: Message,
    v: Value,
    /// Pulse number (a repeat is dropped once a newer pulse exists).
    n: u64,
    repeat: bool,
}

#[derive(Debug, Clone, Copy, Default)]
struct Counters {
    inertial: u8,
    inertial_time: u8,
    navigation: u8,
    navigation_time: u8,
    accuracy: u8,
    pps: u8,
}

/// The BAHRS model.
pub struct BahrsModel {
    cfg: BahrsConfig,
    noise: Rng,
    drift: f64,
    start_gps_ns: i64,
    boot_gps_ns: i64,
    mcu0_us: f64,
    outputs_from_gps_ns: i64,
    versions_pending: bool,
    first_sample_mcu_us: [u64; 3],
    next_k: [u64; 3],
    period_us: [f64; 3],
    next_pps_gps_s: i64,
    pps_wired: bool,
    counters: Counters,
    resets_s: Vec<f64>,
    next_reset: usize,
    unique_id: [u32; 3],
    /// Time messages (0x05, 0x04) waiting for `time_message_lag` later data messages.
    lagged: [VecDeque<(i64, Message, Value)>; 2],
    /// 0x06 reports waiting for their ready time, in ready order.
    reports: VecDeque<Report>,
    /// Pulses captured so far (a repeated report stops when a newer pulse exists).
    pulses: u64,
    /// Software capture latency draws.
    capture: Rng,
    /// Pressure height held while the pressure port is blocked (issue 25), m.
    blocked_height_m: Option<f64>,
}

impl BahrsModel {
    /// A BAHRS powered on at the scenario start. `pps_wired`: a PPS source drives its sync input.
    pub fn new(
        cfg: &BahrsConfig,
        world: &World,
        faults: &FaultSchedule,
        seed: u64,
        pps_wired: bool,
    ) -> Self {
        let mut clock = Rng::stream(seed, "bahrs/clock");
        let drift = clock.range(-cfg.clock_drift_ppm_max, cfg.clock_drift_ppm_max) * 1e-6;
        let mcu0_us = clock.range(0.0, 10.0e6).floor();
        let unique_id = [0, 1, 2].map(|_| clock.next_u64() as u32);
        let start = world.start_gps_ns;
        let mut m = Self {
            cfg: cfg.clone(),
            noise: Rng::stream(seed, "bahrs/noise"),
            drift,
            start_gps_ns: start,
            boot_gps_ns: start,
            mcu0_us,
            outputs_from_gps_ns: start,
            versions_pending: true,
            first_sample_mcu_us: [0; 3],
            next_k: [0; 3],
            period_us: [
                cfg.inertial_rate_hz,
                cfg.navigation_rate_hz,
                cfg.accuracy_rate_hz,
            ]
            .map(|hz| 1e6 / hz),
            next_pps_gps_s: start.div_euclid(NS_PER_S) + 1,
            pps_wired,
            counters: Counters::default(),
            resets_s: faults.resets("bahrs"),
            next_reset: 0,
            unique_id,
            lagged: [VecDeque::new(), VecDeque::new()],
            reports: VecDeque::new(),
            pulses: 0,
            capture: Rng::stream(seed, "bahrs/capture"),
            blocked_height_m: None,
        };
        m.align_schedules();
        m
    }

    /// The MCU clock drift drawn for this run (fraction, e.g. 3.1e-5 for +31 ppm).
    pub fn drift(&self) -> f64 {
        self.drift
    }

    /// MCU time at a GPS time (fractional us).
    pub fn mcu_us_at(&self, t_gps_ns: i64) -> f64 {
        self.mcu0_us + (t_gps_ns - self.boot_gps_ns) as f64 / 1000.0 * (1.0 + self.drift)
    }

    fn gps_of_mcu(&self, mcu_us: u64) -> i64 {
        self.boot_gps_ns
            + ((mcu_us as f64 - self.mcu0_us) * 1000.0 / (1.0 + self.drift)).round() as i64
    }

    /// First sample of each schedule: the first whole period of MCU time after outputs start.
    fn align_schedules(&mut self) {
        let m = self.mcu_us_at(self.outputs_from_gps_ns);
        for i in 0..3 {
            self.first_sample_mcu_us[i] =
                ((m / self.period_us[i]).ceil() * self.period_us[i]).round() as u64;
            self.next_k[i] = 0;
        }
    }

    fn sample_mcu(&self, i: usize) -> u64 {
        self.first_sample_mcu_us[i] + (self.next_k[i] as f64 * self.period_us[i]).round() as u64
    }

    fn next_event(&self) -> (i64, Event) {
        let mut best = (i64::MAX, Event::Accuracy);
        let mut consider = |t: i64, e: Event| {
            if (t, e) < best {
                best = (t, e);
            }
        };
        if let Some(r) = self.resets_s.get(self.next_reset) {
            consider(self.start_gps_ns + (r * 1e9).round() as i64, Event::Reset);
        }
        if self.versions_pending {
            consider(self.outputs_from_gps_ns, Event::Versions);
        }
        if self.pps_wired {
            consider(self.next_pps_gps_s * NS_PER_S, Event::Pps);
        }
        if let Some(r) = self.reports.front() {
            consider(r.ready, Event::SyncReport);
        }
        for (i, e) in [Event::Inertial, Event::Navigation, Event::Accuracy]
            .into_iter()
            .enumerate()
        {
            consider(self.gps_of_mcu(self.sample_mcu(i)), e);
        }
        best
    }

    fn inertial_health(&self, t_s: f64, f: &FaultSchedule) -> InertialHealth {
        let h = |s| f.bahrs_health(t_s, s).unwrap_or(Health::Safe);
        let sf = h(HealthSignal::SpecificForce);
        let ar = h(HealthSignal::AngularRate);
        InertialHealth::new([sf; 3], [ar; 3])
    }

    fn navigation_health(&self, t_s: f64, f: &FaultSchedule) -> NavigationHealth {
        let h = |s| f.bahrs_health(t_s, s).unwrap_or(Health::Safe);
        NavigationHealth::new(
            h(HealthSignal::PressureHeight),
            h(HealthSignal::VelocityDown),
            h(HealthSignal::Roll),
            h(HealthSignal::Pitch),
            h(HealthSignal::Heading),
        )
    }

    /// Queues a time message of stream `i` (0 = 0x05, 1 = 0x04) and sends the ones that have
    /// waited for `time_message_lag` data messages, ready with the current data message.
    fn emit_time(
        &mut self,
        i: usize,
        out: &mut Vec<Emission>,
        t: i64,
        ready: i64,
        m: Message,
        v: Value,
    ) {
        self.lagged[i].push_back((t, m, v));
        while self.lagged[i].len() > self.cfg.time_message_lag as usize {
            let Some((t, m, v)) = self.lagged[i].pop_front() else {
                break;
            };
            self.emit(out, t, ready, m, v);
        }
    }

    fn emit(&self, out: &mut Vec<Emission>, t_gps_ns: i64, ready: i64, m: Message, values: Value) {
        let kind = match m {
            Message::Inertial(_) => "inertial",
            Message::Navigation(_) => "navigation",
            Message::Accuracy(_) => "accuracy",
            Message::NavigationTime(_) => "navigation_time",
            Message::InertialTime(_) => "inertial_time",
            Message::SyncPulseTime(_) => "sync_pulse_time",
            Message::SoftwareVersion(_) => "software_version",
            Message::HardwareVersion(_) => "hardware_version",
            _ => "other",
        };
        let mut values = obj(values);
        values.insert("type_id".into(), json!(m.type_id()));
        if let Some(seq) = m.seq() {
            values.insert("seq".into(), json!(seq));
        }
        out.push(Emission {
            t_ready_gps_ns: ready,
            bytes: m.to_frame(),
            kind,
            t_gps_ns,
            values,
        });
    }

    /// A PPS second at `t`: captures it (unless lost) and queues its 0x06 report.
    fn pulse(&mut self, t: i64, world: &World, faults: &FaultSchedule) {
        let t_s = world.elapsed_s(t);
        // Without a VN-200 fix no GpsPps pulse comes, unless the input is miswired to a pulse
        // that does not follow that fix (issue 25 point 4's fault).
        let no_fix = faults.gnss_lost("vn200", t_s) && !faults.bahrs_sync_miswired(t_s);
        if t < self.outputs_from_gps_ns || faults.pps_lost(t_s) || no_fix {
            return;
        }
        let sync = &self.cfg.sync;
        let latency_ns = self.capture.range(0.0, sync.capture_latency_us.max(0.0)) * 1000.0;
        let edge = t + (sync.edge_offset_ms * 1e6).round() as i64;
        // The instant whose MCU time the report carries: the edge plus the capture latency.
        let captured = edge + latency_ns.round() as i64;
        if captured < self.boot_gps_ns {
            return;
        }
        let mcu = self.mcu_us_at(captured).floor() as u64;
        let seq = self.counters.pps;
        self.counters.pps = seq.wrapping_add(1);
        self.pulses += 1;
        let m = Message::SyncPulseTime(SyncPulseTime {
            seq,
            mcu_time_us: mcu,
        });
        let delay_ns = match sync.report_delay_ms {
            Some(ms) => (ms.max(0.0) * 1e6).round() as i64,
            None => i64::from(self.cfg.latency_us) * 1000,
        };
        let v = json!({ "mcu_time_us": mcu, "mcu_time_exact_us": self.mcu_us_at(captured) });
        self.queue_report(Report {
            ready: edge + delay_ns,
            t: captured,
            m,
            v,
            n: self.pulses,
            repeat: false,
        });
    }

    fn queue_report(&mut self, r: Report) {
        let at = self.reports.partition_point(|q| q.ready <= r.ready);
        self.reports.insert(at, r);
    }

    /// Sends the earliest queued 0x06; with `report_repeat_ms`, queues it again, until a newer
    /// pulse exists.
    fn report(&mut self, out: &mut Vec<Emission>) {
        let Some(r) = self.reports.pop_front() else {
            return;
        };
        if r.repeat && r.n != self.pulses {
            return;
        }
        self.emit(out, r.t, r.ready, r.m, r.v.clone());
        let every = self.cfg.sync.report_repeat_ms;
        if every > 0.0 {
            self.queue_report(Report {
                ready: r.ready + (every * 1e6).round().max(1.0) as i64,
                repeat: true,
                ..r
            });
        }
    }

    fn sample(
        &mut self,
        i: usize,
        t: i64,
        world: &World,
        faults: &FaultSchedule,
        out: &mut Vec<Emission>,
    ) {
        let mcu = self.sample_mcu(i);
        self.next_k[i] += 1;
        let ready = t + i64::from(self.cfg.latency_us) * 1000;
        let o = world.ownship(t);
        let t_s = world.elapsed_s(t);
        let n = self.cfg.noise.clone();
        let c = &mut self.counters;
        match i {
            0 => {
                let (seq, tseq) = (c.inertial, c.inertial_time);
                c.inertial = seq.wrapping_add(1);
                c.inertial_time = tseq.wrapping_add(1);
                let sf = o
                    .specific_force_body_mps2
                    .map(|v| v + self.noise.gauss(n.specific_force_mps2));
                let bias = faults.bahrs_gyro_bias_radps(t_s);
                let mut ar = o
                    .angular_rate_body_radps
                    .map(|v| v + self.noise.gauss(n.angular_rate_radps));
                for (a, b) in ar.iter_mut().zip(bias) {
                    *a += b;
                }
                let health = self.inertial_health(t_s, faults);
                let m = Message::Inertial(Inertial::from_si(seq, sf, ar, health));
                let mut v = json!({
                    "mcu_time_us": mcu,
                    "specific_force_body_mps2": o.specific_force_body_mps2,
                    "angular_rate_body_radps": o.angular_rate_body_radps,
                    "health_word": health.0,
                });
                // Only while a gyro fault acts, so fault-free recordings stay as they were.
                if bias != [0.0; 3] {
                    v["gyro_fault_radps"] = json!(bias);
                }
                self.emit(out, t, ready, m, v);
                let tm = Message::InertialTime(DataTime {
                    seq: tseq,
                    data_seq: seq,
                    mcu_time_us: mcu,
                });
                let v = json!({ "data_seq": seq, "mcu_time_us": mcu });
                self.emit_time(0, out, t, ready, tm, v);
            }
            1 => {
                let (seq, tseq) = (c.navigation, c.navigation_time);
                c.navigation = seq.wrapping_add(1);
                c.navigation_time = tseq.wrapping_add(1);
                let fault = [Axis::Roll, Axis::Pitch, Axis::Heading]
                    .map(|a| faults.bahrs_attitude_bias_rad(t_s, a));
                let mag = faults.magnetic_offset_rad(t_s);
                let health = self.navigation_health(t_s, faults);
                // Noise is drawn whatever the fault, so the other signals' draws stay the same.
                let mut height = o.alt_pressure_m + self.noise.gauss(n.pressure_height_m);
                let mut vd = o.vel_ned_mps[2] + self.noise.gauss(n.velocity_down_mps);
                let blocked = faults.pressure_port_blocked(t_s);
                if blocked {
                    // A blocked static port traps the pressure: the height stays at its last
                    // value and the baro-damped vertical velocity reads 0.
                    height = *self.blocked_height_m.get_or_insert(height);
                    vd = 0.0;
                } else {
                    self.blocked_height_m = None;
                }
                let m = Message::Navigation(Navigation::from_si(
                    seq,
                    height,
                    vd,
                    o.roll_rad + fault[0] + self.noise.gauss(n.tilt_rad),
                    o.pitch_rad + fault[1] + self.noise.gauss(n.tilt_rad),
                    o.heading_mag_rad + fault[2] + mag + self.noise.gauss(n.heading_rad),
                    health,
                ));
                let mut v = json!({
                    "mcu_time_us": mcu,
                    "alt_pressure_m": o.alt_pressure_m,
                    "velocity_down_mps": o.vel_ned_mps[2],
                    "roll_rad": o.roll_rad,
                    "pitch_rad": o.pitch_rad,
                    "heading_mag_rad": o.heading_mag_rad,
                    "yaw_rad": o.yaw_rad,
                    "declination_rad": o.declination_rad,
                    "attitude_fault_rad": fault,
                    "magnetic_disturbance_rad": mag,
                    "health_word": health.0,
                });
                // Only while the port is blocked, so fault-free recordings stay as they were.
                if blocked {
                    v["pressure_port_blocked"] = json!(true);
                }
                self.emit(out, t, ready, m, v);
                let tm = Message::NavigationTime(DataTime {
                    seq: tseq,
                    data_seq: seq,
                    mcu_time_us: mcu,
                });
                let v = json!({ "data_seq": seq, "mcu_time_us": mcu });
                self.emit_time(1, out, t, ready, tm, v);
            }
            _ => {
                let seq = c.accuracy;
                c.accuracy = seq.wrapping_add(1);
                // A sigma below half an LSB would round to 0, which means "invalid": send 1 LSB.
                let raw = |s: f64| ((s / ANGLE_RAD_PER_LSB).round() as u16).max(1);
                let m = Message::Accuracy(Accuracy {
                    seq,
                    std_north_raw: raw(n.tilt_rad),
                    std_east_raw: raw(n.tilt_rad),
                    std_heading_raw: raw(n.heading_rad),
                    mcu_time_us: mcu,
                });
                let v = json!({
                    "mcu_time_us": mcu,
                    "std_north_rad": n.tilt_rad,
                    "std_east_rad": n.tilt_rad,
                    "std_heading_rad": n.heading_rad,
                });
                self.emit(out, t, ready, m, v);
            }
        }
    }
}

impl DeviceModel for BahrsModel {
    fn name(&self) -> &'static str {
        "bahrs"
    }

    fn protocol(&self) -> &'static str {
        Protocol::Bahrs.name()
    }

    fn baud(&self) -> u32 {
        self.cfg.baud
    }

    fn advance(
        &mut self,
        world: &World,
        faults: &FaultSchedule,
        until_gps_ns: i64,
        out: &mut Vec<Emission>,
    ) {
        let latency_ns = i64::from(self.cfg.latency_us) * 1000;
        loop {
            let (t, e) = self.next_event();
            let ready = if matches!(e, Event::Reset | Event::Versions | Event::SyncReport) {
                t
            } else {
                t + latency_ns
            };
            if ready >= until_gps_ns {
                return;
            }
            match e {
                Event::Reset => {
                    self.next_reset += 1;
                    self.boot_gps_ns = t;
                    self.mcu0_us = 0.0;
                    self.outputs_from_gps_ns = t + BOOT_NS;
                    self.versions_pending = true;
                    self.counters = Counters::default();
                    // Time messages still queued in the device are lost with the reset.
                    self.lagged.iter_mut().for_each(VecDeque::clear);
                    self.reports.clear();
                    self.align_schedules();
                }
                Event::Versions => {
                    self.versions_pending = false;
                    let sw = Message::SoftwareVersion(SoftwareVersion {
                        project_code: *b"BAH",
                        major: 2,
                        minor: 0,
                    });
                    self.emit(
                        out,
                        t,
                        t,
                        sw,
                        json!({ "project_code": "BAH", "major": 2, "minor": 0 }),
                    );
                    let hw = Message::HardwareVersion(HardwareVersion {
                        mcu_id: 0x0451,
                        unique_id: self.unique_id,
                    });
                    self.emit(
                        out,
                        t,
                        t,
                        hw,
                        json!({ "mcu_id": 0x0451, "unique_id": self.unique_id }),
                    );
                }
                Event::Pps => {
                    self.next_pps_gps_s += 1;
                    self.pulse(t, world, faults);
                }
                Event::SyncReport => self.report(out),
                Event::Inertial => self.sample(0, t, world, faults, out),
                Event::Navigation => self.sample(1, t, world, faults, out),
                Event::Accuracy => self.sample(2, t, world, faults, out),
            }
        }
    }
}
