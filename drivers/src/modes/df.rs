//! Downlink formats (ICAO Annex 10 Vol IV, 3.1.2): the frame-level decode of one Mode S reply
//! or squitter, parity included.
//!
//! | DF | length | parity | decoded here |
//! |---|---|---|---|
//! | 0 | 56 | AP | VS, altitude (AC13) |
//! | 4 | 56 | AP | FS, altitude |
//! | 5 | 56 | AP | FS, identity (squawk) |
//! | 11 | 56 | PI (II/SI in the low 7 bits) | capability, address |
//! | 16 | 112 | AP | VS, altitude |
//! | 17 | 112 | PI = 0 | ADS-B ME |
//! | 18 | 112 | PI = 0 | ADS-B ME for CF 0, 1, 2, 5, 6; other CF recognised only |
//! | 20 | 112 | AP | FS, altitude, Comm-B MB (BDS 2,0 callsign when recognisable) |
//! | 21 | 112 | AP | FS, identity, Comm-B MB |
//! | 24 | 112 | AP | recognised by its first two bits (Comm-D), not decoded |
//!
//! Other DFs are counted as unknown. A frame whose length does not match its DF is malformed.
//! AP frames yield the address *recovered* from the parity, which the frame alone cannot verify:
//! the tracker accepts it only for an address already seen in a frame with verified parity.

use serde::Serialize;

use super::altitude::decode_ac13;
use super::commb::bds20_callsign;
use super::crc;
use super::ident::Callsign;
use super::me::Me;
use super::squawk::Squawk;

/// How the address of a frame was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Parity {
    /// DF11/17/18: the address is in the frame and the parity checked.
    Verified,
    /// DF11 whose parity checked with this interrogator code (II/SI, 1..127) overlaid.
    Interrogator(u8),
    /// DF17: the parity checked after flipping this one bit (opt-in correction only).
    Corrected(u8),
    /// DF0/4/5/16/20/21: the address recovered from address/parity, not verifiable alone.
    AddressParity,
}

/// The DF-specific content of a frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Content {
    /// DF11 all-call reply.
    AllCall {
        /// Transponder capability (CA).
        capability: u8,
    },
    /// DF0/4/5/16/20/21 surveillance or Comm-B reply.
    Surveillance {
        /// Flight status (DF4/5/20/21) or vertical status as 0/1 (DF0/16: VS).
        status: u8,
        /// Altitude, ft (DF0/4/16/20).
        altitude_ft: Option<i32>,
        /// Identity (DF5/21).
        squawk: Option<Squawk>,
        /// Comm-B MB field (DF20/21), 56 bits.
        mb: Option<u64>,
        /// BDS 2,0 callsign when the MB field is recognisably one.
        callsign: Option<Callsign>,
    },
    /// DF17/18 extended squitter.
    Extended {
        /// CA (DF17) or CF (DF18).
        ca_cf: u8,
        /// The raw 56-bit ME field.
        me_raw: u64,
        /// The decoded ME field.
        me: Me,
    },
    /// DF18 with a CF whose ME is not an ADS-B message (coarse TIS-B, management), or DF24.
    NotDecoded,
}

/// One decoded Mode S frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ModeS {
    /// Downlink format (24 for every frame starting with bits 11).
    pub df: u8,
    /// The 24-bit address.
    pub icao: u32,
    /// How the address was obtained.
    pub parity: Parity,
    /// DF-specific content.
    pub content: Content,
}

/// Why a frame was not decoded.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Reject {
    /// The frame length does not match its DF.
    #[error("frame length {len} bytes does not match DF{df}")]
    Length {
        /// DF.
        df: u8,
        /// Length in bytes.
        len: usize,
    },
    /// DF11/17/18 parity did not check.
    #[error("parity check failed for DF{df} (syndrome {syndrome:06X})")]
    Parity {
        /// DF.
        df: u8,
        /// The syndrome.
        syndrome: u32,
    },
    /// A DF this decoder does not handle.
    #[error("unknown downlink format {0}")]
    UnknownDf(u8),
}

/// Decoding options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct DecodeOptions {
    /// Repair DF17 frames whose parity fails by exactly one bit outside the DF field. Off by
    /// default: a corrected frame is a guess, which a DAA stack must not be given.
    pub correct_df17_single_bit: bool,
}

