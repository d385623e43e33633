//! DO-365 (Phase I) well-clear geometry of one intruder against the ownship: closest point of
//! approach, modified tau, the well-clear volume now and over a lookahead, and the alert level.
//!
//! Definitions used (s: relative horizontal position of the intruder, v: relative horizontal
//! velocity (intruder minus ownship), r = |s|, dz: intruder altitude minus ownship altitude, vz: its
//! rate):
//! - time to horizontal CPA `tcpa = -s.v / |v|^2` when closing (`s.v < 0`), else 0;
//! - horizontal miss distance `HMD = |s + v tcpa|`;
//! - modified tau `tau_mod = (DMOD^2 - r^2) / (s.v)`, defined only when closing and `r > DMOD`
//!   (DMOD = DTHR); undefined when diverging or already inside DMOD;
//! - the DWC volume holds at a state when `|dz| <= ZTHR` (TCOA threshold 0, so the vertical test is
//!   on the separation itself) and either `r <= DTHR` or (`HMD <= DTHR` and
//!   `0 <= tau_mod <= TTHR`);
//! - thresholds: DTHR = 0.66 NM = 1222.32 m (4010 ft, not 4000), ZTHR = 450 ft, TTHR = 35 s;
//! - alert levels: 3 warning = DWC volume within 25 s; 2 corrective = DWC volume within 55 s;
//!   1 preventive = the volume with ZTHR 700 ft within 55 s; 0 otherwise.
//!
//! Predicted loss of well-clear is found exactly on the straight-line projection: each clause of
//! the volume is an interval of time (the tau clause is a quadratic inequality), so the intervals
//! within the lookahead come out in closed form, with no time stepping.

use nalgebra::Vector2;

use crate::units::{M_PER_FT, M_PER_NM};

/// Well-clear thresholds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thresholds {
    /// Horizontal distance threshold (and DMOD), m.
    pub dthr_m: f64,
    /// Vertical separation threshold, m.
    pub zthr_m: f64,
    /// Modified tau threshold, s.
    pub tthr_s: f64,
}

impl Thresholds {
    /// DO-365 DWC: DTHR 0.66 NM, ZTHR 450 ft, TTHR 35 s.
    pub const DWC: Thresholds = Thresholds {
        dthr_m: 0.66 * M_PER_NM,
        zthr_m: 450.0 * M_PER_FT,
        tthr_s: 35.0,
    };
    /// The preventive-alert volume: as DWC with ZTHR 700 ft.
    pub const PREVENTIVE: Thresholds = Thresholds {
        dthr_m: 0.66 * M_PER_NM,
        zthr_m: 700.0 * M_PER_FT,
        tthr_s: 35.0,
    };
}

/// Lookahead of the loss-of-well-clear prediction, s.
pub const LOOKAHEAD_S: f64 = 180.0;
/// Alerting times, s: warning, corrective and preventive.
pub const WARNING_TIME_S: f64 = 25.0;
/// Corrective and preventive alerting time, s.
pub const ALERT_TIME_S: f64 = 55.0;

/// Relative state of an intruder in the ownship's local tangent plane (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relative {
    /// Horizontal position of the intruder relative to the ownship, east and north, m.
    pub s: Vector2<f64>,
    /// Horizontal velocity of the intruder relative to the ownship, east and north, m/s.
    pub v: Vector2<f64>,
    /// Intruder altitude minus ownship altitude, m: the middle of its possible range when the
    /// altitudes are not known like with like.
    pub dz_m: f64,
    /// Half-width of the range of `dz_m`, m: 0 when the altitudes are comparable; otherwise the
    /// vertical test holds whenever some separation in `dz_m +- dz_spread_m` would.
    pub dz_spread_m: f64,
    /// Rate of `dz_m`, m/s: the middle of its possible range when a vertical rate is unknown.
    pub vz_mps: f64,
    /// Half-width of the range of `vz_mps`, m/s: 0 when both vertical rates are known; with an
    /// unknown rate, the vertical test holds whenever some rate in `vz_mps +- vz_spread_mps`
    /// could bring the separation within the threshold (see [`crate::traffic::policy`]).
    pub vz_spread_mps: f64,
}

/// A closed time interval, s from now.
pub type Interval = (f64, f64);

/// Up to two disjoint intervals, in time order (the most the well-clear volume can produce on
/// straight lines), held without allocation.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Intervals {
    len: usize,
    items: [Interval; 2],
}

impl Intervals {
    fn push(&mut self, iv: Interval) {
        if self.len < 2 {
            self.items[self.len] = iv;
            self.len += 1;
        }
    }

