//! The publisher and subscriber wrappers: services built from [`crate::policy`], event wake-up,
//! sequence numbers, send timestamps, gap counting and dead-node cleanup.

use core::fmt::Debug;
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
    AllocationStrategy, BackpressureStrategy, CallbackProgression, IceoryxSend, NodeName,
    ServiceName, SignalHandlingMode, ZeroCopySend, ipc,
};
use iceoryx2::sample::Sample;
use iceoryx2::service::Service as _;
use iceoryx2::service::builder::publish_subscribe::Builder as PubSubBuilder;
use iceoryx2::service::port_factory::PortFactory as _;
use iceoryx2::service::port_factory::event::PortFactory as EventFactory;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as PubSubFactory;
use iceoryx2::service::port_factory::publisher::PortFactoryPublisher;

use crate::clock::monotonic_ns;
use crate::names::SERVICE_ROOT;
use crate::names::Topic;
use crate::payload::traffic::{MAX_TARGETS, Target, TrafficHeader, TrafficPayload};
use crate::payload::{FixedPayload, Header, Payload, SCHEMA_VERSION};
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

/// The publish-subscribe and event services of one topic: `B` is what iceoryx2 carries (a
/// fixed payload, or the slice of targets), `M` its user header.
type Services<B, M> = (
    PubSubFactory<ipc::Service, B, M>,
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

    fn service_name(&self, name: &str) -> Result<ServiceName, BusError> {
        ServiceName::new(name).map_err(|e| BusError::InvalidName {
            name: name.to_string(),
            reason: format!("{e:?}"),
        })
    }

    /// The publish-subscribe builder of `topic` with its policy applied; the caller opens it
    /// (iceoryx2 opens fixed and slice services through different methods).
    fn pubsub_builder<B, M>(
        &self,
        topic: Topic,
    ) -> Result<PubSubBuilder<B, M, ipc::Service>, BusError>
    where
        B: Debug + IceoryxSend + ?Sized,
        M: Debug + ZeroCopySend,
    {
        let policy = topic.policy();
        let sname = self.service_name(&topic.service_name(&self.prefix))?;
        Ok(self
            .node
            .service_builder(&sname)
            .publish_subscribe::<B>()
            .user_header::<M>()
            .enable_safe_overflow(
                policy.overflow == Overflow::LatestWins && self.lossless_wait_ns.is_none(),
            )
            .subscriber_max_buffer_size(self.buffer_size(&policy))
            .history_size(policy.history_size)
            .subscriber_max_borrowed_samples(policy.max_borrowed)
            .max_subscribers(policy.max_subscribers)
            .max_publishers(policy.max_publishers)
            .max_nodes(policy.max_nodes))
    }

    /// The event service that wakes `topic`'s subscribers.
    fn event_service(&self, topic: Topic) -> Result<EventFactory<ipc::Service>, BusError> {
        let policy = topic.policy();
        let ename = topic.event_name(&self.prefix);
        self.node
            .service_builder(&self.service_name(&ename)?)
            .event()
            .max_notifiers(policy.max_publishers)
            .max_listeners(policy.max_subscribers)
            .max_nodes(policy.max_nodes)
            .open_or_create()
            .map_err(iox("open event service", &ename))
    }

    fn services<T: FixedPayload>(&self) -> Result<Services<T, ()>, BusError> {
        let name = T::TOPIC.service_name(&self.prefix);
        let pubsub = self
            .pubsub_builder::<T, ()>(T::TOPIC)?
            .open_or_create()
            .map_err(iox("open publish-subscribe service", &name))?;
        Ok((pubsub, self.event_service(T::TOPIC)?))
    }

    fn traffic_services(&self) -> Result<Services<[Target], TrafficHeader>, BusError> {
        let name = Topic::Traffic.service_name(&self.prefix);
        let pubsub = self
            .pubsub_builder::<[Target], TrafficHeader>(Topic::Traffic)?
            .open_or_create()
            .map_err(iox("open publish-subscribe service", &name))?;
        Ok((pubsub, self.event_service(Topic::Traffic)?))
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

    /// The publisher side shared by every topic: the wake-up notifier, sequence numbers and the
    /// bounded waits of the lossless mode, with the backpressure settings applied to `builder`.
    fn sender<'f, B, M>(
        &self,
        topic: Topic,
        builder: PortFactoryPublisher<'f, ipc::Service, B, M>,
        event: &EventFactory<ipc::Service>,
    ) -> Result<(PortFactoryPublisher<'f, ipc::Service, B, M>, Sender), BusError>
    where
        B: Debug + IceoryxSend + ?Sized,
        M: Debug + ZeroCopySend,
    {
        let name = topic.service_name(&self.prefix);
        let failed = Arc::new(AtomicU64::new(0));
        let counter = Arc::clone(&failed);
        let send_started = Arc::new(AtomicU64::new(0));
        let started = Arc::clone(&send_started);
        let wait_ns = self.lossless_wait_ns;
        // In flight, never wait for a subscriber: a full buffer (alerts only; state topics
        // overflow) makes the delivery to that subscriber fail at once, counted here. In the
        // lossless regression mode, wait for the subscriber (bounded), then the same.
        let builder = builder
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
            });
        let notifier = event
            .notifier_builder()
            .create()
            .map_err(iox("create notifier", &name))?;
        Ok((
            builder,
            Sender {
                topic,
                notifier,
                next_seq: 1,
                failed,
                send_started,
                lossless_wait_ns: self.lossless_wait_ns,
                notify_failures: 0,
                pending: false,
            },
        ))
    }

    /// Creates a publisher of `T` on its topic's service.
    pub fn publisher<T: FixedPayload>(&self) -> Result<Publisher<T>, BusError> {
        let name = T::TOPIC.service_name(&self.prefix);
        let (pubsub, event) = self.services::<T>()?;
        let (builder, sender) = self.sender(T::TOPIC, pubsub.publisher_builder(), &event)?;
        let inner = builder.create().map_err(iox("create publisher", &name))?;
        Ok(Publisher {
            inner,
            sender,
            _pubsub: pubsub,
            _event: event,
        })
    }

    /// Creates the traffic publisher: pictures go out as a slice of targets sized by their
    /// count. Decision: the service's chunks are sized for [`MAX_TARGETS`] once (static
    /// allocation), so a growing picture never reallocates the segment in flight; a sample
    /// still carries and copies only its `count` targets.
    pub fn traffic_publisher(&self) -> Result<TrafficPublisher, BusError> {
        let name = Topic::Traffic.service_name(&self.prefix);
        let (pubsub, event) = self.traffic_services()?;
        let builder = pubsub
            .publisher_builder()
            .initial_max_slice_len(MAX_TARGETS)
            .allocation_strategy(AllocationStrategy::Static);
        let (builder, sender) = self.sender(Topic::Traffic, builder, &event)?;
        let inner = builder.create().map_err(iox("create publisher", &name))?;
        Ok(TrafficPublisher {
            inner,
            sender,
            _pubsub: pubsub,
            _event: event,
        })
    }

    /// The subscriber side shared by every topic: the wake-up listener and the gap counters.
    fn receiver(
        &self,
        topic: Topic,
        event: &EventFactory<ipc::Service>,
    ) -> Result<Receiver, BusError> {
        let listener = event
            .listener_builder()
            .create()
            .map_err(iox("create listener", &topic.service_name(&self.prefix)))?;
        Ok(Receiver {
            topic,
            listener,
            last_seq: Vec::new(),
            missed: 0,
            received: 0,
        })
    }

    /// Creates a subscriber of `T` on its topic's service; it receives the topic's history first.
    pub fn subscriber<T: FixedPayload>(&self) -> Result<Subscriber<T>, BusError> {
        let name = T::TOPIC.service_name(&self.prefix);
        let policy = T::TOPIC.policy();
        let (pubsub, event) = self.services::<T>()?;
        let inner = pubsub
            .subscriber_builder()
            .buffer_size(self.buffer_size(&policy))
            .create()
            .map_err(iox("create subscriber", &name))?;
        Ok(Subscriber {
            inner,
            receiver: self.receiver(T::TOPIC, &event)?,
            pubsub,
            _event: event,
        })
    }

    /// Creates the traffic subscriber; it receives the latest picture first.
    pub fn traffic_subscriber(&self) -> Result<TrafficSubscriber, BusError> {
        let name = Topic::Traffic.service_name(&self.prefix);
        let policy = Topic::Traffic.policy();
        let (pubsub, event) = self.traffic_services()?;
        let inner = pubsub
            .subscriber_builder()
            .buffer_size(self.buffer_size(&policy))
            .create()
            .map_err(iox("create subscriber", &name))?;
        Ok(TrafficSubscriber {
            inner,
            receiver: self.receiver(Topic::Traffic, &event)?,
            pubsub,
            _event: event,
        })
    }
}

