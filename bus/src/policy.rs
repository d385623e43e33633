//! Delivery policy per topic: the deliberate choice of what happens when a subscriber is slow or
//! dead. Publisher and subscribers build their services from this one table, so their settings
//! always match (iceoryx2 refuses to open a service with incompatible settings).
//!
//! The rule for every topic: `send()` never waits for a subscriber. iceoryx2's default for a full
//! subscriber buffer without overflow is "retry until delivered", which blocked `send()` for 4 s
//! after a subscriber was killed (DOMAIN-NOTES, iceoryx2).
//!
//! - State topics (attitude, ownship, traffic, integrity): **latest state wins**. Safe overflow is
//!   on: a full subscriber buffer drops its oldest sample. A small history hands a late joiner the
//!   current state at once. A consumer that misses states sees the gap in `header.seq`.
//! - Alerts: **nothing lost silently**. No overflow (an unread alert is never overwritten), a large
//!   buffer, and the backpressure strategy "discard data" for a subscriber whose buffer is still
//!   full: delivery to that one subscriber fails at once, the publisher counts the failure
//!   ([`crate::Publisher::failed_deliveries`]) and the subscriber sees a gap in `header.seq`.

use crate::names::Topic;

/// What a full subscriber buffer does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Overflow {
    /// The oldest unread sample is replaced (iceoryx2 safe overflow).
    LatestWins,
    /// Unread samples are kept; a new sample for that subscriber is discarded and counted.
    DiscardAndCount,
}

/// Service settings of one topic.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Policy {
    /// Full-buffer behaviour.
    pub overflow: Overflow,
    /// Samples a subscriber can hold unread.
    pub buffer_size: usize,
    /// Samples replayed to a new subscriber.
    pub history_size: usize,
    /// Samples a subscriber may hold borrowed at once.
    pub max_borrowed: usize,
    /// Subscribers the service admits.
    pub max_subscribers: usize,
    /// Publishers the service admits (alerts: `vigil run` and a separate `vigil monitor`).
    pub max_publishers: usize,
    /// Nodes the service admits.
    pub max_nodes: usize,
}

impl Topic {
    /// The topic's delivery policy.
    pub const fn policy(self) -> Policy {
        match self {
            // A sample slot holds MAX_TARGETS targets (221 KiB; a picture copies only its count):
            // keep the number of samples in shared memory small.
            Topic::Traffic => Policy {
                overflow: Overflow::LatestWins,
                buffer_size: 2,
                history_size: 1,
                max_borrowed: 2,
                max_subscribers: 8,
                max_publishers: 1,
                max_nodes: 16,
            },
            Topic::Attitude | Topic::Ownship | Topic::Integrity => Policy {
                overflow: Overflow::LatestWins,
                buffer_size: 8,
                history_size: 1,
                max_borrowed: 2,
                max_subscribers: 16,
                max_publishers: 1,
                max_nodes: 24,
            },
            Topic::Alerts => Policy {
                overflow: Overflow::DiscardAndCount,
                buffer_size: 256,
                history_size: 16,
                max_borrowed: 4,
                max_subscribers: 16,
                max_publishers: 4,
                max_nodes: 24,
            },
        }
    }
}