    /// The intervals as a slice.
    pub fn as_slice(&self) -> &[Interval] {
        &self.items[..self.len]
    }

    /// The first interval.
    pub fn first(&self) -> Option<Interval> {
        self.as_slice().first().copied()
    }
}

/// The geometry of one encounter.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Geometry {
    /// Horizontal distance, m.
    pub horizontal_distance_m: f64,
    /// Vertical separation (intruder above ownship positive), m; `None` when the intruder's
    /// altitude is unknown (the vertical test then takes it as co-altitude).
    pub vertical_separation_m: Option<f64>,
    /// Range rate (horizontal), m/s; negative when closing. `None` when a velocity is unknown.
    pub range_rate_mps: Option<f64>,
    /// Time to horizontal CPA, s (0 when diverging); `None` when a velocity is unknown.
    pub tcpa_s: Option<f64>,
    /// Horizontal miss distance at CPA, m; `None` when a velocity is unknown.
    pub hmd_m: Option<f64>,
    /// Modified tau, s; `None` when diverging or inside DMOD.
    pub tau_mod_s: Option<f64>,
    /// The DWC volume holds now.
    pub well_clear_violated_now: bool,
    /// First interval of predicted loss of well-clear within the lookahead.
    pub loss_of_well_clear_interval_s: Option<Interval>,
    /// Alert level 0-3.
    pub alert_level: u8,
}

impl Relative {
    /// Horizontal distance, m.
    pub fn range_m(&self) -> f64 {
        self.s.norm()
    }

    /// Time to horizontal CPA, s; 0 when diverging or not moving relative to each other.
    pub fn tcpa_s(&self) -> f64 {
        let sv = self.s.dot(&self.v);
        let vv = self.v.norm_squared();
        if sv < 0.0 && vv > 0.0 { -sv / vv } else { 0.0 }
    }

    /// Horizontal miss distance at CPA, m.
    pub fn hmd_m(&self) -> f64 {
        (self.s + self.v * self.tcpa_s()).norm()
    }

    /// Modified tau with DMOD = `dmod_m`, s; `None` when not closing or already inside DMOD.
    pub fn tau_mod_s(&self, dmod_m: f64) -> Option<f64> {
        let sv = self.s.dot(&self.v);
        let r2 = self.s.norm_squared();
        (sv < 0.0 && r2 > dmod_m * dmod_m).then(|| (dmod_m * dmod_m - r2) / sv)
    }

    /// The state `t` seconds ahead on straight lines.
    pub fn at(&self, t: f64) -> Relative {
        Relative {
            s: self.s + self.v * t,
            dz_m: self.dz_m + self.vz_mps * t,
            // The reachable band widens with time; `violates` tests the centre only, so `at` is
            // exact for known rates (spread 0), which is what the scan tests use.
            ..*self
        }
    }

    /// Whether the well-clear volume `th` holds now.
    pub fn violates(&self, th: &Thresholds) -> bool {
        if self.dz_m.abs() - self.dz_spread_m > th.zthr_m {
            return false;
        }
        let r = self.range_m();
        r <= th.dthr_m
            || (self.hmd_m() <= th.dthr_m
                && self.tau_mod_s(th.dthr_m).is_some_and(|t| t <= th.tthr_s))
    }

    /// The intervals within `[0, lookahead_s]` during which the volume `th` holds, in order.
    pub fn violation_intervals(&self, th: &Thresholds, lookahead_s: f64) -> Intervals {
        self.clip(&self.horizontal_intervals(th), th.zthr_m, lookahead_s)
    }

