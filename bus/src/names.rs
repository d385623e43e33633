//! Every service name vigil uses, in one place.
//!
//! A topic `T` is carried by two iceoryx2 services: the publish-subscribe service
//! `[PREFIX/]vigil/T` and the event service `[PREFIX/]vigil/T/event` that wakes subscribers, so
//! they wait instead of polling. iceoryx2 service names are global on a host: a deployment sets its
//! own prefix in the configuration, and every test uses a unique one so tests run in parallel.

use core::fmt;
use core::str::FromStr;

use serde::Serialize;

/// Root segment of every vigil service name.
pub const SERVICE_ROOT: &str = "vigil";

/// One of vigil's published topics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Topic {
    /// Voted attitude with the cross-check verdicts ([`crate::AttitudePayload`]).
    Attitude,
    /// Ownship state ([`crate::OwnshipPayload`]).
    Ownship,
    /// Traffic picture ([`crate::TrafficPayload`]).
    Traffic,
    /// Links, decoders and clock ([`crate::IntegrityPayload`]).
    Integrity,
    /// Alert events ([`crate::AlertPayload`]).
    Alerts,
}

impl Topic {
    /// Every topic.
    pub const ALL: [Topic; 5] = [
        Topic::Attitude,
        Topic::Ownship,
        Topic::Traffic,
        Topic::Integrity,
        Topic::Alerts,
    ];

    /// The topic's name segment, e.g. `"traffic"`.
    pub const fn as_str(self) -> &'static str {
        match self {
            Topic::Attitude => "attitude",
            Topic::Ownship => "ownship",
            Topic::Traffic => "traffic",
            Topic::Integrity => "integrity",
            Topic::Alerts => "alerts",
        }
    }

    /// Name of the topic's publish-subscribe service under `prefix`.
    pub fn service_name(self, prefix: &str) -> String {
        service_name(prefix, self.as_str())
    }

    /// Name of the topic's event (wake-up) service under `prefix`.
    pub fn event_name(self, prefix: &str) -> String {
        format!("{}/event", self.service_name(prefix))
    }
}

impl fmt::Display for Topic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.as_str())
    }
}

/// A topic name that is not one of vigil's.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown topic {0:?} (expected attitude, ownship, traffic, integrity or alerts)")]
pub struct UnknownTopic(pub String);

impl FromStr for Topic {
    type Err = UnknownTopic;
    /// Parses a topic name; `vigil/traffic` is accepted as well as `traffic`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let name = s.strip_prefix("vigil/").unwrap_or(s);
        Topic::ALL
            .into_iter()
            .find(|t| t.as_str() == name)
            .ok_or_else(|| UnknownTopic(s.to_string()))
    }
}

/// Builds a full service name from a deployment prefix and a topic, e.g. `("test42", "traffic")`
/// gives `"test42/vigil/traffic"`; an empty prefix gives `"vigil/traffic"`.
pub fn service_name(prefix: &str, topic: &str) -> String {
    let prefix = prefix.trim_matches('/');
    if prefix.is_empty() {
        format!("{SERVICE_ROOT}/{topic}")
    } else {
        format!("{prefix}/{SERVICE_ROOT}/{topic}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_carry_the_prefix() {
        assert_eq!(service_name("", "traffic"), "vigil/traffic");
        assert_eq!(service_name("t1", "alerts"), "t1/vigil/alerts");
        assert_eq!(service_name("/t1/", "alerts"), "t1/vigil/alerts");
        assert_eq!(Topic::Attitude.event_name("p"), "p/vigil/attitude/event");
    }

    #[test]
    fn topics_parse_from_their_names() {
        for t in Topic::ALL {
            assert_eq!(t.as_str().parse::<Topic>(), Ok(t));
        }
        assert_eq!("vigil/ownship".parse::<Topic>(), Ok(Topic::Ownship));
        assert!("weather".parse::<Topic>().is_err());
    }
}
