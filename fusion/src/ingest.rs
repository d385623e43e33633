//! The ingest stage, shared by the live service and every replay: a port's read chunks (device,
//! wire protocol, host receive time, bytes) through the drivers' [`PortDecoder`] (chosen once per
//! port from the protocol table) to typed [`Sample`]s, each with the receive time of its own last
//! byte ([`ChunkClock`]), and through the [`Aligner`] onto GPS time. The pipeline takes the
//! aligned samples from here.
//!
//! Sans-IO: chunks and their times are passed in; every aligned sample is handed to the caller's
//! closure, whose error (of any type) stops the feed and is passed back.

use std::collections::BTreeMap;

use bytes::BytesMut;
use vigil_drivers::DecodeStats;
use vigil_drivers::protocol::{PortDecoder, PortFrame, PortMessage, Protocol};
use vigil_drivers::replay::PortSummary;

use crate::time::aligner::{AlignedSample, Aligner, AlignerConfig, Device, Sample};
use crate::time::host_timed::ChunkClock;

/// Decoded samples of one port: (sample, start offset, wire length).
type Samples = Vec<(Sample, u64, usize)>;

/// How a port is read.
enum Decoding {
    /// A protocol of the table: its decoder and the received bytes it has not consumed yet.
    Decoded(Box<PortDecoder>, BytesMut),
    /// Not a protocol vigil decodes: counted, not decoded.
    NoDecoder { chunks: u64, bytes: u64 },
}

/// One recorded port: its name, its receive clock and its decoder.
struct DevicePort {
    name: String,
    clock: ChunkClock,
    decoding: Decoding,
    cadence: Cadence,
}

/// Frames in a row of one length, nothing skipped between them, before
/// [`Ingest::bytes_until_whole_message`] predicts the next frame.
const STEADY_FRAMES: u32 = 8;

/// Whether a port's stream is a steady run of frames of one length (issue 21), judged from its
/// decoder's counters after each read, whatever the read boundaries: a reader woken late takes a
/// frame and the start of the next, or two frames, in one read, and the run goes on.
#[derive(Debug, Default, Clone, Copy)]
struct Cadence {
    /// Counters after the previous read: bytes consumed, bytes skipped, frames decoded.
    at: (u64, u64, u64),
    /// Length of every frame of the run, bytes.
    len: Option<u64>,
    /// Frames in a row of length `len`.
    run: u32,
}

impl Cadence {
    fn update(&mut self, stats: DecodeStats) {
        let now = (
            stats.bytes_consumed,
            stats.bytes_skipped,
            stats.frames_decoded,
        );
        let (consumed, skipped, frames) = (now.0 - self.at.0, now.1 - self.at.1, now.2 - self.at.2);
        self.at = now;
        if skipped > 0 {
            (self.len, self.run) = (None, 0);
        } else if frames == 1 {
            if self.len == Some(consumed) {
                self.run = self.run.saturating_add(1);
            } else {
                (self.len, self.run) = (Some(consumed), 1);
            }
        } else if frames > 1 {
            // Several frames in one read: their lengths are not told apart, only their sum.
            // Decision: a sum of exactly `frames` run lengths continues the run (a mix of other
            // lengths with that sum is possible but harmless: a wrong prediction costs at most
            // the reader's bounded wait, once); any other sum ends it.
            if self.len.is_some_and(|l| consumed == l * frames) {
                self.run = self
                    .run
                    .saturating_add(u32::try_from(frames).unwrap_or(u32::MAX));
            } else {
                (self.len, self.run) = (None, 0);
            }
        }
    }
}

impl DevicePort {
    /// Decodes what `bytes` completes (`eof`: and what is left at the end of the stream).
    fn samples(&mut self, bytes: &[u8], eof: bool, out: &mut Samples, spare: &mut SpareVn200) {
        match &mut self.decoding {
            Decoding::Decoded(d, buf) => {
                buf.extend_from_slice(bytes);
                d.stock_vn200(spare);
                let _ = d.decode(buf, eof, &mut |m| -> Result<(), ()> {
                    out.push(sample(m));
                    Ok(())
                });
            }
            Decoding::NoDecoder { chunks, bytes: n } => {
                if !eof {
                    *chunks += 1;
                    *n += bytes.len() as u64;
                }
            }
        }
    }

