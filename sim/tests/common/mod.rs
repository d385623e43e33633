//! Helpers shared by the integration tests: decode a port's bytes with the drivers' decoders and
//! re-encode each message with the drivers' encoders, keyed by the offset of its first byte.

#![allow(dead_code)]

use bytes::BytesMut;
use vigil_drivers::DeviceDecoder;
use vigil_drivers::ttmrf::mixed::{MixedDecoder, MixedMessage};
use vigil_drivers::ttmrf::raw::{BeastDecoder, beast, hex};
use vigil_drivers::ttmrf::text::TextMessage;
use vigil_drivers::vn200::Vn200Message;
use vigil_drivers::vn200::ascii::ChecksumKind;

/// Decodes a whole stream, returning (offset of first byte, message) pairs.
pub fn decode_located<D: DeviceDecoder>(mut d: D, bytes: &[u8]) -> Vec<(u64, D::Message)> {
    let mut buf = BytesMut::from(bytes);
    let mut out = Vec::new();
    while let Some(m) = d.decode(&mut buf) {
        out.push((d.stats().last_frame_start, m));
    }
    while let Some(m) = d.decode_eof(&mut buf) {
        out.push((d.stats().last_frame_start, m));
    }
    out
}

/// A VN-200 message as the sensor sends it (binary unsplit, ASCII with an 8-bit checksum).
pub fn vn200_bytes(m: &Vn200Message) -> Vec<u8> {
    match m {
        Vn200Message::Binary(b) => b.encode(),
        Vn200Message::Ascii(a) => a.encode(ChecksumKind::Xor8),
    }
}

/// A TT-Multi-RF text message as the module sends it.
pub fn ttmrf_text_bytes(m: &TextMessage) -> Vec<u8> {
    match m {
        TextMessage::Csv(c) => c.to_line().into_bytes(),
        TextMessage::Json(j) => j.to_wire().into_bytes(),
        TextMessage::Nmea(n) => n.to_line().into_bytes(),
        TextMessage::At(a) => a.to_line().into_bytes(),
    }
}

/// Every message of a TT-Multi-RF port: text (CSV, JSON, NMEA, AT) and raw HEX lines through the
/// drivers' port decoder ([`MixedDecoder`], stream order), and raw Beast frames through their own
/// decoder over the same bytes, merged in offset order.
pub fn ttmrf_located(bytes: &[u8]) -> Vec<(u64, Vec<u8>)> {
    let mut v: Vec<(u64, Vec<u8>)> = decode_located(MixedDecoder::new(), bytes)
        .into_iter()
        .map(|(o, m)| match m {
            MixedMessage::Text(t) => (o, ttmrf_text_bytes(&t)),
            MixedMessage::Raw(f) => {
                let mut b = BytesMut::new();
                hex::encode_hex(&f, true, &mut b);
                (o, b.to_vec())
            }
        })
        .collect();
    for (o, f) in decode_located(BeastDecoder::new(), bytes) {
        let mut b = BytesMut::new();
        beast::encode_beast(&f, &mut b);
        v.push((o, b.to_vec()));
    }
    v.sort_by_key(|e| e.0);
    v
}
