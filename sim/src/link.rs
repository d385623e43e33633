//! Serial link model: a device's bytes leave at its baud rate (10 bits per byte, 8N1) and reach the
//! host in read chunks after an OS/USB latency; link faults damage or lose bytes on the way.
//!
//! - A message starts when it is ready and the line is free; byte `i` has fully arrived at the
//!   adapter `(i + 1) x 10 / baud` s after the start.
//! - The host read returns chunks of 1 ..= `max_chunk_bytes` bytes (uniform; with `full_chunks`,
//!   always `max_chunk_bytes`, as a USB adapter sending full packets). A chunk ends early
//!   when the line goes idle (a gap before the next message), as a USB adapter flushes on idle.
//!   Its receive time is the host-clock time of its last byte plus a latency uniform in
//!   `latency_ms +- latency_jitter_ms`, never earlier than the previous chunk of the same port.
//! - Faults: a bit error flips one random bit of a byte (probability `1 - (1 - rate)^10` per byte);
//!   a dropped byte and every byte sent during a link loss never reach the host; they all still
//!   take their time on the line. A message with any such byte is marked corrupted in the truth.
//! - An FTDI adapter (`host.ftdi_latency_timer_ms` names the port; issue 18) sends a USB packet
//!   of [`FTDI_PACKET_BYTES`] when it is full, else when its latency timer runs out: the timer
//!   restarts at every packet sent, and a partial packet goes out at the first expiry after its
//!   first byte (a sparse port's message tail waits up to the timer; a dense one fills packets).
//!   The host receives a packet after the configured latency (the USB poll and the OS).
//! - A native UART or a USB CDC bridge (`host.adapters`; issue 18 point 1): see [`Adapter`]'s
//!   variants (FIFO-trigger reads and the FIFO timeout; 64-byte packets on the 1 ms USB frame).
//! - A device holds at most [`TX_BUFFER_BYTES`] unsent bytes: a message that does not fit (the
//!   configured output exceeds the baud rate) is discarded by the device and marked corrupted
//!   (it never reaches the host).

use crate::device::{Emission, FaultSchedule};
use crate::rng::Rng;
use crate::scenario::{Adapter, HostConfig};

/// Transmit buffer of a device, bytes.
pub const TX_BUFFER_BYTES: f64 = 4096.0;

/// Data bytes of an FTDI full-speed USB packet (64 bytes less 2 status bytes).
pub const FTDI_PACKET_BYTES: usize = 62;

/// Host monotonic clock: `t_host = offset + (t_gps - start) (1 + drift)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostClock {
    /// GPS time of the scenario start, ns.
    pub start_gps_ns: i64,
    /// Host monotonic time at the scenario start, ns.
    pub offset_ns: u64,
    /// Drift against GPS time (fraction).
    pub drift: f64,
}

impl HostClock {
    /// Host monotonic time of a GPS time, ns (saturating at 0).
    pub fn host_ns(&self, t_gps_ns: i64) -> u64 {
        self.host_ns_since_start((t_gps_ns - self.start_gps_ns) as f64)
    }

    /// Host monotonic time of a GPS time given in ns since the scenario start, ns. Decision: link
    /// timing is computed in f64 ns relative to the start (exact to well below 1 ns over days);
    /// absolute GPS ns in f64 would be quantised to 256 ns.
    pub fn host_ns_since_start(&self, since_start_ns: f64) -> u64 {
        let dt = since_start_ns * (1.0 + self.drift);
        (self.offset_ns as f64 + dt).round().max(0.0) as u64
    }
}

/// A chunk of bytes as one host read returns it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Chunk {
    /// Port index (order of the simulator's ports).
    pub port: u16,
    /// Host monotonic receive time, ns.
    pub t_host_ns: u64,
    /// The bytes.
    pub bytes: Vec<u8>,
}

/// What happened to one message on the link.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transmission {
    /// GPS time its first byte started on the wire, ns.
    pub t_tx_gps_ns: i64,
    /// A fault damaged or lost at least one of its bytes.
    pub corrupted: bool,
    /// Offset in the port's received byte stream at which the message's first byte arrived (or
    /// would have, had it been lost): the join key between truth and a decoder's `Located.offset`.
    pub rx_offset: u64,
}

struct OpenChunk {
    bytes: Vec<u8>,
    target: usize,
    /// Completion of the last byte, ns since the scenario start.
    last_done_ns: f64,
}

