//! The simulator's MCAP sink: a run written as a vigil recording ([`vigil_record`]), with the
//! truth records on the `/truth` channel and the run parameters in the `vigil.sim` metadata.

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use vigil_record::{METADATA_NAME, RawRecorder, TRUTH_TOPIC};

use crate::engine::{RunInfo, Sink, SinkError};
use crate::link::Chunk;
use crate::truth::TruthRecord;

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