/// What every publisher does besides writing its payload: stamps headers with sequence numbers
/// and send times, retries loans in the lossless mode, wakes the subscribers, counts failures.
struct Sender {
    topic: Topic,
    notifier: Notifier<ipc::Service>,
    next_seq: u64,
    failed: Arc<AtomicU64>,
    /// Host monotonic time the current send started, ns (for the lossless wait).
    send_started: Arc<AtomicU64>,
    /// The lossless mode's bounded wait, ns (see [`BusConfig::lossless_wait_s`]).
    lossless_wait_ns: Option<u64>,
    notify_failures: u64,
    /// A sample was sent and its subscribers not woken yet.
    pending: bool,
}

impl Sender {
    /// Runs `loan` until it succeeds; in the lossless mode a failed loan is retried within the
    /// bounded wait. (A slow subscriber can hold every sample of the publisher's segment, its
    /// buffer plus what it has borrowed: the loan fails until it releases one.)
    fn loan<S, E: Debug>(&self, mut loan: impl FnMut() -> Result<S, E>) -> Result<S, BusError> {
        let deadline = self
            .lossless_wait_ns
            .map(|w| monotonic_ns().saturating_add(w));
        loop {
            match loan() {
                Ok(s) => return Ok(s),
                Err(_) if deadline.is_some_and(|d| monotonic_ns() < d) => {
                    std::thread::sleep(Duration::from_micros(50));
                }
                Err(e) => return Err(iox("loan sample", self.topic.as_str())(e)),
            }
        }
    }

