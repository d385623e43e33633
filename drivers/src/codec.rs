//! The decoder trait shared by all devices and its adapter to `tokio_util::codec`.

use bytes::BytesMut;

use crate::DecodeStats;

/// A sans-IO decoder of one device's byte stream.
///
/// Contract (tested for every device with [`crate::testkit`]):
/// - `decode` removes bytes from the front of `buf` and returns the next message, or `None` when
///   the buffer holds no complete message yet (the unconsumed tail is kept for the next call);
/// - it never fails and never panics: corrupt input is skipped and counted in [`DecodeStats`];
/// - it is resynchronising: after any garbage, the next valid frame is found;
/// - feeding the same bytes in any split gives the same messages;
/// - it keeps the buffer bounded: a device whose frames have a maximum length never waits for
///   more than that many bytes before skipping.
pub trait DeviceDecoder {
    /// The typed message this decoder yields.
    type Message;

    /// Decodes the next message from the front of `buf`, or returns `None` if more bytes are needed.
    fn decode(&mut self, buf: &mut BytesMut) -> Option<Self::Message>;

    /// Decodes what is left at the end of a stream, when no more bytes will come.
    ///
    /// The default treats a candidate frame that still waits for bytes as truncated: it drops that
    /// candidate's first byte (counted as skipped) and rescans, so a complete frame hiding behind a
    /// false or truncated header is still found; at the end every remaining byte is counted.
    /// Line-oriented decoders may override it (e.g. to accept a last line without terminator).
    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<Self::Message> {
        loop {
            if let Some(m) = self.decode(buf) {
                return Some(m);
            }
            if buf.is_empty() {
                return None;
            }
            self.stats_mut().skip(buf, 1);
        }
    }

    /// The decoder's counters.
    fn stats(&self) -> &DecodeStats;

    /// Mutable access to the counters (for the default `decode_eof`).
    fn stats_mut(&mut self) -> &mut DecodeStats;
}

/// A decoded message with the stream offset of its first byte.
///
/// The transport keeps a map from stream offsets to host receive times of the chunks it fed in;
/// the offset of a message's first byte gives the receive time of that byte.
#[derive(Debug, Clone, PartialEq)]
pub struct Located<M> {
    /// Offset of the message's first byte in the stream, counted from the first byte fed in.
    pub offset: u64,
    /// The message.
    pub message: M,
}

/// Adapter from a [`DeviceDecoder`] to [`tokio_util::codec::Decoder`], for `FramedRead` over a
/// serial port or a file. It never returns `Err` (which would end a `FramedRead`).
#[derive(Debug, Default, Clone)]
pub struct Codec<D>(pub D);

impl<D: DeviceDecoder> tokio_util::codec::Decoder for Codec<D> {
    type Item = Located<D::Message>;
    type Error = std::io::Error;

    fn decode(&mut self, src: &mut BytesMut) -> Result<Option<Self::Item>, Self::Error> {
        Ok(self.0.decode(src).map(|message| Located {
            offset: self.0.stats().last_frame_start,
            message,
        }))
    }

    fn decode_eof(&mut self, src: &mut BytesMut) -> Result<Option<Self::Item>, Self::Error> {
        Ok(self.0.decode_eof(src).map(|message| Located {
            offset: self.0.stats().last_frame_start,
            message,
        }))
    }
}

/// Decodes a complete byte slice (treated as the whole stream, end included) without tokio.
pub fn decode_slice<D: DeviceDecoder>(decoder: &mut D, bytes: &[u8]) -> Vec<D::Message> {
    let mut buf = BytesMut::from(bytes);
    let mut out = Vec::new();
    while let Some(m) = decoder.decode(&mut buf) {
        out.push(m);
    }
    while let Some(m) = decoder.decode_eof(&mut buf) {
        out.push(m);
    }
    out
}
