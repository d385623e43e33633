//! Recordings a flight-test engineer can open (issue 20): the raw port channels (the source of
//! truth, what replays read) plus, as configured, decoded and fused JSON channels with JSON
//! Schemas, on the flight's UTC timeline, with a metadata record saying what made the file.
//! Written by `vigil run` (`[record]`) and by `vigil replay FLIGHT.mcap --out RICH.mcap`.
//!
//! Channels ([`ChannelSet`]):
//!
//! | topic | schema | written with |
//! |---|---|---|
//! | `/<device>/raw` | `vigil.raw.<protocol>` (bytes; no schema language) | every set |
//! | `/vigil/attitude_check` | `vigil.AttitudeCheck` ([`messages::AttitudeCheck`]) | `raw+fused`, `all` |
//! | `/vigil/ownship` | `vigil.Ownship` | `raw+fused`, `all` |
//! | `/vigil/ownship/fix` | `foxglove.LocationFix` (Map panel) | `raw+fused`, `all` |
//! | `/vigil/traffic` | `vigil.Traffic` | `raw+fused`, `all` |
//! | `/vigil/traffic/geojson` | `foxglove.GeoJSON` (Map panel) | `raw+fused`, `all` |
//! | `/vigil/integrity` | `vigil.Integrity` | `raw+fused`, `all` |
//! | `/vigil/alerts` | `vigil.Alert` (transition + active set) | `raw+fused`, `all` |
//! | `/vigil/alerts/log` | `foxglove.Log` (Log panel) | `raw+fused`, `all` |
//! | `/<device>/decoded` | `vigil.Decoded` | `all` |
//!
//! Time ([`LogClock`]): every message's `publish_time` (and the JSON messages' `t_host_ns`) is
//! the host monotonic time; its `log_time` is that time on the UTC timeline (ns since the Unix
//! epoch), through the host-clock model the service learns from the VN-200 (GPS time, then
//! GPS - UTC leap seconds), so the file opens at the flight's date and time. Until that model
//! locks, messages are held in memory and written with the first offset learned; after a lock is
//! lost the last offset is kept, so the timeline never jumps back.
//!
//! Decision (what a kill may lose): held messages are not on disk, so the hold is kept short.
//! While a clock reference has arrived (a lock is then a few seconds away) messages are held up
//! to [`PRELOCK_HOLD_NS`]; while none has (no VN-200 on the ports, or one without GPS time) only
//! up to [`NO_REFERENCE_HOLD_NS`], one flush period. After either (or [`PRELOCK_HOLD_BYTES`]) the
//! held messages are written with `log_time` = host monotonic time, and so is everything until
//! the lock: such a file opens at 1970 + uptime and jumps to the flight's date at the lock (the
//! `vigil.timeline` metadata written at the lock gives the offset). A SIGKILL therefore loses at
//! most one flush period (1 s) plus, before the lock, the held messages: at most 1 s without a
//! clock reference, at most 10 s while a lock is under way.

pub mod foxglove;
pub mod messages;

use std::collections::BTreeMap;
use std::io::{Seek, Write};

use anyhow::Result;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};
use vigil_bus::{AlertPayload, IntegrityPayload};
use vigil_fusion::pipeline::Fused;
use vigil_fusion::time::aligner::AlignedSample;
use vigil_record::{PortLink, RawRecorder};

use messages::ActiveAlert;

/// Longest time messages are held waiting for the clock to lock once a clock reference has
/// arrived, ns of host time.
pub const PRELOCK_HOLD_NS: u64 = 10_000_000_000;
/// Longest time messages are held while no clock reference has arrived, ns of host time (one
/// flush period: a lock is not in sight, and held messages would be lost on a kill).
pub const NO_REFERENCE_HOLD_NS: u64 = 1_000_000_000;
/// Most bytes held waiting for the clock to lock.
pub const PRELOCK_HOLD_BYTES: usize = 32 * 1024 * 1024;

