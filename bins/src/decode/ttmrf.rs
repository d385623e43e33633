//! `vigil decode --device ttmrf --format ...`: dispatch to the protocol decoders.
//!
//! `--format auto`: the module sends one output protocol at a time (its configuration selects it),
//! so a binary protocol is recognised from the first frame in the stream and the whole stream is
//! decoded with it; text (CSV, JSON, NMEA, AT responses, which may interleave on one port) is then
//! detected line by line by the text decoder.

use std::io::{Cursor, Read, Write};

use anyhow::Result;

use super::{DecodeArgs, JsonLines, Summary, TtFormat};

/// Decodes a TT-Multi-RF byte stream in the chosen format.
pub fn decode<W: Write>(
    args: &DecodeArgs,
    input: &mut dyn Read,
    out: &mut JsonLines<W>,
) -> Result<Summary> {
    if args.reference.is_some()
        && !matches!(
            args.format,
            TtFormat::Hex | TtFormat::Hexd | TtFormat::Beast
        )
    {
        anyhow::bail!("--ref applies to the raw Mode S formats (hex, hexd, beast) only");
    }
    let mut prefix = Vec::with_capacity(SNIFF_LEN);
    input.take(SNIFF_LEN as u64).read_to_end(&mut prefix)?;
    let format = match args.format {
        TtFormat::Auto => sniff(&prefix),
        f => f,
    };
    let mut input = Cursor::new(prefix).chain(input);
    let input: &mut dyn Read = &mut input;
    match format {
        TtFormat::Auto | TtFormat::Csv | TtFormat::Json | TtFormat::Nmea | TtFormat::At => {
            super::ttmrf_text::decode(format, input, out)
        }
        TtFormat::Mavlink | TtFormat::Gdl90 | TtFormat::Asterix => {
            super::ttmrf_binary::decode(format, input, out)
        }
        TtFormat::Hex | TtFormat::Hexd | TtFormat::Beast => {
            super::modes::decode(format, args.reference.as_deref(), input, out)
        }
    }
}

/// Bytes read ahead to recognise a binary protocol.
const SNIFF_LEN: usize = 4096;

/// The protocol of a stream from its first bytes: the first position where a binary frame start
/// (with a plausible second byte) or a text line start is seen decides. Text stays `Auto`.
fn sniff(prefix: &[u8]) -> TtFormat {
    for (i, &b) in prefix.iter().enumerate() {
        let next = prefix.get(i + 1).copied();
        let line_start = i == 0 || matches!(prefix[i - 1], b'\n' | b'\r');
        match (b, next) {
            // Text line starts: CSV, JSON, NMEA, AT.
            (b'#' | b'{' | b'$', _) | (b'A', Some(b'T')) if line_start => return TtFormat::Auto,
            // Raw Mode S HEX ('*') or timestamped AVR ('@') lines.
            (b'*' | b'@', _) if line_start => return TtFormat::Hex,
            // GDL90: flag byte, then a message id the module sends (0, 10, 11, 20).
            (0x7E, Some(0 | 10 | 11 | 20)) => return TtFormat::Gdl90,
            // MAVLink 1 / 2 start bytes, then a payload length (ADSB_VEHICLE is 38, COLLISION 19,
            // both possibly truncated in MAVLink 2).
            (0xFE | 0xFD, Some(1..=38)) => return TtFormat::Mavlink,
            // Beast: escape byte, then a frame type.
            (0x1A, Some(0x31..=0x33)) => return TtFormat::Beast,
            // ASTERIX: category 21 or 23, then a big-endian block length of 6..4096 (high byte
            // 0..=15).
            (21 | 23, Some(0..=15)) if i == 0 => return TtFormat::Asterix,
            _ => {}
        }
    }
    TtFormat::Auto
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sniffs_each_protocol_from_its_first_frame() {
        assert_eq!(sniff(b"#A:4CA2D6,,,\r\n"), TtFormat::Auto);
        assert_eq!(sniff(b"{\"src\":1}\r\n"), TtFormat::Auto);
        assert_eq!(sniff(b"junk\r\n$GPGGA,..."), TtFormat::Auto);
        assert_eq!(sniff(b"*8D4840D6202CC371C32CE0576098;\r\n"), TtFormat::Hex);
        assert_eq!(sniff(&[0x00, 0x7E, 20, 0x00]), TtFormat::Gdl90);
        assert_eq!(sniff(&[0xFD, 38, 0, 0]), TtFormat::Mavlink);
        assert_eq!(sniff(&[0xFE, 38, 0, 0]), TtFormat::Mavlink);
        assert_eq!(sniff(&[0x1A, 0x33, 0, 0]), TtFormat::Beast);
        assert_eq!(sniff(&[21, 0x00, 0x2C, 0xFF]), TtFormat::Asterix);
        assert_eq!(sniff(b""), TtFormat::Auto);
    }
}
