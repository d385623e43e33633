//! TT-Multi-RF MAVLink output (manual 6.5, 7.2.1 "ADS-B MAVLink protocol", 8.2.1 "FLARM MAVLink
//! protocol", 10.2.1 UAT): ADSB_VEHICLE (#246) for every ADS-B, UAT and FLARM target once per
//! second and COLLISION (#247) for FLARM threats, in MAVLink 1 or MAVLink 2 framing.
//!
//! Framing (mavlink.io "Serialization"): v1 `FE len seq sys comp msgid payload crc16`, v2
//! `FD len incompat compat seq sys comp msgid(3, LE) payload crc16 [signature 13]`; the CRC is
//! X.25 (MCRF4XX) over everything after the start byte plus the message's CRC_EXTRA. Message
//! definitions, CRC_EXTRA, the checksum routine, payload (de)serialisation and the encoders come
//! from the `mavlink` crate (common dialect); [`MavlinkDecoder`] adds the byte-stream handling
//! the house needs: resynchronisation, bounded buffering and counters.
//!
//! Decisions:
//! - A candidate frame whose checksum fails loses only its start byte, and the search resumes
//!   at the next byte (a false start byte inside garbage must not swallow a real frame). At the
//!   end of the stream, an incomplete candidate is treated the same way.
//! - Only ADSB_VEHICLE and COLLISION are decoded. Another message of the common dialect with a
//!   valid checksum counts as `unknown_types` and is skipped whole; a message ID outside the
//!   dialect cannot be checked (no CRC_EXTRA), so its start byte is skipped like garbage.
//! - MAVLink 2 incompatibility flags other than "signed" (0x01) are not supported: such a start
//!   byte is skipped like garbage. Signatures are skipped, not verified (no key on this link).
//! - A MAVLink 1 payload of the wrong length, or an enum value outside the dialect, counts as
//!   `malformed`. MAVLink 2 payloads may be truncated (trailing zeros) as the standard allows.
//! - A COLLISION directly after an ADSB_VEHICLE of the same id carries that vehicle: it is the
//!   FLARM target the collision refers to (manual 8.2.1).

pub mod adsb_vehicle;
pub mod collision;

#[cfg(test)]
mod tests;

use bytes::BytesMut;
use mavlink::dialects::common::{ADSB_VEHICLE_DATA, COLLISION_DATA, MavMessage};
use mavlink::{MavHeader, MavlinkVersion, Message, MessageData};
use serde::Serialize;

use crate::traffic::TrafficReport;
use crate::{DecodeStats, DeviceDecoder};
pub use adsb_vehicle::AdsbVehicle;
pub use collision::Collision;

/// MAVLink 1 start byte.
pub const STX_V1: u8 = 0xFE;
/// MAVLink 2 start byte.
pub const STX_V2: u8 = 0xFD;
/// MAVLink 2 incompatibility flag: the frame is signed.
pub const IFLAG_SIGNED: u8 = 0x01;
/// Length of a MAVLink 2 signature.
pub const SIGNATURE_LEN: usize = 13;
/// Longest MAVLink frame: v2 header 10 + payload 255 + CRC 2 + signature 13.
pub const MAX_FRAME_LEN: usize = 10 + 255 + 2 + SIGNATURE_LEN;

/// The frame header of a decoded message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct FrameInfo {
    /// MAVLink version, 1 or 2.
    pub version: u8,
    /// Packet sequence number.
    pub sequence: u8,
    /// Sender system id.
    pub system_id: u8,
    /// Sender component id.
    pub component_id: u8,
    /// The frame carried a (not verified) MAVLink 2 signature.
    pub signed: bool,
}

/// One decoded MAVLink message.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum MavlinkMessage {
    /// ADSB_VEHICLE.
    AdsbVehicle {
        /// Frame header.
        frame: FrameInfo,
        /// The vehicle.
        vehicle: AdsbVehicle,
    },
    /// COLLISION.
    Collision {
        /// Frame header.
        frame: FrameInfo,
        /// The collision threat.
        collision: Collision,
        /// The ADSB_VEHICLE sent directly before it with the same id, if any.
        target: Option<AdsbVehicle>,
    },
}

impl MavlinkMessage {
    /// The common traffic report of an ADSB_VEHICLE (a COLLISION gives `None`: its target was
    /// already reported by the ADSB_VEHICLE before it).
    pub fn to_traffic(&self) -> Option<TrafficReport> {
        match self {
            Self::AdsbVehicle { vehicle, .. } => Some(vehicle.to_traffic()),
            Self::Collision { .. } => None,
        }
    }

    /// The frame header.
    pub fn frame(&self) -> FrameInfo {
        match self {
            Self::AdsbVehicle { frame, .. } | Self::Collision { frame, .. } => *frame,
        }
    }
}

/// Appends a MAVLink frame carrying `vehicle` (unsigned, `frame.version` 1 or else 2).
pub fn encode_adsb_vehicle(frame: &FrameInfo, vehicle: &AdsbVehicle, out: &mut Vec<u8>) {
    encode(frame, &MavMessage::ADSB_VEHICLE(vehicle.to_data()), out);
}

