//! Altitude codes: the 13-bit AC field of DF0/4/16/20 (ICAO Annex 10 Vol IV, 3.1.2.6.5.4) and the
//! 12-bit altitude of the airborne position squitter (DO-260B 2.2.3.2.3.4).
//!
//! Bit layout of AC13, most significant first (the Gillham pulse names):
//!
//! ```text
//!  12  11  10   9   8   7   6   5   4   3   2   1   0
//!  C1  A1  C2  A2  C4  A4  M   B1  Q   B2  D2  B4  D4      (Q holds D1 when Q = 0)
//! ```
//!
//! - all zero: altitude not available;
//! - M = 0, Q = 1: 11-bit binary N, altitude = 25 N - 1000 ft (so -1000 ft .. 50 175 ft);
//! - M = 0, Q = 0: Gillham (Gray) code in 100 ft steps, -1200 ft .. 126 700 ft;
//! - M = 1: metric altitude. Its coding is not defined precisely enough in the documents we have,
//!   and no transponder we know uses it: decision, reported as unavailable (`None`).
//!
//! AC12 is AC13 without the M bit.

/// Feet from a 13-bit AC field (DF0/4/16/20), `None` when unavailable or not decodable.
#[inline]
pub fn decode_ac13(ac13: u16) -> Option<i32> {
    let ac13 = ac13 & 0x1FFF;
    if ac13 == 0 || ac13 & 0x0040 != 0 {
        return None;
    }
    if ac13 & 0x0010 != 0 {
        // Q = 1: remove M (bit 6) and Q (bit 4).
        let n = ((ac13 & 0x1F80) >> 2) | ((ac13 & 0x0020) >> 1) | (ac13 & 0x000F);
        return Some(i32::from(n) * 25 - 1000);
    }
    gillham_to_feet(ac13)
}

/// Feet from a 12-bit ME altitude field (airborne position), `None` when unavailable.
#[inline]
pub fn decode_ac12(ac12: u16) -> Option<i32> {
    decode_ac13(ac12_to_ac13(ac12))
}

/// Inserts a zero M bit into an AC12 field.
#[inline]
pub fn ac12_to_ac13(ac12: u16) -> u16 {
    ((ac12 & 0x0FC0) << 1) | (ac12 & 0x003F)
}

/// Removes the M bit from an AC13 field.
#[inline]
pub fn ac13_to_ac12(ac13: u16) -> u16 {
    ((ac13 & 0x1F80) >> 1) | (ac13 & 0x003F)
}

/// Gray code to binary.
#[inline]
fn gray_to_binary(mut g: u32) -> u32 {
    let mut b = g;
    while g > 1 {
        g >>= 1;
        b ^= g;
    }
    b
}

/// Gillham code (AC13 with M = 0, Q = 0; bit 4 holds D1) to feet.
///
/// The 500 ft rings are the Gray code D1 D2 D4 A1 A2 A4 B1 B2 B4; the 100 ft steps within a ring
/// are the "five-cycle" code C1 C2 C4, whose Gray value 1..4 (and 7, read as 5) counts up in even
/// rings and down in odd rings. Gray 0, 5 and 6 are illegal.
fn gillham_to_feet(ac13: u16) -> Option<i32> {
    let bit = |n: u16| u32::from((ac13 >> n) & 1);
    let (c1, a1, c2, a2, c4, a4) = (bit(12), bit(11), bit(10), bit(9), bit(8), bit(7));
    let (b1, b2, d2, b4, d4) = (bit(5), bit(3), bit(2), bit(1), bit(0));
    // D1, the Gray code's top bit, shares bit 4 with Q, and this path has Q = 0: D1 is always
    // 0 here (ICAO: "D1 not used"), which is why the code ends at 126 700 ft.
    let g500 =
        (d2 << 7) | (d4 << 6) | (a1 << 5) | (a2 << 4) | (a4 << 3) | (b1 << 2) | (b2 << 1) | b4;
    let g100 = (c1 << 2) | (c2 << 1) | c4;
    let n500 = gray_to_binary(g500) as i32;
    let mut n100 = match gray_to_binary(g100) {
        0 | 5 | 6 => return None,
        7 => 5,
        n => n as i32,
    };
    if n500 % 2 == 1 {
        n100 = 6 - n100;
    }
    Some(n500 * 500 + n100 * 100 - 1300)
}

