//! Serial link model: a device's bytes leave at its baud rate (10 bits per byte, 8N1) and reach the
//! host in read chunks after an OS/USB latency; link faults damage or lose bytes on the way.
//!
//! - A message starts when it is ready and the line is free; byte `i` has fully arrived at the
//!   adapter `(i + 1) x 10 / baud` s after the start.
//! - The host read returns chunks of 1 ..= `max_chunk_bytes` bytes (uniform). A chunk ends early
//!   when the line goes idle (a gap before the next message), as a USB adapter flushes on idle.
//!   Its receive time is the host-clock time of its last byte plus a latency uniform in
//!   `latency_ms +- latency_jitter_ms`, never earlier than the previous chunk of the same port.
//! - Faults: a bit error flips one random bit of a byte (probability `1 - (1 - rate)^10` per byte);
//!   a dropped byte and every byte sent during a link loss never reach the host; they all still
//!   take their time on the line. A message with any such byte is marked corrupted in the truth.

use crate::device::{Emission, FaultSchedule};
use crate::rng::Rng;
use crate::scenario::HostConfig;
use crate::truth::World;

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
    pub fn host_ns(&self, t_gps_ns: f64) -> u64 {
        let dt = (t_gps_ns - self.start_gps_ns as f64) * (1.0 + self.drift);
        (self.offset_ns as f64 + dt).max(0.0) as u64
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
    last_done_gps_ns: f64,
}

/// The link of one port.
pub struct Link {
    device: &'static str,
    port: u16,
    byte_ns: f64,
    line_free_gps_ns: f64,
    host: HostConfig,
    rng: Rng,
    last_host_ns: u64,
    open: Option<OpenChunk>,
    rx_bytes: u64,
}

impl Link {
    /// The link of `device` on port index `port`.
    pub fn new(device: &'static str, port: u16, baud: u32, host: &HostConfig, seed: u64) -> Self {
        Self {
            device,
            port,
            byte_ns: 10.0e9 / f64::from(baud.max(1)),
            line_free_gps_ns: f64::MIN,
            host: host.clone(),
            rng: Rng::stream(seed, &format!("link/{device}")),
            last_host_ns: 0,
            open: None,
            rx_bytes: 0,
        }
    }

    /// Sends one message: appends the chunks that complete to `out`.
    pub fn transmit(
        &mut self,
        e: &Emission,
        world: &World,
        faults: &FaultSchedule,
        clock: &HostClock,
        out: &mut Vec<Chunk>,
    ) -> Transmission {
        let ready = e.t_ready_gps_ns as f64;
        let start = ready.max(self.line_free_gps_ns);
        if start > self.line_free_gps_ns + 0.5 * self.byte_ns {
            // The line was idle: the adapter has flushed what it held.
            self.close(clock, out);
        }
        let mut corrupted = false;
        let rx_offset = self.rx_bytes;
        let t0_s = world.elapsed_s(start as i64);
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
            let open = self.open.get_or_insert_with(|| OpenChunk {
                bytes: Vec::new(),
                target: 0,
                last_done_gps_ns: done,
            });
            if open.target == 0 {
                open.target = self.rng.one_to(self.host.max_chunk_bytes) as usize;
            }
            open.bytes.push(byte);
            self.rx_bytes += 1;
            open.last_done_gps_ns = done;
            if open.bytes.len() >= open.target {
                self.close(clock, out);
            }
        }
        self.line_free_gps_ns = start + e.bytes.len() as f64 * self.byte_ns;
        Transmission {
            t_tx_gps_ns: start.round() as i64,
            corrupted,
            rx_offset,
        }
    }

    /// Ends the open chunk (if any) and appends it to `out`.
    pub fn close(&mut self, clock: &HostClock, out: &mut Vec<Chunk>) {
        let Some(open) = self.open.take() else { return };
        if open.bytes.is_empty() {
            return;
        }
        let lat_ms = self.host.latency_ms + self.rng.range(-1.0, 1.0) * self.host.latency_jitter_ms;
        let t = clock
            .host_ns(open.last_done_gps_ns + lat_ms.max(0.0) * 1e6)
            .max(self.last_host_ns);
        self.last_host_ns = t;
        out.push(Chunk {
            port: self.port,
            t_host_ns: t,
            bytes: open.bytes,
        });
    }
}
