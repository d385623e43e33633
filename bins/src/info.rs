//! `vigil info FILE.mcap`: a summary of a recording in the manner of `mcap info` (issue 20):
//! header, message count, time range (UTC when the file is on the UTC timeline), chunks and their
//! compression, one line per channel (topic, messages, rate, schema, encoding) and the metadata
//! records. Read from the file's summary section (found through its footer, without reading the
//! data); a file without one (a killed recorder) is streamed instead and says so.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom};
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use mcap::records::Record;
use vigil_fusion::time::gps;
use vigil_record::Recorded;
use vigil_record::read_recording_from;

/// Arguments of `vigil info`.
#[derive(Debug, Args)]
pub struct InfoArgs {
    /// The MCAP recording.
    pub input: PathBuf,
}

/// One channel of the summary.
#[derive(Debug, Default, Clone)]
struct ChannelLine {
    topic: String,
    schema: String,
    encoding: String,
    messages: u64,
}

/// What the summary says.
#[derive(Debug, Default)]
struct Info {
    messages: u64,
    start: u64,
    end: u64,
    chunks: u64,
    compression: BTreeMap<String, u64>,
    channels: BTreeMap<u16, ChannelLine>,
    metadata: Vec<String>,
    from_summary: bool,
    damage: Option<String>,
}

/// A log time as text: UTC date and time when it is on the UTC timeline (after 2000), else
/// seconds of host monotonic time.
pub fn time_text(t_ns: u64) -> String {
    let t = i64::try_from(t_ns).unwrap_or(i64::MAX);
    if t < 946_684_800 * gps::NS_PER_S {
        return format!("{:.3} s (host monotonic)", t as f64 * 1e-9);
    }
    let secs = t.div_euclid(gps::NS_PER_S);
    let (y, m, d) = gps::civil_from_days(secs.div_euclid(gps::S_PER_DAY));
    let sod = secs.rem_euclid(gps::S_PER_DAY);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}.{:03}Z",
        sod / 3600,
        sod / 60 % 60,
        sod % 60,
        t.rem_euclid(gps::NS_PER_S) / 1_000_000
    )
}

fn from_summary(mut f: File) -> Option<Info> {
    let end = f.seek(SeekFrom::End(-37)).ok()?;
    let mut buf = Vec::new();
    (&mut f).take(37).read_to_end(&mut buf).ok()?;
    if buf.len() != 37 || buf[0] != 0x02 {
        return None;
    }
    let start = u64::from_le_bytes(buf[9..17].try_into().ok()?);
    if start == 0 || start >= end {
        return None;
    }
    f.seek(SeekFrom::Start(start)).ok()?;
    buf.clear();
    (&mut f).take(end - start).read_to_end(&mut buf).ok()?;
    let mut info = Info {
        from_summary: true,
        ..Info::default()
    };
    let mut schemas: BTreeMap<u16, String> = BTreeMap::new();
    let mut counts: BTreeMap<u16, u64> = BTreeMap::new();
    let mut rest = buf.as_slice();
    while rest.len() >= 9 {
        let op = rest[0];
        let len = usize::try_from(u64::from_le_bytes(rest[1..9].try_into().ok()?)).ok()?;
        let body = rest.get(9..9 + len)?;
        rest = &rest[9 + len..];
        match mcap::parse_record(op, body) {
            Ok(Record::Schema { header, .. }) => {
                schemas.insert(header.id, header.name);
            }
            Ok(Record::Channel(c)) => {
                info.channels.insert(
                    c.id,
                    ChannelLine {
                        topic: c.topic,
                        schema: schemas.get(&c.schema_id).cloned().unwrap_or_default(),
                        encoding: c.message_encoding,
                        messages: 0,
                    },
                );
            }
            Ok(Record::Statistics(s)) => {
                info.messages = s.message_count;
                info.start = s.message_start_time;
                info.end = s.message_end_time;
                counts = s.channel_message_counts;
            }
            Ok(Record::ChunkIndex(c)) => {
                info.chunks += 1;
                *info.compression.entry(c.compression).or_insert(0) += 1;
            }
            Ok(Record::MetadataIndex(m)) => info.metadata.push(m.name),
            _ => {}
        }
    }
    for (id, n) in counts {
        if let Some(c) = info.channels.get_mut(&id) {
            c.messages = n;
        }
    }
    Some(info)
}

