//! Device models: each turns the world's truth into the device's messages, encoded with the
//! drivers' own encoders, with the device's clock, noise and scheduled faults.
//!
//! A model plugs in through [`DeviceModel`]; the engine owns one serial link per model: [`bahrs`],
//! [`watson`], [`vn200`] and [`ttmrf`], in that port order. Adding one:
//! 1. `sim/src/device/<name>.rs`: a struct implementing [`DeviceModel`]; draw randomness only from
//!    `Rng::stream(seed, "<name>/...")`; emit each message with the driver's encoder, its true
//!    `t_gps_ns` and its true values (SI, units in names); answer host commands in `receive`;
//!    use [`FaultSchedule`] (`gnss_lost`, `pps_lost`, `resets`) and `World::intruders`.
//! 2. Build it in `Simulator::with_magnetic` from `scenario.devices.<name>` and drop the name from
//!    `devices_without_model`.
//! 3. `vigil replay`: add the driver's decoder to `bins/src/replay.rs` (keyed by the model's
//!    `protocol()` string).

pub mod bahrs;
#[cfg(test)]
mod scripted_host;
pub mod ttmrf;
pub mod ttmrf_binary;
pub mod vn200;
pub mod watson;

use serde_json::{Map, Value};
use vigil_drivers::bahrs::Health;

use crate::scenario::faults_active as active;
use crate::scenario::{Axis, Fault, HealthSignal, HealthWord};
use crate::truth::World;

/// One message a device puts on its serial line.
#[derive(Debug, Clone, PartialEq)]
pub struct Emission {
    /// GPS time at which the device has the message ready to send, ns.
    pub t_ready_gps_ns: i64,
    /// The encoded message.
    pub bytes: Vec<u8>,
    /// Message type name, for the truth record.
    pub kind: &'static str,
    /// True GPS time the message refers to, ns.
    pub t_gps_ns: i64,
    /// True values it encodes (before noise) and the device's own stamps.
    pub values: Map<String, Value>,
}

/// A simulated device on one serial port.
pub trait DeviceModel: Send {
    /// Device name, also the port name in recordings ("bahrs").
    fn name(&self) -> &'static str;
    /// Wire protocol of the port, for the recording's channel metadata.
    fn protocol(&self) -> &'static str;
    /// Baud rate of the port (10 bits per byte on the wire).
    fn baud(&self) -> u32;
    /// Appends, in order of ready time, every message that becomes ready before `until_gps_ns`.
    fn advance(
        &mut self,
        world: &World,
        faults: &FaultSchedule,
        until_gps_ns: i64,
        out: &mut Vec<Emission>,
    );
    /// Bytes the host wrote to the device's port at `t_gps_ns` (commands: the VN-200 ASCII
    /// protocol, TT-Multi-RF AT commands). The default ignores them (BAHRS and Watson only talk).
    /// Answers come out of the next `advance`.
    fn receive(&mut self, t_gps_ns: i64, bytes: &[u8]) {
        let _ = (t_gps_ns, bytes);
    }
}

/// The scenario's fault schedule with the queries device and link models need.
#[derive(Debug, Clone, Default)]
pub struct FaultSchedule {
    faults: Vec<Fault>,
}

fn health_of(w: HealthWord) -> Health {
    match w {
        HealthWord::Unavailable => Health::Unavailable,
        HealthWord::Safe => Health::Safe,
        HealthWord::IntegrityRisk => Health::IntegrityRisk,
        HealthWord::Undefined => Health::Undefined,
    }
}

impl FaultSchedule {
    /// The schedule of a scenario.
    pub fn new(faults: &[Fault]) -> Self {
        Self {
            faults: faults.to_vec(),
        }
    }

    /// The faults.
    pub fn faults(&self) -> &[Fault] {
        &self.faults
    }

    /// BAHRS attitude error on `axis` at `t_s` (seconds from start), rad.
    pub fn bahrs_attitude_bias_rad(&self, t_s: f64, axis: Axis) -> f64 {
        let mut deg = 0.0;
        for f in &self.faults {
            if let Fault::BahrsAttitudeBias {
                from_s,
                to_s,
                axis: a,
                bias_deg,
                rate_dps,
            } = f
                && *a == axis
                && active(t_s, *from_s, *to_s)
            {
                deg += bias_deg + rate_dps * (t_s - from_s);
            }
        }
        deg.to_radians()
    }

    /// Whether the BAHRS pressure port is blocked at `t_s`.
    pub fn pressure_port_blocked(&self, t_s: f64) -> bool {
        self.faults.iter().any(|f| {
            matches!(f, Fault::PressurePortBlocked { from_s, to_s } if active(t_s, *from_s, *to_s))
        })
    }

    /// The VN-200 vertical drift at `t_s` (issue 25 point 6): added height, m, and added climb
    /// rate, m/s (up positive); zero without the fault.
    pub fn vn200_vertical_drift(&self, t_s: f64) -> (f64, f64) {
        self.faults.iter().fold((0.0, 0.0), |(h, r), f| match f {
            Fault::Vn200VerticalDrift {
                from_s,
                to_s,
                rate_mps,
            } if active(t_s, *from_s, *to_s) => (h + rate_mps * (t_s - from_s), r + rate_mps),
            _ => (h, r),
        })
    }

    /// BAHRS gyro bias per body axis at `t_s`, rad/s.
    pub fn bahrs_gyro_bias_radps(&self, t_s: f64) -> [f64; 3] {
        let mut dps = [0.0; 3];
        for f in &self.faults {
            if let Fault::BahrsGyroBias {
                from_s,
                to_s,
                axis,
                bias_dps,
                rate_dps_per_s,
            } = f
                && active(t_s, *from_s, *to_s)
            {
                dps[axis.index()] += bias_dps + rate_dps_per_s * (t_s - from_s);
            }
        }
        dps.map(f64::to_radians)
    }

