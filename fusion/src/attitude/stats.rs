//! Detection thresholds from a false-alarm probability: the two-sided Gaussian bound per axis and
//! the chi-square bound with 3 degrees of freedom for the joint test.
//!
//! Closed forms used (so no table is needed):
//! - per axis, `P(|z| > k) = erfc(k / sqrt 2)`;
//! - chi-square with 3 degrees of freedom, `P(X > c) = erfc(sqrt(c/2)) + sqrt(2c/pi) exp(-c/2)`.
//!
//! Both are decreasing in the threshold, so the threshold for a probability is found by bisection
//! to full double precision.

/// Two-sided tail probability of a standard normal variable: `P(|z| > k)`.
pub fn normal_two_sided_tail(k: f64) -> f64 {
    libm::erfc(k / std::f64::consts::SQRT_2)
}

/// Upper tail of a chi-square variable with 3 degrees of freedom: `P(X > c)`.
pub fn chi2_3_tail(c: f64) -> f64 {
    if c <= 0.0 {
        return 1.0;
    }
    libm::erfc((c / 2.0).sqrt()) + (2.0 * c / std::f64::consts::PI).sqrt() * (-c / 2.0).exp()
}

/// The smallest `x` in `[0, hi]` with `tail(x) <= p`, by bisection (tail decreasing).
fn invert(tail: impl Fn(f64) -> f64, p: f64, hi: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, hi);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if tail(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    hi
}

/// Per-axis threshold `k` (in sigmas) for a two-sided false-alarm probability `p_fa` per sample.
pub fn axis_threshold(p_fa: f64) -> f64 {
    invert(normal_two_sided_tail, p_fa.clamp(1e-300, 1.0), 40.0)
}

/// Joint chi-square (3 dof) threshold for a false-alarm probability `p_fa` per sample.
pub fn joint_threshold(p_fa: f64) -> f64 {
    invert(chi2_3_tail, p_fa.clamp(1e-300, 1.0), 2000.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_quantiles() {
        // Standard tables: P(|z| > 1.959964) = 0.05; P(|z| > 2.575829) = 0.01.
        assert!((axis_threshold(0.05) - 1.959_964).abs() < 1e-6);
        assert!((axis_threshold(0.01) - 2.575_829).abs() < 1e-6);
        // The defaults: 1e-5 per sample gives 4.42 sigma per axis and 25.9 jointly.
        assert!(
            (axis_threshold(1e-5) - 4.417_173).abs() < 1e-5,
            "{}",
            axis_threshold(1e-5)
        );
        // Chi-square 3 dof table values: 7.814728 at 0.05, 11.344867 at 0.01, 16.266236 at 0.001.
        assert!((joint_threshold(0.05) - 7.814_728).abs() < 1e-5);
        assert!((joint_threshold(0.01) - 11.344_867).abs() < 1e-5);
        assert!((joint_threshold(0.001) - 16.266_236).abs() < 1e-5);
        assert!(
            (joint_threshold(1e-5) - 25.9).abs() < 0.05,
            "{}",
            joint_threshold(1e-5)
        );
    }

    #[test]
    fn chi2_tail_is_the_sum_of_three_squared_normals() {
        // For 1 dof the tail is erfc(sqrt(c/2)); the 3-dof closed form must exceed it and agree
        // with the known median 2.365974.
        assert!((chi2_3_tail(2.365_974) - 0.5).abs() < 1e-6);
        assert!(chi2_3_tail(4.0) > normal_two_sided_tail(2.0));
        assert_eq!(chi2_3_tail(0.0), 1.0);
    }

    #[test]
    fn at_a_false_alarm_probability_of_one_both_thresholds_are_zero() {
        // p = 1 (the top of the clamp): every tail value is <= 1, so the smallest threshold with
        // tail <= p is 0. Near 0 both tails round to exactly 1.0 over a span of doubles (up to
        // about 1e-16 sigmas, 1e-10 for the chi-square), so this also tells "tail <= p" from
        // "tail < p", which would stop at the end of that span.
        assert!(axis_threshold(1.0) < 1e-50, "{}", axis_threshold(1.0));
        assert!(joint_threshold(1.0) < 1e-50, "{}", joint_threshold(1.0));
    }
}
