//! The host monotonic clock shared by all processes (Linux `CLOCK_MONOTONIC`), in ns.

/// `CLOCK_MONOTONIC` now, ns. Comparable between processes of one host, so a subscriber can
/// compute the latency from a publisher's send stamp.
pub fn monotonic_ns() -> u64 {
    let t = rustix::time::clock_gettime(rustix::time::ClockId::Monotonic);
    (t.tv_sec as u64)
        .saturating_mul(1_000_000_000)
        .saturating_add(t.tv_nsec as u64)
}
