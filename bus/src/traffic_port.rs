//! The traffic topic's publisher and subscriber: a [`TrafficHeader`] as the iceoryx2 user header
//! and the targets as a slice sized by the picture's count (schema 2, see
//! [`crate::payload::traffic`]). Same policies, sequence numbers, send stamps, gap counting and
//! wake-up events as the fixed-size topics ([`crate::Publisher`], [`crate::Subscriber`]).

use std::time::{Duration, Instant};

use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher as IoxPublisher;
use iceoryx2::port::subscriber::Subscriber as IoxSubscriber;
use iceoryx2::prelude::{AllocationStrategy, BackpressureStrategy, ServiceName, ipc};
use iceoryx2::sample::Sample;
use iceoryx2::service::port_factory::event::PortFactory as EventFactory;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as PubSubFactory;
use serde::{Serialize, Serializer};

use crate::clock::monotonic_ns;
use crate::names::Topic;
use crate::payload::Header;
use crate::payload::traffic::{
    MAX_TARGETS, Target, TrafficHeader, TrafficPayload, serialize_picture,
};
use crate::policy::Overflow;
use crate::port::{Bus, BusError, SendState, SeqTracker, iox, stamp};

type TrafficFactory = PubSubFactory<ipc::Service, [Target], TrafficHeader>;

impl Bus {
    fn traffic_services(&self) -> Result<(TrafficFactory, EventFactory<ipc::Service>), BusError> {
        let topic = Topic::Traffic;
        let policy = topic.policy();
        let name = topic.service_name(self.prefix());
        let sname = ServiceName::new(&name).map_err(|e| BusError::InvalidName {
            name: name.clone(),
            reason: format!("{e:?}"),
        })?;
        let pubsub = self
            .node
            .service_builder(&sname)
            .publish_subscribe::<[Target]>()
            .user_header::<TrafficHeader>()
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
        Ok((pubsub, self.event_service(topic)?))
    }

    /// Creates the traffic publisher (slices of up to [`MAX_TARGETS`] targets).
    pub fn traffic_publisher(&self) -> Result<TrafficPublisher, BusError> {
        let name = Topic::Traffic.service_name(self.prefix());
        let (pubsub, event) = self.traffic_services()?;
        let send = SendState::new(self.lossless_wait_ns);
        // Static allocation: every sample slot holds MAX_TARGETS targets (the shared memory is
        // reserved once, at start); a sample only copies and sends its `count`.
        let inner = pubsub
            .publisher_builder()
            .initial_max_slice_len(MAX_TARGETS)
            .allocation_strategy(AllocationStrategy::Static)
            .backpressure_strategy(BackpressureStrategy::DiscardData)
            .set_backpressure_handler(send.handler())
            .create()
            .map_err(iox("create publisher", &name))?;
        let notifier = event
            .notifier_builder()
            .create()
            .map_err(iox("create notifier", &name))?;
        Ok(TrafficPublisher {
            inner,
            notifier,
            _pubsub: pubsub,
            _event: event,
            next_seq: 1,
            send,
            notify_failures: 0,
        })
    }

    /// Creates a traffic subscriber; it receives the topic's history first.
    pub fn traffic_subscriber(&self) -> Result<TrafficSubscriber, BusError> {
        let name = Topic::Traffic.service_name(self.prefix());
        let policy = Topic::Traffic.policy();
        let (pubsub, event) = self.traffic_services()?;
        let inner = pubsub
            .subscriber_builder()
            .buffer_size(self.buffer_size(&policy))
            .create()
            .map_err(iox("create subscriber", &name))?;
        let listener = event
            .listener_builder()
            .create()
            .map_err(iox("create listener", &name))?;
        Ok(TrafficSubscriber {
            inner,
            listener,
            _pubsub: pubsub,
            _event: event,
            seq: SeqTracker::default(),
        })
    }
}

/// Publishes the traffic picture.
pub struct TrafficPublisher {
    inner: IoxPublisher<ipc::Service, [Target], TrafficHeader>,
    notifier: Notifier<ipc::Service>,
    _pubsub: TrafficFactory,
    _event: EventFactory<ipc::Service>,
    next_seq: u64,
    send: SendState,
    notify_failures: u64,
}

