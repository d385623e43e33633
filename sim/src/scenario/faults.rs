//! The fault schedule: what goes wrong, when (seconds from the scenario start) and on which device.

use serde::{Deserialize, Serialize};

use super::{Devices, ScenarioError, invalid_key as invalid};

/// An attitude axis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    /// Roll.
    Roll,
    /// Pitch.
    Pitch,
    /// Magnetic heading.
    Heading,
}

/// A body axis of an inertial sensor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BodyAxis {
    /// Body x (forward).
    X,
    /// Body y (right).
    Y,
    /// Body z (down).
    Z,
}

impl BodyAxis {
    /// Index 0, 1, 2 of x, y, z.
    pub fn index(self) -> usize {
        match self {
            BodyAxis::X => 0,
            BodyAxis::Y => 1,
            BodyAxis::Z => 2,
        }
    }
}

/// A BAHRS signal whose 2-bit health the schedule sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HealthSignal {
    /// Every signal of 0x01 and 0x02.
    All,
    /// Specific force, all axes.
    SpecificForce,
    /// Angular rate, all axes.
    AngularRate,
    /// Pressure height.
    PressureHeight,
    /// Downward velocity.
    VelocityDown,
    /// Roll.
    Roll,
    /// Pitch.
    Pitch,
    /// Magnetic heading.
    Heading,
}

/// A health value (section 2.4 of the BAHRS protocol).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HealthWord {
    /// 00.
    Unavailable,
    /// 01.
    Safe,
    /// 10.
    IntegrityRisk,
    /// 11.
    Undefined,
}

/// One scheduled fault. `to_s` absent means "until the end".
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Fault {
    /// A BAHRS attitude bias: `bias_deg + rate_dps x (t - from_s)` added to one axis.
    BahrsAttitudeBias {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Axis.
        axis: Axis,
        /// Constant part, deg.
        #[serde(default)]
        bias_deg: f64,
        /// Ramp, deg/s.
        #[serde(default)]
        rate_dps: f64,
    },
    /// Issue 25: the BAHRS static pressure port is blocked. Its pressure height stays at the
    /// value it had when the port blocked and its downward velocity reads 0, while its health
    /// still says "safe" (the unit does not notice).
    PressurePortBlocked {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
    },
    /// Issue 25 point 6: the VN-200's vertical channel drifts: its altitude gains
    /// `rate_mps x (t - from_s)` and its NED down velocity reads `rate_mps` less (a climb
    /// `rate_mps` faster than the truth), while its INS status still says Tracking with a fix.
    Vn200VerticalDrift {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Added climb rate, m/s (up positive).
        rate_mps: f64,
    },
    /// Issue 25: a BAHRS gyro bias on one body axis, `bias_dps + rate_dps_per_s x (t - from_s)`
    /// deg/s added to the angular rate of 0x01, while its health still says "safe".
    BahrsGyroBias {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Body axis.
        axis: BodyAxis,
        /// Constant part, deg/s.
        #[serde(default)]
        bias_dps: f64,
        /// Growth, deg/s per second.
        #[serde(default)]
        rate_dps_per_s: f64,
    },
    /// BAHRS health bits forced to a value.
    BahrsHealth {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Which signal(s).
        signal: HealthSignal,
        /// The value sent.
        health: HealthWord,
    },
    /// A magnetic disturbance: the magnetic heading of BAHRS and Watson is off by this much.
    MagneticDisturbance {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Heading error, deg.
        heading_offset_deg: f64,
    },
    /// A device restarts: counters and its clock start again, versions are sent again.
    DeviceReset {
        /// Device name.
        device: String,
        /// When, s.
        at_s: f64,
    },
    /// No PPS reaches the BAHRS sync input (and no PPS-based timing).
    PpsLoss {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
    },
    /// The VN-200 / TT-Multi-RF lose GNSS (used by their device models).
    GnssOutage {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Only this device's receiver loses its fix (e.g. "vn200": an antenna fault while the
        /// TT-Multi-RF's own GNSS keeps working); absent: every receiver (jamming).
        #[serde(default)]
        device: Option<String>,
    },
    /// The link of a device is cut: bytes sent meanwhile are lost.
    LinkLoss {
        /// Device name.
        device: String,
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
    },
    /// Random bit errors on a link, at `rate` per bit.
    BitErrors {
        /// Device name.
        device: String,
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Probability per bit.
        rate: f64,
    },
    /// Random dropped bytes on a link, at `rate` per byte.
    DroppedBytes {
        /// Device name.
        device: String,
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Probability per byte.
        rate: f64,
    },
    // --- issue 25 point 4: a health disagreement ---
    /// The BAHRS sync input is wired to a pulse that does not follow the VN-200's GNSS fix (e.g.
    /// another receiver's PPS, or a VN-200 SyncOut not in GpsPps mode): pulses keep reaching
    /// the BAHRS every GPS second in this window even while the VN-200 has no fix (the ICD's
    /// SyncOut GpsPps would stop then, Table 3.22). A scheduled `pps_loss` still stops them.
    BahrsSyncMiswired {
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
    },
    // --- issue 25 point 7: a fault that makes `ins_not_tracking` reachable ---
    /// The VN-200's INS filter restarts at `at_s` (e.g. a `$VNRRS`-style filter reset, or the
    /// filter diverging and re-initialising). Modelled from the ICD (24-20006-R1, firmware 2.1
    /// changes: "An INS reset now holds INS Status Mode at 0 for 1 second"; Table 2.78): InsStatus
    /// mode NotTracking (0, outputs invalid) for 1 s, then Aligning (1: position and velocity
    /// valid, attitude not) for `aligning_s`, then Tracking again. The ICD does not say how long
    /// aligning takes (it depends on the motion): the scenario says. Output messages keep flowing
    /// (only the mode bits change), with the truth plus noise in their attitude fields.
    InsReset {
        /// When the filter restarts, s.
        at_s: f64,
        /// Time in Aligning after the 1 s in NotTracking, s.
        #[serde(default)]
        aligning_s: f64,
    },
    // --- issue 18 point 4: a device's own time wrong ---
    /// A device names time wrongly: from `from_s` its time stamps are `offset_ms` off while its
    /// data, its PPS and its link stay right. The VN-200: TimeGps, GpsTow and GpsWeek (a GPS
    /// time a second off after a leap-second error, a week off after a week-number error);
    /// TimeGpsPps (time since the pulse) stays right. The TT-Multi-RF: JSON `ts` and raw TS24h
    /// (a `ts` a second off); TS1s, NMEA and the GNSS section stay right.
    DeviceTimeOffset {
        /// "vn200" or "ttmrf".
        device: String,
        /// Start, s.
        from_s: f64,
        /// End, s.
        to_s: Option<f64>,
        /// Added to every time stamp, ms.
        offset_ms: f64,
    },
}

