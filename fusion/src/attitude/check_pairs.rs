//! The pair comparisons of one check (step 3 of [`AttitudeChecker::compare_at`]): both detectors
//! on each pair of units and each axis, then each pair's joint chi-square test. Every pair and
//! axis keeps its own persistence state in the checker, so the order here is only the record's.

use super::*;

/// The pairs compared, as indices into `[bahrs, vn200, watson]`, in record order: BAHRS-VN200,
/// BAHRS-Watson, VN200-Watson.
const PAIR_UNITS: [(usize, usize); 3] = [(0, 1), (0, 2), (1, 2)];

/// What every pair comparison of one check shares.
pub(super) struct PairInputs<'a> {
    /// Comparison time (the BAHRS sample's), GPS ns.
    pub(super) t: i64,
    /// Time since the previous check, s (the persistence step).
    pub(super) dt_s: f64,
    /// The units `[bahrs, vn200, watson]`, ready to compare.
    pub(super) units: [&'a Prepared; 3],
    /// Euler-angle rates roll, pitch, heading, rad/s (the timing term of the variances).
    pub(super) euler_radps: [f64; 3],
    /// Variance of the declination, rad^2 (0 without a declination).
    pub(super) decl_var: f64,
}

impl PairInputs<'_> {
    /// The variance terms of the difference between units `ia` and `ib` on `axis` (index `ai`):
    /// both units' own variances, both mounting uncertainties, the timing term (the rate times
    /// both units' time-alignment sigmas), and on the heading the declination when exactly one
    /// unit of the pair is magnetic (the VN-200 heading is true; the BAHRS and the Watson are
    /// made true with the same declination, so between those two its error cancels).
    fn variance_terms(
        &self,
        p: &CheckParams,
        (ia, ib): (usize, usize),
        ai: usize,
        axis: Axis,
    ) -> VarianceTerms {
        let mount = [
            p.mounting_bahrs.sigma_deg * DEG,
            p.mounting_vn200.sigma_deg * DEG,
            p.mounting_watson.sigma_deg * DEG,
        ];
        let (ua, ub) = (self.units[ia], self.units[ib]);
        // Exactly one magnetic unit in the pair: the declination error shows.
        let one_magnetic = (ia == 1) != (ib == 1);
        let ts = (ua.sigma_ns.powi(2) + ub.sigma_ns.powi(2)).sqrt() * 1e-9;
        VarianceTerms {
            a: ua.var[ai],
            b: ub.var[ai],
            mounting: mount[ia].powi(2) + mount[ib].powi(2),
            rate_radps: self.euler_radps[ai],
            timing_sigma_s: ts,
            declination: if axis == Axis::Heading && one_magnetic {
                self.decl_var
            } else {
                0.0
            },
        }
    }
}

impl AttitudeChecker {
    /// Every pair on every axis, then each pair's joint test, as the record's pairs.
    pub(super) fn compare_pairs(&mut self, inp: &PairInputs) -> PairsRecord {
        PairsRecord {
            bahrs_vn200: self.compare_pair(inp, 0),
            bahrs_watson: self.compare_pair(inp, 1),
            vn200_watson: self.compare_pair(inp, 2),
        }
    }

    /// Pair `pi` (an index into `PAIR_UNITS`): its three axes, then the joint test over them.
    fn compare_pair(&mut self, inp: &PairInputs, pi: usize) -> PairRecord {
        let mut zs = [None; 3];
        let mut axes = [not_compared_pair(); 3];
        for (ai, axis) in Axis::ALL.into_iter().enumerate() {
            let (record, z) = self.compare_pair_axis(inp, pi, ai, axis);
            axes[ai] = record;
            zs[ai] = z;
        }
        PairRecord {
            roll: axes[0],
            pitch: axes[1],
            heading: axes[2],
            joint: self.joint_test(pi, zs, inp.dt_s),
        }
    }

