//! `vigil measure --floor`: what reading the simulated ports costs on this machine when
//! nothing is done with the bytes (issue 21).
//!
//! `vigil measure` reports `vigil run`'s CPU, and on a virtual machine most of it can be the
//! price of being woken, not vigil's work. `--floor` starts this reader in `vigil run`'s place
//! (a hidden subcommand of the same executable, on the same terminals, with the same read
//! policy) and reports the same figures for it: the ports read on arrival (`read_interval_ms`
//! 0: the VN-200 and the Watson by default) are polled and read as their bytes arrive, the
//! paced ones drained on the shared grid of their interval, and every byte is thrown away. No
//! decode, no fusion, no publication (so no latency either).
//!
//! With `--bus-prefix` and `--vn200` (`vigil measure --floor-publish`) it is a latency floor as
//! well: the VN-200 port's bytes go through vigil's VN-200 decoder, and each binary message's
//! GPS time is published at once as an attitude sample (nothing else in it) on the prefix's
//! `vigil/attitude`, which `vigil measure` subscribes to and matches as it does `vigil run`'s.
//! Its latency is the terminal, one wake-up of a reader, a decode (about 0.1 us) and one
//! iceoryx2 publication with its event: the least a service woken by the terminal and
//! publishing over iceoryx2, as `vigil run` is, must do to hand a VN-200 message's time to a
//! subscriber in another process on this machine.
//!
//! Decision: a port read on arrival is read with `VMIN` 1 here, where `vigil run` raises `VMIN`
//! to a whole message once the stream is steady. With `VMIN` 1 this reader returns to user
//! space on every chunk, so at the default 1-64-byte reads it does more than the service's
//! kernel-only wake-ups (a plain reader's cost, not a floor under the service's); with
//! whole-message reads (`--max-chunk-bytes 4096`) the two are the same, one wake-up a message,
//! and its CPU is the floor under `vigil run`'s that no change inside vigil can remove.

use std::fs::File;
use std::io::{ErrorKind, Read};
use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result, anyhow, bail};
use bytes::BytesMut;
use clap::Args;
use tokio::time::Instant;
use vigil_bus::payload::attitude::AttitudePayload;
use vigil_bus::{Bus, BusConfig, Publisher};
use vigil_drivers::DeviceDecoder;
use vigil_drivers::vn200::{Vn200Decoder, Vn200Message};
use vigil_fusion::time::vn200::Vn200Times;
use vigil_service::runtime::reader::{READ_BYTES, next_on_grid};

/// Arguments of the hidden `vigil measure-floor` (started by `vigil measure --floor`).
#[derive(Debug, Args)]
pub struct FloorArgs {
    /// A port as MS:PATH: read every MS milliseconds on a shared grid, or as its bytes arrive
    /// when MS is 0 (repeatable).
    #[arg(long = "port", value_name = "MS:PATH", value_parser = parse_port, required = true)]
    pub ports: Vec<(f64, PathBuf)>,
    /// Publish on this bus prefix: each VN-200 binary message's GPS time as an attitude sample
    /// (the latency floor).
    #[arg(long, requires = "vn200")]
    pub bus_prefix: Option<String>,
    /// The VN-200's port (one of the `--port` paths, read on arrival) whose messages are
    /// decoded and published.
    #[arg(long, requires = "bus_prefix")]
    pub vn200: Option<PathBuf>,
}

/// Longest wait between two looks at iceoryx2's termination flag when publishing.
const SIGNAL_CHECK: Duration = Duration::from_millis(100);

/// The VN-200 side of the latency floor: vigil's decoder, and the publisher of the times.
struct Timer {
    decoder: Vn200Decoder,
    bytes: BytesMut,
    publisher: Publisher<AttitudePayload>,
}

impl Timer {
    /// Decodes what `chunk` completes and publishes each binary message's GPS time (a message
    /// without one is not published: `vigil run` would not fuse it at a GPS time either). The
    /// rest of the sample is its default: only `vigil measure`, on its own prefix, reads it.
    fn feed(&mut self, chunk: &[u8]) -> Result<()> {
        self.bytes.extend_from_slice(chunk);
        while let Some(m) = self.decoder.decode(&mut self.bytes) {
            let Vn200Message::Binary(o) = m else {
                continue;
            };
            if let Some(t) = Vn200Times::of(&o).time_gps_ns {
                self.publisher.publish_with(|p| p.header.gps_time_ns = t)?;
            }
        }
        Ok(())
    }
}

/// Parses MS:PATH.
fn parse_port(s: &str) -> Result<(f64, PathBuf), String> {
    let (ms, path) = s
        .split_once(':')
        .ok_or_else(|| format!("{s:?}: expected MS:PATH"))?;
    let ms: f64 = ms.parse().map_err(|e| format!("{ms:?}: {e}"))?;
    if !(ms.is_finite() && ms >= 0.0) {
        return Err(format!("{ms}: an interval is 0 or more milliseconds"));
    }
    Ok((ms, PathBuf::from(path)))
}

