//! The BAHRS stream decoder and the host-side encoder.

use bytes::{BufMut, BytesMut};

use super::frame::{
    CRC_LEN, HEADER_LEN, MARKER_1, MARKER_2, OLDER_VERSIONS, PROTOCOL_VERSION, crc32_mpeg2, layout,
};
use super::messages::{Message, PayloadError};
use crate::{DecodeStats, DeviceDecoder};

/// Why a candidate frame was rejected. The decoder counts every rejection in [`DecodeStats`] and
/// keeps the latest one (with its stream offset) for logs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum Error {
    /// The CRC of a protocol 2.0 frame did not verify.
    #[error(
        "bahrs: crc mismatch in type {msg_type:#04x} frame at byte {offset}: received {received:#010x}, computed {computed:#010x}"
    )]
    Checksum {
        /// Stream offset of the frame's first byte.
        offset: u64,
        /// Message type byte.
        msg_type: u8,
        /// CRC in the frame.
        received: u32,
        /// CRC computed over the frame.
        computed: u32,
    },
    /// A protocol 2.0 header with a type that has no documented layout (e.g. a debug message).
    #[error("bahrs: unknown message type {msg_type:#04x} at byte {offset}, resynchronising")]
    UnknownType {
        /// Stream offset of the frame's first byte.
        offset: u64,
        /// Message type byte.
        msg_type: u8,
    },
    /// A header of an older protocol version (0x0001 or 0x0002). Other version values are not
    /// taken for headers at all (they are far more likely data that happens to contain "NE").
    #[error(
        "bahrs: unsupported protocol version {version:#06x} at byte {offset} (vigil reads 0x0003)"
    )]
    UnsupportedVersion {
        /// Stream offset of the frame's first byte.
        offset: u64,
        /// Version field as received.
        version: u16,
    },
    /// A frame whose CRC verified but whose content is out of range.
    #[error("bahrs: malformed type {msg_type:#04x} frame at byte {offset}: nvm page {page} > 249")]
    Malformed {
        /// Stream offset of the frame's first byte.
        offset: u64,
        /// Message type byte.
        msg_type: u8,
        /// The out-of-range page number.
        page: u8,
    },
}

/// Sans-IO decoder of a BAHRS byte stream (protocol 2.0).
///
/// It aligns on the 'N''E' marker, derives the frame length from the type, verifies the CRC and
/// decodes the payload. On a CRC failure it drops one byte and rescans, so a false marker inside a
/// payload cannot hide the next real frame. Types without a documented length (the undocumented
/// debug messages) are skipped the same way: the scan moves on to the next marker whose frame checks
/// out. It never waits for more than [`super::frame::MAX_FRAME_LEN`] bytes.
#[derive(Debug, Default, Clone)]
pub struct Decoder {
    stats: DecodeStats,
    last_error: Option<Error>,
}

impl Decoder {
    /// A decoder at the start of a stream.
    pub fn new() -> Self {
        Self::default()
    }

    /// The counters.
    pub fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    /// The most recent rejection, if any.
    pub fn last_error(&self) -> Option<&Error> {
        self.last_error.as_ref()
    }

    /// Takes the most recent rejection, leaving none.
    pub fn take_last_error(&mut self) -> Option<Error> {
        self.last_error.take()
    }
}

impl DeviceDecoder for Decoder {
    type Message = Message;

    #[inline]
    fn decode(&mut self, buf: &mut BytesMut) -> Option<Message> {
        loop {
            // Align on the first marker byte.
            if buf.first() != Some(&MARKER_1) {
                match memchr::memchr(MARKER_1, buf) {
                    Some(p) => self.stats.skip(buf, p),
                    None => {
                        let n = buf.len();
                        self.stats.skip(buf, n);
                        return None;
                    }
                }
            }
            if buf.len() >= 2 && buf[1] != MARKER_2 {
                self.stats.skip(buf, 1);
                continue;
            }
            if buf.len() < HEADER_LEN {
                return None;
            }
            let offset = self.stats.bytes_consumed;
            let version = u16::from_le_bytes([buf[2], buf[3]]);
            let msg_type = buf[4];
            let older = OLDER_VERSIONS.contains(&version);
            if version != PROTOCOL_VERSION && !older {
                // Not a header we know: treat the 'N' as data rather than wait for a frame length
                // that would mean nothing in an unknown version.
                self.stats.skip(buf, 1);
                continue;
            }
            let Some(layout) = layout(msg_type) else {
                if version == PROTOCOL_VERSION {
                    self.stats.unknown_types += 1;
                    self.last_error = Some(Error::UnknownType { offset, msg_type });
                } else {
                    self.unsupported(offset, version);
                }
                self.stats.skip(buf, 1);
                continue;
            };
            let len = layout.frame_len();
            if buf.len() < len {
                return None;
            }
            let body = &buf[..len - CRC_LEN];
            let computed = crc32_mpeg2(body);
            let received =
                u32::from_le_bytes([buf[len - 4], buf[len - 3], buf[len - 2], buf[len - 1]]);
            if computed != received {
                if version == PROTOCOL_VERSION {
                    self.stats.checksum_failures += 1;
                    self.last_error = Some(Error::Checksum {
                        offset,
                        msg_type,
                        received,
                        computed,
                    });
                } else {
                    self.unsupported(offset, version);
                }
                self.stats.skip(buf, 1);
                continue;
            }
            if older {
                // A complete frame of an older version that checks out under the 2.0 layout: its
                // fields may mean something else, so it is counted and dropped, not decoded.
                self.unsupported(offset, version);
                self.stats.skip(buf, len);
                continue;
            }
            let payload = &buf[HEADER_LEN..HEADER_LEN + layout.payload_len];
            match Message::decode_payload(msg_type, payload) {
                Some(Ok(message)) => {
                    self.stats.take_frame(buf, len);
                    return Some(message);
                }
                Some(Err(PayloadError::PageOutOfRange(page))) => {
                    self.stats.malformed += 1;
                    self.last_error = Some(Error::Malformed {
                        offset,
                        msg_type,
                        page,
                    });
                    self.stats.skip(buf, len);
                }
                // Unreachable: the layout exists and the payload has its length. Skip rather than
                // trust that.
                None => self.stats.skip(buf, 1),
            }
        }
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

impl Decoder {
    fn unsupported(&mut self, offset: u64, version: u16) {
        self.stats.unsupported_version += 1;
        self.last_error = Some(Error::UnsupportedVersion { offset, version });
    }
}

/// Encoder of BAHRS frames for `tokio_util::codec::FramedWrite` (service requests the host sends,
/// and any message for the simulator).
#[derive(Debug, Default, Clone, Copy)]
pub struct Encoder;

impl tokio_util::codec::Encoder<Message> for Encoder {
    type Error = std::io::Error;

    fn encode(&mut self, item: Message, dst: &mut BytesMut) -> Result<(), Self::Error> {
        dst.put_slice(&item.to_frame());
        Ok(())
    }
}
