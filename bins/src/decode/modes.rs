//! `vigil decode --device ttmrf --format hex|hexd|beast [--ref LAT,LON]`.

use std::io::{Read, Write};

use anyhow::{Result, bail};

use super::{JsonLines, Summary, TtFormat};

/// Decodes raw Mode S frames (not implemented yet).
pub fn decode<W: Write>(
    format: TtFormat,
    _reference: Option<&str>,
    _input: &mut dyn Read,
    _out: &mut JsonLines<W>,
) -> Result<Summary> {
    bail!("decoding raw Mode S {format:?} is not implemented yet")
}
