//! BAHRS frame layout and CRC (BAHRS serial protocol 2.0, sections 2.1-2.3 and 6).
//!
//! ```text
//!  byte  0    1    2      3      4     5 .. 5+LEN   .. +PAD_LEN     4 bytes
//!       'N'  'E'  ver lo ver hi  type  payload       padding        CRC-32/MPEG-2, little-endian
//!       \____________________ covered by the CRC ____________________/
//! ```
//!
//! Decisions where the document is inconsistent (shared by every part of vigil):
//! - The frame table puts a `uint16` protocol version at "position 3" and the type at "position 4",
//!   which cannot both hold. We read the header as 'N', 'E', a little-endian u16 version (bytes 2-3,
//!   0-based) and the type (byte 4): 5 header bytes. This is the only reading in which the version
//!   is a u16 as the table says and the frame stays byte-aligned with the padding rule.
//! - `PAD_LEN = 4 - (5 + LEN) % 4` is taken literally: 1 to 4 bytes, so a frame whose header and
//!   payload already fill whole words still gets 4 padding bytes. Padding bytes are sent as zero
//!   and not checked on receipt (the CRC covers them).
//! - 0xF2, 0xF3 and 0xFF are not padded (section 5 remarks).
//! - The CRC is stored little-endian, like every other multi-byte field (section 2.1).

/// First frame marker byte, ASCII 'N'.
pub const MARKER_1: u8 = b'N';
/// Second frame marker byte, ASCII 'E'.
pub const MARKER_2: u8 = b'E';
/// Protocol version identifier of document version 2.0 (section 6).
pub const PROTOCOL_VERSION: u16 = 0x0003;
/// Older protocol identifiers (document versions 0.1-1.1) that a real device may still send.
pub const OLDER_VERSIONS: [u16; 2] = [0x0001, 0x0002];
/// Header length: two markers, u16 version, u8 type.
pub const HEADER_LEN: usize = 5;
/// CRC length.
pub const CRC_LEN: usize = 4;
/// Longest frame of protocol 2.0 (0xF3: 5 + 33 + 4), so the decoder never waits for more bytes.
pub const MAX_FRAME_LEN: usize = 42;

/// CRC-32/MPEG-2 generator polynomial (section 2.2), non-reflected.
const CRC32_POLY: u32 = 0x04C1_1DB7;

/// Slice-by-16 tables of CRC-32/MPEG-2: `CRC32_TABLES[k][b]` is the register contribution of byte
/// `b` followed by `k` zero bytes. Built at compile time from the polynomial.
static CRC32_TABLES: [[u32; 256]; 16] = {
    let mut t = [[0u32; 256]; 16];
    let mut b = 0;
    while b < 256 {
        let mut r = (b as u32) << 24;
        let mut bit = 0;
        while bit < 8 {
            r = if r & 0x8000_0000 != 0 {
                (r << 1) ^ CRC32_POLY
            } else {
                r << 1
            };
            bit += 1;
        }
        t[0][b] = r;
        b += 1;
    }
    let mut k = 1;
    while k < 16 {
        let mut b = 0;
        while b < 256 {
            let prev = t[k - 1][b];
            t[k][b] = (prev << 8) ^ t[0][(prev >> 24) as usize];
            b += 1;
        }
        k += 1;
    }
    t
};

/// Feeds `N` bytes (4, 8 or 16) to the register in one step: the register is folded into the
/// first four bytes and every byte looks its contribution up independently. The bytes after the
/// first four do not depend on the register, so their part is combined first and the register's
/// path through a step is one table load and a few XORs.
#[inline(always)]
fn crc32_step<const N: usize>(crc: u32, bytes: &[u8; N]) -> u32 {
    let mut data = 0;
    for i in 4..N {
        data ^= CRC32_TABLES[N - 1 - i][bytes[i] as usize];
    }
    let [h0, h1, h2, h3] =
        (crc ^ u32::from_be_bytes([bytes[0], bytes[1], bytes[2], bytes[3]])).to_be_bytes();
    data ^ ((CRC32_TABLES[N - 1][h0 as usize] ^ CRC32_TABLES[N - 2][h1 as usize])
        ^ (CRC32_TABLES[N - 3][h2 as usize] ^ CRC32_TABLES[N - 4][h3 as usize]))
}

