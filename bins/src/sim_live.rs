//! `vigil sim --pty-dir DIR`: the simulation live on Linux pseudo-terminals, one per device port,
//! so vigil's real serial path (tokio-serial) reads them. `DIR/<device>` is a symbolic link to the
//! port's terminal (e.g. `/dev/pts/7`); the device/path pairs are also printed on stdout.
//!
//! Chunks are written to the terminal's master side at their host receive time, paced against the
//! wall clock (`--speed` times real time). The slave side is kept open here in raw mode, so no line
//! discipline changes a byte (a CR stays a CR) before a reader opens it. A terminal nobody reads
//! fills up; further bytes are dropped and counted, as a serial line without a listener loses them.
//! What a reader writes to a terminal is handed to that port's device model (`host_input`).

use std::os::fd::OwnedFd;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use rustix::fs::{Mode, OFlags};
use rustix::io::Errno;
use vigil_sim::{Chunk, RunInfo, Sink, SinkError, TruthRecord};

/// One pseudo-terminal.
pub struct Pty {
    master: OwnedFd,
    _slave: OwnedFd,
    /// Path of the slave side.
    pub path: PathBuf,
}

/// Opens a pseudo-terminal with its slave side in raw mode and its master non-blocking.
pub fn open_pty() -> Result<Pty> {
    use rustix::pty::{OpenptFlags, grantpt, openpt, ptsname, unlockpt};
    let master = openpt(OpenptFlags::RDWR | OpenptFlags::NOCTTY).context("openpt")?;
    grantpt(&master).context("grantpt")?;
    unlockpt(&master).context("unlockpt")?;
    let name = ptsname(&master, Vec::new()).context("ptsname")?;
    let path = PathBuf::from(name.to_string_lossy().into_owned());
    let slave = rustix::fs::open(&path, OFlags::RDWR | OFlags::NOCTTY, Mode::empty())
        .with_context(|| format!("open {}", path.display()))?;
    let mut t = rustix::termios::tcgetattr(&slave).context("tcgetattr")?;
    t.make_raw();
    rustix::termios::tcsetattr(&slave, rustix::termios::OptionalActions::Now, &t)
        .context("tcsetattr")?;
    rustix::fs::fcntl_setfl(&master, OFlags::NONBLOCK).context("fcntl")?;
    Ok(Pty {
        master,
        _slave: slave,
        path,
    })
}

/// Creates `dir/<device>` links to the ports' terminals (replacing old links).
pub fn link_ports(dir: &Path, names: &[&str], ptys: &[Pty]) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("create {}", dir.display()))?;
    for (name, pty) in names.iter().zip(ptys) {
        let link = dir.join(name);
        let _ = std::fs::remove_file(&link);
        std::os::unix::fs::symlink(&pty.path, &link)
            .with_context(|| format!("link {}", link.display()))?;
    }
    Ok(())
}

/// Write stamps of one device's messages (`vigil measure`): when the last byte of each of its
/// messages has been written to the terminal.
pub struct Stamper {
    device: &'static str,
    port: u16,
    /// Bytes of the port written so far (the messages' `rx_offset` counts in the same stream).
    written: u64,
    /// (offset just past the message's last byte, the message's GPS time ns), in stream order.
    pending: std::collections::VecDeque<(u64, i64)>,
    tx: std::sync::mpsc::Sender<Stamp>,
}

/// One message's write stamp.
#[derive(Debug, Clone, Copy)]
pub struct Stamp {
    /// The message's GPS time (its sample time), ns.
    pub t_gps_ns: i64,
    /// `CLOCK_MONOTONIC` just before the write of its last byte, ns.
    pub written_mono_ns: u64,
}

impl Stamper {
    /// Stamps the messages of `device` on port `port`, sending each stamp to `tx`.
    pub fn new(device: &'static str, port: u16, tx: std::sync::mpsc::Sender<Stamp>) -> Self {
        Self {
            device,
            port,
            written: 0,
            pending: Default::default(),
            tx,
        }
    }
}

