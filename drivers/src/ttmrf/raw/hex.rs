//! HEX and HEXd raw lines (TT-Multi-RF manual 7.2.2 "ADS-B HEX protocol", "ADS-B HEXd
//! protocol", 10.2.2 "UAT raw protocols").
//!
//! ```text
//! *8D4CA7E858B9838206BA422BBD7B; (-71,4,75BCD15,2B5792B49315)\r\n   HEX, Mode S long
//! *7700; (-95,167,75BCD15,2B5792B49315)\r\n                         HEX, Mode A/C (octal digits)
//! *5D4B18FFFC710B;\n                                                 HEXd (dump1090 AVR)
//! @030BF18CC2AB5F4001594B0FBB;\n                                     AVR with 12 MHz MLAT ticks
//! ```
//!
//! Extended fields: SIGS (dBm, signed decimal), SIGQ (decimal), TS1s and TS24h (hexadecimal
//! nanoseconds). Decisions where the manual is loose:
//! - the OCR'd examples read `(=70, 3, ...)`: we take SIGS as a signed decimal and accept spaces;
//!   two to four fields are accepted (the TS fields exist only with a PPS);
//! - payload kind by length: 4 digits Mode A/C, 14/28 Mode S, otherwise a UAT frame if its byte
//!   count is one UAT frames have (18/34 downlink, 432 uplink, or with Reed-Solomon parity
//!   30/48/552: the manual's "long frame has 48 bytes" example), else malformed;
//! - a line ends at `\n` (a preceding `\r` is dropped); at most [`MAX_LINE`] bytes, so a line
//!   without an end is skipped rather than buffered forever.

use bytes::BytesMut;

use super::{ModeAcFrame, ModeSFrame, RawFrame, RxMeta, UatFrame, mode_ac_code};
use crate::modes::hex_val;
use crate::{DecodeStats, DeviceDecoder};

/// Longest line accepted: a 552-byte UAT uplink (1104 digits) plus fields, with margin.
pub const MAX_LINE: usize = 1280;

/// Byte lengths accepted as UAT payloads (see the module doc).
const UAT_LENGTHS: [usize; 6] = [18, 30, 34, 48, 432, 552];

/// Decoder of HEX / HEXd / AVR lines.
#[derive(Debug, Default, Clone)]
pub struct HexDecoder {
    stats: DecodeStats,
}

impl HexDecoder {
    /// A new decoder.
    pub fn new() -> Self {
        Self::default()
    }
}

#[inline]
fn is_start(b: u8) -> bool {
    b == b'*' || b == b'@'
}

/// Parses the hex digits of `s` into `out` (whose length is `s.len() / 2`).
#[inline]
fn hex_into(s: &[u8], out: &mut [u8]) -> Option<()> {
    if s.len() != out.len() * 2 {
        return None;
    }
    for (o, p) in out.iter_mut().zip(s.chunks_exact(2)) {
        *o = (hex_val(p[0])? << 4) | hex_val(p[1])?;
    }
    Some(())
}

fn parse_hex_u64(s: &[u8]) -> Option<u64> {
    if s.is_empty() || s.len() > 16 {
        return None;
    }
    s.iter()
        .try_fold(0u64, |acc, &c| Some((acc << 4) | u64::from(hex_val(c)?)))
}

fn parse_dec_i16(s: &[u8]) -> Option<i16> {
    let (neg, digits) = match s.first() {
        Some(b'-') => (true, &s[1..]),
        Some(b'+') => (false, &s[1..]),
        _ => (false, s),
    };
    if digits.is_empty() || digits.len() > 5 {
        return None;
    }
    let mut v: i32 = 0;
    for &c in digits {
        if !c.is_ascii_digit() {
            return None;
        }
        v = v * 10 + i32::from(c - b'0');
    }
    i16::try_from(if neg { -v } else { v }).ok()
}

fn trim(mut s: &[u8]) -> &[u8] {
    while let [b' ' | b'\t', rest @ ..] = s {
        s = rest;
    }
    while let [rest @ .., b' ' | b'\t'] = s {
        s = rest;
    }
    s
}

/// Parses the extended fields `(SIGS,SIGQ[,TS1s[,TS24h]])` into `meta`.
fn parse_fields(s: &[u8], meta: &mut RxMeta) -> Option<()> {
    let s = trim(s);
    if s.is_empty() {
        return Some(());
    }
    let inner = s.strip_prefix(b"(")?.strip_suffix(b")")?;
    let mut n = 0;
    for (i, f) in inner.split(|&c| c == b',').enumerate() {
        let f = trim(f);
        match i {
            0 => meta.signal_dbm = Some(parse_dec_i16(f)?),
            1 => meta.signal_quality = Some(parse_dec_i16(f)?),
            2 => meta.ts_pps_ns = Some(parse_hex_u64(f)?),
            3 => meta.ts_utc_ns = Some(parse_hex_u64(f)?),
            _ => return None,
        }
        n = i + 1;
    }
    (n >= 2).then_some(())
}

