//! TT-Multi-RF samples on GPS time (issue 7, "TT-Multi-RF"; manual: JSON `ts`, HEX extended
//! fields `(SIGS,SIGQ,TS1s,TS24h)`).
//!
//! - JSON `ts`: ms since UTC midnight. Placed on its day by [`resolve_time_of_day`] with the
//!   reference GPS time from the host clock (known to ms, far inside the +-12 h the day choice
//!   needs) and the GPS - UTC offset in force. Decision: the manual does not say whether `ts` is
//!   truncated or rounded to the ms; it is taken as truncated (a millisecond counter), so the
//!   sample lies in `[ts, ts + 1 ms)`: +0.5 ms, sigma 1 ms / sqrt(12) = 0.29 ms.
//! - Raw frames with TS24h (ns since UTC midnight, PPS-disciplined): the same placement, sigma
//!   [`TtAlignerConfig::ts24h_sigma_ns`].
//! - Raw frames with TS1s only (ns since the receiver's last PPS): the PPS second is the whole GPS
//!   second nearest to the host-clock estimate minus TS1s (the host model is good to ms, far inside
//!   +-0.5 s); the stamp adds TS1s to it.
//! - A stale leap-second table (no GnssTimeInfo, past the table's validity) may be a second short:
//!   the time is given with status coasting and 1 s added to its sigma, never as locked.
//! - CSV, MAVLink, GDL90, ASTERIX and NMEA carry no receive time here: host clock
//!   ([`super::host_timed`]).

use vigil_drivers::ttmrf::raw::RxMeta;

use super::gps::{LeapSeconds, NS_PER_S, resolve_time_of_day};
use super::host::HostClock;
use super::host_timed::{HostTimedLink, first_byte_host_ns, tx_ns};
use super::pps::pulse_second;
use super::{AlignedTime, ClockStatus, NotAligned, Rx, TimeSource};

/// Parameters of the TT-Multi-RF time placement, with units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TtAlignerConfig {
    /// The serial link (the simulator and the module's default: 921 600 baud). Decision: the
    /// manual states no delay between reception and output; 0 +- 0.5 ms (1 sigma) is assumed for
    /// the host-timed outputs, as for the VN-200 (the module sends a message as it decodes it;
    /// so does the simulator's model). A mean of 0.5 ms, with the VN-200's unknown delay also
    /// taken as link delay by the host clock, put CSV lines ~1 ms early against the simulator:
    /// more than 2 sigma for about 5 % of them.
    pub link: HostTimedLink,
    /// 1-sigma of a TS24h / TS1s stamp, ns. Decision: 1 us (a PPS-disciplined counter; the
    /// manual gives ns resolution but no accuracy).
    pub ts24h_sigma_ns: f64,
    /// Longest wait of a message in the module's transmit buffer while its line is full
    /// ([`super::line_load`]), ns. Decision: the manual states neither the buffer nor what the
    /// module does when its output exceeds the line; 0.5 s of output is 46 KB at 921 600 baud
    /// (far more than an MCU-class module holds; the simulator's 4 KiB wait 44 ms) and half the
    /// smallest time fault the cross-check is for (a `ts` a second off), which stays caught. A
    /// deeper queue (a large buffer at a low baud) is called a disagreement and raised as one,
    /// and the line's samples no time of its own can place are then not aligned; so are they
    /// once the line has been full for longer than this with no time of its own bounding the
    /// wait (`Aligner::place_checked`). Must stay under the 640 ms a [`super::line_load`]
    /// history spans, or a line full for longer would not be seen.
    pub queue_limit_ns: i64,
    /// The module's transmit buffer, bytes, when the integrator knows it (`None`: unknown, the
    /// default). A message that finds the buffer full is lost in the module, so one that is
    /// sent waited at most for the bytes ahead of it: this many bytes' line time (4096 bytes:
    /// 0.36 s at 115 200 baud). That bounds the wait of a full line's messages however long
    /// the line has been full, so below [`Self::queue_limit_ns`] the line's host-timed samples
    /// stay placed, with this wait in their sigma. Decision: the manual gives no buffer size,
    /// so vigil assumes none; a figure smaller than the real buffer would pass late times off
    /// within too small a sigma (a time of its own, JSON `ts` or TS24h, earlier than it allows
    /// is still called a disagreement).
    pub output_buffer_bytes: Option<u32>,
}

