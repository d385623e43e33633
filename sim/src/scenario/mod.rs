//! The scenario model (TOML via serde) and the built-in named scenarios.
//!
//! A scenario says where and when the flight happens, the ownship's and every intruder's
//! trajectory, which devices are present with their rates and output protocols, the host link
//! parameters, and a fault schedule. All times in a scenario are seconds from its start.

mod builtin;
mod devices;
mod faults;

use serde::{Deserialize, Serialize};

pub use builtin::{BUILTIN_NAMES, builtin};
pub use devices::{
    Adapter, BahrsConfig, BahrsNoise, BahrsSync, Devices, HostConfig, TtmrfConfig, Vn200Config,
    WatsonConfig, WatsonNoise,
};
pub(crate) use faults::active as faults_active;
pub use faults::{Axis, BodyAxis, Fault, HealthSignal, HealthWord};

use crate::rng::Rng;
use crate::trajectory::Segment;

/// Why a scenario could not be used.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// The TOML did not parse or a key is wrong (the message names it).
    #[error("scenario: {0}")]
    Toml(#[from] toml::de::Error),
    /// A value is out of range.
    #[error("scenario: {key}: {reason}")]
    Invalid {
        /// The offending key.
        key: String,
        /// Why.
        reason: String,
    },
    /// No built-in scenario of that name.
    #[error("scenario: no built-in scenario {0:?} (known: {known})", known = BUILTIN_NAMES.join(", "))]
    Unknown(String),
    /// The start time is malformed or outside the leap-second table.
    #[error("scenario: {0}")]
    Time(#[from] crate::units::TimeError),
}

/// A complete scenario.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name.
    pub name: String,
    /// What the scenario exercises.
    #[serde(default)]
    pub description: String,
    /// Start time, UTC, `YYYY-MM-DDTHH:MM:SSZ`.
    pub start_utc: String,
    /// Sea-level pressure of the day, hPa (1013.25 = standard day).
    #[serde(default = "default_qnh")]
    pub qnh_hpa: f64,
    /// The ownship.
    pub ownship: Ownship,
    /// Explicit intruders.
    #[serde(default)]
    pub intruders: Vec<Intruder>,
    /// Generated intruders (added after the explicit ones).
    #[serde(default)]
    pub traffic: Option<TrafficGenerator>,
    /// Devices on board and their ports.
    #[serde(default)]
    pub devices: Devices,
    /// Host side of the serial links.
    #[serde(default)]
    pub host: HostConfig,
    /// Fault schedule.
    #[serde(default)]
    pub faults: Vec<Fault>,
}

fn default_qnh() -> f64 {
    1013.25
}

/// The ownship's start and trajectory.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ownship {
    /// Start latitude, deg (the scenario origin).
    pub lat_deg: f64,
    /// Start longitude, deg.
    pub lon_deg: f64,
    /// Start height above the WGS-84 ellipsoid, m. Decision: the simulated geoid is the ellipsoid
    /// (undulation 0), so this is also the height above mean sea level used for pressure.
    pub height_m: f64,
    /// Initial track (true heading), deg.
    pub track_deg: f64,
    /// Horizontal speed, m/s.
    pub speed_mps: f64,
    /// Trajectory segments; straight and level after the last one.
    #[serde(default)]
    pub segments: Vec<Segment>,
    /// How many times the segment list is flown (0 and 1 both mean once), e.g. a racetrack.
    #[serde(default)]
    pub repeat: u32,
}

impl Ownship {
    /// The segment list with its repetitions expanded.
    pub fn expanded_segments(&self) -> Vec<Segment> {
        let n = self.repeat.clamp(1, 10_000) as usize;
        self.segments
            .iter()
            .copied()
            .cycle()
            .take(self.segments.len() * n)
            .collect()
    }
}

/// Radio link on which an intruder is received.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Link {
    /// ADS-B on 1090 MHz (Mode S extended squitter).
    Adsb1090,
    /// UAT on 978 MHz.
    Uat978,
    /// FLARM.
    Flarm,
}

