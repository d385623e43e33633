//! Reading an open serial port after its set-up: every byte once, as few wake-ups as possible.
//!
//! A port is opened and set up with tokio-serial ([`crate::runtime::setup`] needs its async reads, writes
//! and baud changes); then its descriptor is detached ([`detach`]) and read here in one of two
//! ways:
//!
//! - **On arrival** ([`read_on_arrival`]), for the latency-critical ports (the VN-200 always):
//!   each readiness event gives one `read(2)`. A read shorter than the buffer has emptied the
//!   line discipline (`n_tty_read` copies everything available and flushes the pending receive
//!   work first), so the readiness is cleared at once instead of learning it from a second read
//!   that fails with `EAGAIN`: one system call per chunk instead of two. Clearing is safe against
//!   a racing arrival: tokio clears only if no newer readiness event was seen, and a byte that
//!   arrives after the read raises a new edge-triggered epoll event anyway.
//! - **Paced** ([`read_paced`]), for ports whose samples tolerate a bounded wait (the TT-Multi-RF
//!   and the BAHRS by default): the descriptor is not registered with epoll at all, so arriving
//!   bytes wake nobody, and it is drained every `interval`, on a grid shared by every paced port
//!   (multiples of the interval from one epoch), so ports with the same interval are drained in
//!   the same wake-up. At full rates this removes ~3200 wake-ups a second. Each chunk is
//!   stamped with the drain time; the aligner adds the wait (uniform over the interval) to the
//!   host-timed samples' delay and sigma
//!   ([`vigil_fusion::time::host_timed::HostTimedLink::with_read_interval`]).

use std::fs::File;
use std::io::{ErrorKind, Read};
use std::os::fd::AsFd;
use std::time::Duration;

use tokio::io::Interest;
use tokio::io::unix::AsyncFd;
use tokio::time::Instant;
use tokio_serial::SerialStream;
use vigil_bus::clock::monotonic_ns;

/// Largest read, bytes: the Linux line discipline's whole buffer (`N_TTY_BUF_SIZE`).
pub const READ_BYTES: usize = 4096;

/// The port's descriptor, taken from its tokio-serial stream (which is dropped: it deregisters
/// its own descriptor from epoll and closes it; the duplicate keeps the line open, so its
/// settings, baud rate included, stay and nothing is hung up). The stream's exclusive-use flag
/// (`TIOCEXCL`), which its drop releases, is set again on the duplicate.
pub fn detach(serial: SerialStream) -> std::io::Result<File> {
    let fd = {
        use std::os::fd::AsRawFd;
        let raw = serial.as_raw_fd();
        // SAFETY: `raw` is the stream's open descriptor and the stream outlives this borrow,
        // which only duplicates it (tokio-serial offers no `AsFd`).
        let borrowed = unsafe { std::os::fd::BorrowedFd::borrow_raw(raw) };
        borrowed.try_clone_to_owned()?
    };
    drop(serial);
    // Best effort, like tokio-serial's own: a device that refuses it is still read.
    let _ = rustix::termios::ioctl_tiocexcl(fd.as_fd());
    Ok(File::from(fd))
}

/// The line discipline's `VMIN` of a port read on arrival (issue 21): how many bytes must be
/// waiting before the port reports itself readable.
///
/// With `VTIME` 0, a non-blocking descriptor polls readable only once `VMIN` bytes are waiting
/// (`n_tty_poll`). Each USB packet still wakes the thread inside the kernel (the line discipline
/// wakes its pollers on every arrival), but only to find the port not yet readable: the
/// process returns to user space, reads and processes once per message instead of once per
/// packet.
struct Vmin {
    /// The value set now (1 when the port opened: any byte makes it readable).
    now: u8,
    /// Time of the last read, host monotonic ns, and the interval between the last two reads
    /// made with `VMIN` above 1 (the message period), ns.
    last_read_ns: Option<u64>,
    period_ns: Option<u64>,
}

