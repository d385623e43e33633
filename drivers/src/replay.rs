//! Replay core: the raw chunks of any number of ports (a recording's, the simulator's) through
//! their [`PortDecoder`]s, each decoded message stamped with the host receive time of the chunk
//! that held its first byte. Sans-IO: chunks and their times are passed in.
//!
//! The decoder of a port is chosen once, when its first chunk arrives, by the protocol table
//! ([`Protocol::resolve`] of its channel's `protocol` metadata, else of the device name). A
//! TT-Multi-RF port recorded with a binary decoded protocol is read by that protocol's decoder
//! alone: AT lines on it (state messages after a reset) are skipped bytes in its counters, and a
//! port switched between text and binary protocols by AT commands during the recording decodes
//! only the protocol it started with. `index` counts decoded messages per device (it equals the
//! simulator truth's `index` while nothing of that device was lost or damaged); `offset` equals
//! the truth's `rx_offset` for every intact message. The TT-Multi-RF text port carries text (CSV,
//! JSON, NMEA, AT) and raw Mode S HEX lines interleaved: it is read by the
//! [`MixedDecoder`](crate::ttmrf::mixed::MixedDecoder), which yields both in stream order. Ports
//! of unknown protocols are counted, not decoded.

use std::collections::{BTreeMap, VecDeque};

use bytes::BytesMut;
use serde::Serialize;

use crate::DecodeStats;
use crate::protocol::{PortDecoder, PortFrame, Protocol};

pub use crate::protocol::{Message, RawLine, TtmrfMessage};

/// One decoded message with its place in the recording.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Decoded<'a> {
    /// Device (port) name.
    pub device: &'a str,
    /// 0-based order among this device's decoded messages.
    pub index: u64,
    /// Offset of its first byte in the port's received stream.
    pub offset: u64,
    /// Host receive time of the chunk holding its first byte, ns.
    pub t_host_ns: u64,
    /// The message.
    pub message: Message<'a>,
}

/// What a port's replay counted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum PortSummary {
    /// A decoded port: the decoder's counters.
    Decoded(DecodeStats),
    /// A port without a decoder.
    NoDecoder {
        /// Always true.
        no_decoder: bool,
        /// Chunks seen.
        chunks: u64,
        /// Bytes seen.
        bytes: u64,
    },
}

/// A decoded port: its decoder, its unconsumed bytes and the receive times of its chunks.
struct Port {
    decoder: PortDecoder,
    buf: BytesMut,
    chunks: VecDeque<(u64, u64)>,
    fed: u64,
    index: u64,
}

impl Port {
    fn new(protocol: Protocol) -> Self {
        Self {
            decoder: PortDecoder::new(protocol),
            buf: BytesMut::with_capacity(1 << 12),
            chunks: VecDeque::new(),
            fed: 0,
            index: 0,
        }
    }

    /// Receive time of the chunk holding stream offset `offset` (offsets only grow).
    fn t_host_of(chunks: &mut VecDeque<(u64, u64)>, offset: u64) -> u64 {
        while chunks.len() > 1 && chunks[1].0 <= offset {
            chunks.pop_front();
        }
        chunks.front().map_or(0, |c| c.1)
    }

    fn run<E>(
        &mut self,
        device: &str,
        eof: bool,
        f: &mut impl FnMut(Decoded<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let Self {
            decoder,
            buf,
            chunks,
            index,
            ..
        } = self;
        decoder.decode(buf, eof, &mut |m: PortFrame| {
            let t_host_ns = Self::t_host_of(chunks, m.offset);
            let i = *index;
            *index += 1;
            f(Decoded {
                device,
                index: i,
                offset: m.offset,
                t_host_ns,
                message: m.message.as_message(),
            })
        })
    }

    fn push(&mut self, t_host_ns: u64, bytes: &[u8]) {
        self.chunks.push_back((self.fed, t_host_ns));
        self.fed += bytes.len() as u64;
        self.buf.extend_from_slice(bytes);
    }
}

enum AnyPort {
    Decoded(Box<Port>),
    NoDecoder { chunks: u64, bytes: u64 },
}

/// Replays chunks of any number of ports.
#[derive(Default)]
pub struct Replayer {
    ports: BTreeMap<String, AnyPort>,
}

impl Replayer {
    /// A replayer with no ports yet (they are created as their first chunk arrives).
    pub fn new() -> Self {
        Self::default()
    }

