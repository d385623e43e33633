//! The one protocol table: every wire protocol vigil decodes, its name in configurations and
//! recordings, its default baud, its device family, and [`PortDecoder`], which dispatches a
//! port's bytes to that protocol's codec.
//!
//! # How to add a protocol
//!
//! 1. Add one row to the `protocols!` table below: the variant, its name, default baud, device
//!    family, decoder and message constructor. The macro makes the [`Protocol`] variant, its
//!    entries in [`Protocol::ALL`], [`Protocol::name`], [`Protocol::default_baud`] and
//!    [`Protocol::device`], and its [`PortDecoder`] variant with its arm in every dispatch.
//! 2. Only if its decoder yields a message type not yet in [`PortMessage`]: add it there and to
//!    [`PortMessage::as_message`] / [`Message`] (and to fusion's `Sample`, to use it).
//! 3. The compiler then lists whatever else must decide about it (exhaustive matches in the
//!    service's policy, e.g. its default read interval). Nothing else selects decoders by string: the name is
//!    parsed once, by [`Protocol::resolve`], when a port is configured or a recorded channel is
//!    first seen.
//!
//! Decision (resolution of a recorded channel's `protocol` metadata, issue 19): names are matched
//! exactly, and an empty name falls back to the four standard device names (`bahrs`, `watson`,
//! `vn200`, `ttmrf`). Before this table, `vigil replay --emit aligned`/`fused` matched prefixes
//! (`vn200*`, `ttmrf-hex*`, other `ttmrf*`) while `--emit decoded` and the configuration matched
//! exactly. Exact matching won: every recording vigil and its simulator write carries one of the
//! [`Protocol::name`]s (they are written from this table), the configuration already refuses other
//! names, and a prefix guess would decode a channel named, say, `vn200-binary-v3` with a decoder
//! that may not be its own, where an unknown name stays visible (the port is counted, not
//! decoded). `ttmrf-hex` is now decoded by `--emit decoded` as well (it was counted as a port
//! without decoder there, while the aligned path decoded it).

use bytes::BytesMut;
use serde::{Serialize, Serializer};
use tokio_util::codec::Decoder as _;

use crate::ttmrf::asterix::{AsterixDecoder, AsterixMessage};
use crate::ttmrf::gdl90::{Gdl90Decoder, Gdl90Message, TrafficAltitude};
use crate::ttmrf::mavlink::{MavlinkDecoder, MavlinkMessage};
use crate::ttmrf::mixed::{MixedDecoder, MixedMessage};
use crate::ttmrf::raw::hex::HexDecoder;
use crate::ttmrf::raw::{RawFrame, RxMeta, encode_hex_string};
use crate::ttmrf::text::TextMessage;
use crate::vn200::Vn200Message;
use crate::vn200::boxed::BoxedDecoder;
use crate::{Codec, DecodeStats, DeviceDecoder, bahrs, watson};

