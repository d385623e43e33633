//! The stateful cross-check (issue 8): BAHRS, VN-200 and Watson samples go in, one
//! [`AttitudeRecord`] per BAHRS sample comes out.
//!
//! Comparisons happen at each BAHRS sample time. The VN-200 and the Watson are interpolated on
//! the rotation group (slerp) between their samples around that time. Samples arrive in any
//! interleaving, so a BAHRS sample waits until both other units have a sample after it, or until
//! waiting longer could not help (a unit later than its freshness limit is "stale"). Records come
//! out in BAHRS time order; [`AttitudeChecker::finish`] releases the rest at the end of a stream.
//!
//! Magnetic headings (BAHRS, Watson) become true by adding the declination at the VN-200
//! position (or a fallback position from the ownship) from a [`DeclinationModel`], refreshed every
//! `declination_refresh_s` or after about 10 km. Mounting offsets are removed from every unit.

use std::collections::VecDeque;

use nalgebra::UnitQuaternion;

use super::angles::{from_ypr, interpolate, to_ypr, wrap_2pi};
use super::compare::{Axis, VarianceTerms, compare_axis, euler_rates, tilt_variances, unmount};
use super::coverage::{
    self, Arrival, CoverageRecord, CoverageState, NotComparedReason, SLOT_ROLL, SLOT_VERTICAL,
    SLOTS,
};
use super::gates::{self, FrozenDetector, Gate, GateReason};
use super::inertial::{InertialChannel, InertialRecord, Vn200Inertial, vn200_at};
use super::isolation::{Isolation, PairVerdict, Pairs, Unit, isolate};
use super::params::{CheckParams, ParamError};
use super::persistence::Persistence;
use super::record::*;
use super::samples::{BahrsSample, Vn200Sample, WatsonSample};
use super::vertical::{VerticalChannel, VerticalRecord, Vn200Vertical};
use super::vote::vote;
use crate::magnetic::{Declination, DeclinationModel, MagneticZone};

#[path = "check_isolation.rs"]
mod check_isolation;
#[path = "check_pairs.rs"]
mod check_pairs;
#[path = "prompt.rs"]
mod prompt;

use check_isolation::{FaultSummary, raw_isolation};
use check_pairs::PairInputs;

const DEG: f64 = std::f64::consts::PI / 180.0;
/// History kept per unit, samples (bounded memory).
const MAX_HISTORY: usize = 256;
/// BAHRS samples waiting for the other units, at most.
const MAX_PENDING: usize = 256;

#[derive(Debug, Clone, Copy, Default)]
struct PairAxisState {
    stat: Persistence,
    fixed: Persistence,
    last_compared_ns: Option<i64>,
}

/// A unit's attitude at the comparison time, ready to compare.
#[derive(Debug, Clone, Copy)]
struct Prepared {
    /// Roll, pitch, true heading, rad (after mounting and declination).
    values: Option<[f64; 3]>,
    heading_mag: Option<f64>,
    /// Variances roll, pitch, heading, rad^2.
    var: [f64; 3],
    gates: [Gate; 3],
    sigma_ns: f64,
    age_s: Option<f64>,
    rates: Option<[f64; 3]>,
    /// Time from the sample used to the comparison time when no later sample brackets that
    /// time (the value is held), s; 0 when interpolated, and for the BAHRS at its own time.
    held_s: f64,
}

impl Prepared {
    /// A unit with nothing to compare, for the reason `g`.
    fn missing(g: GateReason) -> Self {
        Self {
            values: None,
            heading_mag: None,
            var: [0.0; 3],
            gates: [Some(g); 3],
            sigma_ns: 0.0,
            age_s: None,
            rates: None,
            held_s: 0.0,
        }
    }
}

struct DeclinationCache {
    t_ns: i64,
    lat_deg: f64,
    lon_deg: f64,
    value: Option<Declination>,
}

