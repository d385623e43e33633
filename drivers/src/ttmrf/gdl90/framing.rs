//! GDL90 framing (GDL 90 Data Interface Specification 560-1058-00 Rev A, 2.2): every message is
//! `0x7E | message ID | data | FCS (LSB first) | 0x7E`, and any 0x7E or 0x7D between the flags —
//! in the ID, the data *or the FCS* — is sent as 0x7D followed by the byte XOR 0x20.

use super::crc::fcs;

/// Flag byte that opens and closes every frame.
pub const FLAG: u8 = 0x7E;
/// Control-escape byte.
pub const ESCAPE: u8 = 0x7D;
/// XOR applied to an escaped byte.
pub const ESCAPE_XOR: u8 = 0x20;

/// Longest clear message (ID + data) the decoder accepts: the Uplink Data message (ID 7) is the
/// longest GDL90 message, 1 + 3 + 432 = 436 bytes.
pub const MAX_CLEAR_LEN: usize = 436;
/// Longest escaped content between two flags: clear message plus FCS, every byte escaped.
pub const MAX_ESCAPED_LEN: usize = 2 * (MAX_CLEAR_LEN + 2);

/// Why the content between two flags is not a message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum FrameError {
    /// A 0x7D was the last byte before the closing flag.
    #[error("gdl90 frame ends inside an escape sequence")]
    DanglingEscape,
    /// Fewer than 3 clear bytes (ID + 2 FCS bytes).
    #[error("gdl90 frame too short: {0} clear bytes")]
    TooShort(usize),
    /// The FCS did not verify.
    #[error("gdl90 fcs mismatch: computed {computed:#06x}, received {received:#06x}")]
    Fcs {
        /// FCS computed over ID and data.
        computed: u16,
        /// FCS found in the frame.
        received: u16,
    },
}

/// Removes the escaping of `escaped` (the bytes between the flags) into `clear`, checks the FCS
/// and returns the clear message (ID + data) without the FCS.
pub fn unframe<'a>(escaped: &[u8], clear: &'a mut Vec<u8>) -> Result<&'a [u8], FrameError> {
    clear.clear();
    let mut it = escaped.iter();
    while let Some(&b) = it.next() {
        if b == ESCAPE {
            match it.next() {
                Some(&n) => clear.push(n ^ ESCAPE_XOR),
                None => return Err(FrameError::DanglingEscape),
            }
        } else {
            clear.push(b);
        }
    }
    let n = clear.len();
    if n < 3 {
        return Err(FrameError::TooShort(n));
    }
    let (message, fcs_bytes) = clear.split_at(n - 2);
    let received = u16::from_le_bytes([fcs_bytes[0], fcs_bytes[1]]);
    let computed = fcs(message);
    if computed != received {
        return Err(FrameError::Fcs { computed, received });
    }
    Ok(&clear[..n - 2])
}

fn push_escaped(out: &mut Vec<u8>, b: u8) {
    if b == FLAG || b == ESCAPE {
        out.push(ESCAPE);
        out.push(b ^ ESCAPE_XOR);
    } else {
        out.push(b);
    }
}

/// Appends the complete frame (flags, escaping, FCS) of a clear message (ID + data) to `out`.
pub fn frame(message: &[u8], out: &mut Vec<u8>) {
    out.push(FLAG);
    for &b in message {
        push_escaped(out, b);
    }
    for b in fcs(message).to_le_bytes() {
        push_escaped(out, b);
    }
    out.push(FLAG);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_heartbeat_frame() {
        // GDL 90 spec 2.2.4: 7E 00 81 41 DB D0 08 02 B3 8B 7E.
        let mut out = Vec::new();
        frame(&[0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02], &mut out);
        assert_eq!(
            out,
            [
                0x7E, 0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8B, 0x7E
            ]
        );
    }

    #[test]
    fn escapes_flag_and_escape_in_data() {
        // Message ID 0x7E (not a real ID; framing does not care) and data byte 0x7D:
        // 0x7E -> 7D 5E, 0x7D -> 7D 5D.
        let mut out = Vec::new();
        frame(&[0x7E, 0x7D], &mut out);
        assert_eq!(&out[..5], &[0x7E, 0x7D, 0x5E, 0x7D, 0x5D]);
        let mut clear = Vec::new();
        let inner = &out[1..out.len() - 1];
        assert_eq!(unframe(inner, &mut clear).unwrap(), &[0x7E, 0x7D]);
    }

    #[test]
    fn any_escaped_octet_is_restored_by_the_xor() {
        // GDL 90 (2.2.1) restores the octet after a Control-Escape by XOR with 0x20, and an
        // HDLC-style sender (RFC 1662) may escape octets that need no escaping. The spec's
        // heartbeat (2.2.4) with its 0x41 sent as 7D 61 (0x61 ^ 0x20 = 0x41; an OR would
        // leave 0x61) and its 0x02 as 7D 22.
        let inner = [
            0x00, 0x81, 0x7D, 0x61, 0xDB, 0xD0, 0x08, 0x7D, 0x22, 0xB3, 0x8B,
        ];
        let mut clear = Vec::new();
        assert_eq!(
            unframe(&inner, &mut clear).unwrap(),
            &[0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02]
        );
    }

    #[test]
    fn escapes_inside_the_fcs() {
        // Search three-byte messages 0x14 a b whose FCS has a 0x7E or 0x7D byte, then check
        // by hand that the FCS bytes went out escaped and that the frame decodes. (Two-byte
        // messages cannot serve: with this algorithm and init 0 the FCS of [a, b] is a << 8 | b.)
        assert_eq!(fcs(&[0x12, 0x34]), 0x1234);
        let mut found = 0;
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                let crc = fcs(&[0x14, a, b]).to_le_bytes();
                let specials = crc.iter().filter(|&&c| c == FLAG || c == ESCAPE).count();
                if specials == 0 || a == FLAG || a == ESCAPE || b == FLAG || b == ESCAPE {
                    continue;
                }
                let mut out = Vec::new();
                frame(&[0x14, a, b], &mut out);
                // 2 flags + 3 data + 2 FCS + one extra byte per escaped FCS byte.
                assert_eq!(out.len(), 7 + specials);
                let mut expect = vec![FLAG, 0x14, a, b];
                for c in crc {
                    if c == FLAG || c == ESCAPE {
                        expect.extend([ESCAPE, c ^ 0x20]);
                    } else {
                        expect.push(c);
                    }
                }
                expect.push(FLAG);
                assert_eq!(out, expect);
                let mut clear = Vec::new();
                assert_eq!(
                    unframe(&out[1..out.len() - 1], &mut clear).unwrap(),
                    &[0x14, a, b]
                );
                found += 1;
            }
        }
        assert!(found > 100, "{found}");
    }

    #[test]
    fn errors() {
        let mut clear = Vec::new();
        assert_eq!(
            unframe(&[0x00, 0x7D], &mut clear),
            Err(FrameError::DanglingEscape)
        );
        assert_eq!(
            unframe(&[0x00, 0x01], &mut clear),
            Err(FrameError::TooShort(2))
        );
        assert!(matches!(
            unframe(
                &[0x00, 0x81, 0x41, 0xDB, 0xD0, 0x08, 0x02, 0xB3, 0x8C],
                &mut clear
            ),
            Err(FrameError::Fcs {
                computed: 0x8BB3,
                received: 0x8CB3
            })
        ));
    }
}