    /// Stamps `h` as the next sample of this publisher.
    fn stamp(&mut self, h: &mut Header) {
        h.schema_version = SCHEMA_VERSION;
        h.reserved = 0;
        h.seq = self.next_seq;
        h.send_mono_ns = monotonic_ns();
        self.next_seq += 1;
        self.send_started.store(h.send_mono_ns, Ordering::Relaxed);
    }

    /// Counts a sent sample's outcome and wakes the subscribers now (`wake`), or leaves the
    /// wake-up pending for [`Sender::notify_pending`].
    fn sent<E: Debug>(&mut self, r: Result<usize, E>, wake: bool) -> Result<usize, BusError> {
        let delivered = r.map_err(iox("send", self.topic.as_str()))?;
        self.pending = true;
        if wake {
            self.notify_pending();
        }
        Ok(delivered)
    }

    /// Wakes the subscribers if a sample was sent since the last wake-up: one event (a system
    /// call per listening subscriber) however many samples.
    fn notify_pending(&mut self) {
        if !std::mem::take(&mut self.pending) {
            return;
        }
        // A failed wake-up (e.g. a listener that died) must not fail the publication: the sample
        // is in the subscribers' buffers and they find it at their next wait timeout.
        if self.notifier.notify().is_err() {
            self.notify_failures += 1;
        }
    }
}

