//! Binary output messages (ICD chapter 2 and Appendix B.1).
//!
//! ```text
//! 0xFA | group byte(s) | type word(s) per active group | payload | CRC-16 (big-endian)
//! ```
//!
//! - Group bytes (Table 2.1): bit 7 of each is an extension bit announcing one more group byte
//!   (at most four, B.1.1). This ICD defines groups 0-6 only; any other group bit makes the
//!   payload length unknowable, and the candidate is counted as an unknown type.
//! - Type words: one or two little-endian 16-bit words per active group, in group order; bit 15
//!   announces a second word. Type offsets follow the tables (offset 16 = bit 0 of the second
//!   word), see [`group`].
//! - Payload: the selected types, ordered by group then type offset, no padding (2.1.3).
//! - CRC: CRC16-CCITT (XMODEM) over header and payload, sent big-endian, so the CRC over header,
//!   payload and CRC is zero (2.1.3, 1.4.3).
//! - A message longer than 600 bytes is sent as split packets (B.1.2, see [`crate::vn200::split`]);
//!   so a candidate whose implied length exceeds [`MAX_MESSAGE_LEN`] is a false sync.
//!
//! Here the *body* of a message is its header and payload (what the CRC covers, without the
//! CRC); the concatenated payloads of split packets form a body too.

pub mod attitude;
pub mod common;
pub mod gnss;
pub(crate) mod group;
pub mod imu;
pub mod ins;
pub mod time;
pub mod wire;

use serde::Serialize;

pub use attitude::AttitudeGroup;
pub use common::CommonGroup;
pub use gnss::{GnssGroup, RawMeas, RawMeasEntry, SatInfo, SatInfoEntry};
pub use group::LenError;
pub use imu::ImuGroup;
pub use ins::InsGroup;
pub use time::TimeGroup;
pub use wire::{
    DeltaTheta, Deltas, GnssDop, GnssFix, GnssFixKind, GnssTimeInfo, Heave, ImuPair, Lla, MagPres,
    Quaternion, TimeUtc, Ypr,
};

use crate::vn200::crc::crc16;
use wire::Rd;

/// Sync byte of a binary output message.
pub const SYNC: u8 = 0xFA;

/// Largest binary output message sent unsplit, sync and CRC included (B.1.2: messages over 600
/// bytes are split).
pub const MAX_MESSAGE_LEN: usize = 600;

/// Largest header: four group bytes and two type words for each of the seven groups.
const MAX_HEADER_LEN: usize = 4 + 7 * 4;

/// The binary groups of Table 2.1, in offset order.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Group {
    /// Common group (offset 0).
    Common = 0,
    /// Time group (offset 1).
    Time = 1,
    /// IMU group (offset 2).
    Imu = 2,
    /// GNSS group, primary receiver (offset 3).
    Gnss = 3,
    /// Attitude group (offset 4).
    Attitude = 4,
    /// INS group (offset 5).
    Ins = 5,
    /// GNSS2 group, secondary receiver (offset 6).
    Gnss2 = 6,
}

impl Group {
    /// All groups in offset order.
    pub const ALL: [Group; 7] = [
        Group::Common,
        Group::Time,
        Group::Imu,
        Group::Gnss,
        Group::Attitude,
        Group::Ins,
        Group::Gnss2,
    ];

    /// Lower-case name, as used in JSON output.
    pub fn name(self) -> &'static str {
        match self {
            Group::Common => "common",
            Group::Time => "time",
            Group::Imu => "imu",
            Group::Gnss => "gnss",
            Group::Attitude => "attitude",
            Group::Ins => "ins",
            Group::Gnss2 => "gnss2",
        }
    }

    /// The type mask selecting the named types (field names of the group's struct, e.g.
    /// `"ypr"`, `"time_gps_ns"`), or `None` if a name is not a type of this group. Used to
    /// build Register 75-77 configurations.
    pub fn type_mask(self, names: &[&str]) -> Option<u32> {
        names.iter().try_fold(0u32, |acc, name| {
            let t = self.types().iter().find(|t| t.1 == *name)?;
            Some(acc | 1 << t.0)
        })
    }

    /// Every type of the group: (offset, field name, Table 2.2 size, variable-length).
    pub fn types(self) -> &'static [(u8, &'static str, usize, bool)] {
        match self {
            Group::Common => CommonGroup::TYPES,
            Group::Time => TimeGroup::TYPES,
            Group::Imu => ImuGroup::TYPES,
            Group::Gnss | Group::Gnss2 => GnssGroup::TYPES,
            Group::Attitude => AttitudeGroup::TYPES,
            Group::Ins => InsGroup::TYPES,
        }
    }
}

