//! Mode S and ADS-B (DO-260B) decoding of raw 1090 MHz frames, as the TT-Multi-RF hands them
//! over in its raw protocols (manual 7.2.2; framing in [`crate::ttmrf::raw`]).
//!
//! Layers, each usable alone:
//! - [`crc`]: the 24-bit parity; [`df::decode`]: one frame to a [`ModeS`] value with its parity
//!   checked (no error correction unless [`DecodeOptions::correct_df17_single_bit`] is set);
//! - one module per register or field: [`altitude`], [`squawk`], [`ident`] (TC 1-4),
//!   [`surface`] (TC 5-8), [`airborne_position`] (TC 9-18, 20-22), [`velocity`] (TC 19),
//!   [`status`] (TC 28), [`target_state`] (TC 29), [`opstatus`] (TC 31), [`nic`], [`commb`]
//!   (BDS 2,0), [`cpr`] (position decoding);
//! - [`tracker`]: per-aircraft state (CPR pairing, NIC supplements, known addresses) in a
//!   bounded table, producing positions and [`crate::traffic::TrafficReport`]s;
//! - [`decoder::ModesDecoder`]: a [`crate::DeviceDecoder`] over a raw framing decoder that
//!   yields one [`decoder::ModesOutput`] per frame that passed its checks;
//! - [`encode`]: frames the simulator sends (identification, airborne position, velocity,
//!   operational status, DF11), with their parity.
//!
//! Everything works on fixed arrays and integers: no allocation per frame except the optional
//! traffic report.

pub mod airborne_position;
pub mod altitude;
pub mod commb;
pub mod cpr;
pub mod crc;
pub mod decoder;
pub mod df;
pub mod encode;
pub mod ident;
pub mod me;
pub mod nic;
pub mod opstatus;
pub mod squawk;
pub mod status;
pub mod surface;
pub mod target_state;
pub mod tracker;
pub mod velocity;

#[cfg(test)]
mod oracle_tests;

pub use decoder::{ModesDecoder, ModesOutput};
pub use df::{Content, DecodeOptions, ModeS, Parity, Reject, bits, decode, downlink_format, me_of};
pub use me::Me;
pub use tracker::{Tracker, TrackerConfig};

/// Parses a frame written as hex digits (14 or 28 of them, either case) into a 14-byte array and
/// its length in bytes. `None` for other lengths or non-hex characters.
pub fn parse_hex_frame(hex: &str) -> Option<([u8; 14], usize)> {
    let h = hex.as_bytes();
    if h.len() != 14 && h.len() != 28 {
        return None;
    }
    let mut f = [0u8; 14];
    for (i, pair) in h.chunks_exact(2).enumerate() {
        f[i] = (hex_val(pair[0])? << 4) | hex_val(pair[1])?;
    }
    Some((f, h.len() / 2))
}

/// Hex digit values by byte (0xFF = not a hex digit).
static HEX_LUT: [u8; 256] = {
    let mut t = [0xFFu8; 256];
    let mut i = 0;
    while i < 10 {
        t[b'0' as usize + i] = i as u8;
        i += 1;
    }
    let mut i = 0;
    while i < 6 {
        t[b'A' as usize + i] = 10 + i as u8;
        t[b'a' as usize + i] = 10 + i as u8;
        i += 1;
    }
    t
};

/// Value of one hex digit.
#[inline]
pub(crate) fn hex_val(c: u8) -> Option<u8> {
    let v = HEX_LUT[usize::from(c)];
    (v != 0xFF).then_some(v)
}

/// Test helper: a frame from hex, panicking on bad input.
#[cfg(test)]
pub(crate) fn hex_frame(hex: &str) -> ([u8; 14], usize) {
    parse_hex_frame(hex).expect("valid hex frame")
}