/// The 12-bit ME altitude field for `alt_ft` in 25 ft steps (Q = 1), rounding to the nearest
/// step; `None` outside -1000 .. 50 175 ft (where Gillham coding would be needed).
pub fn encode_ac12_q25(alt_ft: i32) -> Option<u16> {
    let n = (alt_ft + 1000 + 12).div_euclid(25);
    if !(0..=0x7FF).contains(&n) {
        return None;
    }
    let n = n as u16;
    Some(((n & 0x7F0) << 1) | 0x0010 | (n & 0x000F))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn q_bit_25ft() {
        // Hand computation: N = 1520 -> 1520 * 25 - 1000 = 37 000 ft. N = 0b101_1111_0000:
        // AC12 = N[10:4] << 5 | Q << 4 | N[3:0] = 0b1011111_1_0000 = 0xBF0.
        assert_eq!(decode_ac12(0xBF0), Some(37_000));
        // The published example 8D40621D58C382D690C8AC2863A7 has ALT field 0xC38 -> 38 000 ft.
        assert_eq!(decode_ac12(0xC38), Some(38_000));
        // N = 0 with Q = 1: -1000 ft (negative altitudes are legal).
        assert_eq!(decode_ac12(0x010), Some(-1000));
        // N = 39: 39 * 25 - 1000 = -25 ft. N = 0b100111 -> AC12 = 0b10_1_0111 = 0x57.
        assert_eq!(decode_ac12(0x057), Some(-25));
        // Unavailable.
        assert_eq!(decode_ac12(0), None);
        assert_eq!(decode_ac13(0), None);
    }

    #[test]
    fn ac13_from_the_capture() {
        // dump1090 on the ulss7 capture: "DF:0 ... AC:1177 ... Altitude: 6425 ft", "AC:563 ->
        // 2675 ft", "AC:1296 -> 7000 ft", "AC:5136 -> 31000 ft" (AC printed in decimal).
        // By hand for 5136 = 0x1410: Q set, N = 0x1400 >> 2 = 1280 -> 1280 * 25 - 1000.
        assert_eq!(decode_ac13(1177), Some(6425));
        assert_eq!(decode_ac13(563), Some(2675));
        assert_eq!(decode_ac13(1296), Some(7000));
        assert_eq!(decode_ac13(5136), Some(31_000));
    }

    #[test]
    fn metric_is_unavailable() {
        assert_eq!(decode_ac13(0x0040 | 0x0010 | 0x0100), None);
    }

    #[test]
    fn gillham_hand_computed() {
        // -1200 ft: ring n500 = 0, step n100 = 1 -> C1 C2 C4 Gray of 1 = 0b001 -> only C4 set.
        assert_eq!(decode_ac13(1 << 8), Some(-1200));
        // -1000 ft: n500 = 0, n100 = 3 -> Gray(3) = 0b010 -> C2.
        assert_eq!(decode_ac13(1 << 10), Some(-1000));
        // 0 ft: -1300 + 500 n500 + 100 n100 = 0 -> n500 = 2, n100 = 3 (even ring counts up).
        // Gray(2) = 0b11 -> B2 B4 set; C2 set.
        assert_eq!(decode_ac13((1 << 3) | (1 << 1) | (1 << 10)), Some(0));
        // 100 ft: n500 = 2 (even), n100 = 4 -> Gray(4) = 0b110 -> C1 C2.
        assert_eq!(
            decode_ac13((1 << 3) | (1 << 1) | (1 << 12) | (1 << 10)),
            Some(100)
        );
        // Odd ring counts down: n500 = 1 (Gray 0b1 -> B4), C4 only (n100 = 1 -> 6-1 = 5):
        // -1300 + 500 + 500 = -300 ft.
        assert_eq!(decode_ac13((1 << 1) | (1 << 8)), Some(-300));
        // Illegal C code 0 (no C pulse).
        assert_eq!(decode_ac13(1 << 1), None);
        // C1 alone is Gray 0b100 = binary 7, read as step 5: n500 = 0 -> -1300 + 500 = -800 ft.
        assert_eq!(decode_ac13(1 << 12), Some(-800));
        // C1 C2 C4 all set is Gray 0b111 = binary 5: illegal.
        assert_eq!(decode_ac13((1 << 12) | (1 << 10) | (1 << 8)), None);
    }

    #[test]
    fn gillham_agrees_with_q25_on_every_100ft() {
        // Build Gillham codes from altitude by the inverse mapping and check monotonicity.
        let mut seen = std::collections::BTreeMap::new();
        for ac in 0u16..0x2000 {
            if ac & 0x0050 != 0 {
                continue; // M or Q set
            }
            if let Some(ft) = decode_ac13(ac) {
                assert_eq!(ft % 100, 0);
                assert!((-1200..=126_700).contains(&ft), "{ac:#x} {ft}");
                assert!(seen.insert(ft, ac).is_none(), "two codes for {ft}");
            }
        }
        // Without D1 (bit 4 = Q position, used only when Q=0 anyway) every 100 ft step from
        // -1200 to 62 700 ft has a code.
        for ft in (-1200..=62_700).step_by(100) {
            assert!(seen.contains_key(&ft), "{ft}");
        }
    }

    #[test]
    fn encode_round_trip() {
        for ft in (-1000..=50_175).step_by(25) {
            let ac = encode_ac12_q25(ft).unwrap();
            assert_eq!(decode_ac12(ac), Some(ft));
        }
        assert_eq!(encode_ac12_q25(-1025), None);
        assert_eq!(encode_ac12_q25(50_200), None);
        assert_eq!(ac13_to_ac12(ac12_to_ac13(0xABC)), 0xABC);
    }
}