    /// The health the schedule forces on a BAHRS signal at `t_s`, if any (the last matching
    /// entry wins).
    pub fn bahrs_health(&self, t_s: f64, signal: HealthSignal) -> Option<Health> {
        let mut h = None;
        for f in &self.faults {
            if let Fault::BahrsHealth {
                from_s,
                to_s,
                signal: s,
                health,
            } = f
                && (*s == signal || *s == HealthSignal::All)
                && active(t_s, *from_s, *to_s)
            {
                h = Some(health_of(*health));
            }
        }
        h
    }

    /// Magnetic heading error of the magnetic sensors at `t_s`, rad.
    pub fn magnetic_offset_rad(&self, t_s: f64) -> f64 {
        self.faults
            .iter()
            .filter_map(|f| match f {
                Fault::MagneticDisturbance {
                    from_s,
                    to_s,
                    heading_offset_deg,
                } if active(t_s, *from_s, *to_s) => Some(heading_offset_deg.to_radians()),
                _ => None,
            })
            .sum()
    }

    /// Whether the PPS is lost at `t_s`.
    pub fn pps_lost(&self, t_s: f64) -> bool {
        self.faults
            .iter()
            .any(|f| matches!(f, Fault::PpsLoss { from_s, to_s } if active(t_s, *from_s, *to_s)))
    }

    /// Whether the BAHRS sync input is miswired at `t_s` (its pulses do not follow the VN-200's
    /// fix).
    pub fn bahrs_sync_miswired(&self, t_s: f64) -> bool {
        self.faults.iter().any(|f| {
            matches!(f, Fault::BahrsSyncMiswired { from_s, to_s } if active(t_s, *from_s, *to_s))
        })
    }

    /// Whether `device`'s GNSS receiver has no fix at `t_s`.
    pub fn gnss_lost(&self, device: &str, t_s: f64) -> bool {
        self.faults.iter().any(|f| {
            matches!(f, Fault::GnssOutage { from_s, to_s, device: d }
                if active(t_s, *from_s, *to_s) && d.as_deref().is_none_or(|d| d == device))
        })
    }

    /// Reset times of a device, s from start, ascending.
    pub fn resets(&self, device: &str) -> Vec<f64> {
        let mut v: Vec<f64> = self
            .faults
            .iter()
            .filter_map(|f| match f {
                Fault::DeviceReset { device: d, at_s } if d == device => Some(*at_s),
                _ => None,
            })
            .collect();
        v.sort_by(f64::total_cmp);
        v
    }

    /// The VN-200 INS mode (InsStatus bits 0-1) an [`Fault::InsReset`] forces at `t_s`, if any:
    /// 0 (NotTracking) for the first second after the reset, then 1 (Aligning) for its
    /// `aligning_s`. The latest reset that started at or before `t_s` decides.
    pub fn ins_reset_mode(&self, t_s: f64) -> Option<u16> {
        /// NotTracking after an INS reset (ICD firmware 2.1 changes), s.
        const NOT_TRACKING_S: f64 = 1.0;
        self.faults
            .iter()
            .filter_map(|f| match f {
                Fault::InsReset { at_s, aligning_s } if t_s >= *at_s => Some((*at_s, *aligning_s)),
                _ => None,
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
            .and_then(|(at_s, aligning_s)| {
                let since = t_s - at_s;
                if since < NOT_TRACKING_S {
                    Some(0)
                } else if since < NOT_TRACKING_S + aligning_s {
                    Some(1)
                } else {
                    None
                }
            })
    }

    /// What a [`Fault::DeviceTimeOffset`] adds to `device`'s time stamps at `t_s`, ns.
    pub fn time_offset_ns(&self, device: &str, t_s: f64) -> i64 {
        self.faults
            .iter()
            .filter_map(|f| match f {
                Fault::DeviceTimeOffset {
                    device: d,
                    from_s,
                    to_s,
                    offset_ms,
                } if d == device && active(t_s, *from_s, *to_s) => {
                    Some((offset_ms * 1e6).round() as i64)
                }
                _ => None,
            })
            .sum()
    }

    /// Whether the link of `device` is cut at `t_s`.
    pub fn link_lost(&self, device: &str, t_s: f64) -> bool {
        self.faults.iter().any(
            |f| matches!(f, Fault::LinkLoss { device: d, from_s, to_s } if d == device && active(t_s, *from_s, *to_s)),
        )
    }

    /// Bit error rate (per bit) on the link of `device` at `t_s`.
    pub fn bit_error_rate(&self, device: &str, t_s: f64) -> f64 {
        self.faults
            .iter()
            .filter_map(|f| match f {
                Fault::BitErrors {
                    device: d,
                    from_s,
                    to_s,
                    rate,
                } if d == device && active(t_s, *from_s, *to_s) => Some(*rate),
                _ => None,
            })
            .sum()
    }

    /// Dropped-byte rate (per byte) on the link of `device` at `t_s`.
    pub fn drop_rate(&self, device: &str, t_s: f64) -> f64 {
        self.faults
            .iter()
            .filter_map(|f| match f {
                Fault::DroppedBytes {
                    device: d,
                    from_s,
                    to_s,
                    rate,
                } if d == device && active(t_s, *from_s, *to_s) => Some(*rate),
                _ => None,
            })
            .sum()
    }
}