/// Computes the CRC-32/MPEG-2 (poly 0x04C11DB7, init 0xFFFFFFFF, no reflection, no final XOR) of
/// `bytes`.
///
/// Slice-by-16, then one 8-byte and one 4-byte step for the rest: the bytes a frame's CRC covers
/// are 16, 20 or 24 for the periodic messages, and finishing them byte by byte would make the tail
/// a chain of up to 8 dependent table loads (the `crc` crate's slice-by-16 does that), which is
/// what the decoder waits on.
#[inline]
pub fn crc32_mpeg2(bytes: &[u8]) -> u32 {
    let mut crc = 0xFFFF_FFFF;
    let mut chunks = bytes.chunks_exact(16);
    for c in &mut chunks {
        crc = crc32_step::<16>(crc, c.try_into().expect("16-byte chunk"));
    }
    let mut rest = chunks.remainder();
    if let Some((c, tail)) = rest.split_first_chunk::<8>() {
        crc = crc32_step(crc, c);
        rest = tail;
    }
    if let Some((c, tail)) = rest.split_first_chunk::<4>() {
        crc = crc32_step(crc, c);
        rest = tail;
    }
    for &b in rest {
        crc = (crc << 8) ^ CRC32_TABLES[0][usize::from((crc >> 24) as u8 ^ b)];
    }
    crc
}

/// Frame geometry of one message type.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Payload length in bytes (LEN).
    pub payload_len: usize,
    /// Whether the frame is padded to whole 32-bit words.
    pub padded: bool,
}

impl Layout {
    /// Padding length: `4 - (5 + LEN) % 4` for padded types (1 to 4), 0 otherwise.
    #[inline]
    pub const fn pad_len(&self) -> usize {
        if self.padded {
            4 - (HEADER_LEN + self.payload_len) % 4
        } else {
            0
        }
    }

    /// Total frame length: header, payload, padding and CRC.
    #[inline]
    pub const fn frame_len(&self) -> usize {
        HEADER_LEN + self.payload_len + self.pad_len() + CRC_LEN
    }
}

/// The layout of a protocol 2.0 message type, or `None` for types without a documented layout
/// (the undocumented debug messages and anything else).
///
/// One load from a table that [`documented_layout`] fills at compile time: the decoder looks a
/// layout up on every frame, and a load costs less than the branch a `match` on the type becomes.
#[inline]
pub const fn layout(msg_type: u8) -> Option<Layout> {
    LAYOUTS[msg_type as usize]
}

/// [`documented_layout`] of every type byte.
static LAYOUTS: [Option<Layout>; 256] = {
    let mut table = [None; 256];
    let mut t = 0;
    while t < 256 {
        table[t] = documented_layout(t as u8);
        t += 1;
    }
    table
};

/// The documented layouts (section 5): the one place a type's payload length and padding are
/// written down.
const fn documented_layout(msg_type: u8) -> Option<Layout> {
    let (payload_len, padded) = match msg_type {
        0x01 => (15, true), // seq + 6 x i16 + u16 health
        0x02 => (13, true), // seq + 5 x 16-bit + u16 health
        0x03 => (15, true), // seq + 3 x u16 + u64
        0x04 | 0x05 => (10, true),
        0x06 => (9, true),
        0x0F => (7, true),
        0x1F => (14, true),
        0xF0 | 0xF1 => (0, true),
        0xF2 => (1, false),
        0xF3 => (33, false),
        0xFF => (2, false),
        _ => return None,
    };
    Some(Layout {
        payload_len,
        padded,
    })
}

