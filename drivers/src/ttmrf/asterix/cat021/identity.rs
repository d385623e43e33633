//! CAT021 ed 2.1 identification items: I021/161 Track Number, I021/015 Service Identification,
//! I021/080 Target Address, I021/170 Target Identification, I021/020 Emitter Category,
//! I021/070 Mode 3/A Code, I021/210 MOPS Version, I021/008 Aircraft Operational Status and
//! I021/132 Message Amplitude (EUROCONTROL-SPEC-0149-12 ed 2.1, 5.2).

use serde::Serialize;

use super::super::item::{ItemError, be_u64, push_be};

fn fixed<const N: usize>(b: &[u8], name: &'static str) -> Result<[u8; N], ItemError> {
    b.try_into().map_err(|_| ItemError::Malformed(name))
}

/// I021/161 Track Number: 12 bits (the top 4 bits of the item are spare).
pub fn decode_track_number(b: &[u8]) -> Result<u16, ItemError> {
    let b = fixed::<2>(b, "I021/161")?;
    Ok(u16::from_be_bytes(b) & 0x0FFF)
}

/// Appends I021/161.
pub fn encode_track_number(tn: u16, out: &mut Vec<u8>) {
    out.extend_from_slice(&(tn & 0x0FFF).to_be_bytes());
}

/// I021/080 Target Address: 24 bits.
pub fn decode_address(b: &[u8]) -> Result<u32, ItemError> {
    let b = fixed::<3>(b, "I021/080")?;
    Ok(be_u64(&b) as u32)
}

/// Appends I021/080.
pub fn encode_address(a: u32, out: &mut Vec<u8>) {
    push_be(u64::from(a & 0xFF_FFFF), 3, out);
}

/// The ICAO 6-bit character of a code (Annex 10 IA-5 subset): 1..=26 'A'..'Z', 32 space,
/// 48..=57 '0'..'9'. Other codes are not defined and become '?'.
fn ia5(code: u8) -> char {
    match code {
        1..=26 => char::from(b'A' + code - 1),
        32 => ' ',
        48..=57 => char::from(code),
        _ => '?',
    }
}

fn ia5_code(c: char) -> u8 {
    match c {
        'A'..='Z' => c as u8 - b'A' + 1,
        '0'..='9' => c as u8,
        _ => 32,
    }
}

/// I021/170 Target Identification: 8 characters of 6 bits, trailing spaces removed. Undefined
/// codes become '?' (the FLARM `STEALTH`/`NOTRACK` markers of manual 8.2.1 are plain text).
pub fn decode_target_id(b: &[u8]) -> Result<String, ItemError> {
    let b = fixed::<6>(b, "I021/170")?;
    let v = be_u64(&b);
    let s: String = (0..8)
        .map(|i| ia5(((v >> (42 - 6 * i)) & 0x3F) as u8))
        .collect();
    Ok(s.trim_end().to_string())
}

/// Appends I021/170: the first 8 characters, padded with spaces; characters outside A-Z, 0-9
/// become spaces.
pub fn encode_target_id(id: &str, out: &mut Vec<u8>) {
    let mut v = 0u64;
    let mut chars = id.chars();
    for _ in 0..8 {
        v = (v << 6) | u64::from(ia5_code(chars.next().unwrap_or(' ')));
    }
    push_be(v, 6, out);
}

/// I021/070 Mode 3/A code as four octal digits written in decimal (7700 for 7700).
pub fn decode_mode3a(b: &[u8]) -> Result<u16, ItemError> {
    let v = u16::from_be_bytes(fixed::<2>(b, "I021/070")?) & 0x0FFF;
    Ok((v >> 9) * 1000 + ((v >> 6) & 7) * 100 + ((v >> 3) & 7) * 10 + (v & 7))
}

/// Appends I021/070 from the four-digit form (each digit taken modulo 8).
pub fn encode_mode3a(code: u16, out: &mut Vec<u8>) {
    let d = |p: u16| (code / p % 10) & 7;
    let v = d(1000) << 9 | d(100) << 6 | d(10) << 3 | d(1);
    out.extend_from_slice(&v.to_be_bytes());
}

/// I021/210 MOPS Version.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct MopsVersion {
    /// VNS: the MOPS version is not supported by the ground station (the TT-Multi-RF sets it for
    /// FLARM targets, manual 8.2.1).
    pub vns: bool,
    /// VN: 0 ED102/DO-260, 1 DO-260A, 2 ED102A/DO-260B, 3 ED-102B/DO-260C.
    pub vn: u8,
    /// LTT link technology: 0 other, 1 UAT, 2 1090 ES, 3 VDL 4, 4..7 not assigned.
    pub ltt: u8,
}

