//! The deterministic fusion pipeline: time-aligned samples in, fused outputs out.
//!
//! [`Pipeline`] takes every [`AlignedSample`] the [`crate::time::aligner::Aligner`] finalises
//! and feeds the parts of the fusion layer:
//! - BAHRS 0x02 (with the latest 0x03 and 0x01), VN-200 binary outputs and Watson lines go to the
//!   [`AttitudeChecker`] (issue 8); each comparison comes out as an [`AttitudeRecord`];
//! - the same samples, the TT-Multi-RF GNSS (JSON `gnss` section, NMEA GGA/RMC) and the vote go
//!   to the [`OwnshipBuilder`];
//! - every traffic report of every TT-Multi-RF protocol (CSV, JSON, MAVLink, GDL90, ASTERIX, raw
//!   Mode S through the drivers' tracker) goes to the [`TrackManager`] (issue 9).
//!
//! At every fusion step (GPS time on a fixed grid, [`PipelineConfig::step_s`]) the pipeline emits
//! the ownship and the traffic picture with DO-365 geometry and filtered alert levels.
//!
//! The pipeline's clock is the GPS time of the samples themselves: a step at time `T` is taken
//! when the first sample at or after `T` arrives, so replaying the same samples gives the same
//! outputs (no wall clock). Only samples whose clock model is locked or coasting move the clock
//! (a locking model's samples are used but do not move it), and samples of an unlocked model are
//! not used at all, so a device's guess cannot push the clock; a jump of more than
//! [`PipelineConfig::max_step_gap_s`] restarts the grid instead of emitting every step between.
//! Samples that are not aligned are counted per device ([`DeviceActivity`]) and otherwise not
//! used: the fusion compares samples on one timebase only.

use serde::Serialize;
use vigil_drivers::bahrs::{self, Accuracy, Inertial};
use vigil_drivers::modes::df::{self, DecodeOptions};
use vigil_drivers::modes::tracker::{Tracker, TrackerConfig};
use vigil_drivers::traffic::TrafficReport;
use vigil_drivers::ttmrf::gdl90::TrafficAltitude;
use vigil_drivers::ttmrf::nmea::{NmeaBody, NmeaSentence, Rmc};
use vigil_drivers::ttmrf::raw::RawFrame;
use vigil_drivers::ttmrf::text::TextMessage;
use vigil_drivers::vn200::Vn200Message;

use crate::attitude::checker::AttitudeChecker;
use crate::attitude::health::HealthCheck;
use crate::attitude::isolation::Unit;
use crate::attitude::params::{CheckParams, ParamError};
use crate::attitude::record::AttitudeRecord;
use crate::attitude::samples::{BahrsInertial, BahrsSample, Vn200Sample, WatsonSample};
use crate::magnetic::DeclinationModel;
use crate::ownship::builder::GnssFix;
use crate::ownship::{OwnshipBuilder, OwnshipParams, OwnshipSolution};
use crate::time::aligner::{AlignedSample, Device, Sample};
use crate::time::{AlignedTime, ClockStatus};
use crate::traffic::{Target, TrackManager, TrafficParams, TrafficStats};

#[cfg(test)]
mod tests;

const NS_PER_S: f64 = 1e9;

/// Parameters of the pipeline, with units and defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PipelineConfig {
    /// Attitude cross-check.
    pub check: CheckParams,
    /// Ownship builder.
    pub ownship: OwnshipParams,
    /// Traffic fusion.
    pub traffic: TrafficParams,
    /// Period of the fusion steps (ownship and traffic picture), s. Default 1 s: the rate of the
    /// TT-Multi-RF's decoded outputs, and of the DO-365 alert filter's M-of-N steps.
    pub step_s: f64,
    /// A clock jump longer than this restarts the step grid instead of emitting every step, s.
    pub max_step_gap_s: f64,
    /// Altitude kind of GDL90 traffic reports (set from the module's configuration).
    pub gdl90_altitude: TrafficAltitudeKind,
    /// Also emit a prompt attitude ([`Fused::Prompt`]) at every attitude sample. Default off:
    /// the replays and their golden files hold the check records; `vigil run` turns it on.
    pub prompt_attitude: bool,
}

