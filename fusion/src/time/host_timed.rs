//! Samples without a usable time of their own (Watson lines, TT-Multi-RF CSV / MAVLink / GDL90 /
//! ASTERIX), placed on GPS time through the host clock model ([`HostClock`]), and the transmission
//! time of a frame at its baud rate (issue 7, "Watson and anything without its own time").
//!
//! A message whose last byte reached the host at `h` (an [`Rx`]) started on the wire at about
//! `h - tx_ns(len, baud)` host time; the host clock maps that to the GPS time its first byte left the
//! device, and the device's output delay (sample instant to first byte) is subtracted. The stated
//! 1-sigma combines the host model's (link-delay spread, envelope scatter, coasting) with the
//! uncertainty of that output delay.

use std::collections::VecDeque;

use super::host::HostClock;
use super::{AlignedTime, NotAligned, Reads, Rx, TimeSource};

/// Bits per byte on an 8N1 serial line (start + 8 data + stop).
pub const BITS_PER_BYTE: i64 = 10;

/// Transmission time of `bytes` bytes at `baud` bit/s, 8N1, ns. A 64-byte Watson line at 9600 baud:
/// 64 x 10 / 9600 s = 66.67 ms.
pub fn tx_ns(bytes: usize, baud: u32) -> i64 {
    let bits = (bytes as i64).saturating_mul(BITS_PER_BYTE);
    bits.saturating_mul(1_000_000_000) / i64::from(baud.max(1))
}

/// Host time at which the last byte of a received message reached the host, as far as its reads
/// tell, ns: the read of its last byte, less the line time of the bytes that read returned
/// after it, where the reads are known ([`Reads::after_bytes`]). Decision: those bytes followed
/// the message on the wire, back to back at the most, so the read came at least their line
/// time after its end; taking exactly that is never too early, and a line that sends messages
/// back to back (a list of targets sent at once) would otherwise stamp a message late by up to
/// a read of the next one (5.6 ms for 64 bytes at 115 200 baud).
pub fn last_byte_host_ns(rx: Rx, baud: u32) -> i64 {
    rx.host_ns - tx_ns(rx.reads.map_or(0, |r| r.after_bytes), baud)
}

/// Host time at which the first byte of a received message left the device: its last byte's
/// arrival ([`last_byte_host_ns`]) minus its own transmission time, ns.
pub fn first_byte_host_ns(rx: Rx, baud: u32) -> i64 {
    last_byte_host_ns(rx, baud) - tx_ns(rx.wire_len, baud)
}

/// Link of a host-timed port.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HostTimedLink {
    /// Baud rate, bit/s.
    pub baud: u32,
    /// Device output delay, sample instant to first byte on the wire, ns.
    pub output_delay_ns: i64,
    /// 1-sigma of that delay, ns.
    pub output_delay_sigma_ns: f64,
}

impl HostTimedLink {
    /// The Watson AHRS-E304 port: 9600 baud (document). Decision: the document states no delay
    /// between the sample and its line; 1 ms +- 0.5 ms (1-sigma) is assumed (a line formatted by a
    /// small MCU right after its sample; the simulator uses 1 ms). Measure it per installation.
    pub const WATSON: Self = Self {
        baud: vigil_drivers::watson::BAUD,
        output_delay_ns: 1_000_000,
        output_delay_sigma_ns: 500_000.0,
    };
}

impl HostTimedLink {
    /// This link read every `interval_ns` instead of as its bytes arrive (a paced port): a
    /// message's last byte then waits between 0 and the interval before its read stamps it.
    /// Taken as uniform, the wait adds half the interval to the output delay and
    /// `interval / sqrt(12)` (root-sum-square) to its sigma. 0 leaves the link as it is.
    pub fn with_read_interval(self, interval_ns: u64) -> Self {
        let i = interval_ns as f64;
        Self {
            output_delay_ns: self
                .output_delay_ns
                .saturating_add(i64::try_from(interval_ns / 2).unwrap_or(i64::MAX)),
            output_delay_sigma_ns: (self.output_delay_sigma_ns.powi(2) + i * i / 12.0).sqrt(),
            ..self
        }
    }
}