/// Parses one line (without its `\n`; a trailing `\r` is allowed).
pub fn parse_line(line: &[u8]) -> Option<RawFrame> {
    let line = line.strip_suffix(b"\r").unwrap_or(line);
    let (&start, rest) = line.split_first()?;
    let semi = rest.iter().position(|&c| c == b';')?;
    let (mut payload, fields) = (&rest[..semi], &rest[semi + 1..]);
    let mut meta = RxMeta::default();
    if start == b'@' {
        let (ts, p) = payload.split_at_checked(12)?;
        let t = parse_hex_u64(ts)?;
        meta.mlat_ticks = (t != 0).then_some(t);
        payload = p;
    } else if start != b'*' {
        return None;
    }
    parse_fields(fields, &mut meta)?;
    match payload.len() {
        4 => {
            let mut b = [0u8; 2];
            hex_into(payload, &mut b)?;
            let code = mode_ac_code(u16::from_be_bytes(b))?;
            Some(RawFrame::ModeAc(ModeAcFrame { code, meta }))
        }
        14 | 28 => {
            let mut bytes = [0u8; 14];
            let len = payload.len() / 2;
            hex_into(payload, &mut bytes[..len])?;
            Some(RawFrame::ModeS(ModeSFrame {
                bytes,
                len: len as u8,
                meta,
            }))
        }
        n if n % 2 == 0 && UAT_LENGTHS.contains(&(n / 2)) && start == b'*' => {
            let mut bytes = vec![0u8; n / 2];
            hex_into(payload, &mut bytes)?;
            Some(RawFrame::Uat(UatFrame {
                // 432 bytes (552 with parity) is an uplink; downlinks are 18 to 48.
                uplink: bytes.len() >= 432,
                bytes,
                meta,
            }))
        }
        _ => None,
    }
}

impl DeviceDecoder for HexDecoder {
    type Message = RawFrame;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<RawFrame> {
        loop {
            if buf.is_empty() {
                return None;
            }
            if !is_start(buf[0]) {
                let n = buf.iter().position(|&b| is_start(b)).unwrap_or(buf.len());
                self.stats.skip(buf, n);
                continue;
            }
            // One pass over the line: its end, and any start byte inside it (which means the
            // line holds a broken frame followed by another: only the broken part is dropped).
            let window = &buf[..buf.len().min(MAX_LINE)];
            let mut nl = None;
            let mut next_start = None;
            for (i, &b) in window.iter().enumerate().skip(1) {
                if b == b'\n' {
                    nl = Some(i);
                    break;
                }
                if next_start.is_none() && is_start(b) {
                    next_start = Some(i);
                }
            }
            let Some(nl) = nl else {
                if buf.len() >= MAX_LINE {
                    self.stats.malformed += 1;
                    self.stats.skip(buf, 1);
                    continue;
                }
                return None;
            };
            let end = next_start.unwrap_or(nl);
            match parse_line(&buf[..end]) {
                Some(f) if next_start.is_none() => {
                    self.stats.take_frame(buf, nl + 1);
                    return Some(f);
                }
                _ => {
                    self.stats.malformed += 1;
                    let n = next_start.unwrap_or(nl + 1);
                    self.stats.skip(buf, n);
                }
            }
        }
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<RawFrame> {
        if let Some(f) = self.decode(buf) {
            return Some(f);
        }
        if buf.is_empty() {
            return None;
        }
        // A last line without its newline (the buffer starts with a start byte here).
        let n = buf.len();
        if buf[1..].iter().all(|&b| !is_start(b))
            && let Some(f) = parse_line(&buf[..])
        {
            self.stats.take_frame(buf, n);
            return Some(f);
        }
        self.stats.malformed += 1;
        self.stats.skip(buf, n);
        None
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

fn push_hex(out: &mut BytesMut, bytes: &[u8]) {
    const D: &[u8; 16] = b"0123456789ABCDEF";
    for &b in bytes {
        out.extend_from_slice(&[D[usize::from(b >> 4)], D[usize::from(b & 15)]]);
    }
}

/// Writes a frame as a HEX line: `*<hex>;` then, when `extended` and the frame has a signal
/// level, ` (SIGS,SIGQ,TS1s,TS24h)` (times omitted when absent), then CRLF. With `extended`
/// false it writes HEXd (`*<hex>;` CRLF).
pub fn encode_hex(frame: &RawFrame, extended: bool, out: &mut BytesMut) {
    out.extend_from_slice(b"*");
    let meta = match frame {
        RawFrame::ModeS(f) => {
            push_hex(out, f.data());
            f.meta
        }
        RawFrame::ModeAc(f) => {
            push_hex(out, &f.code.0.to_be_bytes());
            f.meta
        }
        RawFrame::Uat(f) => {
            push_hex(out, &f.bytes);
            f.meta
        }
    };
    out.extend_from_slice(b";");
    if extended && let Some(s) = meta.signal_dbm {
        let mut fields = format!(" ({},{}", s, meta.signal_quality.unwrap_or(0));
        if let Some(t) = meta.ts_pps_ns {
            fields.push_str(&format!(",{t:X}"));
            if let Some(u) = meta.ts_utc_ns {
                fields.push_str(&format!(",{u:X}"));
            }
        }
        fields.push(')');
        out.extend_from_slice(fields.as_bytes());
    }
    out.extend_from_slice(b"\r\n");
}

#[cfg(test)]
#[path = "hex_tests.rs"]
mod tests;