/// Which altitude GDL90 traffic reports carry (the module's "altitude priority" setting).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TrafficAltitudeKind {
    /// Barometric priority: pressure altitude (the GDL90 definition, default).
    #[default]
    Pressure,
    /// Geometric priority: geometric altitude when the target sent one (see
    /// [`TrafficAltitude::GeometricPreferred`]).
    GeometricPreferred,
}

impl Default for PipelineConfig {
    fn default() -> Self {
        Self {
            check: CheckParams::default(),
            ownship: OwnshipParams::default(),
            traffic: TrafficParams::default(),
            step_s: 1.0,
            max_step_gap_s: 10.0,
            gdl90_altitude: TrafficAltitudeKind::Pressure,
            prompt_attitude: false,
        }
    }
}

/// The traffic picture of one fusion step.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrafficPicture {
    /// Always "traffic".
    pub kind: &'static str,
    /// GPS time of the step, ns.
    pub t_gps_ns: i64,
    /// Targets in priority order (alert level, time to loss of well-clear, range).
    pub targets: Vec<Target>,
    /// Track manager counters so far.
    pub stats: TrafficStats,
}

/// One output of the pipeline.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Fused {
    /// One attitude cross-check record per BAHRS navigation sample.
    Attitude(Box<AttitudeRecord>),
    /// The ownship at a fusion step.
    Ownship(Box<OwnshipSolution>),
    /// The traffic picture at a fusion step.
    Traffic(TrafficPicture),
    /// The voted attitude at the time of an attitude sample, as soon as it arrives, with the
    /// verdicts of the newest check record (only with [`PipelineConfig::prompt_attitude`]; see
    /// [`AttitudeChecker::prompt`]).
    Prompt(Box<AttitudeRecord>),
}

impl Fused {
    /// GPS time of the output, ns.
    pub fn t_gps_ns(&self) -> i64 {
        match self {
            Fused::Attitude(r) | Fused::Prompt(r) => r.t_gps_ns,
            Fused::Ownship(o) => o.ownship.t_gps_ns,
            Fused::Traffic(p) => p.t_gps_ns,
        }
    }
}

/// What the pipeline saw of one device.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct DeviceActivity {
    /// Samples received.
    pub samples: u64,
    /// Samples that were not aligned (not used).
    pub not_aligned: u64,
    /// Samples whose clock model was unlocked (not used).
    pub unlocked: u64,
    /// GPS time of the newest sample used, ns.
    pub last_t_gps_ns: Option<i64>,
    /// Clock status of the newest aligned sample.
    pub last_status: Option<ClockStatus>,
    // --- issue 24 ---
    /// Records dropped at the fusion's entry for an impossible value (the decoders drop and count
    /// their own; this catches what a decoder cannot see, e.g. raw Mode S decoded here).
    pub invalid_values: u64,
}

/// Per-device activity, in [`Device::ALL`] order.
pub type Activity = [(Device, DeviceActivity); 4];

/// The fusion pipeline (see the module documentation).
pub struct Pipeline {
    cfg: PipelineConfig,
    checker: AttitudeChecker,
    ownship: OwnshipBuilder,
    tracks: TrackManager,
    modes: Tracker,
    last_inertial: Option<Inertial>,
    /// The latest 0x01 on GPS time, for the inertial channel (issue 25 point 5).
    last_inertial_aligned: Option<BahrsInertial>,
    last_accuracy: Option<Accuracy>,
    /// The health cross-check (issue 25 point 4).
    health: HealthCheck,
    last_rmc: Option<(i64, Rmc)>,
    next_step_ns: Option<i64>,
    activity: Activity,
    /// Traffic reports taken (all protocols).
    reports: u64,
    /// Boxes of prompt records handed back by the caller ([`Pipeline::recycle`]), reused so a
    /// prompt output allocates nothing in the steady state (issue 21).
    // The boxes themselves are what is kept: a prompt output carries one.
    #[allow(clippy::vec_box)]
    spare_records: Vec<Box<AttitudeRecord>>,
}