/// Writes a complete frame (header, payload, zero padding, CRC) of `msg_type` to `out`.
///
/// `payload` must have the type's documented length; the message encoders guarantee it.
pub fn write_frame(msg_type: u8, version: u16, payload: &[u8], out: &mut Vec<u8>) {
    let pad = layout(msg_type).map_or(0, |l| l.pad_len());
    let start = out.len();
    out.extend_from_slice(&[MARKER_1, MARKER_2]);
    out.extend_from_slice(&version.to_le_bytes());
    out.push(msg_type);
    out.extend_from_slice(payload);
    out.extend(std::iter::repeat_n(0u8, pad));
    let crc = crc32_mpeg2(&out[start..]);
    out.extend_from_slice(&crc.to_le_bytes());
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crc_check_value_of_the_document() {
        // Section 2.2: check = 0x0376E6E7 for "123456789".
        assert_eq!(crc32_mpeg2(b"123456789"), 0x0376_E6E7);
    }

    #[test]
    fn crc_of_a_single_zero_byte_by_hand() {
        // Hand computation: init 0xFFFFFFFF, no reflection. Feeding 0x00 shifts the register left by
        // 8 bits eight times with the top bit set each time; equivalently CRC(0x00) with init all ones
        // equals CRC of 0xFF 0xFF 0xFF 0xFF 0x00 with init 0, which a bitwise reference gives.
        fn bitwise(data: &[u8], init: u32) -> u32 {
            let mut reg = init;
            for &b in data {
                reg ^= (b as u32) << 24;
                for _ in 0..8 {
                    reg = if reg & 0x8000_0000 != 0 {
                        (reg << 1) ^ 0x04C1_1DB7
                    } else {
                        reg << 1
                    };
                }
            }
            reg
        }
        assert_eq!(bitwise(b"123456789", 0xFFFF_FFFF), 0x0376_E6E7);
        for data in [
            &b""[..],
            &[0u8][..],
            &[0xFF, 0x00, 0x4E][..],
            b"NE\x03\x00\x06",
        ] {
            assert_eq!(crc32_mpeg2(data), bitwise(data, 0xFFFF_FFFF), "{data:?}");
        }
    }

    #[test]
    fn crc_agrees_with_the_crc_crate_at_every_length_and_alignment() {
        // The `crc` crate's CRC-32/MPEG-2 is an independent implementation (byte-wise table),
        // so every path here (16-, 8-, 4-byte steps and the byte tail) is checked against it.
        let reference = crc::Crc::<u32>::new(&crc::CRC_32_MPEG_2);
        let data: Vec<u8> = (0..160u32)
            .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
            .collect();
        for start in 0..4 {
            for end in start..=data.len() {
                let bytes = &data[start..end];
                assert_eq!(
                    crc32_mpeg2(bytes),
                    reference.checksum(bytes),
                    "{start}..{end}"
                );
            }
        }
    }

    #[test]
    fn frame_lengths_by_hand() {
        // 0x01: LEN 15, 5 + 15 = 20 is a multiple of 4, so PAD_LEN = 4 - 0 = 4; 5 + 15 + 4 + 4 = 28.
        assert_eq!(layout(0x01).unwrap().pad_len(), 4);
        assert_eq!(layout(0x01).unwrap().frame_len(), 28);
        // 0x02: LEN 13, 18 % 4 = 2, PAD 2; 5 + 13 + 2 + 4 = 24.
        assert_eq!(layout(0x02).unwrap().frame_len(), 24);
        // 0x03: LEN 15 like 0x01: 28.
        assert_eq!(layout(0x03).unwrap().frame_len(), 28);
        // 0x04/0x05: LEN 10, 15 % 4 = 3, PAD 1; 20.
        assert_eq!(layout(0x04).unwrap().frame_len(), 20);
        assert_eq!(layout(0x05).unwrap().frame_len(), 20);
        // 0x06: LEN 9, 14 % 4 = 2, PAD 2; 20.
        assert_eq!(layout(0x06).unwrap().frame_len(), 20);
        // 0x0F: LEN 7, 12 % 4 = 0, PAD 4; 20.
        assert_eq!(layout(0x0F).unwrap().frame_len(), 20);
        // 0x1F: LEN 14, 19 % 4 = 3, PAD 1; 24.
        assert_eq!(layout(0x1F).unwrap().frame_len(), 24);
        // 0xF0/0xF1: LEN 0, PAD 3; 12.
        assert_eq!(layout(0xF0).unwrap().frame_len(), 12);
        // Unpadded service messages.
        assert_eq!(layout(0xF2).unwrap().frame_len(), 10);
        assert_eq!(layout(0xF3).unwrap().frame_len(), 42);
        assert_eq!(layout(0xFF).unwrap().frame_len(), 11);
        assert_eq!(layout(0x10), None);
        let max = (0..=255u8).filter_map(layout).map(|l| l.frame_len()).max();
        assert_eq!(max, Some(MAX_FRAME_LEN));
        // Header + payload + padding of padded types is a whole number of 32-bit words.
        for t in [0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x0F, 0x1F, 0xF0, 0xF1] {
            let l = layout(t).unwrap();
            assert_eq!(
                (HEADER_LEN + l.payload_len + l.pad_len()) % 4,
                0,
                "type {t:#04x}"
            );
        }
    }

    #[test]
    fn written_frame_by_hand() {
        // 0xF1 (exit diagnostics): empty payload, 3 zero padding bytes, then the CRC.
        let mut out = Vec::new();
        write_frame(0xF1, PROTOCOL_VERSION, &[], &mut out);
        assert_eq!(&out[..8], &[0x4E, 0x45, 0x03, 0x00, 0xF1, 0, 0, 0]);
        let crc = crc32_mpeg2(&out[..8]);
        assert_eq!(&out[8..], &crc.to_le_bytes());
    }
}
