//! The optional live view of `vigil run` for the Foxglove/Lichtblick tools (issue 10, "bins/":
//! "an optional, feature-gated live view ... bound to localhost, off the safety path"): its
//! configuration section `[live_view]` (`crate::config::live_view`) and the switch between a build with the cargo feature
//! `foxglove` (the view of `crate::outputs::foxglove_view`) and one without (no view).
//!
//! Decision: `live_view.enabled = true` in a build without the feature is refused at start
//! (configuration validation, key `live_view.enabled`) rather than warned about and ignored: an
//! operator who asked for the view and silently got none would look for a fault elsewhere, and
//! the fix (rebuild with `--features foxglove`, or set `enabled = false`) is known at once.

use crate::Outputs;

pub use crate::config::live_view::{AVAILABLE, DEFAULT_PORT, LiveViewSection};

/// The live view, when the build carries it.
#[cfg(feature = "foxglove")]
pub type View = crate::outputs::foxglove_view::FoxgloveView;

/// The live view of a build without the feature: a type with no value (never started).
#[cfg(not(feature = "foxglove"))]
#[derive(Debug)]
pub enum View {}

#[cfg(not(feature = "foxglove"))]
impl Outputs for View {
    fn publish<T: vigil_bus::Payload>(&mut self, _: &T) {
        match *self {}
    }
}

/// Starts the view when the section enables it: `None` when disabled, when the build lacks the
/// feature, or when the server fails to start (logged; the service goes on without it).
pub fn start(section: &LiveViewSection) -> Option<View> {
    if !section.enabled {
        return None;
    }
    #[cfg(feature = "foxglove")]
    {
        match crate::outputs::foxglove_view::FoxgloveView::start(section.tcp_port()) {
            Ok(v) => {
                tracing::info!(
                    "live view: Foxglove WebSocket server on ws://127.0.0.1:{}",
                    v.port()
                );
                Some(v)
            }
            Err(e) => {
                tracing::error!("live view not started (the service goes on without it): {e}");
                None
            }
        }
    }
    #[cfg(not(feature = "foxglove"))]
    {
        // Validation refuses this; kept safe for a caller that skipped it.
        tracing::warn!(
            "live view on port {}: this build has no live view (cargo feature foxglove)",
            section.tcp_port()
        );
        None
    }
}

/// Publishes to two outputs: `vigil run` publishes to the bus ([`crate::runtime::live::BusOutputs`]) and
/// to the live view when it runs (`Tee(bus, Option<View>)`). The first output is served first,
/// so the view never delays the bus.
#[derive(Debug)]
pub struct Tee<A, B>(pub A, pub B);

impl<A: Outputs, B: Outputs> Outputs for Tee<A, B> {
    fn publish<T: vigil_bus::Payload>(&mut self, p: &T) {
        self.0.publish(p);
        self.1.publish(p);
    }

    fn traffic_picture(
        &mut self,
        pic: &vigil_fusion::pipeline::TrafficPicture,
        own: Option<&vigil_fusion::ownship::Ownship>,
    ) {
        self.0.traffic_picture(pic, own);
        self.1.traffic_picture(pic, own);
    }

    fn end_step(&mut self) {
        self.0.end_step();
        self.1.end_step();
    }
}

/// An output that may be absent (a view that is disabled or failed to start).
impl<O: Outputs> Outputs for Option<O> {
    fn publish<T: vigil_bus::Payload>(&mut self, p: &T) {
        if let Some(o) = self {
            o.publish(p);
        }
    }

    fn traffic_picture(
        &mut self,
        pic: &vigil_fusion::pipeline::TrafficPicture,
        own: Option<&vigil_fusion::ownship::Ownship>,
    ) {
        if let Some(o) = self {
            o.traffic_picture(pic, own);
        }
    }

    fn end_step(&mut self) {
        if let Some(o) = self {
            o.end_step();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::config::Config;
    use crate::{Collected, Outputs};
    use vigil_bus::{AlertPayload, OwnshipPayload};

    #[test]
    fn section_defaults_and_parses() {
        let c = Config::parse("").unwrap();
        assert_eq!(
            c.live_view,
            LiveViewSection {
                enabled: false,
                port: 8765
            }
        );
        let c = Config::parse("[live_view]\nport = 9000\n").unwrap();
        assert_eq!(c.live_view.port, 9000);
        assert!(!c.live_view.enabled);
        assert!(c.validate().is_ok());
        let e = Config::parse("[live_view]\nhost = \"0.0.0.0\"\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `host`"), "{e}");
    }

    #[test]
    fn bad_port_is_named() {
        for port in ["0", "65536", "100000"] {
            let c = Config::parse(&format!("[live_view]\nport = {port}\n")).unwrap();
            let e = c.validate().unwrap_err();
            assert_eq!(e.key, "live_view.port", "port {port}");
            assert!(e.reason.contains(port), "{e}");
        }
        // A negative port does not even parse into the unsigned field.
        assert!(Config::parse("[live_view]\nport = -1\n").is_err());
        for port in [1u32, 65_535] {
            let s = LiveViewSection {
                enabled: false,
                port,
            };
            assert_eq!(s.validate(false), Ok(()));
            assert_eq!(u32::from(s.tcp_port()), port);
        }
    }

    #[test]
    fn enabled_without_the_feature_is_refused() {
        let s = LiveViewSection {
            enabled: true,
            port: 8765,
        };
        let e = s.validate(false).unwrap_err();
        assert_eq!(e.key, "live_view.enabled");
        assert!(e.reason.contains("--features foxglove"), "{e}");
        assert_eq!(s.validate(true), Ok(()));
        // The whole configuration follows this build's availability.
        let c = Config::parse("[live_view]\nenabled = true\n").unwrap();
        assert_eq!(c.validate().is_ok(), AVAILABLE);
    }

    #[test]
    fn disabled_view_does_not_start() {
        assert!(start(&LiveViewSection::default()).is_none());
    }

    #[test]
    fn tee_publishes_to_both_and_skips_an_absent_output() {
        let mut tee = Tee(Collected::default(), Some(Collected::default()));
        tee.publish(&OwnshipPayload::default());
        tee.publish(&AlertPayload::default());
        assert_eq!((tee.0.ownship.len(), tee.0.alerts.len()), (1, 1));
        let second = tee.1.as_ref().unwrap();
        assert_eq!((second.ownship.len(), second.alerts.len()), (1, 1));
        let mut tee = Tee(Collected::default(), None::<Collected>);
        tee.publish(&OwnshipPayload::default());
        assert_eq!(tee.0.ownship.len(), 1);
    }
}
