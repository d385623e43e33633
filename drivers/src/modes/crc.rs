//! Mode S parity: the 24-bit CRC of ICAO Annex 10 Vol IV, 3.1.2.3.3 (generator polynomial
//! 0x1FFF409, written here without its top bit as 0xFFF409).
//!
//! The last 24 bits of every Mode S frame are parity. For DF11/17/18 the parity field is the CRC
//! itself (DF11 may have the interrogator code II/SI XORed into the low 7 bits), so the
//! [`syndrome`] of a clean frame is zero (or the II/SI code). For DF0/4/5/16/20/21 the parity field
//! is the CRC XORed with the aircraft address (address/parity, AP), so the syndrome *is* the
//! address: it can be recovered, but not verified from the frame alone.
//!
//! Table-driven, one byte per step: 11 table lookups for a long frame.

/// The generator polynomial without its x^24 term.
pub const POLY: u32 = 0xFF_F409;

/// Byte-at-a-time remainder table.
static TABLE: [u32; 256] = build_table();

const fn build_table() -> [u32; 256] {
    let mut t = [0u32; 256];
    let mut i = 0;
    while i < 256 {
        let mut c = (i as u32) << 16;
        let mut k = 0;
        while k < 8 {
            c = if c & 0x80_0000 != 0 {
                (c << 1) ^ POLY
            } else {
                c << 1
            };
            k += 1;
        }
        t[i] = c & 0xFF_FFFF;
        i += 1;
    }
    t
}

/// The 24-bit CRC remainder of `data` (the bits before the parity field).
#[inline]
pub fn remainder(data: &[u8]) -> u32 {
    let mut crc = 0u32;
    for &b in data {
        crc = ((crc << 8) & 0xFF_FFFF) ^ TABLE[(((crc >> 16) as u8) ^ b) as usize];
    }
    crc
}

/// The syndrome of a whole frame: CRC of the data bits XOR the transmitted parity field.
/// Zero for a clean DF17/18 frame; the address for an AP frame. Frames shorter than 4 bytes
/// give 0xFFFFFFFF (never a valid syndrome).
#[inline]
pub fn syndrome(frame: &[u8]) -> u32 {
    let n = frame.len();
    if n < 4 {
        return u32::MAX;
    }
    let (data, parity) = frame.split_at(n - 3);
    let p = (u32::from(parity[0]) << 16) | (u32::from(parity[1]) << 8) | u32::from(parity[2]);
    remainder(data) ^ p
}

/// Syndromes of single-bit errors in a 112-bit frame, indexed by bit (0 = first bit sent).
static SINGLE_BIT_112: [u32; 112] = build_single_bit();

const fn build_single_bit() -> [u32; 112] {
    let mut out = [0u32; 112];
    let mut bit = 0;
    while bit < 112 {
        let mut f = [0u8; 14];
        f[bit / 8] = 0x80 >> (bit % 8);
        // Same computation as `syndrome`, written out for const evaluation.
        let mut crc = 0u32;
        let mut i = 0;
        while i < 11 {
            crc = ((crc << 8) & 0xFF_FFFF) ^ TABLE[(((crc >> 16) as u8) ^ f[i]) as usize];
            i += 1;
        }
        out[bit] = crc ^ ((f[11] as u32) << 16 | (f[12] as u32) << 8 | f[13] as u32);
        bit += 1;
    }
    out
}

/// The bit (0 = first bit sent) whose flip would explain `syndrome` in a 112-bit frame, if one
/// does. Bits 0..5 (the DF field) are never returned: a "corrected" DF would be a different
/// frame, not a repaired one.
pub fn single_bit_error_112(syndrome: u32) -> Option<usize> {
    if syndrome == 0 {
        return None;
    }
    SINGLE_BIT_112
        .iter()
        .enumerate()
        .skip(5)
        .find(|&(_, &s)| s == syndrome)
        .map(|(i, _)| i)
}