/// The table: one row per wire protocol, expanded by [`protocols!`] into [`Protocol`] (with
/// [`Protocol::ALL`], [`Protocol::name`], [`Protocol::default_baud`], [`Protocol::device`]) and
/// [`PortDecoder`] (its codec, [`PortDecoder::new`], [`PortDecoder::protocol`],
/// [`PortDecoder::decode`], [`PortDecoder::stats`]). A row: the variant (with its doc), its name
/// in configurations and recordings, its default baud rate (bit/s), its device family, its codec's
/// decoder type and how to make one, and the [`PortMessage`] constructor of its messages.
///
/// Default bauds: the Watson's is the only one its document fixes (9600); the VN-200 and the
/// TT-Multi-RF run at 921 600 (a rate both documents list; the VN-200's factory 115 200 cannot
/// carry its 400 Hz outputs); the BAHRS document names no rate (115 200 is the installation's).
macro_rules! protocols {
    ($(
        $(#[$doc:meta])*
        $variant:ident {
            name: $name:literal,
            baud: $baud:expr,
            device: $device:ident,
            decoder: $decoder:ty = $new:expr,
            message: $wrap:expr $(,)?
        }
    ),+ $(,)?) => {
        /// The wire protocol of a port: selects the decoder and the device family.
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum Protocol {
            $($(#[$doc])* $variant,)+
        }

        impl Protocol {
            /// Every protocol, in table order.
            pub const ALL: [Protocol; [$(Protocol::$variant),+].len()] = [$(Protocol::$variant),+];

            /// The protocol's name in the configuration and in recordings' channel metadata (the
            /// names `vigil replay` selects decoders by).
            pub const fn name(self) -> &'static str {
                match self {
                    $(Protocol::$variant => $name,)+
                }
            }

            /// The device's usual baud rate, bit/s (the simulator's defaults).
            pub const fn default_baud(self) -> u32 {
                match self {
                    $(Protocol::$variant => $baud,)+
                }
            }

            /// The device family speaking this protocol.
            pub const fn device(self) -> Device {
                match self {
                    $(Protocol::$variant => Device::$device,)+
                }
            }
        }

        /// The decoder of one port: one variant per [`Protocol`], each holding its codec (boxed:
        /// the decoders' buffers differ widely in size). Built once per port
        /// ([`PortDecoder::new`]); decoding dispatches by one match, no strings, no lookups.
        pub enum PortDecoder {
            $(
                #[doc = concat!("[`Protocol::", stringify!($variant), "`].")]
                $variant(Box<Codec<$decoder>>),
            )+
        }

        impl PortDecoder {
            /// The decoder of `protocol`, at the start of its stream.
            pub fn new(protocol: Protocol) -> Self {
                match protocol {
                    $(Protocol::$variant => PortDecoder::$variant(Box::new(Codec($new))),)+
                }
            }

            /// The protocol this decoder reads.
            pub fn protocol(&self) -> Protocol {
                match self {
                    $(PortDecoder::$variant(_) => Protocol::$variant,)+
                }
            }

            /// Decodes every message `buf` completes (removing its bytes) and hands each to `f`,
            /// in stream order. `buf` holds the port's received bytes not yet consumed (append
            /// each read to it); `eof`: no more bytes will come, so what is left is decoded or
            /// counted as skipped. Stops at the first error of `f`.
            pub fn decode<E>(
                &mut self,
                buf: &mut BytesMut,
                eof: bool,
                f: &mut impl FnMut(PortFrame) -> Result<(), E>,
            ) -> Result<(), E> {
                match self {
                    $(PortDecoder::$variant(c) => run(c, buf, eof, $wrap, f),)+
                }
            }

            /// The decoder's counters so far.
            pub fn stats(&self) -> DecodeStats {
                match self {
                    $(PortDecoder::$variant(c) => *c.0.stats(),)+
                }
            }
        }
    };
}

protocols! {
    /// BAHRS protocol 2.0 (binary).
    Bahrs {
        name: "bahrs-2.0",
        baud: 115_200,
        device: Bahrs,
        decoder: bahrs::Decoder = bahrs::Decoder::new(),
        message: PortMessage::Bahrs,
    },
    /// Watson AHRS-E304 text lines.
    Watson {
        name: "watson-ahrs-e304",
        baud: 9600,
        device: Watson,
        decoder: watson::Decoder = watson::Decoder::new(),
        message: PortMessage::Watson,
    },
    /// VN-200 ICD 1.3 (binary and ASCII). Each message is decoded in place into a recycled box
    /// (issue 21; see [`PortDecoder::stock_vn200`]).
    Vn200 {
        name: "vn200-icd",
        baud: 921_600,
        device: Vn200,
        decoder: BoxedDecoder = BoxedDecoder::new(),
        message: PortMessage::Vn200,
    },
    /// TT-Multi-RF text outputs (CSV, JSON, NMEA, ... in auto mode) and raw HEX lines,
    /// interleaved, in stream order.
    TtmrfText {
        name: "ttmrf-text",
        baud: 921_600,
        device: Ttmrf,
        decoder: MixedDecoder = MixedDecoder::new(),
        message: PortMessage::from,
    },
    /// TT-Multi-RF raw HEX lines only.
    TtmrfHex {
        name: "ttmrf-hex",
        baud: 921_600,
        device: Ttmrf,
        decoder: HexDecoder = HexDecoder::new(),
        message: PortMessage::TtmrfRaw,
    },
    /// TT-Multi-RF decoded output in MAVLink 2.
    TtmrfMavlink {
        name: "ttmrf-mavlink",
        baud: 921_600,
        device: Ttmrf,
        decoder: MavlinkDecoder = MavlinkDecoder::new(),
        message: PortMessage::TtmrfMavlink,
    },
    /// TT-Multi-RF decoded output in GDL90 (barometric altitude priority: the simulator's module
    /// sends pressure altitude in Traffic Reports, the GDL90 definition).
    TtmrfGdl90 {
        name: "ttmrf-gdl90",
        baud: 921_600,
        device: Ttmrf,
        decoder: Gdl90Decoder = Gdl90Decoder::new(TrafficAltitude::Pressure),
        message: PortMessage::TtmrfGdl90,
    },
    /// TT-Multi-RF decoded output in ASTERIX CAT021/023.
    TtmrfAsterix {
        name: "ttmrf-asterix",
        baud: 921_600,
        device: Ttmrf,
        decoder: AsterixDecoder = AsterixDecoder::default(),
        message: PortMessage::TtmrfAsterix,
    },
}
impl PortDecoder {
    /// Hands boxes of VN-200 messages the caller is done with to this decoder, if it is the
    /// VN-200's: it decodes its next messages straight into them (issue 21: no 928-byte message
    /// built and moved, no allocation per message). It takes up to its bound
    /// ([`crate::vn200::boxed::SPARE_BOXES`]); other decoders take none.
    pub fn stock_vn200(&mut self, spare: &mut crate::vn200::boxed::SpareBoxes) {
        if let PortDecoder::Vn200(c) = self {
            c.0.stock(spare);
        }
    }
}

/// The device families of the installation (one clock model each in the aligner).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Device {
    /// BAHRS (MCU clock disciplined by the VN-200 PPS).
    Bahrs,
    /// Watson AHRS-E304 (host clock).
    Watson,
    /// VN-200 (native GPS time).
    Vn200,
    /// TT-Multi-RF (UTC time of day, PPS stamps or host clock).
    Ttmrf,
}

impl Device {
    /// Every device, in report order.
    pub const ALL: [Device; 4] = [Device::Bahrs, Device::Watson, Device::Vn200, Device::Ttmrf];

    /// The device (port) name used in recordings and the truth file.
    pub fn name(self) -> &'static str {
        match self {
            Device::Bahrs => "bahrs",
            Device::Watson => "watson",
            Device::Vn200 => "vn200",
            Device::Ttmrf => "ttmrf",
        }
    }
}

