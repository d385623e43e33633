//! Reading a recording as a stream (issue 20, "Replay streams" and "A recording is valid in any
//! message order"): record by record from any [`Read`], one chunk in memory at a time, whatever
//! the file's length.
//!
//! - The data section is walked record by record (`opcode`, `length`, body; MCAP format
//!   specification, "Records"). Chunks are decompressed (none or zstd), their CRC checked when
//!   it is set, and their records parsed with the `mcap` crate's [`mcap::parse_record`].
//! - Order: raw port messages (topics `*/raw`) are handed out in receive-time order (their
//!   `publish_time`: the host monotonic receive time in every vigil recording), stable for equal
//!   times, within the window of the chunks read so far: a message is released once a later
//!   chunk starts (its `message_start_time`) after it. So any order of the messages inside a chunk
//!   (e.g. grouped by channel) replays as received; across chunks, the writer's chunks are
//!   assumed to follow time, as the MCAP writers do. Other messages (truth, decoded, fused) are
//!   handed out in file order as they come: replays read the raw channels only.
//! - Damage: a chunk whose CRC does not match, whose compression is unknown (lz4 is not built
//!   in) or that does not decompress or parse is skipped, counted and described, and reading goes
//!   on with the next record. A file that ends inside a record (a killed writer) or whose record
//!   framing is broken (an implausible length or opcode) ends the reading there, with what was read
//!   so far handed out and the rest described. Nothing here panics on any input.
//! - Memory: the reorder window is bounded ([`MAX_WINDOW_BYTES`]): past it the oldest messages
//!   are released early (a file whose chunks do not follow time replays slightly out of order
//!   rather than exhausting memory).

use std::collections::{BTreeMap, VecDeque};
use std::io::{self, Read};

use crate::PortLink;
use crate::write::{METADATA_NAME, TRUTH_TOPIC};

/// Largest record body read into memory, bytes: a longer length is taken as damage (vigil's
/// chunks are [`crate::write::CHUNK_BYTES`] uncompressed; other writers use up to a few MiB).
pub const MAX_RECORD_BYTES: u64 = 256 * 1024 * 1024;
/// Largest reorder window, bytes of buffered messages.
pub const MAX_WINDOW_BYTES: usize = 64 * 1024 * 1024;

const MAGIC: &[u8; 8] = b"\x89MCAP0\r\n";
const OP_HEADER: u8 = 0x01;
const OP_FOOTER: u8 = 0x02;
const OP_SCHEMA: u8 = 0x03;
const OP_CHANNEL: u8 = 0x04;
const OP_MESSAGE: u8 = 0x05;
const OP_CHUNK: u8 = 0x06;
const OP_METADATA: u8 = 0x0C;
const OP_DATA_END: u8 = 0x0F;

/// How reading a recording went.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct ReadOutcome {
    /// Messages handed out.
    pub messages: u64,
    /// Everything that was skipped or not read, in file order, as one text (`None`: the whole
    /// file was read): damaged chunks skipped, and where and why reading stopped early.
    pub damage: Option<String>,
    /// Chunks skipped as damaged (their messages are lost; the rest of the file was read).
    pub skipped_chunks: u64,
    /// Bytes of the file consumed.
    pub bytes_read: u64,
}

impl ReadOutcome {
    fn note(&mut self, what: String) {
        match &mut self.damage {
            Some(d) => {
                d.push_str("; ");
                d.push_str(&what);
            }
            None => self.damage = Some(what),
        }
    }
}

/// What a channel is, from its topic and metadata.
#[derive(Debug, Clone)]
struct ChannelInfo {
    topic: String,
    kind: Kind,
    device: String,
    protocol: String,
    /// The link the channel's metadata records (issue 18: it reaches the aligner).
    link: PortLink,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    Raw,
    Truth,
    Other,
}

impl ChannelInfo {
    fn of(c: &mcap::records::Channel) -> Self {
        let topic = c.topic.clone();
        let (kind, device) = if topic == TRUTH_TOPIC {
            (Kind::Truth, String::new())
        } else if let Some(stripped) = topic.strip_suffix("/raw") {
            let d = c
                .metadata
                .get("device")
                .cloned()
                .unwrap_or_else(|| stripped.trim_start_matches('/').to_string());
            (Kind::Raw, d)
        } else {
            (Kind::Other, String::new())
        };
        Self {
            topic,
            kind,
            device,
            protocol: c.metadata.get("protocol").cloned().unwrap_or_default(),
            link: PortLink::read_from(&c.metadata),
        }
    }
}

