//! `vigil decode --device ttmrf --format ...`: dispatch to the protocol decoders.

use std::io::{Read, Write};

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
    match args.format {
        TtFormat::Auto | TtFormat::Csv | TtFormat::Json | TtFormat::Nmea | TtFormat::At => {
            super::ttmrf_text::decode(args.format, input, out)
        }
        TtFormat::Mavlink | TtFormat::Gdl90 | TtFormat::Asterix => {
            super::ttmrf_binary::decode(args.format, input, out)
        }
        TtFormat::Hex | TtFormat::Hexd | TtFormat::Beast => {
            super::modes::decode(args.format, args.reference.as_deref(), input, out)
        }
    }
}
