//! The one configuration file of `vigil run` (issue 10, "Configuration"): TOML, every parameter
//! with a default, unknown keys refused, validated at start with errors that name the key
//! (`ports[2].baud: must be one of ...`). `vigil config --example` prints [`EXAMPLE`], a commented
//! file that parses back to [`Config::default`].
//!
//! Decision: inside a `[[ports]]` entry, `device` and `path` are required (a port without them
//! means nothing); the `ports` list as a whole has a default (the four devices on
//! `/dev/ttyUSB0..3`), and `baud` and `protocol` default from the device.
//!
//! The `[monitor]` section is the monitor's own parameter table ([`MonitorParams`], validated by
//! it; its errors are reported under `monitor.`).

pub mod bridge;
mod error;
pub mod live_view;
pub mod realtime;

pub use error::ConfigError;
pub(crate) use error::invalid;

use std::path::{Path, PathBuf};

use vigil_drivers::protocol::Device;
use vigil_monitor::MonitorParams;
use vigil_record::PortLink;

use serde::{Deserialize, Serialize};
use vigil_fusion::pipeline::{PipelineConfig, TrafficAltitudeKind};

use crate::runtime::setup::{Setup, TtText, VN200_IMU_HZ};
use live_view::LiveViewSection;
use realtime::RealtimeSection;

/// Baud rates a port may use (the standard UART rates the four devices support).
pub const BAUD_RATES: [u32; 9] = [
    4800, 9600, 19_200, 38_400, 57_600, 115_200, 230_400, 460_800, 921_600,
];

/// The wire protocol of a port: the drivers' protocol table (names, default bauds, device
/// families, decoders), re-exported for the configuration's users.
pub use vigil_drivers::protocol::Protocol;

/// Service policy: how often a port of `protocol` is read by default, ms; 0: as its bytes arrive.
/// Decision: the TT-Multi-RF and the BAHRS are drained every 10 ms (together, see
/// [`crate::runtime::reader`]). At full rates their ~3200 reads a second were more than half of
/// `vigil run`'s wake-ups. The TT-Multi-RF's traffic is published once a second (10 ms is
/// 2.5 m at a 250 m/s closing speed) and its JSON and raw HEX carry their own times; the
/// BAHRS's samples carry its MCU time and its cross-checks are not latency-bound. The aligner
/// adds the wait to the host-timed outputs' sigma. The VN-200 (the latency-critical
/// attitude) and the Watson (host-timed at 0.8 ms sigma, 16 reads a second) are read on
/// arrival.
pub const fn default_read_interval_ms(protocol: Protocol) -> f64 {
    match protocol {
        Protocol::Watson | Protocol::Vn200 => 0.0,
        Protocol::Bahrs
        | Protocol::TtmrfText
        | Protocol::TtmrfHex
        | Protocol::TtmrfMavlink
        | Protocol::TtmrfGdl90
        | Protocol::TtmrfAsterix => 10.0,
    }
}

/// Service policy: whether a port of `protocol` may be paced: not the VN-200, the host clock's
/// reference (its wait would shift every host-timed sample) and the latency-critical
/// attitude.
pub const fn pacing_allowed(protocol: Protocol) -> bool {
    !matches!(protocol, Protocol::Vn200)
}

/// `[bus]`: the iceoryx2 publication.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BusSection {
    /// Prefix of every service name (`PREFIX/vigil/traffic`); empty for plain `vigil/...`.
    pub prefix: String,
    /// iceoryx2 node name of this process.
    pub node_name: String,
    /// Period of the dead-node cleanup, s.
    pub cleanup_period_s: f64,
}

impl Default for BusSection {
    fn default() -> Self {
        Self {
            prefix: String::new(),
            node_name: "vigil-run".to_string(),
            cleanup_period_s: 1.0,
        }
    }
}

/// `[[ports]]`: one serial port.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PortConfig {
    /// Port name (recording channel `/<device>/raw`, integrity entry): letters, digits, `-`, `_`,
    /// at most 16 bytes.
    pub device: String,
    /// Serial device path, e.g. `/dev/ttyUSB0`.
    pub path: PathBuf,
    /// Baud rate; 0 (default) takes the protocol's usual rate.
    #[serde(default)]
    pub baud: u32,
    /// Wire protocol (see [`Protocol::name`]); empty (default) infers it from the device name.
    #[serde(default)]
    pub protocol: String,
    /// Read the port every this many ms instead of as its bytes arrive, ms; absent: the
    /// protocol's default ([`default_read_interval_ms`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub read_interval_ms: Option<f64>,
    /// The port's USB adapter latency timer, ms (an FTDI chip holds a partial USB packet until
    /// it runs out: 16 ms by default on Linux, 1..=255); 0: no such adapter (a native UART, a
    /// USB CDC device). Absent: `vigil run` reads it from sysfs when the port is an FTDI
    /// device (`/sys/bus/usb-serial/devices/ttyUSBn/latency_timer`), else none is modelled.
    /// The aligner widens that port's host-timed sigmas by it (issue 18 point 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latency_timer_ms: Option<f64>,
    /// TT-Multi-RF ports only: the module's transmit buffer, bytes, when known from its maker
    /// (the manual does not give it). While the module's output fills its line, a message
    /// waits at most this many bytes' line time, so the line's samples with no time of their
    /// own (CSV, HEXd) stay placed with that wait in their sigma instead of being marked not
    /// aligned once the line has been full for 0.5 s. Absent (default): not known, no bound
    /// assumed. Too small a figure would pass late times off as right.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub output_buffer_bytes: Option<u32>,
}

