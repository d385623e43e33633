//! Device presence, rates, output protocols and host link parameters of a scenario.

use serde::{Deserialize, Serialize};

use super::{ScenarioError, invalid_key as invalid};

/// Which devices are on board. A missing table means the device is absent.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Devices {
    /// BAHRS baro-inertial AHRS.
    pub bahrs: Option<BahrsConfig>,
    /// Watson AHRS-E304.
    pub watson: Option<WatsonConfig>,
    /// VectorNav VN-200 (model: `device::vn200`).
    pub vn200: Option<Vn200Config>,
    /// Aerobits TT-Multi-RF (model: `device::ttmrf`).
    pub ttmrf: Option<TtmrfConfig>,
}

impl Devices {
    pub(crate) fn validate(&self) -> Result<(), ScenarioError> {
        if let Some(b) = &self.bahrs {
            check_baud("devices.bahrs.baud", b.baud)?;
            for (key, hz, max) in [
                ("inertial_rate_hz", b.inertial_rate_hz, 1000.0),
                ("navigation_rate_hz", b.navigation_rate_hz, 1000.0),
                ("accuracy_rate_hz", b.accuracy_rate_hz, 100.0),
            ] {
                if !(hz > 0.0 && hz <= max) {
                    return Err(invalid(
                        &format!("devices.bahrs.{key}"),
                        format!("must be within 0 .. {max}"),
                    ));
                }
            }
            // Frame lengths (BAHRS protocol 2.0 with padding and CRC): 0x01 28, 0x05 20, 0x02 24,
            // 0x04 20, 0x03 28 bytes; 0x06 (20 bytes) once a second.
            let bytes_per_s = 48.0 * b.inertial_rate_hz
                + 44.0 * b.navigation_rate_hz
                + 28.0 * b.accuracy_rate_hz
                + 20.0;
            if bytes_per_s > f64::from(b.baud) / 10.0 {
                return Err(invalid(
                    "devices.bahrs.baud",
                    format!(
                        "{} baud carries {} bytes/s, the rates need {bytes_per_s:.0}",
                        b.baud,
                        b.baud / 10
                    ),
                ));
            }
            if b.time_message_lag > 100 {
                return Err(invalid(
                    "devices.bahrs.time_message_lag",
                    "must be within 0 .. 100",
                ));
            }
            if !(0.0..=1000.0).contains(&b.clock_drift_ppm_max) {
                return Err(invalid(
                    "devices.bahrs.clock_drift_ppm_max",
                    "must be within 0 .. 1000",
                ));
            }
        }
        if let Some(w) = &self.watson {
            check_baud("devices.watson.baud", w.baud)?;
            if !(w.rate_hz > 0.0 && w.rate_hz <= 100.0) {
                return Err(invalid("devices.watson.rate_hz", "must be within 0 .. 100"));
            }
        }
        if let Some(v) = &self.vn200 {
            check_baud("devices.vn200.baud", v.baud)?;
            if !(v.rate_hz > 0.0 && v.rate_hz <= 400.0) {
                return Err(invalid("devices.vn200.rate_hz", "must be within 0 .. 400"));
            }
            // The default binary output is 139 bytes (sync, 9 header bytes, 127 payload, CRC).
            let bytes_per_s = 139.0 * v.rate_hz;
            if bytes_per_s > f64::from(v.baud) / 10.0 {
                return Err(invalid(
                    "devices.vn200.baud",
                    format!(
                        "{} baud carries {} bytes/s, the output needs {bytes_per_s:.0}",
                        v.baud,
                        v.baud / 10
                    ),
                ));
            }
        }
        if let Some(t) = &self.ttmrf {
            check_baud("devices.ttmrf.baud", t.baud)?;
            if !matches!(
                t.protocol.as_str(),
                "csv" | "json" | "mavlink" | "gdl90" | "asterix"
            ) {
                return Err(invalid(
                    "devices.ttmrf.protocol",
                    "must be csv, json, mavlink, gdl90 or asterix",
                ));
            }
            // The manual gives the module one UART for every output. Binary frames may hold any
            // byte (`*`, `\n` included), so HEX lines between them cannot be framed reliably, and
            // the binary decoders skip text as garbage: a scenario with a binary decoded
            // protocol must switch raw output off (decision; the manual does not say).
            if matches!(t.protocol.as_str(), "mavlink" | "gdl90" | "asterix") && t.raw != "off" {
                return Err(invalid(
                    "devices.ttmrf.raw",
                    "must be off with a binary decoded protocol (mavlink, gdl90, asterix)",
                ));
            }
            if !matches!(t.raw.as_str(), "off" | "hex" | "hexd" | "beast") {
                return Err(invalid(
                    "devices.ttmrf.raw",
                    "must be off, hex, hexd or beast",
                ));
            }
        }
        Ok(())
    }
}