/// The type words of a type mask (table offsets): the first word, and the second when any
/// offset of 16 or more is selected (the first then carries the extension bit 15).
pub fn type_words(mask: u32) -> (u16, Option<u16>) {
    let low = (mask & 0x7FFF) as u16;
    let high = ((mask >> 16) & 0x7FFF) as u16;
    if high != 0 {
        (low | 0x8000, Some(high))
    } else {
        (low, None)
    }
}

/// A message header: the active groups and each group's type mask (table offsets).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Header {
    /// Active groups, bit = group offset (0-6).
    pub groups: u8,
    /// Type mask of each group, indexed by group offset (0 for inactive groups).
    pub types: [u32; 7],
    /// Header length in bytes (group bytes and type words).
    pub len: usize,
}

/// Why a candidate body could not be measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Probe {
    /// More bytes are needed to tell.
    NeedMore,
    /// Not a message: no group, an empty type mask, or too many extension bytes/words.
    Invalid,
    /// Selects a group or type this ICD does not define (length unknowable).
    Unknown,
    /// The implied length exceeds the largest unsplit message.
    TooLong,
}

/// Parses the header at the start of `body` (the bytes after the sync byte).
#[inline(always)]
pub fn parse_header(body: &[u8]) -> Result<Header, Probe> {
    let mut pos = 0usize;
    let mut groups = 0u8;
    // Group bytes: the first carries groups 0-6; extension bytes carry groups this ICD does
    // not define.
    loop {
        let b = *body.get(pos).ok_or(Probe::NeedMore)?;
        if pos == 0 {
            groups = b & 0x7F;
        } else if b & 0x7F != 0 {
            return Err(Probe::Unknown);
        }
        pos += 1;
        if b & 0x80 == 0 {
            break;
        }
        if pos == 4 {
            return Err(Probe::Invalid);
        }
    }
    if groups == 0 {
        return Err(Probe::Invalid);
    }
    let mut types = [0u32; 7];
    for (g, t) in types.iter_mut().enumerate() {
        if groups & (1 << g) == 0 {
            continue;
        }
        let w0 = read_u16(body, pos)?;
        pos += 2;
        let mut mask = u32::from(w0 & 0x7FFF);
        if w0 & 0x8000 != 0 {
            let w1 = read_u16(body, pos)?;
            pos += 2;
            if w1 & 0x8000 != 0 {
                return Err(Probe::Invalid);
            }
            mask |= u32::from(w1) << 16;
        }
        if mask == 0 {
            return Err(Probe::Invalid);
        }
        *t = mask;
    }
    debug_assert!(pos <= MAX_HEADER_LEN);
    Ok(Header {
        groups,
        types,
        len: pos,
    })
}

#[inline(always)]
fn read_u16(b: &[u8], pos: usize) -> Result<u16, Probe> {
    let bytes = b.get(pos..pos + 2).ok_or(Probe::NeedMore)?;
    Ok(u16::from_le_bytes([bytes[0], bytes[1]]))
}

/// Payload length of one group for `mask`, looking at the group's payload bytes if needed.
#[inline(always)]
fn group_len(g: usize, mask: u32, bytes: &[u8]) -> Result<usize, LenError> {
    match g {
        0 => CommonGroup::payload_len(mask, bytes),
        1 => TimeGroup::payload_len(mask, bytes),
        2 => ImuGroup::payload_len(mask, bytes),
        4 => AttitudeGroup::payload_len(mask, bytes),
        5 => InsGroup::payload_len(mask, bytes),
        _ => GnssGroup::payload_len(mask, bytes),
    }
}

/// Measures the body at the start of `body` (header and payload, no sync, no CRC): its header
/// and its length. `max_len` bounds the body (a longer one is [`Probe::TooLong`]).
#[inline(always)]
pub fn body_len(body: &[u8], max_len: usize) -> Result<(Header, usize), Probe> {
    let header = parse_header(body)?;
    let mut len = header.len;
    for g in 0..7 {
        let mask = header.types[g];
        if mask == 0 {
            continue;
        }
        let rest = body.get(len..).unwrap_or(&[]);
        match group_len(g, mask, rest) {
            Ok(n) => len = len.saturating_add(n),
            Err(LenError::UnknownType) => return Err(Probe::Unknown),
            Err(LenError::NeedMore) => {
                // The count of a variable type is not here yet: if even the bytes needed to see
                // it exceed the bound, this is not a message.
                return Err(if body.len() >= max_len {
                    Probe::TooLong
                } else {
                    Probe::NeedMore
                });
            }
        }
        if len > max_len {
            return Err(Probe::TooLong);
        }
    }
    Ok((header, len))
}