/// Spare record boxes kept at most (a step makes one prompt per attitude sample).
const SPARE_RECORDS: usize = 4;

impl Pipeline {
    /// Takes back an output the caller is done with: its record's box is reused by the next
    /// prompt output. Optional (an output dropped instead is simply freed).
    pub fn recycle(&mut self, f: Fused) {
        if let Fused::Prompt(b) | Fused::Attitude(b) = f
            && self.spare_records.len() < SPARE_RECORDS
        {
            self.spare_records.push(b);
        }
    }

    /// A pipeline with the given parameters and declination model (the WMM in service:
    /// [`crate::magnetic::Wmm`]).
    pub fn new(
        cfg: PipelineConfig,
        model: Box<dyn DeclinationModel + Send>,
    ) -> Result<Self, ParamError> {
        Ok(Self {
            checker: AttitudeChecker::new(cfg.check, model)?,
            ownship: OwnshipBuilder::new(cfg.ownship),
            tracks: TrackManager::new(cfg.traffic),
            modes: Tracker::new(TrackerConfig::default()),
            cfg,
            last_inertial: None,
            last_inertial_aligned: None,
            last_accuracy: None,
            health: HealthCheck::new(cfg.check.health),
            last_rmc: None,
            spare_records: Vec::with_capacity(SPARE_RECORDS),
            next_step_ns: None,
            activity: Device::ALL.map(|d| (d, DeviceActivity::default())),
            reports: 0,
        })
    }

    /// The parameters in force.
    pub fn config(&self) -> &PipelineConfig {
        &self.cfg
    }

    /// Per-device activity so far.
    pub fn activity(&self) -> &Activity {
        &self.activity
    }

    /// The health cross-check (issue 25 point 4): its verdicts at a time, and the newest BAHRS
    /// signal health and VN-200 status.
    pub fn health(&self) -> &HealthCheck {
        &self.health
    }

    /// Traffic reports taken so far (all protocols).
    pub fn reports(&self) -> u64 {
        self.reports
    }

    /// Number of traffic tracks held.
    pub fn tracks(&self) -> usize {
        self.tracks.len()
    }

    /// Takes one aligned sample; pushes the outputs it completes onto `out`.
    pub fn handle(&mut self, s: &AlignedSample, out: &mut Vec<Fused>) {
        let act = &mut self.activity[device_slot(s.device)].1;
        act.samples += 1;
        // The health cross-check's clock and BAHRS inputs (issue 25 point 4): a BAHRS that is
        // not aligned still reports its health and its pulses.
        if let Ok(t) = &s.aligned.time
            && t.status != ClockStatus::Unlocked
        {
            self.health.observe_time(t.t_gps_ns);
        }
        if let Sample::Bahrs(m) = &s.aligned.message {
            match m {
                bahrs::Message::SyncPulseTime(_) => self.health.bahrs_pulse(),
                bahrs::Message::Navigation(n) => self.health.bahrs_navigation(n.health),
                bahrs::Message::Inertial(i) => self.health.bahrs_inertial(i.health),
                _ => self.health.bahrs_message(),
            }
        }
        let time = match s.aligned.time {
            Ok(t) => t,
            Err(_) => {
                act.not_aligned += 1;
                // Coverage (issue 25): the unit is there but off the timebase, and says so.
                if let Some(unit) = attitude_unit(s.device) {
                    self.checker.note_unaligned(unit);
                }
                return;
            }
        };
        act.last_status = Some(time.status);
        if time.status == ClockStatus::Unlocked {
            // A time from a model that is not locked is a guess: not compared with anything.
            act.unlocked += 1;
            if let Some(unit) = attitude_unit(s.device) {
                self.checker.note_unaligned(unit);
            }
            return;
        }
        act.last_t_gps_ns = Some(
            act.last_t_gps_ns
                .map_or(time.t_gps_ns, |p| p.max(time.t_gps_ns)),
        );
        if matches!(time.status, ClockStatus::Locked | ClockStatus::Coasting) {
            self.advance(time.t_gps_ns, out);
        }
        let attitude = self.take(&s.aligned.message, &time);
        self.drain_checker(out);
        // After the checks this sample completed, so the prompt carries their verdicts.
        if attitude
            && self.cfg.prompt_attitude
            && let Some(unit) = attitude_unit(s.device)
            && let Some(r) = self.checker.prompt(time.t_gps_ns, unit)
        {
            let b = match self.spare_records.pop() {
                Some(mut b) => {
                    *b = r;
                    b
                }
                None => Box::new(r),
            };
            out.push(Fused::Prompt(b));
        }
    }

