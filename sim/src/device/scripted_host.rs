//! Test support: a memory sink whose host writes given bytes to one device's port at the
//! simulation windows listed (for the command protocols of the VN-200 and the TT-Multi-RF).

use crate::engine::{MemorySink, RunInfo, Sink, SinkError};
use crate::link::Chunk;
use crate::truth::TruthRecord;

/// Records everything like [`MemorySink`] and answers `host_input` from a script of
/// (window index, bytes) pairs for the port of `device`.
pub(crate) struct ScriptedHost {
    pub(crate) inner: MemorySink,
    device: &'static str,
    script: Vec<(usize, Vec<u8>)>,
    polls: usize,
    pub(crate) port: u16,
}

impl ScriptedHost {
    /// A host that writes `script` to the port of `device`.
    pub(crate) fn new(device: &'static str, script: Vec<(usize, Vec<u8>)>) -> Self {
        Self {
            inner: MemorySink::default(),
            device,
            script,
            polls: 0,
            port: 0,
        }
    }
}

impl Sink for ScriptedHost {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        self.port = info
            .ports
            .iter()
            .position(|p| p.device == self.device)
            .unwrap() as u16;
        self.inner.start(info)
    }
    fn chunk(&mut self, c: &Chunk) -> Result<(), SinkError> {
        self.inner.chunk(c)
    }
    fn truth(&mut self, r: &TruthRecord, t: u64) -> Result<(), SinkError> {
        self.inner.truth(r, t)
    }
    fn host_input(&mut self) -> Vec<(u16, Vec<u8>)> {
        let k = self.polls;
        self.polls += 1;
        self.script
            .iter()
            .filter(|(w, _)| *w == k)
            .map(|(_, b)| (self.port, b.clone()))
            .collect()
    }
}