impl PortConfig {
    fn new(device: &str, path: &str, protocol: Protocol) -> Self {
        Self {
            device: device.to_string(),
            path: PathBuf::from(path),
            baud: protocol.default_baud(),
            protocol: protocol.name().to_string(),
            read_interval_ms: None,
            latency_timer_ms: None,
            output_buffer_bytes: None,
        }
    }
}

/// `[configure]`: device set-up sent when a port opens (see [`crate::runtime::setup`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ConfigureSection {
    /// Write the VN-200 binary output 1 (Register 75) on every VN-200 port.
    pub vn200_binary_outputs: bool,
    /// Its output rate, Hz: 800 / n for a whole n >= 2 (400, 200, 100, 80, 50, 40, ...).
    pub vn200_rate_hz: u32,
    /// Set the TT-Multi-RF decoded protocols (and NMEA) with AT commands on every TT-Multi-RF
    /// port.
    pub ttmrf_protocol: bool,
    /// Decoded protocol of ADS-B, UAT and FLARM: `"json"` or `"csv"`.
    pub ttmrf_decoded: TtText,
    /// The TT-Multi-RF's GNSS NMEA output (the ownship fallback position).
    pub ttmrf_gnss_nmea: bool,
}

impl Default for ConfigureSection {
    fn default() -> Self {
        Self {
            vn200_binary_outputs: false,
            vn200_rate_hz: 200,
            ttmrf_protocol: false,
            ttmrf_decoded: TtText::Json,
            ttmrf_gnss_nmea: true,
        }
    }
}

/// `[record]`: MCAP recording of the raw port input.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RecordSection {
    /// Output file; absent: no recording.
    pub path: Option<PathBuf>,
    /// Period of the flush to disk, s (at most 1 s: a killed process loses at most that much).
    pub flush_period_s: f64,
    // --- issue 20: decoded and fused channels ---
    /// Channels recorded: `raw`, `raw+fused` (default) or `all` (see `recording`).
    pub channels: crate::recording::ChannelSet,
}

impl Default for RecordSection {
    fn default() -> Self {
        Self {
            path: None,
            flush_period_s: 1.0,
            channels: crate::recording::ChannelSet::default(),
        }
    }
}

/// `[pipeline]`: fusion parameters (the rest of [`PipelineConfig`] keeps its defaults).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PipelineSection {
    /// Period of the ownship/traffic steps, s.
    pub step_s: f64,
    /// A clock jump longer than this restarts the step grid, s.
    pub max_step_gap_s: f64,
    /// Altitude of GDL90 traffic: `"pressure"` or `"geometric_preferred"` (the module's
    /// altitude priority setting).
    pub gdl90_altitude: Gdl90Altitude,
    /// What `vigil/attitude` carries: `"prompt"` or `"checks"`.
    pub attitude_output: AttitudeOutput,
}

/// What the `vigil/attitude` service publishes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AttitudeOutput {
    /// One voted attitude per sample of any attitude unit (the VN-200's rate), as soon as the
    /// sample arrives, with the verdicts of the newest cross-check (default).
    #[default]
    Prompt,
    /// One per cross-check (per BAHRS navigation sample), once the other units have samples
    /// around it: up to a Watson period (84 ms) later.
    Checks,
}

/// Configuration form of [`TrafficAltitudeKind`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Gdl90Altitude {
    /// Pressure altitude (GDL90 definition).
    #[default]
    Pressure,
    /// Geometric when the target sent one.
    GeometricPreferred,
}

impl Default for PipelineSection {
    fn default() -> Self {
        let d = PipelineConfig::default();
        Self {
            step_s: d.step_s,
            max_step_gap_s: d.max_step_gap_s,
            gdl90_altitude: Gdl90Altitude::Pressure,
            attitude_output: AttitudeOutput::Prompt,
        }
    }
}

impl PipelineSection {
    /// The pipeline parameters.
    pub fn pipeline_config(&self) -> PipelineConfig {
        PipelineConfig {
            step_s: self.step_s,
            max_step_gap_s: self.max_step_gap_s,
            gdl90_altitude: match self.gdl90_altitude {
                Gdl90Altitude::Pressure => TrafficAltitudeKind::Pressure,
                Gdl90Altitude::GeometricPreferred => TrafficAltitudeKind::GeometricPreferred,
            },
            prompt_attitude: self.attitude_output == AttitudeOutput::Prompt,
            ..PipelineConfig::default()
        }
    }
}

/// `[link]`: port supervision.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LinkSection {
    /// A port with no decoded message for this long is reported silent, s.
    pub silence_s: f64,
    /// First wait before reopening a failed port, s (doubled after each failure).
    pub reconnect_initial_s: f64,
    /// Longest wait between reopening attempts, s.
    pub reconnect_max_s: f64,
}