    /// Ends the stream: compares what the checker still holds (no further step is taken: a step
    /// needs a sample at or after its time).
    pub fn finish(&mut self, out: &mut Vec<Fused>) {
        self.checker.finish();
        self.drain_checker(out);
    }

    fn drain_checker(&mut self, out: &mut Vec<Fused>) {
        while let Some(r) = self.checker.next_record() {
            self.ownship.update_attitude(&r);
            out.push(Fused::Attitude(Box::new(r)));
        }
    }

    /// Takes every fusion step up to GPS time `t` (ns).
    fn advance(&mut self, t: i64, out: &mut Vec<Fused>) {
        let step = (self.cfg.step_s.max(1e-3) * NS_PER_S) as i64;
        let gap = (self.cfg.max_step_gap_s.max(self.cfg.step_s) * NS_PER_S) as i64;
        let next = match self.next_step_ns {
            // The first step is the first grid point at or after the first sample.
            None => t
                .div_euclid(step)
                .saturating_add(i64::from(t.rem_euclid(step) != 0))
                .saturating_mul(step),
            Some(n) if t.saturating_sub(n) > gap => {
                // A jump (outage, or a replay with a gap): restart the grid at the new time.
                t.div_euclid(step).saturating_mul(step)
            }
            Some(n) => n,
        };
        let mut n = next;
        while n <= t {
            self.step(n, out);
            match n.checked_add(step) {
                Some(x) => n = x,
                // The end of the timebase: no later step exists.
                None => break,
            }
        }
        self.next_step_ns = Some(n);
    }

    fn step(&mut self, t: i64, out: &mut Vec<Fused>) {
        let Some(own) = self.ownship.state(t) else {
            return;
        };
        let targets = self.tracks.picture(t, &own.ownship);
        out.push(Fused::Ownship(Box::new(own)));
        out.push(Fused::Traffic(TrafficPicture {
            kind: "traffic",
            t_gps_ns: t,
            targets,
            stats: *self.tracks.stats(),
        }));
    }

    /// Feeds one sample to the parts that use it; true when it was an attitude sample (for the
    /// prompt output).
    fn take(&mut self, msg: &Sample, time: &AlignedTime) -> bool {
        let t = time.t_gps_ns;
        let mut attitude = false;
        match msg {
            Sample::Bahrs(m) => match m {
                bahrs::Message::Inertial(i) => {
                    self.last_inertial = Some(*i);
                    self.last_inertial_aligned = Some(BahrsInertial::new(time, i));
                }
                bahrs::Message::Accuracy(a) => self.last_accuracy = Some(*a),
                bahrs::Message::Navigation(n) => {
                    let mut b = BahrsSample::new(
                        time,
                        n,
                        self.last_accuracy.as_ref(),
                        self.last_inertial.as_ref(),
                    );
                    b.inertial = self.last_inertial_aligned;
                    self.ownship.update_bahrs(&b);
                    self.checker.set_fallback_position(self.ownship.position(t));
                    self.checker.push_bahrs(b);
                    attitude = true;
                }
                _ => {}
            },
            Sample::Vn200(m) => {
                if let Vn200Message::Binary(out) = m.as_ref()
                    && let Some(v) = Vn200Sample::from_output(time, out)
                {
                    self.health.vn200_status(t, v.ins_status);
                    self.ownship.update_vn200(&v);
                    self.checker.push_vn200(v);
                    attitude = true;
                }
            }
            Sample::Watson(l) => {
                self.checker.push_watson(WatsonSample::new(time, l));
                attitude = true;
            }
            Sample::TtText(m) => {
                match m.as_ref() {
                    TextMessage::Json(j) => {
                        if let Some(g) = j.gnss.as_ref() {
                            let f = GnssFix::from_json(t, g);
                            // Issue 25 point 6: the altitude as the third vertical opinion (an
                            // epoch without a fix is recorded as such, so it breaks the window).
                            self.checker
                                .push_tt_gnss(t, f.as_ref().and_then(|f| f.alt_wgs84_m));
                            if let Some(f) = f {
                                self.ownship.update_gnss(f);
                            }
                        }
                    }
                    TextMessage::Nmea(n) => self.take_nmea(t, n),
                    _ => {}
                }
                for r in m.traffic_reports() {
                    self.report(t, &r);
                }
            }
            Sample::TtRaw(f) => {
                if let RawFrame::ModeS(frame) = f.as_ref()
                    && let Ok(msg) = df::decode(frame.data(), DecodeOptions::default())
                    && let Some(r) = self.modes.update(&msg, &frame.meta).report
                {
                    self.report(t, &r);
                }
            }
            Sample::TtMavlink(m) => {
                if let Some(r) = m.to_traffic() {
                    self.report(t, &r);
                }
            }
            Sample::TtGdl90(m) => {
                let alt = match self.cfg.gdl90_altitude {
                    TrafficAltitudeKind::Pressure => TrafficAltitude::Pressure,
                    TrafficAltitudeKind::GeometricPreferred => TrafficAltitude::GeometricPreferred,
                };
                if let Some(r) = m.to_traffic(alt) {
                    self.report(t, &r);
                }
            }
            Sample::TtAsterix(m) => {
                if let Some(r) = m.to_traffic() {
                    self.report(t, &r);
                }
            }
        }
        attitude
    }