/// One buffered raw message, ordered by (receive time, arrival).
#[derive(Debug, PartialEq, Eq)]
struct Pending {
    t_host_ns: u64,
    order: u64,
    channel: u16,
    /// The message's bytes: `State::arena[start..start + len]`.
    start: usize,
    len: usize,
}

impl Pending {
    fn key(&self) -> (u64, u64) {
        (self.t_host_ns, self.order)
    }
}

/// The reader's state: channels, the reorder window and the outcome.
struct State {
    channels: BTreeMap<u16, ChannelInfo>,
    /// Sorted by [`Pending::key`]. A deque, not a heap: a writer's messages nearly always come
    /// in receive order, so a message is appended at the back and released from the front in
    /// O(1); only an out-of-order one is inserted in the middle.
    window: VecDeque<Pending>,
    window_bytes: usize,
    /// The window's message bytes, one buffer for all (no allocation per message): cleared
    /// when the window empties, compacted when mostly released.
    arena: Vec<u8>,
    order: u64,
    outcome: ReadOutcome,
}

impl State {
    fn emit<E>(
        &mut self,
        p: &Pending,
        f: &mut impl FnMut(Recorded<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let Some(c) = self.channels.get(&p.channel) else {
            return Ok(());
        };
        self.outcome.messages += 1;
        f(Recorded::Raw {
            device: &c.device,
            protocol: &c.protocol,
            t_host_ns: p.t_host_ns,
            bytes: &self.arena[p.start..p.start + p.len],
            link: c.link,
        })
    }

    /// Releases every buffered message received before `until` (all with `None`), and the
    /// oldest ones while the window is over its size limit.
    fn release<E>(
        &mut self,
        until: Option<u64>,
        f: &mut impl FnMut(Recorded<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        while let Some(top) = self.window.front() {
            let due = until.is_none_or(|u| top.t_host_ns < u);
            if !due && self.window_bytes <= MAX_WINDOW_BYTES {
                break;
            }
            let Some(p) = self.window.pop_front() else {
                break;
            };
            self.window_bytes -= p.len;
            self.emit(&p, f)?;
        }
        if self.window.is_empty() {
            self.arena.clear();
        } else if self.arena.len() > 2 * self.window_bytes + (1 << 20) {
            let mut kept = Vec::with_capacity(self.window_bytes);
            for p in &mut self.window {
                let from = p.start;
                p.start = kept.len();
                kept.extend_from_slice(&self.arena[from..from + p.len]);
            }
            self.arena = kept;
        }
        Ok(())
    }

    /// A message record: raw ones into the window, others handed out now.
    fn message<E>(
        &mut self,
        m: mcap::records::MessageHeader,
        data: &[u8],
        f: &mut impl FnMut(Recorded<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let Some(c) = self.channels.get(&m.channel_id) else {
            return Ok(());
        };
        match c.kind {
            Kind::Raw => {
                self.order += 1;
                self.window_bytes += data.len();
                let p = Pending {
                    t_host_ns: m.publish_time,
                    order: self.order,
                    channel: m.channel_id,
                    start: self.arena.len(),
                    len: data.len(),
                };
                self.arena.extend_from_slice(data);
                if self.window.back().is_none_or(|b| b.key() <= p.key()) {
                    self.window.push_back(p);
                } else {
                    let at = self.window.partition_point(|q| q.key() <= p.key());
                    self.window.insert(at, p);
                }
                Ok(())
            }
            Kind::Truth => {
                self.outcome.messages += 1;
                f(Recorded::Truth {
                    t_host_ns: m.log_time,
                    json: data,
                })
            }
            Kind::Other => {
                self.outcome.messages += 1;
                let topic = c.topic.as_str();
                f(Recorded::Other { topic })
            }
        }
    }

    /// Records inside a decompressed chunk (or a single top-level record).
    fn records<E>(
        &mut self,
        mut body: &[u8],
        f: &mut impl FnMut(Recorded<'_>) -> Result<(), E>,
    ) -> Result<Result<(), String>, E> {
        while !body.is_empty() {
            let Some((op, rec, rest)) = split_record(body) else {
                return Ok(Err("a record inside the chunk is cut short".into()));
            };
            body = rest;
            if let Err(e) = self.record(op, rec, f)? {
                return Ok(Err(e));
            }
        }
        Ok(Ok(()))
    }

    /// One schema, channel or message record; others are ignored.
    fn record<E>(
        &mut self,
        op: u8,
        body: &[u8],
        f: &mut impl FnMut(Recorded<'_>) -> Result<(), E>,
    ) -> Result<Result<(), String>, E> {
        if !matches!(op, OP_CHANNEL | OP_MESSAGE) {
            return Ok(Ok(()));
        }
        match mcap::parse_record(op, body) {
            Ok(mcap::records::Record::Channel(c)) => {
                self.channels.insert(c.id, ChannelInfo::of(&c));
                Ok(Ok(()))
            }
            Ok(mcap::records::Record::Message { header, data }) => {
                self.message(header, &data, f).map(Ok)
            }
            Ok(_) => Ok(Ok(())),
            Err(e) => Ok(Err(format!("bad record 0x{op:02x}: {e}"))),
        }
    }
}

/// Splits `(opcode, body, rest)` off a byte slice of records.
fn split_record(b: &[u8]) -> Option<(u8, &[u8], &[u8])> {
    let op = *b.first()?;
    let len = u64::from_le_bytes(b.get(1..9)?.try_into().ok()?);
    let len = usize::try_from(len).ok()?;
    let body = b.get(9..9usize.checked_add(len)?)?;
    Some((op, body, &b[9 + len..]))
}

/// A chunk record's parts (MCAP specification, "Chunk (op=0x06)").
struct Chunk<'a> {
    message_start_time: u64,
    message_end_time: u64,
    uncompressed_size: u64,
    uncompressed_crc: u32,
    compression: &'a str,
    records: &'a [u8],
}

fn parse_chunk(b: &[u8]) -> Option<Chunk<'_>> {
    let u64_at =
        |i: usize| -> Option<u64> { Some(u64::from_le_bytes(b.get(i..i + 8)?.try_into().ok()?)) };
    let message_start_time = u64_at(0)?;
    let message_end_time = u64_at(8)?;
    let uncompressed_size = u64_at(16)?;
    let uncompressed_crc = u32::from_le_bytes(b.get(24..28)?.try_into().ok()?);
    let clen = usize::try_from(u32::from_le_bytes(b.get(28..32)?.try_into().ok()?)).ok()?;
    let compression = std::str::from_utf8(b.get(32..32usize.checked_add(clen)?)?).ok()?;
    let at = 32 + clen;
    let rlen = usize::try_from(u64_at(at)?).ok()?;
    let records = b.get(at + 8..(at + 8).checked_add(rlen)?)?;
    Some(Chunk {
        message_start_time,
        message_end_time,
        uncompressed_size,
        uncompressed_crc,
        compression,
        records,
    })
}

/// The records of a chunk, decompressed and checked.
fn chunk_records<'a>(c: &Chunk<'a>, scratch: &'a mut Vec<u8>) -> Result<&'a [u8], String> {
    let data: &[u8] = match c.compression {
        "" => c.records,
        "zstd" => {
            if c.uncompressed_size > MAX_RECORD_BYTES {
                return Err(format!(
                    "uncompressed size {} implausible",
                    c.uncompressed_size
                ));
            }
            scratch.clear();
            let mut d =
                zstd::stream::read::Decoder::new(c.records).map_err(|e| format!("zstd: {e}"))?;
            (&mut d)
                .take(c.uncompressed_size)
                .read_to_end(scratch)
                .map_err(|e| format!("zstd: {e}"))?;
            scratch.as_slice()
        }
        other => return Err(format!("compression {other:?} is not supported")),
    };
    if data.len() as u64 != c.uncompressed_size {
        return Err(format!(
            "{} bytes after decompression, {} announced",
            data.len(),
            c.uncompressed_size
        ));
    }
    if c.uncompressed_crc != 0 {
        // CRC-32/ISO-HDLC, as the MCAP specification gives; crc32fast (SIMD) because a byte-table
        // CRC was half the time of a decoded replay.
        let crc = crc32fast::hash(data);
        if crc != c.uncompressed_crc {
            return Err(format!(
                "crc 0x{crc:08x}, 0x{:08x} recorded",
                c.uncompressed_crc
            ));
        }
    }
    Ok(data)
}

/// Reads a record body of `n` bytes into `body[..n]`, or as many as there are (fewer: the file
/// ended); returns the count. `body` only grows, so a reused buffer is neither zeroed again nor
/// copied through the reader's own buffer (a large `read` bypasses a `BufReader`), and it grows
/// at most 1 MiB past what has been read, so a damaged length does not allocate its whole claim.
fn read_body(r: &mut impl Read, body: &mut Vec<u8>, n: u64) -> io::Result<usize> {
    let n = usize::try_from(n).unwrap_or(usize::MAX);
    let mut got = 0;
    while got < n {
        let end = n.min(got.saturating_add(1 << 20).max(body.len()));
        if body.len() < end {
            body.resize(end, 0);
        }
        match r.read(&mut body[got..end]) {
            Ok(0) => break,
            Ok(k) => got += k,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(got)
}

/// Reads `n` bytes, or as many as there are (a short read means the file ended).
fn read_up_to(r: &mut impl Read, buf: &mut Vec<u8>, n: u64) -> io::Result<usize> {
    buf.clear();
    r.by_ref().take(n).read_to_end(buf)
}

/// Reads every message of an MCAP stream (see the module documentation for the order and the
/// handling of damage) and hands it to `f`. `f` may stop the reading by returning an error, which
/// is passed back; I/O errors of `r` end the reading and are described in the outcome.
pub fn read_recording_from<R: Read, E>(
    mut r: R,
    mut f: impl FnMut(Recorded<'_>) -> Result<(), E>,
) -> Result<ReadOutcome, E> {
    let mut st = State {
        channels: BTreeMap::new(),
        window: VecDeque::new(),
        window_bytes: 0,
        arena: Vec::new(),
        order: 0,
        outcome: ReadOutcome::default(),
    };
    let mut buf = Vec::new();
    match read_up_to(&mut r, &mut buf, 8) {
        Ok(8) if buf.as_slice() == MAGIC => st.outcome.bytes_read = 8,
        _ => {
            st.outcome
                .note("not an mcap file: no MCAP magic at the start".into());
            return Ok(st.outcome);
        }
    }
    let mut scratch = Vec::new();
    let mut body = Vec::new();
    loop {
        let at = st.outcome.bytes_read;
        let n = match read_up_to(&mut r, &mut buf, 9) {
            Ok(n) => n,
            Err(e) => {
                st.outcome.note(format!("read error at byte {at}: {e}"));
                break;
            }
        };
        if n == 0 {
            st.outcome.note(format!(
                "the file ends at byte {at} without its summary (truncated)"
            ));
            break;
        }
        if n < 9 {
            st.outcome.note(format!(
                "the file ends inside a record header at byte {at} (truncated)"
            ));
            break;
        }
        let op = buf[0];
        let len = u64::from_le_bytes(buf[1..9].try_into().unwrap_or_default());
        if op == 0 || len > MAX_RECORD_BYTES {
            st.outcome.note(format!(
                "record framing broken at byte {at} (opcode 0x{op:02x}, length {len}): the rest of the file is not read"
            ));
            break;
        }
        if op == OP_DATA_END || op == OP_FOOTER {
            st.outcome.bytes_read = at + 9;
            break;
        }
        match read_body(&mut r, &mut body, len) {
            Ok(n) if n as u64 == len => {}
            Ok(n) => {
                st.outcome.note(format!(
                    "the file ends inside a record at byte {at} ({n} of its {len} bytes; truncated)"
                ));
                break;
            }
            Err(e) => {
                st.outcome.note(format!("read error at byte {at}: {e}"));
                break;
            }
        }
        st.outcome.bytes_read = at + 9 + len;
        // `len` fits in usize: read_body read that many bytes.
        let rec = &body[..len as usize];
        match op {
            OP_CHUNK => {
                let Some(c) = parse_chunk(rec) else {
                    st.outcome.skipped_chunks += 1;
                    st.outcome
                        .note(format!("chunk at byte {at} skipped: malformed header"));
                    continue;
                };
                // Everything received before this chunk's first message is final.
                st.release(Some(c.message_start_time), &mut f)?;
                let outcome = match chunk_records(&c, &mut scratch) {
                    Ok(records) => st.records(records, &mut f)?,
                    Err(e) => Err(e),
                };
                if let Err(e) = outcome {
                    st.outcome.skipped_chunks += 1;
                    st.outcome.note(format!("chunk at byte {at} skipped: {e}"));
                }
            }
            OP_MESSAGE => {
                // An unchunked message is its own window.
                if let Ok(mcap::records::Record::Message { header, .. }) =
                    mcap::parse_record(op, rec)
                {
                    st.release(Some(header.publish_time), &mut f)?;
                }
                if let Err(e) = st.record(op, rec, &mut f)? {
                    st.outcome.note(format!("record at byte {at} skipped: {e}"));
                }
            }
            OP_CHANNEL => {
                if let Err(e) = st.record(op, rec, &mut f)? {
                    st.outcome.note(format!("record at byte {at} skipped: {e}"));
                }
            }
            OP_HEADER | OP_SCHEMA | OP_METADATA => {}
            _ => {}
        }
    }
    st.release(None, &mut f)?;
    Ok(st.outcome)
}

/// The first metadata record named `name` of an MCAP stream, looked for before the first message
/// (vigil writes its metadata at the start, so a file without it is not read to its end); `None`
/// when there is none there or the file is unreadable before it.
pub fn read_metadata_from<R: Read>(mut r: R, name: &str) -> Option<BTreeMap<String, String>> {
    let mut buf = Vec::new();
    if read_up_to(&mut r, &mut buf, 8).ok()? != 8 || buf.as_slice() != MAGIC {
        return None;
    }
    loop {
        if read_up_to(&mut r, &mut buf, 9).ok()? != 9 {
            return None;
        }
        let op = buf[0];
        let len = u64::from_le_bytes(buf[1..9].try_into().ok()?);
        if op == 0 || op == OP_DATA_END || op == OP_FOOTER || len > MAX_RECORD_BYTES {
            return None;
        }
        if read_up_to(&mut r, &mut buf, len).ok()? as u64 != len {
            return None;
        }
        if op == OP_METADATA
            && let Ok(mcap::records::Record::Metadata(m)) = mcap::parse_record(op, &buf)
            && m.name == name
        {
            return Some(m.metadata);
        }
        // A chunk with messages (a chunk of channel records only has times 0) or a message: the
        // start is over.
        let has_messages =
            parse_chunk(&buf).is_some_and(|c| c.message_end_time != 0 || c.message_start_time != 0);
        if op == OP_MESSAGE || (op == OP_CHUNK && has_messages) {
            return None;
        }
    }
}

/// First and last log time of a recording's messages, ns, from the statistics record of its
/// summary (found through the footer, without reading the data section); `None` for a file
/// without a readable summary (a truncated recording) or without messages.
pub fn recorded_span_from<R: Read + io::Seek>(mut r: R) -> Option<(u64, u64)> {
    use io::SeekFrom;
    // Footer record (1 + 8 + 20 bytes) and the closing magic.
    let end = r.seek(SeekFrom::End(-37)).ok()?;
    let mut buf = Vec::new();
    if read_up_to(&mut r, &mut buf, 37).ok()? != 37 || &buf[29..] != MAGIC || buf[0] != OP_FOOTER {
        return None;
    }
    let summary_start = u64::from_le_bytes(buf[9..17].try_into().ok()?);
    if summary_start == 0 || summary_start >= end {
        return None;
    }
    r.seek(SeekFrom::Start(summary_start)).ok()?;
    read_up_to(&mut r, &mut buf, end - summary_start).ok()?;
    let mut rest = buf.as_slice();
    while let Some((op, body, next)) = split_record(rest) {
        if let Ok(mcap::records::Record::Statistics(s)) = mcap::parse_record(op, body) {
            return (s.message_count > 0).then_some((s.message_start_time, s.message_end_time));
        }
        rest = next;
    }
    None
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
        /// What the live service was told of the port's link (its channel's metadata: the same
        /// for every chunk of the channel).
        link: PortLink,
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

/// First and last log time of a recording's messages, ns, from its MCAP statistics record (for
/// progress reports); `None` when the file has no readable summary (a truncated recording) or no
/// messages.
pub fn recorded_span(mcap: &[u8]) -> Option<(u64, u64)> {
    let stats = mcap::Summary::read(mcap).ok()??.stats?;
    (stats.message_count > 0).then_some((stats.message_start_time, stats.message_end_time))
}

/// Reads every message of an MCAP file held in memory and hands it to `f`: raw chunks in receive
/// order, damaged chunks skipped, a truncated file read up to the damage; the outcome says what
/// was skipped ([`read_recording_from`], which reads any stream). `f` may
/// stop the reading by returning an error, which is passed back.
pub fn read_recording<E>(
    buf: &[u8],
    f: impl FnMut(Recorded<'_>) -> Result<(), E>,
) -> Result<ReadOutcome, E> {
    read_recording_from(buf, f)
}

/// The `vigil.sim` metadata of a recording, if present and readable.
pub fn read_metadata(buf: &[u8]) -> Option<BTreeMap<String, String>> {
    read_metadata_from(buf, METADATA_NAME)
}