/// GPS time of a host-timed sample, or why there is none.
pub fn host_timed(
    host: &HostClock,
    rx: Rx,
    link: HostTimedLink,
) -> Result<AlignedTime, NotAligned> {
    let h = first_byte_host_ns(rx, link.baud);
    let (t, sigma) = match hold_back_ns(host, rx, link.baud) {
        Some((hold, spread)) => host.to_gps_read(h).map(|(t, sigma)| {
            // With a single read's delay L and the read before's P both uniform over `spread`
            // (s), the last read's delay is max(L, P - gap): it exceeds L by (P - gap - L)+,
            // whose mean is h^3 / (6 s^2) and root mean square h^2 / (s sqrt(12)) (h the
            // most it can hold back; by hand: E[(x - L)+] = x^2 / 2s, integrated over x in
            // 0..h with density 1/s).
            let s2 = spread * spread;
            let mean = hold.powi(3) / (6.0 * s2);
            let rms = hold * hold / (s2.sqrt() * 12f64.sqrt());
            (t - mean.round() as i64, (sigma.powi(2) + rms * rms).sqrt())
        }),
        None => host.to_gps(h),
    }
    .ok_or(NotAligned::HostClockUnknown)?;
    Ok(AlignedTime {
        t_gps_ns: t - link.output_delay_ns,
        sigma_ns: (sigma.powi(2) + link.output_delay_sigma_ns.powi(2)).sqrt(),
        source: TimeSource::HostClock,
        status: host.status(h),
    })
}

/// How long the last read of a message may have been held back by the read before it, ns, when
/// the host clock knows a single read's delay (issue 18 point 1); `None`: the reads or the
/// single-read delay are unknown, and the reference messages' delay applies. Reads come in
/// order, so a read can wait for the one before it; that one ended at least the transmission
/// time of the last read's own bytes (`gap`) earlier, so it can hold the last read back by at
/// most `spread - gap` (the spread of a single read's delay): a slow port's line (a Watson's
/// bytes take 1 ms each) mostly has a single read's delay, a fast port's message split over
/// reads (the VN-200's) more. Returns (most hold-back, spread), ns. Decision: a message in one
/// read is treated alike (the previous message may have ended just before it).
fn hold_back_ns(host: &HostClock, rx: Rx, baud: u32) -> Option<(f64, f64)> {
    let (r, spread) = (rx.reads?, host.read_spread_ns()?);
    Some(((spread - tx_ns(r.last_bytes, baud) as f64).max(0.0), spread))
}

/// Receive times of a port's read chunks by stream offset: which read delivered a given byte
/// (replay knows the chunks; [`Rx::host_ns`] wants the read that delivered a message's last byte).
#[derive(Debug, Clone, Default)]
pub struct ChunkClock {
    chunks: VecDeque<(u64, i64)>,
    fed: u64,
}

/// Chunks remembered by a [`ChunkClock`] (a message longer than this many reads gets the time of
/// the oldest one kept).
const CHUNK_CLOCK_CAPACITY: usize = 4096;

impl ChunkClock {
    /// Records a read of `len` bytes at host time `host_ns`.
    pub fn push(&mut self, host_ns: i64, len: usize) {
        if len == 0 {
            return;
        }
        if self.chunks.len() == CHUNK_CLOCK_CAPACITY {
            self.chunks.pop_front();
        }
        self.chunks.push_back((self.fed, host_ns));
        self.fed += len as u64;
    }

    /// Host time of the read that delivered stream byte `offset` (queries must not go back more
    /// than the chunk last asked for: older chunks are forgotten). `None` before any read.
    pub fn time_of(&mut self, offset: u64) -> Option<i64> {
        while self.chunks.len() > 1 && self.chunks[1].0 <= offset {
            self.chunks.pop_front();
        }
        self.chunks.front().map(|c| c.1)
    }

