//! A port's link as the live service modelled it, kept as its raw channel's metadata so that a
//! replay times the port's bytes as the flight did (issue 18).

use std::collections::BTreeMap;

/// What the aligner was told of a port's link: kept as channel metadata on the port's
/// `/<device>/raw` channel when set (absent keys read back as the defaults), and read back as
/// [`crate::Recorded::Raw::link`].
///
/// Each number a recording cannot give (absent, or not a number) reads as "not known", which is
/// also what the live service uses when it is not configured: a replay never invents a figure.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct PortLink {
    /// Baud rate of the port (metadata `baud`, always written); 0: not recorded.
    pub baud: u32,
    /// How often the port was read, ns (metadata `read_interval_ns`); 0: as its bytes arrived.
    pub read_interval_ns: u64,
    /// The port's USB adapter latency timer, ns (metadata `latency_timer_ns`); 0: none known
    /// (a native UART, a USB CDC device, or not known: the aligner models no adapter wait in
    /// either case).
    pub latency_timer_ns: u64,
    /// The device's transmit buffer as the live service was told it, bytes (metadata
    /// `output_buffer_bytes`); `None`: not stated. A recorded 0 also reads as `None` (no writer
    /// sends it: a buffer of nothing would call a full line empty).
    pub output_buffer_bytes: Option<u32>,
}

impl PortLink {
    /// A link known by its baud alone (read as the bytes arrive, no adapter timer, no stated
    /// buffer).
    pub fn baud(baud: u32) -> Self {
        Self {
            baud,
            ..Self::default()
        }
    }

    /// Adds the link's keys to a raw channel's metadata: `baud` always, the others only when set.
    pub(crate) fn write_to(&self, meta: &mut BTreeMap<String, String>) {
        meta.insert("baud".to_string(), self.baud.to_string());
        if self.read_interval_ns > 0 {
            let v = self.read_interval_ns.to_string();
            meta.insert("read_interval_ns".to_string(), v);
        }
        if self.latency_timer_ns > 0 {
            let v = self.latency_timer_ns.to_string();
            meta.insert("latency_timer_ns".to_string(), v);
        }
        if let Some(bytes) = self.output_buffer_bytes {
            meta.insert("output_buffer_bytes".to_string(), bytes.to_string());
        }
    }

    /// The link a raw channel's metadata records (see the fields for what absent keys mean).
    pub(crate) fn read_from(meta: &BTreeMap<String, String>) -> Self {
        fn number<T: std::str::FromStr>(meta: &BTreeMap<String, String>, key: &str) -> Option<T> {
            meta.get(key).and_then(|v| v.parse().ok())
        }
        Self {
            baud: number(meta, "baud").unwrap_or(0),
            read_interval_ns: number(meta, "read_interval_ns").unwrap_or(0),
            latency_timer_ns: number(meta, "latency_timer_ns").unwrap_or(0),
            output_buffer_bytes: number(meta, "output_buffer_bytes").filter(|&b: &u32| b > 0),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unset_keys_are_not_written_and_absent_or_bad_ones_read_as_not_known() {
        let mut meta = BTreeMap::new();
        PortLink::baud(9600).write_to(&mut meta);
        assert_eq!(meta.len(), 1, "{meta:?}");
        assert_eq!(meta["baud"], "9600");
        assert_eq!(PortLink::read_from(&meta), PortLink::baud(9600));
        assert_eq!(PortLink::read_from(&BTreeMap::new()), PortLink::default());
        let bad = BTreeMap::from(
            [
                ("baud", "fast"),
                ("read_interval_ns", "-1"),
                ("latency_timer_ns", "16 ms"),
                ("output_buffer_bytes", "0"),
            ]
            .map(|(k, v)| (k.to_string(), v.to_string())),
        );
        assert_eq!(PortLink::read_from(&bad), PortLink::default());
    }
}