impl Default for LinkSection {
    fn default() -> Self {
        Self {
            silence_s: 2.0,
            reconnect_initial_s: 0.1,
            reconnect_max_s: 5.0,
        }
    }
}

/// `[status]`: periodic reports.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct StatusSection {
    /// Period of the one-line status log, s.
    pub period_s: f64,
    /// Period of the `integrity` publication (and monitor evaluation), s.
    pub integrity_period_s: f64,
}

impl Default for StatusSection {
    fn default() -> Self {
        Self {
            period_s: 10.0,
            integrity_period_s: 1.0,
        }
    }
}

/// `[outputs.mavlink]`: fused traffic as MAVLink `ADSB_VEHICLE` over UDP (see
/// [`crate::outputs::mavlink_out`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MavlinkSection {
    /// Destination `HOST:PORT` (an IP address; e.g. `"127.0.0.1:14550"`, a ground station's
    /// usual port). Empty: no MAVLink output.
    pub address: String,
    /// MAVLink system id vigil sends as (usually the vehicle's), 1..=255.
    pub system_id: u8,
    /// MAVLink component id vigil sends as (156: `MAV_COMP_ID_ADSB`).
    pub component_id: u8,
}

impl Default for MavlinkSection {
    fn default() -> Self {
        Self {
            address: String::new(),
            system_id: 1,
            component_id: 156,
        }
    }
}

impl MavlinkSection {
    /// Whether the output is configured.
    pub fn enabled(&self) -> bool {
        !self.address.is_empty()
    }
}

/// `[outputs.gdl90]`: traffic and ownship as GDL90 over UDP (see [`crate::outputs::gdl90_out`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Gdl90Section {
    /// Destination `HOST:PORT` (an IP address; EFBs listen on port 4000, often on the broadcast
    /// address, e.g. `"192.168.1.255:4000"`). Empty: no GDL90 output.
    pub address: String,
}

impl Gdl90Section {
    /// Whether the output is configured.
    pub fn enabled(&self) -> bool {
        !self.address.is_empty()
    }
}

/// `[outputs]`: vigil's outputs besides the bus.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutputsSection {
    /// MAVLink traffic output.
    pub mavlink: MavlinkSection,
    /// GDL90 traffic output.
    pub gdl90: Gdl90Section,
}

/// The whole configuration of `vigil run`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Publication.
    pub bus: BusSection,
    /// Serial ports (default: the four devices on `/dev/ttyUSB0` .. `/dev/ttyUSB3`).
    pub ports: Vec<PortConfig>,
    /// Device set-up at start.
    pub configure: ConfigureSection,
    /// Recording.
    pub record: RecordSection,
    /// Fusion.
    pub pipeline: PipelineSection,
    /// Port supervision.
    pub link: LinkSection,
    /// Periodic reports.
    pub status: StatusSection,
    /// Monitor thresholds and rule timings.
    pub monitor: MonitorParams,
    /// Foxglove live view (cargo feature `foxglove`; see [`crate::outputs::live_view`]).
    pub live_view: LiveViewSection,
    /// CPU wake-up latency (see [`crate::runtime::realtime`]).
    pub realtime: RealtimeSection,
    /// Outputs besides the bus (MAVLink traffic).
    pub outputs: OutputsSection,
    /// `vigil bridge`: the topics on Zenoh (issue 22).
    pub bridge: crate::config::bridge::BridgeSection,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            bus: BusSection::default(),
            ports: vec![
                PortConfig::new("bahrs", "/dev/ttyUSB0", Protocol::Bahrs),
                PortConfig::new("watson", "/dev/ttyUSB1", Protocol::Watson),
                PortConfig::new("vn200", "/dev/ttyUSB2", Protocol::Vn200),
                PortConfig::new("ttmrf", "/dev/ttyUSB3", Protocol::TtmrfText),
            ],
            configure: ConfigureSection::default(),
            record: RecordSection::default(),
            pipeline: PipelineSection::default(),
            link: LinkSection::default(),
            status: StatusSection::default(),
            monitor: MonitorParams::default(),
            live_view: LiveViewSection::default(),
            realtime: RealtimeSection::default(),
            outputs: OutputsSection::default(),
            bridge: crate::config::bridge::BridgeSection::default(),
        }
    }
}

/// A validated port: its configuration with the protocol and baud resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Port {
    /// Port name.
    pub device: String,
    /// Serial device path.
    pub path: PathBuf,
    /// Baud rate.
    pub baud: u32,
    /// Wire protocol.
    pub protocol: Protocol,
    /// Device set-up to run each time the port opens.
    pub setup: Option<Setup>,
    /// Read every this many ns (0: as the bytes arrive); see [`crate::runtime::reader`].
    pub read_interval_ns: u64,
    /// The USB adapter latency timer, ns: configured, read from sysfs by `vigil run`, or
    /// recorded (a replay); `None`: not known, no adapter wait modelled.
    pub latency_timer_ns: Option<u64>,
    /// The device's transmit buffer, bytes (TT-Multi-RF ports only): configured or recorded;
    /// `None`: not known, no bound on a full line's wait assumed.
    pub output_buffer_bytes: Option<u32>,
}