/// The attitude and health cross-check (see the module documentation).
pub struct AttitudeChecker {
    params: CheckParams,
    k_axis: f64,
    k_joint: f64,
    model: Box<dyn DeclinationModel + Send>,
    vn: VecDeque<(Vn200Sample, bool)>,
    watson: VecDeque<(WatsonSample, bool)>,
    pending: VecDeque<(BahrsSample, bool)>,
    frozen: [FrozenDetector; 3],
    decl: Option<DeclinationCache>,
    fallback_position: Option<[f64; 3]>,
    /// [pair][axis]: pairs BAHRS-VN200, BAHRS-Watson, VN200-Watson; axes roll, pitch, heading.
    pairs: [[PairAxisState; 3]; 3],
    joint: [Persistence; 3],
    last_t_ns: Option<i64>,
    /// Since when each axis (roll, pitch, heading, joint) has been settling, GPS ns.
    settle_since: [Option<i64>; 4],
    /// The previous outcome of each axis (roll, pitch, heading, joint).
    prev_isolation: [Isolation; 4],
    vertical: VerticalChannel,
    /// Issue 25 point 5: the BAHRS 0x01 against the VN-200 Accel and AngularRate.
    inertial: InertialChannel,
    finished: bool,
    /// The newest BAHRS sample compared, with its frozen verdict (the prompt output's BAHRS
    /// when none is pending).
    last_bahrs: Option<(BahrsSample, bool)>,
    /// Verdicts of the newest record (the prompt output's).
    last_verdicts: Option<prompt::Verdicts>,
    /// GPS time of the newest prompt output, ns.
    last_prompt_ns: Option<i64>,
    // --- issue 25: coverage ---
    /// Last comparison per unit and check, and how each unit's samples arrive.
    coverage: CoverageState,
}

impl AttitudeChecker {
    /// A checker with the given parameters and declination model.
    pub fn new(
        params: CheckParams,
        model: Box<dyn DeclinationModel + Send>,
    ) -> Result<Self, ParamError> {
        params.validate()?;
        Ok(Self {
            k_axis: params.axis_threshold(),
            k_joint: params.joint_threshold(),
            params,
            model,
            vn: VecDeque::new(),
            watson: VecDeque::new(),
            pending: VecDeque::new(),
            frozen: Default::default(),
            decl: None,
            fallback_position: None,
            pairs: Default::default(),
            joint: Default::default(),
            last_t_ns: None,
            settle_since: [None; 4],
            prev_isolation: [Isolation::NoFault; 4],
            vertical: VerticalChannel::default(),
            inertial: InertialChannel::default(),
            finished: false,
            last_bahrs: None,
            last_verdicts: None,
            last_prompt_ns: None,
            coverage: CoverageState::default(),
        })
    }

    /// The parameters in force.
    pub fn params(&self) -> &CheckParams {
        &self.params
    }

    /// A position (lat deg, lon deg, height m) for the declination when the VN-200 has none
    /// (e.g. the TT-Multi-RF GNSS through the ownship).
    pub fn set_fallback_position(&mut self, lla: Option<[f64; 3]>) {
        self.fallback_position = lla;
    }

    /// Notes that a sample of `unit` arrived but could not be used: not aligned on GPS time, or
    /// its clock model unlocked (coverage: such a unit is "not aligned" or "not wired" rather
    /// than "absent" or "stale"; cleared by its next aligned sample).
    pub fn note_unaligned(&mut self, unit: Unit) {
        self.coverage.arrival[unit_slot(unit)].unaligned_now = true;
    }

    fn note_aligned(&mut self, unit: Unit) {
        self.coverage.arrival[unit_slot(unit)] = Arrival {
            unaligned_now: false,
            ever_aligned: true,
        };
    }

    /// Adds a BAHRS navigation sample (it is compared once the others catch up).
    pub fn push_bahrs(&mut self, s: BahrsSample) {
        self.note_aligned(Unit::Bahrs);
        let f = self.frozen[0].update(
            [
                s.roll_rad,
                s.pitch_rad,
                s.heading_mag_rad,
                s.velocity_down_mps,
            ],
            s.t_gps_ns,
            self.params.frozen_window_s,
        );
        self.pending.push_back((s, f));
    }

