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
