//! The ME field of an extended squitter (DF17/18), dispatched on its type code
//! (DO-260B 2.2.3.2, Table 2-8).

use serde::Serialize;

use super::airborne_position::AirbornePosition;
use super::bits;
use super::ident::Identification;
use super::opstatus::OperationalStatus;
use super::status::AircraftStatus;
use super::surface::SurfacePosition;
use super::target_state::TargetState;
use super::velocity::Velocity;

/// A decoded ME field.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Me {
    /// TC 1-4.
    Identification(Identification),
    /// TC 5-8.
    SurfacePosition(SurfacePosition),
    /// TC 9-18, 20-22.
    AirbornePosition(AirbornePosition),
    /// TC 19, subtypes 1-4.
    Velocity(Velocity),
    /// TC 28.
    Status(AircraftStatus),
    /// TC 29 subtype 1.
    TargetState(TargetState),
    /// TC 31 subtypes 0-1.
    OperationalStatus(OperationalStatus),
    /// Anything else (TC 0 "no position", 23-27, 30, reserved subtypes): recognised, not decoded.
    Other {
        /// The type code.
        typecode: u8,
        /// The subtype field (ME bits 6-8).
        subtype: u8,
    },
}

impl Me {
    /// Decodes a 56-bit ME field.
    #[inline]
    pub fn decode(me: u64) -> Self {
        let tc = bits(me, 1, 5) as u8;
        let other = Me::Other {
            typecode: tc,
            subtype: bits(me, 6, 3) as u8,
        };
        match tc {
            1..=4 => Me::Identification(Identification::decode(me)),
            5..=8 => Me::SurfacePosition(SurfacePosition::decode(me)),
            9..=18 | 20..=22 => Me::AirbornePosition(AirbornePosition::decode(me)),
            19 => Velocity::decode(me).map_or(other, Me::Velocity),
            28 => Me::Status(AircraftStatus::decode(me)),
            29 => TargetState::decode(me).map_or(other, Me::TargetState),
            31 => OperationalStatus::decode(me).map_or(other, Me::OperationalStatus),
            _ => other,
        }
    }

    /// The type code.
    pub fn typecode(&self) -> u8 {
        match self {
            Me::Identification(i) => i.typecode,
            Me::SurfacePosition(s) => s.typecode,
            Me::AirbornePosition(a) => a.typecode,
            Me::Velocity(_) => 19,
            Me::Status(_) => 28,
            Me::TargetState(_) => 29,
            Me::OperationalStatus(_) => 31,
            Me::Other { typecode, .. } => *typecode,
        }
    }
}
