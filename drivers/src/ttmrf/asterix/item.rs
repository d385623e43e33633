//! ASTERIX record structure shared by every category (EUROCONTROL ASTERIX Part 1, 4.3 and 4.5):
//! the Field Specification (FSPEC) and the length rule of each data item, so that any item the
//! UAP defines can be skipped exactly even when vigil does not decode it.
//!
//! Length rules:
//! - fixed: a known number of octets;
//! - extended: a first part, then further parts for as long as the last octet's FX bit (bit 1)
//!   is set;
//! - repetitive: a one-octet repetition factor REP, then REP elements of fixed length;
//! - explicit: a one-octet length that counts itself (Reserved Expansion and Special Purpose
//!   fields);
//! - compound: a primary subfield (an FSPEC-like bit map with FX) followed by the subfields it
//!   marks, each with its own rule.

/// How the length of a data item (or of a compound item's subfield) is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// Fixed length, octets.
    Fixed(usize),
    /// Extended: `first` octets, then `ext` octets more while the last octet's FX bit is set.
    Extended {
        /// Octets of the first part.
        first: usize,
        /// Octets of each extension.
        ext: usize,
    },
    /// Extended with a fixed number of parts at most: like [`Rule::Extended`] with 1-octet
    /// parts, but the octet at position `max` ends the item whatever its last bit (I021/271:
    /// "the LSB in the first extension is not used as FX-bit").
    ExtendedMax(usize),
    /// One-octet REP followed by REP elements of this many octets.
    Repetitive(usize),
    /// One-octet length that includes itself.
    Explicit,
    /// Primary subfield (bits 8..2 of each octet mark subfields in order, bit 1 is FX) followed
    /// by the subfields; `None` marks a spare subfield position.
    Compound(&'static [Option<Rule>]),
}