/// Name of the metadata record with what made the file.
pub const METADATA_RUN: &str = "vigil.run";
/// Name of the metadata record written when the timeline locks.
pub const METADATA_TIMELINE: &str = "vigil.timeline";
/// Name of the metadata record with the devices' versions and serial numbers.
pub const METADATA_DEVICES: &str = "vigil.devices";

/// Which channels a recording gets (`[record] channels`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
pub enum ChannelSet {
    /// The raw port channels only.
    #[serde(rename = "raw")]
    Raw,
    /// Raw plus the fused topics (attitude checks, ownship, traffic, integrity, alerts).
    #[default]
    #[serde(rename = "raw+fused")]
    RawFused,
    /// Raw, fused, and every decoded message per device.
    #[serde(rename = "all")]
    All,
}

impl ChannelSet {
    /// Every set, in the order the command line lists them.
    pub const ALL: [ChannelSet; 3] = [ChannelSet::Raw, ChannelSet::RawFused, ChannelSet::All];

    /// The set's name in the configuration (`[record] channels`) and on the command line.
    pub const fn name(self) -> &'static str {
        match self {
            ChannelSet::Raw => "raw",
            ChannelSet::RawFused => "raw+fused",
            ChannelSet::All => "all",
        }
    }

    /// The set named `name` (see [`ChannelSet::name`]).
    pub fn from_name(name: &str) -> Option<ChannelSet> {
        Self::ALL.into_iter().find(|c| c.name() == name)
    }

    /// The fused channels are written.
    pub fn fused(self) -> bool {
        self != ChannelSet::Raw
    }

    /// The decoded channels are written.
    pub fn decoded(self) -> bool {
        self == ChannelSet::All
    }
}

/// What the service produced, handed to a recorder (and to `vigil replay --emit fused`).
#[derive(Debug, Clone)]
pub enum Tapped {
    /// A decoded message with its time (only when decoded channels are wanted).
    Sample(Box<AlignedSample>),
    /// A fused output.
    Fused(Box<Fused>),
    /// An integrity report.
    Integrity(Box<IntegrityPayload>),
    /// The alert transitions of one monitor evaluation and the active set after it.
    Alerts(Vec<AlertPayload>, Vec<ActiveAlert>),
}

/// The host-to-UTC offset used for log times (see the module documentation).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LogClock {
    /// UTC (Unix ns) minus host monotonic ns, once known.
    pub offset_ns: Option<i64>,
    /// The clock did not lock within the hold: host time is written until it does.
    pub gave_up: bool,
}

impl LogClock {
    /// The log time of a message produced at host time `t_host_ns`, `None` while held.
    pub fn log_time(&self, t_host_ns: u64) -> Option<u64> {
        match self.offset_ns {
            Some(off) => {
                let t = i64::try_from(t_host_ns)
                    .unwrap_or(i64::MAX)
                    .saturating_add(off);
                Some(u64::try_from(t).unwrap_or(0))
            }
            None => self.gave_up.then_some(t_host_ns),
        }
    }
}

/// One JSON channel: its id.
#[derive(Debug, Clone, Copy)]
struct Fx {
    check: u16,
    ownship: u16,
    fix: u16,
    traffic: u16,
    geojson: u16,
    integrity: u16,
    alerts: u16,
    log: u16,
}

/// The JSON Schema of `T`, as bytes.
pub fn schema_of<T: JsonSchema>() -> Vec<u8> {
    serde_json::to_vec(&schemars::schema_for!(T)).unwrap_or_default()
}

/// A message held until the clock locks: (channel, host time, bytes).
type Held = (u16, u64, Vec<u8>);

/// The recorder of `vigil run` and `vigil replay --out` (see the module documentation).
pub struct RichRecorder<W: Write + Seek> {
    rec: RawRecorder<W>,
    set: ChannelSet,
    fused: Option<Fx>,
    decoded: BTreeMap<&'static str, u16>,
    clock: LogClock,
    held: Vec<Held>,
    held_bytes: usize,
    line: Vec<u8>,
    /// Device identities seen (`vigil.devices`), and whether they changed since written.
    devices: BTreeMap<String, String>,
    devices_changed: bool,
}

