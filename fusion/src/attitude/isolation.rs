//! Fault isolation with three attitude sources, by pairwise verdicts.
//!
//! Pairs: BAHRS-VN200, BAHRS-Watson, VN200-Watson. Per axis:
//! - both pairs containing one unit fail and the third pair passes: that unit is isolated;
//! - exactly one pair fails (the others pass or were not compared): detected, not isolated;
//! - two pairs fail but the third was not compared: detected, not isolated (nothing confirms that
//!   the other two agree);
//! - all three pairs fail: multiple fault (no consistent pair);
//! - heading only: the BAHRS and the Watson are both magnetic. When they agree with each other and
//!   both disagree with a healthy VN-200 (true heading), the likely cause is a magnetic disturbance
//!   (or a wrong declination), not a VN-200 fault, and it is reported as such.

use serde::Serialize;

/// An attitude source.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Unit {
    /// The BAHRS baro-inertial AHRS.
    Bahrs,
    /// The VN-200 GNSS/INS.
    Vn200,
    /// The Watson AHRS-E304.
    Watson,
}

/// A set of attitude units, in the order BAHRS, VN-200, Watson: the units a voted axis used.
/// A bit set on the stack, so voting allocates nothing (issue 21: the prompt attitude runs at
/// the VN-200's rate). Serialised as the list of its units, as the `Vec` it replaced was.
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct UnitSet(u8);

impl UnitSet {
    const ALL: [Unit; 3] = [Unit::Bahrs, Unit::Vn200, Unit::Watson];

    fn bit(u: Unit) -> u8 {
        match u {
            Unit::Bahrs => 1,
            Unit::Vn200 => 2,
            Unit::Watson => 4,
        }
    }

    /// Adds `u`.
    pub fn insert(&mut self, u: Unit) {
        self.0 |= Self::bit(u);
    }

    /// Whether `u` is in the set.
    pub fn contains(&self, u: &Unit) -> bool {
        self.0 & Self::bit(*u) != 0
    }

    /// Units in the set.
    pub fn len(&self) -> usize {
        self.0.count_ones() as usize
    }

    /// Whether the set is empty.
    pub fn is_empty(&self) -> bool {
        self.0 == 0
    }

    /// The units, BAHRS first, then VN-200, then Watson.
    pub fn iter(&self) -> impl Iterator<Item = &Unit> + '_ {
        Self::ALL.iter().filter(|u| self.contains(u))
    }
}

impl FromIterator<Unit> for UnitSet {
    fn from_iter<I: IntoIterator<Item = Unit>>(it: I) -> Self {
        let mut s = Self::default();
        for u in it {
            s.insert(u);
        }
        s
    }
}

impl std::fmt::Debug for UnitSet {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.iter()).finish()
    }
}

impl PartialEq<Vec<Unit>> for UnitSet {
    fn eq(&self, other: &Vec<Unit>) -> bool {
        self.iter().eq(other.iter())
    }
}

impl Serialize for UnitSet {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_seq(self.iter())
    }
}

/// Outcome of one pairwise comparison.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PairVerdict {
    /// Compared and consistent.
    Pass,
    /// Compared and inconsistent (after persistence).
    Fail,
    /// Not compared (a gate closed: invalid, stale or frozen input).
    NotCompared,
}

/// The three pairwise verdicts of one axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Pairs {
    /// BAHRS against VN-200.
    pub bahrs_vn200: PairVerdict,
    /// BAHRS against Watson.
    pub bahrs_watson: PairVerdict,
    /// VN-200 against Watson.
    pub vn200_watson: PairVerdict,
}

/// What the pairwise verdicts of an axis say.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "unit")]
pub enum Isolation {
    /// No pair failed.
    NoFault,
    /// Fewer than one pair could be compared.
    NotCompared,
    /// A disagreement was detected but cannot be pinned on one unit.
    DetectedNotIsolated,
    /// One unit is isolated as faulty.
    Isolated(Unit),
    /// No consistent pair: more than one unit is wrong.
    MultipleFault,
    /// Heading only: the two magnetic units agree against a healthy VN-200.
    MagneticDisturbance,
    /// One pair failed while another pair of the axis exceeds its threshold without having
    /// failed yet: the outcome is held (not declared) for at most `isolation_settle_s` while
    /// that pair's persistence decides (set by the checker, never by [`isolate`]).
    Settling,
}