/// Publishes one fixed-size payload type; stamps the header, sends, and wakes the subscribers.
pub struct Publisher<T: FixedPayload> {
    inner: IoxPublisher<ipc::Service, T, ()>,
    sender: Sender,
    _pubsub: PubSubFactory<ipc::Service, T, ()>,
    _event: EventFactory<ipc::Service>,
}

impl<T: FixedPayload> Publisher<T> {
    /// Sends a copy of `value` (its header's `gps_time_ns` is kept; the rest is stamped). Returns
    /// the number of subscribers it was delivered to.
    pub fn publish(&mut self, value: &T) -> Result<usize, BusError> {
        self.publish_with(|p| *p = *value)
    }

    /// Loans a sample in shared memory, lets `fill` write it in place (it starts as
    /// `T::default()`), stamps the header and sends it. Returns the number of subscribers
    /// reached.
    pub fn publish_with(&mut self, fill: impl FnOnce(&mut T)) -> Result<usize, BusError> {
        self.send(fill, true)
    }

    /// [`Publisher::publish`] without the wake-up: the sample is delivered, and the subscribers
    /// are woken by the next [`Publisher::notify_pending`] (one event for every sample sent
    /// since; issue 21: a processing step that publishes several samples costs one system call
    /// per subscriber, not one per sample). A subscriber polling without waiting sees the
    /// sample at once.
    pub fn publish_deferred(&mut self, value: &T) -> Result<usize, BusError> {
        self.send(|p| *p = *value, false)
    }

    /// Wakes the subscribers if a sample was sent since the last wake-up.
    pub fn notify_pending(&mut self) {
        self.sender.notify_pending();
    }

    fn send(&mut self, fill: impl FnOnce(&mut T), wake: bool) -> Result<usize, BusError> {
        let mut sample = self.sender.loan(|| self.inner.loan())?;
        let payload = sample.payload_mut();
        fill(payload);
        self.sender.stamp(payload.header_mut());
        self.sender.sent(sample.send(), wake)
    }

    /// Sequence number the next sample will carry.
    pub fn next_seq(&self) -> u64 {
        self.sender.next_seq
    }

    /// Deliveries that failed because a subscriber's buffer was full (alerts), since creation.
    pub fn failed_deliveries(&self) -> u64 {
        self.sender.failed.load(Ordering::Relaxed)
    }

    /// Wake-up notifications that failed, since creation.
    pub fn notify_failures(&self) -> u64 {
        self.sender.notify_failures
    }
}

/// Publishes traffic pictures: a [`TrafficHeader`] and a slice of exactly `count` targets.
pub struct TrafficPublisher {
    inner: IoxPublisher<ipc::Service, [Target], TrafficHeader>,
    sender: Sender,
    _pubsub: PubSubFactory<ipc::Service, [Target], TrafficHeader>,
    _event: EventFactory<ipc::Service>,
}

impl TrafficPublisher {
    /// Sends `picture` (its header's `gps_time_ns` is kept; the rest is stamped): its targets
    /// are copied once, into a loaned slice of their count. Returns the number of subscribers
    /// reached.
    pub fn publish(&mut self, picture: &TrafficPayload) -> Result<usize, BusError> {
        self.send(picture, true)
    }

    /// [`TrafficPublisher::publish`] without the wake-up (see [`Publisher::publish_deferred`]).
    pub fn publish_deferred(&mut self, picture: &TrafficPayload) -> Result<usize, BusError> {
        self.send(picture, false)
    }

    /// Wakes the subscribers if a picture was sent since the last wake-up.
    pub fn notify_pending(&mut self) {
        self.sender.notify_pending();
    }

    fn send(&mut self, picture: &TrafficPayload, wake: bool) -> Result<usize, BusError> {
        let targets = &picture.targets[..picture.targets.len().min(MAX_TARGETS)];
        let sample = self
            .sender
            .loan(|| self.inner.loan_slice_uninit(targets.len()))?;
        let mut sample = sample.write_from_slice(targets);
        let mut h = picture.wire_header();
        h.count = targets.len() as u32;
        self.sender.stamp(&mut h.header);
        *sample.user_header_mut() = h;
        self.sender.sent(sample.send(), wake)
    }

