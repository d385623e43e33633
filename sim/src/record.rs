//! MCAP recordings: one channel per device port carrying the raw read chunks (log time = host
//! monotonic receive time, ns), a `/truth` channel carrying the truth records as JSON, and a
//! `vigil.sim` metadata record with the run parameters.
//!
//! - Topics: `/<device>/raw` (message encoding `application/octet-stream`, channel metadata
//!   `device`, `protocol`, `baud`) and `/truth` (encoding `json`). No schemas.
//! - Chunks of at most 64 KiB, uncompressed: a writer that dies loses at most its open chunk, and a
//!   truncated file is read message by message up to the damage ([`read_recording`] stops there
//!   and says so).
//! - The writer's library string is fixed ("vigil"), so the same run gives the same bytes.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use mcap::records::{MessageHeader, Metadata};
use mcap::{WriteOptions, Writer};

use crate::engine::{RunInfo, Sink, SinkError};
use crate::link::Chunk;
use crate::truth::TruthRecord;

/// Topic of the truth channel.
pub const TRUTH_TOPIC: &str = "/truth";
/// Name of the metadata record with the run parameters.
pub const METADATA_NAME: &str = "vigil.sim";
/// Largest uncompressed chunk, bytes.
pub const CHUNK_BYTES: u64 = 64 * 1024;

/// Topic of a device port's raw channel.
pub fn raw_topic(device: &str) -> String {
    format!("/{device}/raw")
}

/// An MCAP writer with one raw channel per device port (used by the simulator's [`McapSink`] and
/// by live recording).
pub struct RawRecorder<W: Write + Seek> {
    writer: Writer<W>,
    port_channels: Vec<u16>,
    sequences: BTreeMap<u16, u32>,
}

impl<W: Write + Seek> RawRecorder<W> {
    /// A recorder writing to `w` with a `/<device>/raw` channel per port, given as
    /// (device, protocol, baud) in port-index order.
    pub fn new(w: W, ports: &[(&str, &str, u32)]) -> Result<Self, mcap::McapError> {
        Self::with_read_intervals(w, ports, &[])
    }

    /// As [`RawRecorder::new`], with each port's read interval, ns (0 or absent: read as the
    /// bytes arrive), kept as channel metadata `read_interval_ns` when not 0 so that a replay
    /// models the wait as the live service did ([`Recorded::Raw::read_interval_ns`]).
    pub fn with_read_intervals(
        w: W,
        ports: &[(&str, &str, u32)],
        read_intervals_ns: &[u64],
    ) -> Result<Self, mcap::McapError> {
        let mut writer = WriteOptions::new()
            .compression(None)
            .chunk_size(Some(CHUNK_BYTES))
            .profile("vigil")
            .library("vigil")
            .create(w)?;
        let mut port_channels = Vec::with_capacity(ports.len());
        for (i, (device, protocol, baud)) in ports.iter().enumerate() {
            let mut meta = BTreeMap::from([
                ("device".to_string(), device.to_string()),
                ("protocol".to_string(), protocol.to_string()),
                ("baud".to_string(), baud.to_string()),
            ]);
            if let Some(&ns) = read_intervals_ns.get(i).filter(|&&ns| ns > 0) {
                meta.insert("read_interval_ns".to_string(), ns.to_string());
            }
            port_channels.push(writer.add_channel(
                0,
                &raw_topic(device),
                "application/octet-stream",
                &meta,
            )?);
        }
        Ok(Self {
            writer,
            port_channels,
            sequences: BTreeMap::new(),
        })
    }

    /// Adds a JSON channel and returns its id.
    pub fn add_json_channel(&mut self, topic: &str) -> Result<u16, mcap::McapError> {
        self.writer.add_channel(0, topic, "json", &BTreeMap::new())
    }

    /// Writes a metadata record.
    pub fn write_metadata(
        &mut self,
        name: &str,
        metadata: BTreeMap<String, String>,
    ) -> Result<(), mcap::McapError> {
        self.writer.write_metadata(&Metadata {
            name: name.to_string(),
            metadata,
        })
    }

    /// Writes one message on a channel.
    pub fn write(
        &mut self,
        channel_id: u16,
        t_host_ns: u64,
        data: &[u8],
    ) -> Result<(), mcap::McapError> {
        let seq = self.sequences.entry(channel_id).or_insert(0);
        *seq = seq.wrapping_add(1);
        let header = MessageHeader {
            channel_id,
            sequence: *seq,
            log_time: t_host_ns,
            publish_time: t_host_ns,
        };
        self.writer.write_to_known_channel(&header, data)
    }

