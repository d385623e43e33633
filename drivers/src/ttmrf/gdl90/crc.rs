//! GDL90 Frame Check Sequence: CRC-16-CCITT as GDL 90 Data Interface Specification 560-1058-00
//! Rev A, 2.2.3 defines it.
//!
//! Polynomial 0x1021, initial value 0, no reflection, no final XOR, computed with the
//! specification's own table-driven update `crc = table[crc >> 8] ^ (crc << 8) ^ byte` over the
//! message ID and data (before escaping). The FCS goes on the wire least significant byte first.

/// The 256-entry table of the specification's `crcInit()`, built at compile time.
const TABLE: [u16; 256] = build_table();

const fn build_table() -> [u16; 256] {
    let mut table = [0u16; 256];
    let mut i = 0;
    while i < 256 {
        let mut crc = (i as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = (crc << 1) ^ if crc & 0x8000 != 0 { 0x1021 } else { 0 };
            bit += 1;
        }
        table[i] = crc;
        i += 1;
    }
    table
}

/// FCS of a clear (unescaped) message: message ID plus data.
pub fn fcs(message: &[u8]) -> u16 {
    message.iter().fold(0u16, |crc, &b| {
        TABLE[usize::from(crc >> 8)] ^ (crc << 8) ^ u16::from(b)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_matches_the_polynomial() {
        // i = 1: 0x0100 shifted 7 times reaches 0x8000, the 8th shift carries: 0x1021.
        // i = 2: 0x0200 carries on the 7th shift (0x1021), then shifts once more: 0x2042.
        assert_eq!(TABLE[0], 0);
        assert_eq!(TABLE[1], 0x1021);
        assert_eq!(TABLE[2], 0x2042);
        // The table of a CRC is linear over XOR.
        assert_eq!(TABLE[3], TABLE[1] ^ TABLE[2]);
    }

    #[test]
    fn spec_heartbeat_example() {
        // GDL 90 spec 2.2.4 example heartbeat: 7E 00 81 41 DB D0 08 02 B3 8B 7E.
        // The FCS of the clear message 00 81 41 DB D0 08 02 is 0x8BB3, sent LSB first (B3 8B).
        assert_eq!(fcs(&[0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]), 0x8BB3);
    }

    #[test]
    fn empty_is_zero() {
        assert_eq!(fcs(&[]), 0);
    }
}
