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
//! - A queue shorter than that (a list of targets the device sends at once, once a second:
//!   the manual's "sending list of aircraft every second" reads either way, and a module that
//!   reports its table in turn queues nothing) is bounded apart, message by message, by the
//!   output that can have been sent back to back before it ([`LineLoad::queued_for_ns`]),
//!   from the bytes the host's reads returned and how far a read may stamp them late. The
//!   full span stays for the line's state (`line_full`) and for the host clock's references.
//! - History is kept for [`SLOTS`] slots of [`SLOT_NS`] (640 ms), more than the longest wait
//!   the aligner accepts (0.5 s).

use super::host_timed::{BITS_PER_BYTE, tx_ns};

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
    /// The latest host time counted into each slot, ns (`i64::MIN` for an empty one).
    latest: [i64; SLOTS],
    /// Index (host time / [`SLOT_NS`]) of the newest slot counted into, `None` before the first.
    newest: Option<i64>,
}

impl Default for LineLoad {
    fn default() -> Self {
        Self {
            slots: [0; SLOTS],
            latest: [i64::MIN; SLOTS],
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
                    self.latest[ring(i)] = i64::MIN;
                }
                index
            }
            None => index,
        };
        self.newest = Some(newest);
        let s = &mut self.slots[ring(newest)];
        *s = s.saturating_add(bytes);
        let latest = &mut self.latest[ring(newest)];
        *latest = (*latest).max(host_ns);
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

    /// The longest a message received at `host_ns` (the read of its last byte), `own_bytes`
    /// long and already counted, can have waited in the device behind earlier output on a
    /// line at `baud` bit/s, ns: the line time of the bytes before it that can have been sent
    /// back to back with it (a device that sends its list of targets once a second queues the
    /// list's later messages behind the earlier ones, a queue far shorter than the
    /// [`MIN_SPAN_NS`] [`Self::full_for_ns`] needs). 0 when nothing before it can have been.
    ///
    /// `slack_ns` is the most the host may stamp one message's end later than another's beyond
    /// their spacing on the wire (the port's read interval, its adapter's latency timer and
    /// the spread of a read's delay). Messages sent back to back from one stamped `h0` to this
    /// one took at least `host_ns - h0 - slack` of line time after the first; so a run can have
    /// begun in slot `i` only if the bytes counted from slot `i` on cover `host_ns` minus the
    /// latest time counted into it, less the slack, and one begun before slot `i` only if they
    /// cover `host_ns - i x slot - slack`: the scan stops at the first slot where even that
    /// fails. Decision: a run's start is known to its slot ([`SLOT_NS`]), and every byte
    /// counted from that slot on is taken as ahead of the message (some may predate the run):
    /// the bound may take in output up to a slot earlier than the stamps allow, never less.
    /// Bytes the decoder skipped between messages are not counted, so garbage inside a run can
    /// end it early (as for the load).
    pub fn queued_for_ns(&self, host_ns: i64, baud: u32, own_bytes: usize, slack_ns: i64) -> i64 {
        let Some(newest) = self.newest else { return 0 };
        let now = host_ns.div_euclid(SLOT_NS).max(newest);
        // Whether `bytes` of line and the slack cover `span_ns`: `tx_ns(bytes, baud) + slack_ns
        // >= span_ns`, without a division per slot (a whole number n has floor(x) >= n exactly
        // when x >= n).
        let per_s = i128::from(baud.max(1));
        let covers = |bytes: usize, span_ns: i64| {
            bytes as i128 * i128::from(BITS_PER_BYTE) * 1_000_000_000
                >= (i128::from(span_ns) - i128::from(slack_ns)) * per_s
        };
        let (mut bytes, mut run) = (0usize, 0usize);
        for k in 0..SLOTS as i64 {
            let i = now - k;
            let here = if i <= newest {
                self.slots[ring(i)] as usize
            } else {
                0
            };
            bytes += here;
            // An empty slot's latest is i64::MIN: no run begins there.
            if covers(bytes, host_ns.saturating_sub(self.latest[ring(i)])) {
                run = bytes;
            }
            if !covers(bytes, host_ns - i * SLOT_NS) {
                break;
            }
        }
        (tx_ns(run, baud) - tx_ns(own_bytes, baud)).max(0)
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

    /// A list of ten 100-byte messages sent at once at 115 200 baud, each stamped as its last
    /// byte arrives: 100 x 10 / 115 200 s = 8 680 555.6 ns apiece (by hand), so message `k`
    /// waited behind `k` of them, and the bound is that, to the ns (the line was quiet before).
    /// The same messages spread 100 ms apart waited for nothing.
    #[test]
    fn a_list_sent_at_once_queues_each_message_behind_the_ones_before() {
        let one = 8_680_555.6;
        let t0 = 50 * S + 1_234_567;
        let mut l = LineLoad::default();
        for k in 0..10i64 {
            let h = t0 + ((k + 1) as f64 * one) as i64;
            l.add(h, 100);
            let q = l.queued_for_ns(h, 115_200, 100, MS);
            assert!((q as f64 - k as f64 * one).abs() <= 1.0, "{k}: {q}");
        }
        let mut spread = LineLoad::default();
        for k in 0..10 {
            let h = t0 + k * 100 * MS;
            spread.add(h, 100);
            assert_eq!(spread.queued_for_ns(h, 115_200, 100, MS), 0, "{k}");
        }
    }

    /// Two 100-byte messages stamped 20 ms apart at 115 200 baud (8 680 555 ns of line each,
    /// rounded down). Back to back, the second's end left 8.68 ms after the first's, so the
    /// host stamped it 11.32 ms later than the first beyond that: they can have been only with
    /// at least 11.32 ms of slack (by hand). The bound knows the first stamp to its 5 ms slot
    /// (the first is 2 ms into it, 3 ms before its end) and takes the two as possibly back to
    /// back from 8.32 ms of slack on: never short, long by those 3 ms. Joined, the second
    /// waited for the first: 17 361 111 - 8 680 555 ns.
    #[test]
    fn the_slack_decides_whether_two_messages_can_have_been_back_to_back() {
        let t0 = 70 * S + 2 * MS;
        let mut l = LineLoad::default();
        l.add(t0, 100);
        l.add(t0 + 20 * MS, 100);
        let q = |slack_ns| l.queued_for_ns(t0 + 20 * MS, 115_200, 100, slack_ns);
        assert_eq!(q(11_400_000), 8_680_556);
        assert_eq!(q(8_400_000), 8_680_556);
        assert_eq!(q(8_300_000), 0);
        // The boundary, to the ns: from the first's slot end (70.005 s) to the second stamp is
        // 17 ms, which the second's 8 680 555 ns of line and 8 319 445 ns of slack just cover.
        assert_eq!(q(8_319_445), 8_680_556);
        assert_eq!(q(8_319_444), 0);
        assert_eq!(q(2 * MS), 0);
        assert_eq!(LineLoad::default().queued_for_ns(t0, 115_200, 100, MS), 0);
    }

    /// A 10-byte message stamped 0.5 ms into its slot, and a 100-byte one stamped 14 ms after it
    /// at 115 200 baud (868 055 and 8 680 555 ns of line, by hand). Back to back, the second's
    /// stamp would be at most its own line time plus the slack after the first's: with 1 ms of
    /// slack (9.68 ms) it cannot have waited for the first, although its line time and slack do
    /// cover the 9.5 ms since the first's slot ended (the slot alone does not decide); with 5.5
    /// ms (14.18 ms) it can have: 9 548 611 - 8 680 555 ns.
    #[test]
    fn output_stamped_too_early_in_its_slot_is_not_counted_ahead() {
        let t0 = 80 * S + 500_000;
        let mut l = LineLoad::default();
        l.add(t0, 10);
        l.add(t0 + 14 * MS, 100);
        let q = |slack_ns| l.queued_for_ns(t0 + 14 * MS, 115_200, 100, slack_ns);
        assert_eq!(q(MS), 0);
        assert_eq!(q(5_500_000), 868_056);
    }

    /// The same list of ten read every 10 ms (a paced port: each read stamps what arrived in
    /// the 10 ms before it, 10 ms of slack): the bound is never below a message's true wait,
    /// and above it by no more than a read's worth of line (the messages a read returns are
    /// all taken as possibly ahead of each other, and the bytes before the run's read too).
    #[test]
    fn paced_reads_of_a_list_never_bound_a_wait_short() {
        let one = 8_680_555.6;
        let t0 = 90 * S;
        let mut l = LineLoad::default();
        for k in 0..10i64 {
            let end = t0 + ((k + 1) as f64 * one) as i64;
            // The read after the last byte, on the 10 ms grid.
            let h = (end / (10 * MS) + 1) * 10 * MS;
            l.add(h, 100);
            let q = l.queued_for_ns(h, 115_200, 100, 10 * MS + MS) as f64;
            let truth = k as f64 * one;
            assert!(q >= truth - 1.0, "{k}: {q} < {truth}");
            assert!(q <= truth + 10e6 + one, "{k}: {q} vs {truth}");
        }
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