impl TrafficPublisher {
    /// Sends `picture` (its header's `gps_time_ns` is kept; the rest is stamped): the first
    /// [`MAX_TARGETS`] targets, copied once into a loaned slice of their length. Returns the
    /// number of subscribers reached.
    pub fn publish(&mut self, picture: &TrafficPayload) -> Result<usize, BusError> {
        let service = Topic::Traffic.as_str();
        let n = picture.targets.len().min(MAX_TARGETS);
        let mut sample = self
            .send
            .loan_retrying(service, || self.inner.loan_slice_uninit(n))?;
        let mut head = picture.wire_header();
        stamp(&mut head.header, &mut self.next_seq, &self.send);
        *sample.user_header_mut() = head;
        let sample = sample.write_from_slice(&picture.targets[..n]);
        let delivered = sample.send().map_err(iox("send", service))?;
        // As for the fixed-size topics: a failed wake-up never fails the publication.
        if self.notifier.notify().is_err() {
            self.notify_failures += 1;
        }
        Ok(delivered)
    }

    /// Sequence number the next sample will carry.
    pub fn next_seq(&self) -> u64 {
        self.next_seq
    }

    /// Deliveries that failed because a subscriber's buffer was full, since creation.
    pub fn failed_deliveries(&self) -> u64 {
        self.send.failed()
    }

    /// Wake-up notifications that failed, since creation.
    pub fn notify_failures(&self) -> u64 {
        self.notify_failures
    }
}

/// A received traffic picture, read in place in shared memory (drop it soon: see
/// [`crate::Received`]).
pub struct ReceivedTraffic {
    sample: Sample<ipc::Service, [Target], TrafficHeader>,
    /// Samples of the same publisher missed just before this one (gap in `header.seq`).
    pub missed_before: u64,
    /// Host monotonic time when it was received, ns.
    pub receive_mono_ns: u64,
}

impl ReceivedTraffic {
    /// The wire header (count and dropped included).
    pub fn wire_header(&self) -> &TrafficHeader {
        self.sample.user_header()
    }

    /// The common header.
    pub fn header(&self) -> &Header {
        &self.wire_header().header
    }

    /// The targets: the slice, cut to the header's count when that is smaller.
    pub fn targets(&self) -> &[Target] {
        let all = self.sample.payload();
        let n = (self.wire_header().count as usize).min(all.len());
        &all[..n]
    }

    /// Targets the publisher dropped because the picture was full.
    pub fn dropped(&self) -> u32 {
        self.wire_header().dropped
    }

    /// A copy that outlives the sample.
    pub fn to_payload(&self) -> TrafficPayload {
        TrafficPayload::from_wire(self.wire_header(), self.sample.payload())
    }

    /// Latency from the publisher's send stamp to reception, ns (0 if the clocks disagree).
    pub fn latency_ns(&self) -> u64 {
        self.receive_mono_ns
            .saturating_sub(self.header().send_mono_ns)
    }
}

impl Serialize for ReceivedTraffic {
    /// The same form as [`TrafficPayload`]'s.
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        serialize_picture(s, self.header(), self.dropped(), self.targets())
    }
}

/// Receives the traffic picture, waits on the topic's event service, counts sequence gaps.
pub struct TrafficSubscriber {
    inner: IoxSubscriber<ipc::Service, [Target], TrafficHeader>,
    listener: Listener<ipc::Service>,
    _pubsub: TrafficFactory,
    _event: EventFactory<ipc::Service>,
    seq: SeqTracker,
}

impl TrafficSubscriber {
    /// Takes the next sample without waiting.
    pub fn try_receive(&mut self) -> Result<Option<ReceivedTraffic>, BusError> {
        let Some(sample) = self
            .inner
            .receive()
            .map_err(iox("receive", Topic::Traffic.as_str()))?
        else {
            return Ok(None);
        };
        let receive_mono_ns = monotonic_ns();
        let missed_before = self
            .seq
            .record(sample.origin(), sample.user_header().header.seq);
        Ok(Some(ReceivedTraffic {
            sample,
            missed_before,
            receive_mono_ns,
        }))
    }

    /// Waits up to `timeout` for the publisher's wake-up; true when woken.
    pub fn wait(&self, timeout: Duration) -> Result<bool, BusError> {
        let n = self
            .listener
            .timed_wait(|_| {}, timeout)
            .map_err(iox("wait", Topic::Traffic.as_str()))?;
        Ok(n > 0)
    }

    /// The next sample, waiting up to `timeout` for one.
    pub fn receive_timeout(
        &mut self,
        timeout: Duration,
    ) -> Result<Option<ReceivedTraffic>, BusError> {
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
        self.seq.received
    }

    /// Samples missed (sequence gaps) since creation.
    pub fn missed(&self) -> u64 {
        self.seq.missed
    }
}
