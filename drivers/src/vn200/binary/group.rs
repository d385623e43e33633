//! The `binary_group!` macro: declares one binary group as a struct with one optional field per
//! binary type, keyed by the type's bit offset in the group's type words.
//!
//! Bit offsets follow the ICD's type tables (Tables 2.3 to 2.89). Those tables number GnssRawMeas,
//! GnssStatus and GnssAltMSL 16, 17, 18, skipping 15 (the extension bit of the first type word),
//! while the example in Appendix B.1.1 counts data bits only (its offset 16 is bit 1 of the second
//! word). VectorNav's current SDK follows the tables, and so does this crate: offset `k` is bit
//! `k % 16` of type word `k / 16`, so offset 16 is bit 0 of the second type word. The combined
//! type mask used here is therefore `word0 & 0x7FFF | (word1 & 0x7FFF) << 16`.

/// Why a payload length could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LenError {
    /// A variable-length type's count is beyond the bytes available so far.
    NeedMore,
    /// The type mask selects a type this crate does not know (its size is unknown).
    UnknownType,
}

macro_rules! binary_group {
    (
        $(#[$m:meta])*
        pub struct $name:ident {
            $( $(#[$fm:meta])* $off:literal => pub $f:ident : $t:ty, )*
        }
    ) => {
        $(#[$m])*
        #[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
        pub struct $name {
            $(
                $(#[$fm])*
                #[serde(skip_serializing_if = "Option::is_none")]
                pub $f: Option<$t>,
            )*
        }

        impl $name {
            /// Mask of the type offsets this group defines (bit k = table offset k).
            pub const KNOWN: u32 = 0 $(| (1u32 << $off))*;

            /// Every type of the group: (bit offset, field name, size in bytes as in Table 2.2
            /// (one entry for variable types), variable-length).
            pub const TYPES: &'static [(u8, &'static str, usize, bool)] = &[
                $((
                    $off,
                    stringify!($f),
                    <$t as $crate::vn200::binary::wire::Wire>::SIZE,
                    <$t as $crate::vn200::binary::wire::Wire>::VARIABLE,
                ),)*
            ];

            /// The type mask (table offsets) of the fields present.
            pub fn type_mask(&self) -> u32 {
                let mut m = 0u32;
                $( if self.$f.is_some() { m |= 1u32 << $off; } )*
                m
            }

            /// Mask of the variable-length types.
            const VARIABLE_MASK: u32 = 0 $(| if <$t as $crate::vn200::binary::wire::Wire>::VARIABLE {
                1u32 << $off
            } else {
                0
            })*;

            /// Size of each fixed type by offset (0 for undefined and variable types).
            const SIZES: [u16; 32] = {
                let mut a = [0u16; 32];
                $(
                    if !<$t as $crate::vn200::binary::wire::Wire>::VARIABLE {
                        a[$off] = <$t as $crate::vn200::binary::wire::Wire>::SIZE as u16;
                    }
                )*
                a
            };

            /// Length of this group's payload for type mask `mask`, given the bytes from the
            /// start of the group's payload (only variable types look at them).
            // VARIABLE_MASK is zero for the groups without variable types.
            #[allow(clippy::bad_bit_mask)]
            #[inline(always)]
            pub(crate) fn payload_len(
                mask: u32,
                bytes: &[u8],
            ) -> Result<usize, $crate::vn200::binary::group::LenError> {
                use $crate::vn200::binary::group::LenError;
                use $crate::vn200::binary::wire::Wire;
                if mask & !Self::KNOWN != 0 {
                    return Err(LenError::UnknownType);
                }
                if mask & Self::VARIABLE_MASK == 0 {
                    // Fixed types only (the usual case): add the sizes of the set bits.
                    let mut m = mask;
                    let mut n = 0usize;
                    while m != 0 {
                        n += usize::from(Self::SIZES[(m.trailing_zeros() & 31) as usize]);
                        m &= m - 1;
                    }
                    return Ok(n);
                }
                let mut n = 0usize;
                $(
                    if mask & (1u32 << $off) != 0 {
                        // A fixed type's `wire_len` is its SIZE without looking (inlined).
                        n += <$t as Wire>::wire_len(bytes.get(n..).unwrap_or(&[]))
                            .ok_or(LenError::NeedMore)?;
                    }
                )*
                Ok(n)
            }

            /// Reads the types selected by `mask` in offset order (the caller checks the
            /// cursor for a short read). Not inlined: each group is read straight into its
            /// place in the message, which measured faster than one large inlined body.
            #[inline(never)]
            pub(crate) fn read(mask: u32, r: &mut $crate::vn200::binary::wire::Rd<'_>) -> Self {
                use $crate::vn200::binary::wire::Wire;
                Self {
                    $(
                        $f: if mask & (1u32 << $off) != 0 {
                            Some(<$t as Wire>::read(r))
                        } else {
                            None
                        },
                    )*
                }
            }

            /// Reads the types selected by `mask` into `self` in place, in offset order: every
            /// field is overwritten (the unselected ones become `None`), so the result equals
            /// [`Self::read`]'s. Not inlined, like `read`: it writes straight into the caller's
            /// message (issue 21: no group built on the stack and copied).
            #[inline(never)]
            pub(crate) fn read_into(
                &mut self,
                mask: u32,
                r: &mut $crate::vn200::binary::wire::Rd<'_>,
            ) {
                use $crate::vn200::binary::wire::Wire;
                $(
                    self.$f = if mask & (1u32 << $off) != 0 {
                        Some(<$t as Wire>::read(r))
                    } else {
                        None
                    };
                )*
            }

            /// Appends the present types in offset order.
            pub(crate) fn write(&self, out: &mut Vec<u8>) {
                use $crate::vn200::binary::wire::Wire;
                $( if let Some(v) = &self.$f { v.write(out); } )*
            }
        }
    };
}
pub(crate) use binary_group;