impl Port {
    /// A port met in a recording (a replay): the recorded link, the protocol's default baud where
    /// the recording has none (issue 18), no serial path and no set-up.
    pub fn recorded(device: &str, protocol: Protocol, link: &PortLink) -> Self {
        Self {
            device: device.to_string(),
            path: PathBuf::new(),
            baud: if link.baud > 0 {
                link.baud
            } else {
                protocol.default_baud()
            },
            protocol,
            setup: None,
            read_interval_ns: link.read_interval_ns,
            latency_timer_ns: (link.latency_timer_ns > 0).then_some(link.latency_timer_ns),
            output_buffer_bytes: link.output_buffer_bytes,
        }
    }

    /// What the aligner is told of the port's link, and what a recording keeps of it (an
    /// unknown latency timer and a native one are both 0 there: no adapter wait either way).
    pub fn link(&self) -> PortLink {
        PortLink {
            baud: self.baud,
            read_interval_ns: self.read_interval_ns,
            latency_timer_ns: self.latency_timer_ns.unwrap_or(0),
            output_buffer_bytes: self.output_buffer_bytes,
        }
    }
}

/// The service's part of the example configuration (see [`example`]).
pub const EXAMPLE: &str = r#"# vigil run configuration (TOML). Every key is optional: the values shown are the defaults.
# Unknown keys are refused; `vigil run` names the key of any invalid value at start.

[bus]
# Prefix of every iceoryx2 service name: "" publishes vigil/attitude, vigil/traffic, ...;
# "site1" publishes site1/vigil/attitude, ... (service names are global on a host).
prefix = ""
# iceoryx2 node name of this process.
node_name = "vigil-run"
# Period of the cleanup of dead subscribers' resources, s.
cleanup_period_s = 1.0

# One [[ports]] table per serial port. device: port name (letters, digits, '-', '_'; at most
# 16 bytes); path: serial device; baud: one of 4800 9600 19200 38400 57600 115200 230400 460800
# 921600 (0: the protocol's usual rate); protocol: bahrs-2.0, watson-ahrs-e304, vn200-icd,
# ttmrf-text, ttmrf-hex, ttmrf-mavlink, ttmrf-gdl90 or ttmrf-asterix ("" infers it from the
# device names bahrs, watson, vn200, ttmrf); read_interval_ms: read the port every this many ms
# instead of as its bytes arrive, saving wake-ups (default 10 for bahrs-2.0 and ttmrf-*, 0
# otherwise; not for vn200-icd; the wait enters the host-timed samples' sigma);
# latency_timer_ms: the port's USB adapter latency timer (FTDI: 1..255, 16 by default on Linux;
# 0: none, a native UART or USB CDC device; absent: read from the FTDI driver's sysfs file when
# the port is one); it enters the host-timed samples' sigma. output_buffer_bytes (TT-Multi-RF
# ports only, absent by default): the module's transmit buffer, bytes, if its maker states it;
# it bounds the wait of a full line's messages, which then stay placed (see README).
[[ports]]
device = "bahrs"
path = "/dev/ttyUSB0"
baud = 115200
protocol = "bahrs-2.0"

[[ports]]
device = "watson"
path = "/dev/ttyUSB1"
baud = 9600
protocol = "watson-ahrs-e304"

[[ports]]
device = "vn200"
path = "/dev/ttyUSB2"
baud = 921600
protocol = "vn200-icd"

[[ports]]
device = "ttmrf"
path = "/dev/ttyUSB3"
baud = 921600
protocol = "ttmrf-text"

[configure]
# Device set-up each time a port opens. VN-200: write binary output 1 (Register 75) with the
# outputs vigil reads, at vn200_rate_hz (800 / n for a whole n >= 2); not saved to flash.
vn200_binary_outputs = false
vn200_rate_hz = 200
# TT-Multi-RF: set the decoded protocol of ADS-B, UAT and FLARM ("json" or "csv") and the GNSS
# NMEA output with AT commands (the module keeps them).
ttmrf_protocol = false
ttmrf_decoded = "json"
ttmrf_gnss_nmea = true

[record]
# MCAP recording of the raw port input (uncomment to record; `vigil replay` reads it).
# path = "/var/lib/vigil/flight.mcap"
# Flush to disk at least this often, s (0 < value <= 1).
flush_period_s = 1.0
# Channels: "raw" (the port bytes, what replays read), "raw+fused" (plus attitude checks,
# ownship, traffic, integrity and alerts as JSON with schemas, on the UTC timeline) or "all"
# (plus every decoded message per device). See README, "Recordings".
channels = "raw+fused"

[pipeline]
# Period of the ownship and traffic outputs, s (GPS-time grid).
step_s = 1.0
# A time jump longer than this restarts the output grid, s.
max_step_gap_s = 10.0
# Altitude carried by GDL90 traffic: "pressure" or "geometric_preferred".
gdl90_altitude = "pressure"
# What vigil/attitude carries: "prompt" (the voted attitude at every attitude sample, VN-200
# rate, published as each arrives, with the newest cross-check's verdicts) or "checks" (one per
# cross-check, per BAHRS navigation sample, up to a Watson period later).
attitude_output = "prompt"

[link]
# A port with no decoded message for this long is reported silent, s.
silence_s = 2.0
# Reopening a missing or failed port: first wait, s (doubled after each failure) ...
reconnect_initial_s = 0.1
# ... up to this, s.
reconnect_max_s = 5.0