/// The link of one port.
pub struct Link {
    device: &'static str,
    port: u16,
    byte_ns: f64,
    start_gps_ns: i64,
    /// When the line is free again, ns since the scenario start.
    line_free_ns: f64,
    host: HostConfig,
    rng: Rng,
    last_host_ns: u64,
    open: Option<OpenChunk>,
    rx_bytes: u64,
    /// FTDI latency timer, ns, if the port is behind one.
    ftdi_timer_ns: Option<f64>,
    /// FTDI: when the latency timer last restarted (a packet sent), ns since the start.
    ftdi_restart_ns: f64,
    /// FTDI: when the open packet goes out if it does not fill first, ns since the start.
    ftdi_flush_ns: f64,
    /// Another named adapter, if the port is behind one.
    adapter: Option<Adapter>,
}

/// Native UART: bytes per read (the receive FIFO's trigger level).
pub const UART_FIFO_TRIGGER_BYTES: usize = 8;
/// Native UART: a partial FIFO is read this many character times after its last byte.
pub const UART_TIMEOUT_CHARS: f64 = 4.0;
/// USB CDC: bytes per full-speed bulk packet.
pub const CDC_PACKET_BYTES: usize = 64;
/// USB CDC: the full-speed frame period, ns.
pub const CDC_FRAME_NS: f64 = 1e6;

impl Link {
    /// The link of `device` on port index `port`.
    pub fn new(
        device: &'static str,
        port: u16,
        baud: u32,
        host: &HostConfig,
        start_gps_ns: i64,
        seed: u64,
    ) -> Self {
        Self {
            device,
            port,
            byte_ns: 10.0e9 / f64::from(baud.max(1)),
            start_gps_ns,
            line_free_ns: f64::MIN,
            host: host.clone(),
            rng: Rng::stream(seed, &format!("link/{device}")),
            last_host_ns: 0,
            open: None,
            rx_bytes: 0,
            ftdi_timer_ns: host.ftdi_latency_timer_ms.get(device).map(|ms| ms * 1e6),
            ftdi_restart_ns: 0.0,
            ftdi_flush_ns: f64::MAX,
            adapter: host.adapters.get(device).copied(),
        }
    }

    /// FTDI: the timer expiry that sends a packet whose first byte arrived at `t` (ns since the
    /// start): the first expiry after it, on the grid restarted by the last packet.
    fn ftdi_expiry_after(&self, timer: f64, t: f64) -> f64 {
        let k = ((t - self.ftdi_restart_ns) / timer).floor() + 1.0;
        self.ftdi_restart_ns + k.max(1.0) * timer
    }

    /// FTDI: sends the open packet at its timer expiry if that is before `t` (ns since start).
    fn ftdi_flush_before(&mut self, t: f64, clock: &HostClock, out: &mut Vec<Chunk>) {
        if self.open.is_some() && self.ftdi_flush_ns <= t {
            let at = self.ftdi_flush_ns;
            self.send(at, clock, out);
        }
    }

    /// Sends one message: appends the chunks that complete to `out`.
    pub fn transmit(
        &mut self,
        e: &Emission,
        faults: &FaultSchedule,
        clock: &HostClock,
        out: &mut Vec<Chunk>,
    ) -> Transmission {
        let ready = (e.t_ready_gps_ns - self.start_gps_ns) as f64;
        let backlog_bytes = ((self.line_free_ns - ready) / self.byte_ns).max(0.0);
        if backlog_bytes + e.bytes.len() as f64 > TX_BUFFER_BYTES {
            return Transmission {
                t_tx_gps_ns: e.t_ready_gps_ns,
                corrupted: true,
                rx_offset: self.rx_bytes,
            };
        }
        let start = ready.max(self.line_free_ns);
        if self.ftdi_timer_ns.is_none() && start > self.line_free_ns + 0.5 * self.byte_ns {
            // The line was idle: the adapter has flushed what it held.
            self.close(clock, out);
        }
        let mut corrupted = false;
        let rx_offset = self.rx_bytes;
        let t0_s = start * 1e-9;
        let ber = faults.bit_error_rate(self.device, t0_s);
        let drop = faults.drop_rate(self.device, t0_s);
        let p_byte_error = 1.0 - (1.0 - ber).powi(10);
        for (i, &b) in e.bytes.iter().enumerate() {
            let done = start + (i + 1) as f64 * self.byte_ns;
            let t_s = t0_s + (i + 1) as f64 * self.byte_ns * 1e-9;
            if faults.link_lost(self.device, t_s) || self.rng.chance(drop) {
                corrupted = true;
                continue;
            }
            let mut byte = b;
            if self.rng.chance(p_byte_error) {
                byte ^= 1 << (self.rng.next_u64() % 8);
                corrupted = true;
            }
            if let Some(timer) = self.ftdi_timer_ns {
                self.ftdi_flush_before(done, clock, out);
                if self.open.is_none() {
                    self.ftdi_flush_ns = self.ftdi_expiry_after(timer, done);
                }
            }
            let ftdi = self.ftdi_timer_ns.is_some();
            let open = self.open.get_or_insert_with(|| OpenChunk {
                bytes: Vec::new(),
                target: 0,
                last_done_ns: done,
            });
            if open.target == 0 {
                open.target = if ftdi {
                    FTDI_PACKET_BYTES
                } else if self.adapter == Some(Adapter::NativeUart) {
                    UART_FIFO_TRIGGER_BYTES
                } else if self.adapter == Some(Adapter::UsbCdc) {
                    CDC_PACKET_BYTES
                } else if self.host.full_chunks {
                    self.host.max_chunk_bytes as usize
                } else {
                    self.rng.one_to(self.host.max_chunk_bytes) as usize
                };
            }
            open.bytes.push(byte);
            self.rx_bytes += 1;
            open.last_done_ns = done;
            if open.bytes.len() >= open.target {
                if ftdi {
                    self.send(done, clock, out);
                } else {
                    self.close(clock, out);
                }
            }
        }
        self.line_free_ns = start + e.bytes.len() as f64 * self.byte_ns;
        Transmission {
            t_tx_gps_ns: self.start_gps_ns + start.round() as i64,
            corrupted,
            rx_offset,
        }
    }