impl MopsVersion {
    /// Decodes the one-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        let [o] = fixed::<1>(b, "I021/210")?;
        Ok(Self {
            vns: o & 0x40 != 0,
            vn: (o >> 3) & 7,
            ltt: o & 7,
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        out.push(u8::from(self.vns) << 6 | (self.vn & 7) << 3 | (self.ltt & 7));
    }
}

/// I021/008 Aircraft Operational Status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct OperationalStatus {
    /// RA: TCAS II or ACAS RA active.
    pub ra: bool,
    /// TC: target change report capability (0 none, 1 TC+0 only, 2 multiple TC, 3 reserved).
    pub tc: u8,
    /// TS: target state report capability.
    pub ts: bool,
    /// ARV: air-referenced velocity report capability.
    pub arv: bool,
    /// CDTI/A: cockpit display of traffic information airborne.
    pub cdti_a: bool,
    /// "not TCAS": TCAS system status is NOT operational (the bit is set when TCAS is off).
    pub not_tcas: bool,
    /// SA: single antenna.
    pub sa: bool,
}

impl OperationalStatus {
    /// Decodes the one-octet item.
    pub fn decode(b: &[u8]) -> Result<Self, ItemError> {
        let [o] = fixed::<1>(b, "I021/008")?;
        Ok(Self {
            ra: o & 0x80 != 0,
            tc: (o >> 5) & 3,
            ts: o & 0x10 != 0,
            arv: o & 0x08 != 0,
            cdti_a: o & 0x04 != 0,
            not_tcas: o & 0x02 != 0,
            sa: o & 0x01 != 0,
        })
    }

    /// Appends the item.
    pub fn encode(&self, out: &mut Vec<u8>) {
        out.push(
            u8::from(self.ra) << 7
                | (self.tc & 3) << 5
                | u8::from(self.ts) << 4
                | u8::from(self.arv) << 3
                | u8::from(self.cdti_a) << 2
                | u8::from(self.not_tcas) << 1
                | u8::from(self.sa),
        );
    }
}

/// One-octet items read as they are: I021/015 Service Identification, I021/020 Emitter
/// Category (ECAT).
pub fn decode_u8(b: &[u8], name: &'static str) -> Result<u8, ItemError> {
    Ok(fixed::<1>(b, name)?[0])
}

/// I021/132 Message Amplitude, dBm (signed octet).
pub fn decode_amplitude(b: &[u8]) -> Result<i8, ItemError> {
    Ok(fixed::<1>(b, "I021/132")?[0] as i8)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_id() {
        // "N825V   ": N=14, 8=56, 2=50, 5=53, V=22, space=32 x3.
        // Bits: 001110 111000 110010 110101 010110 100000 100000 100000
        //     = 0011 1011 1000 1100 1011 0101 0101 1010 0000 1000 0010 0000
        //     = 3B 8C B5 5A 08 20.
        let b = [0x3B, 0x8C, 0xB5, 0x5A, 0x08, 0x20];
        assert_eq!(decode_target_id(&b).unwrap(), "N825V");
        let mut out = Vec::new();
        encode_target_id("N825V", &mut out);
        assert_eq!(out, b);
        // All-zero codes are undefined: '?' x 8.
        assert_eq!(decode_target_id(&[0; 6]).unwrap(), "????????");
    }

    #[test]
    fn mode3a() {
        // 7700 octal = 111 111 000 000 = 0x0FC0.
        assert_eq!(decode_mode3a(&[0x0F, 0xC0]).unwrap(), 7700);
        // Spare top nibble ignored; 1234 = 001 010 011 100 = 0x29C.
        assert_eq!(decode_mode3a(&[0xF2, 0x9C]).unwrap(), 1234);
        let mut out = Vec::new();
        encode_mode3a(1234, &mut out);
        assert_eq!(out, [0x02, 0x9C]);
    }

    #[test]
    fn mops_and_status() {
        // 0x02: VNS 0, VN 0, LTT 2 (1090 ES) -- the value in the CAT021 sample.
        assert_eq!(
            MopsVersion::decode(&[0x02]).unwrap(),
            MopsVersion {
                vns: false,
                vn: 0,
                ltt: 2
            }
        );
        // 0x51 = 0101 0001: VNS 1, VN 2, LTT 1 (UAT).
        let m = MopsVersion::decode(&[0x51]).unwrap();
        assert_eq!((m.vns, m.vn, m.ltt), (true, 2, 1));
        // 0xA5 = 1010 0101: RA, TC 1, CDTI/A, SA.
        let s = OperationalStatus::decode(&[0xA5]).unwrap();
        assert!(s.ra && s.cdti_a && s.sa && !s.ts && !s.arv && !s.not_tcas);
        assert_eq!(s.tc, 1);
        let mut out = Vec::new();
        s.encode(&mut out);
        m.encode(&mut out);
        assert_eq!(out, [0xA5, 0x51]);
    }

    #[test]
    fn small_items() {
        assert_eq!(decode_track_number(&[0xF1, 0x23]).unwrap(), 0x123);
        assert_eq!(decode_address(&[0xAB, 0x45, 0x49]).unwrap(), 0xAB4549);
        assert_eq!(decode_amplitude(&[0xCB]).unwrap(), -53);
        assert!(decode_address(&[1, 2]).is_err());
    }
}
