//! The publisher and subscriber wrappers: services built from [`crate::policy`], event wake-up,
//! sequence numbers, send timestamps, gap counting and dead-node cleanup.

use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use iceoryx2::identifiers::UniquePublisherId;
use iceoryx2::node::{Node, NodeBuilder};
use iceoryx2::port::BackpressureAction;
use iceoryx2::port::listener::{Listener, ListenerWaitError};
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher as IoxPublisher;
use iceoryx2::port::subscriber::Subscriber as IoxSubscriber;
use iceoryx2::prelude::{
    BackpressureStrategy, CallbackProgression, NodeName, ServiceName, SignalHandlingMode, ipc,
};
use iceoryx2::sample::Sample;
use iceoryx2::service::Service as _;
use iceoryx2::service::port_factory::PortFactory as _;
use iceoryx2::service::port_factory::event::PortFactory as EventFactory;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as PubSubFactory;

use crate::clock::monotonic_ns;
use crate::names::SERVICE_ROOT;
use crate::payload::{Payload, SCHEMA_VERSION};
use crate::policy::Overflow;

/// A failure of the bus, with the service it concerns.
#[derive(Debug, thiserror::Error)]
pub enum BusError {
    /// A name was rejected by iceoryx2 (bad characters or too long).
    #[error("invalid iceoryx2 name {name:?}: {reason}")]
    InvalidName {
        /// The rejected name.
        name: String,
        /// iceoryx2's reason.
        reason: String,
    },
    /// An iceoryx2 operation failed.
    #[error("{op} on {service}: {reason}")]
    Iceoryx {
        /// What was attempted (e.g. "open publish-subscribe service").
        op: &'static str,
        /// Service name (or node name).
        service: String,
        /// iceoryx2's error.
        reason: String,
    },
}

fn iox<E: core::fmt::Debug>(op: &'static str, service: &str) -> impl FnOnce(E) -> BusError {
    move |e| BusError::Iceoryx {
        op,
        service: service.to_string(),
        reason: format!("{e:?}"),
    }
}

/// Smallest subscriber buffer of the lossless mode, samples (see [`BusConfig::lossless_wait_s`]).
pub const LOSSLESS_BUFFER: usize = 64;

/// Bus settings of one process.
#[derive(Debug, Clone)]
pub struct BusConfig {
    /// Deployment prefix of every service name (empty: plain `vigil/...`).
    pub prefix: String,
    /// iceoryx2 node name (shows in iceoryx2's tools), e.g. `"vigil-run"`.
    pub node_name: String,
    /// Let iceoryx2 catch SIGINT/SIGTERM so [`Bus::termination_requested`] reports them. Off for a
    /// program that handles signals itself (`vigil run` with tokio).
    pub handle_signals: bool,
    /// Period of [`Bus::cleanup_if_due`], s.
    pub cleanup_period_s: f64,
    /// Regression-test mode (`vigil replay --publish --speed max`): `Some(wait_s)` makes every
    /// topic lossless: no safe overflow, and a publisher whose subscriber's buffer is full waits
    /// for it to read, up to `wait_s` per sample, before discarding and counting (so a dead
    /// subscriber cannot hang the replay). Publisher and subscribers of a prefix must all use the
    /// same mode (iceoryx2 refuses to open a service with a different overflow setting). Never
    /// for flight: there a slow consumer must not slow the publisher.
    pub lossless_wait_s: Option<f64>,
}

impl Default for BusConfig {
    fn default() -> Self {
        Self {
            prefix: String::new(),
            node_name: "vigil".to_string(),
            handle_signals: false,
            cleanup_period_s: 1.0,
            lossless_wait_s: None,
        }
    }
}

/// Outcome of one dead-node cleanup.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct CleanupReport {
    /// Dead nodes whose resources were removed.
    pub cleaned: u64,
    /// Dead nodes that could not be cleaned (no permission, or another process was at it).
    pub failed: u64,
}

/// The publish-subscribe and event services of one topic.
type Services<T> = (
    PubSubFactory<ipc::Service, T, ()>,
    EventFactory<ipc::Service>,
);