/// One intruder.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Intruder {
    /// 24-bit address, upper-case hex (e.g. "4CA123").
    pub address: String,
    /// Link it transmits on.
    pub link: Link,
    /// Callsign (up to 8 characters).
    #[serde(default)]
    pub callsign: String,
    /// ADS-B emitter category, e.g. "A1" (light) .. "B6" (UAV).
    #[serde(default = "default_category")]
    pub emitter_category: String,
    /// Start position north of the scenario origin, m.
    pub north_m: f64,
    /// Start position east of the scenario origin, m.
    pub east_m: f64,
    /// Start height above the WGS-84 ellipsoid, m.
    pub height_m: f64,
    /// Initial track, deg.
    pub track_deg: f64,
    /// Horizontal speed, m/s.
    pub speed_mps: f64,
    /// Trajectory segments.
    #[serde(default)]
    pub segments: Vec<Segment>,
    /// A spoofed target: the position it reports is offset from where it truly is by this much
    /// (north, east, down, m). `None` for an honest target.
    #[serde(default)]
    pub spoof_offset_ned_m: Option<[f64; 3]>,
    /// Scenario time the spoofing starts, s (default 0: from the start). Before it the target
    /// reports its true position, so a receiver sees the reported position jump when it starts.
    #[serde(default)]
    pub spoof_from_s: f64,
    // --- issue 24: fail-safe scenarios ---
    /// A slow-drift spoof: from `spoof_from_s` the reported position moves away from the true one
    /// at this rate (north, east, m/s) while the reported velocity stays the true one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spoof_drift_ne_mps: Option<[f64; 2]>,
    /// Fields the target's reports leave out (JSON and CSV output): "altitude", "velocity"
    /// (track and speed), "vertical_rate".
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub omit: Vec<String>,
    /// Age of the data the module sends for this target, s: each report carries the state of
    /// this long ago (MAVLink says so in `tslc`, rounded to whole seconds).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub report_age_s: f64,
    /// Scenario time from which the target is no longer received (it flies on in the truth).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub silent_from_s: Option<f64>,
    // --- issue 25 point 7: a spoof that ends, so `suspected_spoofing` can clear ---
    /// Scenario time the spoofing (offset or drift) stops, s; absent: it never does. From then
    /// the target reports its true position again (a receiver sees the position jump back).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spoof_to_s: Option<f64>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn default_category() -> String {
    "A1".into()
}

/// Deterministic generator of many intruders (busy airspace).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrafficGenerator {
    /// Number of intruders.
    pub count: u32,
    /// They start uniformly within this radius of the origin, m.
    pub radius_m: f64,
    /// Heights are uniform within +-this of the ownship start height, m.
    pub height_band_m: f64,
    /// Seed of the generator (independent of the run seed: the scenario is the same every run).
    pub seed: u64,
}

/// Lowest height a generated intruder flies at, m above the WGS-84 ellipsoid.
const GENERATED_FLOOR_M: f64 = 150.0;

/// The height of a generated intruder `offset_m` from the ownship's start height. An offset that
/// would put it below [`GENERATED_FLOOR_M`] is mirrored upwards (a band of +-1500 m around an
/// ownship at 600 m drew intruders 900 m below the ellipsoid: impossible values that vigil now
/// rejects, issue 24). The random draw is the same, so the other intruders do not change.
fn generated_height_m(origin_height_m: f64, offset_m: f64) -> f64 {
    let h = origin_height_m + offset_m;
    if h < GENERATED_FLOOR_M {
        origin_height_m + offset_m.abs()
    } else {
        h
    }
}

impl TrafficGenerator {
    /// The generated intruders. Links cycle ADS-B, ADS-B, UAT, FLARM; addresses start at 0xA00000.
    pub fn generate(&self, origin_height_m: f64) -> Vec<Intruder> {
        let mut rng = Rng::stream(self.seed, "traffic");
        (0..self.count)
            .map(|i| {
                let r = self.radius_m * rng.uniform().sqrt();
                let bearing = rng.range(0.0, std::f64::consts::TAU);
                let link =
                    [Link::Adsb1090, Link::Adsb1090, Link::Uat978, Link::Flarm][i as usize % 4];
                let turn = rng.range(-2.0, 2.0);
                Intruder {
                    address: format!("{:06X}", 0xA0_0000 + i),
                    link,
                    callsign: format!("GEN{i:04}"),
                    emitter_category: if link == Link::Flarm {
                        "B1".into()
                    } else {
                        "A1".into()
                    },
                    north_m: r * bearing.cos(),
                    east_m: r * bearing.sin(),
                    height_m: generated_height_m(
                        origin_height_m,
                        rng.range(-self.height_band_m, self.height_band_m),
                    ),
                    track_deg: rng.range(0.0, 360.0),
                    speed_mps: rng.range(20.0, 120.0),
                    segments: vec![
                        Segment::Straight {
                            duration_s: rng.range(30.0, 300.0),
                        },
                        Segment::Turn {
                            duration_s: rng.range(10.0, 60.0),
                            rate_dps: turn,
                        },
                    ],
                    spoof_offset_ned_m: None,
                    spoof_from_s: 0.0,
                    spoof_drift_ne_mps: None,
                    omit: Vec::new(),
                    report_age_s: 0.0,
                    silent_from_s: None,
                    spoof_to_s: None,
                }
            })
            .collect()
    }
}

