//! `vigil replay FILE.mcap --emit aligned`: every decoded message on GPS time (issue 7, "Output").
//!
//! One JSON line per input message, in the order the aligner finalises them (BAHRS pairing and the
//! host-clock wait reorder them; `index` joins them back): `device`, `index` (0-based per device,
//! the truth file's `index` while nothing of the device was lost), `t_gps_ns`, `sigma_ns`,
//! `time_source`, `status` (unlocked / locking / locked / coasting) for aligned samples, or
//! `not_aligned` (the reason) with the three time fields null. Every message comes out once.
//!
//! Every port is decoded by the drivers' [`PortDecoder`], chosen once per port by the protocol
//! table ([`Protocol::resolve`] of the channel's `protocol` metadata, else of the device name;
//! exact names, see `vigil_drivers::protocol`). Each message's receive time is that of the read
//! holding its last byte ([`ChunkClock`]); its wire length comes from re-encoding it (BAHRS,
//! Watson) or from the decoder's consumed count (VN-200, TT-Multi-RF; see [`PortFrame`]).

use std::collections::BTreeMap;
use std::io::Write;

use anyhow::Result;
use bytes::BytesMut;
use serde::Serialize;
use vigil_drivers::DecodeStats;
use vigil_drivers::protocol::{PortDecoder, PortFrame, PortMessage, Protocol};
use vigil_drivers::replay::PortSummary;
use vigil_fusion::time::aligner::{AlignedSample, Aligner, AlignerConfig, Device, Sample};
use vigil_fusion::time::host_timed::ChunkClock;
use vigil_fusion::time::{ClockStatus, NotAligned, TimeSource};
use vigil_record::{Recorded, read_recording_from};

use crate::replay::ReplaySummary;

/// One output line.
#[derive(Debug, Serialize)]
pub struct AlignedLine {
    /// Device name.
    pub device: &'static str,
    /// 0-based per-device input index.
    pub index: u64,
    /// GPS time, ns since 1980-01-06, or null.
    pub t_gps_ns: Option<i64>,
    /// 1-sigma, ns, or null.
    pub sigma_ns: Option<f64>,
    /// Where the time came from, or null.
    pub time_source: Option<TimeSource>,
    /// Clock model state, or null.
    pub status: Option<ClockStatus>,
    /// Why there is no time, or null.
    pub not_aligned: Option<NotAligned>,
}

impl AlignedLine {
    /// The line of one aligned sample.
    pub fn of(s: &AlignedSample) -> Self {
        let (t, why) = match s.aligned.time {
            Ok(a) => (Some(a), None),
            Err(e) => (None, Some(e)),
        };
        Self {
            device: s.device.name(),
            index: s.index,
            t_gps_ns: t.map(|a| a.t_gps_ns),
            sigma_ns: t.map(|a| a.sigma_ns),
            time_source: t.map(|a| a.source),
            status: t.map(|a| a.status),
            not_aligned: why,
        }
    }
}

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
}

impl DevicePort {
    /// Decodes what `bytes` completes (`eof`: and what is left at the end of the stream).
    fn samples(&mut self, bytes: &[u8], eof: bool) -> Samples {
        let mut out = Samples::new();
        match &mut self.decoding {
            Decoding::Decoded(d, buf) => {
                buf.extend_from_slice(bytes);
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
        out
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
    /// [`AlignedReplay::finish`]): BAHRS, Watson and undecoded ports.
    fn finishes_first(&self) -> bool {
        match &self.decoding {
            Decoding::Decoded(d, _) => {
                matches!(d.protocol().device(), Device::Bahrs | Device::Watson)
            }
            Decoding::NoDecoder { .. } => true,
        }
    }
}

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
        PortMessage::Vn200(v) => (Sample::Vn200(Box::new(v)), wire),
        PortMessage::TtmrfText(t) => (Sample::TtText(Box::new(t)), wire),
        PortMessage::TtmrfRaw(r) => (Sample::TtRaw(Box::new(r)), wire),
        PortMessage::TtmrfMavlink(x) => (Sample::TtMavlink(Box::new(x)), wire),
        PortMessage::TtmrfGdl90(x) => (Sample::TtGdl90(Box::new(x)), wire),
        PortMessage::TtmrfAsterix(x) => (Sample::TtAsterix(Box::new(x)), wire),
    };
    (s, m.offset, len)
}

/// The aligned replay: one [`PortDecoder`] per port, one [`Aligner`].
pub struct AlignedReplay {
    aligner: Aligner,
    /// Every port seen, in order of first appearance. A recording has a handful, so one linear
    /// scan per chunk finds it (it replaced five map lookups by name per chunk, about 4 % of a
    /// fused replay's instructions).
    ports: Vec<DevicePort>,
}

impl Default for AlignedReplay {
    fn default() -> Self {
        Self::new()
    }
}

impl AlignedReplay {
    /// A replay with default aligner parameters.
    pub fn new() -> Self {
        Self {
            aligner: Aligner::new(AlignerConfig::default()),
            ports: Vec::new(),
        }
    }