/// One process's connection to the bus: an iceoryx2 node and the deployment prefix.
///
/// Dead nodes (processes that died without dropping their ports, e.g. after SIGKILL) keep their
/// ports registered until someone cleans them up; a new `Bus` cleans once at creation and
/// [`Bus::cleanup_if_due`] should be called from the owner's periodic task.
pub struct Bus {
    node: Node<ipc::Service>,
    prefix: String,
    cleanup_period: Duration,
    last_cleanup: Instant,
    lossless_wait_ns: Option<u64>,
}

impl Bus {
    /// Creates the node and removes what dead nodes left behind.
    ///
    /// iceoryx2's own log is set to errors only (its default warns on stderr that no config file
    /// was found, which is the normal case); the `IOX2_LOG_LEVEL` environment variable overrides.
    pub fn new(config: &BusConfig) -> Result<Self, BusError> {
        iceoryx2::prelude::set_log_level_from_env_or(iceoryx2::prelude::LogLevel::Error);
        let name = NodeName::new(&config.node_name).map_err(|e| BusError::InvalidName {
            name: config.node_name.clone(),
            reason: format!("{e:?}"),
        })?;
        let mode = if config.handle_signals {
            SignalHandlingMode::HandleTerminationRequests
        } else {
            SignalHandlingMode::Disabled
        };
        let node = NodeBuilder::new()
            .name(&name)
            .signal_handling_mode(mode)
            .create::<ipc::Service>()
            .map_err(iox("create node", &config.node_name))?;
        let bus = Self {
            node,
            prefix: config.prefix.clone(),
            cleanup_period: Duration::from_secs_f64(config.cleanup_period_s.max(0.0)),
            last_cleanup: Instant::now(),
            lossless_wait_ns: config
                .lossless_wait_s
                .map(|s| (s.clamp(0.0, 3600.0) * 1e9) as u64),
        };
        bus.cleanup_dead_nodes();
        if config.handle_signals {
            // iceoryx2 installs its SIGINT/SIGTERM handlers on the first wait, not when the node
            // is created: wait once now, so a signal right after start is caught (and reported by
            // `termination_requested`) instead of killing the process.
            let _ = bus.node.wait(Duration::ZERO);
        }
        Ok(bus)
    }

    /// The deployment prefix.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// Removes the resources of every dead node of the host and disconnects their ports. Does not
    /// wait for a node another process is already cleaning.
    pub fn cleanup_dead_nodes(&self) -> CleanupReport {
        let s = self.node.try_cleanup_dead_nodes();
        CleanupReport {
            cleaned: s.cleanups,
            failed: s.failed_cleanups,
        }
    }

    /// Runs [`Bus::cleanup_dead_nodes`] when the cleanup period has passed since the last one.
    pub fn cleanup_if_due(&mut self) -> Option<CleanupReport> {
        if self.last_cleanup.elapsed() < self.cleanup_period {
            return None;
        }
        self.last_cleanup = Instant::now();
        Some(self.cleanup_dead_nodes())
    }

    /// The deployment prefixes under which vigil services exist on this host now (`""` for the
    /// default names), sorted, each once: what `vigil listen` suggests when nothing publishes
    /// under the prefix it was given. A service is vigil's when its name is `[PREFIX/]vigil/...`.
    pub fn prefixes_in_use(&self) -> Result<Vec<String>, BusError> {
        let mut prefixes = Vec::new();
        let root = format!("{SERVICE_ROOT}/");
        ipc::Service::list(self.node.config(), |s| {
            let name = s.static_details.name().as_str();
            let prefix = if name.starts_with(&root) {
                Some("")
            } else {
                name.find(&format!("/{root}")).map(|i| &name[..i])
            };
            if let Some(p) = prefix
                && !prefixes.iter().any(|q: &String| q == p)
            {
                prefixes.push(p.to_string());
            }
            CallbackProgression::Continue
        })
        .map_err(iox("list services", "*"))?;
        prefixes.sort();
        Ok(prefixes)
    }