    /// The end of a simulation window at `until_ns` (ns since the start): ends the open chunk,
    /// except on an FTDI port whose packet's timer expires later (more bytes may join it).
    pub fn end_window(&mut self, until_ns: f64, clock: &HostClock, out: &mut Vec<Chunk>) {
        match self.ftdi_timer_ns {
            Some(_) => self.ftdi_flush_before(until_ns, clock, out),
            None => self.close(clock, out),
        }
    }

    /// The end of the run: sends whatever the port still holds.
    pub fn finish(&mut self, clock: &HostClock, out: &mut Vec<Chunk>) {
        match self.ftdi_timer_ns {
            Some(_) => self.ftdi_flush_before(f64::MAX, clock, out),
            None => self.close(clock, out),
        }
    }

    /// FTDI: the open packet leaves the adapter at `at_ns` (ns since start); the timer restarts.
    fn send(&mut self, at_ns: f64, clock: &HostClock, out: &mut Vec<Chunk>) {
        if let Some(open) = self.open.as_mut() {
            open.last_done_ns = at_ns;
        }
        self.ftdi_restart_ns = at_ns;
        self.ftdi_flush_ns = f64::MAX;
        self.close(clock, out);
    }

    /// Ends the open chunk (if any) and appends it to `out`.
    pub fn close(&mut self, clock: &HostClock, out: &mut Vec<Chunk>) {
        let Some(open) = self.open.take() else { return };
        if open.bytes.is_empty() {
            return;
        }
        let jitter = self.rng.range(-1.0, 1.0);
        let partial = open.bytes.len() < open.target;
        let (ready_ns, lat_ms) = match self.adapter {
            Some(Adapter::NativeUart) => (
                open.last_done_ns
                    + if partial {
                        UART_TIMEOUT_CHARS * self.byte_ns
                    } else {
                        0.0
                    },
                0.1 + 0.05 * jitter,
            ),
            Some(Adapter::UsbCdc) => (
                ((open.last_done_ns / CDC_FRAME_NS).floor() + 1.0) * CDC_FRAME_NS,
                0.2 + 0.1 * jitter,
            ),
            None => (
                open.last_done_ns,
                self.host.latency_ms + jitter * self.host.latency_jitter_ms,
            ),
        };
        let t = clock
            .host_ns_since_start(ready_ns + lat_ms.max(0.0) * 1e6)
            .max(self.last_host_ns);
        self.last_host_ns = t;
        out.push(Chunk {
            port: self.port,
            t_host_ns: t,
            bytes: open.bytes,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::magnetic::Wmm2025;
    use crate::scenario::{Fault, builtin};
    use crate::truth::World;

    fn setup(faults: Vec<Fault>) -> (World, FaultSchedule, HostClock) {
        let s = builtin("headon").unwrap();
        let w = World::new(&s, Box::new(Wmm2025)).unwrap();
        let clock = HostClock {
            start_gps_ns: w.start_gps_ns,
            offset_ns: 5_000_000_000,
            drift: 0.0,
        };
        (w, FaultSchedule::new(&faults), clock)
    }

    fn emission(t: i64, n: usize) -> Emission {
        Emission {
            t_ready_gps_ns: t,
            bytes: (0..n).map(|i| i as u8).collect(),
            kind: "test",
            t_gps_ns: t,
            values: Default::default(),
        }
    }

    #[test]
    fn bytes_are_paced_at_the_baud_rate_and_arrive_after_the_latency() {
        let (w, f, clock) = setup(vec![]);
        let host = HostConfig {
            max_chunk_bytes: 16,
            ..HostConfig::default()
        };
        let mut link = Link::new("watson", 0, 9600, &host, w.start_gps_ns, 1);
        let mut out = Vec::new();
        let t0 = w.start_gps_ns + 1_000_000_000;
        let tx = link.transmit(&emission(t0, 64), &f, &clock, &mut out);
        // A second message ready while the line is busy waits for it: 64 bytes x 10 bits / 9600
        // baud = 66.667 ms.
        let tx2 = link.transmit(&emission(t0 + 10_000_000, 10), &f, &clock, &mut out);
        link.close(&clock, &mut out);
        assert_eq!(tx.t_tx_gps_ns, t0);
        assert_eq!(tx2.t_tx_gps_ns, t0 + 66_666_667);
        assert_eq!((tx.rx_offset, tx2.rx_offset), (0, 64));
        let all: Vec<u8> = out.iter().flat_map(|c| c.bytes.clone()).collect();
        assert_eq!(all.len(), 74);
        assert_eq!(&all[..64], &emission(0, 64).bytes[..]);
        assert!(out.iter().all(|c| (1..=16).contains(&c.bytes.len())));
        assert!(out.windows(2).all(|p| p[0].t_host_ns <= p[1].t_host_ns));
        // The last byte of the second message is complete at 74 x 1.041667 ms = 77.083 ms after
        // t0; the host sees it 0.5 .. 1.5 ms later. Host time at t0 is 6 s (offset 5 s + 1 s).
        let last = out.last().unwrap().t_host_ns as f64 - 6.0e9;
        assert!((77.583e6..=78.584e6).contains(&last), "{last}");
    }

    #[test]
    fn full_chunks_are_whole_packets_but_for_the_one_the_idle_line_ends() {
        let (w, f, clock) = setup(vec![]);
        let host = HostConfig {
            max_chunk_bytes: 62,
            full_chunks: true,
            ..HostConfig::default()
        };
        let mut link = Link::new("vn200", 0, 921_600, &host, w.start_gps_ns, 1);
        let mut out = Vec::new();
        let t0 = w.start_gps_ns + 1_000_000_000;
        // 150 bytes, then 100 bytes 2.5 ms later (the line idle in between): 62 + 62 + 26, then
        // 62 + 38.
        link.transmit(&emission(t0, 150), &f, &clock, &mut out);
        link.transmit(&emission(t0 + 2_500_000, 100), &f, &clock, &mut out);
        link.close(&clock, &mut out);
        let sizes: Vec<usize> = out.iter().map(|c| c.bytes.len()).collect();
        assert_eq!(sizes, [62, 62, 26, 62, 38]);
    }

    #[test]
    fn bit_errors_at_the_configured_rate_and_link_loss_loses_bytes() {
        let faults = vec![
            Fault::BitErrors {
                device: "bahrs".into(),
                from_s: 0.0,
                to_s: None,
                rate: 1e-3,
            },
            Fault::LinkLoss {
                device: "bahrs".into(),
                from_s: 100.0,
                to_s: Some(101.0),
            },
        ];
        let (w, f, clock) = setup(faults);
        let mut link = Link::new(
            "bahrs",
            0,
            1_000_000,
            &HostConfig::default(),
            w.start_gps_ns,
            2,
        );
        let mut out = Vec::new();
        // 200 messages of 1000 bytes, 10 ms each at 1 Mbaud, starting at 1 s: 1 .. 3 s.
        let mut corrupted = 0;
        for k in 0..200 {
            let tx = link.transmit(
                &emission(w.start_gps_ns + 1_000_000_000 + k * 10_000_000, 1000),
                &f,
                &clock,
                &mut out,
            );
            corrupted += usize::from(tx.corrupted);
        }
        link.close(&clock, &mut out);
        let got: Vec<u8> = out.iter().flat_map(|c| c.bytes.clone()).collect();
        let sent: Vec<u8> = (0..200).flat_map(|_| (0..1000).map(|i| i as u8)).collect();
        let flipped = got.iter().zip(&sent).filter(|(a, b)| a != b).count();
        // Expected 200 000 x (1 - 0.999^10) = 1991 damaged bytes (sd about 44).
        assert!((1800..2200).contains(&flipped), "{flipped}");
        // Every damaged byte differs in exactly one bit.
        assert!(
            got.iter()
                .zip(&sent)
                .all(|(a, b)| (a ^ b).count_ones() <= 1)
        );
        // Nearly every 1000-byte message holds a damaged byte: 1 - (1 - 0.00996)^1000 = 0.99995.
        assert!(corrupted >= 195, "{corrupted}");
        // 100 .. 101 s is outside the run: nothing lost.
        assert_eq!(got.len(), 200_000);
        // Now across a link loss of 1 s: 1 Mbaud = 100 000 bytes lost.
        let mut link = Link::new(
            "bahrs",
            0,
            1_000_000,
            &HostConfig::default(),
            w.start_gps_ns,
            2,
        );
        let mut out = Vec::new();
        for k in 0..300 {
            link.transmit(
                &emission(w.start_gps_ns + 99_500_000_000 + k * 10_000_000, 1000),
                &f,
                &clock,
                &mut out,
            );
        }
        link.close(&clock, &mut out);
        let n: usize = out.iter().map(|c| c.bytes.len()).sum();
        assert!((199_990..=200_010).contains(&n), "{n}");
    }

    #[test]
    fn a_full_transmit_buffer_discards_messages() {
        let (w, f, clock) = setup(vec![]);
        let mut link = Link::new("watson", 0, 9600, &HostConfig::default(), w.start_gps_ns, 3);
        let mut out = Vec::new();
        // 100 messages of 100 bytes ready at once: 40 fill the 4096-byte buffer (4000 bytes), the
        // 41st would make 4100.
        let lost: Vec<bool> = (0..100)
            .map(|_| {
                link.transmit(&emission(w.start_gps_ns, 100), &f, &clock, &mut out)
                    .corrupted
            })
            .collect();
        assert!(lost[..40].iter().all(|l| !l));
        assert!(lost[40..].iter().all(|l| *l));
        link.close(&clock, &mut out);
        assert_eq!(out.iter().map(|c| c.bytes.len()).sum::<usize>(), 4000);
    }

    #[test]
    fn native_uart_reads_fifo_triggers_and_times_out_a_partial_one() {
        let (w, f, clock) = setup(vec![]);
        let mut host = HostConfig::default();
        host.adapters.insert("watson".into(), Adapter::NativeUart);
        let mut link = Link::new("watson", 0, 9600, &host, w.start_gps_ns, 1);
        let mut out = Vec::new();
        let t0 = w.start_gps_ns + 1_000_000_000;
        link.transmit(&emission(t0, 20), &f, &clock, &mut out);
        link.close(&clock, &mut out);
        // 20 bytes: two 8-byte FIFO reads and a partial one of 4.
        let sizes: Vec<usize> = out.iter().map(|c| c.bytes.len()).collect();
        assert_eq!(sizes, vec![8, 8, 4]);
        // A byte takes 10 / 9600 s = 1.0417 ms. The second read: byte 16 done at 16.667 ms,
        // then 0.1 +- 0.05 ms. The partial one: byte 20 at 20.833 ms, plus the 4-character
        // timeout (4.167 ms), plus 0.1 +- 0.05 ms. Host time at t0 is 6 s.
        let at = |i: usize| out[i].t_host_ns as f64 - 6.0e9;
        assert!((16.7166e6..=16.8167e6).contains(&at(1)), "{}", at(1));
        assert!((25.0499e6..=25.1501e6).contains(&at(2)), "{}", at(2));
    }

    #[test]
    fn usb_cdc_sends_64_byte_packets_on_the_1_ms_frame() {
        let (w, f, clock) = setup(vec![]);
        let mut host = HostConfig::default();
        host.adapters.insert("ttmrf".into(), Adapter::UsbCdc);
        let mut link = Link::new("ttmrf", 0, 921_600, &host, w.start_gps_ns, 1);
        let mut out = Vec::new();
        let t0 = w.start_gps_ns + 1_000_000_000;
        link.transmit(&emission(t0, 100), &f, &clock, &mut out);
        link.close(&clock, &mut out);
        let sizes: Vec<usize> = out.iter().map(|c| c.bytes.len()).collect();
        assert_eq!(sizes, vec![64, 36]);
        // 100 bytes x 10 / 921600 s = 1.085 ms: the first packet is full at 0.694 ms and goes
        // with the frame at 1 ms, the rest with the frame at 2 ms; then 0.2 +- 0.1 ms.
        let at = |i: usize| out[i].t_host_ns as f64 - 6.0e9;
        assert!((1.0999e6..=1.3001e6).contains(&at(0)), "{}", at(0));
        assert!((2.0999e6..=2.3001e6).contains(&at(1)), "{}", at(1));
    }
}