/// Opens a terminal raw and non-blocking, with `VMIN` 1 and `VTIME` 0 (as tokio-serial leaves
/// `vigil run`'s ports before its reader takes them).
fn open_raw(path: &PathBuf) -> Result<File> {
    use rustix::fs::{Mode, OFlags};
    use rustix::termios::{OptionalActions, SpecialCodeIndex, tcgetattr, tcsetattr};
    let fd = rustix::fs::open(
        path,
        OFlags::RDWR | OFlags::NOCTTY | OFlags::NONBLOCK | OFlags::CLOEXEC,
        Mode::empty(),
    )
    .with_context(|| format!("opening {}", path.display()))?;
    let mut t = tcgetattr(&fd).with_context(|| format!("{}: not a terminal", path.display()))?;
    t.make_raw();
    t.special_codes[SpecialCodeIndex::VMIN] = 1;
    t.special_codes[SpecialCodeIndex::VTIME] = 0;
    tcsetattr(&fd, OptionalActions::Now, &t)?;
    Ok(File::from(fd))
}

/// Reads `file` until it would block, handing each read to `sink` (when there is one); false
/// when it ended or failed.
fn drain(mut file: &File, buf: &mut [u8], mut sink: Option<&mut Timer>) -> Result<bool> {
    loop {
        match file.read(buf) {
            Ok(0) => return Ok(false),
            Ok(n) => {
                if let Some(timer) = sink.as_deref_mut() {
                    timer.feed(&buf[..n])?;
                }
                if n < buf.len() {
                    return Ok(true);
                }
            }
            Err(e) if e.kind() == ErrorKind::WouldBlock => return Ok(true),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(_) => return Ok(false),
        }
    }
}

/// Reads the ports until one of them ends or the process is stopped. Without a bus, SIGTERM's
/// default action ends it (there is nothing to clean up); with one, iceoryx2 catches SIGTERM and
/// the loop returns, so the bus's resources are released.
pub fn run(args: &FloorArgs) -> Result<()> {
    use rustix::event::{PollFd, PollFlags, Timespec, poll};
    let bus = match &args.bus_prefix {
        Some(prefix) => Some(
            Bus::new(&BusConfig {
                prefix: prefix.clone(),
                node_name: "vigil-measure-floor".to_string(),
                handle_signals: true,
                ..BusConfig::default()
            })
            .context("connecting to the bus")?,
        ),
        None => None,
    };
    let mut timer = match (&bus, &args.vn200) {
        (Some(bus), Some(path)) => {
            if !args.ports.iter().any(|(ms, p)| p == path && *ms == 0.0) {
                bail!(
                    "--vn200 {}: not one of the ports read on arrival",
                    path.display()
                );
            }
            Some(Timer {
                decoder: Vn200Decoder::default(),
                bytes: BytesMut::with_capacity(2 * READ_BYTES),
                publisher: bus.publisher::<AttitudePayload>()?,
            })
        }
        _ => None,
    };
    let mut arrival = Vec::new();
    let mut paced = Vec::new();
    for (ms, path) in &args.ports {
        let file = open_raw(path)?;
        if *ms == 0.0 {
            arrival.push((file, args.vn200.as_ref() == Some(path)));
        } else {
            paced.push((Duration::from_secs_f64(ms / 1000.0), file));
        }
    }
    // tokio's `Instant` (a std one inside): the grid is `vigil run`'s own `next_on_grid`.
    let epoch = Instant::now();
    // Each paced port's next drain: its interval's grid from one epoch, so ports with the same
    // interval are drained in one wake-up, as `vigil run` does.
    let mut next: Vec<Instant> = paced.iter().map(|(every, _)| epoch + *every).collect();
    let mut buf = vec![0u8; READ_BYTES];
    // Built once: `poll` rewrites each entry's returned events.
    let mut fds: Vec<PollFd<'_>> = arrival
        .iter()
        .map(|(f, _)| PollFd::new(f, PollFlags::IN))
        .collect();
    loop {
        if bus.as_ref().is_some_and(Bus::termination_requested) {
            return Ok(());
        }
        let now = Instant::now();
        for ((every, file), at) in paced.iter().zip(next.iter_mut()) {
            if *at <= now {
                if !drain(file, &mut buf, None)? {
                    bail!("a paced port ended");
                }
                // The next instant of the grid (missed ones are skipped).
                *at = next_on_grid(epoch, *every, now.max(*at + *every));
            }
        }
        let mut wait = next
            .iter()
            .min()
            .map(|at| at.saturating_duration_since(Instant::now()));
        // With a bus, at most 100 ms (whatever the paced intervals), so a SIGTERM caught by
        // iceoryx2 is seen soon even if it came between the check above and the poll.
        if bus.is_some() {
            wait = Some(wait.map_or(SIGNAL_CHECK, |w| w.min(SIGNAL_CHECK)));
        }
        let timeout = wait.map(|d| Timespec {
            tv_sec: d.as_secs() as _,
            tv_nsec: d.subsec_nanos() as _,
        });
        match poll(&mut fds, timeout.as_ref()) {
            Ok(_) | Err(rustix::io::Errno::INTR) => {}
            Err(e) => return Err(anyhow!("poll: {e}")),
        }
        for (p, (file, timed)) in fds.iter().zip(&arrival) {
            let sink = timer.as_mut().filter(|_| *timed);
            if !p.revents().is_empty() && !drain(file, &mut buf, sink)? {
                bail!("a port read on arrival ended");
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ports_parse_as_interval_and_path() {
        assert_eq!(
            parse_port("10:/tmp/x/bahrs").unwrap(),
            (10.0, PathBuf::from("/tmp/x/bahrs"))
        );
        // Only the first colon separates: a path may hold more.
        assert_eq!(parse_port("0:/a:b").unwrap(), (0.0, PathBuf::from("/a:b")));
        for bad in ["/tmp/x", "x:/p", "-1:/p", "inf:/p", "NaN:/p"] {
            assert!(parse_port(bad).is_err(), "{bad}");
        }
    }
}
