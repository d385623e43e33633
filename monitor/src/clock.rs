//! The clock of a monitor that watches published payloads (`vigil monitor`): GPS time is known
//! only from the payloads, so "now" is the newest payload GPS time advanced by the host time
//! elapsed since it came. Sans-IO: host times are passed in.

/// The monitor's clock: the newest payload GPS time, advanced by the host time since it came.
#[derive(Debug, Clone, Copy, Default)]
pub struct GpsClock {
    newest: Option<(i64, u64)>,
}

impl GpsClock {
    /// A payload with GPS time `gps_ns` arrived at host monotonic time `mono_ns`.
    pub fn observe(&mut self, gps_ns: i64, mono_ns: u64) {
        if gps_ns == 0 {
            return;
        }
        if self.newest.is_none_or(|(g, _)| gps_ns > g) {
            self.newest = Some((gps_ns, mono_ns));
        }
    }

    /// GPS time now (host monotonic `mono_ns`), or `None` before any GPS time was seen.
    pub fn now(&self, mono_ns: u64) -> Option<i64> {
        self.newest.map(|(g, m)| {
            let elapsed = i64::try_from(mono_ns.saturating_sub(m)).unwrap_or(i64::MAX);
            g.saturating_add(elapsed)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clock_is_the_newest_gps_time_advanced_by_host_time() {
        let mut c = GpsClock::default();
        assert_eq!(c.now(5), None, "no time before a payload");
        c.observe(0, 10);
        assert_eq!(
            c.now(20),
            None,
            "unknown GPS time (0) does not set the clock"
        );
        c.observe(1_000, 100);
        assert_eq!(c.now(100), Some(1_000));
        assert_eq!(c.now(350), Some(1_250), "advanced by 250 ns of host time");
        // An older payload does not move it back.
        c.observe(900, 400);
        assert_eq!(c.now(400), Some(1_300));
        c.observe(2_000, 500);
        assert_eq!(c.now(500), Some(2_000));
        // A host time before the stamp (never expected) does not move it back either.
        assert_eq!(c.now(0), Some(2_000));
        // The same GPS time arriving again later (a second topic stamped at the same instant)
        // is older news: the first arrival keeps anchoring the clock.
        c.observe(2_000, 800);
        assert_eq!(c.now(1_000), Some(2_500));
    }
}