[status]
# Period of the one-line status log, s.
period_s = 10.0
# Period of the integrity publication and of the monitor's evaluation, s.
integrity_period_s = 1.0


"#;

/// The commented example printed by `vigil config --example`: [`EXAMPLE`], the live view's, the
/// real-time and the monitor's own commented sections; it parses to [`Config::default`].
pub fn example() -> String {
    format!(
        "{EXAMPLE}{}{}{}{}",
        LiveViewSection::EXAMPLE,
        RealtimeSection::EXAMPLE,
        crate::config::bridge::BridgeSection::EXAMPLE,
        MonitorParams::example_toml()
    )
}

fn positive(key: &str, v: f64) -> Result<(), ConfigError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(invalid(key, format!("must be a positive number (got {v})")))
    }
}

impl Config {
    /// Parses a configuration text (no validation).
    pub fn parse(text: &str) -> Result<Self, toml::de::Error> {
        toml::from_str(text)
    }

    /// Reads, parses and validates a configuration file.
    pub fn load(path: &Path) -> anyhow::Result<(Self, Vec<Port>)> {
        use anyhow::Context;
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let c = Self::parse(&text).with_context(|| format!("in {}", path.display()))?;
        let ports = c
            .validate()
            .with_context(|| format!("in {}", path.display()))?;
        Ok((c, ports))
    }

    /// Checks every value; returns the ports with protocol and baud resolved, or the first
    /// invalid key.
    pub fn validate(&self) -> Result<Vec<Port>, ConfigError> {
        // The order of the checks is the order of the sections in the example: the first error
        // found is the one reported.
        self.validate_bus()?;
        self.bridge.validate()?;
        self.validate_outputs()?;
        self.validate_port_count()?;
        let ports = (0..self.ports.len())
            .map(|i| self.validate_port(i))
            .collect::<Result<Vec<_>, _>>()?;
        self.validate_periods()?;
        self.live_view.validate(live_view::AVAILABLE)?;
        self.realtime.validate()?;
        self.monitor.validate().map_err(|e| {
            invalid(
                format!("monitor.{}", e.key),
                format!("{} (got {})", e.expected, e.value),
            )
        })?;
        Ok(ports)
    }

