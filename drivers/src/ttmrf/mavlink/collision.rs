//! MAVLink COLLISION (#247): the FLARM subsystem's threat message (manual 8.2.1 "FLARM Collision
//! message"). The target it refers to is described by the ADSB_VEHICLE sent directly before it
//! ([`super::MavlinkDecoder`] pairs them, see [`super::MavlinkMessage::Collision`]).

use mavlink::dialects::common::{
    COLLISION_DATA, MavCollisionAction, MavCollisionSrc, MavCollisionThreatLevel,
};
use num_traits::FromPrimitive;
use serde::Serialize;

/// Message ID of COLLISION.
pub const ID: u32 = 247;

/// One COLLISION message.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Collision {
    /// MAV_COLLISION_SRC: 0 ADS-B, 1 MAVLink GPS_GLOBAL_INT.
    pub src: u8,
    /// Identifier of the other vehicle (the FLARM id / address of the preceding ADSB_VEHICLE).
    pub id: u32,
    /// MAV_COLLISION_ACTION: 0 none, 1 report, 2 ascend or descend, 3 move horizontally,
    /// 4 move perpendicular, 5 RTL, 6 hover.
    pub action: u8,
    /// MAV_COLLISION_THREAT_LEVEL: 0 none, 1 low, 2 high.
    pub threat_level: u8,
    /// Estimated time until the closest approach, s.
    pub time_to_minimum_delta_s: f32,
    /// Closest vertical distance, m.
    pub altitude_minimum_delta_m: f32,
    /// Closest horizontal distance, m.
    pub horizontal_minimum_delta_m: f32,
}

impl Collision {
    /// Converts the crate's decoded payload.
    pub fn from_data(d: &COLLISION_DATA) -> Self {
        Self {
            src: d.src as u8,
            id: d.id,
            action: d.action as u8,
            threat_level: d.threat_level as u8,
            time_to_minimum_delta_s: d.time_to_minimum_delta,
            altitude_minimum_delta_m: d.altitude_minimum_delta,
            horizontal_minimum_delta_m: d.horizontal_minimum_delta,
        }
    }

    /// Converts back to the crate's payload (unknown enum values become 0).
    pub fn to_data(&self) -> COLLISION_DATA {
        COLLISION_DATA {
            id: self.id,
            time_to_minimum_delta: self.time_to_minimum_delta_s,
            altitude_minimum_delta: self.altitude_minimum_delta_m,
            horizontal_minimum_delta: self.horizontal_minimum_delta_m,
            src: MavCollisionSrc::from_u8(self.src).unwrap_or_default(),
            action: MavCollisionAction::from_u8(self.action).unwrap_or_default(),
            threat_level: MavCollisionThreatLevel::from_u8(self.threat_level).unwrap_or_default(),
        }
    }
}