    /// Writes one raw chunk of port `port` (index in the order given to [`RawRecorder::new`]).
    pub fn write_raw(
        &mut self,
        port: u16,
        t_host_ns: u64,
        bytes: &[u8],
    ) -> Result<(), mcap::McapError> {
        let id = *self
            .port_channels
            .get(usize::from(port))
            .ok_or(mcap::McapError::UnknownChannel(0, port))?;
        self.write(id, t_host_ns, bytes)
    }

    /// Ends the open chunk and flushes it to the output, so a recorder killed later loses nothing
    /// written so far.
    pub fn flush(&mut self) -> Result<(), mcap::McapError> {
        self.writer.flush()
    }

    /// Writes the summary and returns the inner writer.
    pub fn finish(mut self) -> Result<W, mcap::McapError> {
        self.writer.finish()?;
        Ok(self.writer.into_inner())
    }
}

/// A [`Sink`] writing an MCAP file, and optionally the truth as JSON Lines.
pub struct McapSink<W: Write + Seek> {
    output: Option<W>,
    recorder: Option<RawRecorder<W>>,
    /// The `/truth` channel, `None` when truth stays out of the recording.
    truth_channel: Option<u16>,
    truth_in_mcap: bool,
    truth_lines: Option<Box<dyn Write>>,
    line: Vec<u8>,
}

impl<W: Write + Seek> McapSink<W> {
    /// A sink writing to `w`; `truth_lines` also receives one JSON line per truth record.
    pub fn new(w: W, truth_lines: Option<Box<dyn Write>>) -> Result<Self, mcap::McapError> {
        Ok(Self {
            output: Some(w),
            recorder: None,
            truth_channel: None,
            truth_in_mcap: true,
            truth_lines,
            line: Vec::with_capacity(512),
        })
    }

    /// Leaves the `/truth` channel out of the recording (it is about 85 % of a recording's size;
    /// the truth JSON Lines file still gets every record).
    pub fn without_truth_channel(mut self) -> Self {
        self.truth_in_mcap = false;
        self
    }

    fn recorder(&mut self) -> Result<&mut RawRecorder<W>, SinkError> {
        self.recorder
            .as_mut()
            .ok_or_else(|| "mcap sink used before start".into())
    }

    /// Writes the summary and returns the inner writer.
    pub fn finish(mut self) -> Result<W, SinkError> {
        if let Some(t) = self.truth_lines.as_mut() {
            t.flush()?;
        }
        match (self.recorder.take(), self.output.take()) {
            (Some(r), _) => Ok(r.finish()?),
            (None, Some(w)) => Ok(w),
            (None, None) => Err("mcap sink has no output".into()),
        }
    }
}

impl<W: Write + Seek> Sink for McapSink<W> {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        let w = self.output.take().ok_or("mcap sink started twice")?;
        let ports: Vec<(&str, &str, u32)> = info
            .ports
            .iter()
            .map(|p| (p.device, p.protocol, p.baud))
            .collect();
        let mut rec = RawRecorder::new(w, &ports)?;
        if self.truth_in_mcap {
            self.truth_channel = Some(rec.add_json_channel(TRUTH_TOPIC)?);
        }
        let names: Vec<&str> = info.ports.iter().map(|p| p.device).collect();
        let metadata = BTreeMap::from([
            ("scenario".to_string(), info.scenario.clone()),
            ("seed".to_string(), info.seed.to_string()),
            ("start_gps_ns".to_string(), info.start_gps_ns.to_string()),
            ("duration_ns".to_string(), info.duration_ns.to_string()),
            (
                "host_clock_offset_ns".to_string(),
                info.host_clock.offset_ns.to_string(),
            ),
            (
                "host_clock_drift".to_string(),
                format!("{:e}", info.host_clock.drift),
            ),
            ("ports".to_string(), names.join(",")),
            (
                "devices_without_model".to_string(),
                info.devices_without_model.join(","),
            ),
        ]);
        rec.write_metadata(METADATA_NAME, metadata)?;
        self.recorder = Some(rec);
        Ok(())
    }

    fn chunk(&mut self, chunk: &Chunk) -> Result<(), SinkError> {
        self.recorder()?
            .write_raw(chunk.port, chunk.t_host_ns, &chunk.bytes)?;
        Ok(())
    }

    fn truth(&mut self, record: &TruthRecord, t_host_ns: u64) -> Result<(), SinkError> {
        self.line.clear();
        serde_json::to_writer(&mut self.line, record)?;
        let line = std::mem::take(&mut self.line);
        let r = match self.truth_channel {
            Some(channel) => self
                .recorder()
                .and_then(|rec| Ok(rec.write(channel, t_host_ns, &line)?)),
            None => Ok(()),
        };
        if let Some(t) = self.truth_lines.as_mut() {
            t.write_all(&line)?;
            t.write_all(b"\n")?;
        }
        self.line = line;
        r
    }
}