fn check_baud(key: &str, baud: u32) -> Result<(), ScenarioError> {
    if (1200..=4_000_000).contains(&baud) {
        Ok(())
    } else {
        Err(invalid(key, "must be within 1200 .. 4000000"))
    }
}

/// BAHRS output configuration and error model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BahrsConfig {
    /// Baud rate. Decision: the protocol document names none; at the default rates the stream is
    /// about 7 050 bytes/s (70.5 kbit/s with 10 bits per byte), so 115 200 baud (61 % load).
    pub baud: u32,
    /// Rate of 0x01 (each followed by its 0x05), Hz.
    pub inertial_rate_hz: f64,
    /// Rate of 0x02 (each followed by its 0x04), Hz.
    pub navigation_rate_hz: f64,
    /// Rate of 0x03, Hz.
    pub accuracy_rate_hz: f64,
    /// Largest MCU clock drift, ppm; the run draws one uniformly within +-this.
    pub clock_drift_ppm_max: f64,
    /// Time from a sample to its message being ready to send, us.
    pub latency_us: u32,
    /// How many later data messages of its stream a 0x05 / 0x04 waits for (0 = right after its
    /// data message), to exercise late time messages.
    pub time_message_lag: u32,
    /// 1-sigma noise of every signal.
    pub noise: BahrsNoise,
    /// How the synchronisation pulse is captured and reported (issue 18: the document leaves it
    /// open).
    pub sync: BahrsSync,
}

/// Readings of what the BAHRS document leaves open about its synchronisation pulse (issue 18).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
#[serde(default, deny_unknown_fields)]
pub struct BahrsSync {
    /// Time from the pulse to its 0x06 being ready, ms; `None`: `latency_us` (right after it).
    pub report_delay_ms: Option<f64>,
    /// 0: one 0x06 per pulse; N: the latest pulse's 0x06 is sent again every N ms until the next
    /// pulse ("time of the latest pulse", reported periodically).
    pub report_repeat_ms: f64,
    /// The edge the BAHRS captures, ms after the PPS second: 0 the rising edge; 100 the falling
    /// edge of the VN-200's 100 ms SyncOut pulse (a wrong-edge installation).
    pub edge_offset_ms: f64,
    /// Software capture: each pulse's MCU time is taken late by a latency uniform in 0 ..= this,
    /// us (0: hardware capture, truncated to the us).
    pub capture_latency_us: f64,
}

impl Default for BahrsConfig {
    fn default() -> Self {
        Self {
            baud: 115_200,
            inertial_rate_hz: 100.0,
            navigation_rate_hz: 50.0,
            accuracy_rate_hz: 1.0,
            clock_drift_ppm_max: 50.0,
            latency_us: 500,
            time_message_lag: 0,
            noise: BahrsNoise::default(),
            sync: BahrsSync::default(),
        }
    }
}

/// 1-sigma white noise of the BAHRS signals (also what 0x03 reports for the angles).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct BahrsNoise {
    /// Specific force, m/s^2.
    pub specific_force_mps2: f64,
    /// Angular rate, rad/s.
    pub angular_rate_radps: f64,
    /// Pressure height, m.
    pub pressure_height_m: f64,
    /// Downward velocity, m/s.
    pub velocity_down_mps: f64,
    /// Roll and pitch, rad.
    pub tilt_rad: f64,
    /// Magnetic heading, rad.
    pub heading_rad: f64,
}