/// One binary output message, decoded: one optional struct per group, one optional field per
/// binary type. A group is present when its group bit was set.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct BinaryOutput {
    /// Common group.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub common: Option<CommonGroup>,
    /// Time group.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub time: Option<TimeGroup>,
    /// IMU group.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub imu: Option<ImuGroup>,
    /// GNSS group (primary receiver). Boxed: the GNSS groups are the largest and the rarest
    /// (5 Hz), so the common messages stay small to move.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gnss: Option<Box<GnssGroup>>,
    /// Attitude group.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub attitude: Option<AttitudeGroup>,
    /// INS group.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ins: Option<InsGroup>,
    /// GNSS2 group (secondary receiver), boxed like [`BinaryOutput::gnss`].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gnss2: Option<Box<GnssGroup>>,
}

impl BinaryOutput {
    /// Decodes a complete body (header and payload, exactly). `None` if the body is not exactly
    /// one well-formed message of known types.
    pub fn decode_body(body: &[u8]) -> Option<Self> {
        let header = parse_header(body).ok()?;
        Self::decode_payload(&header, body.get(header.len..)?)
    }

    /// Decodes the payload that follows a parsed header. `None` unless the payload holds
    /// exactly the types the header selects.
    #[inline(always)]
    pub fn decode_payload(header: &Header, payload: &[u8]) -> Option<Self> {
        let mut r = Rd::new(payload);
        let t = &header.types;
        let m = BinaryOutput {
            common: (t[0] != 0).then(|| CommonGroup::read(t[0], &mut r)),
            time: (t[1] != 0).then(|| TimeGroup::read(t[1], &mut r)),
            imu: (t[2] != 0).then(|| ImuGroup::read(t[2], &mut r)),
            gnss: (t[3] != 0).then(|| Box::new(GnssGroup::read(t[3], &mut r))),
            attitude: (t[4] != 0).then(|| AttitudeGroup::read(t[4], &mut r)),
            ins: (t[5] != 0).then(|| InsGroup::read(t[5], &mut r)),
            gnss2: (t[6] != 0).then(|| Box::new(GnssGroup::read(t[6], &mut r))),
        };
        (!r.is_short() && r.remaining() == 0).then_some(m)
    }

    /// Decodes the payload that follows a parsed header into `self`, in place (issue 21: the
    /// caller's message is written once, not built and moved). Every group is overwritten (absent
    /// ones become `None`; a present GNSS group reuses its box), so on success `self` equals what
    /// [`BinaryOutput::decode_payload`] returns. Returns whether the payload holds exactly the
    /// types the header selects; on `false`, `self` holds a partial decode and must not be used.
    #[inline(always)]
    pub fn decode_payload_into(&mut self, header: &Header, payload: &[u8]) -> bool {
        let mut r = Rd::new(payload);
        let t = &header.types;
        read_slot(&mut self.common, t[0], |g| g.read_into(t[0], &mut r));
        read_slot(&mut self.time, t[1], |g| g.read_into(t[1], &mut r));
        read_slot(&mut self.imu, t[2], |g| g.read_into(t[2], &mut r));
        read_boxed_slot(&mut self.gnss, t[3], |g| g.read_into(t[3], &mut r));
        read_slot(&mut self.attitude, t[4], |g| g.read_into(t[4], &mut r));
        read_slot(&mut self.ins, t[5], |g| g.read_into(t[5], &mut r));
        read_boxed_slot(&mut self.gnss2, t[6], |g| g.read_into(t[6], &mut r));
        !r.is_short() && r.remaining() == 0
    }

    /// Decodes a complete framed message (sync, body, CRC), checking the CRC.
    pub fn decode_frame(frame: &[u8]) -> Option<Self> {
        let (&sync, rest) = frame.split_first()?;
        if sync != SYNC || rest.len() < 2 || crc16(rest) != 0 {
            return None;
        }
        Self::decode_body(&rest[..rest.len() - 2])
    }

