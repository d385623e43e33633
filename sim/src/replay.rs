//! Replay core: feeds a recording's raw chunks through the drivers' decoders (`DeviceDecoder`
//! through `Codec`, so each message comes with `Located::offset`) and stamps every decoded message
//! with the host receive time of the chunk that held its first byte.
//!
//! The decoder of a port is chosen by its channel's `protocol` metadata (`bahrs-2.0`,
//! `watson-ahrs-e304`, `vn200-icd`, `ttmrf-text`, `ttmrf-mavlink`, `ttmrf-gdl90`,
//! `ttmrf-asterix`), else by the device name. A TT-Multi-RF port recorded with a binary decoded
//! protocol is read by that protocol's decoder alone: AT lines on it (state messages after a
//! reset) are skipped bytes in its counters, and a port switched between text and binary
//! protocols by AT commands during the recording decodes only the protocol it started with. `index` counts decoded
//! messages per device (it equals the truth's `index` while nothing of that device was lost or
//! damaged); `offset` equals the truth's `rx_offset` for every intact message. The TT-Multi-RF
//! text port carries text (CSV, JSON, NMEA, AT) and raw Mode S HEX lines interleaved: it is read
//! by the drivers' [`MixedDecoder`], which yields both in stream order. Ports of unknown protocols
//! are counted, not decoded.

use std::collections::{BTreeMap, VecDeque};

use bytes::BytesMut;
use serde::{Serialize, Serializer};
use tokio_util::codec::Decoder as _;
use vigil_drivers::ttmrf::asterix::{AsterixDecoder, AsterixMessage};
use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, Gdl90Message, TrafficAltitude};
use vigil_drivers::ttmrf::mavlink::{MavlinkDecoder, MavlinkMessage};
use vigil_drivers::ttmrf::mixed::{MixedDecoder, MixedMessage};
use vigil_drivers::ttmrf::raw::{RawFrame, RxMeta, encode_hex_string};
use vigil_drivers::ttmrf::text::TextMessage;
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};
use vigil_drivers::{Codec, DecodeStats, DeviceDecoder, bahrs, watson};

/// A decoded message of any device.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Message<'a> {
    /// BAHRS protocol 2.0.
    Bahrs(&'a bahrs::Message),
    /// Watson AHRS-E304 line.
    Watson(&'a watson::Line),
    /// VN-200 binary or ASCII message.
    Vn200(&'a Vn200Message),
    /// TT-Multi-RF decoded message: text (CSV, JSON, NMEA, AT) or binary (MAVLink, GDL90,
    /// ASTERIX).
    Ttmrf(TtmrfMessage<'a>),
    /// TT-Multi-RF raw frame (HEX line), written as a [`RawLine`].
    #[serde(serialize_with = "raw_line")]
    TtmrfRaw(&'a RawFrame),
}

/// A TT-Multi-RF decoded-protocol message.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(untagged)]
pub enum TtmrfMessage<'a> {
    /// CSV, JSON, NMEA or AT.
    Text(&'a TextMessage),
    /// MAVLink ADSB_VEHICLE / COLLISION.
    Mavlink(&'a MavlinkMessage),
    /// GDL90.
    Gdl90(&'a Gdl90Message),
    /// ASTERIX CAT021 / CAT023 record.
    Asterix(&'a AsterixMessage),
}

fn raw_line<S: Serializer>(f: &&RawFrame, s: S) -> Result<S::Ok, S::Error> {
    RawLine::of(f).serialize(s)
}

/// A raw frame of the TT-Multi-RF port as replay writes it: the frame's bytes in hex and the
/// receiver's metadata (the Mode S content is the Mode S decoder's job).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RawLine {
    /// "mode_s", "mode_ac" or "uat".
    pub raw: &'static str,
    /// Frame bytes, upper-case hex (Mode A/C: the four octal digits as two bytes).
    pub frame_hex: String,
    /// Receive metadata (signal, TS1s, TS24h).
    pub meta: RxMeta,
}

impl RawLine {
    /// The output form of a raw frame.
    pub fn of(f: &RawFrame) -> Self {
        let (raw, bytes, meta) = match f {
            RawFrame::ModeS(m) => ("mode_s", m.data().to_vec(), m.meta),
            RawFrame::ModeAc(m) => ("mode_ac", m.code.0.to_be_bytes().to_vec(), m.meta),
            RawFrame::Uat(u) => ("uat", u.bytes.clone(), u.meta),
        };
        Self {
            raw,
            frame_hex: encode_hex_string(&bytes),
            meta,
        }
    }
}

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

/// Wraps a driver's message type into [`Message`].
trait Wrap {
    fn wrap(&self) -> Message<'_>;
}

impl Wrap for bahrs::Message {
    fn wrap(&self) -> Message<'_> {
        Message::Bahrs(self)
    }
}

impl Wrap for watson::Line {
    fn wrap(&self) -> Message<'_> {
        Message::Watson(self)
    }
}

impl Wrap for Vn200Message {
    fn wrap(&self) -> Message<'_> {
        Message::Vn200(self)
    }
}

impl Wrap for MixedMessage {
    fn wrap(&self) -> Message<'_> {
        match self {
            MixedMessage::Text(t) => Message::Ttmrf(TtmrfMessage::Text(t)),
            MixedMessage::Raw(f) => Message::TtmrfRaw(f),
        }
    }
}

impl Wrap for MavlinkMessage {
    fn wrap(&self) -> Message<'_> {
        Message::Ttmrf(TtmrfMessage::Mavlink(self))
    }
}

impl Wrap for Gdl90Message {
    fn wrap(&self) -> Message<'_> {
        Message::Ttmrf(TtmrfMessage::Gdl90(self))
    }
}