/// Appends a MAVLink HEARTBEAT from an ADS-B receiver component (`MAV_TYPE_ADSB`, no autopilot,
/// state active): what a traffic source sends once a second so that autopilots and ground
/// stations list it (vigil's MAVLink traffic output).
pub fn encode_adsb_heartbeat(frame: &FrameInfo, out: &mut Vec<u8>) {
    use mavlink::dialects::common::{HEARTBEAT_DATA, MavAutopilot, MavModeFlag, MavState, MavType};
    let hb = HEARTBEAT_DATA {
        custom_mode: 0,
        mavtype: MavType::MAV_TYPE_ADSB,
        autopilot: MavAutopilot::MAV_AUTOPILOT_INVALID,
        base_mode: MavModeFlag::empty(),
        system_status: MavState::MAV_STATE_ACTIVE,
        mavlink_version: 3,
    };
    encode(frame, &MavMessage::HEARTBEAT(hb), out);
}

/// Appends a MAVLink frame carrying `collision` (unsigned, `frame.version` 1 or else 2).
pub fn encode_collision(frame: &FrameInfo, collision: &Collision, out: &mut Vec<u8>) {
    encode(frame, &MavMessage::COLLISION(collision.to_data()), out);
}

fn encode(frame: &FrameInfo, msg: &MavMessage, out: &mut Vec<u8>) {
    let header = MavHeader {
        system_id: u32::from(frame.system_id),
        component_id: frame.component_id,
        sequence: frame.sequence,
    };
    // Writing into a Vec cannot fail, and both messages have 8-bit IDs (valid in MAVLink 1).
    let _ = if frame.version == 1 {
        mavlink::write_v1_msg(out, header, msg)
    } else {
        mavlink::write_v2_msg(out, header, msg)
    };
}

/// `tokio_util` encoder of MAVLink frames (for the simulated module and `FramedWrite`): each
/// message goes out with its own [`FrameInfo`] (version, sequence, ids); signing is not
/// supported.
#[derive(Debug, Clone, Copy, Default)]
pub struct MavlinkEncoder;

impl tokio_util::codec::Encoder<MavlinkMessage> for MavlinkEncoder {
    type Error = std::io::Error;

    fn encode(&mut self, msg: MavlinkMessage, dst: &mut BytesMut) -> Result<(), Self::Error> {
        let mut out = Vec::with_capacity(MAX_FRAME_LEN);
        match &msg {
            MavlinkMessage::AdsbVehicle { frame, vehicle } => {
                encode_adsb_vehicle(frame, vehicle, &mut out)
            }
            MavlinkMessage::Collision {
                frame, collision, ..
            } => encode_collision(frame, collision, &mut out),
        }
        dst.extend_from_slice(&out);
        Ok(())
    }
}

/// What the front of the buffer holds.
enum Candidate {
    /// Not a frame start: skip one byte.
    NotAFrame,
    /// Need more bytes.
    Incomplete,
    /// A complete frame of `len` bytes whose checksum failed.
    BadChecksum,
    /// A complete, checked frame of `len` bytes.
    Frame {
        len: usize,
        info: FrameInfo,
        msgid: u32,
        payload_start: usize,
        payload_len: usize,
    },
}

fn candidate(buf: &[u8]) -> Candidate {
    let Some(&stx) = buf.first() else {
        return Candidate::Incomplete;
    };
    let (header_len, v2) = match stx {
        STX_V1 => (6, false),
        STX_V2 => (10, true),
        _ => return Candidate::NotAFrame,
    };
    if buf.len() < header_len {
        return Candidate::Incomplete;
    }
    let payload_len = usize::from(buf[1]);
    let (msgid, info, signed) = if v2 {
        let incompat = buf[2];
        if incompat & !IFLAG_SIGNED != 0 {
            return Candidate::NotAFrame;
        }
        let signed = incompat & IFLAG_SIGNED != 0;
        let info = FrameInfo {
            version: 2,
            sequence: buf[4],
            system_id: buf[5],
            component_id: buf[6],
            signed,
        };
        (
            u32::from_le_bytes([buf[7], buf[8], buf[9], 0]),
            info,
            signed,
        )
    } else {
        let info = FrameInfo {
            version: 1,
            sequence: buf[2],
            system_id: buf[3],
            component_id: buf[4],
            signed: false,
        };
        (u32::from(buf[5]), info, false)
    };
    let crc_at = header_len + payload_len;
    let len = crc_at + 2 + if signed { SIGNATURE_LEN } else { 0 };
    if buf.len() < len {
        return Candidate::Incomplete;
    }
    // A message outside the dialect has no CRC_EXTRA: it cannot be checked.
    if MavMessage::default_message_from_id(msgid).is_none() {
        return Candidate::NotAFrame;
    }
    let crc = mavlink::calculate_crc(&buf[1..crc_at], MavMessage::extra_crc(msgid));
    if crc != u16::from_le_bytes([buf[crc_at], buf[crc_at + 1]]) {
        return Candidate::BadChecksum;
    }
    Candidate::Frame {
        len,
        info,
        msgid,
        payload_start: header_len,
        payload_len,
    }
}