    /// Sequence number the next sample will carry.
    pub fn next_seq(&self) -> u64 {
        self.sender.next_seq
    }
}

/// A received sample, read in place in shared memory, with what the subscriber learnt from it.
///
/// It borrows a slot of the publisher's shared memory until dropped: a subscriber may hold at most
/// the topic's [`crate::policy::Policy::max_borrowed`] at once (receiving more fails), so copy out
/// what must be kept and drop it.
pub struct Received<T: FixedPayload> {
    sample: Sample<ipc::Service, T, ()>,
    /// Samples of the same publisher missed just before this one (gap in `header.seq`).
    pub missed_before: u64,
    /// Host monotonic time when it was received, ns.
    pub receive_mono_ns: u64,
}

impl<T: FixedPayload> Received<T> {
    /// The payload.
    pub fn payload(&self) -> &T {
        self.sample.payload()
    }

    /// Latency from the publisher's send stamp to reception, ns (0 if the clocks disagree).
    pub fn latency_ns(&self) -> u64 {
        latency_ns(self.payload().header(), self.receive_mono_ns)
    }
}

fn latency_ns(h: &Header, receive_mono_ns: u64) -> u64 {
    receive_mono_ns.saturating_sub(h.send_mono_ns)
}

impl<T: FixedPayload> core::ops::Deref for Received<T> {
    type Target = T;
    fn deref(&self) -> &T {
        self.payload()
    }
}

/// A received traffic picture, read in place in shared memory (see [`Received`] on holding it).
pub struct ReceivedTraffic {
    sample: Sample<ipc::Service, [Target], TrafficHeader>,
    /// Samples of the same publisher missed just before this one (gap in `header.seq`).
    pub missed_before: u64,
    /// Host monotonic time when it was received, ns.
    pub receive_mono_ns: u64,
}

impl ReceivedTraffic {
    /// The user header: common header and counts.
    pub fn wire_header(&self) -> &TrafficHeader {
        self.sample.user_header()
    }

    /// The common header.
    pub fn header(&self) -> &Header {
        &self.wire_header().header
    }

    /// Targets not published because the picture was full.
    pub fn dropped(&self) -> u32 {
        self.wire_header().dropped
    }

    /// The targets, most urgent first (the header's count clamped to the slice).
    pub fn targets(&self) -> &[Target] {
        let t = self.sample.payload();
        &t[..(self.wire_header().count as usize).min(t.len())]
    }

    /// A copy of the picture, to keep after the sample is released.
    pub fn to_payload(&self) -> TrafficPayload {
        TrafficPayload::from_wire(self.wire_header(), self.sample.payload())
    }

    /// Latency from the publisher's send stamp to reception, ns (0 if the clocks disagree).
    pub fn latency_ns(&self) -> u64 {
        latency_ns(self.header(), self.receive_mono_ns)
    }
}

/// What every subscriber does besides reading its payload: waits for the publisher's wake-up and
/// counts sequence gaps per publisher.
struct Receiver {
    topic: Topic,
    listener: Listener<ipc::Service>,
    /// Last sequence number seen per publisher (a topic may have several: alerts).
    last_seq: Vec<(UniquePublisherId, u64)>,
    missed: u64,
    received: u64,
}

impl Receiver {
    /// Records sample `seq` of publisher `origin`; returns the samples missed just before it.
    fn observe(&mut self, origin: UniquePublisherId, seq: u64) -> u64 {
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
        missed_before
    }

    fn wait(&self, timeout: Duration) -> Result<bool, BusError> {
        match self.listener.timed_wait(|_| {}, timeout) {
            Ok(n) => Ok(n > 0),
            Err(ListenerWaitError::InterruptSignal) => Ok(false),
            Err(e) => Err(iox("wait", self.topic.as_str())(e)),
        }
    }

