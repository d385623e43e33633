//! The vertical channel (issue 8, "Tests, persistence, isolation"): the BAHRS downward velocity
//! against the VN-200 NED down velocity, and the BAHRS pressure-height rate against the VN-200
//! altitude rate, at each BAHRS sample time.
//!
//! Both rates are differenced over the same pair of times (the current BAHRS sample and the one
//! about `rate_window_s` earlier), so timing cancels. Each comparison has the statistical detector
//! (`|z| / k`, `k` from the false-alarm probability) and the same persistence as the attitude axes.
//! Decision: there is no certified fixed limit for these, so only the statistical detector runs.
//!
//! Issue 25 point 6, the third opinion ([`ThirdOpinion`]): the TT-Multi-RF GNSS altitude,
//! differenced over [`TT_RATE_WINDOW_S`], against the BAHRS pressure-height rate and the VN-200
//! altitude rate over the same two epochs. With a BAHRS-VN-200 miscompare, the unit that
//! disagrees with both others is isolated ([`isolate_vertical`]); without the TT GNSS (absent,
//! no fix, stale, window filling) the record says why, and nothing is isolated by it.

use std::collections::VecDeque;

use serde::Serialize;
use vigil_drivers::bahrs::Health;

use super::gates::{Gate, GateReason};
use super::isolation::PairVerdict;
use super::isolation::Unit;
use super::params::CheckParams;
use super::persistence::{Persistence, PersistenceParams};
use super::samples::BahrsSample;

/// The VN-200's vertical state interpolated to the BAHRS sample time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Vn200Vertical {
    /// NED down velocity, m/s.
    pub vel_down_mps: Option<f64>,
    /// Height above the ellipsoid, m.
    pub alt_m: Option<f64>,
    /// VelU, m/s.
    pub vel_u_mps: Option<f64>,
    /// PosU, m.
    pub pos_u_m: Option<f64>,
    /// Gate of the VN-200 velocity and position (None: valid).
    pub gate: Gate,
}

/// One vertical comparison.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VerticalComparison {
    /// BAHRS value, m/s (down positive for the velocity, up positive for the height rate).
    pub bahrs_mps: Option<f64>,
    /// VN-200 value, m/s, same sign convention.
    pub vn200_mps: Option<f64>,
    /// Difference BAHRS minus VN-200, m/s.
    pub diff_mps: Option<f64>,
    /// Combined 1-sigma, m/s.
    pub sigma_mps: Option<f64>,
    /// Statistical test ratio (1 at the threshold).
    pub stat_ratio: Option<f64>,
    /// Persistent verdict.
    pub verdict: PairVerdict,
    /// Why not compared.
    pub gate: Gate,
}

/// Both vertical comparisons of one sample.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct VerticalRecord {
    /// Downward velocity.
    pub velocity_down: VerticalComparison,
    /// Height rate (pressure height rate against altitude rate), up positive.
    pub height_rate: VerticalComparison,
    /// BAHRS health of the pressure height and the downward velocity of the sample (issue 25
    /// point 6: published with the comparisons); `None` before the first sample.
    pub bahrs_health: Option<[Health; 2]>,
    /// Issue 25 point 6: the TT-Multi-RF GNSS altitude as a third opinion on the height rate.
    pub third: ThirdOpinion,
}

/// State of the vertical channel.
#[derive(Debug, Clone, Default)]
pub struct VerticalChannel {
    history: VecDeque<(i64, f64, f64)>,
    velocity: Persistence,
    rate: Persistence,
    /// TT-Multi-RF GNSS epochs: GPS ns, altitude m (`None` without a fix).
    tt: VecDeque<(i64, Option<f64>)>,
    /// BAHRS pressure height and VN-200 altitude (each when usable) at BAHRS times, m.
    long: VecDeque<Heights>,
    tt_bahrs: Persistence,
    tt_vn: Persistence,
    /// The third opinion computed at the newest TT epoch (its GPS ns).
    last_third: Option<(i64, ThirdOpinion)>,
}

fn health_gate(h: Health) -> Gate {
    match h {
        Health::Safe => None,
        Health::Unavailable => Some(GateReason::HealthUnavailable),
        Health::IntegrityRisk => Some(GateReason::HealthIntegrityRisk),
        Health::Undefined => Some(GateReason::HealthUndefined),
    }
}

impl VerticalChannel {
    /// Compares at the BAHRS sample `b`; `dt_s` since the previous comparison, `k` the per-axis
    /// threshold.
    pub fn update(
        &mut self,
        b: &BahrsSample,
        vn: &Vn200Vertical,
        dt_s: f64,
        k: f64,
        p: &CheckParams,
    ) -> VerticalRecord {
        let vp = &p.vertical;
        let pp = &p.persistence;
        // Downward velocity.
        let gate_v = health_gate(b.health.velocity_down())
            .or(vn.gate)
            .or(vn.vel_down_mps.is_none().then_some(GateReason::NoData));
        let velocity_down = match (gate_v, vn.vel_down_mps) {
            (None, Some(v)) => {
                let s_vn = vn.vel_u_mps.unwrap_or(vp.vn200_velocity_sigma_mps);
                let sigma = (vp.bahrs_velocity_sigma_mps.powi(2) + s_vn.powi(2)).sqrt();
                VerticalComparison::compared(
                    b.velocity_down_mps,
                    v,
                    sigma,
                    k,
                    &mut self.velocity,
                    dt_s,
                    pp,
                )
            }
            _ => not_compared(Some(b.velocity_down_mps), vn.vel_down_mps, gate_v),
        };
        // Height rates over the window, from pairs recorded when both heights were usable.
        let gate_h = health_gate(b.health.pressure_height())
            .or(vn.gate)
            .or(vn.alt_m.is_none().then_some(GateReason::NoData));
        let height_rate = match (gate_h, vn.alt_m) {
            (None, Some(alt)) => {
                self.history
                    .push_back((b.t_gps_ns, b.pressure_height_m, alt));
                let window_ns = (vp.rate_window_s * 1e9) as i64;
                while self
                    .history
                    .get(1)
                    .is_some_and(|h| b.t_gps_ns.saturating_sub(h.0) >= window_ns)
                {
                    self.history.pop_front();
                }
                while self.history.len() > 4096 {
                    self.history.pop_front();
                }
                match self.history.front() {
                    Some(&(t0, h0, a0))
                        if b.t_gps_ns.saturating_sub(t0) as f64 >= 0.8 * window_ns as f64 =>
                    {
                        let span = b.t_gps_ns.saturating_sub(t0) as f64 * 1e-9;
                        let rb = (b.pressure_height_m - h0) / span;
                        let rv = (alt - a0) / span;
                        // Issue 25: the VN-200 states its own position uncertainty (PosU); a
                        // rate differenced over `span` has at least sqrt(2) PosU / span when
                        // the two ends' errors are independent. Real GNSS errors are correlated
                        // over a second, so this is conservative; the simulator draws them
                        // independently per sample, and with the fixed 0.3 m/s alone the
                        // nominal flight failed this comparison within 4 s (a false alert).
                        let s_vn = vn.pos_u_m.map_or(vp.vn200_alt_rate_sigma_mps, |u| {
                            vp.vn200_alt_rate_sigma_mps
                                .max(std::f64::consts::SQRT_2 * u / span)
                        });
                        let sigma = (vp.pressure_rate_sigma_mps.powi(2) + s_vn.powi(2)).sqrt();
                        VerticalComparison::compared(rb, rv, sigma, k, &mut self.rate, dt_s, pp)
                    }
                    _ => not_compared(None, None, Some(GateReason::NoData)),
                }
            }
            _ => {
                // A gap breaks the rate: start again when both are usable.
                self.history.clear();
                not_compared(None, None, gate_h)
            }
        };
        let hb = health_gate(b.health.pressure_height())
            .is_none()
            .then_some(b.pressure_height_m);
        let hv = vn.alt_m.filter(|_| vn.gate.is_none());
        self.record_heights(b.t_gps_ns, hb, hv);
        let fail =
            velocity_down.verdict == PairVerdict::Fail || height_rate.verdict == PairVerdict::Fail;
        let third = self.third_opinion(b.t_gps_ns, vn.pos_u_m, k, p, fail);
        VerticalRecord {
            velocity_down,
            height_rate,
            bahrs_health: Some([b.health.pressure_height(), b.health.velocity_down()]),
            third,
        }
    }
}