/// Whether `t_s` lies in [from, to).
pub(crate) fn active(t_s: f64, from_s: f64, to_s: Option<f64>) -> bool {
    t_s >= from_s && to_s.is_none_or(|to| t_s < to)
}

const DEVICES: [&str; 4] = ["bahrs", "watson", "vn200", "ttmrf"];

impl Fault {
    pub(crate) fn validate(&self, key: &str, _devices: &Devices) -> Result<(), ScenarioError> {
        let (from, to) = match self {
            Fault::BahrsAttitudeBias { from_s, to_s, .. }
            | Fault::BahrsHealth { from_s, to_s, .. }
            | Fault::PressurePortBlocked { from_s, to_s }
            | Fault::Vn200VerticalDrift { from_s, to_s, .. }
            | Fault::BahrsGyroBias { from_s, to_s, .. }
            | Fault::MagneticDisturbance { from_s, to_s, .. }
            | Fault::PpsLoss { from_s, to_s }
            | Fault::BahrsSyncMiswired { from_s, to_s }
            | Fault::GnssOutage { from_s, to_s, .. }
            | Fault::LinkLoss { from_s, to_s, .. }
            | Fault::BitErrors { from_s, to_s, .. }
            | Fault::DroppedBytes { from_s, to_s, .. }
            | Fault::DeviceTimeOffset { from_s, to_s, .. } => (*from_s, *to_s),
            Fault::DeviceReset { at_s, .. } | Fault::InsReset { at_s, .. } => (*at_s, None),
        };
        if !(from.is_finite() && from >= 0.0) {
            return Err(invalid(&format!("{key}.from_s"), "must be finite and >= 0"));
        }
        if to.is_some_and(|t| !(t.is_finite() && t > from)) {
            return Err(invalid(
                &format!("{key}.to_s"),
                "must be finite and after from_s",
            ));
        }
        match self {
            Fault::DeviceReset { device, .. }
            | Fault::LinkLoss { device, .. }
            | Fault::BitErrors { device, .. }
            | Fault::DroppedBytes { device, .. }
                if !DEVICES.contains(&device.as_str()) =>
            {
                Err(invalid(
                    &format!("{key}.device"),
                    format!("must be one of {}", DEVICES.join(", ")),
                ))
            }
            Fault::GnssOutage {
                device: Some(device),
                ..
            } if !["vn200", "ttmrf"].contains(&device.as_str()) => Err(invalid(
                &format!("{key}.device"),
                "must be vn200 or ttmrf (the devices with a GNSS receiver)",
            )),
            Fault::DeviceTimeOffset { device, .. }
                if !["vn200", "ttmrf"].contains(&device.as_str()) =>
            {
                Err(invalid(
                    &format!("{key}.device"),
                    "must be vn200 or ttmrf (the devices that stamp their own time)",
                ))
            }
            Fault::DeviceTimeOffset { offset_ms, .. } if !offset_ms.is_finite() => {
                Err(invalid(&format!("{key}.offset_ms"), "must be finite"))
            }
            Fault::InsReset { aligning_s, .. }
                if !(aligning_s.is_finite() && *aligning_s >= 0.0) =>
            {
                Err(invalid(
                    &format!("{key}.aligning_s"),
                    "must be finite and >= 0",
                ))
            }
            Fault::BitErrors { rate, .. } | Fault::DroppedBytes { rate, .. }
                if !(0.0..=0.5).contains(rate) =>
            {
                Err(invalid(&format!("{key}.rate"), "must be within 0 .. 0.5"))
            }
            _ => Ok(()),
        }
    }
}
