//! vigil's publication contract: iceoryx2 service names and fixed-size `#[repr(C)]` payloads.
//!
//! This crate depends on nothing else of vigil's, so a consumer (a detect-and-avoid stack, an
//! integrity monitor, a test harness) needs only this crate. The payloads arrive with the service
//! issue; for now it fixes the naming scheme.
#![deny(missing_docs)]

/// Prefix of every vigil service name. A deployment (and every test) adds its own prefix in front,
/// because iceoryx2 service names are global on a host.
pub const SERVICE_ROOT: &str = "vigil";

/// Builds a full service name from a deployment prefix and a topic, e.g. `("test42", "traffic")`
/// gives `"test42/vigil/traffic"`; an empty prefix gives `"vigil/traffic"`.
pub fn service_name(prefix: &str, topic: &str) -> String {
    if prefix.is_empty() {
        format!("{SERVICE_ROOT}/{topic}")
    } else {
        format!("{prefix}/{SERVICE_ROOT}/{topic}")
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn names_carry_the_prefix() {
        assert_eq!(super::service_name("", "traffic"), "vigil/traffic");
        assert_eq!(super::service_name("t1", "alerts"), "t1/vigil/alerts");
    }
}