impl TtAlignerConfig {
    /// The longest a message that was sent can have waited in the stated transmit buffer, ns:
    /// the buffer's line time at `baud` ([`Self::output_buffer_bytes`]); `None` when no buffer
    /// is stated. It bounds a full line's wait only when within [`Self::queue_limit_ns`].
    pub fn buffer_wait_ns(&self, baud: u32) -> Option<i64> {
        self.output_buffer_bytes.map(|b| tx_ns(b as usize, baud))
    }
}

impl Default for TtAlignerConfig {
    fn default() -> Self {
        Self {
            link: HostTimedLink {
                baud: 921_600,
                output_delay_ns: 0,
                output_delay_sigma_ns: 500_000.0,
            },
            ts24h_sigma_ns: 1_000.0,
            queue_limit_ns: 500_000_000,
            output_buffer_bytes: None,
        }
    }
}

/// 1-sigma of a ms stamp, ns. Decision (issue 18 point 5): the manual does not say whether
/// `ts` is truncated or rounded to the ms. Truncated, the time lies in [ts, ts + 1) ms; rounded,
/// in [ts - 0.5, ts + 0.5) ms. Both readings are covered by the union [ts - 0.5, ts + 1) ms:
/// its mid-point ([`TS_MS_MID_NS`]) and the sigma of a uniform 1.5 ms wide, 1.5 ms / sqrt(12);
/// either reading's error then stays within 0.75 ms = 1.73 sigma.
pub const TS_MS_SIGMA_NS: f64 = 433_012.7;

/// Offset of a ms stamp's assumed time from the stamp, ns (the mid-point above).
pub const TS_MS_MID_NS: i64 = 250_000;

/// Places a time of day (ns since UTC midnight, `resolution_ns` added for a truncated stamp's mid
/// point) with the host clock as the day reference.
fn place_time_of_day(
    ns_of_day: i64,
    sigma_ns: f64,
    rx: Rx,
    link: HostTimedLink,
    host: &HostClock,
    leap: LeapSeconds,
) -> Result<AlignedTime, NotAligned> {
    let h = first_byte_host_ns(rx, link.baud);
    let (reference, _) = host.to_gps(h).ok_or(NotAligned::HostClockUnknown)?;
    let t = resolve_time_of_day(ns_of_day, reference, leap.gps_minus_utc_s)
        .map_err(|_| NotAligned::BadTimeStamp)?;
    let (status, sigma) = if leap.table_valid {
        (ClockStatus::Locked, sigma_ns)
    } else {
        (ClockStatus::Coasting, (sigma_ns.powi(2) + 1e18).sqrt())
    };
    Ok(AlignedTime {
        t_gps_ns: t,
        sigma_ns: sigma,
        source: TimeSource::UtcTimeOfDay,
        status,
    })
}

/// GPS time of a JSON message's `ts` (ms since UTC midnight).
pub fn json_ts(
    ts_ms: u32,
    rx: Rx,
    cfg: &TtAlignerConfig,
    host: &HostClock,
    leap: LeapSeconds,
) -> Result<AlignedTime, NotAligned> {
    let ns = i64::from(ts_ms) * 1_000_000 + TS_MS_MID_NS;
    place_time_of_day(ns, TS_MS_SIGMA_NS, rx, cfg.link, host, leap)
}