impl<W: Write + Seek> RichRecorder<W> {
    /// A recorder on `rec` (its raw channels already added) writing the channels of `set`.
    pub fn new(mut rec: RawRecorder<W>, set: ChannelSet) -> Result<Self> {
        let fused = if set.fused() {
            let none = BTreeMap::new();
            let mut add = |topic: &str, name: &str, schema: Vec<u8>| {
                rec.add_schema_channel(topic, name, &schema, &none)
            };
            Some(Fx {
                check: add(
                    "/vigil/attitude_check",
                    "vigil.AttitudeCheck",
                    schema_of::<messages::AttitudeCheck>(),
                )?,
                ownship: add(
                    "/vigil/ownship",
                    "vigil.Ownship",
                    schema_of::<messages::Ownship>(),
                )?,
                fix: add(
                    "/vigil/ownship/fix",
                    "foxglove.LocationFix",
                    schema_of::<foxglove::LocationFix>(),
                )?,
                traffic: add(
                    "/vigil/traffic",
                    "vigil.Traffic",
                    schema_of::<messages::Traffic>(),
                )?,
                geojson: add(
                    "/vigil/traffic/geojson",
                    "foxglove.GeoJSON",
                    schema_of::<foxglove::GeoJson>(),
                )?,
                integrity: add(
                    "/vigil/integrity",
                    "vigil.Integrity",
                    schema_of::<messages::Integrity>(),
                )?,
                alerts: add(
                    "/vigil/alerts",
                    "vigil.Alert",
                    schema_of::<messages::Alert>(),
                )?,
                log: add(
                    "/vigil/alerts/log",
                    "foxglove.Log",
                    schema_of::<foxglove::Log>(),
                )?,
            })
        } else {
            None
        };
        Ok(Self {
            rec,
            set,
            fused,
            decoded: BTreeMap::new(),
            clock: LogClock::default(),
            held: Vec::new(),
            held_bytes: 0,
            line: Vec::with_capacity(1024),
            devices: BTreeMap::new(),
            devices_changed: false,
        })
    }

    /// Writes a metadata record.
    pub fn write_metadata(&mut self, name: &str, m: BTreeMap<String, String>) -> Result<()> {
        Ok(self.rec.write_metadata(name, m)?)
    }

    /// Tells the recorder the host-to-UTC offset at host time `t_host_ns` (`None`: not locked)
    /// and whether the clock has had any reference yet (it decides how long messages are held,
    /// see the module documentation). At the first offset the held messages are written.
    pub fn set_clock(
        &mut self,
        t_host_ns: u64,
        utc_offset_ns: Option<i64>,
        references_seen: bool,
    ) -> Result<()> {
        match utc_offset_ns {
            Some(off) => {
                let first = self.clock.offset_ns.is_none();
                self.clock.offset_ns = Some(off);
                if first {
                    self.write_metadata(
                        METADATA_TIMELINE,
                        BTreeMap::from([
                            ("utc_minus_host_ns".to_string(), off.to_string()),
                            ("locked_at_host_ns".to_string(), t_host_ns.to_string()),
                            (
                                "host_time_before_lock".to_string(),
                                self.clock.gave_up.to_string(),
                            ),
                        ]),
                    )?;
                    self.release_held()?;
                }
            }
            None => {
                let oldest = self.held.first().map(|h| h.1);
                let hold_ns = if references_seen {
                    PRELOCK_HOLD_NS
                } else {
                    NO_REFERENCE_HOLD_NS
                };
                let over_time = oldest.is_some_and(|t| t_host_ns.saturating_sub(t) > hold_ns);
                if !self.clock.gave_up && (over_time || self.held_bytes > PRELOCK_HOLD_BYTES) {
                    self.clock.gave_up = true;
                    self.release_held()?;
                }
            }
        }
        Ok(())
    }

    fn release_held(&mut self) -> Result<()> {
        for (ch, t, data) in std::mem::take(&mut self.held) {
            let log = self.clock.log_time(t).unwrap_or(t);
            self.rec.write_at(ch, log, t, &data)?;
        }
        self.held_bytes = 0;
        Ok(())
    }

