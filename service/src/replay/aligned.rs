//! `vigil replay FILE.mcap --emit aligned`: every decoded message on GPS time (issue 7, "Output").
//!
//! One JSON line per input message, in the order the aligner finalises them (BAHRS pairing and the
//! host-clock wait reorder them; `index` joins them back): `device`, `index` (0-based per device,
//! the truth file's `index` while nothing of the device was lost), `t_gps_ns`, `sigma_ns`,
//! `time_source`, `status` (unlocked / locking / locked / coasting) for aligned samples, or
//! `not_aligned` (the reason) with the three time fields null. Every message comes out once.
//!
//! BAHRS and Watson are decoded by `vigil_sim::replay::Replayer`; the VN-200 (binary and ASCII)
//! and TT-Multi-RF ports are decoded here, where each message's wire length is known (channel
//! protocol `vn200*`, `ttmrf-hex*`, `ttmrf-mavlink`, `ttmrf-gdl90`, `ttmrf-asterix`, other
//! `ttmrf*`: the text port with interleaved HEX lines, `ttmrf::mixed`; else the device name
//! `vn200` / `ttmrf`). Each message's receive time is that of the read holding its last byte
//! ([`ChunkClock`]); its wire length comes from re-encoding it (BAHRS, Watson) or from the decoder's
//! offsets (the start of the next message bounds it; see `Port`).

use std::collections::BTreeMap;
use std::io::Write;

use anyhow::Result;
use bytes::BytesMut;
use serde::Serialize;
use tokio_util::codec::Decoder as _;
use vigil_drivers::ttmrf::asterix::AsterixDecoder;
use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, TrafficAltitude};
use vigil_drivers::ttmrf::mavlink::MavlinkDecoder;
use vigil_drivers::ttmrf::mixed::{MixedDecoder, MixedMessage};
use vigil_drivers::ttmrf::raw::hex::HexDecoder;
use vigil_drivers::vn200::Vn200Decoder;
use vigil_drivers::{Codec, DecodeStats, DeviceDecoder};
use vigil_fusion::time::aligner::{AlignedSample, Aligner, AlignerConfig, Device, Sample};
use vigil_fusion::time::host_timed::ChunkClock;
use vigil_fusion::time::{ClockStatus, NotAligned, TimeSource};
use vigil_record::Recorded;
use vigil_record::read_recording_from;
use vigil_sim::replay::{Decoded, Message, PortSummary, Replayer};

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

/// A port decoded here: its decoder and buffer.
struct Port<D: DeviceDecoder> {
    codec: Codec<D>,
    buf: BytesMut,
}

impl<D: DeviceDecoder> Port<D> {
    fn new(d: D) -> Self {
        Self {
            codec: Codec(d),
            buf: BytesMut::with_capacity(1 << 12),
        }
    }

    /// Decodes what `bytes` completes; returns (start offset, wire length, message) of every
    /// message, as soon as the decoder has it. Its wire length is what the decoder consumed from
    /// the message's start (its end is the decoder's consumed count), so its receive time is
    /// that of its own last byte. (An earlier version held each message back until the next
    /// one's start bounded its length: one message period of latency on every VN-200 and
    /// TT-Multi-RF message, 2.5 ms at 400 Hz.)
    fn feed(&mut self, bytes: &[u8], eof: bool) -> Vec<(u64, usize, D::Message)> {
        self.buf.extend_from_slice(bytes);
        let mut out = Vec::new();
        loop {
            let next = if eof {
                self.codec.decode_eof(&mut self.buf)
            } else {
                self.codec.decode(&mut self.buf)
            };
            let Ok(Some(l)) = next else { break };
            let end = self.codec.0.stats().bytes_consumed;
            let len = end.saturating_sub(l.offset).max(1);
            out.push((
                l.offset,
                usize::try_from(len).unwrap_or(usize::MAX),
                l.message,
            ));
        }
        out
    }
}