impl Vmin {
    /// Longest wait for a whole message before the port is read anyway, ns: 1.5 message periods
    /// (10 ms before a period is known), at least 1 ms (the timer's resolution), at most 100 ms.
    fn patience_ns(&self) -> u64 {
        self.period_ns
            .map_or(10_000_000, |p| p + p / 2)
            .clamp(1_000_000, 100_000_000)
    }

    /// Sets `VMIN` to `want` (clamped to 1..=255, the field's range; longer messages are read as
    /// they arrive). Returns false when the port refused (it is then read as it arrives).
    fn set(&mut self, file: &File, want: usize) -> bool {
        let v = u8::try_from(want).ok().filter(|v| *v > 0).unwrap_or(1);
        if v == self.now {
            return true;
        }
        let ok = rustix::termios::tcgetattr(file).and_then(|mut t| {
            t.special_codes[rustix::termios::SpecialCodeIndex::VMIN] = v;
            t.special_codes[rustix::termios::SpecialCodeIndex::VTIME] = 0;
            rustix::termios::tcsetattr(file, rustix::termios::OptionalActions::Now, &t)
        });
        if ok.is_ok() {
            self.now = v;
        }
        ok.is_ok()
    }

    /// A read happened at `t` ns with `VMIN` as it was.
    fn read_at(&mut self, t: u64) {
        if let Some(last) = self.last_read_ns
            && self.now > 1
        {
            self.period_ns = Some(t.saturating_sub(last));
        }
        self.last_read_ns = Some(t);
    }
}

/// Reads `file` as its bytes arrive, handing each chunk with its host monotonic read time (ns)
/// to `chunk`, until the port fails or ends; returns why.
///
/// `chunk` returns how many more bytes complete the next message when the port's stream is a
/// steady run of messages of one length
/// ([`vigil_fusion::ingest::Ingest::bytes_until_whole_message`]; when the read ended on a message
/// boundary, a whole message's length): the port is then made readable only once that many bytes
/// wait ([`Vmin`]), so a message costs one return to user space however many USB packets carry
/// it, even when a late wake-up read the start of the next message with the last one. The read,
/// and so the message's receive time, is the moment its last byte arrived, as before.
///
/// Decision: a message of another length (shorter: it never reaches `VMIN`) would wait for the
/// next one. The wait is bounded: after 1.5 message periods without a read the port is read
/// anyway and `VMIN` goes back to 1; such a message is stamped late by at most that, once, and
/// the stream is read as it arrives until it is steady again (eight messages of one length; a
/// wait that ran out only because the device paused keeps the run, and `VMIN` is set again
/// after the next read).
/// The VN-200's messages carry their GPS time; the late stamp only feeds the host clock fit one
/// high-delay point.
pub async fn read_on_arrival(
    file: File,
    mut chunk: impl FnMut(u64, &[u8]) -> Option<usize>,
) -> String {
    // SAFETY: the `File` owns its open descriptor and is moved into the `AsyncFd`, which keeps
    // it (same descriptor, same open file description) until it is dropped.
    let afd = match unsafe { AsyncFd::register_with_interest(file, Interest::READABLE) } {
        Ok(a) => a,
        Err(e) => return format!("cannot poll: {e}"),
    };
    let mut vmin = Vmin {
        now: 0,
        last_read_ns: None,
        period_ns: None,
    };
    if !vmin.set(afd.get_ref(), 1) {
        // Not a terminal (a test's pipe, say): read as the bytes arrive, with no VMIN.
        vmin.now = 1;
    }
    let mut buf = vec![0u8; READ_BYTES];
    loop {
        let mut guard = if vmin.now > 1 {
            let patience = Duration::from_nanos(vmin.patience_ns());
            match tokio::time::timeout(patience, afd.readable()).await {
                Ok(Ok(g)) => g,
                Ok(Err(e)) => return e.to_string(),
                Err(_) => {
                    // No whole message in time: read what waits (setting VMIN to 1 wakes the
                    // port's pollers, so it is reported readable if a byte waits).
                    vmin.set(afd.get_ref(), 1);
                    continue;
                }
            }
        } else {
            match afd.readable().await {
                Ok(g) => g,
                Err(e) => return e.to_string(),
            }
        };
        // One chunk: what waits, in as many reads as it takes. With VMIN above 1 the line
        // discipline hands at most 64 bytes per read(2) (Linux 6: the tty layer copies through a
        // 64-byte kernel buffer and non-canonical reads do not continue), so the port is read
        // until it would block; with VMIN 1 one read takes everything (see the module
        // documentation) unless it fills the buffer.
        let (mut filled, mut t, mut drained) = (0, 0, false);
        let end = loop {
            match guard.try_io(|f| f.get_ref().read(&mut buf[filled..])) {
                Ok(Ok(0)) => break Some("end of file".to_string()),
                Ok(Ok(n)) => {
                    if filled == 0 {
                        t = monotonic_ns();
                    }
                    filled += n;
                    if filled == buf.len() {
                        break None;
                    }
                    if vmin.now <= 1 {
                        drained = true;
                        break None;
                    }
                }
                Ok(Err(e)) if e.kind() == ErrorKind::Interrupted => {}
                Ok(Err(e)) => break Some(e.to_string()),
                // Would block: `try_io` cleared the readiness; wait for the next event.
                Err(_) => break None,
            }
        };
        if drained {
            // Drained (see the module documentation).
            guard.clear_ready();
        }
        drop(guard);
        if filled > 0 {
            vmin.read_at(t);
            let want = chunk(t, &buf[..filled]).unwrap_or(1);
            if !vmin.set(afd.get_ref(), want) {
                vmin.set(afd.get_ref(), 1);
            }
        }
        if let Some(why) = end {
            return why;
        }
    }
}

