//! `vigil replay`: feed a recording's raw chunks through the drivers' decoders and write every
//! decoded message as one JSON line: `device`, `index` (0-based order of decoded messages of that
//! device), `offset` (the stream offset of its first byte, `Located::offset`), `t_host_ns` (host
//! receive time of the chunk holding that byte) and `message` (the driver's message as serde
//! writes it).
//!
//! `index` equals the truth file's `index` as long as no message of that device was lost or
//! damaged; `offset` equals the truth's `rx_offset` for every intact message, always.
//!
//! The decoder of a channel is chosen by its `protocol` metadata (`bahrs-2.0`, `watson-ahrs-e304`),
//! or by the device name when the channel has none.
//!
//! Output is a deterministic function of the file: replaying twice gives identical bytes. Devices
//! without a decoder here (VN-200, TT-Multi-RF until their drivers land) are counted in the summary
//! on stderr, with each decoder's counters and any damage found in the file.

use std::collections::{BTreeMap, VecDeque};
use std::io::{self, BufWriter, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result, anyhow};
use bytes::BytesMut;
use clap::Args;
use serde::Serialize;
use serde_json::json;
use tokio_util::codec::Decoder as _;
use vigil_drivers::{Codec, DecodeStats, DeviceDecoder, bahrs, watson};
use vigil_sim::record::{Recorded, read_recording};

/// Arguments of `vigil replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The MCAP recording.
    pub input: PathBuf,
    /// Pace the replay at this multiple of real time (default: as fast as possible).
    #[arg(long)]
    pub speed: Option<f64>,
}

#[derive(Serialize)]
struct Line<'a, M: Serialize> {
    device: &'a str,
    index: u64,
    offset: u64,
    t_host_ns: u64,
    message: &'a M,
}

/// One port's decoder with the map from stream offsets to chunk receive times.
struct Port<D: DeviceDecoder> {
    codec: Codec<D>,
    buf: BytesMut,
    chunks: VecDeque<(u64, u64)>,
    fed: u64,
    index: u64,
}

impl<D: DeviceDecoder> Port<D>
where
    D::Message: Serialize,
{
    fn new(decoder: D) -> Self {
        Self {
            codec: Codec(decoder),
            buf: BytesMut::with_capacity(1 << 12),
            chunks: VecDeque::new(),
            fed: 0,
            index: 0,
        }
    }

    fn t_host_of(&mut self, offset: u64) -> u64 {
        while self.chunks.len() > 1 && self.chunks[1].0 <= offset {
            self.chunks.pop_front();
        }
        self.chunks.front().map_or(0, |c| c.1)
    }

    fn emit<W: Write>(
        &mut self,
        device: &str,
        offset: u64,
        m: &D::Message,
        out: &mut W,
    ) -> Result<()> {
        let t_host_ns = self.t_host_of(offset);
        serde_json::to_writer(
            &mut *out,
            &Line {
                device,
                index: self.index,
                offset,
                t_host_ns,
                message: m,
            },
        )?;
        out.write_all(b"\n")?;
        self.index += 1;
        Ok(())
    }

    fn feed<W: Write>(
        &mut self,
        device: &str,
        t_host_ns: u64,
        bytes: &[u8],
        out: &mut W,
    ) -> Result<()> {
        self.chunks.push_back((self.fed, t_host_ns));
        self.fed += bytes.len() as u64;
        self.buf.extend_from_slice(bytes);
        while let Some(l) = self.codec.decode(&mut self.buf)? {
            self.emit(device, l.offset, &l.message, out)?;
        }
        Ok(())
    }

    fn finish<W: Write>(&mut self, device: &str, out: &mut W) -> Result<DecodeStats> {
        while let Some(l) = self.codec.decode_eof(&mut self.buf)? {
            self.emit(device, l.offset, &l.message, out)?;
        }
        Ok(*self.codec.0.stats())
    }
}

enum AnyPort {
    Bahrs(Port<bahrs::Decoder>),
    Watson(Port<watson::Decoder>),
    NoDecoder { chunks: u64, bytes: u64 },
}