impl Default for BahrsNoise {
    fn default() -> Self {
        Self {
            specific_force_mps2: 0.02,
            angular_rate_radps: 0.001,
            pressure_height_m: 0.5,
            velocity_down_mps: 0.05,
            tilt_rad: 0.1f64.to_radians(),
            heading_rad: 0.5f64.to_radians(),
        }
    }
}

/// Watson AHRS-E304 output configuration and error model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WatsonConfig {
    /// Baud rate (document: 9600 8N1).
    pub baud: u32,
    /// Line rate, Hz (document: about 11.85).
    pub rate_hz: f64,
    /// 1-sigma noise.
    pub noise: WatsonNoise,
}

impl Default for WatsonConfig {
    fn default() -> Self {
        Self {
            baud: 9600,
            rate_hz: 11.85,
            noise: WatsonNoise::default(),
        }
    }
}

/// 1-sigma white noise of the Watson signals, in its own units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct WatsonNoise {
    /// Bank and elevation, deg.
    pub tilt_deg: f64,
    /// Heading, deg.
    pub heading_deg: f64,
    /// Accelerations, g.
    pub accel_g: f64,
    /// Rates, deg/s.
    pub rate_dps: f64,
    /// Velocity, km/h.
    pub velocity_kmh: f64,
}

impl Default for WatsonNoise {
    fn default() -> Self {
        Self {
            tilt_deg: 0.2,
            heading_deg: 1.0,
            accel_g: 0.005,
            rate_dps: 0.1,
            velocity_kmh: 1.0,
        }
    }
}

/// VN-200 configuration (`device::vn200`: Register 75 starts at `rate_hz`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Vn200Config {
    /// Baud rate.
    pub baud: u32,
    /// Binary output rate, Hz (up to 400); the sensor divides its 800 Hz IMU rate, so the rate
    /// sent is 800 / round(800 / rate_hz) (e.g. 150 -> 160 Hz).
    pub rate_hz: f64,
    /// Whether the PPS output is wired (to the BAHRS sync input).
    pub pps: bool,
}

impl Default for Vn200Config {
    fn default() -> Self {
        Self {
            baud: 921_600,
            rate_hz: 200.0,
            pps: true,
        }
    }
}

/// TT-Multi-RF configuration (`device::ttmrf`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TtmrfConfig {
    /// Baud rate.
    pub baud: u32,
    /// Decoded output protocol at power-on: "csv", "json", "mavlink", "gdl90" or "asterix" (the
    /// module's `ADSB_RX_PROTOCOL_DECODED`; AT commands may change it later).
    pub protocol: String,
    /// Raw Mode S output: "off", "hex", "hexd", "beast".
    pub raw: String,
    /// Whether the GNSS section / NMEA output is enabled.
    pub gnss: bool,
    /// JSON `ts` from the time of the message (issue 18: the manual does not say): false
    /// truncates it to the ms, true rounds it to the nearest ms.
    pub ts_rounded: bool,
    // --- issue 24 ---
    /// Whether the GNSS section / RMC carries track and speed (false: a receiver that leaves
    /// them out, so the ownship velocity is unknown when the VN-200 is not tracking).
    pub gnss_velocity: bool,
    /// Whether GGA carries the geoid separation (false: mean-sea-level height only).
    pub nmea_geoid_separation: bool,
    /// Whether the module sends its list of targets at once, every traffic message at the
    /// whole second (after the GNSS output), in target order, so each waits on the line
    /// behind the ones before it. The manual's "module is sending list of aircraft every
    /// second" reads either way; false (the default) spreads them over the second.
    pub list_at_once: bool,
}

impl Default for TtmrfConfig {
    fn default() -> Self {
        Self {
            baud: 921_600,
            protocol: "json".into(),
            raw: "off".into(),
            gnss: true,
            ts_rounded: false,
            gnss_velocity: true,
            nmea_geoid_separation: true,
            list_at_once: false,
        }
    }
}

