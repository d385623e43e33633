//! The serial loop shared by `vigil run` (every read processed, published and optionally
//! recorded) and `vigil record` (every read recorded, nothing processed): each port is opened with
//! tokio-serial, set up when configured, then read on arrival or paced on a shared grid
//! ([`reader`]), and reopened with backoff when it fails or disappears.

use std::cell::RefCell;
use std::path::PathBuf;
use std::rc::Rc;
use std::time::Duration;

use tokio_serial::SerialPortBuilderExt;
use vigil_bus::clock::monotonic_ns;

use crate::config::{LinkSection, Port};
use crate::runtime::reader;
use crate::runtime::setup::Setup;

/// What the loop needs to know of a port.
#[derive(Debug, Clone)]
pub struct SerialPort {
    /// Port name (logs, the recording's channel).
    pub device: String,
    /// Serial device path.
    pub path: PathBuf,
    /// Baud rate.
    pub baud: u32,
    /// Device set-up run each time the port opens.
    pub setup: Option<Setup>,
    /// Read every this many ns (0: as the bytes arrive).
    pub read_interval_ns: u64,
}

impl From<&Port> for SerialPort {
    fn from(p: &Port) -> Self {
        Self {
            device: p.device.clone(),
            path: p.path.clone(),
            baud: p.baud,
            setup: p.setup,
            read_interval_ns: p.read_interval_ns,
        }
    }
}

/// Where the port tasks hand what they read and what happens to the link (one thread: borrowed
/// only between awaits).
pub trait PortSink {
    /// A read of port `port` at host monotonic time `t_host_ns`.
    fn chunk(&mut self, port: usize, t_host_ns: u64, bytes: &[u8]);
    /// Port `port` opened.
    fn opened(&mut self, port: usize);
    /// Port `port` closed or failed to open, and why.
    fn closed(&mut self, port: usize, reason: &str);
    /// Origin of the paced ports' common drain grid.
    fn epoch(&self) -> tokio::time::Instant;
    /// How many more bytes complete port `port`'s next message when its stream is steady: a
    /// port read on arrival then wakes the service only once that many bytes wait
    /// ([`reader::read_on_arrival`]). `None`: wake on every arrival.
    fn bytes_until_whole_message(&self, _port: usize) -> Option<usize> {
        None
    }
}

/// A period in seconds from the configuration, at least 1 ms.
pub fn secs(s: f64) -> Duration {
    Duration::from_secs_f64(s.max(1e-3))
}

/// Reads port `i` forever, reopening it with exponential backoff (`link`): each read goes to
/// `sink` with its host monotonic time, the moment it returns (no queue between the read and the
/// sink). The device set-up, when the port has one, runs each time it opens; what the device
/// sends meanwhile reaches the sink afterwards, each read with its own receive time.
pub async fn port_task<S: PortSink>(
    i: usize,
    port: SerialPort,
    link: LinkSection,
    ctx: Rc<RefCell<S>>,
) {
    let initial = secs(link.reconnect_initial_s);
    let mut delay = initial;
    loop {
        let path = port.path.to_string_lossy().into_owned();
        match tokio_serial::new(&path, port.baud).open_native_async() {
            Ok(mut serial) => {
                delay = initial;
                ctx.borrow_mut().opened(i);
                if let Some(setup) = port.setup {
                    let mut during: Vec<(u64, Vec<u8>)> = Vec::new();
                    let mut forward = |b: Vec<u8>| during.push((monotonic_ns(), b));
                    crate::runtime::setup::run(&port.device, setup, &mut serial, &mut forward)
                        .await;
                    for (t, b) in during {
                        ctx.borrow_mut().chunk(i, t, &b);
                    }
                }
                let chunk = |t: u64, b: &[u8]| ctx.borrow_mut().chunk(i, t, b);
                let reason = match reader::detach(serial) {
                    Err(e) => format!("cannot take the descriptor: {e}"),
                    Ok(file) if port.read_interval_ns > 0 => {
                        let every = Duration::from_nanos(port.read_interval_ns);
                        let epoch = ctx.borrow().epoch();
                        reader::read_paced(file, every, epoch, chunk).await
                    }
                    Ok(file) => {
                        let chunk = |t: u64, b: &[u8]| {
                            let mut c = ctx.borrow_mut();
                            c.chunk(i, t, b);
                            c.bytes_until_whole_message(i)
                        };
                        reader::read_on_arrival(file, chunk).await
                    }
                };
                ctx.borrow_mut().closed(i, &reason);
            }
            Err(e) => ctx.borrow_mut().closed(i, &format!("cannot open: {e}")),
        }
        tokio::time::sleep(delay).await;
        delay = (delay * 2).min(secs(link.reconnect_max_s));
    }
}
