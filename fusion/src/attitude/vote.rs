//! The voted attitude (issue 8): per axis, the median of the valid units, with provenance.
//!
//! Three values: the middle one (its unit is `selected`); two: their mean (no unit selected);
//! one: that value. Headings are voted on the circle: the values are taken relative to the first,
//! wrapped to +-180 deg, voted, and the result wrapped back to [0, 360).

use super::angles::{angle_diff, wrap_2pi};
use super::isolation::Unit;
use super::record::VotedAxis;

const DEG: f64 = std::f64::consts::PI / 180.0;

/// Votes over `(unit, value rad)`; `circular` for headings. `None` without any value.
pub fn vote(cands: &[(Unit, f64)], circular: bool) -> Option<VotedAxis> {
    let &(_, r0) = cands.first()?;
    let rel = |v: f64| if circular { angle_diff(v, r0) } else { v };
    // One candidate per unit, so three at most: sorted on the stack (this runs at the VN-200's
    // rate in the prompt attitude); more only through a caller passing duplicates.
    let mut small = [(Unit::Bahrs, 0.0); 3];
    let mut big = Vec::new();
    let xs: &mut [(Unit, f64)] = if cands.len() <= small.len() {
        for (d, &(u, v)) in small.iter_mut().zip(cands) {
            *d = (u, rel(v));
        }
        &mut small[..cands.len()]
    } else {
        big.extend(cands.iter().map(|&(u, v)| (u, rel(v))));
        &mut big
    };
    xs.sort_by(|a, b| a.1.total_cmp(&b.1));
    let (value, selected) = match xs.len() {
        1 => (xs[0].1, Some(xs[0].0)),
        2 => (0.5 * (xs[0].1 + xs[1].1), None),
        n => (xs[n / 2].1, (n % 2 == 1).then_some(xs[n / 2].0)),
    };
    let value = if circular {
        wrap_2pi(value + r0)
    } else {
        value
    };
    Some(VotedAxis {
        value_deg: value / DEG,
        used: cands.iter().map(|c| c.0).collect(),
        selected,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_three_two_and_one() {
        let v = vote(
            &[
                (Unit::Bahrs, 10.0 * DEG),
                (Unit::Vn200, 2.0 * DEG),
                (Unit::Watson, 3.0 * DEG),
            ],
            false,
        )
        .unwrap();
        assert!((v.value_deg - 3.0).abs() < 1e-12);
        assert_eq!(v.selected, Some(Unit::Watson));
        assert_eq!(v.used, vec![Unit::Bahrs, Unit::Vn200, Unit::Watson]);
        let v = vote(
            &[(Unit::Vn200, 2.0 * DEG), (Unit::Watson, 3.0 * DEG)],
            false,
        )
        .unwrap();
        assert!((v.value_deg - 2.5).abs() < 1e-12 && v.selected.is_none());
        let v = vote(&[(Unit::Vn200, -4.0 * DEG)], false).unwrap();
        assert!((v.value_deg + 4.0).abs() < 1e-12 && v.selected == Some(Unit::Vn200));
        assert!(vote(&[], true).is_none());
    }

    #[test]
    fn heading_vote_across_north() {
        // 358, 1 and 3 deg: the median is 1 deg (not 3, which a plain sort of 1, 3, 358 gives).
        let v = vote(
            &[
                (Unit::Bahrs, 358.0 * DEG),
                (Unit::Vn200, 1.0 * DEG),
                (Unit::Watson, 3.0 * DEG),
            ],
            true,
        )
        .unwrap();
        assert!((v.value_deg - 1.0).abs() < 1e-9, "{}", v.value_deg);
        assert_eq!(v.selected, Some(Unit::Vn200));
        // Two across north: 359 and 3 average to 1.
        let v = vote(
            &[(Unit::Bahrs, 359.0 * DEG), (Unit::Vn200, 3.0 * DEG)],
            true,
        )
        .unwrap();
        assert!((v.value_deg - 1.0).abs() < 1e-9);
    }

    #[test]
    fn more_than_three_values_the_middle_one_is_voted() {
        // Five values (a caller passing duplicates): sorted 2, 3, 5, 7, 10, the median is 5, the
        // VN-200's second value.
        let v = vote(
            &[
                (Unit::Bahrs, 10.0 * DEG),
                (Unit::Vn200, 2.0 * DEG),
                (Unit::Watson, 3.0 * DEG),
                (Unit::Bahrs, 7.0 * DEG),
                (Unit::Vn200, 5.0 * DEG),
            ],
            false,
        )
        .unwrap();
        assert!((v.value_deg - 5.0).abs() < 1e-12, "{}", v.value_deg);
        assert_eq!(v.selected, Some(Unit::Vn200));
    }
}
