//! `vigil monitor`: the integrity monitor as a separate process (issue 10, "monitor/"). It
//! subscribes over iceoryx2 to `attitude`, `ownship`, `traffic` and `integrity`, runs the same
//! [`Monitor`] as `vigil run`, and publishes each alert state change on `vigil/alerts`.
//!
//! - Thresholds: the `[monitor]` section of `--config FILE` (the rest of the file is ignored, so
//!   `vigil run`'s own configuration file serves), defaults without it.
//! - Clock: the newest payload GPS time seen, advanced by the host monotonic time elapsed since
//!   that payload arrived. Decision: the brief says "the newest payload GPS time"; without the
//!   advance, a monitor whose every feed stops would stand still at the last time and never say
//!   that the feeds went silent, which is the one thing it must say then. While payloads flow the
//!   advance is the (sub-millisecond) delivery delay. Before the first payload with a GPS time
//!   the monitor has no time and evaluates nothing. Payloads with `gps_time_ns` 0 (unknown) are
//!   judged but do not move the clock.
//! - Evaluation: after every received payload (so a one-sample condition such as the BAHRS
//!   "integrity risk" flag is seen even when several payloads arrive at once), and every 10 ms
//!   while idle (the wait on the attitude topic's event times out then; the other topics are
//!   drained at each wake-up, so they wait at most that long).
//! - No silent loss of alerts: the alerts topic never overwrites an unread alert (see
//!   `vigil_bus::policy`). An alert the publisher cannot send (no sample to loan) stays queued and
//!   is retried at each wake-up (at most [`MAX_QUEUED`] are kept: beyond that the oldest are
//!   dropped, counted and reported, so a publisher that never recovers cannot exhaust memory);
//!   deliveries that failed because a subscriber's buffer was full are counted by the publisher
//!   and reported on stderr as they happen and at exit.
//! - SIGINT/SIGTERM end it cleanly (iceoryx2's signal handling, [`Bus::termination_requested`]),
//!   after one last attempt to send what is queued. A summary line goes to stderr at exit.

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use clap::Args;
use vigil_bus::clock::monotonic_ns;
use vigil_bus::{
    AlertPayload, AttitudePayload, Bus, BusConfig, IntegrityPayload, OwnshipPayload, Payload,
    Publisher, Topic, TopicSubscriber,
};
use vigil_monitor::{GpsClock, Monitor, MonitorParams};
use vigil_service::json_names::{Code, code_word};

/// Arguments of `vigil monitor`.
#[derive(Debug, Args)]
pub struct MonitorArgs {
    /// Deployment prefix of the service names (as in the publisher's configuration).
    #[arg(long, default_value = "")]
    pub prefix: String,
    /// TOML configuration file; only its `[monitor]` section is read.
    #[arg(long)]
    pub config: Option<PathBuf>,
    /// Stop after this many seconds (default: until SIGINT/SIGTERM).
    #[arg(long)]
    pub duration: Option<f64>,
}

/// Reads the `[monitor]` section of a TOML file (defaults when it has none) and validates it.
pub fn load_params(path: &Path) -> Result<MonitorParams> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut doc: toml::Table =
        toml::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
    let params = match doc.remove("monitor") {
        None => MonitorParams::default(),
        Some(section) => section
            .try_into()
            .with_context(|| format!("{}: in [monitor]", path.display()))?,
    };
    params
        .validate()
        .with_context(|| format!("{}", path.display()))?;
    Ok(params)
}

/// Most alerts kept waiting for the publisher.
pub const MAX_QUEUED: usize = 4096;

/// Appends `alerts` to `queue`, keeping at most `max`: the oldest beyond that are dropped.
/// Returns how many were dropped.
fn enqueue(queue: &mut VecDeque<AlertPayload>, alerts: Vec<AlertPayload>, max: usize) -> u64 {
    queue.extend(alerts);
    let excess = queue.len().saturating_sub(max);
    queue.drain(..excess);
    excess as u64
}

