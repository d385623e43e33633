//! The 13-bit identity (Mode A code, "squawk") field of DF5/21 and of the TC 28 emergency
//! squitter (ICAO Annex 10 Vol IV, 3.1.2.6.7.1).
//!
//! Layout, most significant first: `C1 A1 C2 A2 C4 A4 X B1 D1 B2 D2 B4 D4`; each of the four
//! octal digits is `x4 x2 x1`.

use serde::Serialize;

/// A Mode A code: four octal digits, held as 0xABCD (one digit per nibble) so that `{:04X}`
/// prints it the way pilots say it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
pub struct Squawk(pub u16);

impl Squawk {
    /// Decodes an ID13 field.
    #[inline]
    pub fn from_id13(id13: u16) -> Self {
        let bit = |n: u16| (id13 >> n) & 1;
        let a = (bit(7) << 2) | (bit(9) << 1) | bit(11);
        let b = (bit(1) << 2) | (bit(3) << 1) | bit(5);
        let c = (bit(8) << 2) | (bit(10) << 1) | bit(12);
        let d = (bit(0) << 2) | (bit(2) << 1) | bit(4);
        Squawk((a << 12) | (b << 8) | (c << 4) | d)
    }

    /// Encodes as an ID13 field (the X bit 6 is zero).
    pub fn to_id13(self) -> u16 {
        let digit = |shift: u16| (self.0 >> shift) & 7;
        let (a, b, c, d) = (digit(12), digit(8), digit(4), digit(0));
        let put = |v: u16, b4: u16, b2: u16, b1: u16| {
            (((v >> 2) & 1) << b4) | (((v >> 1) & 1) << b2) | ((v & 1) << b1)
        };
        put(a, 7, 9, 11) | put(b, 1, 3, 5) | put(c, 8, 10, 12) | put(d, 0, 2, 4)
    }

    /// The code as four decimal digits, e.g. 7700 (the form `TrafficReport::squawk` uses).
    pub fn as_decimal(self) -> u16 {
        let d = |s: u16| (self.0 >> s) & 0xF;
        d(12) * 1000 + d(8) * 100 + d(4) * 10 + d(0)
    }

    /// The code as it is written: four octal digits.
    pub fn digits(self) -> [u8; 4] {
        let d = |s: u16| b'0' + ((self.0 >> s) & 7) as u8;
        [d(12), d(8), d(4), d(0)]
    }
}

impl std::fmt::Display for Squawk {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{:04X}", self.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn capture_example() {
        // dump1090: "DF:5 ... ID:6165 ... Squawk: 1017"; 6165 = 0x1815
        // = C1 A1 . . . . . . D1 . D2 . D4 -> A=1, B=0, C=1, D=7.
        let s = Squawk::from_id13(6165);
        assert_eq!(s.to_string(), "1017");
        assert_eq!(s.as_decimal(), 1017);
        // Every digit in its decimal place.
        assert_eq!(Squawk(0x7654).as_decimal(), 7654);
        // "DF:21 ... ID:4922 ... Squawk: 2751"
        assert_eq!(Squawk::from_id13(4922).to_string(), "2751");
    }

    #[test]
    fn round_trip_all_codes() {
        for code in 0u16..4096 {
            let s = Squawk(
                ((code >> 9) & 7) << 12
                    | ((code >> 6) & 7) << 8
                    | ((code >> 3) & 7) << 4
                    | (code & 7),
            );
            let id = s.to_id13();
            assert_eq!(id & 0x40, 0);
            assert_eq!(Squawk::from_id13(id), s);
        }
        assert_eq!(&Squawk(0x7700).digits(), b"7700");
    }
}