/// Isolates per the rules of the module. `heading` selects the magnetic rule, which needs
/// `vn200_healthy` (INS tracking without error bits).
pub fn isolate(p: &Pairs, heading: bool, vn200_healthy: bool) -> Isolation {
    use PairVerdict::{Fail, NotCompared, Pass};
    let all = [p.bahrs_vn200, p.bahrs_watson, p.vn200_watson];
    let fails = all.iter().filter(|v| **v == Fail).count();
    let compared = all.iter().filter(|v| **v != NotCompared).count();
    if compared == 0 {
        return Isolation::NotCompared;
    }
    match fails {
        0 => Isolation::NoFault,
        1 => Isolation::DetectedNotIsolated,
        3 => Isolation::MultipleFault,
        _ => {
            // Two pairs failed: the unit they share is suspect if the third pair passed.
            let (suspect, third) = if p.vn200_watson != Fail {
                (Unit::Bahrs, p.vn200_watson)
            } else if p.bahrs_watson != Fail {
                (Unit::Vn200, p.bahrs_watson)
            } else {
                (Unit::Watson, p.bahrs_vn200)
            };
            match (third, suspect) {
                (Pass, Unit::Vn200) if heading && vn200_healthy => Isolation::MagneticDisturbance,
                (Pass, u) => Isolation::Isolated(u),
                _ => Isolation::DetectedNotIsolated,
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::PairVerdict::{Fail, NotCompared as Nc, Pass};
    use super::*;

    fn p(bv: PairVerdict, bw: PairVerdict, vw: PairVerdict) -> Pairs {
        Pairs {
            bahrs_vn200: bv,
            bahrs_watson: bw,
            vn200_watson: vw,
        }
    }

    #[test]
    fn every_combination_of_verdicts() {
        // All 27 combinations, with the expected outcome written out from the rules.
        let verdicts = [Pass, Fail, Nc];
        for bv in verdicts {
            for bw in verdicts {
                for vw in verdicts {
                    let got = isolate(&p(bv, bw, vw), false, true);
                    let fails = [bv, bw, vw].iter().filter(|v| **v == Fail).count();
                    let compared = [bv, bw, vw].iter().filter(|v| **v != Nc).count();
                    let expected = if compared == 0 {
                        Isolation::NotCompared
                    } else {
                        match (fails, bv, bw, vw) {
                            (0, ..) => Isolation::NoFault,
                            (1, ..) => Isolation::DetectedNotIsolated,
                            (3, ..) => Isolation::MultipleFault,
                            (2, Fail, Fail, Pass) => Isolation::Isolated(Unit::Bahrs),
                            (2, Fail, Pass, Fail) => Isolation::Isolated(Unit::Vn200),
                            (2, Pass, Fail, Fail) => Isolation::Isolated(Unit::Watson),
                            (2, ..) => Isolation::DetectedNotIsolated, // third not compared
                            _ => unreachable!(),
                        }
                    };
                    assert_eq!(got, expected, "{bv:?} {bw:?} {vw:?}");
                }
            }
        }
    }

    #[test]
    fn magnetic_disturbance_on_heading() {
        let vn_odd_one_out = p(Fail, Pass, Fail);
        assert_eq!(
            isolate(&vn_odd_one_out, true, true),
            Isolation::MagneticDisturbance
        );
        // An unhealthy VN-200 is simply isolated.
        assert_eq!(
            isolate(&vn_odd_one_out, true, false),
            Isolation::Isolated(Unit::Vn200)
        );
        // On roll or pitch there is no magnetic excuse.
        assert_eq!(
            isolate(&vn_odd_one_out, false, true),
            Isolation::Isolated(Unit::Vn200)
        );
        // BAHRS isolated on heading stays a BAHRS fault.
        assert_eq!(
            isolate(&p(Fail, Fail, Pass), true, true),
            Isolation::Isolated(Unit::Bahrs)
        );
    }

    #[test]
    fn every_combination_on_heading_with_a_healthy_and_an_unhealthy_vn200() {
        // On heading, the only difference from the other axes: BAHRS-VN200 and VN200-Watson fail
        // while BAHRS-Watson passes -> magnetic disturbance when the VN-200 is healthy, VN-200
        // isolated when it is not. Every other combination is as on roll and pitch.
        let verdicts = [Pass, Fail, Nc];
        for healthy in [true, false] {
            for bv in verdicts {
                for bw in verdicts {
                    for vw in verdicts {
                        let pairs = p(bv, bw, vw);
                        let got = isolate(&pairs, true, healthy);
                        let expected = match (bv, bw, vw) {
                            (Fail, Pass, Fail) if healthy => Isolation::MagneticDisturbance,
                            _ => isolate(&pairs, false, healthy),
                        };
                        assert_eq!(got, expected, "{bv:?} {bw:?} {vw:?} healthy {healthy}");
                    }
                }
            }
        }
    }

    #[test]
    fn a_unit_set_is_empty_until_a_unit_goes_in_and_lists_its_units_bahrs_first() {
        let mut s = UnitSet::default();
        assert!(s.is_empty());
        assert_eq!(format!("{s:?}"), "[]");
        s.insert(Unit::Watson);
        s.insert(Unit::Bahrs);
        assert!(!s.is_empty());
        assert_eq!(s.len(), 2);
        assert_eq!(format!("{s:?}"), "[Bahrs, Watson]");
        assert!(s == vec![Unit::Bahrs, Unit::Watson]);
        assert!(s != vec![Unit::Watson, Unit::Bahrs]);
        assert!(s != vec![Unit::Bahrs]);
    }
}