/// Sans-IO decoder of a MAVLink 1/2 byte stream, yielding ADSB_VEHICLE and COLLISION.
#[derive(Debug, Clone, Default)]
pub struct MavlinkDecoder {
    stats: DecodeStats,
    /// The ADSB_VEHICLE of the previous decoded frame, for pairing with a COLLISION.
    last_vehicle: Option<AdsbVehicle>,
}

impl MavlinkDecoder {
    /// A fresh decoder.
    pub fn new() -> Self {
        Self::default()
    }
}

/// Outcome of decoding a checked frame's payload.
enum Parsed {
    /// A message of the dialect this decoder does not hand out.
    Unknown,
    /// Wrong MAVLink 1 payload length or an enum value outside the dialect.
    Malformed,
    /// A decoded message.
    Message(MavlinkMessage),
}

fn parse(info: FrameInfo, msgid: u32, payload: &[u8]) -> Parsed {
    let version = if info.version == 1 {
        MavlinkVersion::V1
    } else {
        MavlinkVersion::V2
    };
    let v1_len_ok = |n: usize| version == MavlinkVersion::V2 || payload.len() == n;
    let msg = match msgid {
        ADSB_VEHICLE_DATA::ID if v1_len_ok(ADSB_VEHICLE_DATA::ENCODED_LEN) => {
            ADSB_VEHICLE_DATA::deser(version, payload).map(|d| MavlinkMessage::AdsbVehicle {
                frame: info,
                vehicle: AdsbVehicle::from_data(&d),
            })
        }
        COLLISION_DATA::ID if v1_len_ok(COLLISION_DATA::ENCODED_LEN) => {
            COLLISION_DATA::deser(version, payload).map(|d| MavlinkMessage::Collision {
                frame: info,
                collision: Collision::from_data(&d),
                target: None,
            })
        }
        ADSB_VEHICLE_DATA::ID | COLLISION_DATA::ID => return Parsed::Malformed,
        _ => return Parsed::Unknown,
    };
    match msg {
        Ok(m) => Parsed::Message(m),
        Err(_) => Parsed::Malformed,
    }
}

impl DeviceDecoder for MavlinkDecoder {
    type Message = MavlinkMessage;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<MavlinkMessage> {
        loop {
            if buf.is_empty() {
                return None;
            }
            if buf[0] != STX_V1 && buf[0] != STX_V2 {
                let n = buf
                    .iter()
                    .position(|&b| b == STX_V1 || b == STX_V2)
                    .unwrap_or(buf.len());
                self.stats.skip(buf, n);
                continue;
            }
            match candidate(buf) {
                Candidate::Incomplete => return None,
                Candidate::NotAFrame => self.stats.skip(buf, 1),
                Candidate::BadChecksum => {
                    self.stats.checksum_failures += 1;
                    self.stats.skip(buf, 1);
                }
                Candidate::Frame {
                    len,
                    info,
                    msgid,
                    payload_start,
                    payload_len,
                } => {
                    let payload = &buf[payload_start..payload_start + payload_len];
                    match parse(info, msgid, payload) {
                        Parsed::Unknown => {
                            self.stats.unknown_types += 1;
                            self.last_vehicle = None;
                            self.stats.skip(buf, len);
                        }
                        Parsed::Malformed => {
                            self.stats.malformed += 1;
                            self.last_vehicle = None;
                            self.stats.skip(buf, len);
                        }
                        // Issue 24: one ADSB_VEHICLE is one record; an impossible value drops it
                        // alone (its bytes counted as skipped) and counts it.
                        Parsed::Message(MavlinkMessage::AdsbVehicle { vehicle, .. })
                            if vehicle.to_traffic().check_values().is_err() =>
                        {
                            self.stats.invalid_values += 1;
                            self.last_vehicle = None;
                            self.stats.skip(buf, len);
                        }
                        Parsed::Message(mut msg) => {
                            let previous = self.last_vehicle.take();
                            match &mut msg {
                                MavlinkMessage::AdsbVehicle { vehicle, .. } => {
                                    self.last_vehicle = Some(vehicle.clone());
                                }
                                MavlinkMessage::Collision {
                                    collision, target, ..
                                } => {
                                    *target = previous.filter(|v| v.icao_address == collision.id);
                                }
                            }
                            self.stats.take_frame(buf, len);
                            return Some(msg);
                        }
                    }
                }
            }
        }
    }

    /// At the end of the stream a candidate frame that still lacks bytes can never complete:
    /// its start byte is dropped and the rest is searched again, so a false start byte near the
    /// end (with a long claimed length) does not take real frames after it down with it.
    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<MavlinkMessage> {
        loop {
            if let Some(m) = self.decode(buf) {
                return Some(m);
            }
            if buf.is_empty() {
                return None;
            }
            self.stats.skip(buf, 1);
        }
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}