/// The downlink format of a frame (0 for an empty slice).
#[inline]
pub fn downlink_format(frame: &[u8]) -> u8 {
    match frame.first() {
        Some(&b) if b >> 6 == 3 => 24,
        Some(&b) => b >> 3,
        None => 0,
    }
}

#[inline]
fn word32(f: &[u8]) -> u32 {
    // Callers pass at least 7 bytes.
    u32::from_be_bytes([f[0], f[1], f[2], f[3]])
}

#[inline]
fn mb_of(f: &[u8]) -> u64 {
    let mut w = [0u8; 8];
    w[1..].copy_from_slice(&f[4..11]);
    u64::from_be_bytes(w)
}

/// Decodes one frame (7 or 14 bytes) with its parity check.
pub fn decode(frame: &[u8], opts: DecodeOptions) -> Result<ModeS, Reject> {
    let df = downlink_format(frame);
    let want = match df {
        0 | 4 | 5 | 11 => 7,
        16 | 17 | 18 | 20 | 21 | 24 => 14,
        _ => return Err(Reject::UnknownDf(df)),
    };
    if frame.len() != want {
        return Err(Reject::Length {
            df,
            len: frame.len(),
        });
    }
    let syndrome = crc::syndrome(frame);
    let w = word32(frame);
    let addr_field = w & 0xFF_FFFF;
    match df {
        11 => {
            if syndrome >= 0x80 {
                return Err(Reject::Parity { df, syndrome });
            }
            let parity = if syndrome == 0 {
                Parity::Verified
            } else {
                Parity::Interrogator(syndrome as u8)
            };
            Ok(ModeS {
                df,
                icao: addr_field,
                parity,
                content: Content::AllCall {
                    capability: ((w >> 24) & 7) as u8,
                },
            })
        }
        17 | 18 => {
            let mut f = [0u8; 14];
            f.copy_from_slice(frame);
            let mut parity = Parity::Verified;
            if syndrome != 0 {
                let bit = if df == 17 && opts.correct_df17_single_bit {
                    crc::single_bit_error_112(syndrome)
                } else {
                    None
                };
                match bit {
                    Some(b) => {
                        f[b / 8] ^= 0x80 >> (b % 8);
                        parity = Parity::Corrected(b as u8);
                    }
                    None => return Err(Reject::Parity { df, syndrome }),
                }
            }
            let w = word32(&f);
            let me_raw = me_of(&f);
            let ca_cf = ((w >> 24) & 7) as u8;
            let content = if df == 17 || matches!(ca_cf, 0 | 1 | 2 | 5 | 6) {
                Content::Extended {
                    ca_cf,
                    me_raw,
                    me: Me::decode(me_raw),
                }
            } else {
                Content::NotDecoded
            };
            Ok(ModeS {
                df,
                icao: w & 0xFF_FFFF,
                parity,
                content,
            })
        }
        24 => Ok(ModeS {
            df,
            icao: syndrome,
            parity: Parity::AddressParity,
            content: Content::NotDecoded,
        }),
        _ => {
            // DF0/4/5/16/20/21: AP.
            let status = match df {
                0 | 16 => ((w >> 26) & 1) as u8,
                _ => ((w >> 24) & 7) as u8,
            };
            let code13 = (w & 0x1FFF) as u16;
            let (altitude_ft, squawk) = match df {
                5 | 21 => (None, Some(Squawk::from_id13(code13))),
                _ => (decode_ac13(code13), None),
            };
            let mb = (df >= 20).then(|| mb_of(frame));
            Ok(ModeS {
                df,
                icao: syndrome,
                parity: Parity::AddressParity,
                content: Content::Surveillance {
                    status,
                    altitude_ft,
                    squawk,
                    mb,
                    callsign: mb.and_then(bds20_callsign),
                },
            })
        }
    }
}

/// The 56-bit ME (or MB) field of a 14-byte frame.
#[inline]
pub fn me_of(f: &[u8; 14]) -> u64 {
    let mut w = [0u8; 8];
    w[1..].copy_from_slice(&f[4..11]);
    u64::from_be_bytes(w)
}

/// Bits `start..start + len` (1-indexed as the standards number them) of a 56-bit ME field.
#[inline]
pub fn bits(me: u64, start: u32, len: u32) -> u64 {
    (me >> (57 - start - len)) & ((1u64 << len) - 1)
}

#[cfg(test)]
#[path = "df_tests.rs"]
mod tests;