    /// Type mask (table offsets) of each group, indexed by group offset; 0 = group absent or
    /// empty. Groups present with no type are not encoded.
    pub fn type_masks(&self) -> [u32; 7] {
        [
            self.common.as_ref().map_or(0, |g| g.type_mask()),
            self.time.as_ref().map_or(0, |g| g.type_mask()),
            self.imu.as_ref().map_or(0, |g| g.type_mask()),
            self.gnss.as_ref().map_or(0, |g| g.type_mask()),
            self.attitude.as_ref().map_or(0, |g| g.type_mask()),
            self.ins.as_ref().map_or(0, |g| g.type_mask()),
            self.gnss2.as_ref().map_or(0, |g| g.type_mask()),
        ]
    }

    /// The group byte (bit = group offset of each group with at least one type).
    pub fn group_byte(&self) -> u8 {
        self.type_masks()
            .iter()
            .enumerate()
            .fold(0, |acc, (g, &m)| if m != 0 { acc | 1 << g } else { acc })
    }

    /// Appends the body (header and payload) to `out`.
    pub fn encode_body(&self, out: &mut Vec<u8>) {
        let masks = self.type_masks();
        out.push(self.group_byte());
        for &m in masks.iter().filter(|&&m| m != 0) {
            let (w0, w1) = type_words(m);
            out.extend_from_slice(&w0.to_le_bytes());
            if let Some(w1) = w1 {
                out.extend_from_slice(&w1.to_le_bytes());
            }
        }
        if masks[0] != 0
            && let Some(g) = &self.common
        {
            g.write(out);
        }
        if masks[1] != 0
            && let Some(g) = &self.time
        {
            g.write(out);
        }
        if masks[2] != 0
            && let Some(g) = &self.imu
        {
            g.write(out);
        }
        if masks[3] != 0
            && let Some(g) = &self.gnss
        {
            g.write(out);
        }
        if masks[4] != 0
            && let Some(g) = &self.attitude
        {
            g.write(out);
        }
        if masks[5] != 0
            && let Some(g) = &self.ins
        {
            g.write(out);
        }
        if masks[6] != 0
            && let Some(g) = &self.gnss2
        {
            g.write(out);
        }
    }

    /// Appends the framed message (sync, body, big-endian CRC) to `out`. A message longer than
    /// [`MAX_MESSAGE_LEN`] is what the sensor would split: see [`crate::vn200::split::encode_split`].
    pub fn encode_into(&self, out: &mut Vec<u8>) {
        out.push(SYNC);
        let start = out.len();
        self.encode_body(out);
        let crc = crc16(&out[start..]);
        out.extend_from_slice(&crc.to_be_bytes());
    }

    /// The bytes the sensor would send: the framed message, or split packets (numbered from 1,
    /// with `message_id`) when it exceeds [`MAX_MESSAGE_LEN`]. `None` if even split packets
    /// cannot carry it (more than 15 packets).
    pub fn encode_for_wire(&self, message_id: u8) -> Option<Vec<u8>> {
        let framed = self.encode();
        if framed.len() <= MAX_MESSAGE_LEN {
            return Some(framed);
        }
        crate::vn200::split::encode_split(
            &framed[1..framed.len() - 2],
            message_id,
            crate::vn200::split::MAX_PACKET_PAYLOAD,
        )
    }

    /// The framed message as a new vector.
    pub fn encode(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(128);
        self.encode_into(&mut out);
        out
    }
}

/// Fills the group slot `slot` in place when its type mask is non-zero (a group absent before is
/// first set to its default, then `read` overwrites every field), or empties it.
#[inline(always)]
fn read_slot<G: Default>(slot: &mut Option<G>, mask: u32, read: impl FnOnce(&mut G)) {
    if mask == 0 {
        *slot = None;
    } else {
        read(slot.get_or_insert_with(G::default));
    }
}

/// [`read_slot`] for a boxed group: a box already there is reused (no allocation).
#[inline(always)]
fn read_boxed_slot<G: Default>(slot: &mut Option<Box<G>>, mask: u32, read: impl FnOnce(&mut G)) {
    if mask == 0 {
        *slot = None;
    } else {
        read(slot.get_or_insert_with(Box::default));
    }
}

/// Encodes binary output messages for a `FramedWrite` (the simulator's side of the port).
#[derive(Debug, Clone, Copy, Default)]
pub struct BinaryEncoder;

impl tokio_util::codec::Encoder<&BinaryOutput> for BinaryEncoder {
    type Error = std::io::Error;

    fn encode(
        &mut self,
        item: &BinaryOutput,
        dst: &mut bytes::BytesMut,
    ) -> Result<(), Self::Error> {
        let mut v = Vec::with_capacity(128);
        item.encode_into(&mut v);
        dst.extend_from_slice(&v);
        Ok(())
    }
}

#[cfg(test)]
mod tests;