    /// Adds a TT-Multi-RF GNSS epoch (issue 25 point 6, the third vertical opinion): its GPS
    /// time, ns, and its altitude above the ellipsoid, m (`None` without a fix).
    pub fn push_tt_gnss(&mut self, t_gps_ns: i64, alt_m: Option<f64>) {
        self.vertical.push_tt_gnss(t_gps_ns, alt_m);
    }

    /// Adds a VN-200 sample.
    pub fn push_vn200(&mut self, s: Vn200Sample) {
        self.note_aligned(Unit::Vn200);
        let q = s.attitude.quaternion();
        let f = self.frozen[1].update(
            [q.w, q.i, q.j, q.k],
            s.t_gps_ns,
            self.params.frozen_window_s,
        );
        push_sorted(&mut self.vn, (s, f), |x| x.0.t_gps_ns);
    }

    /// Adds a Watson sample.
    pub fn push_watson(&mut self, s: WatsonSample) {
        self.note_aligned(Unit::Watson);
        let f = self.frozen[2].update(
            [s.roll_rad, s.pitch_rad, s.heading_mag_rad, s.rates_radps[2]],
            s.t_gps_ns,
            self.params.frozen_window_s,
        );
        push_sorted(&mut self.watson, (s, f), |x| x.0.t_gps_ns);
    }

    /// Marks the end of the stream: every pending BAHRS sample is compared now.
    pub fn finish(&mut self) {
        self.finished = true;
    }

    fn horizon_ns(&self, period_s: f64) -> i64 {
        (self.params.max_age_periods * period_s * 1e9) as i64
    }

    /// The next record, when a pending BAHRS sample can be compared.
    pub fn next_record(&mut self) -> Option<AttitudeRecord> {
        let &(b, _) = self.pending.front()?;
        let newest = [
            self.pending.back().map(|x| x.0.t_gps_ns),
            self.vn.back().map(|x| x.0.t_gps_ns),
            self.watson.back().map(|x| x.0.t_gps_ns),
        ]
        .into_iter()
        .flatten()
        .max()
        .unwrap_or(b.t_gps_ns);
        let waited = newest.saturating_sub(b.t_gps_ns);
        let ready = |latest: Option<i64>, horizon: i64| {
            latest.is_some_and(|t| t >= b.t_gps_ns) || waited > horizon
        };
        let go = self.finished
            || self.pending.len() > MAX_PENDING
            || (ready(
                self.vn.back().map(|x| x.0.t_gps_ns),
                self.horizon_ns(self.params.vn200_period_s),
            ) && ready(
                self.watson.back().map(|x| x.0.t_gps_ns),
                self.horizon_ns(self.params.watson_period_s),
            ));
        if !go {
            return None;
        }
        let (b, frozen) = self.pending.pop_front()?;
        let rec = self.compare_at(&b, frozen);
        prune(&mut self.vn, b.t_gps_ns, |x| x.0.t_gps_ns);
        prune(&mut self.watson, b.t_gps_ns, |x| x.0.t_gps_ns);
        Some(rec)
    }

    fn declination(&mut self, t_ns: i64) -> Option<Declination> {
        let pos = self
            .vn
            .iter()
            .rev()
            .find(|x| x.0.ins_status.position_valid())
            .and_then(|x| x.0.lla)
            .or(self.fallback_position)?;
        let refresh_ns = (self.params.declination_refresh_s * 1e9) as i64;
        let stale = match &self.decl {
            None => true,
            Some(c) => {
                t_ns.saturating_sub(c.t_ns).unsigned_abs() > refresh_ns.unsigned_abs()
                    || (pos[0] - c.lat_deg).abs() > 0.1
                    || ((pos[1] - c.lon_deg) * (pos[0] * DEG).cos()).abs() > 0.1
            }
        };
        if stale {
            // A refused query is remembered too, so it is retried at the refresh period only.
            let value = self.model.declination(pos[0], pos[1], pos[2], t_ns).ok();
            self.decl = Some(DeclinationCache {
                t_ns,
                lat_deg: pos[0],
                lon_deg: pos[1],
                value,
            });
        }
        self.decl.as_ref().and_then(|c| c.value)
    }