    fn put(&mut self, channel: u16, t_host_ns: u64, data: &[u8]) -> Result<()> {
        match self.clock.log_time(t_host_ns) {
            Some(log) => Ok(self.rec.write_at(channel, log, t_host_ns, data)?),
            None => {
                self.held_bytes += data.len();
                self.held.push((channel, t_host_ns, data.to_vec()));
                Ok(())
            }
        }
    }

    fn put_json<T: Serialize>(&mut self, channel: u16, t_host_ns: u64, v: &T) -> Result<()> {
        let mut line = std::mem::take(&mut self.line);
        line.clear();
        serde_json::to_writer(&mut line, v)?;
        let r = self.put(channel, t_host_ns, &line);
        self.line = line;
        r
    }

    /// Adds a raw port channel (a replay meets its ports as it goes); returns its port index.
    pub fn add_port(&mut self, device: &str, protocol: &str, link: &PortLink) -> Result<u16> {
        Ok(self.rec.add_port_with_link(device, protocol, link)?)
    }

    /// Records one raw chunk of port `port` received at host time `t_host_ns`.
    pub fn raw(&mut self, port: u16, t_host_ns: u64, bytes: &[u8]) -> Result<()> {
        let ch = self
            .rec
            .raw_channel(port)
            .ok_or_else(|| anyhow::anyhow!("no raw channel for port {port}"))?;
        self.put(ch, t_host_ns, bytes)
    }

    /// Records what the service produced at host time `t_host_ns`.
    pub fn tapped(&mut self, t_host_ns: u64, t: &Tapped) -> Result<()> {
        match t {
            Tapped::Sample(s) => {
                if let Some((k, v)) = identity(s)
                    && self.devices.get(&k) != Some(&v)
                {
                    self.devices.insert(k, v);
                    self.devices_changed = true;
                }
                if self.set.decoded() {
                    self.sample(t_host_ns, s)?;
                }
                Ok(())
            }
            Tapped::Fused(f) => self.fused(t_host_ns, f),
            Tapped::Integrity(p) => match self.fused {
                Some(fx) => self.put_json(
                    fx.integrity,
                    t_host_ns,
                    &messages::Integrity::of(p, t_host_ns),
                ),
                None => Ok(()),
            },
            Tapped::Alerts(alerts, active) => {
                let Some(fx) = self.fused else { return Ok(()) };
                for a in alerts {
                    let m = messages::Alert::of(a, active, t_host_ns);
                    self.put_json(fx.alerts, t_host_ns, &m)?;
                    if let Some(l) = foxglove::Log::of(&m) {
                        self.put_json(fx.log, t_host_ns, &l)?;
                    }
                }
                Ok(())
            }
        }
    }

    fn sample(&mut self, t_host_ns: u64, s: &AlignedSample) -> Result<()> {
        let device = s.device.name();
        let ch = match self.decoded.get(device) {
            Some(&c) => c,
            None => {
                let c = self.rec.add_schema_channel(
                    &format!("/{device}/decoded"),
                    "vigil.Decoded",
                    &schema_of::<messages::Decoded>(),
                    &BTreeMap::from([("device".to_string(), device.to_string())]),
                )?;
                self.decoded.insert(device, c);
                c
            }
        };
        self.put_json(ch, t_host_ns, &messages::Decoded::of(s, t_host_ns))
    }