    /// Pair `pi` on `axis` (index `ai`), with the normalised difference `z` for the joint test.
    ///
    /// Not compared while either unit's gate on the axis is closed: the persistence state is
    /// carried unchanged (a closed gate is no evidence either way). After a gap longer than
    /// `reset_after_gap_s` the state is reset, since it described another situation. Otherwise
    /// the statistical detector (ratio with persistence, and a CUSUM on z) and the fixed
    /// comparator judge the difference; either one's fault fails the pair on the axis.
    fn compare_pair_axis(
        &mut self,
        inp: &PairInputs,
        pi: usize,
        ai: usize,
        axis: Axis,
    ) -> (AxisPair, Option<f64>) {
        let p = self.params;
        let (ia, ib) = PAIR_UNITS[pi];
        let (ua, ub) = (inp.units[ia], inp.units[ib]);
        let st = &mut self.pairs[pi][ai];
        let open = ua.gates[ai].is_none() && ub.gates[ai].is_none();
        let (Some(va), Some(vb), true) = (ua.values, ub.values, open) else {
            let record = AxisPair {
                verdict: PairVerdict::NotCompared,
                comparison: None,
                stat_exceeded: false,
                fixed_exceeded: false,
                stat_fault: st.stat.fault,
                fixed_fault: st.fixed.fault,
                cusum: st.stat.cusum,
            };
            return (record, None);
        };
        if st
            .last_compared_ns
            .is_some_and(|t0| inp.t.saturating_sub(t0) as f64 * 1e-9 > p.reset_after_gap_s)
        {
            st.stat.reset();
            st.fixed.reset();
        }
        st.last_compared_ns = Some(inp.t);
        let var = inp.variance_terms(&p, (ia, ib), ai, axis);
        let bank = 0.5 * (va[0] + vb[0]);
        let c = compare_axis(&p, axis, va[ai], vb[ai], &var, self.k_axis, bank);
        // The CUSUM gets z clamped to the threshold: it is the slow-drift detector, and a
        // glitch of a sample or two must not declare through it. It then declares no
        // sooner than limit / (k - slack) samples (25 at the defaults, 0.5 s at 50 Hz).
        let zc = c.z.clamp(-self.k_axis, self.k_axis);
        let sf = st.stat.update(c.stat_ratio, zc, inp.dt_s, &p.persistence);
        let ff = st
            .fixed
            .update(c.fixed_ratio, 0.0, inp.dt_s, &p.persistence);
        let record = AxisPair {
            verdict: if sf || ff {
                PairVerdict::Fail
            } else {
                PairVerdict::Pass
            },
            comparison: Some(c),
            stat_exceeded: c.stat_ratio > 1.0,
            fixed_exceeded: c.fixed_ratio > 1.0,
            stat_fault: sf,
            fixed_fault: ff,
            cusum: st.stat.cusum,
        };
        (record, Some(c.z))
    }

    /// The joint chi-square test (3 degrees of freedom) of pair `pi` over its normalised
    /// differences `zs`, with its own persistence. Not compared unless all three axes were: a
    /// sum over fewer axes would need another threshold, and the per-axis tests still run.
    fn joint_test(&mut self, pi: usize, zs: [Option<f64>; 3], dt_s: f64) -> JointTest {
        let [Some(a), Some(b), Some(c)] = zs else {
            return JointTest {
                chi2: None,
                ratio: None,
                verdict: PairVerdict::NotCompared,
            };
        };
        let chi2 = a * a + b * b + c * c;
        let ratio = chi2 / self.k_joint;
        let f = self.joint[pi].update(ratio, 0.0, dt_s, &self.params.persistence);
        JointTest {
            chi2: Some(chi2),
            ratio: Some(ratio),
            verdict: if f {
                PairVerdict::Fail
            } else {
                PairVerdict::Pass
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::magnetic::FixedDeclination;

    fn checker(p: CheckParams) -> AttitudeChecker {
        let model = Box::new(FixedDeclination(Declination {
            declination_rad: 0.0,
            sigma_rad: 0.3 * DEG,
            horizontal_nt: 20_000.0,
            zone: MagneticZone::Normal,
        }));
        AttitudeChecker::new(p, model).unwrap()
    }

    /// A unit with open gates: roll, pitch, true heading (rad), their variances (rad^2) and the
    /// 1-sigma of its time (ns).
    fn unit(values: [f64; 3], var: [f64; 3], sigma_ns: f64) -> Prepared {
        Prepared {
            values: Some(values),
            heading_mag: None,
            var,
            gates: [None; 3],
            sigma_ns,
            age_s: Some(0.0),
            rates: None,
            held_s: 0.0,
        }
    }

    /// Pair inputs at time `t` (ns), 20 ms after the previous check, with no body rates and no
    /// declination, so only the units' own variances and the mountings enter the variance.
    fn inputs<'a>(t: i64, units: [&'a Prepared; 3]) -> PairInputs<'a> {
        PairInputs {
            t,
            dt_s: 0.02,
            units,
            euler_radps: [0.0; 3],
            decl_var: 0.0,
        }
    }