    /// The (unclipped) times at which the horizontal part of the volume `th` holds: the union of
    /// its two clauses, sorted and merged.
    fn horizontal_intervals(&self, th: &Thresholds) -> [Option<Interval>; 2] {
        // Clause 1: r(t) <= DTHR  <=>  |v|^2 t^2 + 2 s.v t + |s|^2 - DTHR^2 <= 0.
        let vv = self.v.norm_squared();
        let sv = self.s.dot(&self.v);
        let ss = self.s.norm_squared();
        let d2 = th.dthr_m * th.dthr_m;
        let near = quadratic_le_zero(vv, 2.0 * sv, ss - d2);
        // Clause 2: HMD <= DTHR and 0 <= tau_mod(t) <= TTHR, while closing (t < tcpa) and outside
        // DMOD. tau_mod(t) <= T  <=>  r(t)^2 - D^2 <= -T s(t).v  (s(t).v < 0)
        //                        <=>  |v|^2 t^2 + (2 s.v + T |v|^2) t + |s|^2 + T s.v - D^2 <= 0.
        // tau_mod >= 0 holds whenever it is defined. HMD is the same at every t before CPA, and
        // HMD^2 = |s|^2 - (s.v)^2 / |v|^2.
        let mut tau = None;
        if vv > 0.0 && sv < 0.0 && ss - sv * sv / vv <= d2 {
            let tcpa = -sv / vv;
            let t = th.tthr_s;
            if let Some((a, b)) = quadratic_le_zero(vv, 2.0 * sv + t * vv, ss + t * sv - d2) {
                let b = b.min(tcpa);
                if a <= b {
                    tau = Some((a, b));
                }
            }
        }
        match (near, tau) {
            (Some(x), Some(y)) => {
                let (x, y) = if x.0 <= y.0 { (x, y) } else { (y, x) };
                if y.0 <= x.1 {
                    [Some((x.0, x.1.max(y.1))), None]
                } else {
                    [Some(x), Some(y)]
                }
            }
            (x, y) => [x.or(y), None],
        }
    }

    /// Intersects horizontal intervals with the vertical one (`|dz| <= zthr_m`) and the lookahead.
    // Inlined (as `alert_level_from`): issue 24's unknown-altitude bands made both too large for
    // LLVM to inline on its own, and the calls cost 20 % of `geometry` (criterion, 1000 intruders
    // from cached ECEF: 16.4 us before issue 24, 20.1 us without, 16.5-16.9 us with).
    #[inline(always)]
    fn clip(&self, horizontal: &[Option<Interval>; 2], zthr_m: f64, lookahead_s: f64) -> Intervals {
        let mut out = Intervals::default();
        let Some(vertical) = within(
            (self.dz_m, self.dz_spread_m),
            (self.vz_mps, self.vz_spread_mps),
            zthr_m,
        ) else {
            return out;
        };
        for &(a, b) in horizontal.iter().flatten() {
            let lo = a.max(vertical.0).max(0.0);
            let hi = b.min(vertical.1).min(lookahead_s);
            if lo <= hi {
                out.push((lo, hi));
            }
        }
        out
    }

    /// Time until the volume `th` is first entered within the lookahead (0 if it holds now).
    pub fn time_to_violation_s(&self, th: &Thresholds, lookahead_s: f64) -> Option<f64> {
        self.violation_intervals(th, lookahead_s)
            .first()
            .map(|iv| iv.0)
    }

    /// The DO-365 Phase I alert level (0-3) of this state, with no history.
    pub fn alert_level(&self) -> u8 {
        let h = self.horizontal_intervals(&Thresholds::DWC);
        self.alert_level_from(
            &h,
            self.clip(&h, Thresholds::DWC.zthr_m, ALERT_TIME_S).first(),
        )
    }

    /// The alert level from the horizontal intervals (the DWC and preventive volumes share them:
    /// they differ only in ZTHR) and the first DWC interval of any lookahead of at least 55 s.
    #[inline(always)]
    fn alert_level_from(&self, h: &[Option<Interval>; 2], first_dwc: Option<Interval>) -> u8 {
        match first_dwc {
            Some((t, _)) if t <= WARNING_TIME_S => 3,
            Some((t, _)) if t <= ALERT_TIME_S => 2,
            _ if self
                .clip(h, Thresholds::PREVENTIVE.zthr_m, ALERT_TIME_S)
                .first()
                .is_some() =>
            {
                1
            }
            _ => 0,
        }
    }

    /// Every quantity of the encounter.
    pub fn geometry(&self) -> Geometry {
        let r = self.range_m();
        let h = self.horizontal_intervals(&Thresholds::DWC);
        let first = self.clip(&h, Thresholds::DWC.zthr_m, LOOKAHEAD_S).first();
        Geometry {
            horizontal_distance_m: r,
            vertical_separation_m: Some(self.dz_m),
            range_rate_mps: Some(if r > 0.0 {
                self.s.dot(&self.v) / r
            } else {
                -self.v.norm()
            }),
            tcpa_s: Some(self.tcpa_s()),
            hmd_m: Some(self.hmd_m()),
            tau_mod_s: self.tau_mod_s(Thresholds::DWC.dthr_m),
            // Inside the volume now exactly when the first interval starts at 0 (intervals are
            // clipped at 0, so a volume holding now starts there).
            well_clear_violated_now: first.is_some_and(|iv| iv.0 == 0.0),
            loss_of_well_clear_interval_s: first,
            alert_level: self.alert_level_from(&h, first),
        }
    }
}