/// Summary of a replay (written to stderr as JSON).
#[derive(Debug, Serialize, Default)]
pub struct ReplaySummary {
    /// Always "summary".
    pub kind: &'static str,
    /// MCAP messages read.
    pub mcap_messages: u64,
    /// Where reading stopped early (truncated or damaged file).
    pub damage: Option<String>,
    /// Per device: decoder counters, or chunks/bytes for devices without a decoder.
    pub devices: BTreeMap<String, serde_json::Value>,
}

/// Replays `mcap` into `out`. `speed`: pace at this multiple of real time.
pub fn replay<W: Write>(mcap: &[u8], out: &mut W, speed: Option<f64>) -> Result<ReplaySummary> {
    let mut ports: BTreeMap<String, AnyPort> = BTreeMap::new();
    let mut pace: Option<(u64, Instant)> = None;
    let outcome = read_recording(mcap, |m| -> Result<()> {
        let Recorded::Raw {
            device,
            protocol,
            t_host_ns,
            bytes,
        } = m
        else {
            return Ok(());
        };
        if let Some(x) = speed {
            let (t0, wall0) = *pace.get_or_insert((t_host_ns, Instant::now()));
            let due = Duration::from_secs_f64(t_host_ns.saturating_sub(t0) as f64 / 1e9 / x);
            if let Some(wait) = due.checked_sub(wall0.elapsed()) {
                std::thread::sleep(wait);
            }
        }
        let port = ports
            .entry(device.to_string())
            .or_insert_with(|| match (protocol, device) {
                ("bahrs-2.0", _) | ("", "bahrs") => {
                    AnyPort::Bahrs(Port::new(bahrs::Decoder::new()))
                }
                ("watson-ahrs-e304", _) | ("", "watson") => {
                    AnyPort::Watson(Port::new(watson::Decoder::new()))
                }
                _ => AnyPort::NoDecoder {
                    chunks: 0,
                    bytes: 0,
                },
            });
        match port {
            AnyPort::Bahrs(p) => p.feed(device, t_host_ns, bytes, out),
            AnyPort::Watson(p) => p.feed(device, t_host_ns, bytes, out),
            AnyPort::NoDecoder { chunks, bytes: n } => {
                *chunks += 1;
                *n += bytes.len() as u64;
                Ok(())
            }
        }
    })?;
    let mut summary = ReplaySummary {
        kind: "summary",
        mcap_messages: outcome.messages,
        damage: outcome.damage,
        ..Default::default()
    };
    for (device, port) in &mut ports {
        let v = match port {
            AnyPort::Bahrs(p) => serde_json::to_value(p.finish(device, out)?)?,
            AnyPort::Watson(p) => serde_json::to_value(p.finish(device, out)?)?,
            AnyPort::NoDecoder { chunks, bytes } => {
                json!({ "no_decoder": true, "chunks": chunks, "bytes": bytes })
            }
        };
        summary.devices.insert(device.clone(), v);
    }
    Ok(summary)
}

/// Runs `vigil replay`.
pub fn run(args: &ReplayArgs) -> Result<()> {
    if args.speed.is_some_and(|x| !(x.is_finite() && x > 0.0)) {
        return Err(anyhow!("--speed must be a positive number"));
    }
    let data = std::fs::read(&args.input)
        .with_context(|| format!("cannot read {}", args.input.display()))?;
    let stdout = io::stdout();
    let mut out = BufWriter::with_capacity(1 << 16, stdout.lock());
    let summary = match replay(&data, &mut out, args.speed) {
        Ok(s) => s,
        Err(e)
            if e.downcast_ref::<io::Error>()
                .is_some_and(|e| e.kind() == io::ErrorKind::BrokenPipe) =>
        {
            return Ok(());
        }
        Err(e) => return Err(e),
    };
    match out.flush() {
        Err(e) if e.kind() != io::ErrorKind::BrokenPipe => {
            return Err(e).context("writing standard output");
        }
        _ => {}
    }
    eprintln!("{}", serde_json::to_string(&summary)?);
    Ok(())
}
