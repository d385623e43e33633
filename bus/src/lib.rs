//! vigil's publication contract over iceoryx2 zero-copy shared memory: service names, payloads,
//! delivery policies, and the publisher/subscriber wrappers.
//!
//! This crate depends on nothing else of vigil's, so a consumer (a detect-and-avoid stack, an
//! integrity monitor, a test harness) needs only this crate. See `examples/subscriber.rs` for a
//! minimal consumer.
//!
//! - [`names`]: every service name, `[PREFIX/]vigil/{attitude,ownship,traffic,integrity,alerts}`,
//!   each with an event service `.../event` for wake-up.
//! - [`payload`]: every payload, `#[repr(C)]` (fixed size; traffic a header and a slice of
//!   targets sized by their count), with a schema version and a sequence
//!   number.
//! - [`policy`]: what a full subscriber buffer does, per topic (a slow or dead subscriber never
//!   blocks the publisher).
//! - [`Bus`], [`Publisher`], [`Subscriber`]: the wrappers that apply all of the above.
#![deny(missing_docs)]

pub mod clock;
pub mod names;
pub mod payload;
pub mod policy;
mod port;

pub use names::{SERVICE_ROOT, Topic, UnknownTopic, service_name};
pub use payload::alerts::AlertPayload;
pub use payload::attitude::{AttitudePayload, ChannelComparison, UnitAttitude};
pub use payload::integrity::{DeviceIntegrity, IntegrityPayload};
pub use payload::ownship::OwnshipPayload;
pub use payload::traffic::{MAX_TARGETS, Target, TrafficHeader, TrafficPayload};
pub use payload::{FixedPayload, Header, Payload, SCHEMA_VERSION};
pub use port::{
    Bus, BusConfig, BusError, CleanupReport, Delivered, LOSSLESS_BUFFER, Publisher, Received,
    ReceivedTraffic, Subscriber, TopicSubscriber, TrafficPublisher, TrafficSubscriber,
};