    fn close(got: f64, want: f64) -> bool {
        (got - want).abs() <= 1e-12 * want.abs()
    }

    #[test]
    fn each_pair_sums_its_own_terms_and_the_declination_only_with_one_magnetic_unit() {
        // Every term distinct per unit, axis and pair, so a term taken from the wrong unit, or a
        // wrong operator between two of them, shows.
        let mut p = CheckParams::default();
        p.mounting_bahrs.sigma_deg = 0.1;
        p.mounting_vn200.sigma_deg = 0.2;
        p.mounting_watson.sigma_deg = 0.4;
        // Time sigmas 44, 117 and 240 us: each pair's root sum of squares is a whole number of
        // microseconds (an Euler brick): 125 (BAHRS-VN200), 244 (BAHRS-Watson), 267 (VN200-Watson).
        let b = unit([0.0; 3], [1e-6, 2e-6, 3e-6], 44e3);
        let v = unit([0.0; 3], [4e-6, 5e-6, 6e-6], 117e3);
        let w = unit([0.0; 3], [7e-6, 8e-6, 9e-6], 240e3);
        let inp = PairInputs {
            t: 0,
            dt_s: 0.02,
            units: [&b, &v, &w],
            euler_radps: [0.1, 0.2, 0.3],
            decl_var: 2.5e-5,
        };
        // (pair, own variances of its units per axis, mounting deg^2, timing sigma s, whether the
        // heading carries the declination). The BAHRS and the Watson are both magnetic and made
        // true with the same declination: between them its error cancels; each of them against
        // the (true) VN-200 carries it.
        let cases = [
            (
                (0, 1),
                [(1e-6, 4e-6), (2e-6, 5e-6), (3e-6, 6e-6)],
                0.01 + 0.04,
                125e-6,
                true,
            ),
            (
                (0, 2),
                [(1e-6, 7e-6), (2e-6, 8e-6), (3e-6, 9e-6)],
                0.01 + 0.16,
                244e-6,
                false,
            ),
            (
                (1, 2),
                [(4e-6, 7e-6), (5e-6, 8e-6), (6e-6, 9e-6)],
                0.04 + 0.16,
                267e-6,
                true,
            ),
        ];
        for (pair, own, mount_deg2, ts, magnetic) in cases {
            for (ai, axis) in Axis::ALL.into_iter().enumerate() {
                let got = inp.variance_terms(&p, pair, ai, axis);
                let what = format!("{pair:?} {axis:?}: {got:?}");
                assert!(close(got.a, own[ai].0) && close(got.b, own[ai].1), "{what}");
                assert!(close(got.mounting, mount_deg2 * DEG * DEG), "{what}");
                assert!(close(got.timing_sigma_s, ts), "{what}");
                assert_eq!(got.rate_radps, inp.euler_radps[ai], "{what}");
                let decl = if axis == Axis::Heading && magnetic {
                    2.5e-5
                } else {
                    0.0
                };
                assert_eq!(got.declination, decl, "{what}");
            }
        }
    }