    /// One comparison step at the BAHRS sample `b` against the buffered VN-200 and Watson
    /// samples (`frozen`: the BAHRS frozen detector's verdict for `b`).
    ///
    /// The steps, in order: (1) the time step since the previous check and the declination;
    /// (2) each unit at `b`'s time, ready to compare (interpolated, unmounted, true heading,
    /// gated); (3) every pair on every axis and each pair's joint test (`check_pairs`);
    /// (4) the isolation those verdicts point at, then (5) its transitions from the previous
    /// outcome and the fault flags (`check_isolation`); (6) the vote over the units left; (7) the
    /// vertical and inertial channels and the coverage of the check.
    pub fn compare_at(&mut self, b: &BahrsSample, frozen: bool) -> AttitudeRecord {
        let t = b.t_gps_ns;
        let dt_s = self.advance_clock(t);
        let decl = self.declination(t);

        let (mag_gate, rz, d_rad) = magnetic_frame(decl);
        let bahrs = self.prepare_bahrs(b, frozen, &rz, mag_gate, d_rad);
        let (vn, vn_healthy, vn_vertical) = self.prepare_vn200(t);
        let watson = self.prepare_watson(t, &rz, mag_gate);
        let units = [&bahrs, &vn, &watson];

        let pairs = self.compare_pairs(&PairInputs {
            t,
            dt_s,
            units,
            euler_radps: timing_rates(units, b),
            decl_var: decl.map(|d| d.sigma_rad * d.sigma_rad).unwrap_or(0.0),
        });

        let raw = raw_isolation(&pairs, vn_healthy);
        let isolation = self.settle_isolation(t, raw, &pairs);
        let faults = FaultSummary::of(&isolation);

        // The vote: units open on the axis and not isolated on it.
        let voted = vote_units(units, [isolation.roll, isolation.pitch, isolation.heading]);

        let p = self.params;
        let vertical = self.vertical.update(b, &vn_vertical, dt_s, self.k_axis, &p);
        let inertial = self.compare_inertial(b, t);
        let coverage = self.check_coverage(t, units, &pairs, &vertical);
        let rec = AttitudeRecord {
            kind: KIND,
            t_gps_ns: t,
            fault: faults.fault,
            isolated: faults.isolated,
            multiple_fault: faults.multiple,
            magnetic_disturbance: isolation.heading == Isolation::MagneticDisturbance,
            bahrs_integrity_risk: bahrs_integrity_risk(b),
            vn200_healthy: vn_healthy,
            bahrs: unit_values(&bahrs),
            vn200: unit_values(&vn),
            watson: unit_values(&watson),
            declination: decl.map(declination_record),
            pairs,
            isolation,
            voted,
            vertical,
            inertial,
            coverage,
        };
        self.last_verdicts = Some(prompt::Verdicts::of(&rec));
        self.last_bahrs = Some((*b, frozen));
        rec
    }

    /// Moves the check's clock to `t` (GPS ns) and returns the step from the previous check, s:
    /// the persistence counters integrate over it. Capped at 1 s so that a gap in the BAHRS
    /// stream cannot declare or clear a fault at once; the nominal BAHRS period at the first
    /// check or when time does not advance (a repeated or out-of-order sample).
    fn advance_clock(&mut self, t: i64) -> f64 {
        let dt_s = match self.last_t_ns {
            Some(t0) if t > t0 => (t.saturating_sub(t0) as f64 * 1e-9).min(1.0),
            _ => self.params.bahrs_period_s,
        };
        self.last_t_ns = Some(t);
        dt_s
    }