    /// The port's decoder counters, `None` without a decoder.
    fn stats(&self) -> Option<DecodeStats> {
        match &self.decoding {
            Decoding::Decoded(d, _) => Some(d.stats()),
            Decoding::NoDecoder { .. } => None,
        }
    }

    /// The port's line in the replay summary.
    fn summary(&self) -> PortSummary {
        match &self.decoding {
            Decoding::Decoded(d, _) => PortSummary::Decoded(d.stats()),
            Decoding::NoDecoder { chunks, bytes } => PortSummary::NoDecoder {
                no_decoder: true,
                chunks: *chunks,
                bytes: *bytes,
            },
        }
    }

    /// Whether the port's stream is finished in the first group at the end (see
    /// [`Ingest::finish`]): BAHRS, Watson and undecoded ports.
    fn finishes_first(&self) -> bool {
        match &self.decoding {
            Decoding::Decoded(d, _) => {
                matches!(d.protocol().device(), Device::Bahrs | Device::Watson)
            }
            Decoding::NoDecoder { .. } => true,
        }
    }
}

/// Boxes of VN-200 messages whose samples were handed out, handed back to the VN-200 port's
/// decoder, which decodes the next messages straight into them: the VN-200 stream (400 Hz) then
/// allocates nothing and copies no message per message (issue 21).
type SpareVn200 = vigil_drivers::vn200::boxed::SpareBoxes;

/// Spare VN-200 boxes kept at most: as many as the decoder takes (a chunk holds one message in
/// the steady state).
const SPARE_VN200: usize = vigil_drivers::vn200::boxed::SPARE_BOXES;

/// A decoded message as a [`Sample`] with its start offset and wire length.
///
/// Decision: the BAHRS and Watson lengths are their messages re-encoded, as when these two went
/// through the simulator's `Replayer` (which reported start offsets only); kept so every aligned
/// time stays as it was. The others use the decoder's consumed count.
fn sample(m: PortFrame) -> (Sample, u64, usize) {
    let wire = usize::try_from(m.wire_len).unwrap_or(usize::MAX);
    let (s, len) = match m.message {
        PortMessage::Bahrs(b) => (Sample::Bahrs(b), b.to_frame().len()),
        PortMessage::Watson(l) => (Sample::Watson(l), l.to_bytes().len()),
        PortMessage::Vn200(b) => (Sample::Vn200(b), wire),
        PortMessage::TtmrfText(t) => (Sample::TtText(Box::new(t)), wire),
        PortMessage::TtmrfRaw(r) => (Sample::TtRaw(Box::new(r)), wire),
        PortMessage::TtmrfMavlink(x) => (Sample::TtMavlink(Box::new(x)), wire),
        PortMessage::TtmrfGdl90(x) => (Sample::TtGdl90(Box::new(x)), wire),
        PortMessage::TtmrfAsterix(x) => (Sample::TtAsterix(Box::new(x)), wire),
    };
    (s, m.offset, len)
}

/// The ingest stage: one [`PortDecoder`] per port, one [`Aligner`].
pub struct Ingest {
    aligner: Aligner,
    /// Every port seen, in order of first appearance. A recording has a handful, so one linear
    /// scan per chunk finds it (it replaced five map lookups by name per chunk, about 4 % of a
    /// fused replay's instructions).
    ports: Vec<DevicePort>,
    /// Reused buffers (issue 21: no allocation per chunk once grown): a chunk's decoded
    /// messages, and the samples one message made final.
    samples: Samples,
    aligned: Vec<AlignedSample>,
    spare_vn200: SpareVn200,
}

impl Default for Ingest {
    fn default() -> Self {
        Self::new()
    }
}

impl Ingest {
    /// An ingest stage with default aligner parameters and no port yet (ports are added as their
    /// first chunk arrives).
    pub fn new() -> Self {
        Self {
            aligner: Aligner::new(AlignerConfig::default()),
            ports: Vec::new(),
            samples: Samples::new(),
            aligned: Vec::new(),
            spare_vn200: Vec::with_capacity(SPARE_VN200),
        }
    }