/// One message read back from a recording.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Recorded<'a> {
    /// A raw read chunk of a device port.
    Raw {
        /// Device name (channel metadata `device`, else the topic).
        device: &'a str,
        /// Wire protocol (channel metadata `protocol`; empty when absent).
        protocol: &'a str,
        /// Host receive time, ns.
        t_host_ns: u64,
        /// The bytes.
        bytes: &'a [u8],
        /// How often the port was read, ns (channel metadata `read_interval_ns`); 0: as its
        /// bytes arrived (also when absent, and when unreadable).
        read_interval_ns: u64,
        /// Baud rate of the port (channel metadata `baud`); 0 when absent or unreadable.
        baud: u32,
    },
    /// A truth record (JSON).
    Truth {
        /// Log time, ns.
        t_host_ns: u64,
        /// The JSON text.
        json: &'a [u8],
    },
    /// A message on any other channel.
    Other {
        /// Its topic.
        topic: &'a str,
    },
}

/// How reading a recording ended.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ReadOutcome {
    /// Messages read.
    pub messages: u64,
    /// Where reading stopped early and why (a truncated or damaged file), if it did.
    pub damage: Option<String>,
}

/// First and last log time of a recording's messages, ns, from its MCAP statistics record (for
/// progress reports); `None` when the file has no readable summary (a truncated recording) or no
/// messages.
pub fn recorded_span(mcap: &[u8]) -> Option<(u64, u64)> {
    let stats = mcap::Summary::read(mcap).ok()??.stats?;
    (stats.message_count > 0).then_some((stats.message_start_time, stats.message_end_time))
}

/// Reads every message of an MCAP file in file order and hands it to `f`. A damaged or truncated
/// file is read up to the damage; the outcome says where it stopped. `f` may stop the reading by
/// returning an error, which is passed back.
pub fn read_recording<E>(
    buf: &[u8],
    mut f: impl FnMut(Recorded<'_>) -> Result<(), E>,
) -> Result<ReadOutcome, E> {
    let mut outcome = ReadOutcome::default();
    let stream = match mcap::MessageStream::new_with_options(
        buf,
        mcap::read::Options::IgnoreEndMagic.into(),
    ) {
        Ok(s) => s,
        Err(e) => {
            outcome.damage = Some(format!("not an mcap file: {e}"));
            return Ok(outcome);
        }
    };
    for m in stream {
        let m = match m {
            Ok(m) => m,
            Err(e) => {
                outcome.damage = Some(format!("stopped after {} messages: {e}", outcome.messages));
                break;
            }
        };
        outcome.messages += 1;
        let topic = m.channel.topic.as_str();
        let rec = if topic == TRUTH_TOPIC {
            Recorded::Truth {
                t_host_ns: m.log_time,
                json: &m.data,
            }
        } else if let Some(stripped) = topic.strip_suffix("/raw") {
            let device = m
                .channel
                .metadata
                .get("device")
                .map_or(stripped.trim_start_matches('/'), |d| d.as_str());
            Recorded::Raw {
                device,
                protocol: m
                    .channel
                    .metadata
                    .get("protocol")
                    .map_or("", |p| p.as_str()),
                t_host_ns: m.log_time,
                bytes: &m.data,
                read_interval_ns: m
                    .channel
                    .metadata
                    .get("read_interval_ns")
                    .and_then(|v| v.parse().ok())
                    .unwrap_or(0),

                baud: m
                    .channel
                    .metadata
                    .get("baud")
                    .and_then(|v| v.parse().ok())
                    .unwrap_or(0),
            }
        } else {
            Recorded::Other { topic }
        };
        f(rec)?;
    }
    Ok(outcome)
}

/// The `vigil.sim` metadata of a recording, if present and readable.
pub fn read_metadata(buf: &[u8]) -> Option<BTreeMap<String, String>> {
    let reader =
        mcap::read::LinearReader::new_with_options(buf, mcap::read::Options::IgnoreEndMagic.into())
            .ok()?;
    for rec in reader {
        match rec {
            Ok(mcap::records::Record::Metadata(m)) if m.name == METADATA_NAME => {
                return Some(m.metadata);
            }
            Ok(_) => {}
            Err(_) => return None,
        }
    }
    None
}
