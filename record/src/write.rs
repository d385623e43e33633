//! Writing MCAP recordings: one channel per device port carrying the raw read chunks (log time = host
//! monotonic receive time, ns), a `/truth` channel carrying the truth records as JSON, and a
//! `vigil.sim` metadata record with the run parameters.
//!
//! - Topics: `/<device>/raw` (message encoding `application/octet-stream`, channel metadata
//!   `device`, `protocol` and the port's link, [`crate::PortLink`]; schema
//!   `vigil.raw.<protocol>` with the empty schema encoding: the bytes are the device's own wire
//!   format, the device document is their schema) and
//!   `/truth` (encoding `json`). [`RawRecorder::add_schema_channel`] adds JSON channels with a
//!   JSON Schema (`vigil run`'s decoded and fused channels, issue 20).
//! - Chunks of at most [`CHUNK_BYTES`] uncompressed, zstd-compressed (issue 20; single-threaded,
//!   so the same input gives the same bytes): a writer that dies loses at most its open chunk
//!   (live recorders flush it every second), and a damaged chunk costs only its own messages
//!   ([`crate::read`] skips it and says so).
//! - The writer's library string is fixed ("vigil"), so the same run gives the same bytes.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use mcap::records::{MessageHeader, Metadata};
use mcap::{WriteOptions, Writer};

use crate::PortLink;

/// Topic of the truth channel.
pub const TRUTH_TOPIC: &str = "/truth";
/// Name of the metadata record with the run parameters.
pub const METADATA_NAME: &str = "vigil.sim";
/// Largest uncompressed chunk, bytes. Live recorders also close the chunk at every flush (at most
/// 1 s), which bounds what a kill loses; this bounds what one damaged chunk costs and the
/// reader's memory (issue 20: 256 KiB compresses to within a few per cent of 1 MiB chunks).
pub const CHUNK_BYTES: u64 = 256 * 1024;

/// Whether chunks are compressed (zstd) by default.
pub const COMPRESS_BY_DEFAULT: bool = true;

/// Prefix of a raw channel's schema name (then the wire protocol, else the device name).
pub const RAW_SCHEMA_PREFIX: &str = "vigil.raw.";

/// The writer options of every vigil recording: chunked, zstd when `compress` (one thread, the
/// default level), fixed library string.
pub fn write_options(compress: bool) -> WriteOptions {
    WriteOptions::new()
        .compression(compress.then_some(mcap::Compression::Zstd))
        .compression_threads(0)
        .chunk_size(Some(CHUNK_BYTES))
        .profile("vigil")
        .library("vigil")
}

/// Topic of a device port's raw channel.
pub fn raw_topic(device: &str) -> String {
    format!("/{device}/raw")
}

/// An MCAP writer with one raw channel per device port (used by the simulator's `McapSink`, by
/// `vigil record` and by `vigil run`'s recording).
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
    /// models the wait as the live service did (`PortLink::read_interval_ns`).
    pub fn with_read_intervals(
        w: W,
        ports: &[(&str, &str, u32)],
        read_intervals_ns: &[u64],
    ) -> Result<Self, mcap::McapError> {
        let writer = write_options(COMPRESS_BY_DEFAULT).create(w)?;
        let mut rec = Self {
            writer,
            port_channels: Vec::with_capacity(ports.len()),
            sequences: BTreeMap::new(),
        };
        for (i, (device, protocol, baud)) in ports.iter().enumerate() {
            let interval = read_intervals_ns.get(i).copied().unwrap_or(0);
            rec.add_port(device, protocol, *baud, interval)?;
        }
        Ok(rec)
    }

    /// Adds a port's `/<device>/raw` channel (next port index; see
    /// [`RawRecorder::with_read_intervals`] for the read interval) and returns its index.
    pub fn add_port(
        &mut self,
        device: &str,
        protocol: &str,
        baud: u32,
        read_interval_ns: u64,
    ) -> Result<u16, mcap::McapError> {
        let link = PortLink {
            read_interval_ns,
            ..PortLink::baud(baud)
        };
        self.add_port_with_link(device, protocol, &link)
    }

    /// As [`RawRecorder::add_port`], with everything the aligner was told of the port's link
    /// (its adapter's latency timer, the device's stated transmit buffer), kept as channel
    /// metadata so that a replay times the bytes as the live service did
    /// (`Recorded::Raw::link`).
    pub fn add_port_with_link(
        &mut self,
        device: &str,
        protocol: &str,
        link: &PortLink,
    ) -> Result<u16, mcap::McapError> {
        let mut meta = BTreeMap::from([
            ("device".to_string(), device.to_string()),
            ("protocol".to_string(), protocol.to_string()),
        ]);
        link.write_to(&mut meta);
        let name = if protocol.is_empty() {
            device
        } else {
            protocol
        };
        let schema = self
            .writer
            .add_schema(&format!("{RAW_SCHEMA_PREFIX}{name}"), "", &[])?;
        let id = self.writer.add_channel(
            schema,
            &raw_topic(device),
            "application/octet-stream",
            &meta,
        )?;
        self.port_channels.push(id);
        u16::try_from(self.port_channels.len() - 1).map_err(|_| mcap::McapError::TooManyChannels)
    }

    /// Adds a JSON channel and returns its id.
    pub fn add_json_channel(&mut self, topic: &str) -> Result<u16, mcap::McapError> {
        self.writer.add_channel(0, topic, "json", &BTreeMap::new())
    }

    /// Adds a JSON channel whose messages follow the JSON Schema `schema` (schema encoding
    /// `jsonschema`, named `schema_name`) and returns its id.
    pub fn add_schema_channel(
        &mut self,
        topic: &str,
        schema_name: &str,
        schema: &[u8],
        metadata: &BTreeMap<String, String>,
    ) -> Result<u16, mcap::McapError> {
        let id = self.writer.add_schema(schema_name, "jsonschema", schema)?;
        self.writer.add_channel(id, topic, "json", metadata)
    }

    /// Writes one message with distinct log and publish times, ns (`vigil run`: log time on the
    /// UTC timeline, publish time the host monotonic receive time).
    pub fn write_at(
        &mut self,
        channel_id: u16,
        log_time: u64,
        publish_time: u64,
        data: &[u8],
    ) -> Result<(), mcap::McapError> {
        let seq = self.sequences.entry(channel_id).or_insert(0);
        *seq = seq.wrapping_add(1);
        let header = MessageHeader {
            channel_id,
            sequence: *seq,
            log_time,
            publish_time,
        };
        self.writer.write_to_known_channel(&header, data)
    }

    /// The channel id of port `port`'s raw channel.
    pub fn raw_channel(&self, port: u16) -> Option<u16> {
        self.port_channels.get(usize::from(port)).copied()
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

    /// Writes one message on a channel (log and publish time both `t_host_ns`).
    pub fn write(
        &mut self,
        channel_id: u16,
        t_host_ns: u64,
        data: &[u8],
    ) -> Result<(), mcap::McapError> {
        self.write_at(channel_id, t_host_ns, t_host_ns, data)
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