    #[test]
    fn the_exceeded_flags_are_strictly_over_the_threshold_and_the_limit() {
        let mut p = CheckParams::default();
        p.mounting_bahrs.sigma_deg = 0.0;
        p.mounting_vn200.sigma_deg = 0.0;
        // Roll variances 2^-15 rad^2 each: combined sigma 2^-7 rad, all exact in binary, so a
        // difference of k x 2^-7 rad is exactly k sigmas (ratio 1: at the threshold, not over it).
        let k = p.axis_threshold();
        let sigma = 2f64.powi(-7);
        let var = [2f64.powi(-15); 3];
        let stat = |d: f64| {
            let mut c = checker(p);
            let (b, v) = (unit([d, 0.0, 0.0], var, 0.0), unit([0.0; 3], var, 0.0));
            let (r, _) = c.compare_pair_axis(&inputs(0, [&b, &v, &v]), 0, 0, Axis::Roll);
            (r.comparison.unwrap().stat_ratio, r.stat_exceeded)
        };
        assert_eq!(stat(k * sigma), (1.0, false));
        let (ratio, exceeded) = stat((k * sigma).next_up());
        assert!(ratio > 1.0 && exceeded, "{ratio}");
        assert!(!stat((k * sigma).next_down()).1);
        // The fixed roll limit is 6 deg (issue 8), no timing term: 6 deg is at it, not over.
        let fixed = |d: f64| {
            let mut c = checker(p);
            let (b, v) = (unit([d, 0.0, 0.0], var, 0.0), unit([0.0; 3], var, 0.0));
            let (r, _) = c.compare_pair_axis(&inputs(0, [&b, &v, &v]), 0, 0, Axis::Roll);
            (r.comparison.unwrap().fixed_ratio, r.fixed_exceeded)
        };
        assert_eq!(fixed(6.0 * DEG), (1.0, false));
        let (ratio, exceeded) = fixed((6.0 * DEG).next_up());
        assert!(ratio > 1.0 && exceeded, "{ratio}");
    }

    #[test]
    fn the_heading_limit_widens_on_the_pairs_mean_bank() {
        // Issue 8: heading limit 6 deg, 12 deg while the bank exceeds 6 deg. The bank is the
        // mean of the two units' rolls.
        let limit = |roll_a_deg: f64, roll_b_deg: f64| {
            let mut c = checker(CheckParams::default());
            let b = unit([roll_a_deg * DEG, 0.0, 0.0], [1e-6; 3], 0.0);
            let v = unit([roll_b_deg * DEG, 0.0, 0.0], [1e-6; 3], 0.0);
            let (r, _) = c.compare_pair_axis(&inputs(0, [&b, &v, &v]), 0, 2, Axis::Heading);
            r.comparison.unwrap().limit_deg
        };
        let near = |x: f64, want: f64| (x - want).abs() < 1e-9;
        // Mean (2 + 2) / 2 = 2 deg: level enough.
        assert!(near(limit(2.0, 2.0), 6.0));
        // Mean (10 + 4) / 2 = 7 deg, either sign: banked (neither the difference, 3 deg, nor
        // the product would be).
        assert!(near(limit(10.0, 4.0), 12.0));
        assert!(near(limit(-4.0, -10.0), 12.0));
        // Exactly 6 deg is not over it.
        assert!(near(limit(6.0, 6.0), 6.0));
    }

    #[test]
    fn the_persistence_is_forgotten_after_a_gap_longer_than_reset_after_gap_s() {
        let p = CheckParams::default();
        assert_eq!(p.reset_after_gap_s, 5.0);
        let mut c = checker(p);
        let u = unit([0.0; 3], [1e-6; 3], 0.0);
        let t0 = 1_000_000_000_000;
        c.pairs[0][0].last_compared_ns = Some(t0);
        c.pairs[0][0].stat.cusum = 30.0;
        // Equal values, z = 0: the CUSUM loses its slack (2) a sample, 30 -> 28, when kept.
        let gap = 5_000_000_000;
        let (r, _) = c.compare_pair_axis(&inputs(t0 + gap, [&u, &u, &u]), 0, 0, Axis::Roll);
        assert_eq!(r.cusum, 28.0, "a gap of exactly 5 s keeps the state");
        let (r, _) = c.compare_pair_axis(&inputs(t0 + 2 * gap + 1, [&u, &u, &u]), 0, 0, Axis::Roll);
        assert_eq!(r.cusum, 0.0, "5 s + 1 ns resets it");
    }

    #[test]
    fn the_joint_test_sums_the_three_squared_normalised_differences() {
        let mut c = checker(CheckParams::default());
        // (-3)^2 + 4^2 + 5^2 = 50, over the chi-square(3) bound of 25.9 at 1e-5 (issue 8).
        let j = c.joint_test(0, [Some(-3.0), Some(4.0), Some(5.0)], 0.02);
        assert_eq!(j.chi2, Some(50.0));
        let ratio = j.ratio.unwrap();
        assert!((ratio - 50.0 / 25.9).abs() < 1e-3, "{ratio}");
        // Not compared unless all three axes were.
        let j = c.joint_test(1, [Some(3.0), None, Some(5.0)], 0.02);
        assert_eq!((j.chi2, j.verdict), (None, PairVerdict::NotCompared));
    }
}