impl Wrap for AsterixMessage {
    fn wrap(&self) -> Message<'_> {
        Message::Ttmrf(TtmrfMessage::Asterix(self))
    }
}

struct Port<D: DeviceDecoder> {
    codec: Codec<D>,
    buf: BytesMut,
    chunks: VecDeque<(u64, u64)>,
    fed: u64,
    index: u64,
}

impl<D: DeviceDecoder> Port<D> {
    fn new(decoder: D) -> Self {
        Self {
            codec: Codec(decoder),
            buf: BytesMut::with_capacity(1 << 12),
            chunks: VecDeque::new(),
            fed: 0,
            index: 0,
        }
    }

    /// Receive time of the chunk holding stream offset `offset` (offsets only grow).
    fn t_host_of(&mut self, offset: u64) -> u64 {
        while self.chunks.len() > 1 && self.chunks[1].0 <= offset {
            self.chunks.pop_front();
        }
        self.chunks.front().map_or(0, |c| c.1)
    }

    fn run<E>(
        &mut self,
        device: &str,
        eof: bool,
        f: &mut impl FnMut(Decoded<'_>) -> Result<(), E>,
    ) -> Result<(), E>
    where
        D::Message: Wrap,
    {
        loop {
            let next = if eof {
                self.codec.decode_eof(&mut self.buf)
            } else {
                self.codec.decode(&mut self.buf)
            };
            // `Codec` never returns an error.
            let Ok(Some(l)) = next else { return Ok(()) };
            let t_host_ns = self.t_host_of(l.offset);
            let index = self.index;
            self.index += 1;
            f(Decoded {
                device,
                index,
                offset: l.offset,
                t_host_ns,
                message: l.message.wrap(),
            })?;
        }
    }

    fn push(&mut self, t_host_ns: u64, bytes: &[u8]) {
        self.chunks.push_back((self.fed, t_host_ns));
        self.fed += bytes.len() as u64;
        self.buf.extend_from_slice(bytes);
    }
}

enum AnyPort {
    Bahrs(Port<bahrs::Decoder>),
    Watson(Port<watson::Decoder>),
    Vn200(Box<Port<Vn200Decoder>>),
    Ttmrf(Box<Port<MixedDecoder>>),
    TtmrfMavlink(Box<Port<MavlinkDecoder>>),
    TtmrfGdl90(Box<Port<Gdl90Decoder>>),
    TtmrfAsterix(Box<Port<AsterixDecoder>>),
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
            let port = match (protocol, device) {
                ("bahrs-2.0", _) | ("", "bahrs") => {
                    AnyPort::Bahrs(Port::new(bahrs::Decoder::new()))
                }
                ("watson-ahrs-e304", _) | ("", "watson") => {
                    AnyPort::Watson(Port::new(watson::Decoder::new()))
                }
                ("vn200-icd", _) | ("", "vn200") => {
                    AnyPort::Vn200(Box::new(Port::new(Vn200Decoder::new())))
                }
                ("ttmrf-text", _) | ("", "ttmrf") => {
                    AnyPort::Ttmrf(Box::new(Port::new(MixedDecoder::new())))
                }
                ("ttmrf-mavlink", _) => {
                    AnyPort::TtmrfMavlink(Box::new(Port::new(MavlinkDecoder::new())))
                }
                // The model sends pressure altitude in Traffic Reports (barometric priority).
                ("ttmrf-gdl90", _) => AnyPort::TtmrfGdl90(Box::new(Port::new(Gdl90Decoder::new(
                    TrafficAltitude::Pressure,
                )))),
                ("ttmrf-asterix", _) => {
                    AnyPort::TtmrfAsterix(Box::new(Port::new(AsterixDecoder::default())))
                }
                _ => AnyPort::NoDecoder {
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
            AnyPort::Bahrs(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::Watson(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::Vn200(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::Ttmrf(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::TtmrfMavlink(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::TtmrfGdl90(p) => {
                p.push(t_host_ns, bytes);
                p.run(device, false, f)
            }
            AnyPort::TtmrfAsterix(p) => {
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
            AnyPort::Bahrs(p) => Some(*p.codec.0.stats()),
            AnyPort::Watson(p) => Some(*p.codec.0.stats()),
            AnyPort::Vn200(p) => Some(*p.codec.0.stats()),
            AnyPort::Ttmrf(p) => Some(*p.codec.0.stats()),
            AnyPort::TtmrfMavlink(p) => Some(*p.codec.0.stats()),
            AnyPort::TtmrfGdl90(p) => Some(*p.codec.0.stats()),
            AnyPort::TtmrfAsterix(p) => Some(*p.codec.0.stats()),
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
                AnyPort::Bahrs(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
                }
                AnyPort::Watson(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
                }
                AnyPort::Vn200(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
                }
                AnyPort::Ttmrf(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
                }
                AnyPort::TtmrfMavlink(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
                }
                AnyPort::TtmrfGdl90(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
                }
                AnyPort::TtmrfAsterix(p) => {
                    p.run(device, true, f)?;
                    PortSummary::Decoded(*p.codec.0.stats())
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
    use vigil_drivers::bahrs::SyncPulseTime;

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
}