impl VerticalChannel {
    /// Adds one TT-Multi-RF GNSS epoch: its GPS time, ns, and its altitude above the ellipsoid,
    /// m (`None` without a fix). Epochs not after the newest are ignored.
    pub fn push_tt_gnss(&mut self, t_gps_ns: i64, alt_m: Option<f64>) {
        if self.tt.back().is_some_and(|e| e.0 >= t_gps_ns) {
            return;
        }
        self.tt
            .push_back((t_gps_ns, alt_m.filter(|a| a.is_finite())));
        while self.tt.len() > TT_HISTORY {
            self.tt.pop_front();
        }
    }

    /// Records the heights of the BAHRS sample at `t` for the third opinion's window.
    fn record_heights(&mut self, t: i64, bahrs_m: Option<f64>, vn200_m: Option<f64>) {
        if self.long.back().is_some_and(|e| e.0 >= t) {
            return;
        }
        self.long.push_back((t, bahrs_m, vn200_m));
        let keep_ns = ((1.2 * TT_RATE_WINDOW_S + TT_STALE_S + 1.0) * 1e9) as i64;
        while self
            .long
            .front()
            .is_some_and(|e| t.saturating_sub(e.0) > keep_ns)
            || self.long.len() > 8192
        {
            self.long.pop_front();
        }
    }

    fn tt_not_compared(&mut self, why: TtNotCompared) -> ThirdOpinion {
        self.tt_bahrs.reset();
        self.tt_vn.reset();
        self.last_third = None;
        ThirdOpinion::absent(why)
    }

    /// The third opinion at the comparison time `t`: computed once per TT-Multi-RF epoch (its
    /// persistence runs at the epoch rate, 1 Hz, since the TT rate changes only then), its
    /// isolation re-evaluated with the BAHRS-VN-200 verdict of every sample.
    fn third_opinion(
        &mut self,
        t: i64,
        vn_pos_u_m: Option<f64>,
        k: f64,
        p: &CheckParams,
        bahrs_vn200_fail: bool,
    ) -> ThirdOpinion {
        let Some(i1) = self.tt.iter().rposition(|e| e.0 <= t) else {
            return self.tt_not_compared(TtNotCompared::Absent);
        };
        let (t1, a1) = self.tt[i1];
        if t.saturating_sub(t1) as f64 * 1e-9 > TT_STALE_S {
            return self.tt_not_compared(TtNotCompared::Stale);
        }
        let Some(a1) = a1 else {
            return self.tt_not_compared(TtNotCompared::NoFix);
        };
        if let Some((te, mut r)) = self.last_third
            && te == t1
        {
            r.isolated = isolate_vertical(
                bahrs_vn200_fail,
                r.bahrs_vs_tt.verdict,
                r.vn200_vs_tt.verdict,
            );
            return r;
        }
        // The start: the epoch about one window earlier, every epoch since with a fix (an epoch
        // without a fix breaks the window; it fills again).
        let target = t1 - (TT_RATE_WINDOW_S * 1e9) as i64;
        let mut start = None;
        for j in (0..i1).rev() {
            let (tj, aj) = self.tt[j];
            let Some(aj) = aj else { break };
            if tj <= target + 500_000_000 {
                start = Some((tj, aj));
                break;
            }
        }
        // The older end is at least the window less 0.5 s back by its choice above; a gap in
        // the epochs can make it older, up to 1.2 windows.
        let Some((t0, a0)) =
            start.filter(|(t0, _)| (t1 - t0) as f64 * 1e-9 <= 1.2 * TT_RATE_WINDOW_S)
        else {
            return self.tt_not_compared(TtNotCompared::WindowFilling);
        };
        let span = (t1 - t0) as f64 * 1e-9;
        let dt_s = self
            .last_third
            .map_or(1.0, |(te, _)| (t1 - te) as f64 * 1e-9);
        let vp = &p.vertical;
        let tt_rate = (a1 - a0) / span;
        let sigma_tt = std::f64::consts::SQRT_2 * TT_ALT_SIGMA_M / span;
        // The BAHRS and VN-200 rate sigmas are stated for `rate_window_s`; white height noise
        // scales them by window / span. The VN-200's own PosU bounds its from below, as in the
        // 1 s comparison.
        let scale = vp.rate_window_s / span;
        let sigma_b = vp.pressure_rate_sigma_mps * scale;
        let sigma_v = vn_pos_u_m.map_or(vp.vn200_alt_rate_sigma_mps * scale, |u| {
            (vp.vn200_alt_rate_sigma_mps * scale).max(std::f64::consts::SQRT_2 * u / span)
        });
        // Two epochs (2 s at 1 Hz) over the limit declare; two under it clear.
        let pp = PersistenceParams {
            declare_after_s: 2.0,
            ..p.persistence
        };
        let rate_of = |pick: fn(&Heights) -> Option<f64>| {
            Some((height_at(&self.long, t1, pick)? - height_at(&self.long, t0, pick)?) / span)
        };
        let rb = rate_of(|e| e.1);
        let rv = rate_of(|e| e.2);
        if rb.is_none() && rv.is_none() {
            return self.tt_not_compared(TtNotCompared::NoPartner);
        }
        let compare = |per: &mut Persistence, r: Option<f64>, s: f64| match r {
            Some(r) => {
                let sigma = (s * s + sigma_tt * sigma_tt).sqrt();
                VerticalComparison::compared(r, tt_rate, sigma, k, per, dt_s, &pp)
            }
            None => {
                per.reset();
                not_compared(None, Some(tt_rate), Some(GateReason::NoData))
            }
        };
        let bahrs_vs_tt = compare(&mut self.tt_bahrs, rb, sigma_b);
        let vn200_vs_tt = compare(&mut self.tt_vn, rv, sigma_v);
        let r = ThirdOpinion {
            tt_rate_mps: Some(tt_rate),
            span_s: Some(span),
            bahrs_vs_tt,
            vn200_vs_tt,
            not_compared: None,
            isolated: isolate_vertical(bahrs_vn200_fail, bahrs_vs_tt.verdict, vn200_vs_tt.verdict),
        };
        self.last_third = Some((t1, r));
        r
    }
}

