//! `vigil decode --device ttmrf --format mavlink|gdl90|asterix`.

use std::io::{Read, Write};

use anyhow::{Result, bail};

use super::{JsonLines, Summary, TtFormat};

/// Decodes the TT-Multi-RF binary protocols (not implemented yet).
pub fn decode<W: Write>(
    format: TtFormat,
    _input: &mut dyn Read,
    _out: &mut JsonLines<W>,
) -> Result<Summary> {
    bail!("decoding TT-Multi-RF {format:?} is not implemented yet")
}