/// Why a record could not be walked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum ItemError {
    /// The record ends inside an item or the FSPEC.
    #[error("asterix record truncated in {0}")]
    Truncated(&'static str),
    /// The FSPEC marks an FRN the category's UAP does not define.
    #[error("asterix fspec sets undefined frn {0}")]
    UndefinedFrn(usize),
    /// A compound item's primary subfield marks a subfield the item does not define.
    #[error("asterix compound item {0} sets undefined subfield {1}")]
    UndefinedSubfield(&'static str, usize),
    /// An explicit-length item declares length 0.
    #[error("asterix explicit item {0} has length 0")]
    ZeroLength(&'static str),
    /// A decoded item's content is out of its defined range.
    #[error("asterix item {0} malformed")]
    Malformed(&'static str),
}

/// Length in octets of the item at the start of `b` under `rule` (`name` names it in errors).
pub fn item_len(rule: Rule, b: &[u8], name: &'static str) -> Result<usize, ItemError> {
    let need = |n: usize| {
        if b.len() >= n {
            Ok(n)
        } else {
            Err(ItemError::Truncated(name))
        }
    };
    match rule {
        Rule::Fixed(n) => need(n),
        Rule::Extended { first, ext } => {
            let mut len = first;
            loop {
                need(len)?;
                if len == 0 || b[len - 1] & 1 == 0 {
                    return Ok(len);
                }
                len += ext.max(1);
            }
        }
        Rule::ExtendedMax(max) => {
            let mut len = 1;
            loop {
                need(len)?;
                if len >= max || b[len - 1] & 1 == 0 {
                    return Ok(len);
                }
                len += 1;
            }
        }
        Rule::Repetitive(n) => {
            let rep = usize::from(*b.first().ok_or(ItemError::Truncated(name))?);
            need(1 + rep * n)
        }
        Rule::Explicit => {
            let len = usize::from(*b.first().ok_or(ItemError::Truncated(name))?);
            if len == 0 {
                return Err(ItemError::ZeroLength(name));
            }
            need(len)
        }
        Rule::Compound(subs) => {
            let primary = fspec_len(b).ok_or(ItemError::Truncated(name))?;
            let mut len = primary;
            for index in set_bits(&b[..primary]) {
                let sub = subs
                    .get(index)
                    .copied()
                    .flatten()
                    .ok_or(ItemError::UndefinedSubfield(name, index + 1))?;
                len += item_len(sub, b.get(len..).unwrap_or(&[]), name)?;
            }
            Ok(len)
        }
    }
}

/// Length of the FSPEC (or compound primary subfield) at the start of `b`: octets up to and
/// including the first one whose FX bit is clear. `None` when `b` ends first.
pub fn fspec_len(b: &[u8]) -> Option<usize> {
    b.iter().position(|&o| o & 1 == 0).map(|i| i + 1)
}

/// Zero-based indices (FRN - 1) of the bits set in an FSPEC, in order: bits 8..2 of each octet.
pub fn set_bits(fspec: &[u8]) -> impl Iterator<Item = usize> + '_ {
    fspec.iter().enumerate().flat_map(|(octet, &o)| {
        (0..7).filter_map(move |bit| (o & (0x80 >> bit) != 0).then_some(octet * 7 + bit))
    })
}

/// Builds an FSPEC from zero-based FRN indices (any order; duplicates allowed) and appends it
/// to `out`. An empty set gives one zero octet.
pub fn push_fspec(indices: &[usize], out: &mut Vec<u8>) {
    let octets = indices.iter().map(|i| i / 7 + 1).max().unwrap_or(1);
    let start = out.len();
    out.resize(start + octets, 0);
    for &i in indices {
        out[start + i / 7] |= 0x80 >> (i % 7);
    }
    for o in &mut out[start..start + octets - 1] {
        *o |= 1;
    }
}

/// Reads a big-endian unsigned integer of 1..=8 octets.
pub fn be_u64(b: &[u8]) -> u64 {
    b.iter().fold(0u64, |acc, &x| (acc << 8) | u64::from(x))
}

/// Sign-extends the low `bits` bits of `v`.
pub fn sign_extend(v: u64, bits: u32) -> i64 {
    let shift = 64 - bits;
    ((v << shift) as i64) >> shift
}

/// Appends the low `octets` octets of `v`, big-endian.
pub fn push_be(v: u64, octets: usize, out: &mut Vec<u8>) {
    for i in (0..octets).rev() {
        out.push((v >> (8 * i)) as u8);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SUBS: &[Option<Rule>] = &[
        Some(Rule::Fixed(2)),
        None,
        Some(Rule::Repetitive(3)),
        Some(Rule::Extended { first: 1, ext: 1 }),
    ];

    #[test]
    fn fixed_and_extended() {
        assert_eq!(item_len(Rule::Fixed(3), &[1, 2, 3, 4], "x"), Ok(3));
        assert_eq!(
            item_len(Rule::Fixed(3), &[1, 2], "x"),
            Err(ItemError::Truncated("x"))
        );
        let ext = Rule::Extended { first: 1, ext: 1 };
        // 0x01 has FX set, 0x40 does not: two octets.
        assert_eq!(item_len(ext, &[0x01, 0x40, 0xFF], "x"), Ok(2));
        assert_eq!(item_len(ext, &[0x00], "x"), Ok(1));
        assert_eq!(
            item_len(ext, &[0x01, 0x01], "x"),
            Err(ItemError::Truncated("x"))
        );
        // A 2-octet first part whose second octet carries FX, 1-octet extensions (I023/101).
        let ext2 = Rule::Extended { first: 2, ext: 1 };
        assert_eq!(item_len(ext2, &[0xFF, 0x01, 0x02], "x"), Ok(3));
        assert_eq!(item_len(ext2, &[0x01, 0x00], "x"), Ok(2));
        // At most 2 octets: the second octet's LSB (set here) is data, not FX.
        let max2 = Rule::ExtendedMax(2);
        assert_eq!(item_len(max2, &[0x01, 0x03, 0xFF], "x"), Ok(2));
        assert_eq!(item_len(max2, &[0x02, 0x03], "x"), Ok(1));
        assert_eq!(item_len(max2, &[0x01], "x"), Err(ItemError::Truncated("x")));
    }

    #[test]
    fn repetitive_and_explicit() {
        // REP 2 of 8-octet elements: 1 + 16.
        let b = [2u8; 17];
        assert_eq!(item_len(Rule::Repetitive(8), &b, "x"), Ok(17));
        assert_eq!(
            item_len(Rule::Repetitive(8), &b[..16], "x"),
            Err(ItemError::Truncated("x"))
        );
        assert_eq!(item_len(Rule::Repetitive(8), &[0], "x"), Ok(1));
        assert_eq!(
            item_len(Rule::Explicit, &[5, 8, 0xF0, 0x01, 0x62], "x"),
            Ok(5)
        );
        assert_eq!(
            item_len(Rule::Explicit, &[0, 1], "x"),
            Err(ItemError::ZeroLength("x"))
        );
        assert_eq!(
            item_len(Rule::Explicit, &[], "x"),
            Err(ItemError::Truncated("x"))
        );
    }

    #[test]
    fn compound() {
        // Primary 0xB0 = 1011 0000: subfields 1 (2 octets), 3 (REP 1 x 3), 4 (extended, 1).
        let b = [0xB0, 0xAA, 0xBB, 0x01, 1, 2, 3, 0x00, 0x99];
        assert_eq!(item_len(Rule::Compound(SUBS), &b, "c"), Ok(8));
        // Subfield 2 is spare: error.
        assert_eq!(
            item_len(Rule::Compound(SUBS), &[0x40, 0], "c"),
            Err(ItemError::UndefinedSubfield("c", 2))
        );
        // Primary with FX to a second octet that marks subfield 8 (undefined here).
        assert_eq!(
            item_len(Rule::Compound(SUBS), &[0x01, 0x80], "c"),
            Err(ItemError::UndefinedSubfield("c", 8))
        );
        assert_eq!(
            item_len(Rule::Compound(SUBS), &[0x80, 0xAA], "c"),
            Err(ItemError::Truncated("c"))
        );
    }

    #[test]
    fn fspec_bits() {
        // 0xC5 1D 04 = FRNs 1, 2, 6 | 11, 12, 13 | 20 (third octet bit 3 -> index 14 + 5).
        let f = [0xC5, 0x1D, 0x04];
        assert_eq!(fspec_len(&f), Some(3));
        let bits: Vec<usize> = set_bits(&f).collect();
        assert_eq!(bits, vec![0, 1, 5, 10, 11, 12, 19]);
        let mut out = Vec::new();
        push_fspec(&bits, &mut out);
        assert_eq!(out, f);
        assert_eq!(fspec_len(&[0x01, 0x01]), None);
        let mut out = Vec::new();
        push_fspec(&[], &mut out);
        assert_eq!(out, [0]);
    }

    #[test]
    fn integers() {
        assert_eq!(be_u64(&[0x12, 0x34, 0x56]), 0x123456);
        assert_eq!(sign_extend(0xFFFFFF, 24), -1);
        assert_eq!(sign_extend(0x800000, 24), -8_388_608);
        assert_eq!(sign_extend(0x7FFF, 16), 32767);
        let mut out = Vec::new();
        push_be(0x123456, 3, &mut out);
        assert_eq!(out, [0x12, 0x34, 0x56]);
    }
}
