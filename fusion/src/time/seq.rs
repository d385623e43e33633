//! Pairing data messages with the time messages that time them, by sequence counter.
//!
//! The BAHRS sends each data message (0x01 inertial, 0x02 navigation) with an 8-bit sequence
//! counter, and a separate time message (0x05, 0x04) carrying the MCU time of "the data message with
//! sequence counter N". Counters wrap at 256 (2.56 s at 100 Hz), and the time message usually
//! follows its data message but may come later than the next data message, or (after a loss) never.
//!
//! [`SeqMatcher`] holds unmatched data for a bounded host time (default 0.5 s, far below the 2.56 s
//! wrap, so a counter value is never ambiguous) and emits every data message exactly once: matched
//! with its time, or, when its hold expires, unmatched, so the caller can mark it "not aligned"
//! instead of dropping it. Time messages that arrive before their data are held the same way.

use std::collections::VecDeque;

/// A data message paired (or not) with its device time.
#[derive(Debug, Clone, PartialEq)]
pub struct Paired<T> {
    /// The data message.
    pub data: T,
    /// Its sequence counter.
    pub seq: u8,
    /// Host receive time of the data message, ns.
    pub host_ns: i64,
    /// Device time of the data, in device ticks; `None` when no time message came in time.
    pub device_ticks: Option<u64>,
}

/// Bounded matcher of data and time messages by sequence counter.
#[derive(Debug, Clone)]
pub struct SeqMatcher<T> {
    hold_ns: i64,
    capacity: usize,
    data: VecDeque<(u8, i64, T)>,
    times: VecDeque<(u8, i64, u64)>,
    /// Data messages emitted without a time (hold expired or capacity exceeded).
    pub unmatched_data: u64,
    /// Time messages that never found their data message.
    pub orphan_times: u64,
}

impl<T> SeqMatcher<T> {
    /// A matcher holding unmatched messages for `hold_ns` of host time, at most `capacity` of each.
    pub fn new(hold_ns: i64, capacity: usize) -> Self {
        Self {
            hold_ns,
            capacity: capacity.max(1),
            data: VecDeque::with_capacity(capacity),
            times: VecDeque::with_capacity(capacity),
            unmatched_data: 0,
            orphan_times: 0,
        }
    }

    /// Offers a data message. Returns it paired at once if its time message is already waiting.
    /// If the hold is full, the oldest waiting data message is returned unmatched to make room
    /// (never dropped). At most one message comes back either way (an `Option`, so the common
    /// case allocates nothing).
    pub fn push_data(&mut self, seq: u8, host_ns: i64, data: T) -> Option<Paired<T>> {
        if let Some(i) = self.times.iter().position(|t| t.0 == seq) {
            let (_, _, ticks) = self.times.remove(i).unwrap_or((seq, host_ns, 0));
            return Some(Paired {
                data,
                seq,
                host_ns,
                device_ticks: Some(ticks),
            });
        }
        let mut out = None;
        if self.data.len() == self.capacity
            && let Some((s, h, d)) = self.data.pop_front()
        {
            self.unmatched_data += 1;
            out = Some(Paired {
                data: d,
                seq: s,
                host_ns: h,
                device_ticks: None,
            });
        }
        self.data.push_back((seq, host_ns, data));
        out
    }

    /// Offers a time message: the device time of the data message with counter `data_seq`.
    /// Returns the data message it completes, if that is waiting.
    pub fn push_time(&mut self, data_seq: u8, host_ns: i64, ticks: u64) -> Option<Paired<T>> {
        // The most recent waiting data message with that counter is the one it times.
        if let Some(i) = self.data.iter().rposition(|d| d.0 == data_seq) {
            let (seq, h, data) = self.data.remove(i)?;
            return Some(Paired {
                data,
                seq,
                host_ns: h,
                device_ticks: Some(ticks),
            });
        }
        if self.times.len() == self.capacity {
            self.times.pop_front();
            self.orphan_times += 1;
        }
        self.times.push_back((data_seq, host_ns, ticks));
        None
    }

    /// Releases every data message held longer than the hold time at host time `now_ns`,
    /// unmatched, and forgets time messages as old.
    pub fn expire(&mut self, now_ns: i64) -> Vec<Paired<T>> {
        let mut out = Vec::new();
        while self
            .data
            .front()
            .is_some_and(|d| now_ns - d.1 > self.hold_ns)
        {
            if let Some((seq, host_ns, data)) = self.data.pop_front() {
                self.unmatched_data += 1;
                out.push(Paired {
                    data,
                    seq,
                    host_ns,
                    device_ticks: None,
                });
            }
        }
        while self
            .times
            .front()
            .is_some_and(|t| now_ns - t.1 > self.hold_ns)
        {
            self.times.pop_front();
            self.orphan_times += 1;
        }
        out
    }

    /// Releases everything still held (end of stream), unmatched.
    pub fn flush(&mut self) -> Vec<Paired<T>> {
        self.orphan_times += self.times.len() as u64;
        self.times.clear();
        let out: Vec<_> = self
            .data
            .drain(..)
            .map(|(seq, host_ns, data)| Paired {
                data,
                seq,
                host_ns,
                device_ticks: None,
            })
            .collect();
        self.unmatched_data += out.len() as u64;
        out
    }