    /// The next value `try_receive` gives, waiting up to `timeout` for one.
    fn receive_timeout<R>(
        &mut self,
        timeout: Duration,
        mut try_receive: impl FnMut(&mut Self) -> Result<Option<R>, BusError>,
    ) -> Result<Option<R>, BusError> {
        let deadline = Instant::now() + timeout;
        loop {
            if let Some(r) = try_receive(self)? {
                return Ok(Some(r));
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            self.wait(deadline - now)?;
        }
    }
}

/// Receives one fixed-size payload type, waits on the topic's event service, counts sequence
/// gaps.
pub struct Subscriber<T: FixedPayload> {
    inner: IoxSubscriber<ipc::Service, T, ()>,
    receiver: Receiver,
    pubsub: PubSubFactory<ipc::Service, T, ()>,
    _event: EventFactory<ipc::Service>,
}

impl<T: FixedPayload> Subscriber<T> {
    /// Takes the next sample without waiting.
    pub fn try_receive(&mut self) -> Result<Option<Received<T>>, BusError> {
        Self::take(&self.inner, &mut self.receiver)
    }

    fn take(
        inner: &IoxSubscriber<ipc::Service, T, ()>,
        receiver: &mut Receiver,
    ) -> Result<Option<Received<T>>, BusError> {
        let Some(sample) = inner.receive().map_err(iox("receive", T::TOPIC.as_str()))? else {
            return Ok(None);
        };
        let receive_mono_ns = monotonic_ns();
        let missed_before = receiver.observe(sample.origin(), sample.payload().header().seq);
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
        self.receiver.wait(timeout)
    }

    /// Publishers connected to the topic's service now (0: nothing publishes there).
    pub fn publishers(&self) -> usize {
        self.pubsub.dynamic_config().number_of_publishers()
    }

    /// The next sample, waiting up to `timeout` for one.
    pub fn receive_timeout(&mut self, timeout: Duration) -> Result<Option<Received<T>>, BusError> {
        let inner = &self.inner;
        self.receiver
            .receive_timeout(timeout, |r| Self::take(inner, r))
    }

    /// Samples received since creation.
    pub fn received(&self) -> u64 {
        self.receiver.received
    }

    /// Samples missed (sequence gaps) since creation, over all publishers.
    pub fn missed(&self) -> u64 {
        self.receiver.missed
    }
}

/// Receives traffic pictures (see [`Subscriber`], whose waiting and gap counting it shares).
pub struct TrafficSubscriber {
    inner: IoxSubscriber<ipc::Service, [Target], TrafficHeader>,
    receiver: Receiver,
    pubsub: PubSubFactory<ipc::Service, [Target], TrafficHeader>,
    _event: EventFactory<ipc::Service>,
}

impl TrafficSubscriber {
    /// Takes the next picture without waiting.
    pub fn try_receive(&mut self) -> Result<Option<ReceivedTraffic>, BusError> {
        Self::take(&self.inner, &mut self.receiver)
    }

    fn take(
        inner: &IoxSubscriber<ipc::Service, [Target], TrafficHeader>,
        receiver: &mut Receiver,
    ) -> Result<Option<ReceivedTraffic>, BusError> {
        let Some(sample) = inner
            .receive()
            .map_err(iox("receive", Topic::Traffic.as_str()))?
        else {
            return Ok(None);
        };
        let receive_mono_ns = monotonic_ns();
        let missed_before = receiver.observe(sample.origin(), sample.user_header().header.seq);
        Ok(Some(ReceivedTraffic {
            sample,
            missed_before,
            receive_mono_ns,
        }))
    }

    /// Waits up to `timeout` for the publisher's wake-up (see [`Subscriber::wait`]).
    pub fn wait(&self, timeout: Duration) -> Result<bool, BusError> {
        self.receiver.wait(timeout)
    }

    /// Publishers connected to the service now (0: nothing publishes there).
    pub fn publishers(&self) -> usize {
        self.pubsub.dynamic_config().number_of_publishers()
    }