/// Times at which some separation `y` in `z.0 +- z.1` and some rate `w` in `vz.0 +- vz.1` give
/// `|y + w t| <= zthr`, as one interval (unbounded ends as +-infinity), or `None`. With both
/// spreads 0 this is the plain `|z + vz t| <= zthr`. Only `t >= 0` matters to the callers (they
/// clip at 0), and for `t >= 0` the reachable separations form the band
/// `[z - zs + (vz - vs) t, z + zs + (vz + vs) t]`, which meets `[-zthr, zthr]` exactly when
/// `z - zs + (vz - vs) t <= zthr` and `z + zs + (vz + vs) t >= -zthr`: two half-lines in `t`.
fn within(z: (f64, f64), vz: (f64, f64), zthr: f64) -> Option<Interval> {
    let ((z, zs), (vz, vs)) = (z, vz);
    if zs <= 0.0 && vs <= 0.0 {
        if vz == 0.0 {
            return (z.abs() <= zthr).then_some((f64::NEG_INFINITY, f64::INFINITY));
        }
        let t1 = (-zthr - z) / vz;
        let t2 = (zthr - z) / vz;
        return Some((t1.min(t2), t1.max(t2)));
    }
    // z - zs + (vz - vs) t <= zthr.
    let a = half_line(vz - vs, zthr - z + zs)?;
    // z + zs + (vz + vs) t >= -zthr  <=>  -(vz + vs) t <= zthr + z + zs.
    let b = half_line(-(vz + vs), zthr + z + zs)?;
    let iv = (a.0.max(b.0).max(0.0), a.1.min(b.1));
    (iv.0 <= iv.1).then_some(iv)
}

/// The times `t` with `k t <= c`, as an interval (unbounded ends as +-infinity), or `None`.
fn half_line(k: f64, c: f64) -> Option<Interval> {
    if k == 0.0 {
        (c >= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY))
    } else if k > 0.0 {
        Some((f64::NEG_INFINITY, c / k))
    } else {
        Some((c / k, f64::INFINITY))
    }
}

