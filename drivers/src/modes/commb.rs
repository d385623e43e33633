//! Comm-B replies (DF20/21): recognising the aircraft identification register BDS 2,0
//! (ICAO Doc 9871, A.2.2.2). A Comm-B MB field carries no register number, so BDS 2,0 is
//! inferred: first byte 0x20, all eight characters assigned codes, not all spaces. A register
//! that fails these tests is left undecoded (we never guess).

use super::ident::Callsign;

/// The callsign of a BDS 2,0 MB field, if the field is recognisably one.
#[inline]
pub fn bds20_callsign(mb: u64) -> Option<Callsign> {
    if (mb >> 48) != 0x20 {
        return None;
    }
    let c = Callsign::from_bits48(mb & 0xFFFF_FFFF_FFFF);
    (c.valid && !c.as_str().is_empty()).then_some(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recognises_bds20() {
        let mb = (0x20u64 << 48) | Callsign::encode("AFL032").unwrap();
        assert_eq!(bds20_callsign(mb).unwrap().as_str(), "AFL032");
        // Wrong register number, an unassigned character, all spaces.
        assert!(bds20_callsign((0x21u64 << 48) | Callsign::encode("AFL032").unwrap()).is_none());
        assert!(bds20_callsign(0x20u64 << 48).is_none());
        assert!(bds20_callsign((0x20u64 << 48) | Callsign::encode("").unwrap()).is_none());
        // From the ulss7 capture: DF21 with MB 00000000000000 is not BDS 2,0.
        assert!(bds20_callsign(0).is_none());
    }
}