enum OwnPort {
    Vn200(Box<Port<Vn200Decoder>>),
    /// The TT-Multi-RF text port, with raw HEX lines interleaved when raw output is on (manual:
    /// both go out on the same UART).
    TtMixed(Box<Port<MixedDecoder>>),
    TtHex(Port<HexDecoder>),
    TtMavlink(Box<Port<MavlinkDecoder>>),
    TtGdl90(Box<Port<Gdl90Decoder>>),
    TtAsterix(Box<Port<AsterixDecoder>>),
}

/// One recorded port: its name, its receive clock and, for VN-200 / TT-Multi-RF, its decoder.
struct DevicePort {
    name: String,
    clock: ChunkClock,
    /// `None`: decoded by the Replayer (BAHRS, Watson).
    own: Option<OwnPort>,
}

/// The aligned replay: the Replayer for BAHRS / Watson, own ports for VN-200 / TT-Multi-RF, one
/// [`Aligner`].
pub struct AlignedReplay {
    aligner: Aligner,
    replayer: Replayer,
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
            replayer: Replayer::new(),
            ports: Vec::new(),
        }
    }

    fn own_port(protocol: &str, device: &str) -> Option<OwnPort> {
        Some(match protocol {
            p if p.starts_with("vn200") || (p.is_empty() && device == "vn200") => {
                OwnPort::Vn200(Box::new(Port::new(Vn200Decoder::new())))
            }
            p if p.starts_with("ttmrf-hex") => OwnPort::TtHex(Port::new(HexDecoder::new())),
            "ttmrf-mavlink" => OwnPort::TtMavlink(Box::new(Port::new(MavlinkDecoder::new()))),
            // Barometric priority (the GDL90 definition; the simulator's setting).
            "ttmrf-gdl90" => OwnPort::TtGdl90(Box::new(Port::new(Gdl90Decoder::new(
                TrafficAltitude::Pressure,
            )))),
            "ttmrf-asterix" => OwnPort::TtAsterix(Box::new(Port::new(AsterixDecoder::default()))),
            p if p.starts_with("ttmrf") || (p.is_empty() && device == "ttmrf") => {
                OwnPort::TtMixed(Box::new(Port::new(MixedDecoder::new())))
            }
            _ => return None,
        })
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
        let mut samples: Samples = Vec::new();
        if let Some(p) = &mut port.own {
            samples = own_samples(p, bytes, false);
        } else {
            let mut collect = |d: Decoded<'_>| -> Result<()> {
                samples.extend(replayer_sample(&d));
                Ok(())
            };
            self.replayer
                .feed(device, protocol, t_host_ns, bytes, &mut collect)?;
        }
        self.align(i, samples, f)
    }

    /// The index of port `device` in `ports`, added (with its decoder, chosen once from its wire
    /// `protocol`) when first seen.
    fn port_index(&mut self, device: &str, protocol: &str) -> usize {
        if let Some(i) = self.ports.iter().position(|p| p.name == device) {
            return i;
        }
        self.ports.push(DevicePort {
            name: device.to_string(),
            clock: ChunkClock::default(),
            own: Self::own_port(protocol, device),
        });
        self.ports.len() - 1
    }

    /// The aligner's device kind of port `device` with wire `protocol` (the protocol's prefix,
    /// or, without a protocol, the device name), if it is one of the four.
    fn device_kind(device: &str, protocol: &str) -> Option<Device> {
        let named =
            |kind: &str| protocol.starts_with(kind) || (protocol.is_empty() && device == kind);
        ["bahrs", "watson", "vn200", "ttmrf"]
            .into_iter()
            .zip([Device::Bahrs, Device::Watson, Device::Vn200, Device::Ttmrf])
            .find(|(k, _)| named(k))
            .map(|(_, d)| d)
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
        match self.ports.iter().find(|p| p.name == device) {
            Some(DevicePort { own: Some(p), .. }) => Some(p.stats()),
            _ => self.replayer.stats(device),
        }
    }

    /// Ends every stream, releases what the aligner holds, and returns the Replayer's counters
    /// (ports decoded here are listed with their decoder counters).
    pub fn finish(
        &mut self,
        f: &mut impl FnMut(&AlignedSample) -> Result<()>,
    ) -> Result<BTreeMap<String, PortSummary>> {
        let mut rest: Vec<(String, Samples)> = Vec::new();
        let mut collect = |d: Decoded<'_>| -> Result<()> {
            rest.push((
                d.device.to_string(),
                replayer_sample(&d).into_iter().collect(),
            ));
            Ok(())
        };
        let mut summary = self.replayer.finish(&mut collect)?;
        // Own ports in name order, as the map they were once kept in gave them.
        let mut own: Vec<&mut DevicePort> =
            self.ports.iter_mut().filter(|p| p.own.is_some()).collect();
        own.sort_by(|a, b| a.name.cmp(&b.name));
        for port in own {
            let Some(p) = &mut port.own else { continue };
            rest.push((port.name.clone(), own_samples(p, &[], true)));
            summary.insert(port.name.clone(), PortSummary::Decoded(p.stats()));
        }
        for (device, samples) in rest {
            if let Some(i) = self.ports.iter().position(|p| p.name == device) {
                self.align(i, samples, f)?;
            }
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

/// A Replayer message as a [`Sample`] with its start offset and wire length (re-encoded).
///
/// VN-200 and TT-Multi-RF ports never reach the Replayer here: they are decoded by this module's
/// own ports ([`AlignedReplay::own_port`]), which know each message's wire length (the Replayer
/// reports only start offsets, and the receive time is that of the message's last byte).
fn replayer_sample(d: &Decoded<'_>) -> Option<(Sample, u64, usize)> {
    match d.message {
        Message::Bahrs(m) => Some((Sample::Bahrs(*m), d.offset, m.to_frame().len())),
        Message::Watson(l) => Some((Sample::Watson(*l), d.offset, l.to_bytes().len())),
        Message::Vn200(_) | Message::Ttmrf(_) | Message::TtmrfRaw(_) => None,
    }
}

fn own_samples(p: &mut OwnPort, bytes: &[u8], eof: bool) -> Vec<(Sample, u64, usize)> {
    fn map<D: DeviceDecoder>(
        p: &mut Port<D>,
        bytes: &[u8],
        eof: bool,
        f: impl Fn(D::Message) -> Sample,
    ) -> Samples {
        p.feed(bytes, eof)
            .into_iter()
            .map(|(o, n, m)| (f(m), o, n))
            .collect()
    }
    match p {
        OwnPort::Vn200(p) => map(p, bytes, eof, |m| Sample::Vn200(Box::new(m))),
        OwnPort::TtMixed(p) => map(p, bytes, eof, |m| match m {
            MixedMessage::Text(t) => Sample::TtText(Box::new(t)),
            MixedMessage::Raw(r) => Sample::TtRaw(Box::new(r)),
        }),
        OwnPort::TtHex(p) => map(p, bytes, eof, |m| Sample::TtRaw(Box::new(m))),
        OwnPort::TtMavlink(p) => map(p, bytes, eof, |m| Sample::TtMavlink(Box::new(m))),
        OwnPort::TtGdl90(p) => map(p, bytes, eof, |m| Sample::TtGdl90(Box::new(m))),
        OwnPort::TtAsterix(p) => map(p, bytes, eof, |m| Sample::TtAsterix(Box::new(m))),
    }
}

impl OwnPort {
    /// The port's decoder counters.
    fn stats(&self) -> DecodeStats {
        match self {
            OwnPort::Vn200(p) => *p.codec.0.stats(),
            OwnPort::TtMixed(p) => *p.codec.0.stats(),
            OwnPort::TtHex(p) => *p.codec.0.stats(),
            OwnPort::TtMavlink(p) => *p.codec.0.stats(),
            OwnPort::TtGdl90(p) => *p.codec.0.stats(),
            OwnPort::TtAsterix(p) => *p.codec.0.stats(),
        }
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