/// The first instant at or after `now` on the grid `epoch + k interval` (k = 0, 1, ...).
pub fn next_on_grid(epoch: Instant, interval: Duration, now: Instant) -> Instant {
    let step = interval.as_nanos().max(1);
    let since = now.saturating_duration_since(epoch).as_nanos();
    let k = since.div_ceil(step);
    epoch + Duration::from_nanos(u64::try_from(k * step).unwrap_or(u64::MAX))
}

/// Drains `file` every `interval` on the grid from `epoch` (see the module documentation),
/// handing each chunk with its host monotonic read time (ns) to `chunk`, until the port fails or
/// ends; returns why.
pub async fn read_paced(
    mut file: File,
    interval: Duration,
    epoch: Instant,
    mut chunk: impl FnMut(u64, &[u8]),
) -> String {
    let mut tick =
        tokio::time::interval_at(next_on_grid(epoch, interval, Instant::now()), interval);
    // After a late drain, the next one is back on the grid (shared with the other paced ports).
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Skip);
    let mut buf = vec![0u8; READ_BYTES];
    loop {
        tick.tick().await;
        loop {
            match file.read(&mut buf) {
                Ok(0) => return "end of file".to_string(),
                Ok(n) => {
                    chunk(monotonic_ns(), &buf[..n]);
                    if n < buf.len() {
                        break;
                    }
                }
                Err(e) if e.kind() == ErrorKind::WouldBlock => break,
                Err(e) if e.kind() == ErrorKind::Interrupted => {}
                Err(e) => return e.to_string(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;
    use std::os::fd::OwnedFd;

    /// A pseudo-terminal pair: (master, slave opened as a raw, non-blocking serial port).
    fn pty() -> (File, SerialStream) {
        use rustix::fs::{Mode, OFlags};
        use rustix::pty::{OpenptFlags, grantpt, openpt, ptsname, unlockpt};
        let master: OwnedFd =
            openpt(OpenptFlags::RDWR | OpenptFlags::NOCTTY | OpenptFlags::CLOEXEC).unwrap();
        grantpt(&master).unwrap();
        unlockpt(&master).unwrap();
        let name = ptsname(&master, Vec::new()).unwrap();
        let path = name.to_string_lossy().into_owned();
        let _ = rustix::fs::open(&path, OFlags::RDWR | OFlags::NOCTTY, Mode::empty());
        let serial = tokio_serial::SerialPortBuilderExt::open_native_async(tokio_serial::new(
            &path, 115_200,
        ))
        .unwrap();
        (File::from(master), serial)
    }

    fn rt() -> tokio::runtime::Runtime {
        tokio::runtime::Builder::new_current_thread()
            .enable_all()
            .build()
            .unwrap()
    }

    /// The bytes written in pieces, with pauses, come back whole and in order, and the readers
    /// end with the reason when the other side closes.
    fn round_trip(paced: Option<Duration>) -> (Vec<u8>, usize, String) {
        rt().block_on(async {
            let (mut master, serial) = pty();
            let file = detach(serial).unwrap();
            // 10 000 bytes in 1..=700-byte writes (more than one read buffer at times).
            let data: Vec<u8> = (0..10_000u32).map(|i| (i * 7 + i / 13) as u8).collect();
            let expected = data.clone();
            let writer = tokio::spawn(async move {
                let mut at = 0;
                let mut k = 1usize;
                while at < data.len() {
                    let n = (k * 97 % 700 + 1).min(data.len() - at);
                    master.write_all(&data[at..at + n]).unwrap();
                    at += n;
                    k += 1;
                    tokio::time::sleep(Duration::from_micros(300)).await;
                }
                tokio::time::sleep(Duration::from_millis(50)).await;
                drop(master);
            });
            let mut got = Vec::new();
            let mut chunks = 0;
            let mut last_t = 0;
            let push = |t: u64, b: &[u8]| {
                assert!(t >= last_t, "read times go forward");
                last_t = t;
                got.extend_from_slice(b);
                chunks += 1;
            };
            let why = match paced {
                Some(d) => read_paced(file, d, Instant::now(), push).await,
                None => {
                    let mut push = push;
                    read_on_arrival(file, |t, b| {
                        push(t, b);
                        None
                    })
                    .await
                }
            };
            writer.await.unwrap();
            assert_eq!(got.len(), expected.len());
            assert!(got == expected, "bytes differ");
            (got, chunks, why)
        })
    }

    #[test]
    fn on_arrival_reads_every_byte_in_order_then_reports_the_hang_up() {
        let (_, chunks, why) = round_trip(None);
        assert!(chunks > 1);
        // A pty slave whose master closed reads EIO (some kernels: end of file).
        assert!(
            why.contains("Input/output error") || why == "end of file",
            "{why}"
        );
    }

    #[test]
    fn paced_reads_every_byte_in_order_in_fewer_chunks() {
        let (_, arrival_chunks, _) = round_trip(None);
        let (_, paced_chunks, why) = round_trip(Some(Duration::from_millis(20)));
        // ~130 writes over ~60 ms (with sleeps of at least 0.3 ms): drains every 20 ms
        // take several writes each.
        assert!(
            paced_chunks < arrival_chunks,
            "paced {paced_chunks} vs on arrival {arrival_chunks}"
        );
        assert!(
            why.contains("Input/output error") || why == "end of file",
            "{why}"
        );
    }

    /// Messages of `len` bytes written in `pieces` writes each, 300 us apart, one message every
    /// 3 ms, `count` of them, the other side closed 60 ms after the last; the reader asks for
    /// whole messages of `want` bytes (`None`: as they arrive). Returns the bytes read, the
    /// number of reads, and by how much the last read came before the close, ns.
    fn messages_in_pieces(
        len: usize,
        pieces: usize,
        count: usize,
        want: Option<usize>,
    ) -> (Vec<u8>, usize, i64) {
        rt().block_on(async {
            let (mut master, serial) = pty();
            let file = detach(serial).unwrap();
            let data: Vec<u8> = (0..len * count).map(|i| (i % 251) as u8).collect();
            let expected = data.clone();
            // Its own thread: the reader runs on this one.
            let writer = std::thread::spawn(move || {
                for m in data.chunks(len) {
                    for p in m.chunks(len.div_ceil(pieces)) {
                        master.write_all(p).unwrap();
                        std::thread::sleep(Duration::from_micros(300));
                    }
                    std::thread::sleep(Duration::from_millis(3));
                }
                std::thread::sleep(Duration::from_millis(60));
                let closed = monotonic_ns();
                drop(master);
                closed
            });
            let (mut got, mut reads, mut last) = (Vec::new(), 0, 0);
            read_on_arrival(file, |t, b| {
                got.extend_from_slice(b);
                reads += 1;
                last = t;
                want
            })
            .await;
            let closed = writer.join().unwrap();
            assert!(got == expected, "bytes differ or missing");
            (got, reads, closed as i64 - last as i64)
        })
    }

    #[test]
    fn whole_messages_take_one_read_each() {
        // 30 messages of 100 bytes, 4 writes each: read as they arrive, about 4 reads a message;
        // with VMIN at 100, one chunk (the first, before VMIN is set, may be a piece alone),
        // although the kernel hands it over in 64-byte reads. A writer that stalls mid-message
        // for longer than the reader's patience (10 ms) splits that message in two: on a loaded
        // machine that happens a few times (34 reads once, with the whole suite built at
        // opt-level 0 running beside this test), so the bound leaves room for about ten stalls,
        // still far below the 60 or more of reads as the pieces arrive.
        let (_, per_piece, _) = messages_in_pieces(100, 4, 30, None);
        let (_, whole, _) = messages_in_pieces(100, 4, 30, Some(100));
        assert!(per_piece >= 60, "{per_piece} reads as the pieces arrive");
        assert!(whole <= 40, "{whole} reads for 30 whole messages");
    }

    #[test]
    fn a_shorter_message_than_vmin_is_still_read() {
        // The reader waits for 64 bytes, the messages have 40: each is read with the next one
        // or after the patience (10 ms before a period is known; then back to VMIN 1, whose
        // change wakes the port's poller). Nothing is lost, and the last message is read by
        // the patience, well before the other side closes 60 ms later (not by the hang-up).
        let (got, _, before_close) = messages_in_pieces(40, 2, 10, Some(64));
        assert_eq!(got.len(), 400);
        assert!(
            before_close > 30_000_000,
            "last read {before_close} ns before the close"
        );
    }

    #[test]
    fn paced_ports_share_one_grid() {
        let epoch = Instant::now();
        let ms = Duration::from_millis;
        // 10 ms grid: at 0 -> 0; at 3 ms -> 10 ms; at 10 ms -> 10 ms; at 25 ms -> 30 ms.
        assert_eq!(next_on_grid(epoch, ms(10), epoch), epoch);
        assert_eq!(next_on_grid(epoch, ms(10), epoch + ms(3)), epoch + ms(10));
        assert_eq!(next_on_grid(epoch, ms(10), epoch + ms(10)), epoch + ms(10));
        assert_eq!(next_on_grid(epoch, ms(10), epoch + ms(25)), epoch + ms(30));
    }

    #[test]
    fn a_detached_port_keeps_its_line_open() {
        // (Its TIOCEXCL is not checked here: root, as in CI, opens an exclusive tty anyway.)
        rt().block_on(async {
            let (mut master, serial) = pty();
            let file = detach(serial).unwrap();
            master.write_all(b"abc").unwrap();
            let mut got = Vec::new();
            let reader = read_on_arrival(file, |_, b| {
                got.extend_from_slice(b);
                None
            });
            let _ = tokio::time::timeout(Duration::from_millis(200), reader).await;
            assert_eq!(got, b"abc");
        });
    }
}