    /// The coverage of a check at `t`: what the pairs and the vertical channel compared, and
    /// why the rest was not (see [`coverage`]).
    fn check_coverage(
        &mut self,
        t: i64,
        units: [&Prepared; 3],
        pairs: &PairsRecord,
        vertical: &VerticalRecord,
    ) -> CoverageRecord {
        let mut compared = [false; SLOTS];
        let pair_units = [(0, 1), (0, 2), (1, 2)];
        let records = [&pairs.bahrs_vn200, &pairs.bahrs_watson, &pairs.vn200_watson];
        for (&(ia, ib), r) in pair_units.iter().zip(records) {
            for (ai, a) in [&r.roll, &r.pitch, &r.heading].into_iter().enumerate() {
                if a.comparison.is_some() {
                    compared[ia] = true;
                    compared[ib] = true;
                    compared[SLOT_ROLL + ai] = true;
                }
            }
        }
        let v = [&vertical.velocity_down, &vertical.height_rate];
        compared[SLOT_VERTICAL] = v.iter().any(|c| c.verdict != PairVerdict::NotCompared);
        let arrival = self.coverage.arrival;
        let mut reason = [None; SLOTS];
        for (i, u) in units.iter().enumerate() {
            if !compared[i] {
                reason[i] = Some(coverage::unit_reason(&u.gates, &arrival[i]));
            }
        }
        for ai in 0..3 {
            if !compared[SLOT_ROLL + ai] {
                // The first closed gate, the BAHRS's first: the check exists for it.
                reason[SLOT_ROLL + ai] = Some(
                    (0..3)
                        .find_map(|i| units[i].gates[ai].map(|g| arrival[i].explain(g)))
                        .unwrap_or(NotComparedReason::NoPartner),
                );
            }
        }
        if !compared[SLOT_VERTICAL] {
            reason[SLOT_VERTICAL] = Some(
                v.iter()
                    .find_map(|c| c.gate)
                    .map_or(NotComparedReason::NoPartner, coverage::reason_of_gate),
            );
        }
        self.coverage.record(t, compared, reason)
    }

    /// The BAHRS sample `b` ready to compare (`rz`: the declination rotation, `d_rad` its angle).
    fn prepare_bahrs(
        &self,
        b: &BahrsSample,
        frozen: bool,
        rz: &UnitQuaternion<f64>,
        mag_gate: Gate,
        d_rad: f64,
    ) -> Prepared {
        let p = &self.params;
        let bq = unmount(
            &(*rz * from_ypr(b.heading_mag_rad, b.pitch_rad, b.roll_rad)),
            &p.mounting_bahrs,
        );
        let mut bg = gates::bahrs_source(b);
        if frozen {
            bg = bg.map(|g| g.or(Some(GateReason::Frozen)));
        }
        bg[2] = bg[2].or(mag_gate);
        let (sn, se, sh) = match b.accuracy_rad {
            Some([n, e, h]) => (n.unwrap_or(0.0), e.unwrap_or(0.0), h.unwrap_or(0.0)),
            None => (
                p.bahrs_default_sigma.tilt_deg * DEG,
                p.bahrs_default_sigma.tilt_deg * DEG,
                p.bahrs_default_sigma.heading_deg * DEG,
            ),
        };
        let (vr, vp) = tilt_variances(sn, se, b.heading_mag_rad + d_rad);
        Prepared {
            values: Some(ypr_to_rph(&bq)),
            heading_mag: Some(b.heading_mag_rad),
            var: [vr, vp, sh * sh],
            gates: bg,
            sigma_ns: b.sigma_ns,
            age_s: None,
            rates: b.rates_radps,
            held_s: 0.0,
        }
    }

    /// The inertial channel at the check of `b` (time `t`): the newest 0x01 against the VN-200
    /// interpolated to the 0x01's own time (see [`super::inertial`]).
    fn compare_inertial(&mut self, b: &BahrsSample, t: i64) -> InertialRecord {
        let p = self.params;
        let horizon = self.horizon_ns(p.bahrs_period_s);
        let vn = match b.inertial.as_ref() {
            Some(i) => {
                let (prev, next) = bracket(&self.vn, i.t_gps_ns, |x| x.0.t_gps_ns);
                let vn_horizon = self.horizon_ns(p.vn200_period_s);
                vn200_at(
                    prev.map(|x| &x.0),
                    next.map(|x| &x.0),
                    i.t_gps_ns,
                    vn_horizon,
                )
            }
            None => Vn200Inertial {
                specific_force_mps2: None,
                angular_rate_radps: None,
                slope_per_s: [0.0; 6],
                step: [0.0; 6],
                sigma_ns: 0.0,
                gate: Some(GateReason::NoData),
            },
        };
        self.inertial
            .update(b.inertial.as_ref(), &vn, t, horizon, self.k_axis, &p)
    }

