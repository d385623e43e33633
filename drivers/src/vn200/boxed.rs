//! [`BoxedDecoder`]: the VN-200 decoder as the ingest stage uses it (issue 21). Each message is
//! decoded in place ([`Vn200Decoder::decode_into`]) into a box from a small pool of spare boxes
//! that the consumer hands back ([`BoxedDecoder::stock`]), so the 928-byte message is written
//! once, where the consumer keeps it, and the steady stream allocates nothing.

use bytes::BytesMut;

use super::binary::BinaryOutput;
use super::decoder::{Vn200Decoder, Vn200Message};
use crate::{DecodeStats, DeviceDecoder};

/// Spare boxes a [`BoxedDecoder`] keeps at most (a read chunk usually completes one message).
pub const SPARE_BOXES: usize = 4;

/// Boxes of messages, spare or handed back. Boxed on purpose: each box leaves the pool as a
/// message and comes back later; a `Vec<Vn200Message>` would copy the message out.
pub type SpareBoxes = Vec<Box<Vn200Message>>;

/// A [`Vn200Decoder`] yielding boxed messages, each decoded straight into a recycled box.
#[derive(Debug, Default)]
pub struct BoxedDecoder {
    inner: Vn200Decoder,
    spare: SpareBoxes,
}

impl BoxedDecoder {
    /// A decoder at the start of a stream, with no spare box yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Spare boxes held now.
    pub fn spare_len(&self) -> usize {
        self.spare.len()
    }

    /// Takes boxes of messages the consumer is done with from `spare` until this decoder holds
    /// [`SPARE_BOXES`]; the rest stay in `spare`.
    pub fn stock(&mut self, spare: &mut SpareBoxes) {
        while self.spare.len() < SPARE_BOXES {
            match spare.pop() {
                Some(b) => self.spare.push(b),
                None => break,
            }
        }
    }

    /// A spare box, or a new one (binary, so that the usual message needs no switch).
    fn take_box(&mut self) -> Box<Vn200Message> {
        self.spare
            .pop()
            .unwrap_or_else(|| Box::new(Vn200Message::Binary(BinaryOutput::default())))
    }

    /// One decode step into a spare box: the box when a message was written, else it goes
    /// back to the pool.
    fn step(&mut self, buf: &mut BytesMut, eof: bool) -> Option<Box<Vn200Message>> {
        let mut b = self.take_box();
        let got = if eof {
            self.inner.decode_eof_into(buf, &mut b)
        } else {
            self.inner.decode_into(buf, &mut b)
        };
        if got {
            Some(b)
        } else {
            self.spare.push(b);
            None
        }
    }
}

impl DeviceDecoder for BoxedDecoder {
    type Message = Box<Vn200Message>;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<Box<Vn200Message>> {
        self.step(buf, false)
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<Box<Vn200Message>> {
        self.step(buf, true)
    }

    fn stats(&self) -> &DecodeStats {
        self.inner.stats()
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        self.inner.stats_mut()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testkit::{assert_split_invariant, assert_survives_random};
    use crate::vn200::binary::{CommonGroup, Ypr};

    fn message(i: u16) -> BinaryOutput {
        BinaryOutput {
            common: Some(CommonGroup {
                time_startup_ns: Some(u64::from(i) * 2_500_000),
                ypr: Some(Ypr {
                    yaw_deg: f32::from(i),
                    pitch_deg: 1.0,
                    roll_deg: -1.0,
                }),
                ..Default::default()
            }),
            ..Default::default()
        }
    }

    #[test]
    fn recycled_boxes_carry_each_message_and_the_pool_stays_bounded() {
        let sent: Vec<BinaryOutput> = (0..20).map(message).collect();
        let mut bytes = Vec::new();
        for m in &sent {
            m.encode_into(&mut bytes);
        }
        let mut d = BoxedDecoder::new();
        let mut handed_back = Vec::new();
        let mut buf = BytesMut::new();
        let mut got = Vec::new();
        let mut boxes = std::collections::BTreeSet::new();
        for piece in bytes.chunks(50) {
            d.stock(&mut handed_back);
            buf.extend_from_slice(piece);
            while let Some(b) = d.decode(&mut buf) {
                let Vn200Message::Binary(m) = &*b else {
                    panic!("only binary messages were sent")
                };
                got.push(m.clone());
                boxes.insert(&*b as *const Vn200Message as usize);
                handed_back.push(b);
            }
            assert!(d.spare_len() <= SPARE_BOXES);
        }
        assert_eq!(got, sent);
        assert_eq!(d.stats().frames_decoded, 20);
        // Every box is handed back before the next chunk and none is dropped (so no address is
        // reused by the allocator): a 50-byte chunk completes at most two 26-byte messages, so
        // a few boxes carry all 20 messages.
        assert!(boxes.len() <= 3, "{} boxes for 20 messages", boxes.len());
    }

    #[test]
    fn contract_holds() {
        let mut bytes = Vec::new();
        for i in 0..5 {
            message(i).encode_into(&mut bytes);
        }
        bytes.extend_from_slice(b"$VNYPR,+010.071,+000.278,-002.026*60\r\n");
        assert_split_invariant(BoxedDecoder::new, &bytes);
        assert_survives_random(BoxedDecoder::new, 3, 50, 2000);
    }
}