/// GPS time of a raw frame from its receive metadata: TS24h, else TS1s; `Ok(None)` when it has
/// neither (the caller times it by the host clock).
pub fn raw_meta(
    meta: &RxMeta,
    rx: Rx,
    cfg: &TtAlignerConfig,
    host: &HostClock,
    leap: LeapSeconds,
) -> Option<Result<AlignedTime, NotAligned>> {
    if let Some(ns) = meta.ts_utc_ns {
        let ns = i64::try_from(ns).unwrap_or(i64::MAX);
        return Some(place_time_of_day(
            ns,
            cfg.ts24h_sigma_ns,
            rx,
            cfg.link,
            host,
            leap,
        ));
    }
    let pps = meta.ts_pps_ns?;
    if pps >= NS_PER_S as u64 + NS_PER_S as u64 / 10 {
        // More than 1.1 s since the last pulse: the receiver lost its PPS; the stamp is unusable.
        return Some(Err(NotAligned::BadTimeStamp));
    }
    let h = first_byte_host_ns(rx, cfg.link.baud);
    let Some((est, sigma)) = host.to_gps(h) else {
        return Some(Err(NotAligned::HostClockUnknown));
    };
    if sigma > 0.1 * NS_PER_S as f64 {
        // The host clock is too uncertain to name the second.
        return Some(Err(NotAligned::ClockUnlocked));
    }
    let pps = pps as i64;
    let second = pulse_second(est - cfg.link.output_delay_ns - pps);
    Some(Ok(AlignedTime {
        t_gps_ns: second + pps,
        sigma_ns: cfg.ts24h_sigma_ns,
        source: TimeSource::PpsDisciplined,
        status: host.status(h),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::time::gps::{GPS_EPOCH_UNIX_S, gps_minus_utc_s};
    use crate::time::host::HostClockConfig;

    const MS: i64 = 1_000_000;
    const S: i64 = NS_PER_S;
    /// 2026-06-01 00:00:00 UTC = Unix 1 780 272 000 s.
    const MIDNIGHT_UNIX: i64 = 1_780_272_000;

    fn gps_of_unix(unix_ns: i64) -> i64 {
        unix_ns - GPS_EPOCH_UNIX_S * S + 18 * S
    }

    /// A host clock equal to GPS + 5 s, with a constant 1 ms link delay, learned over 10 s
    /// ending at GPS time `until`.
    fn host_until(until: i64) -> HostClock {
        host_until_with(HostClockConfig::default(), until)
    }

    /// As [`host_until`], with `cfg`.
    fn host_until_with(cfg: HostClockConfig, until: i64) -> HostClock {
        let mut h = HostClock::new(cfg);
        let mut t = until - 10 * S;
        while t <= until {
            h.add(t + 5 * S + MS, t);
            t += 10 * MS;
        }
        h
    }

    fn leap() -> LeapSeconds {
        gps_minus_utc_s(MIDNIGHT_UNIX)
    }

    #[test]
    fn json_ts_across_utc_midnight() {
        let cfg = TtAlignerConfig::default();
        // Module stamps 23:59:59.999 (ts = 86 399 999) for a message received 3 ms later, just
        // after midnight: it belongs to the day before; ts = 2 one ms after midnight.
        let midnight = gps_of_unix(MIDNIGHT_UNIX * S);
        let host = host_until(midnight + 2 * MS);
        for (ts, truth) in [(86_399_999u32, midnight - MS), (2, midnight + 2 * MS)] {
            let rx = Rx {
                host_ns: midnight + 2 * MS + 5 * S + MS,
                wire_len: 0,
                reads: None,
            };
            let a = json_ts(ts, rx, &cfg, &host, leap()).unwrap();
            // Truncated or rounded (issue 18): the mid point of [ts - 0.5, ts + 1) ms, 0.25 ms
            // after the stamp, with the sigma of a uniform 1.5 ms wide: 1.5 / sqrt(12) ms.
            assert_eq!(a.t_gps_ns, truth + MS / 4, "ts {ts}");
            assert_eq!(
                (a.source, a.status),
                (TimeSource::UtcTimeOfDay, ClockStatus::Locked)
            );
            assert!((a.sigma_ns - 433_013.0).abs() < 1.0);
        }
        // The manual's example ts 69 061 337 = 19:11:01.337 UTC, placed on 2026-06-01.
        let t = gps_of_unix((MIDNIGHT_UNIX + 69_061) * S + 337 * MS);
        let host = host_until(t);
        let rx = Rx {
            host_ns: t + 5 * S + 2 * MS,
            wire_len: 0,
            reads: None,
        };
        let a = json_ts(69_061_337, rx, &cfg, &host, leap()).unwrap();
        assert_eq!(a.t_gps_ns, t + MS / 4);
        // Without a host model there is no day.
        let empty = HostClock::new(HostClockConfig::default());
        assert_eq!(
            json_ts(1, rx, &cfg, &empty, leap()),
            Err(NotAligned::HostClockUnknown)
        );
        // A stale table: coasting with 1 s in the sigma.
        let stale = LeapSeconds {
            gps_minus_utc_s: 18,
            table_valid: false,
        };
        let a = json_ts(69_061_337, rx, &cfg, &host, stale).unwrap();
        assert_eq!(a.status, ClockStatus::Coasting);
        // sqrt(0.433 0127 ms^2 + 1 s^2) = 1 s + 93.75 ns.
        assert!(
            (a.sigma_ns - 1_000_000_093.75).abs() < 0.1,
            "{}",
            a.sigma_ns
        );
    }

    #[test]
    fn ts24h_across_midnight_and_ts1s_without_it() {
        let cfg = TtAlignerConfig::default();
        let midnight = gps_of_unix(MIDNIGHT_UNIX * S);
        let host = host_until(midnight + 4 * MS);
        let rx = Rx {
            host_ns: midnight + 4 * MS + 5 * S + MS,
            wire_len: 0,
            reads: None,
        };
        // TS24h 86 399.999 999 5 s: 0.5 us before midnight, the day before.
        let meta = RxMeta {
            ts_utc_ns: Some(86_399_999_999_500),
            ts_pps_ns: Some(999_999_500),
            ..Default::default()
        };
        let a = raw_meta(&meta, rx, &cfg, &host, leap()).unwrap().unwrap();
        assert_eq!(a.t_gps_ns, midnight - 500);
        assert_eq!(a.sigma_ns, 1_000.0);
        // Only TS1s: the same instant from the second of the pulse before it.
        let meta = RxMeta {
            ts_pps_ns: Some(999_999_500),
            ..Default::default()
        };
        let a = raw_meta(&meta, rx, &cfg, &host, leap()).unwrap().unwrap();
        assert_eq!(a.t_gps_ns, midnight - 500);
        assert_eq!(a.source, TimeSource::PpsDisciplined);
        // TS1s 1.5 s: PPS lost, no time; no stamp at all: the caller uses the host clock.
        let meta = RxMeta {
            ts_pps_ns: Some(1_500_000_000),
            ..Default::default()
        };
        assert_eq!(
            raw_meta(&meta, rx, &cfg, &host, leap()),
            Some(Err(NotAligned::BadTimeStamp))
        );
        assert_eq!(raw_meta(&RxMeta::default(), rx, &cfg, &host, leap()), None);
        // TS24h past a day plus a leap second.
        let meta = RxMeta {
            ts_utc_ns: Some(86_401 * S as u64),
            ..Default::default()
        };
        assert_eq!(
            raw_meta(&meta, rx, &cfg, &host, leap()),
            Some(Err(NotAligned::BadTimeStamp))
        );
    }

    /// TS1s counts from the pulse that started the second the frame was received in: the host
    /// clock names that second from the frame's send time less the output delay and TS1s; a TS1s
    /// of 1.1 s or more (no pulse for that long) is no stamp; a host clock too uncertain to name
    /// the second (sigma over 0.1 s) gives none.
    #[test]
    fn ts1s_names_its_pulse_second_through_the_output_delay() {
        let midnight = gps_of_unix(MIDNIGHT_UNIX * S);
        // Received 300 ms after the pulse at midnight, sent 400 ms later (output delay), at
        // 700 ms: midnight + 700 - 400 - 300 ms is the pulse (adding the delay instead would
        // give 800 ms, the next second).
        let mut cfg = TtAlignerConfig::default();
        cfg.link.output_delay_ns = 400 * MS;
        let host = host_until(midnight + 700 * MS);
        let rx = Rx {
            host_ns: midnight + 700 * MS + 5 * S + MS,
            wire_len: 0,
            reads: None,
        };
        let ts1s = |ns: u64| RxMeta {
            ts_pps_ns: Some(ns),
            ..Default::default()
        };
        let a = raw_meta(&ts1s(300_000_000), rx, &cfg, &host, leap())
            .unwrap()
            .unwrap();
        assert_eq!(a.t_gps_ns, midnight + 300 * MS);
        // 1.1 s less 1 ns since the pulse: a stamp (the pulse at midnight - 1 s: 0.7 - 0.4 -
        // 1.1 = -0.8 s rounds to -1 s); 1.1 s: none.
        let a = raw_meta(&ts1s(1_099_999_999), rx, &cfg, &host, leap())
            .unwrap()
            .unwrap();
        assert_eq!(a.t_gps_ns, midnight - S + 1_099_999_999);
        assert_eq!(
            raw_meta(&ts1s(1_100_000_000), rx, &cfg, &host, leap()),
            Some(Err(NotAligned::BadTimeStamp))
        );
        // A host clock whose references are uncertain by 0.2 s cannot name the second; 0.05 s
        // can, and so can exactly 0.1 s (these references fit a line exactly, and the sample is
        // at the last of them: no other term in the sigma).
        for (sigma_ns, ok) in [(0.2e9, false), (0.05e9, true), (0.1e9, true)] {
            let host = host_until_with(
                HostClockConfig {
                    reference_delay_sigma_ns: sigma_ns,
                    ..HostClockConfig::default()
                },
                midnight + 700 * MS,
            );
            let got = raw_meta(&ts1s(300_000_000), rx, &cfg, &host, leap()).unwrap();
            match got {
                Ok(a) => assert!(ok && a.t_gps_ns == midnight + 300 * MS, "{a:?}"),
                Err(e) => assert!(!ok && e == NotAligned::ClockUnlocked, "{e:?}"),
            }
        }
    }
}