    /// The next picture, waiting up to `timeout` for one.
    pub fn receive_timeout(
        &mut self,
        timeout: Duration,
    ) -> Result<Option<ReceivedTraffic>, BusError> {
        let inner = &self.inner;
        self.receiver
            .receive_timeout(timeout, |r| Self::take(inner, r))
    }

    /// Pictures received since creation.
    pub fn received(&self) -> u64 {
        self.receiver.received
    }

    /// Pictures missed (sequence gaps) since creation, over all publishers.
    pub fn missed(&self) -> u64 {
        self.receiver.missed
    }
}

/// A sample copied out of shared memory (see [`TopicSubscriber::receive_copy`]).
#[derive(Debug, Clone)]
pub struct Delivered<T> {
    /// The payload.
    pub payload: T,
    /// Samples of the same publisher missed just before this one (gap in `header.seq`).
    pub missed_before: u64,
    /// Host monotonic time when it was received, ns.
    pub receive_mono_ns: u64,
}

impl<T: Payload> Delivered<T> {
    /// Latency from the publisher's send stamp to reception, ns (0 if the clocks disagree).
    pub fn latency_ns(&self) -> u64 {
        latency_ns(self.payload.header(), self.receive_mono_ns)
    }
}

/// Any topic's subscriber, for consumers written once for every topic (`vigil listen`, the
/// monitor process): samples come copied out of shared memory, the price of treating the
/// traffic slice and the fixed payloads alike. A consumer that wants zero copy uses
/// [`Subscriber`] or [`TrafficSubscriber`] directly.
pub trait TopicSubscriber: Sized {
    /// The payload, as the process holds it.
    type Payload: Payload;
    /// Subscribes on `bus`.
    fn open(bus: &Bus) -> Result<Self, BusError>;
    /// Takes the next sample without waiting, copied out.
    fn receive_copy(&mut self) -> Result<Option<Delivered<Self::Payload>>, BusError>;
    /// Waits up to `timeout` for the publisher's wake-up.
    fn wait(&self, timeout: Duration) -> Result<bool, BusError>;
    /// Publishers connected to the service now.
    fn publishers(&self) -> usize;
    /// Samples missed (sequence gaps) since creation.
    fn missed(&self) -> u64;
}

impl<T: FixedPayload> TopicSubscriber for Subscriber<T> {
    type Payload = T;
    fn open(bus: &Bus) -> Result<Self, BusError> {
        bus.subscriber::<T>()
    }
    fn receive_copy(&mut self) -> Result<Option<Delivered<T>>, BusError> {
        Ok(self.try_receive()?.map(|r| Delivered {
            payload: *r.payload(),
            missed_before: r.missed_before,
            receive_mono_ns: r.receive_mono_ns,
        }))
    }
    fn wait(&self, timeout: Duration) -> Result<bool, BusError> {
        Subscriber::wait(self, timeout)
    }
    fn publishers(&self) -> usize {
        Subscriber::publishers(self)
    }
    fn missed(&self) -> u64 {
        Subscriber::missed(self)
    }
}

impl TopicSubscriber for TrafficSubscriber {
    type Payload = TrafficPayload;
    fn open(bus: &Bus) -> Result<Self, BusError> {
        bus.traffic_subscriber()
    }
    fn receive_copy(&mut self) -> Result<Option<Delivered<TrafficPayload>>, BusError> {
        Ok(self.try_receive()?.map(|r| Delivered {
            payload: r.to_payload(),
            missed_before: r.missed_before,
            receive_mono_ns: r.receive_mono_ns,
        }))
    }
    fn wait(&self, timeout: Duration) -> Result<bool, BusError> {
        TrafficSubscriber::wait(self, timeout)
    }
    fn publishers(&self) -> usize {
        TrafficSubscriber::publishers(self)
    }
    fn missed(&self) -> u64 {
        TrafficSubscriber::missed(self)
    }
}