/// The interval where `a t^2 + b t + c <= 0`, for `a >= 0`. With `a = 0` the linear case: an
/// unbounded interval or none.
fn quadratic_le_zero(a: f64, b: f64, c: f64) -> Option<Interval> {
    if a <= 0.0 {
        return if b == 0.0 {
            (c <= 0.0).then_some((f64::NEG_INFINITY, f64::INFINITY))
        } else if b > 0.0 {
            Some((f64::NEG_INFINITY, -c / b))
        } else {
            Some((-c / b, f64::INFINITY))
        };
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let sq = disc.sqrt();
    // Numerically stable roots.
    let q = -0.5 * (b + b.signum() * sq);
    let (r1, r2) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    Some((r1.min(r2), r1.max(r2)))
}

/// The closed-form helpers against hand-solved cases (issue 23: mutation testing found their
/// degenerate branches untested).
#[cfg(test)]
mod helper_tests {
    use super::*;

    #[test]
    fn quadratic_le_zero_by_hand() {
        // (t - 1)(t - 3) = t^2 - 4t + 3 <= 0 on [1, 3]; 2t^2 - 2 <= 0 on [-1, 1].
        assert_eq!(quadratic_le_zero(1.0, -4.0, 3.0), Some((1.0, 3.0)));
        assert_eq!(quadratic_le_zero(2.0, 0.0, -2.0), Some((-1.0, 1.0)));
        // (t - 1)^2 <= 0 only at t = 1 (a tangent pass exactly at the threshold).
        assert_eq!(quadratic_le_zero(1.0, -2.0, 1.0), Some((1.0, 1.0)));
        // t^2 - 2t <= 0 on [0, 2]: a root at 0, where the stable form's q must not vanish.
        assert_eq!(quadratic_le_zero(1.0, -2.0, 0.0), Some((0.0, 2.0)));
        // t^2 + 1 <= 0 never.
        assert_eq!(quadratic_le_zero(1.0, 0.0, 1.0), None);
        // Linear: 2t - 4 <= 0 for t <= 2; -2t + 4 <= 0 for t >= 2; constant c <= 0 always or never.
        assert_eq!(
            quadratic_le_zero(0.0, 2.0, -4.0),
            Some((f64::NEG_INFINITY, 2.0))
        );
        assert_eq!(
            quadratic_le_zero(0.0, -2.0, 4.0),
            Some((2.0, f64::INFINITY))
        );
        assert_eq!(
            quadratic_le_zero(0.0, 0.0, -1.0),
            Some((f64::NEG_INFINITY, f64::INFINITY))
        );
        assert_eq!(quadratic_le_zero(0.0, 0.0, 1.0), None);
    }

    #[test]
    fn half_lines_by_hand() {
        // 2t <= 6: t <= 3; -2t <= 6: t >= -3; 0 <= c: always, 0 <= -1: never.
        assert_eq!(half_line(2.0, 6.0), Some((f64::NEG_INFINITY, 3.0)));
        assert_eq!(half_line(-2.0, 6.0), Some((-3.0, f64::INFINITY)));
        assert_eq!(
            half_line(0.0, 1.0),
            Some((f64::NEG_INFINITY, f64::INFINITY))
        );
        assert_eq!(half_line(0.0, -1.0), None);
    }

    /// The unknown-altitude band (issue 24): separation 300 +- 50 m, closing at 10 +- 0 m/s,
    /// against ZTHR 100 m: the band [250 - 10t, 350 - 10t] meets [-100, 100] from t = 15 s
    /// (250 - 10t <= 100) to t = 45 s (350 - 10t >= -100). With a rate spread of 5 m/s the
    /// band is [250 - 15t, 350 - 5t]: from t = 10 s to t = 90 s.
    #[test]
    fn the_vertical_band_by_hand() {
        let close = |a: Option<Interval>, b: (f64, f64)| {
            let a = a.unwrap();
            assert!(
                (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9,
                "{a:?} vs {b:?}"
            );
        };
        close(within((300.0, 50.0), (-10.0, 0.0), 100.0), (15.0, 45.0));
        close(within((300.0, 50.0), (-10.0, 5.0), 100.0), (10.0, 90.0));
        // Known values: |300 - 10t| <= 100 from 20 s to 40 s.
        close(within((300.0, 0.0), (-10.0, 0.0), 100.0), (20.0, 40.0));
        // Diverging with a band already beyond ZTHR: never.
        assert_eq!(within((300.0, 50.0), (10.0, 0.0), 100.0), None);
    }

    /// The vertical test of the volume now with a band: held when some separation in dz +-
    /// spread is within ZTHR (exactly at the edge included).
    #[test]
    fn violates_with_a_band() {
        let th = Thresholds {
            dthr_m: 1000.0,
            zthr_m: 100.0,
            tthr_s: 35.0,
        };
        let r = |dz: f64, spread: f64| Relative {
            s: Vector2::new(10.0, 0.0),
            v: Vector2::zeros(),
            dz_m: dz,
            dz_spread_m: spread,
            vz_mps: 0.0,
            vz_spread_mps: 0.0,
        };
        assert!(r(150.0, 50.0).violates(&th), "150 - 50 = 100: at the edge");
        assert!(!r(150.0, 49.0).violates(&th));
        assert!(r(-150.0, 60.0).violates(&th));
        assert!(!r(-150.0, 0.0).violates(&th));
    }

    #[test]
    fn time_to_violation_and_range_rate_by_hand() {
        // Head-on from 5000 m at 100 m/s, co-altitude: the tau clause is met first, when
        // tau_mod = TTHR at r* (3884.61 m): entered after (5000 - r*) / 100 = 11.154 s.
        let s = Relative {
            s: Vector2::new(5000.0, 0.0),
            v: Vector2::new(-100.0, 0.0),
            dz_m: 0.0,
            dz_spread_m: 0.0,
            vz_mps: 0.0,
            vz_spread_mps: 0.0,
        };
        let d = 0.66 * 1852.0;
        let r_star = (3500.0 + (3500.0f64 * 3500.0 + 4.0 * d * d).sqrt()) / 2.0;
        let t = s.time_to_violation_s(&Thresholds::DWC, 180.0).unwrap();
        assert!((t - (5000.0 - r_star) / 100.0).abs() < 1e-6, "{t}");
        assert_eq!(s.time_to_violation_s(&Thresholds::DWC, 5.0), None);
        // On top of the ownship (r = 0), moving apart at 5 m/s: range rate -|v| by convention.
        let on_top = Relative {
            s: Vector2::zeros(),
            v: Vector2::new(3.0, 4.0),
            ..s
        };
        assert_eq!(on_top.geometry().range_rate_mps, Some(-5.0));
        // Elsewhere s.v / r: 3 m/s closing along the line of sight.
        let g = Relative {
            s: Vector2::new(0.0, 100.0),
            v: Vector2::new(4.0, -3.0),
            ..s
        }
        .geometry();
        assert_eq!(g.range_rate_mps, Some(-3.0));
    }
}