    /// Feeds one read chunk; hands every finalised sample to `f`.
    pub fn feed(
        &mut self,
        device: &str,
        protocol: &str,
        t_host_ns: u64,
        bytes: &[u8],
        f: &mut impl FnMut(&AlignedSample) -> Result<()>,
    ) -> Result<()> {
        let i = self.port_index(device, protocol);
        let port = &mut self.ports[i];
        port.clock.push(t_host_ns as i64, bytes.len());
        let samples = port.samples(bytes, false);
        self.align(i, samples, f)
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

    /// The decoder counters of `device` so far (as [`AlignedReplay::finish`] reports them), or
    /// `None` for a port without a decoder or not seen yet.
    pub fn port_stats(&self, device: &str) -> Option<DecodeStats> {
        self.ports.iter().find(|p| p.name == device)?.stats()
    }

    /// Ends every stream, releases what the aligner holds, and returns every port's counters.
    ///
    /// The ports' remaining messages are aligned in this order (the order of the time when BAHRS
    /// and Watson went through the simulator's `Replayer`, kept so the outputs stay identical):
    /// first the BAHRS and Watson ports by name, then the others by name.
    pub fn finish(
        &mut self,
        f: &mut impl FnMut(&AlignedSample) -> Result<()>,
    ) -> Result<BTreeMap<String, PortSummary>> {
        let mut order: Vec<usize> = (0..self.ports.len()).collect();
        order.sort_by(|&a, &b| {
            let (a, b) = (&self.ports[a], &self.ports[b]);
            (!a.finishes_first(), &a.name).cmp(&(!b.finishes_first(), &b.name))
        });
        let mut summary = BTreeMap::new();
        for i in order {
            let rest = self.ports[i].samples(&[], true);
            summary.insert(self.ports[i].name.clone(), self.ports[i].summary());
            self.align(i, rest, f)?;
        }
        for s in self.aligner.flush() {
            f(&s)?;
        }
        Ok(summary)
    }

    /// Aligns `samples` of port `ports[i]`.
    fn align(
        &mut self,
        i: usize,
        samples: Samples,
        f: &mut impl FnMut(&AlignedSample) -> Result<()>,
    ) -> Result<()> {
        let clock = &mut self.ports[i].clock;
        for (sample, offset, len) in samples {
            let Some(rx) = clock.rx(offset, len) else {
                continue;
            };
            for s in self.aligner.handle(sample, rx) {
                f(&s)?;
            }
        }
        Ok(())
    }
}

/// Replays `mcap` through decoding and alignment, handing every aligned sample to `f` in the
/// order the aligner finalises them (also the front half of `vigil replay --emit fused`).
pub fn replay_aligned_with(
    mcap: impl std::io::Read,
    mut f: impl FnMut(&AlignedSample) -> Result<()>,
) -> Result<ReplaySummary> {
    let mut r = AlignedReplay::new();
    let mut seen: Vec<String> = Vec::new();
    let outcome = read_recording_from(mcap, |m| -> Result<()> {
        let Recorded::Raw {
            device,
            protocol,
            t_host_ns,
            bytes,
            read_interval_ns,
            baud,
            latency_timer_ns,
        } = m
        else {
            return Ok(());
        };
        // The live service's pacing, as it modelled it, and the port's recorded baud and
        // adapter timer (a channel's metadata: set once).
        if !seen.iter().any(|d| d == device) {
            seen.push(device.to_string());
            let _ = r.set_read_interval(device, protocol, read_interval_ns);
            let _ = r.set_baud(device, protocol, baud);
            let _ = r.set_latency_timer(device, protocol, latency_timer_ns);
        }
        r.feed(device, protocol, t_host_ns, bytes, &mut f)
    })?;
    let devices = r.finish(&mut f)?;
    Ok(ReplaySummary {
        kind: "summary",
        mcap_messages: outcome.messages,
        damage: outcome.damage,
        devices,
    })
}

/// Replays `mcap` into `out` as aligned JSON lines.
pub fn replay_aligned<W: Write>(mcap: impl std::io::Read, out: &mut W) -> Result<ReplaySummary> {
    replay_aligned_with(mcap, |s| {
        let v = crate::json_names::named_value(&AlignedLine::of(s))?;
        serde_json::to_writer(&mut *out, &v)?;
        out.write_all(b"\n")?;
        Ok(())
    })
}

#[cfg(test)]
#[path = "aligned_tests.rs"]
mod tests;