/// The monitor, its clock and the alerts waiting to be published.
struct Runner {
    monitor: Monitor,
    clock: GpsClock,
    queue: VecDeque<AlertPayload>,
    /// Alerts dropped from a full queue.
    dropped: u64,
}

impl Runner {
    /// Evaluates at the clock's current time, if it has one, and queues the changes.
    fn poll(&mut self) {
        if let Some(t) = self.clock.now(monotonic_ns()) {
            let dropped = enqueue(&mut self.queue, self.monitor.poll(t), MAX_QUEUED);
            if dropped > 0 {
                self.dropped += dropped;
                eprintln!(
                    "vigil monitor: {dropped} unpublished alerts dropped from a full queue \
                     ({} in all)",
                    self.dropped
                );
            }
        }
    }

    /// Takes every waiting sample of `sub`, feeding each to the monitor and evaluating after it.
    /// Returns the number taken.
    fn drain<S: TopicSubscriber>(
        &mut self,
        sub: &mut S,
        feed: impl Fn(&mut Monitor, &S::Payload),
    ) -> Result<usize> {
        let mut n = 0;
        while let Some(r) = sub.receive_copy()? {
            self.clock
                .observe(r.payload.header().gps_time_ns, r.receive_mono_ns);
            feed(&mut self.monitor, &r.payload);
            self.poll();
            n += 1;
        }
        Ok(n)
    }

    /// Publishes the queue in order; stops at the first failure (retried at the next call).
    fn publish(&mut self, publ: &mut Publisher<AlertPayload>, sent: &mut u64) {
        while let Some(a) = self.queue.front() {
            match publ.publish(a) {
                Ok(subscribers) => {
                    eprintln!(
                        "vigil monitor: {} 0x{:08X} {} to {subscribers} subscriber(s): {}",
                        state_name(a.state),
                        a.alert_id,
                        severity_name(a.severity),
                        a.reason()
                    );
                    *sent += 1;
                    self.queue.pop_front();
                }
                Err(e) => {
                    eprintln!(
                        "vigil monitor: cannot publish an alert ({} queued, retrying): {e}",
                        self.queue.len()
                    );
                    break;
                }
            }
        }
    }
}

/// The word of an alert state (the table of `vigil_service::json_names`).
fn state_name(state: u8) -> &'static str {
    code_word(Code::AlertState, u64::from(state)).unwrap_or("state?")
}

/// The word of a severity (the table of `vigil_service::json_names`).
fn severity_name(severity: u8) -> &'static str {
    code_word(Code::Severity, u64::from(severity)).unwrap_or("severity?")
}