impl VerticalComparison {
    /// The comparison of `a` with `b` (m/s) whose combined 1-sigma is `sigma`: the difference
    /// `a - b`, its test ratio (1 at `k` sigmas), and the verdict `persistence` holds after
    /// taking it.
    fn compared(
        a: f64,
        b: f64,
        sigma: f64,
        k: f64,
        persistence: &mut Persistence,
        dt_s: f64,
        pp: &PersistenceParams,
    ) -> Self {
        let j = persistence.judge((a, b), sigma, k, dt_s, pp);
        Self {
            bahrs_mps: Some(a),
            vn200_mps: Some(b),
            diff_mps: Some(j.diff),
            sigma_mps: Some(sigma),
            stat_ratio: Some(j.ratio),
            verdict: j.verdict,
            gate: None,
        }
    }
}

fn not_compared(bahrs: Option<f64>, vn: Option<f64>, gate: Gate) -> VerticalComparison {
    VerticalComparison {
        bahrs_mps: bahrs,
        vn200_mps: vn,
        diff_mps: None,
        sigma_mps: None,
        stat_ratio: None,
        verdict: PairVerdict::NotCompared,
        gate,
    }
}

// --- issue 25 point 6: the TT-Multi-RF GNSS altitude as a third opinion on the height rate ---

/// Window over which the TT-Multi-RF GNSS altitude (and, over the same ends, the BAHRS pressure
/// height and the VN-200 altitude) is differenced, s.
///
/// Decision: the GGA / JSON altitude of a stand-alone receiver has a vertical 1-sigma of about
/// 4 m ([`TT_ALT_SIGMA_M`]); differenced over `W` seconds its rate has a 1-sigma of
/// `sqrt(2) x 4 / W` m/s when the two ends' errors are independent (the simulator draws them
/// independently every second; a real receiver's errors are correlated over seconds, so the
/// figure is conservative). At 20 s that is 0.28 m/s, small enough to tell a 2 m/s climb from a
/// frozen pressure height (k = 4.4 sigma is 1.25 m/s); at the 1 s of the BAHRS / VN-200
/// comparison it would be 5.7 m/s, useless.
pub const TT_RATE_WINDOW_S: f64 = 20.0;
/// Vertical 1-sigma of one TT-Multi-RF GNSS altitude, m. Neither GGA (HDOP only) nor the
/// module's JSON without `acc` states it; 4 m is the usual stand-alone GPS figure (the GPS SPS
/// performance standard's vertical 95 % bound of about 8 m over 1.96) and the simulator's value.
pub const TT_ALT_SIGMA_M: f64 = 4.0;
/// A TT-Multi-RF GNSS epoch older than this at the comparison time is stale, s (the GNSS section
/// and GGA come once per second: two epochs missed).
pub const TT_STALE_S: f64 = 2.5;
/// Heights at one BAHRS sample time: GPS ns, BAHRS pressure height m and VN-200 altitude m,
/// each when usable.
type Heights = (i64, Option<f64>, Option<f64>);
/// TT-Multi-RF epochs kept (1 Hz: about a minute, three windows).
const TT_HISTORY: usize = 64;

/// Why the TT-Multi-RF GNSS third opinion was not compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TtNotCompared {
    /// No TT-Multi-RF GNSS epoch has been received (no module, GNSS section off).
    Absent,
    /// The newest epoch has no fix.
    NoFix,
    /// The newest epoch is older than [`TT_STALE_S`].
    Stale,
    /// Fixes do not yet span the window (start, or after a gap in the fixes).
    WindowFilling,
    /// Neither the BAHRS pressure height nor the VN-200 altitude is usable at both window ends.
    NoPartner,
}

/// The TT-Multi-RF GNSS altitude rate against the BAHRS pressure-height rate and the VN-200
/// altitude rate over the same window, and the isolation it allows.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ThirdOpinion {
    /// TT-Multi-RF GNSS altitude rate over the window, m/s up.
    pub tt_rate_mps: Option<f64>,
    /// Span of the window actually used, s.
    pub span_s: Option<f64>,
    /// BAHRS pressure-height rate against the TT rate (`bahrs_mps` BAHRS, `vn200_mps` the TT
    /// rate), m/s up.
    pub bahrs_vs_tt: VerticalComparison,
    /// VN-200 altitude rate against the TT rate (`bahrs_mps` the VN-200, `vn200_mps` the TT
    /// rate), m/s up.
    pub vn200_vs_tt: VerticalComparison,
    /// Why the third opinion was not compared; `None` when it was.
    pub not_compared: Option<TtNotCompared>,
    /// The unit a BAHRS-VN-200 vertical miscompare is isolated to by the third opinion: the one
    /// that disagrees with both others. `None` without a miscompare, without the third opinion
    /// (the premise-based attribution to the BAHRS then stands, stated by the monitor), or when
    /// the vote does not single one out.
    pub isolated: Option<Unit>,
}

impl ThirdOpinion {
    /// Not compared, for the reason `why`.
    pub fn absent(why: TtNotCompared) -> Self {
        Self {
            tt_rate_mps: None,
            span_s: None,
            bahrs_vs_tt: not_compared(None, None, None),
            vn200_vs_tt: not_compared(None, None, None),
            not_compared: Some(why),
            isolated: None,
        }
    }
}

