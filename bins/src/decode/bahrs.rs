//! `vigil decode --device bahrs`.

use std::io::{Read, Write};

use anyhow::{Result, bail};

use super::{JsonLines, Summary};

/// Decodes a bahrs byte stream (not implemented yet).
pub fn decode<W: Write>(_input: &mut dyn Read, _out: &mut JsonLines<W>) -> Result<Summary> {
    bail!("decoding bahrs is not implemented yet")
}