    /// The VN-200 at `t`: its attitude slerped between the samples around `t` (held from the
    /// last one when none follows), gated (source, stale, frozen, not finite) and unmounted;
    /// whether it is healthy (the magnetic rule needs that); and its vertical channel inputs.
    fn prepare_vn200(&self, t: i64) -> (Prepared, bool, Vn200Vertical) {
        let p = &self.params;
        let horizon = self.horizon_ns(p.vn200_period_s);
        let (prev, next) = bracket(&self.vn, t, |x| x.0.t_gps_ns);
        let Some(&(s0, f0)) = prev else {
            let g = GateReason::NoData;
            let vertical = Vn200Vertical {
                vel_down_mps: None,
                alt_m: None,
                vel_u_mps: None,
                pos_u_m: None,
                gate: Some(g),
            };
            return (Prepared::missing(g), false, vertical);
        };
        let age_ns = t.saturating_sub(s0.t_gps_ns);
        let held_s = if next.is_none() {
            age_ns as f64 * 1e-9
        } else {
            0.0
        };
        let (q, frozen, gate_src, lin) = match next {
            Some(&(s1, f1)) => {
                let span = s1.t_gps_ns.saturating_sub(s0.t_gps_ns) as f64;
                let u = if span > 0.0 {
                    age_ns as f64 / span
                } else {
                    0.0
                };
                let q = interpolate(0.0, &s0.attitude, 1.0, &s1.attitude, u);
                (
                    q,
                    f0 || f1,
                    gates::vn200_source(&s0).or(gates::vn200_source(&s1)),
                    Some((s1, u)),
                )
            }
            None => (s0.attitude, f0, gates::vn200_source(&s0), None),
        };
        let mut gate = gate_src;
        if age_ns > horizon {
            gate = gate.or(Some(GateReason::Stale));
        }
        if frozen {
            gate = gate.or(Some(GateReason::Frozen));
        }
        let q = unmount(&q, &p.mounting_vn200);
        let values = ypr_to_rph(&q);
        if !values.iter().all(|v| v.is_finite()) {
            gate = gate.or(Some(GateReason::NotFinite));
        }
        let sig = s0
            .ypr_sigma_rad
            .filter(|s| s.iter().all(|x| x.is_finite() && *x > 0.0))
            .unwrap_or([
                p.vn200_default_sigma.heading_deg * DEG,
                p.vn200_default_sigma.tilt_deg * DEG,
                p.vn200_default_sigma.tilt_deg * DEG,
            ]);
        let healthy = gates::vn200_healthy(&s0);
        let vertical = vn200_vertical(&s0, lin, age_ns > horizon);
        (
            Prepared {
                values: Some(values),
                heading_mag: None,
                var: [sig[2] * sig[2], sig[1] * sig[1], sig[0] * sig[0]],
                gates: [gate; 3],
                sigma_ns: s0.sigma_ns,
                age_s: Some(age_ns as f64 * 1e-9),
                rates: s0.rates_radps,
                held_s,
            },
            healthy,
            vertical,
        )
    }