    /// Feeds one read chunk; hands every finalised sample to `f`.
    pub fn feed<E>(
        &mut self,
        device: &str,
        protocol: &str,
        t_host_ns: u64,
        bytes: &[u8],
        f: &mut impl FnMut(&AlignedSample) -> Result<(), E>,
    ) -> Result<(), E> {
        let i = self.port_index(device, protocol);
        let port = &mut self.ports[i];
        port.clock.push(t_host_ns as i64, bytes.len());
        let mut samples = std::mem::take(&mut self.samples);
        port.samples(bytes, false, &mut samples, &mut self.spare_vn200);
        if let Decoding::Decoded(d, _) = &port.decoding {
            port.cadence.update(d.stats());
        }
        let r = self.align(i, &mut samples, f);
        self.samples = samples;
        r
    }

    /// The index of port `device` in `ports`, added (with its decoder, chosen once from its wire
    /// `protocol`) when first seen.
    fn port_index(&mut self, device: &str, protocol: &str) -> usize {
        if let Some(i) = self.ports.iter().position(|p| p.name == device) {
            return i;
        }
        let decoding = match Protocol::resolve(protocol, device) {
            Some(p) => Decoding::Decoded(
                Box::new(PortDecoder::new(p)),
                BytesMut::with_capacity(1 << 12),
            ),
            None => Decoding::NoDecoder {
                chunks: 0,
                bytes: 0,
            },
        };
        self.ports.push(DevicePort {
            name: device.to_string(),
            clock: ChunkClock::default(),
            decoding,
            cadence: Cadence::default(),
        });
        self.ports.len() - 1
    }

    /// The aligner's device kind of port `device` with wire `protocol` (the family of its
    /// protocol in the drivers' table), if it is one vigil decodes.
    fn device_kind(device: &str, protocol: &str) -> Option<Device> {
        Protocol::resolve(protocol, device).map(Protocol::device)
    }

    /// Port `device` (wire `protocol`) is read every `interval_ns` (0: as its bytes arrive): the
    /// aligner adds the wait to its host-timed samples ([`Aligner::set_read_interval`]). The
    /// VN-200's is not modelled (`vigil run` reads it on arrival). Returns the device kind the
    /// interval was applied to, if any.
    pub fn set_read_interval(
        &mut self,
        device: &str,
        protocol: &str,
        interval_ns: u64,
    ) -> Option<Device> {
        let kind = Self::device_kind(device, protocol).filter(|k| *k != Device::Vn200)?;
        self.aligner.set_read_interval(kind, interval_ns);
        Some(kind)
    }

    /// Port `device` (wire `protocol`) is behind a USB adapter whose latency timer is
    /// `timer_ns` (0: none): the aligner widens its host-timed samples' sigma by the adapter's
    /// hold ([`Aligner::set_latency_timer`]). Returns the device kind it was applied to, if any.
    pub fn set_latency_timer(
        &mut self,
        device: &str,
        protocol: &str,
        timer_ns: u64,
    ) -> Option<Device> {
        let kind = Self::device_kind(device, protocol)?;
        self.aligner.set_latency_timer(kind, timer_ns);
        Some(kind)
    }

    /// Port `device` (wire `protocol`), when a TT-Multi-RF, has a transmit buffer of `bytes`
    /// (`None`: not stated): the aligner bounds its full line's wait by the buffer's line time
    /// ([`Aligner::set_ttmrf_output_buffer`]). Returns the device kind it was applied to: only
    /// a TT-Multi-RF's line is watched, so other ports give `None`.
    pub fn set_output_buffer(
        &mut self,
        device: &str,
        protocol: &str,
        bytes: Option<u32>,
    ) -> Option<Device> {
        let kind = Self::device_kind(device, protocol).filter(|k| *k == Device::Ttmrf)?;
        self.aligner.set_ttmrf_output_buffer(bytes);
        Some(kind)
    }