impl Protocol {
    /// The protocol of a port or recorded channel: `protocol` is one of the [`Protocol::name`]s
    /// exactly, or empty, and then the standard device names `bahrs`, `watson`, `vn200`, `ttmrf`
    /// imply it. `None`: not a protocol vigil decodes (see the module's decision on exact names).
    pub fn resolve(protocol: &str, device: &str) -> Option<Protocol> {
        if protocol.is_empty() {
            return match device {
                "bahrs" => Some(Protocol::Bahrs),
                "watson" => Some(Protocol::Watson),
                "vn200" => Some(Protocol::Vn200),
                "ttmrf" => Some(Protocol::TtmrfText),
                _ => None,
            };
        }
        Protocol::ALL.into_iter().find(|p| p.name() == protocol)
    }
}

/// A decoded message of any protocol, owned (what [`PortDecoder`] yields; the aligner takes it
/// without a copy).
///
/// Decision: not boxed (clippy's `large_enum_variant`): a `PortMessage` lives only from the
/// decoder to the caller's callback, where it is either serialised in place (`--emit decoded`)
/// or moved into the aligner's boxed sample. The VN-200 message (928 bytes, 400 Hz) is the
/// exception: it comes boxed, decoded in place into a box the caller may hand back with
/// [`PortDecoder::stock_vn200`] (the ingest stage does: no allocation per message); a caller
/// that does not (`--emit decoded`) pays one allocation per VN-200 message.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum PortMessage {
    /// BAHRS protocol 2.0.
    Bahrs(bahrs::Message),
    /// Watson AHRS-E304 line.
    Watson(watson::Line),
    /// VN-200 binary or ASCII message (boxed: see the decision above).
    Vn200(Box<Vn200Message>),
    /// TT-Multi-RF text output (CSV, JSON, NMEA, AT).
    TtmrfText(TextMessage),
    /// TT-Multi-RF raw frame (HEX line).
    TtmrfRaw(RawFrame),
    /// TT-Multi-RF MAVLink ADSB_VEHICLE / COLLISION.
    TtmrfMavlink(MavlinkMessage),
    /// TT-Multi-RF GDL90.
    TtmrfGdl90(Gdl90Message),
    /// TT-Multi-RF ASTERIX CAT021 / CAT023 record.
    TtmrfAsterix(AsterixMessage),
}