    fn prepare_watson(&self, t: i64, rz: &UnitQuaternion<f64>, mag_gate: Gate) -> Prepared {
        let p = &self.params;
        let horizon = self.horizon_ns(p.watson_period_s);
        let (prev, next) = bracket(&self.watson, t, |x| x.0.t_gps_ns);
        let Some(&(s0, f0)) = prev else {
            return Prepared::missing(GateReason::NoData);
        };
        let q_of = |s: &WatsonSample| from_ypr(s.heading_mag_rad, s.pitch_rad, s.roll_rad);
        let age_ns = t.saturating_sub(s0.t_gps_ns);
        let held_s = if next.is_none() {
            age_ns as f64 * 1e-9
        } else {
            0.0
        };
        let (q, frozen, gate_src) = match next {
            Some(&(s1, f1)) => {
                let span = s1.t_gps_ns.saturating_sub(s0.t_gps_ns) as f64;
                let u = if span > 0.0 {
                    age_ns as f64 / span
                } else {
                    0.0
                };
                (
                    interpolate(0.0, &q_of(&s0), 1.0, &q_of(&s1), u),
                    f0 || f1,
                    gates::watson_source(&s0).or(gates::watson_source(&s1)),
                )
            }
            None => (q_of(&s0), f0, gates::watson_source(&s0)),
        };
        let mut gate = gate_src;
        if age_ns > horizon {
            gate = gate.or(Some(GateReason::Stale));
        }
        if frozen {
            gate = gate.or(Some(GateReason::Frozen));
        }
        let (hm, _, _) = to_ypr(&q);
        let q = unmount(&(rz * q), &p.mounting_watson);
        let values = ypr_to_rph(&q);
        if !values.iter().all(|v| v.is_finite()) {
            gate = gate.or(Some(GateReason::NotFinite));
        }
        let (st, sh) = (
            p.watson_sigma.tilt_deg * DEG,
            p.watson_sigma.heading_deg * DEG,
        );
        Prepared {
            values: Some(values),
            heading_mag: Some(wrap_2pi(hm)),
            var: [st * st, st * st, sh * sh],
            gates: [gate, gate, gate.or(mag_gate)],
            sigma_ns: s0.sigma_ns,
            age_s: Some(age_ns as f64 * 1e-9),
            rates: Some(s0.rates_radps),
            held_s,
        }
    }
}

/// The declination's gate on magnetic headings, its rotation about the vertical, and its angle
/// (rad; 0 without a declination).
fn magnetic_frame(decl: Option<Declination>) -> (Gate, UnitQuaternion<f64>, f64) {
    let mag_gate = match decl {
        None => Some(GateReason::NoDeclination),
        Some(d) if d.zone != MagneticZone::Normal => Some(GateReason::MagneticPole),
        Some(_) => None,
    };
    let d_rad = decl.map(|d| d.declination_rad).unwrap_or(0.0);
    (
        mag_gate,
        UnitQuaternion::from_euler_angles(0.0, 0.0, d_rad),
        d_rad,
    )
}

/// The Euler-angle rates roll, pitch, heading, rad/s, for the timing term of the variances: from
/// the body rates of the first unit that has them (BAHRS, VN-200, Watson), at the BAHRS attitude;
/// zero when none has (the timing term then vanishes).
fn timing_rates(units: [&Prepared; 3], b: &BahrsSample) -> [f64; 3] {
    units
        .into_iter()
        .filter_map(|u| u.rates)
        .next()
        .map(|r| euler_rates(r, b.roll_rad, b.pitch_rad))
        .unwrap_or([0.0; 3])
}

/// Whether the BAHRS flags any of its roll, pitch, heading, down velocity or pressure height
/// "integrity risk" in the sample `b` (the record's flag; the gates act on each axis's own health).
fn bahrs_integrity_risk(b: &BahrsSample) -> bool {
    let h = b.health;
    [
        h.roll(),
        h.pitch(),
        h.heading(),
        h.velocity_down(),
        h.pressure_height(),
    ]
    .contains(&vigil_drivers::bahrs::Health::IntegrityRisk)
}

/// The declination as recorded, deg.
fn declination_record(d: Declination) -> DeclinationRecord {
    DeclinationRecord {
        declination_deg: d.declination_rad / DEG,
        sigma_deg: d.sigma_rad / DEG,
        horizontal_nt: d.horizontal_nt,
        zone: d.zone,
    }
}

/// The VN-200's vertical channel inputs at the comparison time: down velocity and altitude
/// interpolated linearly towards the next sample (`next`: it and the fraction of the way to it;
/// held without one), gated by the INS status of the sample before and by staleness.
fn vn200_vertical(
    s0: &Vn200Sample,
    next: Option<(Vn200Sample, f64)>,
    stale: bool,
) -> Vn200Vertical {
    let lerp = |a: Option<f64>, b: Option<f64>| match (a, b, next) {
        (Some(a), Some(b), Some((_, u))) => Some(a + (b - a) * u),
        (Some(a), _, None) => Some(a),
        _ => None,
    };
    let s1 = next.map(|x| x.0);
    let gate = if !s0.ins_status.position_valid() {
        Some(GateReason::InsModeNoAttitude)
    } else if s0.ins_status.imu_error() {
        Some(GateReason::InsErrorBits)
    } else if stale {
        Some(GateReason::Stale)
    } else {
        None
    };
    Vn200Vertical {
        vel_down_mps: lerp(
            s0.vel_ned_mps.map(|v| v[2]),
            s1.and_then(|s| s.vel_ned_mps).map(|v| v[2]),
        ),
        alt_m: lerp(s0.lla.map(|l| l[2]), s1.and_then(|s| s.lla).map(|l| l[2])),
        vel_u_mps: s0.vel_u_mps,
        pos_u_m: s0.pos_u_m,
        gate,
    }
}