    /// True once SIGINT or SIGTERM arrived (only with [`BusConfig::handle_signals`]).
    pub fn termination_requested(&self) -> bool {
        self.node.wait(Duration::ZERO).is_err()
    }

    fn services<T: Payload>(&self) -> Result<Services<T>, BusError> {
        let topic = T::TOPIC;
        let policy = topic.policy();
        let name = topic.service_name(&self.prefix);
        let sname = ServiceName::new(&name).map_err(|e| BusError::InvalidName {
            name: name.clone(),
            reason: format!("{e:?}"),
        })?;
        let pubsub = self
            .node
            .service_builder(&sname)
            .publish_subscribe::<T>()
            .enable_safe_overflow(
                policy.overflow == Overflow::LatestWins && self.lossless_wait_ns.is_none(),
            )
            .subscriber_max_buffer_size(self.buffer_size(&policy))
            .history_size(policy.history_size)
            .subscriber_max_borrowed_samples(policy.max_borrowed)
            .max_subscribers(policy.max_subscribers)
            .max_publishers(policy.max_publishers)
            .max_nodes(policy.max_nodes)
            .open_or_create()
            .map_err(iox("open publish-subscribe service", &name))?;
        let ename = topic.event_name(&self.prefix);
        let esname = ServiceName::new(&ename).map_err(|e| BusError::InvalidName {
            name: ename.clone(),
            reason: format!("{e:?}"),
        })?;
        let event = self
            .node
            .service_builder(&esname)
            .event()
            .max_notifiers(policy.max_publishers)
            .max_listeners(policy.max_subscribers)
            .max_nodes(policy.max_nodes)
            .open_or_create()
            .map_err(iox("open event service", &ename))?;
        Ok((pubsub, event))
    }

    /// A subscriber's buffer: the topic's, or in the lossless mode at least
    /// [`LOSSLESS_BUFFER`] samples. Decision: iceoryx2 0.10 retries a full buffer (the wait of the
    /// lossless mode) but drops a sample silently when the connection's list of chunks in use is
    /// full, which a subscriber that lags while holding samples can cause (seen under heavy load);
    /// a deep buffer keeps a lagging subscriber in the retried case.
    fn buffer_size(&self, policy: &crate::policy::Policy) -> usize {
        if self.lossless_wait_ns.is_some() {
            policy.buffer_size.max(LOSSLESS_BUFFER)
        } else {
            policy.buffer_size
        }
    }

    /// Creates a publisher of `T` on its topic's service.
    pub fn publisher<T: Payload>(&self) -> Result<Publisher<T>, BusError> {
        let name = T::TOPIC.service_name(&self.prefix);
        let (pubsub, event) = self.services::<T>()?;
        let failed = Arc::new(AtomicU64::new(0));
        let counter = Arc::clone(&failed);
        let send_started = Arc::new(AtomicU64::new(0));
        let started = Arc::clone(&send_started);
        let wait_ns = self.lossless_wait_ns;
        // In flight, never wait for a subscriber: a full buffer (alerts only; state topics
        // overflow) makes the delivery to that subscriber fail at once, counted here. In the
        // lossless regression mode, wait for the subscriber (bounded), then the same.
        let inner = pubsub
            .publisher_builder()
            .backpressure_strategy(BackpressureStrategy::DiscardData)
            .set_backpressure_handler(move |_info: &iceoryx2::port::BackpressureInfo| {
                if let Some(wait) = wait_ns
                    && monotonic_ns().saturating_sub(started.load(Ordering::Relaxed)) < wait
                {
                    std::thread::sleep(Duration::from_micros(50));
                    return BackpressureAction::Retry;
                }
                counter.fetch_add(1, Ordering::Relaxed);
                BackpressureAction::DiscardData
            })
            .create()
            .map_err(iox("create publisher", &name))?;
        let notifier = event
            .notifier_builder()
            .create()
            .map_err(iox("create notifier", &name))?;
        Ok(Publisher {
            inner,
            notifier,
            _pubsub: pubsub,
            _event: event,
            next_seq: 1,
            failed,
            send_started,
            lossless_wait_ns: self.lossless_wait_ns,
            notify_failures: 0,
        })
    }

