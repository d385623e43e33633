//! `vigil decode --device watson`: one JSON object per line, in the device's units (named).

use std::io::{Read, Write};

use anyhow::Result;
use vigil_drivers::watson::Decoder;

use super::{JsonLines, Summary, run_decoder};

/// Decodes a Watson AHRS-E304 byte stream. The fields keep the device's units, named in each key
/// (`bank_deg`, `accel_g`, `rate_dps`, `velocity_kmh`); the heading is magnetic.
pub fn decode<W: Write>(input: &mut dyn Read, out: &mut JsonLines<W>) -> Result<Summary> {
    let mut decoder = Decoder::new();
    let stats = run_decoder(&mut decoder, input, out, |line, out| out.write(&line))?;
    Ok(Summary::new("watson", stats))
}