/// Runs `vigil monitor`.
pub fn run(args: &MonitorArgs) -> Result<()> {
    let params = match &args.config {
        Some(path) => load_params(path)?,
        None => MonitorParams::default(),
    };
    if let Some(d) = args.duration
        && !(d.is_finite() && d >= 0.0)
    {
        bail!("--duration {d}: expected a finite number of seconds >= 0");
    }
    let mut bus = Bus::new(&BusConfig {
        prefix: args.prefix.clone(),
        node_name: "vigil-monitor".to_string(),
        handle_signals: true,
        ..BusConfig::default()
    })
    .context("connecting to the bus")?;
    // iceoryx2 installs its SIGINT/SIGTERM handlers at the first question about them: ask now, so
    // a signal from here on ends the loop cleanly instead of killing the process.
    if bus.termination_requested() {
        return Ok(());
    }
    let mut attitude = bus
        .subscriber::<AttitudePayload>()
        .context("subscribing to attitude")?;
    let mut ownship = bus
        .subscriber::<OwnshipPayload>()
        .context("subscribing to ownship")?;
    let mut traffic = bus.traffic_subscriber().context("subscribing to traffic")?;
    let mut integrity = bus
        .subscriber::<IntegrityPayload>()
        .context("subscribing to integrity")?;
    let mut publ = bus
        .publisher::<AlertPayload>()
        .context("creating the alerts publisher")?;
    eprintln!(
        "vigil monitor: running: {} -> {}",
        ["attitude", "ownship", "traffic", "integrity"]
            .map(|t| vigil_bus::service_name(&args.prefix, t))
            .join(", "),
        Topic::Alerts.service_name(&args.prefix)
    );
    let deadline = args
        .duration
        .map(|s| Instant::now() + Duration::from_secs_f64(s));
    let mut runner = Runner {
        monitor: Monitor::new(params),
        clock: GpsClock::default(),
        queue: VecDeque::new(),
        dropped: 0,
    };
    let (mut sent, mut failed_seen, mut received) = (0u64, 0u64, 0usize);
    loop {
        // Slow topics first, so the attitude (the fastest) is judged with the latest of them.
        let mut n = runner.drain(&mut integrity, Monitor::integrity)?;
        n += runner.drain(&mut ownship, Monitor::ownship)?;
        n += runner.drain(&mut traffic, Monitor::traffic)?;
        n += runner.drain(&mut attitude, Monitor::attitude)?;
        if n == 0 {
            runner.poll();
        }
        received += n;
        runner.publish(&mut publ, &mut sent);
        let failed = publ.failed_deliveries();
        if failed > failed_seen {
            eprintln!(
                "vigil monitor: {} alert deliveries failed (a subscriber's buffer was full)",
                failed - failed_seen
            );
            failed_seen = failed;
        }
        if bus.termination_requested() || deadline.is_some_and(|d| Instant::now() >= d) {
            break;
        }
        bus.cleanup_if_due();
        // A signal interrupts the wait (iceoryx2 returns an error for it): then stop cleanly.
        if let Err(e) = attitude.wait(Duration::from_millis(10)) {
            if bus.termination_requested() {
                break;
            }
            return Err(e).context("waiting for payloads");
        }
    }
    runner.publish(&mut publ, &mut sent);
    eprintln!(
        "vigil monitor: stopped; {received} payloads received ({} missed), {sent} alerts \
         published, {} unsent, {} dropped unsent, {} failed deliveries, {} alerts active",
        attitude.missed() + ownship.missed() + traffic.missed() + integrity.missed(),
        runner.queue.len(),
        runner.dropped,
        publ.failed_deliveries(),
        runner.monitor.active().count()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_queue_keeps_the_newest_and_counts_what_it_drops() {
        let alert = |id| AlertPayload {
            alert_id: id,
            ..AlertPayload::default()
        };
        let mut q = VecDeque::new();
        assert_eq!(enqueue(&mut q, vec![alert(1), alert(2)], 3), 0);
        assert_eq!(enqueue(&mut q, vec![alert(3), alert(4), alert(5)], 3), 2);
        let ids: Vec<u32> = q.iter().map(|a| a.alert_id).collect();
        assert_eq!(ids, [3, 4, 5]);
    }

    #[test]
    fn params_come_from_the_monitor_section_only() {
        let dir = std::env::temp_dir().join(format!("vigil-monitor-unit-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.toml");
        std::fs::write(
            &path,
            "[ports]\nbahrs = \"/dev/x\"\n[monitor]\nfeed_silent_s = 4.5\n[monitor.gnss_lost]\nlatch = true\n",
        )
        .unwrap();
        let p = load_params(&path).unwrap();
        assert_eq!(p.feed_silent_s, 4.5);
        assert!(p.gnss_lost.latch);
        assert_eq!(p.gnss_lost.raise_delay_s, 1.0);
        std::fs::write(&path, "[monitor]\nfeed_silent_s = -1.0\n").unwrap();
        let e = format!("{:#}", load_params(&path).unwrap_err());
        assert!(e.contains("monitor.feed_silent_s = -1"), "{e}");
        std::fs::write(&path, "[monitor]\nfeed_silence = 1.0\n").unwrap();
        let e = format!("{:#}", load_params(&path).unwrap_err());
        assert!(e.contains("feed_silence"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
