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

#[cfg(test)]
mod hex_tests {
    use super::*;

    #[test]
    fn every_hex_digit_has_its_value_and_its_neighbours_none() {
        let digits = "0123456789abcdefABCDEF";
        let values = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];
        for (c, want) in digits.bytes().zip(values.iter().chain(&values[10..])) {
            assert_eq!(hex_val(c), Some(*want), "{}", c as char);
        }
        // The ASCII neighbours of each range: '/' ':' '@' 'G' '`' 'g', and NUL, space, 0xFF.
        for c in [b'/', b':', b'@', b'G', b'`', b'g', 0, b' ', 0xFF] {
            assert_eq!(hex_val(c), None, "{c:#04x}");
        }
    }

    #[test]
    fn a_frame_parses_in_either_case_into_its_bytes() {
        // The "1090 MHz Riddle" even position frame: 14 bytes.
        let want = [
            0x8D, 0x40, 0x62, 0x1D, 0x58, 0xC3, 0x82, 0xD6, 0x90, 0xC8, 0xAC, 0x28, 0x63, 0xA7,
        ];
        for hex in [
            "8D40621D58C382D690C8AC2863A7",
            "8d40621d58c382d690c8ac2863a7",
        ] {
            assert_eq!(parse_hex_frame(hex), Some((want, 14)), "{hex}");
        }
        // A short frame: 7 bytes, the rest zero.
        let (f, n) = parse_hex_frame("5D4CA2D4E0A5B7").unwrap();
        assert_eq!(n, 7);
        assert_eq!(f[..7], [0x5D, 0x4C, 0xA2, 0xD4, 0xE0, 0xA5, 0xB7]);
        assert_eq!(f[7..], [0; 7]);
        assert_eq!(parse_hex_frame("5D4CA2D4E0A5B:"), None);
        assert_eq!(parse_hex_frame("5D4CA2D4E0A5B"), None);
    }
}