    /// Data messages waiting for their time.
    pub fn waiting(&self) -> usize {
        self.data.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const MS: i64 = 1_000_000;

    #[test]
    fn time_after_data_pairs() {
        let mut m = SeqMatcher::new(500 * MS, 64);
        assert!(m.push_data(7, 0, "a").is_none());
        let p = m.push_time(7, MS, 123).unwrap();
        assert_eq!((p.data, p.seq, p.device_ticks), ("a", 7, Some(123)));
        assert_eq!(m.waiting(), 0);
    }

    #[test]
    fn late_time_message_after_the_next_data() {
        let mut m = SeqMatcher::new(500 * MS, 64);
        m.push_data(1, 0, "one");
        m.push_data(2, 10 * MS, "two");
        // Time of 2 comes first, then the late time of 1.
        assert_eq!(m.push_time(2, 11 * MS, 20).unwrap().data, "two");
        assert_eq!(m.push_time(1, 12 * MS, 10).unwrap().data, "one");
    }

    #[test]
    fn time_before_data_pairs_too() {
        let mut m = SeqMatcher::new(500 * MS, 64);
        assert!(m.push_time(9, 0, 99).is_none());
        let out = m.push_data(9, MS, "x");
        assert_eq!(
            out,
            Some(Paired {
                data: "x",
                seq: 9,
                host_ns: MS,
                device_ticks: Some(99)
            })
        );
    }

    #[test]
    fn sequence_wrap_at_256() {
        let mut m = SeqMatcher::new(500 * MS, 64);
        let mut paired = 0;
        for k in 0..600u32 {
            let seq = k as u8; // wraps at 256
            let t = i64::from(k) * 10 * MS;
            m.push_data(seq, t, k);
            if let Some(p) = m.push_time(seq, t + MS, u64::from(k) * 10_000) {
                assert_eq!(p.data, k);
                assert_eq!(p.device_ticks, Some(u64::from(k) * 10_000));
                paired += 1;
            }
        }
        assert_eq!(paired, 600);
    }

    #[test]
    fn lost_time_message_is_released_unmatched_not_dropped() {
        let mut m = SeqMatcher::new(500 * MS, 64);
        m.push_data(3, 0, "lost");
        m.push_data(4, 10 * MS, "kept");
        assert!(m.expire(400 * MS).is_empty());
        let out = m.expire(501 * MS);
        assert_eq!(out.len(), 1);
        assert_eq!((out[0].data, out[0].device_ticks), ("lost", None));
        assert_eq!(m.unmatched_data, 1);
        assert_eq!(m.flush().len(), 1);
        assert_eq!(m.unmatched_data, 2);
    }

    #[test]
    fn capacity_bounds_the_hold() {
        let mut m = SeqMatcher::new(10_000 * MS, 4);
        let mut released = Vec::new();
        for k in 0..10u8 {
            released.extend(m.push_data(k, i64::from(k), k));
        }
        assert_eq!(m.waiting(), 4);
        assert_eq!(
            released.iter().map(|p| p.data).collect::<Vec<_>>(),
            vec![0, 1, 2, 3, 4, 5]
        );
    }

    #[test]
    fn a_full_hold_releases_the_oldest_data_counted_and_forgets_the_oldest_time_counted() {
        let mut m = SeqMatcher::new(500 * MS, 2);
        assert!(m.push_data(1, 0, "a").is_none());
        assert!(m.push_data(2, MS, "b").is_none());
        let out = m.push_data(3, 2 * MS, "c");
        assert_eq!(
            out,
            Some(Paired {
                data: "a",
                seq: 1,
                host_ns: 0,
                device_ticks: None
            })
        );
        assert_eq!((m.unmatched_data, m.waiting()), (1, 2));

        // Times without their data: two are held, a third forgets the oldest.
        let mut m = SeqMatcher::<&str>::new(500 * MS, 2);
        assert!(m.push_time(10, 0, 100).is_none());
        assert!(m.push_time(11, 0, 110).is_none());
        assert_eq!(m.orphan_times, 0);
        assert!(m.push_time(12, 0, 120).is_none());
        assert_eq!(m.orphan_times, 1);
        assert_eq!(m.push_data(10, MS, "ten"), None);
        assert_eq!(
            m.push_data(11, MS, "eleven").unwrap().device_ticks,
            Some(110)
        );
        assert_eq!(
            m.push_data(12, MS, "twelve").unwrap().device_ticks,
            Some(120)
        );
    }

    #[test]
    fn the_hold_expires_strictly_after_hold_ns_for_data_and_times() {
        let mut m = SeqMatcher::new(500 * MS, 8);
        m.push_data(1, 100 * MS, "data");
        m.push_time(2, 100 * MS, 222);
        // Held exactly 500 ms: both kept.
        assert!(m.expire(600 * MS).is_empty());
        assert_eq!((m.waiting(), m.orphan_times), (1, 0));
        // 1 ns more: the data released unmatched, the time forgotten, both counted.
        let out = m.expire(600 * MS + 1);
        assert_eq!(out.len(), 1);
        assert_eq!((out[0].data, out[0].device_ticks), ("data", None));
        assert_eq!((m.unmatched_data, m.orphan_times), (1, 1));
        assert_eq!(m.push_data(2, 600 * MS + 2, "late"), None);
    }

    #[test]
    fn flush_counts_what_it_releases_and_the_times_it_forgets() {
        let mut m = SeqMatcher::new(500 * MS, 8);
        m.push_data(1, 0, "a");
        m.push_data(2, 0, "b");
        m.push_time(7, 0, 70);
        m.push_time(8, 0, 80);
        m.push_time(9, 0, 90);
        assert_eq!(m.flush().len(), 2);
        assert_eq!((m.unmatched_data, m.orphan_times), (2, 3));
        assert_eq!(m.push_data(7, MS, "c"), None);
    }
}