    /// Feeds one chunk of `device` (channel protocol `protocol`, may be empty) and hands every
    /// message it completes to `f`.
    pub fn feed<E>(
        &mut self,
        device: &str,
        protocol: &str,
        t_host_ns: u64,
        bytes: &[u8],
        f: &mut impl FnMut(Decoded<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        if !self.ports.contains_key(device) {
            let port = match Protocol::resolve(protocol, device) {
                Some(p) => AnyPort::Decoded(Box::new(Port::new(p))),
                None => AnyPort::NoDecoder {
                    chunks: 0,
                    bytes: 0,
                },
            };
            self.ports.insert(device.to_string(), port);
        }
        let Some(port) = self.ports.get_mut(device) else {
            return Ok(());
        };
        match port {
            AnyPort::Decoded(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::NoDecoder { chunks, bytes: n } => {
                *chunks += 1;
                *n += bytes.len() as u64;
                Ok(())
            }
        }
    }

    /// The decoder counters of `device` so far (`None` for a port without a decoder or not seen
    /// yet). Used by `vigil run` for its periodic integrity report while the stream goes on.
    pub fn stats(&self, device: &str) -> Option<DecodeStats> {
        match self.ports.get(device)? {
            AnyPort::Decoded(p) => Some(p.decoder.stats()),
            AnyPort::NoDecoder { .. } => None,
        }
    }

    /// Ends every port's stream (decoding what is left) and returns their counters.
    pub fn finish<E>(
        &mut self,
        f: &mut impl FnMut(Decoded<'_>) -> Result<(), E>,
    ) -> Result<BTreeMap<String, PortSummary>, E> {
        let mut out = BTreeMap::new();
        for (device, port) in &mut self.ports {
            let s = match port {
                AnyPort::Decoded(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(p.decoder.stats())
                }
                AnyPort::NoDecoder { chunks, bytes } => PortSummary::NoDecoder {
                    no_decoder: true,
                    chunks: *chunks,
                    bytes: *bytes,
                },
            };
            out.insert(device.clone(), s);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bahrs::{self, SyncPulseTime};

    #[test]
    fn messages_get_the_receive_time_of_their_first_byte() {
        // Two 0x06 frames (20 bytes each) cut into chunks of 15, 15 and 10 bytes received at 100,
        // 200 and 300 ns: the first starts in chunk 1, the second at byte 20, in chunk 2.
        let mut bytes = Vec::new();
        for seq in 0..2 {
            bahrs::Message::SyncPulseTime(SyncPulseTime {
                seq,
                mcu_time_us: 7,
            })
            .encode(&mut bytes);
        }
        assert_eq!(bytes.len(), 40);
        let mut r = Replayer::new();
        let mut got = Vec::new();
        let mut f = |d: Decoded<'_>| -> Result<(), ()> {
            got.push((d.index, d.offset, d.t_host_ns));
            Ok(())
        };
        for (i, c) in [&bytes[..15], &bytes[15..30], &bytes[30..]]
            .iter()
            .enumerate()
        {
            r.feed("bahrs", "", 100 * (i as u64 + 1), c, &mut f)
                .unwrap();
        }
        // Not one of the table's names (exact names only): counted, not decoded.
        r.feed("vn200", "vn200-binary", 400, &[1, 2, 3], &mut f)
            .unwrap();
        let summary = r.finish(&mut f).unwrap();
        assert_eq!(got, vec![(0, 0, 100), (1, 20, 200)]);
        assert!(matches!(summary["bahrs"], PortSummary::Decoded(s) if s.frames_decoded == 2));
        assert_eq!(
            summary["vn200"],
            PortSummary::NoDecoder {
                no_decoder: true,
                chunks: 1,
                bytes: 3
            }
        );
    }

    #[test]
    fn ttmrf_port_yields_text_and_raw_lines_in_stream_order() {
        // AT line (14 bytes), HEXd line (18 bytes), AT line: offsets 0, 14, 32; the chunks start
        // at 0, 10 and 20, received at 1, 2 and 3 ns.
        let bytes = b"AT+RUN_START\r\n*5D4B18FFFC710B;\r\nAT+RUN_END\r\n";
        let mut r = Replayer::new();
        let mut got = Vec::new();
        let mut f = |d: Decoded<'_>| -> Result<(), ()> {
            let raw = matches!(d.message, Message::TtmrfRaw(_));
            let json = serde_json::to_value(d.message).unwrap();
            got.push((d.index, d.offset, d.t_host_ns, raw, json));
            Ok(())
        };
        for (i, c) in [&bytes[..10], &bytes[10..20], &bytes[20..]]
            .iter()
            .enumerate()
        {
            r.feed("ttmrf", "ttmrf-text", i as u64 + 1, c, &mut f)
                .unwrap();
        }
        let summary = r.finish(&mut f).unwrap();
        let pos: Vec<_> = got.iter().map(|g| (g.0, g.1, g.2, g.3)).collect();
        assert_eq!(
            pos,
            vec![(0, 0, 1, false), (1, 14, 2, true), (2, 32, 3, false)]
        );
        assert_eq!(got[1].4["frame_hex"], "5D4B18FFFC710B");
        assert_eq!(got[1].4["raw"], "mode_s");
        let PortSummary::Decoded(s) = summary["ttmrf"] else {
            panic!("{summary:?}")
        };
        assert_eq!(
            (s.frames_decoded, s.bytes_consumed),
            (3, bytes.len() as u64)
        );
    }

    #[test]
    fn a_ttmrf_hex_port_is_decoded() {
        // Before the drivers' protocol table this protocol had no decoder in replay (issue 19).
        let mut r = Replayer::new();
        let mut got = Vec::new();
        let mut f = |d: Decoded<'_>| -> Result<(), ()> {
            got.push((d.offset, serde_json::to_value(d.message).unwrap()));
            Ok(())
        };
        r.feed("adsb", "ttmrf-hex", 5, b"*5D4B18FFFC710B;\r\n", &mut f)
            .unwrap();
        r.finish(&mut f).unwrap();
        assert_eq!(got.len(), 1);
        assert_eq!(got[0].0, 0);
        assert_eq!(got[0].1["frame_hex"], "5D4B18FFFC710B");
    }
}