impl PortMessage {
    /// The borrowed, serialisable form (the JSON of `vigil replay --emit decoded`).
    pub fn as_message(&self) -> Message<'_> {
        match self {
            PortMessage::Bahrs(m) => Message::Bahrs(m),
            PortMessage::Watson(m) => Message::Watson(m),
            PortMessage::Vn200(m) => Message::Vn200(m),
            PortMessage::TtmrfText(m) => Message::Ttmrf(TtmrfMessage::Text(m)),
            PortMessage::TtmrfRaw(m) => Message::TtmrfRaw(m),
            PortMessage::TtmrfMavlink(m) => Message::Ttmrf(TtmrfMessage::Mavlink(m)),
            PortMessage::TtmrfGdl90(m) => Message::Ttmrf(TtmrfMessage::Gdl90(m)),
            PortMessage::TtmrfAsterix(m) => Message::Ttmrf(TtmrfMessage::Asterix(m)),
        }
    }
}

impl From<MixedMessage> for PortMessage {
    fn from(m: MixedMessage) -> Self {
        match m {
            MixedMessage::Text(t) => PortMessage::TtmrfText(t),
            MixedMessage::Raw(f) => PortMessage::TtmrfRaw(f),
        }
    }
}

/// A decoded message of any device, borrowed (its serde form is the decoded replay's JSON).
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

/// One message out of a [`PortDecoder`], with its place in the port's stream.
#[derive(Debug, Clone, PartialEq)]
pub struct PortFrame {
    /// Offset of its first byte in the port's received stream (bytes fed since the start).
    pub offset: u64,
    /// Its wire length, bytes: what the decoder consumed from its first byte to its end (at
    /// least 1), so `offset + wire_len` is the stream offset just past its last byte.
    pub wire_len: u64,
    /// The message.
    pub message: PortMessage,
}

/// The decode loop of one codec: each message with its offset and wire length (the decoder's
/// consumed count past its start).
fn run<D: DeviceDecoder, E>(
    codec: &mut Codec<D>,
    buf: &mut BytesMut,
    eof: bool,
    wrap: impl Fn(D::Message) -> PortMessage,
    f: &mut impl FnMut(PortFrame) -> Result<(), E>,
) -> Result<(), E> {
    loop {
        let next = if eof {
            codec.decode_eof(buf)
        } else {
            codec.decode(buf)
        };
        // `Codec` never returns an error.
        let Ok(Some(l)) = next else { return Ok(()) };
        let end = codec.0.stats().bytes_consumed;
        f(PortFrame {
            offset: l.offset,
            wire_len: end.saturating_sub(l.offset).max(1),
            message: wrap(l.message),
        })?;
    }
}

#[cfg(test)]
#[path = "protocol_tests.rs"]
mod tests;