    fn take_nmea(&mut self, t: i64, n: &NmeaSentence) {
        match &n.body {
            NmeaBody::Rmc(r) => self.last_rmc = Some((t, r.clone())),
            NmeaBody::Gga(g) => {
                // The RMC of the same epoch when the module sends it first, else the one of the
                // epoch before (GGA first, as the simulator sends them after manual 9.2.1): a
                // track and speed at most a second old. Decision: up to 1.5 s between their
                // placements, not 1 s: the two are sent back to back, so the previous epoch's
                // RMC lies a second less the GGA's wait behind it before this one, and a bound
                // of exactly one epoch dropped the velocity whenever a placement moved by a
                // fraction of a ms.
                let rmc = self
                    .last_rmc
                    .as_ref()
                    .filter(|(tr, _)| (t - tr).abs() < 1_500_000_000)
                    .map(|(_, r)| r);
                let f = GnssFix::from_nmea(t, g, rmc, self.cfg.ownship.uere_m);
                // Issue 25 point 6: the altitude as the third vertical opinion (quality 0 is
                // recorded as an epoch without a fix).
                self.checker
                    .push_tt_gnss(t, f.as_ref().and_then(|f| f.alt_wgs84_m));
                if let Some(f) = f {
                    self.ownship.update_gnss(f);
                }
            }
            _ => {}
        }
    }

    /// One traffic report at its aligned time `t`: a report with an impossible value is dropped
    /// and counted; the others go to the tracks at their time of applicability (the aligned time
    /// less the age the protocol states, issue 24).
    fn report(&mut self, t: i64, r: &TrafficReport) {
        self.reports += 1;
        if r.check_values().is_err() {
            self.activity[device_slot(Device::Ttmrf)].1.invalid_values += 1;
            return;
        }
        let age_ns = r.data_age_s.map_or(0, |a| (a * NS_PER_S) as i64);
        self.tracks
            .update_at(t.saturating_sub(age_ns), r, r.source_time.is_none());
    }
}

/// The attitude unit a device's samples come from (none for the TT-Multi-RF).
fn attitude_unit(d: Device) -> Option<Unit> {
    match d {
        Device::Bahrs => Some(Unit::Bahrs),
        Device::Vn200 => Some(Unit::Vn200),
        Device::Watson => Some(Unit::Watson),
        Device::Ttmrf => None,
    }
}

fn device_slot(d: Device) -> usize {
    Device::ALL.iter().position(|&x| x == d).unwrap_or(0)
}
