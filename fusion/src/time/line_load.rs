//! How long a serial line has been full: the bytes of the messages received over the last
//! moments of host time against what the line carries at its baud rate (10 bits per byte,
//! 8N1).
//!
//! Why: a device whose output exceeds its line (a TT-Multi-RF reporting 300 targets in JSON
//! with raw HEX at 921 600 baud) queues its messages in its transmit buffer and sends each one
//! late by however much output waits before it: 33-45 ms in the simulator's full-rates
//! scenario, an undocumented amount on the module. A message's own time (JSON `ts`, TS24h)
//! still names when it was made, but its arrival no longer says when it was sent. A message
//! that waited `q` in the queue was preceded by `q` of continuous output on the line, which
//! the host received in the `q` before it: so the span over which the line has been full,
//! measured here, bounds the wait of the message that ends it ([`super::aligner`] acts on it).
//!
//! Decisions:
//! - **Full** is [`FULL_FRACTION`] of the line's bytes per second, over spans of at least
//!   [`MIN_SPAN_NS`]: the host counts bytes when its reads return them (every 10 ms on a
//!   paced port, or when an adapter's latency timer runs out), so a short span may hold one
//!   read more or less than it should. Over 100 ms that is about 10 % of a line read every
//!   10 ms, inside the margin below 100 %; a line loaded to about 75 % may then read as full
//!   now and then, which only widens sigmas (fail-safe).
//! - A queue shorter than 100 ms, or one that grows past the cross-check's 20 ms margin
//!   before the line has been full for 100 ms (output above 1.25 times the line from one
//!   moment to the next), is not seen: the margin covers the first, the second is a
//!   disagreement until the span is reached.
//! - History is kept for [`SLOTS`] slots of [`SLOT_NS`] (640 ms), more than the longest wait
//!   the aligner accepts (0.5 s).

/// Share of a line's bytes per second from which it counts as full (see the module doc).
pub const FULL_FRACTION: f64 = 0.8;

/// Shortest span over which a line counts as full, ns (see the module doc).
pub const MIN_SPAN_NS: i64 = 100_000_000;

/// Length of one counting slot of host time, ns.
pub const SLOT_NS: i64 = 5_000_000;

/// Slots of history kept.
pub const SLOTS: usize = 128;

/// Bytes received on one line per slot of host time, over the last [`SLOTS`] slots. No heap:
/// it sits on the aligner's live path.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LineLoad {
    /// Bytes per slot, by slot index modulo [`SLOTS`].
    slots: [u32; SLOTS],
    /// Index (host time / [`SLOT_NS`]) of the newest slot counted into, `None` before the first.
    newest: Option<i64>,
}

impl Default for LineLoad {
    fn default() -> Self {
        Self {
            slots: [0; SLOTS],
            newest: None,
        }
    }
}

fn ring(index: i64) -> usize {
    index.rem_euclid(SLOTS as i64) as usize
}

impl LineLoad {
    /// Counts a message of `wire_bytes` bytes whose last byte arrived at host time `host_ns`.
    pub fn add(&mut self, host_ns: i64, wire_bytes: usize) {
        let index = host_ns.div_euclid(SLOT_NS);
        let bytes = u32::try_from(wire_bytes).unwrap_or(u32::MAX);
        let newest = match self.newest {
            // An earlier slot (reads of one port come in order; a reordered stamp is not worth
            // a model): counted in the newest one.
            Some(n) if index <= n => n,
            Some(n) => {
                // The slots passed over saw nothing, and the new one starts empty (more than
                // SLOTS of them: every slot).
                for i in (n + 1)..=index.min(n + SLOTS as i64) {
                    self.slots[ring(i)] = 0;
                }
                index
            }
            None => index,
        };
        self.newest = Some(newest);
        let s = &mut self.slots[ring(newest)];
        *s = s.saturating_add(bytes);
    }