/// Writes the parity field of a frame whose parity is the plain CRC (DF11 with II = 0, DF17,
/// DF18), XORed with `overlay` (the II/SI code for DF11, the address for AP frames).
pub fn set_parity(frame: &mut [u8], overlay: u32) {
    let n = frame.len();
    if n < 4 {
        return;
    }
    let p = remainder(&frame[..n - 3]) ^ (overlay & 0xFF_FFFF);
    frame[n - 3] = (p >> 16) as u8;
    frame[n - 2] = (p >> 8) as u8;
    frame[n - 1] = p as u8;
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::modes::hex_frame;

    /// Bit-at-a-time long division, written independently of the table.
    fn slow_remainder(data: &[u8]) -> u32 {
        let mut reg: u32 = 0;
        for &b in data {
            for k in (0..8).rev() {
                let inbit = u32::from((b >> k) & 1);
                let top = (reg >> 23) & 1;
                reg = (reg << 1) & 0xFF_FFFF;
                if top ^ inbit == 1 {
                    reg ^= POLY;
                }
            }
        }
        reg
    }

    #[test]
    fn table_matches_bitwise_division() {
        let mut rng = crate::testkit::XorShift::new(7);
        for len in 0..12 {
            let mut d = vec![0u8; len];
            rng.fill(&mut d);
            assert_eq!(remainder(&d), slow_remainder(&d), "{d:02X?}");
        }
    }

    #[test]
    fn published_frames_check_to_zero() {
        // Classic examples (The 1090 MHz Riddle; ICAO/EUROCONTROL material).
        for h in [
            "8D4840D6202CC371C32CE0576098",
            "8D40621D58C382D690C8AC2863A7",
            "8D40621D58C386435CC412692AD6",
            "8D485020994409940838175B284F",
            "8DA05F219B06B6AF189400CBC33F",
        ] {
            let (f, n) = hex_frame(h);
            assert_eq!(syndrome(&f[..n]), 0, "{h}");
        }
    }

    #[test]
    fn ap_frames_give_the_address() {
        // From the ulss7 capture as decoded by dump1090: "*282018154a9d59; CRC: 400159".
        let (f, n) = hex_frame("282018154A9D59");
        assert_eq!(syndrome(&f[..n]), 0x40_0159);
        // "*a0200233ea59bf163f57ecd3cb13; CRC: 400159"
        let (f, n) = hex_frame("A0200233EA59BF163F57ECD3CB13");
        assert_eq!(syndrome(&f[..n]), 0x40_0159);
    }

    #[test]
    fn every_single_bit_error_is_located() {
        let (f, _) = hex_frame("8D4840D6202CC371C32CE0576098");
        for bit in 5..112 {
            let mut g = f;
            g[bit / 8] ^= 0x80 >> (bit % 8);
            let s = syndrome(&g);
            assert_ne!(s, 0);
            assert_eq!(single_bit_error_112(s), Some(bit));
        }
        assert_eq!(single_bit_error_112(0), None);
    }

    #[test]
    fn set_parity_makes_a_clean_frame() {
        let (mut f, _) = hex_frame("8D4840D6202CC371C32CE0000000");
        set_parity(&mut f, 0);
        assert_eq!(&f[11..], &[0x57, 0x60, 0x98]);
        set_parity(&mut f, 0xABCDEF);
        assert_eq!(syndrome(&f), 0xABCDEF);
        assert_eq!(syndrome(&f[..2]), u32::MAX);
    }

    #[test]
    fn four_bytes_is_the_shortest_frame_with_a_syndrome() {
        // One zero data byte (remainder 0) and the parity field: the syndrome is the parity.
        assert_eq!(syndrome(&[0, 0, 0, 0]), 0);
        assert_eq!(syndrome(&[0, 0x12, 0x34, 0x56]), 0x12_3456);
        assert_eq!(syndrome(&[0, 0, 0]), u32::MAX);
        // set_parity on the same shortest frame: the parity of one data byte 0x80 (its
        // remainder, non-zero), so that the syndrome becomes 0; a 3-byte slice is left alone.
        let mut f = [0x80, 0, 0, 0];
        set_parity(&mut f, 0);
        assert_ne!(f[1..], [0, 0, 0]);
        assert_eq!(syndrome(&f), 0);
        let mut g = [0x80, 0, 0];
        set_parity(&mut g, 0);
        assert_eq!(g, [0x80, 0, 0]);
    }
}
