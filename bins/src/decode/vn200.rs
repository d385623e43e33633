//! `vigil decode --device vn200`.

use std::io::{Read, Write};

use anyhow::{Result, bail};

use super::{JsonLines, Summary};

/// Decodes a vn200 byte stream (not implemented yet).
pub fn decode<W: Write>(_input: &mut dyn Read, _out: &mut JsonLines<W>) -> Result<Summary> {
    bail!("decoding vn200 is not implemented yet")
}