/// Host side of every serial link: USB/OS latency and read chunking, and the host clock.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HostConfig {
    /// Mean latency from a byte's last bit to the host read returning it, ms.
    pub latency_ms: f64,
    /// Half-width of the uniform latency spread, ms (latency is uniform in mean +- this).
    pub latency_jitter_ms: f64,
    /// Largest chunk a host read returns, bytes (chunks are uniform in 1 ..= this, unless
    /// `full_chunks`).
    pub max_chunk_bytes: u32,
    /// Every chunk is `max_chunk_bytes` long, but for the one the line's going idle ends: a
    /// USB-serial adapter that sends a packet as soon as it is full (an FTDI full-speed one:
    /// 62 data bytes per 64-byte packet), instead of the default uniform stress case.
    pub full_chunks: bool,
    /// Largest host monotonic clock drift against GPS time, ppm (drawn within +-this).
    pub clock_drift_ppm_max: f64,
    /// Ports behind an FTDI USB adapter (issue 18): device name -> its latency timer, ms. Such a
    /// port's bytes reach the host in 62-byte packets, sent when full or when the timer runs
    /// out (a partial packet waits up to the timer); the latency above is then the USB poll.
    pub ftdi_latency_timer_ms: std::collections::BTreeMap<String, f64>,
    /// Ports behind another named adapter (issue 18 point 1): device name -> adapter. The
    /// latency above then does not apply to them (each adapter has its own; `link` module).
    pub adapters: std::collections::BTreeMap<String, Adapter>,
}

/// A serial adapter with its own delivery pattern (issue 18 point 1; the FTDI one is
/// [`HostConfig::ftdi_latency_timer_ms`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Adapter {
    /// An on-board UART (16550-type): reads of 8 bytes (the receive FIFO's trigger level), a
    /// partial FIFO read 4 character times after its last byte (the FIFO timeout), then
    /// 0.1 +- 0.05 ms to the read.
    NativeUart,
    /// A USB CDC-ACM bridge at full speed: packets of up to 64 bytes, sent when full or when
    /// the line goes idle, collected at the next 1 ms USB frame, then 0.2 +- 0.1 ms to the
    /// read.
    UsbCdc,
}

impl Default for HostConfig {
    fn default() -> Self {
        Self {
            latency_ms: 1.0,
            latency_jitter_ms: 0.5,
            max_chunk_bytes: 64,
            full_chunks: false,
            clock_drift_ppm_max: 10.0,
            ftdi_latency_timer_ms: std::collections::BTreeMap::new(),
            adapters: std::collections::BTreeMap::new(),
        }
    }
}

impl HostConfig {
    pub(crate) fn validate(&self) -> Result<(), ScenarioError> {
        if !(self.latency_ms >= 0.0 && self.latency_ms <= 1000.0) {
            return Err(invalid("host.latency_ms", "must be within 0 .. 1000"));
        }
        if let Some((d, _)) = self
            .ftdi_latency_timer_ms
            .iter()
            .find(|(_, ms)| !(**ms >= 1.0 && **ms <= 255.0))
        {
            return Err(invalid(
                "host.ftdi_latency_timer_ms",
                format!("{d}: must be within 1 .. 255 (the FTDI timer's range)"),
            ));
        }
        if let Some(d) = self
            .adapters
            .keys()
            .find(|d| self.ftdi_latency_timer_ms.contains_key(*d))
        {
            return Err(invalid(
                "host.adapters",
                format!("{d}: also in host.ftdi_latency_timer_ms (one adapter per port)"),
            ));
        }
        if !(self.latency_jitter_ms >= 0.0 && self.latency_jitter_ms <= self.latency_ms) {
            return Err(invalid(
                "host.latency_jitter_ms",
                "must be within 0 .. latency_ms",
            ));
        }
        if !(1..=65_536).contains(&self.max_chunk_bytes) {
            return Err(invalid("host.max_chunk_bytes", "must be within 1 .. 65536"));
        }
        if !(0.0..=500.0).contains(&self.clock_drift_ppm_max) {
            return Err(invalid(
                "host.clock_drift_ppm_max",
                "must be within 0 .. 500",
            ));
        }
        Ok(())
    }
}