    /// The receive of a message starting at stream offset `offset`, `wire_len` bytes long: the
    /// read holding its last byte, and how the reads split it ([`Reads`]; `None` when the read
    /// holding its first byte is forgotten).
    pub fn rx(&mut self, offset: u64, wire_len: usize) -> Option<Rx> {
        let last = offset + (wire_len as u64).saturating_sub(1);
        // The read holding the first byte becomes the front (older ones are forgotten).
        self.time_of(offset)?;
        let (first_start, first_host_ns) = self.chunks[0];
        let j = self
            .chunks
            .partition_point(|c| c.0 <= last)
            .saturating_sub(1);
        let end = |i: usize| self.chunks.get(i + 1).map_or(self.fed, |c| c.0);
        let reads = (first_start <= offset && wire_len > 0).then(|| {
            let first_bytes = (end(0).min(last + 1) - offset) as usize;
            let last_bytes = if j == 0 {
                first_bytes
            } else {
                (last + 1 - self.chunks[j].0) as usize
            };
            Reads {
                first_host_ns,
                first_bytes,
                last_bytes,
                after_bytes: (end(j) - (last + 1)) as usize,
            }
        });
        Some(Rx {
            host_ns: self.chunks[j].1,
            wire_len,
            reads,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::ClockStatus;
    use crate::time::host::HostClockConfig;
    use crate::time::testrng::Lcg;

    const MS: i64 = 1_000_000;
    const S: i64 = 1_000_000_000;

    #[test]
    fn transmission_times_by_hand() {
        // 64 bytes x 10 bits / 9600 bit/s = 0.0666... s.
        assert_eq!(tx_ns(64, 9600), 66_666_666);
        // 20 bytes at 115 200: 200 / 115200 s = 1.736 ms.
        assert_eq!(tx_ns(20, 115_200), 1_736_111);
        assert_eq!(tx_ns(0, 9600), 0);
        // A zero baud does not divide by zero.
        assert!(tx_ns(1, 0) > 0);
    }

    /// A 20-byte message at 115 200 baud whose last read also returned 40 bytes of the next
    /// one: that read came at least 40 x 10 / 115 200 s = 3 472 222 ns after the message's end,
    /// which began 1 736 111 ns before it (by hand). Without reads, only its own length counts.
    #[test]
    fn the_bytes_a_read_returned_after_a_message_are_taken_off_its_arrival() {
        let reads = Reads {
            first_host_ns: 9_000_000,
            first_bytes: 20,
            last_bytes: 20,
            after_bytes: 40,
        };
        let rx = Rx {
            host_ns: 10_000_000,
            wire_len: 20,
            reads: Some(reads),
        };
        assert_eq!(last_byte_host_ns(rx, 115_200), 10_000_000 - 3_472_222);
        assert_eq!(
            first_byte_host_ns(rx, 115_200),
            10_000_000 - 3_472_222 - 1_736_111
        );
        let unknown = Rx { reads: None, ..rx };
        assert_eq!(first_byte_host_ns(unknown, 115_200), 10_000_000 - 1_736_111);
    }

    #[test]
    fn chunk_clock_names_the_read_of_the_last_byte() {
        // Reads of 10, 5 and 20 bytes at 100, 200, 300 ns: bytes 0-9, 10-14, 15-34.
        let mut c = ChunkClock::default();
        assert_eq!(c.time_of(0), None);
        c.push(100, 10);
        c.push(150, 0);
        c.push(200, 5);
        c.push(300, 20);
        // A 12-byte message at offset 3 ends at byte 14: the second read.
        assert_eq!(
            c.rx(3, 12),
            Some(Rx {
                host_ns: 200,
                wire_len: 12,
                // Bytes 3-9 in the first read (7), 10-14 in the second (5).
                reads: Some(Reads {
                    first_host_ns: 100,
                    first_bytes: 7,
                    last_bytes: 5,
                    // The second read (bytes 10-14) holds nothing after it.
                    after_bytes: 0,
                }),
            })
        );
        // A message inside one read: all its bytes in the first and last read.
        assert_eq!(
            c.rx(15, 4).unwrap().reads,
            Some(Reads {
                first_host_ns: 300,
                first_bytes: 4,
                last_bytes: 4,
                // The third read holds bytes 15-34: 19-34 (16) after the message's 15-18.
                after_bytes: 16,
            })
        );
        assert_eq!(c.time_of(15), Some(300));
        assert_eq!(c.time_of(1_000), Some(300));
        // An empty message has no bytes to split: its read, no split.
        assert_eq!(c.rx(20, 0).map(|r| (r.host_ns, r.reads)), Some((300, None)));
        // A message starting in a read already forgotten (bytes 3-9, the first read's; the
        // read of bytes 15-34 is now the front): the read of its last byte, no split.
        assert_eq!(c.rx(3, 20).map(|r| (r.host_ns, r.reads)), Some((300, None)));
    }

    /// A host clock 3 s ahead of GPS, learned from 20 s of references (GPS 500..520 s) whose
    /// delay is uniform 0.5..1.5 ms.
    fn host_3_s_ahead() -> HostClock {
        let mut host = HostClock::new(HostClockConfig::default());
        let mut rng = Lcg(9);
        for k in 0..2_000 {
            let gps = 500 * S + k * 10 * MS;
            host.add(gps + 3 * S + MS / 2 + (rng.unit() * MS as f64) as i64, gps);
        }
        host
    }

    #[test]
    fn a_read_interval_adds_half_its_length_and_its_uniform_sigma() {
        // Watson, read every 10 ms: delay 1 ms + 5 ms; sigma sqrt(0.5^2 + 10^2 / 12) ms
        // = sqrt(0.25 + 8.3333) = 2.9297 ms.
        let l = HostTimedLink::WATSON.with_read_interval(10 * MS as u64);
        assert_eq!(l.output_delay_ns, 6 * MS);
        assert!((l.output_delay_sigma_ns - 2_929_733.0).abs() < 1.0);
        assert_eq!(l.baud, HostTimedLink::WATSON.baud);
        assert_eq!(
            HostTimedLink::WATSON.with_read_interval(0),
            HostTimedLink::WATSON
        );
    }

    #[test]
    fn paced_watson_lines_are_unbiased_and_within_their_sigma() {
        // As below, but each line waits uniform 0..10 ms for its read (a port drained every
        // 10 ms): the errors average out and stay inside the stated sigma.
        let (host, off) = (host_3_s_ahead(), 3 * S);
        let mut rng = Lcg(11);
        let link = HostTimedLink::WATSON.with_read_interval(10 * MS as u64);
        let (mut sum, mut sum2, mut outside_2sigma, n) = (0.0, 0.0, 0, 500);
        for k in 0..n {
            let sample = 505 * S + k * 20 * MS;
            let wait = (rng.unit() * 10.0 * MS as f64) as i64;
            let rx = Rx {
                host_ns: sample + off + MS + 66_666_666 + MS + wait,
                wire_len: 64,
                reads: None,
            };
            let a = host_timed(&host, rx, link).unwrap();
            let e = (a.t_gps_ns - sample) as f64;
            sum += e;
            sum2 += e * e;
            if e.abs() > 2.0 * a.sigma_ns {
                outside_2sigma += 1;
            }
        }
        let mean = sum / n as f64;
        let sd = (sum2 / n as f64 - mean * mean).sqrt();
        // Mean error well under the 5 ms the wait averages; spread about 10 ms / sqrt(12).
        assert!(mean.abs() < 0.4 * MS as f64, "mean {mean}");
        assert!((sd - 2_887_000.0).abs() < 400_000.0, "sd {sd}");
        // A uniform error is inside 2 sigma always (its half-width is sqrt(3) sigma).
        assert_eq!(outside_2sigma, 0);
    }

    #[test]
    fn a_watson_line_lands_on_its_sample_time() {
        let (host, off) = (host_3_s_ahead(), 3 * S);
        // A Watson sample at GPS 515 s: first byte 1 ms later, last byte 66.67 ms after that, read
        // 1 ms (the mean link delay) after the last byte.
        let sample = 515 * S;
        let rx = Rx {
            host_ns: sample + off + MS + 66_666_666 + MS,
            wire_len: 64,
            reads: None,
        };
        let a = host_timed(&host, rx, HostTimedLink::WATSON).unwrap();
        assert!(
            (a.t_gps_ns - sample).abs() < 100_000,
            "{}",
            a.t_gps_ns - sample
        );
        assert_eq!(a.source, TimeSource::HostClock);
        assert_eq!(a.status, ClockStatus::Locked);
        // sigma: link spread 0.29 ms, the Watson's output delay 0.5 ms and the VN-200's (the
        // host clock's reference) 0.5 ms: sqrt(0.289^2 + 0.5^2 + 0.5^2) = 0.764 ms.
        assert!((a.sigma_ns - 764_000.0).abs() < 40_000.0, "{}", a.sigma_ns);
        // No host model: not aligned, with the reason.
        let empty = HostClock::new(HostClockConfig::default());
        assert_eq!(
            host_timed(&empty, rx, HostTimedLink::WATSON),
            Err(NotAligned::HostClockUnknown)
        );
    }

    #[test]
    fn a_last_read_that_the_one_before_may_hold_back_is_placed_earlier_by_hand() {
        // A host clock with no reference-delay or rate term: references 1 ms late, one a second;
        // in the second bucket 50 single reads, half 0.5 ms and half 2.5 ms late (spread 2 ms,
        // mid-range 1.5 ms: the delay a single read is placed with).
        let mut c = HostClock::new(HostClockConfig {
            reference_delay_sigma_ns: 0.0,
            rate_sigma_ppm: 0.0,
            ..HostClockConfig::default()
        });
        let t0 = 1_000 * S;
        for k in 0..8 {
            let h = t0 + k * S;
            c.add(h, h - MS);
            if k == 1 {
                for j in 0..50 {
                    let hr = h + (10 + j) * MS;
                    let delay = if j % 2 == 0 { MS / 2 } else { 5 * MS / 2 };
                    c.add_read(hr, hr - delay);
                }
            }
        }
        let link = HostTimedLink {
            baud: 115_200,
            output_delay_ns: 0,
            output_delay_sigma_ns: 0.0,
        };
        // A 20-byte message (1,736,111 ns on the wire) whose last read held 10 bytes
        // (868,055 ns): the read before can hold it back by up to 2 ms - 868,055 ns =
        // 1,131,945 ns (h). Mean hold-back h^3 / (6 s^2) = 60,431.7 ns, its rms h^2 / (s sqrt 12)
        // = 184,939.7 ns; the single read's own sigma 2 ms / sqrt 12 = 577,350.3 ns.
        let rx = |last_bytes| Rx {
            host_ns: t0 + 7 * S + 100 * MS,
            wire_len: 20,
            reads: Some(Reads {
                first_host_ns: t0 + 7 * S + 99 * MS,
                first_bytes: 10,
                last_bytes,
                after_bytes: 0,
            }),
        };
        let first_byte = t0 + 7 * S + 100 * MS - 1_736_111;
        let a = host_timed(&c, rx(10), link).unwrap();
        assert_eq!(a.t_gps_ns, first_byte - 1_500_000 - 60_432);
        assert!((a.sigma_ns - 606_247.48).abs() < 0.01, "{}", a.sigma_ns);
        // 30 bytes in the last read take 2,604,166 ns, more than the spread: nothing holds it.
        let rx30 = Rx {
            wire_len: 40,
            ..rx(30)
        };
        let a = host_timed(&c, rx30, link).unwrap();
        assert_eq!(a.t_gps_ns, t0 + 7 * S + 100 * MS - 3_472_222 - 1_500_000);
        assert!((a.sigma_ns - 577_350.27).abs() < 0.01, "{}", a.sigma_ns);
        // Without the reads, the references' own delay (1 ms, no spread) places it.
        let a = host_timed(&c, Rx::new(t0 + 7 * S + 100 * MS, 20), link).unwrap();
        assert_eq!((a.t_gps_ns, a.sigma_ns), (first_byte - MS, 0.0));
    }
}