    fn fused(&mut self, t_host_ns: u64, f: &Fused) -> Result<()> {
        let Some(fx) = self.fused else { return Ok(()) };
        match f {
            Fused::Attitude(a) => self.put_json(
                fx.check,
                t_host_ns,
                &messages::AttitudeCheck::of(a, t_host_ns),
            ),
            // Prompt outputs repeat the check verdicts at the VN-200's rate: not recorded (the raw
            // channels replay them).
            Fused::Prompt(_) => Ok(()),
            Fused::Ownship(o) => {
                let m = messages::Ownship::of(o, t_host_ns);
                self.put_json(fx.ownship, t_host_ns, &m)?;
                match foxglove::LocationFix::of(&m) {
                    Some(fix) => self.put_json(fx.fix, t_host_ns, &fix),
                    None => Ok(()),
                }
            }
            Fused::Traffic(p) => {
                let m = messages::Traffic::of(p, t_host_ns);
                self.put_json(fx.traffic, t_host_ns, &m)?;
                self.put_json(fx.geojson, t_host_ns, &foxglove::GeoJson::of(&m))
            }
        }
    }

    /// Ends the open chunk and writes it out (call at least once a second), with the devices'
    /// identities when they changed.
    pub fn flush(&mut self) -> Result<()> {
        self.write_devices()?;
        Ok(self.rec.flush()?)
    }

    fn write_devices(&mut self) -> Result<()> {
        if self.devices_changed {
            self.devices_changed = false;
            let m = self.devices.clone();
            self.write_metadata(METADATA_DEVICES, m)?;
        }
        Ok(())
    }

    /// Writes what is held (with host times if the clock never locked) and the summary, and
    /// returns the inner writer.
    pub fn finish(mut self) -> Result<W> {
        if !self.held.is_empty() {
            self.clock.gave_up = true;
            self.release_held()?;
        }
        self.write_devices()?;
        Ok(self.rec.finish()?)
    }
}

/// The metadata record of what made a recording: vigil's version and git commit, the command,
/// the full configuration (TOML) and the port list.
pub fn run_metadata(command: &str, config_toml: &str) -> BTreeMap<String, String> {
    BTreeMap::from([
        ("vigil_version".to_string(), env!("CARGO_PKG_VERSION").to_string()),
        ("git_commit".to_string(), env!("VIGIL_GIT_COMMIT").to_string()),
        ("command".to_string(), command.to_string()),
        ("config_toml".to_string(), config_toml.to_string()),
        ("timeline".to_string(), "log_time: UTC ns since the Unix epoch once the clock locks; publish_time: host monotonic ns".to_string()),
    ])
}

/// A device's identity in a decoded message, as (key, value) of the `vigil.devices` metadata:
/// the BAHRS software (0x0F) and hardware (0x1F) versions, the VN-200's model, hardware
/// version, serial number and firmware registers (1-4) when a `$VNRRG` response carries them.
/// Decision: identity is taken from what the devices send; vigil does not query it itself yet
/// (the VN-200 registers are read only if something asks for them on the port).
pub fn identity(s: &AlignedSample) -> Option<(String, String)> {
    use vigil_drivers::bahrs::Message as B;
    use vigil_drivers::vn200::Vn200Message;
    use vigil_drivers::vn200::ascii::AsciiMessage;
    use vigil_drivers::vn200::ascii::RegisterValue as R;
    use vigil_fusion::time::aligner::Sample;
    let kv = |k: &str, v: String| Some((k.to_string(), v));
    match &s.aligned.message {
        Sample::Bahrs(B::SoftwareVersion(v)) => kv(
            "bahrs.software_version",
            format!("{}.{} {}", v.major, v.minor, v.project_code_str()),
        ),
        Sample::Bahrs(B::HardwareVersion(h)) => kv(
            "bahrs.hardware_version",
            format!(
                "mcu 0x{:04X} uid {:08X}-{:08X}-{:08X}",
                h.mcu_id, h.unique_id[0], h.unique_id[1], h.unique_id[2]
            ),
        ),
        Sample::Vn200(m) => match &**m {
            Vn200Message::Ascii(AsciiMessage::ReadResponse { value }) => match value {
                R::Model { model } => kv("vn200.model", model.clone()),
                R::HardwareVersion { version } => kv("vn200.hardware_version", version.to_string()),
                R::SerialNumber { serial } => kv("vn200.serial_number", serial.to_string()),
                R::FirmwareVersion { version } => kv("vn200.firmware_version", version.clone()),
                _ => None,
            },
            _ => None,
        },
        _ => None,
    }
}