pub(crate) fn invalid(key: &str, reason: impl Into<String>) -> ScenarioError {
    ScenarioError::Invalid {
        key: key.into(),
        reason: reason.into(),
    }
}

impl Scenario {
    /// Parses and validates a scenario from TOML text.
    pub fn from_toml(text: &str) -> Result<Self, ScenarioError> {
        let s: Scenario = toml::from_str(text)?;
        s.validate()?;
        Ok(s)
    }

    /// The scenario as TOML text.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_default()
    }

    /// The explicit and the generated intruders.
    pub fn all_intruders(&self) -> Vec<Intruder> {
        let mut v = self.intruders.clone();
        if let Some(g) = &self.traffic {
            v.extend(g.generate(self.ownship.height_m));
        }
        v
    }

    /// Checks ranges; the error names the bad key.
    pub fn validate(&self) -> Result<(), ScenarioError> {
        crate::units::parse_utc_to_gps_ns(&self.start_utc)?;
        let o = &self.ownship;
        if !(-89.0..=89.0).contains(&o.lat_deg) {
            return Err(invalid("ownship.lat_deg", "must be within -89 .. 89"));
        }
        if !(-180.0..=180.0).contains(&o.lon_deg) {
            return Err(invalid("ownship.lon_deg", "must be within -180 .. 180"));
        }
        if !(0.0..=400.0).contains(&o.speed_mps) {
            return Err(invalid("ownship.speed_mps", "must be within 0 .. 400"));
        }
        if !(800.0..=1100.0).contains(&self.qnh_hpa) {
            return Err(invalid("qnh_hpa", "must be within 800 .. 1100"));
        }
        for (i, s) in o.segments.iter().enumerate() {
            check_segment(&format!("ownship.segments[{i}]"), s)?;
        }
        for (i, t) in self.intruders.iter().enumerate() {
            let key = format!("intruders[{i}]");
            match u32::from_str_radix(&t.address, 16) {
                Ok(a) if a <= 0xFF_FFFF && t.address.len() == 6 => {}
                _ => return Err(invalid(&format!("{key}.address"), "must be 6 hex digits")),
            }
            if t.callsign.len() > 8
                || !t
                    .callsign
                    .bytes()
                    .all(|b| b.is_ascii_alphanumeric() || b == b' ')
            {
                return Err(invalid(
                    &format!("{key}.callsign"),
                    "at most 8 letters or digits",
                ));
            }
            for (j, s) in t.segments.iter().enumerate() {
                check_segment(&format!("{key}.segments[{j}]"), s)?;
            }
            if let Some(f) = t
                .omit
                .iter()
                .find(|f| !["altitude", "velocity", "vertical_rate"].contains(&f.as_str()))
            {
                return Err(invalid(
                    &format!("{key}.omit"),
                    format!("unknown field '{f}': altitude, velocity or vertical_rate"),
                ));
            }
            if t.spoof_to_s
                .is_some_and(|to| !(to.is_finite() && to > t.spoof_from_s))
            {
                return Err(invalid(
                    &format!("{key}.spoof_to_s"),
                    "must be finite and after spoof_from_s",
                ));
            }
            if !(0.0..=60.0).contains(&t.report_age_s) {
                return Err(invalid(
                    &format!("{key}.report_age_s"),
                    "must be 0 ..= 60 s",
                ));
            }
        }
        self.devices.validate()?;
        self.host.validate()?;
        for (i, f) in self.faults.iter().enumerate() {
            f.validate(&format!("faults[{i}]"), &self.devices)?;
        }
        Ok(())
    }
}

fn check_segment(key: &str, s: &Segment) -> Result<(), ScenarioError> {
    let (d, omega, w) = s.params();
    if !(d.is_finite() && d >= 0.0) {
        return Err(invalid(
            &format!("{key}.duration_s"),
            "must be finite and >= 0",
        ));
    }
    if omega.to_degrees().abs() > 30.0 {
        return Err(invalid(
            &format!("{key}.rate_dps"),
            "must be within -30 .. 30",
        ));
    }
    if w.abs() > 100.0 {
        return Err(invalid(
            &format!("{key}.vertical_speed_mps"),
            "must be within -100 .. 100",
        ));
    }
    Ok(())
}

pub(crate) use invalid as invalid_key;
