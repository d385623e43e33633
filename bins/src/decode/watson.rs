//! `vigil decode --device watson`.

use std::io::{Read, Write};

use anyhow::{Result, bail};

use super::{JsonLines, Summary};

/// Decodes a watson byte stream (not implemented yet).
pub fn decode<W: Write>(_input: &mut dyn Read, _out: &mut JsonLines<W>) -> Result<Summary> {
    bail!("decoding watson is not implemented yet")
}