    /// How long the line at `baud` bit/s has been full at host time `host_ns`, ns: the longest
    /// span of at least [`MIN_SPAN_NS`], ending with `host_ns`'s slot, whose bytes reach
    /// [`FULL_FRACTION`] of what the line carries in it; 0 when there is none. It bounds the
    /// wait of a message received at `host_ns` in the device's queue (see the module doc).
    pub fn full_for_ns(&self, host_ns: i64, baud: u32) -> i64 {
        let Some(newest) = self.newest else { return 0 };
        let now = host_ns.div_euclid(SLOT_NS).max(newest);
        // Bytes per slot at FULL_FRACTION of the line.
        let full_per_slot = FULL_FRACTION * f64::from(baud) / 10.0 * SLOT_NS as f64 * 1e-9;
        let (mut bytes, mut longest) = (0.0, 0);
        // `now >= newest`, so every slot from `now - SLOTS + 1` up to `newest` is in the history.
        for k in 0..SLOTS as i64 {
            let i = now - k;
            if i <= newest {
                bytes += f64::from(self.slots[ring(i)]);
            }
            let span = (k + 1) * SLOT_NS;
            if span >= MIN_SPAN_NS && bytes >= full_per_slot * (k + 1) as f64 {
                longest = span;
            }
        }
        longest
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const S: i64 = 1_000_000_000;
    const MS: i64 = 1_000_000;

    /// 921 600 baud carries 92 160 bytes a second, 460.8 per 5 ms slot: full from 368.64 bytes
    /// a slot (80 %).
    #[test]
    fn a_line_full_for_a_while_by_hand() {
        let mut l = LineLoad::default();
        assert_eq!(l.full_for_ns(10 * S, 921_600), 0);
        // 200-byte messages every 2.5 ms (80 000 bytes a second, 87 %), from 10 s on: 400 bytes
        // in each of 20 slots, 8 000 bytes, above 20 x 368.64 = 7 372.8. The span reaches on
        // into the silence before while the bytes still cover it: 21 slots (7 741.4), not 22
        // (8 110.1). The bound is long by up to a fifth, never short.
        for k in 0..40 {
            l.add(10 * S + k * 2_500_000, 200);
        }
        assert_eq!(l.full_for_ns(10 * S + 97_500_000, 921_600), 105 * MS);
        // 36 messages (7 200 bytes, 18 slots) never cover 20 slots or more.
        let mut short = LineLoad::default();
        for k in 0..36 {
            short.add(10 * S + k * 2_500_000, 200);
        }
        assert_eq!(short.full_for_ns(10 * S + 97_500_000, 921_600), 0);
        // Another 300 ms of it: 80 slots, 32 000 bytes, cover 86 slots (31 703) but not 87.
        for k in 40..160 {
            l.add(10 * S + k * 2_500_000, 200);
        }
        assert_eq!(l.full_for_ns(10 * S + 397_500_000, 921_600), 430 * MS);
        // Kept up for 2 s: the history's length (640 ms).
        for k in 160..800 {
            l.add(10 * S + k * 2_500_000, 200);
        }
        assert_eq!(l.full_for_ns(11 * S + 997_500_000, 921_600), 640 * MS);
        // Then 50 ms of silence: the 10 newest slots are empty, so n slots hold 400 (n - 10)
        // bytes, which reaches 368.64 n only at n = 128 (47 200 >= 47 186): 640 ms.
        assert_eq!(l.full_for_ns(12 * S + 47 * MS, 921_600), 640 * MS);
        // After 100 ms of silence it no longer holds anywhere (400 (n - 20) < 368.64 n for
        // n <= 128).
        assert_eq!(l.full_for_ns(12 * S + 97 * MS, 921_600), 0);
        // The same bytes on a line eight times faster would never have been full.
        let mut fast = LineLoad::default();
        for k in 0..800 {
            fast.add(10 * S + k * 2_500_000, 200);
        }
        assert_eq!(fast.full_for_ns(11 * S + 997_500_000, 7_372_800), 0);
    }

    /// Reads every 10 ms (a paced port) of a line at 100 %: 921.6 bytes a read land in every
    /// other slot; full for any span from 100 ms on, the odd slot boundaries included.
    #[test]
    fn paced_reads_of_a_full_line_are_full() {
        let mut l = LineLoad::default();
        for k in 0..100 {
            l.add(20 * S + k * 10 * MS, 922);
        }
        let last = 20 * S + 99 * 10 * MS;
        assert_eq!(l.full_for_ns(last, 921_600), 640 * MS);
        // Just before the next read (an empty slot is the newest): still full.
        assert_eq!(l.full_for_ns(last + 9 * MS, 921_600), 640 * MS);
        // A line at 60 % read the same way is never full over 100 ms or more.
        let mut l = LineLoad::default();
        for k in 0..100 {
            l.add(20 * S + k * 10 * MS, 553);
        }
        assert_eq!(l.full_for_ns(last, 921_600), 0);
        assert_eq!(l.full_for_ns(last + 9 * MS, 921_600), 0);
    }

    /// A full line, 300 ms of silence, then one byte: the slots passed over are empty, not
    /// what they held a history ago. By hand: n slots back hold 1 byte for n <= 60, then 400
    /// more per slot, and 400 (n - 60) + 1 never reaches 368.64 n within 128 slots.
    #[test]
    fn slots_passed_over_are_empty() {
        let mut l = LineLoad::default();
        for k in 0..400 {
            l.add(10 * S + k * 2_500_000, 200);
        }
        assert_eq!(l.full_for_ns(10 * S + 997_500_000, 921_600), 640 * MS);
        l.add(11 * S + 295 * MS, 1);
        assert_eq!(l.full_for_ns(11 * S + 295 * MS, 921_600), 0);
    }

    #[test]
    fn an_earlier_host_time_counts_in_the_newest_slot_and_a_long_gap_empties_the_history() {
        let mut l = LineLoad::default();
        // 9600 baud: 4.8 bytes a 5 ms slot, full from 3.84 a slot, 76.8 over 100 ms.
        l.add(5 * S, 70);
        assert_eq!(l.full_for_ns(5 * S, 9600), 0);
        // Stamped a little earlier (a reordered read): counted, not lost.
        l.add(5 * S - 20 * MS, 7);
        assert_eq!(l.full_for_ns(5 * S, 9600), 100 * MS);
        // Ten minutes later, nothing of it is left.
        l.add(605 * S, 1);
        assert_eq!(l.full_for_ns(605 * S, 9600), 0);
    }
}