    /// Port `device` (wire `protocol`) runs at `baud` bit/s, as configured or recorded (issue 18
    /// point 2): the aligner computes that port's transmission times with it. 0 keeps the
    /// built-in rate. Returns the device kind it was applied to, if any.
    pub fn set_baud(&mut self, device: &str, protocol: &str, baud: u32) -> Option<Device> {
        let kind = Self::device_kind(device, protocol)?;
        self.aligner.set_baud(kind, baud);
        Some(kind)
    }

    /// The aligner (its clock models, for the live service's integrity report).
    pub fn aligner(&self) -> &Aligner {
        &self.aligner
    }

    /// How many more bytes complete port `device`'s next frame, when its stream is a steady run
    /// of frames of one length (issue 21): the frame length less the bytes of it already
    /// received. The live reader then waits for that many bytes before it wakes (`VMIN`).
    /// `None` after skipped bytes or a frame of another length, before [`STEADY_FRAMES`] frames
    /// in a row, or when the bytes waiting are not the start of such a frame (as many as a
    /// frame, still undecoded).
    pub fn bytes_until_whole_message(&self, device: &str) -> Option<usize> {
        let port = self.ports.iter().find(|p| p.name == device)?;
        let Decoding::Decoded(_, buf) = &port.decoding else {
            return None;
        };
        let c = port.cadence;
        let len = c.len.filter(|_| c.run >= STEADY_FRAMES)?;
        let missing = len.checked_sub(buf.len() as u64).filter(|m| *m > 0)?;
        usize::try_from(missing).ok()
    }

    /// The decoder counters of `device` so far (as [`Ingest::finish`] reports them), or
    /// `None` for a port without a decoder or not seen yet.
    pub fn port_stats(&self, device: &str) -> Option<DecodeStats> {
        self.ports.iter().find(|p| p.name == device)?.stats()
    }

    /// Ends every stream, releases what the aligner holds, and returns every port's counters.
    ///
    /// The ports' remaining messages are aligned in this order (the order of the time when BAHRS
    /// and Watson went through the simulator's `Replayer`, kept so the outputs stay identical):
    /// first the BAHRS and Watson ports by name, then the others by name.
    pub fn finish<E>(
        &mut self,
        f: &mut impl FnMut(&AlignedSample) -> Result<(), E>,
    ) -> Result<BTreeMap<String, PortSummary>, E> {
        let mut order: Vec<usize> = (0..self.ports.len()).collect();
        order.sort_by(|&a, &b| {
            let (a, b) = (&self.ports[a], &self.ports[b]);
            (!a.finishes_first(), &a.name).cmp(&(!b.finishes_first(), &b.name))
        });
        let mut summary = BTreeMap::new();
        for i in order {
            let mut rest = Samples::new();
            self.ports[i].samples(&[], true, &mut rest, &mut self.spare_vn200);
            summary.insert(self.ports[i].name.clone(), self.ports[i].summary());
            self.align(i, &mut rest, f)?;
        }
        for s in self.aligner.flush() {
            f(&s)?;
        }
        Ok(summary)
    }

    /// Aligns `samples` of port `ports[i]` (taking them all: the buffer is left empty for
    /// reuse, even when `f` fails).
    fn align<E>(
        &mut self,
        i: usize,
        samples: &mut Samples,
        f: &mut impl FnMut(&AlignedSample) -> Result<(), E>,
    ) -> Result<(), E> {
        let clock = &mut self.ports[i].clock;
        let mut aligned = std::mem::take(&mut self.aligned);
        let mut r = Ok(());
        for (sample, offset, len) in samples.drain(..) {
            let Some(rx) = clock.rx(offset, len) else {
                continue;
            };
            self.aligner.handle_into(sample, rx, &mut aligned);
            r = aligned.iter().try_for_each(&mut *f);
            for s in aligned.drain(..) {
                if let Sample::Vn200(b) = s.aligned.message
                    && self.spare_vn200.len() < SPARE_VN200
                {
                    self.spare_vn200.push(b);
                }
            }
            if r.is_err() {
                // As before the buffers: the chunk's other messages are dropped with the error.
                break;
            }
        }
        self.aligned = aligned;
        r
    }
}

#[cfg(test)]
#[path = "ingest_tests.rs"]
mod tests;