/// The vote per axis over the units open on the axis and not isolated on it (`iso_axis`: roll,
/// pitch, heading).
fn vote_units(units: [&Prepared; 3], iso_axis: [Isolation; 3]) -> Voted {
    let names = [Unit::Bahrs, Unit::Vn200, Unit::Watson];
    let axis = |ai: usize| {
        // On the stack: this runs for every prompt output (the VN-200's rate).
        let mut cands = [(Unit::Bahrs, 0.0); 3];
        let mut n = 0;
        for (u, name) in units.iter().zip(names) {
            if u.gates[ai].is_none()
                && iso_axis[ai] != Isolation::Isolated(name)
                && let Some(x) = u.values
            {
                cands[n] = (name, x[ai]);
                n += 1;
            }
        }
        vote(&cands[..n], ai == 2)
    };
    Voted {
        roll: axis(0),
        pitch: axis(1),
        heading: axis(2),
    }
}

/// Index of a unit in the coverage slots (and in `[bahrs, vn200, watson]` arrays).
fn unit_slot(u: Unit) -> usize {
    match u {
        Unit::Bahrs => 0,
        Unit::Vn200 => 1,
        Unit::Watson => 2,
    }
}

fn not_compared_pair() -> AxisPair {
    AxisPair {
        verdict: PairVerdict::NotCompared,
        comparison: None,
        stat_exceeded: false,
        fixed_exceeded: false,
        stat_fault: false,
        fixed_fault: false,
        cusum: 0.0,
    }
}

/// Roll, pitch, true heading in [0, 2 pi) of an attitude, rad.
fn ypr_to_rph(q: &UnitQuaternion<f64>) -> [f64; 3] {
    let (y, p, r) = to_ypr(q);
    [r, p, wrap_2pi(y)]
}

fn unit_values(u: &Prepared) -> UnitValues {
    UnitValues {
        roll_deg: u.values.map(|v| v[0] / DEG),
        pitch_deg: u.values.map(|v| v[1] / DEG),
        heading_deg: u.values.map(|v| v[2] / DEG),
        heading_mag_deg: u.heading_mag.map(|h| h / DEG),
        sigma_deg: u.values.map(|_| u.var.map(|v| v.sqrt() / DEG)),
        age_s: u.age_s,
        gates: AxisGates {
            roll: u.gates[0],
            pitch: u.gates[1],
            heading: u.gates[2],
        },
    }
}

/// The last element at or before `t` and the first after it.
fn bracket<T>(h: &VecDeque<T>, t: i64, time: impl Fn(&T) -> i64) -> (Option<&T>, Option<&T>) {
    let i = h.partition_point(|x| time(x) <= t);
    (i.checked_sub(1).and_then(|j| h.get(j)), h.get(i))
}

/// Inserts keeping time order (samples normally arrive in order: O(1)); bounded.
fn push_sorted<T>(h: &mut VecDeque<T>, x: T, time: impl Fn(&T) -> i64) {
    let t = time(&x);
    let i = h.partition_point(|y| time(y) <= t);
    h.insert(i, x);
    while h.len() > MAX_HISTORY {
        h.pop_front();
    }
}

/// Drops samples no longer needed once comparisons reached `t` (keeps the last one at or before).
fn prune<T>(h: &mut VecDeque<T>, t: i64, time: impl Fn(&T) -> i64) {
    while h.get(1).is_some_and(|x| time(x) <= t) {
        h.pop_front();
    }
}
