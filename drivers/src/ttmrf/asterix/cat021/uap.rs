//! CAT021 edition 2.1 User Application Profile (EUROCONTROL-SPEC-0149-12, ed 2.1, 5.3): the item
//! at each Field Reference Number and its length rule.

use super::super::item::Rule;

const EXT1: Rule = Rule::Extended { first: 1, ext: 1 };

/// I021/220 Met Information subfields: wind speed, wind direction, temperature, turbulence.
const MET: &[Option<Rule>] = &[
    Some(Rule::Fixed(2)),
    Some(Rule::Fixed(2)),
    Some(Rule::Fixed(2)),
    Some(Rule::Fixed(1)),
];

/// I021/110 Trajectory Intent subfields: TIS (extended), TID (repetitive, 15 octets each).
const TRAJECTORY_INTENT: &[Option<Rule>] = &[Some(EXT1), Some(Rule::Repetitive(15))];

/// I021/295 Data Ages: 23 subfields of one octet each (AOS, TRD, M3A, QI, TI, MAM, GH, FL, ISA,
/// FSA, AS, TAS, MH, BVR, GVR, GV, TAR, TI, TS, MET, ROA, ARA, SCC).
const DATA_AGES: &[Option<Rule>] = &[Some(Rule::Fixed(1)); 23];

/// Item name and rule at each FRN (index = FRN - 1); `None` is an FRN the UAP leaves unused.
pub const UAP: [Option<(&str, Rule)>; 49] = [
    Some(("I021/010", Rule::Fixed(2))),
    Some(("I021/040", EXT1)),
    Some(("I021/161", Rule::Fixed(2))),
    Some(("I021/015", Rule::Fixed(1))),
    Some(("I021/071", Rule::Fixed(3))),
    Some(("I021/130", Rule::Fixed(6))),
    Some(("I021/131", Rule::Fixed(8))),
    // FX
    Some(("I021/072", Rule::Fixed(3))),
    Some(("I021/150", Rule::Fixed(2))),
    Some(("I021/151", Rule::Fixed(2))),
    Some(("I021/080", Rule::Fixed(3))),
    Some(("I021/073", Rule::Fixed(3))),
    Some(("I021/074", Rule::Fixed(4))),
    Some(("I021/075", Rule::Fixed(3))),
    // FX
    Some(("I021/076", Rule::Fixed(4))),
    Some(("I021/140", Rule::Fixed(2))),
    Some(("I021/090", EXT1)),
    Some(("I021/210", Rule::Fixed(1))),
    Some(("I021/070", Rule::Fixed(2))),
    Some(("I021/230", Rule::Fixed(2))),
    Some(("I021/145", Rule::Fixed(2))),
    // FX
    Some(("I021/152", Rule::Fixed(2))),
    Some(("I021/200", Rule::Fixed(1))),
    Some(("I021/155", Rule::Fixed(2))),
    Some(("I021/157", Rule::Fixed(2))),
    Some(("I021/160", Rule::Fixed(4))),
    Some(("I021/165", Rule::Fixed(2))),
    Some(("I021/077", Rule::Fixed(3))),
    // FX
    Some(("I021/170", Rule::Fixed(6))),
    Some(("I021/020", Rule::Fixed(1))),
    Some(("I021/220", Rule::Compound(MET))),
    Some(("I021/146", Rule::Fixed(2))),
    Some(("I021/148", Rule::Fixed(2))),
    Some(("I021/110", Rule::Compound(TRAJECTORY_INTENT))),
    Some(("I021/016", Rule::Fixed(1))),
    // FX
    Some(("I021/008", Rule::Fixed(1))),
    // Ed 2.1: first part and at most one extension, whose LSB is data (LW), not FX.
    Some(("I021/271", Rule::ExtendedMax(2))),
    Some(("I021/132", Rule::Fixed(1))),
    Some(("I021/250", Rule::Repetitive(8))),
    Some(("I021/260", Rule::Fixed(7))),
    Some(("I021/400", Rule::Fixed(1))),
    Some(("I021/295", Rule::Compound(DATA_AGES))),
    // FX
    None,
    None,
    None,
    None,
    None,
    Some(("I021/RE", Rule::Explicit)),
    Some(("I021/SP", Rule::Explicit)),
];

/// FRN of an item name, for tests and encoders.
pub fn frn(name: &str) -> Option<usize> {
    UAP.iter()
        .position(|e| e.is_some_and(|(n, _)| n == name))
        .map(|i| i + 1)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frns() {
        assert_eq!(frn("I021/010"), Some(1));
        assert_eq!(frn("I021/080"), Some(11));
        assert_eq!(frn("I021/090"), Some(17));
        assert_eq!(frn("I021/145"), Some(21));
        assert_eq!(frn("I021/170"), Some(29));
        assert_eq!(frn("I021/016"), Some(35));
        assert_eq!(frn("I021/295"), Some(42));
        assert_eq!(frn("I021/RE"), Some(48));
        assert_eq!(frn("I021/SP"), Some(49));
    }
}
