//! Checksums of the VN-200 protocols (ICD 1.4).
//!
//! - 8-bit XOR (1.4.2): ASCII sentences, over the bytes between `$` and `*`.
//! - 16-bit CRC (1.4.3): CRC16-CCITT as given by the ICD's C snippet, which is the XMODEM variant
//!   (polynomial 0x1021, initial value 0, no reflection, no final XOR). Used for every binary
//!   message (over header and payload, sent big-endian so that the CRC over header, payload and
//!   CRC is zero) and, when Register 30 selects it, for ASCII sentences (four hex digits).
//!
//! The CRC is table-driven (slice-by-16 from the `crc` crate): it is the hot path of the binary
//! decoder.

/// CRC-16/XMODEM with a slice-by-16 table (about 8 KiB, built at compile time).
const CRC16: crc::Crc<u16, crc::Table<16>> =
    crc::Crc::<u16, crc::Table<16>>::new(&crc::CRC_16_XMODEM);

/// The ICD's 16-bit CRC (CRC16-CCITT, XMODEM variant) of `bytes`.
///
/// The table loop takes 16 bytes at a time and the remainder one byte at a time, a serial chain
/// that dominated a 111-byte message. With an initial value of 0 and no reflection, leading zero
/// bytes leave the CRC unchanged, so the remainder is moved to the front as one zero-padded
/// 16-byte block and everything runs through the 16-byte loop.
#[inline]
pub fn crc16(bytes: &[u8]) -> u16 {
    let rem = bytes.len() % 16;
    let (head, body) = bytes.split_at(rem);
    if rem == 0 {
        return CRC16.checksum(body);
    }
    let mut block = [0u8; 16];
    block[16 - rem..].copy_from_slice(head);
    let mut digest = CRC16.digest();
    digest.update(&block);
    digest.update(body);
    digest.finalize()
}

/// The ICD's 8-bit XOR checksum of `bytes`.
#[inline]
pub fn xor8(bytes: &[u8]) -> u8 {
    bytes.iter().fold(0, |acc, b| acc ^ b)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The ICD's C snippet (1.4.3) transcribed literally, to check the table-driven CRC against.
    fn crc16_icd_snippet(data: &[u8]) -> u16 {
        let mut crc: u16 = 0;
        for &b in data {
            crc = crc.rotate_left(8); // the byte swap of the snippet
            crc ^= u16::from(b);
            crc ^= (crc & 0xff) >> 4;
            crc ^= crc << 12;
            crc ^= (crc & 0x00ff) << 5;
        }
        crc
    }

    #[test]
    fn crc16_matches_the_icd_snippet_and_the_check_value() {
        // CRC-16/XMODEM check value of "123456789" is 0x31C3 (CRC catalogue).
        assert_eq!(crc16(b"123456789"), 0x31C3);
        assert_eq!(crc16_icd_snippet(b"123456789"), 0x31C3);
        let mut rng = crate::testkit::XorShift::new(7);
        for len in 0..200 {
            let mut v = vec![0u8; len];
            rng.fill(&mut v);
            assert_eq!(crc16(&v), crc16_icd_snippet(&v), "len {len}");
        }
    }

    #[test]
    fn figure_a2_crc_is_zero_over_header_payload_and_crc() {
        // Figure A.2: FA 01 08 00 | Ypr floats | CRC 0x9288 (big-endian).
        let msg = [
            0x01, 0x08, 0x00, 0x93, 0x50, 0x2E, 0x42, 0x83, 0x3E, 0xF1, 0x3F, 0x48, 0xB5, 0x04,
            0xBB, 0x92, 0x88,
        ];
        assert_eq!(crc16(&msg[..15]), 0x9288);
        assert_eq!(crc16(&msg), 0);
    }

    #[test]
    fn xor8_of_icd_examples() {
        // "$VNRRG,5*46" (1.3.1): XOR of "VNRRG,5" is 0x46.
        assert_eq!(xor8(b"VNRRG,5"), 0x46);
        // "$VNWNV*57" (1.3.3).
        assert_eq!(xor8(b"VNWNV"), 0x57);
    }
}