/// The isolation rule of the third opinion: with a BAHRS-VN-200 miscompare, the unit that
/// disagrees with both others; otherwise none.
pub fn isolate_vertical(
    bahrs_vn200_fail: bool,
    bahrs_tt: PairVerdict,
    vn_tt: PairVerdict,
) -> Option<Unit> {
    use PairVerdict::{Fail, Pass};
    match (bahrs_vn200_fail, bahrs_tt, vn_tt) {
        (true, Fail, Pass) => Some(Unit::Bahrs),
        (true, Pass, Fail) => Some(Unit::Vn200),
        _ => None,
    }
}

/// Linear interpolation of a height in the BAHRS-time history at `t` (bracketed by usable
/// samples at most 0.2 s apart); `pick` selects the BAHRS or the VN-200 height.
fn height_at(hist: &VecDeque<Heights>, t: i64, pick: fn(&Heights) -> Option<f64>) -> Option<f64> {
    let i = hist.partition_point(|e| e.0 < t);
    let after = hist.get(i)?;
    let (ta, ha) = (after.0, pick(after)?);
    if ta == t {
        return Some(ha);
    }
    let before = hist.get(i.checked_sub(1)?)?;
    let (tb, hb) = (before.0, pick(before)?);
    if ta - tb > 200_000_000 {
        return None;
    }
    Some(hb + (ha - hb) * (t - tb) as f64 / (ta - tb) as f64)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vigil_drivers::bahrs::NavigationHealth;

    fn b(t_s: f64, h: f64, vd: f64) -> BahrsSample {
        use Health::Safe;
        BahrsSample {
            t_gps_ns: (t_s * 1e9) as i64,
            sigma_ns: 0.0,
            roll_rad: 0.0,
            pitch_rad: 0.0,
            heading_mag_rad: 0.0,
            velocity_down_mps: vd,
            pressure_height_m: h,
            health: NavigationHealth::new(Safe, Safe, Safe, Safe, Safe),
            accuracy_rad: None,
            rates_radps: None,
            inertial: None,
        }
    }

    fn vn(alt: f64, vd: f64) -> Vn200Vertical {
        Vn200Vertical {
            vel_down_mps: Some(vd),
            alt_m: Some(alt),
            vel_u_mps: None,
            pos_u_m: None,
            gate: None,
        }
    }

    #[test]
    fn climb_agrees_and_a_wrong_pressure_rate_fails() {
        let p = CheckParams::default();
        let k = p.axis_threshold();
        let mut ch = VerticalChannel::default();
        // Climbing at 2 m/s, both agree: 50 Hz for 3 s.
        let mut last = None;
        for i in 0..150 {
            let t = i as f64 * 0.02;
            last = Some(ch.update(
                &b(t, 100.0 + 2.0 * t, -2.0),
                &vn(500.0 + 2.0 * t, -2.0),
                0.02,
                k,
                &p,
            ));
        }
        let r = last.unwrap();
        assert_eq!(r.velocity_down.verdict, PairVerdict::Pass);
        assert_eq!(r.height_rate.verdict, PairVerdict::Pass);
        // Over 1.0 s (window): pressure rate 2 m/s exactly, difference 0.
        assert!((r.height_rate.bahrs_mps.unwrap() - 2.0).abs() < 1e-9);
        assert!(r.height_rate.diff_mps.unwrap().abs() < 1e-9);
        // sigma = sqrt(0.7^2 + 0.3^2) = 0.76158.
        assert!((r.height_rate.sigma_mps.unwrap() - 0.761_577).abs() < 1e-6);
        // Now the BAHRS pressure height climbs at 8 m/s while the VN-200 climbs at 2: the rate
        // difference 6 m/s is 7.9 sigma; declared within about 1 s + the 1 s window.
        let mut failed_at = None;
        for i in 150..400 {
            let t = i as f64 * 0.02;
            let hb = 100.0 + 2.0 * 3.0 + 8.0 * (t - 3.0);
            let r = ch.update(&b(t, hb, -2.0), &vn(500.0 + 2.0 * t, -2.0), 0.02, k, &p);
            if r.height_rate.verdict == PairVerdict::Fail && failed_at.is_none() {
                failed_at = Some(t);
            }
            assert_eq!(r.velocity_down.verdict, PairVerdict::Pass);
        }
        let t = failed_at.expect("height-rate fault");
        assert!(t > 3.5 && t < 5.5, "{t}");
    }

    #[test]
    fn gates_close_on_health_and_invalid_vn200() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let mut s = b(0.0, 0.0, 0.0);
        s.health = NavigationHealth::new(
            Health::IntegrityRisk,
            Health::Unavailable,
            Health::Safe,
            Health::Safe,
            Health::Safe,
        );
        let r = ch.update(&s, &vn(0.0, 0.0), 0.02, 4.42, &p);
        assert_eq!(r.velocity_down.gate, Some(GateReason::HealthUnavailable));
        assert_eq!(r.height_rate.gate, Some(GateReason::HealthIntegrityRisk));
        let mut v = vn(0.0, 0.0);
        v.gate = Some(GateReason::InsModeNoAttitude);
        let r = ch.update(&b(0.02, 0.0, 0.0), &v, 0.02, 4.42, &p);
        assert_eq!(r.velocity_down.verdict, PairVerdict::NotCompared);
        assert_eq!(r.height_rate.gate, Some(GateReason::InsModeNoAttitude));
    }
    /// Runs 50 Hz BAHRS samples and 1 Hz TT epochs (exact altitudes, no noise) from `from_s`
    /// to `to_s`; `bahrs(t)` gives (pressure height, down velocity), `vn(t)` (altitude, down
    /// velocity), `tt(t)` the TT altitude (None: no epoch). Returns the records at whole seconds.
    fn fly(
        ch: &mut VerticalChannel,
        range: (f64, f64),
        bahrs: &dyn Fn(f64) -> (f64, f64),
        vnf: &dyn Fn(f64) -> (f64, f64),
        tt: &dyn Fn(f64) -> Option<Option<f64>>,
    ) -> Vec<(f64, VerticalRecord)> {
        let p = CheckParams::default();
        let k = p.axis_threshold();
        let mut out = Vec::new();
        let n0 = (range.0 * 50.0).round() as i64;
        let n1 = (range.1 * 50.0).round() as i64;
        for i in n0..n1 {
            let t = i as f64 * 0.02;
            if i % 50 == 0
                && let Some(a) = tt(t)
            {
                ch.push_tt_gnss((t * 1e9).round() as i64, a);
            }
            let (h, vd) = bahrs(t);
            let (alt, vvd) = vnf(t);
            let r = ch.update(&b(t, h, vd), &vn(alt, vvd), 0.02, k, &p);
            if i % 50 == 0 {
                out.push((t, r));
            }
        }
        out
    }

    /// The hand-derived sigma of the third opinion's BAHRS-TT difference over 20 s:
    /// sqrt((0.7 x 1 / 20)^2 + (sqrt 2 x 4 / 20)^2) = sqrt(0.035^2 + 0.28284^2) = 0.28500 m/s.
    const SIGMA_BT: f64 = 0.285_00;

    /// Climbing at 2 m/s; the BAHRS pressure port blocks at 30 s (height frozen, down velocity
    /// 0): the BAHRS-VN-200 comparison fails within seconds, and the third opinion isolates the
    /// BAHRS when the BAHRS-TT rate difference, growing 2 m/s / 20 s = 0.1 m/s each second,
    /// exceeds k sigma (k = 4.42 at the default false-alarm probability: 1.26 m/s, 12.6 s) and
    /// has persisted for two epochs. The VN-200-TT comparison passes throughout.
    #[test]
    fn third_opinion_isolates_a_frozen_pressure_height_to_the_bahrs() {
        let mut ch = VerticalChannel::default();
        let h = |t: f64| 100.0 + 2.0 * t.min(30.0);
        let rs = fly(
            &mut ch,
            (0.0, 60.0),
            &|t| (h(t), if t < 30.0 { -2.0 } else { 0.0 }),
            &|t| (500.0 + 2.0 * t, -2.0),
            &|t| Some(Some(520.0 + 2.0 * t)),
        );
        // Before 20 s the window is filling; then compared, agreeing, nothing isolated.
        let r5 = rs.iter().find(|(t, _)| *t == 5.0).unwrap().1;
        assert_eq!(r5.third.not_compared, Some(TtNotCompared::WindowFilling));
        let r25 = rs.iter().find(|(t, _)| *t == 25.0).unwrap().1;
        assert_eq!(r25.third.not_compared, None);
        assert!((r25.third.tt_rate_mps.unwrap() - 2.0).abs() < 1e-9);
        assert!((r25.third.bahrs_vs_tt.sigma_mps.unwrap() - SIGMA_BT).abs() < 1e-5);
        assert_eq!(r25.third.bahrs_vs_tt.verdict, PairVerdict::Pass);
        assert_eq!(r25.third.isolated, None);
        let k = CheckParams::default().axis_threshold();
        let crossing_s = k * SIGMA_BT / 0.1;
        let first = rs
            .iter()
            .find(|(_, r)| r.third.isolated.is_some())
            .expect("isolated");
        assert_eq!(first.1.third.isolated, Some(Unit::Bahrs));
        let after = first.0 - 30.0;
        // Crossing, then the filter (alpha 2/3 per epoch) and two epochs of persistence.
        assert!(
            after > crossing_s && after < crossing_s + 4.0,
            "{after} vs {crossing_s}"
        );
        for (_, r) in &rs {
            assert_ne!(r.third.vn200_vs_tt.verdict, PairVerdict::Fail);
            assert_ne!(r.third.isolated, Some(Unit::Vn200));
        }
    }

    /// The VN-200 altitude and down velocity climb at 5 m/s from 30 s while the BAHRS and the
    /// TT GNSS climb at 2: the VN-200 disagrees with both and is isolated; the BAHRS-TT
    /// comparison passes.
    #[test]
    fn third_opinion_isolates_a_wrong_vn200_vertical_to_the_vn200() {
        let mut ch = VerticalChannel::default();
        let alt = |t: f64| 500.0 + 2.0 * t + 3.0 * (t - 30.0).max(0.0);
        let rs = fly(
            &mut ch,
            (0.0, 60.0),
            &|t| (100.0 + 2.0 * t, -2.0),
            &|t| (alt(t), if t < 30.0 { -2.0 } else { -5.0 }),
            &|t| Some(Some(520.0 + 2.0 * t)),
        );
        let isolated: Vec<_> = rs
            .iter()
            .filter_map(|(t, r)| r.third.isolated.map(|u| (*t, u)))
            .collect();
        assert!(!isolated.is_empty());
        assert!(
            isolated.iter().all(|(t, u)| *u == Unit::Vn200 && *t > 30.0),
            "{isolated:?}"
        );
        for (_, r) in &rs {
            assert_ne!(r.third.bahrs_vs_tt.verdict, PairVerdict::Fail);
        }
    }

    /// Without TT GNSS epochs the third opinion says "absent"; an epoch without a fix says "no
    /// fix"; epochs that stop say "stale" after 2.5 s; and none of these isolates a unit, even
    /// with the BAHRS-VN-200 comparison failing (the premise-based attribution stands).
    #[test]
    fn third_opinion_not_compared_says_why() {
        let frozen = |t: f64| (100.0 + 2.0 * t.min(5.0), if t < 5.0 { -2.0 } else { 0.0 });
        let climb = |t: f64| (500.0 + 2.0 * t, -2.0);
        let mut ch = VerticalChannel::default();
        let rs = fly(&mut ch, (0.0, 15.0), &frozen, &climb, &|_| None);
        let last = rs.last().unwrap().1;
        assert_eq!(last.velocity_down.verdict, PairVerdict::Fail);
        assert_eq!(last.third.not_compared, Some(TtNotCompared::Absent));
        assert_eq!(last.third.isolated, None);
        assert_eq!(last.third.tt_rate_mps, None);
        let mut ch = VerticalChannel::default();
        let rs = fly(&mut ch, (0.0, 30.0), &climb, &climb, &|t| {
            Some(Some(520.0 + 2.0 * t))
        });
        assert_eq!(rs.last().unwrap().1.third.not_compared, None);
        let rs = fly(&mut ch, (30.0, 32.0), &climb, &climb, &|_| Some(None));
        assert_eq!(
            rs.last().unwrap().1.third.not_compared,
            Some(TtNotCompared::NoFix)
        );
        // Fixes again: the no-fix epochs broke the window, which fills again for 20 s.
        let rs = fly(&mut ch, (32.0, 40.0), &climb, &climb, &|t| {
            Some(Some(520.0 + 2.0 * t))
        });
        assert_eq!(
            rs.last().unwrap().1.third.not_compared,
            Some(TtNotCompared::WindowFilling)
        );
        let rs = fly(&mut ch, (40.0, 62.0), &climb, &climb, &|t| {
            Some(Some(520.0 + 2.0 * t))
        });
        assert_eq!(rs.last().unwrap().1.third.not_compared, None);
        // No more epochs: the newest (61 s) is stale after 63.5 s.
        let rs = fly(&mut ch, (62.0, 64.0), &climb, &climb, &|_| None);
        let at = |x: f64| {
            rs.iter()
                .find(|(t, _)| *t == x)
                .unwrap()
                .1
                .third
                .not_compared
        };
        assert_eq!(at(63.0), None);
        let rs = fly(&mut ch, (64.0, 65.0), &climb, &climb, &|_| None);
        assert_eq!(rs[0].1.third.not_compared, Some(TtNotCompared::Stale));
    }

    /// A BAHRS sample at the exact GPS time `t_ns` (ns): pressure height `h` m, down velocity
    /// `vd` m/s, all health safe.
    fn b_ns(t_ns: i64, h: f64, vd: f64) -> BahrsSample {
        BahrsSample {
            t_gps_ns: t_ns,
            ..b(0.0, h, vd)
        }
    }

    /// The down-velocity comparison's sigma is the root sum square of the BAHRS sigma and the
    /// VN-200's (its VelU when stated, else the table's default), params.rs defaults 0.5 and 0.2.
    #[test]
    fn velocity_sigma_is_the_root_sum_square_of_both_units_sigmas() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        // sqrt(0.5^2 + 0.2^2) = sqrt(0.29) = 0.538516.
        let r = ch.update(&b(0.0, 0.0, 1.0), &vn(0.0, 0.0), 0.02, 4.42, &p);
        assert!((r.velocity_down.sigma_mps.unwrap() - 0.538_516).abs() < 1e-6);
        assert_eq!(r.velocity_down.diff_mps, Some(1.0));
        // VelU 0.4 m/s stated: sqrt(0.5^2 + 0.4^2) = sqrt(0.41) = 0.640312.
        let mut v = vn(0.0, 0.0);
        v.vel_u_mps = Some(0.4);
        let r = ch.update(&b(0.02, 0.0, 1.0), &v, 0.02, 4.42, &p);
        assert!((r.velocity_down.sigma_mps.unwrap() - 0.640_312).abs() < 1e-6);
    }

    /// The height rates need a span of at least 0.8 window (0.8 s at the default 1 s): at 0.7 s
    /// not compared, at 0.8 s compared, each rate divided by the 0.8 s span, and the VN-200 rate
    /// sigma bounded below by its PosU: sqrt 2 x PosU / span.
    #[test]
    fn height_rate_starts_at_0_8_window_over_the_actual_span_with_the_posu_bound() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let mut v = vn(0.0, 0.0);
        v.pos_u_m = Some(2.0);
        let mut at = |ms: i64| {
            let t = ms as f64 * 1e-3;
            // BAHRS climbs at 2 m/s, the VN-200 at 3 m/s.
            v.alt_m = Some(500.0 + 3.0 * t);
            ch.update(
                &b_ns(ms * 1_000_000, 100.0 + 2.0 * t, 0.0),
                &v,
                0.1,
                4.42,
                &p,
            )
        };
        for ms in (0..700).step_by(100) {
            at(ms);
        }
        let r = at(700);
        assert_eq!(r.height_rate.verdict, PairVerdict::NotCompared);
        assert_eq!(r.height_rate.gate, Some(GateReason::NoData));
        let r = at(800);
        assert_eq!(r.height_rate.gate, None);
        // 1.6 m / 0.8 s and 2.4 m / 0.8 s.
        assert!((r.height_rate.bahrs_mps.unwrap() - 2.0).abs() < 1e-9);
        assert!((r.height_rate.vn200_mps.unwrap() - 3.0).abs() < 1e-9);
        // sqrt(0.7^2 + max(0.3, sqrt 2 x 2 / 0.8)^2) = sqrt(0.49 + 8 / 0.64) = sqrt(12.99)
        // = 3.604164.
        assert!((r.height_rate.sigma_mps.unwrap() - 3.604_164).abs() < 1e-6);
    }

    /// The rate's older end is the newest sample at least one window (1 s) old: with samples at
    /// 0, 0.5, 1 and 1.5 s, the rate at 1.5 s is over 0.5 .. 1.5 s, not 0 .. 1.5 s. The pressure
    /// height steps from 0 to 3 m after 0 s, so the first gives 0 m/s, the second 2 m/s.
    #[test]
    fn height_rate_older_end_is_exactly_one_window_back() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let mut last = None;
        for (ms, h) in [(0, 0.0), (500, 3.0), (1000, 3.0), (1500, 3.0)] {
            last = Some(ch.update(&b_ns(ms * 1_000_000, h, 0.0), &vn(0.0, 0.0), 0.5, 4.42, &p));
        }
        assert_eq!(last.unwrap().height_rate.bahrs_mps, Some(0.0));
    }

    /// The height-rate history is capped at 4096 samples: at 5 kHz (0.2 ms) the window's 1 s
    /// holds 5000, so after 4200 samples the older end is 4095 intervals back (0.819 s, over the
    /// 0.8 s minimum). The pressure height steps 0 -> 1 m after that sample: 1 m / 0.819 s.
    #[test]
    fn height_rate_history_keeps_the_newest_4096_samples() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let n = 4200;
        let mut last = None;
        for i in 0..n {
            let h = if i <= n - 4096 { 0.0 } else { 1.0 };
            last = Some(ch.update(&b_ns(i * 200_000, h, 0.0), &vn(0.0, 0.0), 2e-4, 4.42, &p));
        }
        let r = last.unwrap().height_rate;
        assert!((r.bahrs_mps.unwrap() - 1.0 / 0.819).abs() < 1e-9, "{r:?}");
    }

    /// The pressure port blocks at 30 s but the BAHRS down velocity stays right: only the height
    /// rate miscompares (its CUSUM: 2 m/s is 2.63 sigma, over the slack of 2), and that alone is a
    /// BAHRS-VN-200 miscompare the third opinion isolates to the BAHRS.
    #[test]
    fn a_height_rate_miscompare_alone_is_isolated_by_the_third_opinion() {
        let mut ch = VerticalChannel::default();
        let rs = fly(
            &mut ch,
            (0.0, 60.0),
            &|t| (100.0 + 2.0 * t.min(30.0), -2.0),
            &|t| (500.0 + 2.0 * t, -2.0),
            &|t| Some(Some(520.0 + 2.0 * t)),
        );
        let last = rs.last().unwrap().1;
        assert_eq!(last.velocity_down.verdict, PairVerdict::Pass);
        assert_eq!(last.height_rate.verdict, PairVerdict::Fail);
        assert_eq!(last.third.isolated, Some(Unit::Bahrs));
    }

    /// Without a BAHRS-VN-200 miscompare the third opinion isolates nothing, even when it fails
    /// one unit: the BAHRS climbs at 3.4 m/s, the VN-200 and the TT GNSS at 2. Over 1 s the
    /// difference 1.4 m/s is 1.84 sigma (0.76 m/s): under the threshold and the CUSUM slack
    /// (2), it passes; over 20 s it is 1.4 / 0.285 = 4.9 sigma against the TT, over 4.42.
    #[test]
    fn a_third_opinion_failure_without_a_miscompare_isolates_nothing() {
        let mut ch = VerticalChannel::default();
        let rs = fly(
            &mut ch,
            (0.0, 40.0),
            &|t| (100.0 + 3.4 * t, -2.0),
            &|t| (500.0 + 2.0 * t, -2.0),
            &|t| Some(Some(520.0 + 2.0 * t)),
        );
        let last = rs.last().unwrap().1;
        assert_eq!(last.height_rate.verdict, PairVerdict::Pass);
        assert_eq!(last.velocity_down.verdict, PairVerdict::Pass);
        assert_eq!(last.third.bahrs_vs_tt.verdict, PairVerdict::Fail);
        assert_eq!(last.third.vn200_vs_tt.verdict, PairVerdict::Pass);
        assert!(rs.iter().all(|(_, r)| r.third.isolated.is_none()));
    }

    /// The TT history keeps 64 epochs. The window's older end is the newest epoch at least
    /// 19.5 s (20 s - 0.5 s) before the newest; at one epoch every 0.31 s that is 63 epochs back
    /// (63 x 0.31 = 19.53 s; 62 x 0.31 = 19.22 s is too recent), the oldest of the 64 kept after
    /// 71 epochs. With 63 kept there would be no older end (window filling).
    #[test]
    fn tt_history_keeps_64_epochs() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let mut next = 0_i64;
        let mut last = None;
        for i in 0..=1085_i64 {
            let t_ns = i * 20_000_000;
            while next * 310_000_000 <= t_ns {
                let te = next as f64 * 0.31;
                ch.push_tt_gnss(next * 310_000_000, Some(520.0 + 2.0 * te));
                next += 1;
            }
            let t = t_ns as f64 * 1e-9;
            last = Some(ch.update(
                &b_ns(t_ns, 100.0 + 2.0 * t, -2.0),
                &vn(500.0 + 2.0 * t, -2.0),
                0.02,
                4.42,
                &p,
            ));
        }
        // The newest epoch is 70 (21.7 s): 71 pushed, epochs 7 .. 70 kept.
        assert_eq!(next, 71);
        let third = last.unwrap().third;
        assert_eq!(third.not_compared, None);
        assert!((third.span_s.unwrap() - 19.53).abs() < 1e-9, "{third:?}");
    }

    /// The longest window the third opinion takes (1.2 x 20 = 24 s) compared at the stale limit
    /// (the newest epoch exactly 2.5 s old: not yet stale) needs BAHRS heights up to 26.5 s old,
    /// and one sample more for the interpolation at the older end: the height history keeps
    /// them (27.5 s). BAHRS at 100 Hz on a 5 ms offset (0.995, 1.005, ...), one sample more at
    /// 27.5 s; TT epochs at 1 s and 25 s, received late, just before that sample. The older end
    /// 1 s lies between the samples at 0.995 s (26.505 s old) and 1.005 s.
    #[test]
    fn third_opinion_takes_the_longest_window_at_the_stale_limit() {
        let mut ch = VerticalChannel::default();
        for k in 0..2750_i64 {
            climb_2mps(&mut ch, 5_000_000 + k * 10_000_000);
        }
        // TT climbing at 2.5 m/s: (570 - 510) / 24 s.
        ch.push_tt_gnss(1_000_000_000, Some(510.0));
        ch.push_tt_gnss(25_000_000_000, Some(570.0));
        // The VN-200 states PosU 2 m.
        let third = climb_2mps_posu(&mut ch, 27_500_000_000, Some(2.0)).third;
        assert_eq!(third.not_compared, None, "{third:?}");
        assert_eq!(third.span_s, Some(24.0));
        assert!((third.tt_rate_mps.unwrap() - 2.5).abs() < 1e-9);
        assert!((third.bahrs_vs_tt.bahrs_mps.unwrap() - 2.0).abs() < 1e-9);
        assert!((third.vn200_vs_tt.bahrs_mps.unwrap() - 2.0).abs() < 1e-9);
        // Sigmas over 24 s: the TT's sqrt 2 x 4 / 24 (its square 32 / 576); the BAHRS rate's
        // 0.7 m/s stated for 1 s, x 1 / 24; the VN-200's max(0.3 / 24, sqrt 2 x PosU / 24), PosU
        // winning (its square 8 / 576). BAHRS: sqrt((0.7 / 24)^2 + 32 / 576) = 0.237500;
        // VN-200: sqrt(40 / 576) = 0.263523.
        assert!((third.bahrs_vs_tt.sigma_mps.unwrap() - 0.237_500).abs() < 1e-6);
        assert!((third.vn200_vs_tt.sigma_mps.unwrap() - 0.263_523).abs() < 1e-6);
        // 1 ns later the epoch is stale.
        let third = climb_2mps(&mut ch, 27_500_000_001).third;
        assert_eq!(third.not_compared, Some(TtNotCompared::Stale));
    }

    /// One BAHRS and VN-200 sample at `t_ns`, both climbing at 2 m/s and agreeing; the VN-200
    /// states PosU `pos_u_m`.
    fn climb_2mps_posu(
        ch: &mut VerticalChannel,
        t_ns: i64,
        pos_u_m: Option<f64>,
    ) -> VerticalRecord {
        let p = CheckParams::default();
        let t = t_ns as f64 * 1e-9;
        let v = Vn200Vertical {
            pos_u_m,
            ..vn(500.0 + 2.0 * t, -2.0)
        };
        ch.update(&b_ns(t_ns, 100.0 + 2.0 * t, -2.0), &v, 0.01, 4.42, &p)
    }

    /// [`climb_2mps_posu`] without PosU.
    fn climb_2mps(ch: &mut VerticalChannel, t_ns: i64) -> VerticalRecord {
        climb_2mps_posu(ch, t_ns, None)
    }

    /// The third opinion's height history is capped at 8192 samples. At 400 Hz (2.5 ms) 8200
    /// samples span 20.4975 s, inside the 27.5 s kept by age, so only the cap drops: the window's
    /// older end at the 8192nd newest sample (8191 x 2.5 ms = 20.4775 s back) is kept and
    /// compared; at the 8193rd (20.48 s back) it was dropped, and neither unit's height is there
    /// (no partner).
    #[test]
    fn third_opinion_height_history_keeps_the_newest_8192_samples() {
        let run = |back: i64| {
            let mut ch = VerticalChannel::default();
            let n = 8200_i64;
            for i in 0..n - 1 {
                climb_2mps(&mut ch, i * 2_500_000);
            }
            let t1 = (n - 1) * 2_500_000;
            let t0 = t1 - back * 2_500_000;
            ch.push_tt_gnss(t0, Some(500.0));
            ch.push_tt_gnss(t1, Some(500.0 + 2.0 * (t1 - t0) as f64 * 1e-9));
            climb_2mps(&mut ch, t1).third
        };
        let kept = run(8191);
        assert_eq!(kept.not_compared, None, "{kept:?}");
        assert!((kept.span_s.unwrap() - 20.4775).abs() < 1e-9);
        assert!((kept.bahrs_vs_tt.bahrs_mps.unwrap() - 2.0).abs() < 1e-9);
        assert_eq!(run(8192).not_compared, Some(TtNotCompared::NoPartner));
    }

    /// Without PosU the VN-200 rate's sigma is its stated 0.3 m/s (for 1 s) scaled to the window,
    /// and the persistence of the third opinion counts the time between epochs: it declares
    /// after 2 s over the limit, four epochs at 2 Hz. Epochs every 0.5 s; the TT altitude steps
    /// up 80 m at 30 s; the window is then 19.5 s (the newest epoch at least 19.5 s back), so the
    /// TT rate is 80 / 19.5 m/s over the others' for the next 19.5 s. Its sigma:
    /// sqrt((0.7 / 19.5)^2 + (sqrt 2 x 4 / 19.5)^2) = sqrt(0.49 + 32) / 19.5 = 5.7 / 19.5, so
    /// 80 / 5.7 = 14.0 sigma, ratio 3.2 at 4.42: the filter (alpha 0.5 / (0.5 + 0.5) = 0.5) is
    /// over 1 from the first epoch, the counter rises 0.5 s per epoch and reaches 2 s at the
    /// fourth (31.5 s); the CUSUM (+12 per epoch, limit 60) is still under its limit then.
    #[test]
    fn third_opinion_persistence_counts_the_epoch_interval() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let mut at_epochs = Vec::new();
        for i in 0..=1600_i64 {
            let t_ns = i * 20_000_000;
            let t = t_ns as f64 * 1e-9;
            if i % 25 == 0 {
                let step = if t >= 30.0 { 80.0 } else { 0.0 };
                ch.push_tt_gnss(t_ns, Some(520.0 + 2.0 * t + step));
            }
            let r = ch.update(
                &b_ns(t_ns, 100.0 + 2.0 * t, -2.0),
                &vn(500.0 + 2.0 * t, -2.0),
                0.02,
                4.42,
                &p,
            );
            if i % 25 == 0 {
                at_epochs.push((i / 25, r.third));
            }
        }
        let at = |t: f64| at_epochs[(t * 2.0) as usize].1;
        let r = at(20.0);
        assert_eq!(r.span_s, Some(19.5));
        // sqrt((0.3 / 19.5)^2 + 32 / 19.5^2) = sqrt(32.09) / 19.5 = 0.290502.
        assert!((r.vn200_vs_tt.sigma_mps.unwrap() - 0.290_502).abs() < 1e-6);
        assert!((r.bahrs_vs_tt.sigma_mps.unwrap() - 5.7 / 19.5).abs() < 1e-9);
        for t in [29.5, 30.0, 30.5, 31.0] {
            assert_eq!(at(t).bahrs_vs_tt.verdict, PairVerdict::Pass, "{t}");
        }
        assert!((at(30.0).bahrs_vs_tt.diff_mps.unwrap() + 80.0 / 19.5).abs() < 1e-9);
        assert_eq!(at(31.5).bahrs_vs_tt.verdict, PairVerdict::Fail);
        assert_eq!(at(31.5).vn200_vs_tt.verdict, PairVerdict::Fail);
    }

    /// With the BAHRS pressure height unusable (integrity risk) throughout, the VN-200 altitude
    /// rate is still compared with the TT rate; the BAHRS side says it had no data.
    #[test]
    fn third_opinion_compares_the_unit_whose_heights_are_usable() {
        let p = CheckParams::default();
        let mut ch = VerticalChannel::default();
        let mut last = None;
        for i in 0..=1250_i64 {
            let t_ns = i * 20_000_000;
            let t = t_ns as f64 * 1e-9;
            if i % 50 == 0 {
                ch.push_tt_gnss(t_ns, Some(520.0 + 2.0 * t));
            }
            let mut s = b_ns(t_ns, 100.0 + 2.0 * t, -2.0);
            s.health = NavigationHealth::new(
                Health::IntegrityRisk,
                Health::Safe,
                Health::Safe,
                Health::Safe,
                Health::Safe,
            );
            last = Some(ch.update(&s, &vn(500.0 + 2.0 * t, -2.0), 0.02, 4.42, &p));
        }
        let third = last.unwrap().third;
        assert_eq!(third.not_compared, None, "{third:?}");
        assert_eq!(third.bahrs_vs_tt.verdict, PairVerdict::NotCompared);
        assert_eq!(third.bahrs_vs_tt.gate, Some(GateReason::NoData));
        assert_eq!(third.bahrs_vs_tt.vn200_mps, third.tt_rate_mps);
        assert!((third.vn200_vs_tt.bahrs_mps.unwrap() - 2.0).abs() < 1e-9);
        assert_eq!(third.vn200_vs_tt.verdict, PairVerdict::Pass);
    }

    /// `height_at` interpolates between the samples bracketing `t` when they are at most 0.2 s
    /// apart, takes a sample at `t` itself (even the first, with nothing before it), and gives
    /// nothing across a longer gap or at an unusable sample.
    #[test]
    fn height_at_interpolates_only_within_0_2_s() {
        let ms = |m: i64| m * 1_000_000;
        let hist: VecDeque<Heights> = [
            (ms(1000), Some(1.0), None),
            (ms(1200), Some(3.0), Some(7.0)),
            (ms(1500), Some(6.0), Some(8.0)),
        ]
        .into();
        let bahrs = |t| height_at(&hist, t, |e| e.1);
        let vn200 = |t| height_at(&hist, t, |e| e.2);
        assert_eq!(bahrs(ms(1000)), Some(1.0));
        assert_eq!(bahrs(ms(1200)), Some(3.0));
        // Exactly 0.2 s apart: 1 + (3 - 1) x 50 / 200 = 1.5.
        assert_eq!(bahrs(ms(1050)), Some(1.5));
        // 0.3 s apart: none.
        assert_eq!(bahrs(ms(1300)), None);
        // Before the first and after the last sample: none.
        assert_eq!(bahrs(ms(1000) - 1), None);
        assert_eq!(bahrs(ms(1500) + 1), None);
        // The VN-200 height is unusable at 1 s: none between 1 and 1.2 s, but 7 at 1.2 s.
        assert_eq!(vn200(ms(1100)), None);
        assert_eq!(vn200(ms(1200)), Some(7.0));
    }
}