/// A file without a summary: streamed, counting messages per topic.
fn by_streaming(input: &Path) -> Result<Info> {
    let f = File::open(input).with_context(|| format!("cannot read {}", input.display()))?;
    let mut info = Info::default();
    let mut topics: BTreeMap<String, u64> = BTreeMap::new();
    let outcome = read_recording_from(BufReader::new(f), |m| -> Result<()> {
        let topic = match m {
            Recorded::Raw { device, .. } => format!("/{device}/raw"),
            Recorded::Truth { .. } => vigil_record::TRUTH_TOPIC.to_string(),
            Recorded::Other { topic } => topic.to_string(),
        };
        *topics.entry(topic).or_insert(0) += 1;
        Ok(())
    })?;
    info.messages = outcome.messages;
    info.damage = outcome.damage;
    for (i, (topic, n)) in topics.into_iter().enumerate() {
        let id = u16::try_from(i).unwrap_or(u16::MAX);
        info.channels.insert(
            id,
            ChannelLine {
                topic,
                messages: n,
                ..ChannelLine::default()
            },
        );
    }
    Ok(info)
}

fn render(path: &Path, bytes: u64, info: &Info) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "file:     {} ({bytes} bytes)", path.display());
    if !info.from_summary {
        let _ = writeln!(
            s,
            "summary:  none (the recorder did not finish); counted by reading the file{}",
            info.damage
                .as_ref()
                .map_or(String::new(), |d| format!(": {d}"))
        );
    }
    let _ = writeln!(s, "messages: {}", info.messages);
    if info.from_summary && info.messages > 0 {
        let dur = info.end.saturating_sub(info.start) as f64 * 1e-9;
        let _ = writeln!(s, "start:    {}", time_text(info.start));
        let _ = writeln!(s, "end:      {}", time_text(info.end));
        let _ = writeln!(s, "duration: {dur:.3} s");
        let comp: Vec<String> = info
            .compression
            .iter()
            .map(|(c, n)| format!("{}: {n}", if c.is_empty() { "none" } else { c }))
            .collect();
        let _ = writeln!(s, "chunks:   {} ({})", info.chunks, comp.join(", "));
    }
    let _ = writeln!(s, "channels:");
    let dur = info.end.saturating_sub(info.start) as f64 * 1e-9;
    let width = info
        .channels
        .values()
        .map(|c| c.topic.len())
        .max()
        .unwrap_or(0);
    for (id, c) in &info.channels {
        let rate = if info.from_summary && dur > 0.0 {
            format!(" {:>9.2} Hz", c.messages as f64 / dur)
        } else {
            String::new()
        };
        let _ = writeln!(
            s,
            "  ({id:>2}) {:<width$} {:>9} msgs{rate} : {} [{}]",
            c.topic,
            c.messages,
            if c.schema.is_empty() { "-" } else { &c.schema },
            c.encoding
        );
    }
    if !info.metadata.is_empty() {
        let _ = writeln!(s, "metadata: {}", info.metadata.join(", "));
    }
    s
}

/// Runs `vigil info`.
pub fn run(args: &InfoArgs) -> Result<()> {
    let f =
        File::open(&args.input).with_context(|| format!("cannot read {}", args.input.display()))?;
    let bytes = f.metadata().map(|m| m.len()).unwrap_or(0);
    let info = match from_summary(f) {
        Some(i) => i,
        None => by_streaming(&args.input)?,
    };
    print!("{}", render(&args.input, bytes, &info));
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_on_the_utc_timeline_read_as_dates() {
        // 2026-11-25T12:34:56.789Z = 1795610096.789 s since the Unix epoch (days_from_civil:
        // 20782 days to 2026-11-25, plus 45296.789 s).
        let t = (20_782 * 86_400 + 45_296) * 1_000_000_000u64 + 789_000_000;
        assert_eq!(time_text(t), "2026-11-25T12:34:56.789Z");
        assert_eq!(time_text(5_000_000_000), "5.000 s (host monotonic)");
    }
}