    /// `[bus]`: a node name, a prefix iceoryx2 accepts in a service name.
    fn validate_bus(&self) -> Result<(), ConfigError> {
        if self.bus.node_name.is_empty() {
            return Err(invalid("bus.node_name", "must not be empty"));
        }
        if !self
            .bus
            .prefix
            .bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"-_/.".contains(&b))
        {
            return Err(invalid(
                "bus.prefix",
                "letters, digits, '-', '_', '.' or '/' only",
            ));
        }
        positive("bus.cleanup_period_s", self.bus.cleanup_period_s)?;
        Ok(())
    }

    /// `[outputs]`: addresses that parse, a MAVLink system id that is not the broadcast id.
    fn validate_outputs(&self) -> Result<(), ConfigError> {
        let m = &self.outputs.mavlink;
        if m.enabled() && m.address.parse::<std::net::SocketAddr>().is_err() {
            return Err(invalid(
                "outputs.mavlink.address",
                format!("{:?} is not IP:PORT (e.g. \"127.0.0.1:14550\")", m.address),
            ));
        }
        let g = &self.outputs.gdl90;
        if g.enabled() && g.address.parse::<std::net::SocketAddr>().is_err() {
            return Err(invalid(
                "outputs.gdl90.address",
                format!(
                    "{:?} is not IP:PORT (e.g. \"192.168.1.255:4000\")",
                    g.address
                ),
            ));
        }
        if m.system_id == 0 {
            return Err(invalid(
                "outputs.mavlink.system_id",
                "1..=255 (0 is MAVLink's broadcast id)",
            ));
        }
        Ok(())
    }

    /// `[[ports]]`: at least one, no more than the integrity report can describe.
    fn validate_port_count(&self) -> Result<(), ConfigError> {
        if self.ports.is_empty() {
            return Err(invalid("ports", "at least one port is needed"));
        }
        if self.ports.len() > vigil_bus::payload::integrity::MAX_DEVICES {
            return Err(invalid(
                "ports",
                format!(
                    "at most {} ports (the integrity report's capacity)",
                    vigil_bus::payload::integrity::MAX_DEVICES
                ),
            ));
        }
        Ok(())
    }

    /// `ports[i]`: its name, path, protocol and baud rate, then the set-up and read interval that
    /// follow from them.
    fn validate_port(&self, i: usize) -> Result<Port, ConfigError> {
        let p = &self.ports[i];
        let key = |k: &str| format!("ports[{i}].{k}");
        let name_ok = !p.device.is_empty()
            && p.device.len() <= vigil_bus::payload::integrity::DEVICE_NAME_LEN
            && p.device
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || b == b'-' || b == b'_');
        if !name_ok {
            return Err(invalid(
                key("device"),
                "1 to 16 letters, digits, '-' or '_'",
            ));
        }
        if self.ports[..i].iter().any(|q| q.device == p.device) {
            return Err(invalid(
                key("device"),
                format!("{:?} appears twice", p.device),
            ));
        }
        if p.path.as_os_str().is_empty() {
            return Err(invalid(key("path"), "must not be empty"));
        }
        let Some(protocol) = Protocol::resolve(&p.protocol, &p.device) else {
            let names: Vec<&str> = Protocol::ALL.iter().map(|p| p.name()).collect();
            return Err(invalid(
                key("protocol"),
                format!(
                    "must be one of {} (or empty for a device named bahrs, watson, vn200 \
                     or ttmrf)",
                    names.join(", ")
                ),
            ));
        };
        let baud = if p.baud == 0 {
            protocol.default_baud()
        } else {
            p.baud
        };
        if !BAUD_RATES.contains(&baud) {
            let list: Vec<String> = BAUD_RATES.iter().map(u32::to_string).collect();
            return Err(invalid(
                key("baud"),
                format!("must be one of {} (got {baud})", list.join(", ")),
            ));
        }
        Ok(Port {
            device: p.device.clone(),
            path: p.path.clone(),
            baud,
            protocol,
            setup: self.setup_of(protocol, baud),
            read_interval_ns: self.read_interval_ns(i, p, protocol, baud)?,
            latency_timer_ns: match p.latency_timer_ms {
                None => None,
                Some(ms) if ms.is_finite() && (0.0..=255.0).contains(&ms) => {
                    Some((ms * 1e6).round() as u64)
                }
                Some(_) => {
                    return Err(invalid(
                        key("latency_timer_ms"),
                        "0 (no adapter timer) or 1..=255 ms (the FTDI range)",
                    ));
                }
            },
            output_buffer_bytes: match p.output_buffer_bytes {
                None => None,
                Some(_) if protocol.device() != Device::Ttmrf => {
                    return Err(invalid(
                        key("output_buffer_bytes"),
                        "applies to TT-Multi-RF ports only (the one line vigil watches)",
                    ));
                }
                Some(0) => {
                    return Err(invalid(
                        key("output_buffer_bytes"),
                        "at least 1 byte (leave it out when the buffer is not known)",
                    ));
                }
                Some(b) => Some(b),
            },
        })
    }

    /// The device set-up a port of `protocol` at `baud` gets from `[configure]`.
    fn setup_of(&self, protocol: Protocol, baud: u32) -> Option<Setup> {
        let c = &self.configure;
        match protocol {
            Protocol::Vn200 if c.vn200_binary_outputs => Some(Setup::Vn200 {
                rate_divisor: (VN200_IMU_HZ / c.vn200_rate_hz.max(1)) as u16,
            }),
            Protocol::TtmrfText | Protocol::TtmrfHex if c.ttmrf_protocol => Some(Setup::Ttmrf {
                decoded: c.ttmrf_decoded,
                gnss_nmea: c.ttmrf_gnss_nmea,
                run_baud: baud,
            }),
            _ => None,
        }
    }

    /// `ports[i].read_interval_ms` (or the protocol's default), checked against what the port's
    /// buffer holds at `baud` and against the protocol's pacing rule, in ns.
    fn read_interval_ns(
        &self,
        i: usize,
        p: &PortConfig,
        protocol: Protocol,
        baud: u32,
    ) -> Result<u64, ConfigError> {
        let key = |k: &str| format!("ports[{i}].{k}");
        let interval_ms = p
            .read_interval_ms
            .unwrap_or(default_read_interval_ms(protocol));
        // Half the line discipline's 4 KiB buffer (`N_TTY_BUF_SIZE`, the reader's buffer) per
        // interval at the port's baud rate: the rest is room for a late drain, so the line is
        // never throttled.
        let max_ms = crate::runtime::reader::READ_BYTES as f64 / 2.0 * 10.0 / f64::from(baud) * 1e3;
        if !(interval_ms.is_finite() && (0.0..=max_ms).contains(&interval_ms)) {
            return Err(invalid(
                key("read_interval_ms"),
                format!(
                    "must be 0 to {:.1} ms at {baud} baud (2 KiB of input), got {interval_ms}",
                    (max_ms * 10.0).floor() / 10.0
                ),
            ));
        }
        if interval_ms > 0.0 && !pacing_allowed(protocol) {
            return Err(invalid(
                key("read_interval_ms"),
                format!(
                    "must be 0 for {}: it is read as its bytes arrive (its times would \
                     carry the wait unmodelled)",
                    protocol.name()
                ),
            ));
        }
        Ok((interval_ms * 1e6).round() as u64)
    }

    /// `[configure]`, `[record]`, `[pipeline]`, `[link]`, `[status]`: rates and periods.
    fn validate_periods(&self) -> Result<(), ConfigError> {
        let rate = self.configure.vn200_rate_hz;
        if rate == 0 || !VN200_IMU_HZ.is_multiple_of(rate) || VN200_IMU_HZ / rate < 2 {
            return Err(invalid(
                "configure.vn200_rate_hz",
                format!("must be 800 / n for a whole n >= 2, e.g. 400, 200, 100, 50 (got {rate})"),
            ));
        }
        if let Some(path) = &self.record.path
            && path.as_os_str().is_empty()
        {
            return Err(invalid("record.path", "must not be empty"));
        }
        positive("record.flush_period_s", self.record.flush_period_s)?;
        if self.record.flush_period_s > 1.0 {
            return Err(invalid(
                "record.flush_period_s",
                "must be at most 1 s (a killed process loses at most one period)",
            ));
        }
        positive("pipeline.step_s", self.pipeline.step_s)?;
        if self.pipeline.step_s < 1e-3 {
            return Err(invalid("pipeline.step_s", "must be at least 0.001 s"));
        }
        positive("pipeline.max_step_gap_s", self.pipeline.max_step_gap_s)?;
        positive("link.silence_s", self.link.silence_s)?;
        positive("link.reconnect_initial_s", self.link.reconnect_initial_s)?;
        positive("link.reconnect_max_s", self.link.reconnect_max_s)?;
        if self.link.reconnect_max_s < self.link.reconnect_initial_s {
            return Err(invalid(
                "link.reconnect_max_s",
                "must not be below link.reconnect_initial_s",
            ));
        }
        positive("status.period_s", self.status.period_s)?;
        positive("status.integrity_period_s", self.status.integrity_period_s)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn example_parses_back_to_the_defaults() {
        let c = Config::parse(&example()).unwrap();
        assert_eq!(c, Config::default());
        let ports = c.validate().unwrap();
        assert_eq!(ports.len(), 4);
        assert_eq!(ports[1].protocol, Protocol::Watson);
        assert_eq!(ports[1].baud, 9600);
    }

    /// Issue 18 point 1: `latency_timer_ms` per port: absent (detected by `vigil run`), 0 (no
    /// adapter timer) or the FTDI range 1..=255 ms; anything else names the key.
    #[test]
    fn latency_timers_are_optional_and_validated() {
        let one = |extra: &str| {
            Config::parse(&format!(
                "[[ports]]\ndevice = \"watson\"\npath = \"/dev/x\"\n{extra}"
            ))
            .unwrap()
            .validate()
        };
        assert_eq!(one("").unwrap()[0].latency_timer_ns, None);
        assert_eq!(
            one("latency_timer_ms = 16").unwrap()[0].latency_timer_ns,
            Some(16_000_000)
        );
        assert_eq!(
            one("latency_timer_ms = 0").unwrap()[0].latency_timer_ns,
            Some(0)
        );
        for bad in [
            "latency_timer_ms = 256",
            "latency_timer_ms = -1",
            "latency_timer_ms = nan",
        ] {
            assert_eq!(
                one(bad).unwrap_err().key,
                "ports[0].latency_timer_ms",
                "{bad}"
            );
        }
    }

    /// `output_buffer_bytes`: absent by default (no bound assumed), a positive byte count on a
    /// TT-Multi-RF port (whatever its output protocol), refused on the other ports (their lines
    /// are not watched) and at 0, naming the key.
    #[test]
    fn output_buffers_are_stated_on_ttmrf_ports_only() {
        let one = |device: &str, protocol: &str, extra: &str| {
            Config::parse(&format!(
                "[[ports]]\ndevice = \"{device}\"\npath = \"/dev/x\"\nprotocol = \"{protocol}\"\n{extra}"
            ))
            .unwrap()
            .validate()
        };
        assert_eq!(one("ttmrf", "", "").unwrap()[0].output_buffer_bytes, None);
        for protocol in ["ttmrf-text", "ttmrf-hex", "ttmrf-gdl90"] {
            let p = one("adsb", protocol, "output_buffer_bytes = 4096").unwrap();
            assert_eq!(p[0].output_buffer_bytes, Some(4096), "{protocol}");
        }
        for (device, extra) in [
            ("ttmrf", "output_buffer_bytes = 0"),
            ("watson", "output_buffer_bytes = 4096"),
            ("vn200", "output_buffer_bytes = 4096"),
            ("bahrs", "output_buffer_bytes = 4096"),
        ] {
            let e = one(device, "", extra).unwrap_err();
            assert_eq!(e.key, "ports[0].output_buffer_bytes", "{device} {extra}");
        }
    }

    #[test]
    fn read_intervals_default_per_protocol_and_are_validated() {
        let ports = Config::default().validate().unwrap();
        let ns: Vec<u64> = ports.iter().map(|p| p.read_interval_ns).collect();
        // bahrs and the TT-Multi-RF every 10 ms; watson, vn200 on arrival.
        assert_eq!(ns, [10_000_000, 0, 0, 10_000_000]);
        let one = |device: &str, extra: &str| {
            Config::parse(&format!(
                "[[ports]]\ndevice = \"{device}\"\npath = \"/dev/x\"\n{extra}"
            ))
            .unwrap()
            .validate()
        };
        // Watson at 9600 baud: up to 2048 x 10 / 9600 s = 2133 ms.
        assert_eq!(
            one("watson", "read_interval_ms = 50").unwrap()[0].read_interval_ns,
            50_000_000
        );
        assert_eq!(
            one("ttmrf", "read_interval_ms = 0").unwrap()[0].read_interval_ns,
            0
        );
        // TT-Multi-RF at 921 600 baud: at most 2048 x 10 / 921600 s = 22.2 ms.
        assert_eq!(
            one("ttmrf", "read_interval_ms = 22").unwrap()[0].read_interval_ns,
            22_000_000
        );
        let e = one("ttmrf", "read_interval_ms = 25").unwrap_err();
        assert_eq!(e.key, "ports[0].read_interval_ms");
        assert!(e.reason.contains("0 to 22.2 ms at 921600 baud"), "{e}");
        let e = one("ttmrf", "read_interval_ms = -1").unwrap_err();
        assert_eq!(e.key, "ports[0].read_interval_ms");
        let e = one("vn200", "read_interval_ms = 5").unwrap_err();
        assert_eq!(e.key, "ports[0].read_interval_ms");
        assert!(e.reason.starts_with("must be 0 for vn200-icd"), "{e}");
        assert_eq!(
            one("vn200", "read_interval_ms = 0").unwrap()[0].read_interval_ns,
            0
        );
        // BAHRS at 115 200 baud: up to 2048 x 10 / 115200 s = 177.7 ms.
        assert_eq!(
            one("bahrs", "read_interval_ms = 0").unwrap()[0].read_interval_ns,
            0
        );
        let e = one("bahrs", "read_interval_ms = 178").unwrap_err();
        assert!(e.reason.contains("0 to 177.7 ms at 115200 baud"), "{e}");
    }

    #[test]
    fn an_empty_file_is_the_default() {
        assert_eq!(Config::parse("").unwrap(), Config::default());
    }

    #[test]
    fn errors_name_the_key() {
        let text = r#"
[[ports]]
device = "bahrs"
path = "/dev/a"
[[ports]]
device = "watson"
path = "/dev/b"
[[ports]]
device = "vn200"
path = "/dev/c"
baud = 12345
"#;
        let e = Config::parse(text).unwrap().validate().unwrap_err();
        assert_eq!(e.key, "ports[2].baud");
        assert!(
            e.to_string()
                .starts_with("ports[2].baud: must be one of 4800,")
        );

        let e = Config::parse("[[ports]]\ndevice = \"gyro\"\npath = \"/dev/x\"\n")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "ports[0].protocol");

        let e = Config::parse("[[ports]]\ndevice = \"a\"\npath = \"/x\"\nprotocol = \"vn200-icd\"\n[[ports]]\ndevice = \"a\"\npath = \"/y\"\nprotocol = \"vn200-icd\"\n")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "ports[1].device");

        let e = Config::parse("[record]\nflush_period_s = 2.0\n")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "record.flush_period_s");

        let e = Config::parse("[configure]\nvn200_rate_hz = 300\n")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "configure.vn200_rate_hz");

        let e = Config::parse("[link]\nsilence_s = -1\n")
            .unwrap()
            .validate()
            .unwrap_err();
        assert_eq!(e.key, "link.silence_s");
    }

    #[test]
    fn unknown_keys_are_refused_with_their_name() {
        let e = Config::parse("[pipeline]\nstep = 1.0\n").unwrap_err();
        assert!(e.to_string().contains("unknown field `step`"), "{e}");
        let e = Config::parse("[[ports]]\ndevice = \"bahrs\"\npath = \"/x\"\nspeed = 9600\n")
            .unwrap_err();
        assert!(e.to_string().contains("unknown field `speed`"), "{e}");
    }

    #[test]
    fn configure_section_gives_each_port_its_setup() {
        let c = Config::parse(
            "[configure]\nvn200_binary_outputs = true\nvn200_rate_hz = 400\n\
             ttmrf_protocol = true\nttmrf_decoded = \"csv\"\nttmrf_gnss_nmea = false\n",
        )
        .unwrap();
        let ports = c.validate().unwrap();
        assert_eq!(ports[0].setup, None);
        assert_eq!(ports[1].setup, None);
        // 800 Hz IMU / 400 Hz = divisor 2.
        assert_eq!(ports[2].setup, Some(Setup::Vn200 { rate_divisor: 2 }));
        assert_eq!(
            ports[3].setup,
            Some(Setup::Ttmrf {
                decoded: TtText::Csv,
                gnss_nmea: false,
                run_baud: 921_600
            })
        );
        assert!(
            Config::default()
                .validate()
                .unwrap()
                .iter()
                .all(|p| p.setup.is_none())
        );
    }

    #[test]
    fn pipeline_section_maps_to_the_pipeline_parameters() {
        let c =
            Config::parse("[pipeline]\nstep_s = 0.5\ngdl90_altitude = \"geometric_preferred\"\n")
                .unwrap();
        let p = c.pipeline.pipeline_config();
        assert_eq!(p.step_s, 0.5);
        assert_eq!(p.max_step_gap_s, 10.0);
        assert_eq!(p.gdl90_altitude, TrafficAltitudeKind::GeometricPreferred);
    }

    #[test]
    fn protocol_is_inferred_from_standard_device_names() {
        assert_eq!(Protocol::resolve("", "vn200"), Some(Protocol::Vn200));
        assert_eq!(Protocol::resolve("", "imu"), None);
        assert_eq!(
            Protocol::resolve("ttmrf-hex", "imu"),
            Some(Protocol::TtmrfHex)
        );
        for p in Protocol::ALL {
            assert_eq!(Protocol::resolve(p.name(), "x"), Some(p));
        }
    }
}