/// A sink writing chunks to the terminals at their (scaled) host times.
pub struct LiveSink {
    ptys: Vec<Pty>,
    speed: f64,
    start: Option<(u64, Instant)>,
    stamper: Option<Stamper>,
    /// Bytes dropped because a terminal was full (nobody reading, or reading too late), per
    /// port.
    pub dropped_by_port: Vec<u64>,
    /// Chunks written (one write each).
    pub chunks: u64,
    /// Messages that never reached a terminal whole, per device, from the simulator's truth:
    /// discarded by a device whose output exceeds its line (its buffer full), or lost or
    /// damaged by a link fault of the scenario. Not the service's doing: what a real device on
    /// such a line would lose.
    pub lost_messages: std::collections::BTreeMap<&'static str, u64>,
}

impl LiveSink {
    /// A sink over the ports' terminals, paced at `speed` times real time.
    pub fn new(ptys: Vec<Pty>, speed: f64) -> Self {
        Self {
            dropped_by_port: vec![0; ptys.len()],
            ptys,
            speed,
            start: None,
            stamper: None,
            chunks: 0,
            lost_messages: std::collections::BTreeMap::new(),
        }
    }

    /// Bytes dropped on all ports.
    pub fn dropped_bytes(&self) -> u64 {
        self.dropped_by_port.iter().sum()
    }

    /// Stamps the writes of one device's messages (see [`Stamper`]).
    pub fn with_stamper(mut self, stamper: Stamper) -> Self {
        self.stamper = Some(stamper);
        self
    }
}

impl Sink for LiveSink {
    fn start(&mut self, info: &RunInfo) -> Result<(), SinkError> {
        self.start = Some((info.host_clock.offset_ns, Instant::now()));
        Ok(())
    }

    fn chunk(&mut self, chunk: &Chunk) -> Result<(), SinkError> {
        let (t0, wall0) = *self.start.get_or_insert((chunk.t_host_ns, Instant::now()));
        let due =
            Duration::from_secs_f64(chunk.t_host_ns.saturating_sub(t0) as f64 / 1e9 / self.speed);
        if let Some(wait) = due.checked_sub(wall0.elapsed()) {
            std::thread::sleep(wait);
        }
        let pty = self
            .ptys
            .get(usize::from(chunk.port))
            .ok_or("chunk of an unknown port")?;
        // Stamped just before the write: the bytes are in the terminal no earlier than this, and
        // a stamp taken after could come later than the reader's reaction (2 cores).
        let before_write = vigil_bus::clock::monotonic_ns();
        self.chunks += 1;
        let mut rest = &chunk.bytes[..];
        while !rest.is_empty() {
            match rustix::io::write(&pty.master, rest) {
                Ok(n) => rest = &rest[n..],
                Err(Errno::AGAIN) => {
                    self.dropped_by_port[usize::from(chunk.port)] += rest.len() as u64;
                    break;
                }
                Err(Errno::INTR) => {}
                Err(e) => return Err(Box::new(std::io::Error::from(e))),
            }
        }
        if let Some(st) = self.stamper.as_mut().filter(|st| st.port == chunk.port) {
            // Dropped bytes count too: the offsets are those of the stream the device sent.
            st.written += chunk.bytes.len() as u64;
            while let Some(&(end, t)) = st.pending.front() {
                if end > st.written {
                    break;
                }
                st.pending.pop_front();
                // A receiver that has gone is no reason to stop the simulation.
                let _ = st.tx.send(Stamp {
                    t_gps_ns: t,
                    written_mono_ns: before_write,
                });
            }
        }
        Ok(())
    }

    fn truth(&mut self, record: &TruthRecord, _t_host_ns: u64) -> Result<(), SinkError> {
        if record.corrupted {
            *self.lost_messages.entry(record.device).or_default() += 1;
        }
        if let Some(st) = self
            .stamper
            .as_mut()
            .filter(|st| st.device == record.device)
        {
            let end = record.rx_offset + record.wire.len() as u64;
            st.pending.push_back((end, record.t_gps_ns));
        }
        Ok(())
    }

    /// What readers wrote to the terminals (commands to the devices), read without blocking.
    fn host_input(&mut self) -> Vec<(u16, Vec<u8>)> {
        let mut input = Vec::new();
        let mut buf = [0u8; 4096];
        for (i, pty) in self.ptys.iter().enumerate() {
            let mut bytes = Vec::new();
            while let Ok(n @ 1..) = rustix::io::read(&pty.master, &mut buf) {
                bytes.extend_from_slice(&buf[..n]);
            }
            if !bytes.is_empty() {
                input.push((i as u16, bytes));
            }
        }
        input
    }
}