    /// Creates a subscriber of `T` on its topic's service; it receives the topic's history first.
    pub fn subscriber<T: Payload>(&self) -> Result<Subscriber<T>, BusError> {
        let name = T::TOPIC.service_name(&self.prefix);
        let policy = T::TOPIC.policy();
        let (pubsub, event) = self.services::<T>()?;
        let inner = pubsub
            .subscriber_builder()
            .buffer_size(self.buffer_size(&policy))
            .create()
            .map_err(iox("create subscriber", &name))?;
        let listener = event
            .listener_builder()
            .create()
            .map_err(iox("create listener", &name))?;
        Ok(Subscriber {
            inner,
            listener,
            pubsub,
            _event: event,
            last_seq: Vec::new(),
            missed: 0,
            received: 0,
        })
    }
}

/// Publishes one payload type; stamps the header, sends, and wakes the subscribers.
pub struct Publisher<T: Payload> {
    inner: IoxPublisher<ipc::Service, T, ()>,
    notifier: Notifier<ipc::Service>,
    _pubsub: PubSubFactory<ipc::Service, T, ()>,
    _event: EventFactory<ipc::Service>,
    next_seq: u64,
    failed: Arc<AtomicU64>,
    /// Host monotonic time the current send started, ns (for the lossless wait).
    send_started: Arc<AtomicU64>,
    /// The lossless mode's bounded wait, ns (see [`BusConfig::lossless_wait_s`]).
    lossless_wait_ns: Option<u64>,
    notify_failures: u64,
}

impl<T: Payload> Publisher<T> {
    /// Sends a copy of `value` (its header's `gps_time_ns` is kept; the rest is stamped). Returns
    /// the number of subscribers it was delivered to.
    pub fn publish(&mut self, value: &T) -> Result<usize, BusError> {
        self.publish_with(|p| *p = *value)
    }

    /// Loans a sample in shared memory, lets `fill` write it in place (it starts as
    /// `T::default()`), stamps the header and sends it: the way to publish the large traffic
    /// payload without building it elsewhere first. Returns the number of subscribers reached.
    pub fn publish_with(&mut self, fill: impl FnOnce(&mut T)) -> Result<usize, BusError> {
        let service = T::TOPIC.as_str();
        // In the lossless mode a slow subscriber can still hold every sample of the publisher's
        // segment (its buffer plus what it has borrowed): the loan then fails until it releases
        // one, so the loan is retried within the same bounded wait as a full buffer.
        let loan_deadline = self
            .lossless_wait_ns
            .map(|w| monotonic_ns().saturating_add(w));
        let mut sample = loop {
            match self.inner.loan() {
                Ok(s) => break s,
                Err(_) if loan_deadline.is_some_and(|d| monotonic_ns() < d) => {
                    std::thread::sleep(Duration::from_micros(50));
                }
                Err(e) => return Err(iox("loan sample", service)(e)),
            }
        };
        let payload = sample.payload_mut();
        fill(payload);
        let h = payload.header_mut();
        h.schema_version = SCHEMA_VERSION;
        h.reserved = 0;
        h.seq = self.next_seq;
        h.send_mono_ns = monotonic_ns();
        self.next_seq += 1;
        self.send_started.store(h.send_mono_ns, Ordering::Relaxed);
        let delivered = sample.send().map_err(iox("send", service))?;
        // A failed wake-up (e.g. a listener that died) must not fail the publication: the sample
        // is in the subscribers' buffers and they find it at their next wait timeout.
        if self.notifier.notify().is_err() {
            self.notify_failures += 1;
        }
        Ok(delivered)
    }

    /// Sequence number the next sample will carry.
    pub fn next_seq(&self) -> u64 {
        self.next_seq
    }

    /// Deliveries that failed because a subscriber's buffer was full (alerts), since creation.
    pub fn failed_deliveries(&self) -> u64 {
        self.failed.load(Ordering::Relaxed)
    }

    /// Wake-up notifications that failed, since creation.
    pub fn notify_failures(&self) -> u64 {
        self.notify_failures
    }
}

/// A received sample, read in place in shared memory, with what the subscriber learnt from it.
///
/// It borrows a slot of the publisher's shared memory until dropped: a subscriber may hold at most
/// the topic's [`crate::policy::Policy::max_borrowed`] at once (receiving more fails), so copy out
/// what must be kept and drop it.
pub struct Received<T: Payload> {
    sample: Sample<ipc::Service, T, ()>,
    /// Samples of the same publisher missed just before this one (gap in `header.seq`).
    pub missed_before: u64,
    /// Host monotonic time when it was received, ns.
    pub receive_mono_ns: u64,
}

impl<T: Payload> Received<T> {
    /// The payload.
    pub fn payload(&self) -> &T {
        self.sample.payload()
    }

    /// Latency from the publisher's send stamp to reception, ns (0 if the clocks disagree).
    pub fn latency_ns(&self) -> u64 {
        self.receive_mono_ns
            .saturating_sub(self.payload().header().send_mono_ns)
    }
}

impl<T: Payload> core::ops::Deref for Received<T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.payload()
    }
}

/// Receives one payload type, waits on the topic's event service, counts sequence gaps.
pub struct Subscriber<T: Payload> {
    inner: IoxSubscriber<ipc::Service, T, ()>,
    listener: Listener<ipc::Service>,
    pubsub: PubSubFactory<ipc::Service, T, ()>,
    _event: EventFactory<ipc::Service>,
    /// Last sequence number seen per publisher (a topic may have several: alerts).
    last_seq: Vec<(UniquePublisherId, u64)>,
    missed: u64,
    received: u64,
}

impl<T: Payload> Subscriber<T> {
    /// Takes the next sample without waiting.
    pub fn try_receive(&mut self) -> Result<Option<Received<T>>, BusError> {
        let Some(sample) = self
            .inner
            .receive()
            .map_err(iox("receive", T::TOPIC.as_str()))?
        else {
            return Ok(None);
        };
        let receive_mono_ns = monotonic_ns();
        let seq = sample.payload().header().seq;
        let origin = sample.origin();
        let missed_before = match self.last_seq.iter_mut().find(|(o, _)| *o == origin) {
            Some((_, last)) => {
                // A lower or equal number means the publisher restarted: no gap to report.
                let gap = seq.saturating_sub(last.saturating_add(1));
                *last = seq;
                gap
            }
            None => {
                // First sample of this publisher: history may start anywhere, so no gap.
                self.last_seq.push((origin, seq));
                0
            }
        };
        self.missed += missed_before;
        self.received += 1;
        Ok(Some(Received {
            sample,
            missed_before,
            receive_mono_ns,
        }))
    }

    /// Waits up to `timeout` for the publisher's wake-up (returns at once when one is pending).
    /// Returns true when woken. Wake-ups may be merged; drain with [`Subscriber::try_receive`].
    ///
    /// A SIGINT or SIGTERM (with [`BusConfig::handle_signals`]) ends the wait as a timeout does:
    /// the caller asks [`Bus::termination_requested`] and stops quietly, instead of reporting the
    /// interrupted wait as an error.
    pub fn wait(&self, timeout: Duration) -> Result<bool, BusError> {
        match self.listener.timed_wait(|_| {}, timeout) {
            Ok(n) => Ok(n > 0),
            Err(ListenerWaitError::InterruptSignal) => Ok(false),
            Err(e) => Err(iox("wait", T::TOPIC.as_str())(e)),
        }
    }

    /// Publishers connected to the topic's service now (0: nothing publishes there).
    pub fn publishers(&self) -> usize {
        self.pubsub.dynamic_config().number_of_publishers()
    }

    /// The next sample, waiting up to `timeout` for one.
    pub fn receive_timeout(&mut self, timeout: Duration) -> Result<Option<Received<T>>, BusError> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(r) = self.try_receive()? {
                return Ok(Some(r));
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            self.wait(deadline - now)?;
        }
    }

    /// Samples received since creation.
    pub fn received(&self) -> u64 {
        self.received
    }

    /// Samples missed (sequence gaps) since creation, over all publishers.
    pub fn missed(&self) -> u64 {
        self.missed
    }
}
