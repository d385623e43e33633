//! BAHRS messages (protocol 2.0, sections 3 and 5): typed payloads, their scale factors, and the
//! payload codecs. Fields keep the device's raw integers (so encoding is exact and tests can check
//! bytes); accessor methods give SI values.

use serde::Serialize;

use super::health::{InertialHealth, NavigationHealth};

/// Specific force scale, m/s^2 per LSB (section 3.1).
pub const SPECIFIC_FORCE_MPS2_PER_LSB: f64 = 1.4964e-3;
/// Angular rate scale, rad/s per LSB (section 3.1).
pub const ANGULAR_RATE_RADPS_PER_LSB: f64 = 1.5979452e-4;
/// Pressure height scale, m per LSB (section 3.2).
pub const HEIGHT_M_PER_LSB: f64 = 0.16784924;
/// Pressure height offset, m (section 3.2): height = scale x raw + offset.
pub const HEIGHT_OFFSET_M: f64 = -1000.0;
/// Downward velocity scale, m/s per LSB (section 3.2).
pub const VELOCITY_MPS_PER_LSB: f64 = 9.155413e-3;
/// Angle scale of 0x02 and 0x03, rad per LSB (sections 3.2, 3.3).
pub const ANGLE_RAD_PER_LSB: f64 = 9.587526e-5;
/// Highest NVM page number (sections 5.3, 5.4).
pub const MAX_NVM_PAGE: u8 = 249;

/// Rounds `value / scale` to the nearest raw integer, saturating at the type's range.
fn to_raw_i16(value: f64, scale: f64) -> i16 {
    // `as` saturates and maps NaN to 0.
    (value / scale).round() as i16
}

fn to_raw_u16(value: f64, scale: f64) -> u16 {
    (value / scale).round() as u16
}

/// 0x01: inertial data, body-frame specific force and angular rate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Inertial {
    /// Sequence counter (wraps at 256); 0x05 refers to it.
    pub seq: u8,
    /// Specific force X, Y, Z, raw (x [`SPECIFIC_FORCE_MPS2_PER_LSB`]).
    pub specific_force_raw: [i16; 3],
    /// Angular rate X, Y, Z, raw (x [`ANGULAR_RATE_RADPS_PER_LSB`]).
    pub angular_rate_raw: [i16; 3],
    /// Per-signal health.
    pub health: InertialHealth,
}

impl Inertial {
    /// Payload length.
    pub const LEN: usize = 15;
    /// Message type.
    pub const TYPE: u8 = 0x01;

    /// Specific force, body X/Y/Z, m/s^2.
    pub fn specific_force_mps2(&self) -> [f64; 3] {
        self.specific_force_raw
            .map(|r| f64::from(r) * SPECIFIC_FORCE_MPS2_PER_LSB)
    }

    /// Angular rate, body X/Y/Z, rad/s.
    pub fn angular_rate_radps(&self) -> [f64; 3] {
        self.angular_rate_raw
            .map(|r| f64::from(r) * ANGULAR_RATE_RADPS_PER_LSB)
    }

    /// Builds the message from SI values, rounding to the nearest LSB (saturating).
    pub fn from_si(
        seq: u8,
        specific_force_mps2: [f64; 3],
        angular_rate_radps: [f64; 3],
        health: InertialHealth,
    ) -> Self {
        Self {
            seq,
            specific_force_raw: specific_force_mps2
                .map(|v| to_raw_i16(v, SPECIFIC_FORCE_MPS2_PER_LSB)),
            angular_rate_raw: angular_rate_radps.map(|v| to_raw_i16(v, ANGULAR_RATE_RADPS_PER_LSB)),
            health,
        }
    }
}

/// 0x02: navigation data: pressure height, downward velocity, roll, pitch, magnetic heading.
///
/// Decision: the document types the pressure height as `int16`, but its formula
/// `0.16784924 x raw - 1000` only spans the stated -1000 m .. +10 000 m with an unsigned raw value
/// (0..65535 gives -1000 .. +9999.99 m); signed, every height above 4499.6 m would be unreachable and
/// raw values below 0 would mean heights below -1000 m. Both readings agree for every physically
/// possible height below 4499 m, so we read it as `u16`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Navigation {
    /// Sequence counter (wraps at 256); 0x04 refers to it.
    pub seq: u8,
    /// Pressure height, raw, unsigned (see the type's note).
    pub pressure_height_raw: u16,
    /// Downward velocity, raw.
    pub velocity_down_raw: i16,
    /// Roll angle, raw.
    pub roll_raw: i16,
    /// Pitch angle, raw.
    pub pitch_raw: i16,
    /// Magnetic heading, raw, 0 .. 2 pi.
    pub heading_raw: u16,
    /// Per-signal health.
    pub health: NavigationHealth,
}

impl Navigation {
    /// Payload length.
    pub const LEN: usize = 13;
    /// Message type.
    pub const TYPE: u8 = 0x02;

    /// Pressure height (barometric, standard atmosphere), m.
    pub fn pressure_height_m(&self) -> f64 {
        HEIGHT_M_PER_LSB * f64::from(self.pressure_height_raw) + HEIGHT_OFFSET_M
    }
    /// Velocity downwards, m/s.
    pub fn velocity_down_mps(&self) -> f64 {
        VELOCITY_MPS_PER_LSB * f64::from(self.velocity_down_raw)
    }
    /// Roll, rad.
    pub fn roll_rad(&self) -> f64 {
        ANGLE_RAD_PER_LSB * f64::from(self.roll_raw)
    }
    /// Pitch, rad.
    pub fn pitch_rad(&self) -> f64 {
        ANGLE_RAD_PER_LSB * f64::from(self.pitch_raw)
    }
    /// Magnetic heading, rad, 0 .. 2 pi.
    pub fn heading_mag_rad(&self) -> f64 {
        ANGLE_RAD_PER_LSB * f64::from(self.heading_raw)
    }

    /// Builds the message from SI values, rounding to the nearest LSB (saturating; the heading is
    /// wrapped into 0 .. 2 pi first).
    pub fn from_si(
        seq: u8,
        pressure_height_m: f64,
        velocity_down_mps: f64,
        roll_rad: f64,
        pitch_rad: f64,
        heading_mag_rad: f64,
        health: NavigationHealth,
    ) -> Self {
        // 2 pi is 65535.0015 LSB, so after wrapping the rounded value always fits a u16; 65535
        // stands for 2 pi - 1.4e-7 rad, i.e. north, like 0.
        let heading_raw = to_raw_u16(
            heading_mag_rad.rem_euclid(std::f64::consts::TAU),
            ANGLE_RAD_PER_LSB,
        );
        Self {
            seq,
            pressure_height_raw: to_raw_u16(pressure_height_m - HEIGHT_OFFSET_M, HEIGHT_M_PER_LSB),
            velocity_down_raw: to_raw_i16(velocity_down_mps, VELOCITY_MPS_PER_LSB),
            roll_raw: to_raw_i16(roll_rad, ANGLE_RAD_PER_LSB),
            pitch_raw: to_raw_i16(pitch_rad, ANGLE_RAD_PER_LSB),
            heading_raw,
            health,
        }
    }
}

/// 0x03: attitude accuracy and the MCU time. A standard deviation of 0 means "invalid".
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Accuracy {
    /// Sequence counter.
    pub seq: u8,
    /// Attitude standard deviation about north (tilt), raw; 0 = invalid.
    pub std_north_raw: u16,
    /// Attitude standard deviation about east (tilt), raw; 0 = invalid.
    pub std_east_raw: u16,
    /// Magnetic heading standard deviation, raw; 0 = invalid.
    pub std_heading_raw: u16,
    /// Microcontroller time, us.
    pub mcu_time_us: u64,
}

fn std_rad(raw: u16) -> Option<f64> {
    (raw != 0).then(|| f64::from(raw) * ANGLE_RAD_PER_LSB)
}

impl Accuracy {
    /// Payload length.
    pub const LEN: usize = 15;
    /// Message type.
    pub const TYPE: u8 = 0x03;

    /// Attitude (tilt) standard deviation about north, rad; `None` when the unit marks it invalid.
    pub fn std_north_rad(&self) -> Option<f64> {
        std_rad(self.std_north_raw)
    }
    /// Attitude (tilt) standard deviation about east, rad; `None` when invalid.
    pub fn std_east_rad(&self) -> Option<f64> {
        std_rad(self.std_east_raw)
    }
    /// Magnetic heading standard deviation, rad; `None` when invalid.
    pub fn std_heading_rad(&self) -> Option<f64> {
        std_rad(self.std_heading_raw)
    }
}

/// 0x04 / 0x05: MCU time of the navigation (0x04) or inertial (0x05) message with a given sequence
/// counter.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct DataTime {
    /// Sequence counter of this time message.
    pub seq: u8,
    /// Sequence counter of the data message it times.
    pub data_seq: u8,
    /// Microcontroller time of that data, us.
    pub mcu_time_us: u64,
}

impl DataTime {
    /// Payload length.
    pub const LEN: usize = 10;

    /// False when the data sequence and the time are both zero, which the document defines as
    /// invalid (sections 3.4, 3.5).
    pub fn is_valid(&self) -> bool {
        !(self.data_seq == 0 && self.mcu_time_us == 0)
    }
}

/// 0x06: MCU time of the latest synchronisation pulse (wired to the VN-200 PPS in the installation).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SyncPulseTime {
    /// Sequence counter.
    pub seq: u8,
    /// Microcontroller time of the pulse, us.
    pub mcu_time_us: u64,
}

impl SyncPulseTime {
    /// Payload length.
    pub const LEN: usize = 9;
    /// Message type.
    pub const TYPE: u8 = 0x06;
}

/// 0x0F: software version.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SoftwareVersion {
    /// Project code, three characters as sent.
    pub project_code: [u8; 3],
    /// Major version.
    pub major: u16,
    /// Minor version.
    pub minor: u16,
}

impl SoftwareVersion {
    /// Payload length.
    pub const LEN: usize = 7;
    /// Message type.
    pub const TYPE: u8 = 0x0F;

    /// The project code as text (non-ASCII bytes replaced).
    pub fn project_code_str(&self) -> String {
        String::from_utf8_lossy(&self.project_code).into_owned()
    }
}

/// 0x1F: hardware version.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct HardwareVersion {
    /// MCU id.
    pub mcu_id: u16,
    /// Unique MCU id words 1-3.
    pub unique_id: [u32; 3],
}

impl HardwareVersion {
    /// Payload length.
    pub const LEN: usize = 14;
    /// Message type.
    pub const TYPE: u8 = 0x1F;
}

/// 0xF3: one NVM page (device -> host, not padded).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct NvmPage {
    /// Page number, 0 to 249.
    pub page: u8,
    /// Page content.
    pub data: [u8; 32],
}

/// 0xFF: acknowledgement of a diagnostics message (device -> host, not padded).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Ack {
    /// The message type acknowledged.
    pub acked_type: u8,
    /// 0 = OK, anything else an error code of the device.
    pub status: u8,
}

/// Any BAHRS protocol 2.0 message.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Message {
    /// 0x01 inertial data.
    Inertial(Inertial),
    /// 0x02 navigation data.
    Navigation(Navigation),
    /// 0x03 accuracy.
    Accuracy(Accuracy),
    /// 0x04 time of navigation data.
    NavigationTime(DataTime),
    /// 0x05 time of inertial data.
    InertialTime(DataTime),
    /// 0x06 time of the latest synchronisation pulse.
    SyncPulseTime(SyncPulseTime),
    /// 0x0F software version.
    SoftwareVersion(SoftwareVersion),
    /// 0x1F hardware version.
    HardwareVersion(HardwareVersion),
    /// 0xF0 request to enter diagnostics mode (host -> device).
    EnterDiagnostics,
    /// 0xF1 request to exit diagnostics mode (host -> device).
    ExitDiagnostics,
    /// 0xF2 request to read an NVM page 0..=249 (host -> device).
    ReadNvmPage {
        /// Page number.
        page: u8,
    },
    /// 0xF3 NVM page data (device -> host).
    NvmPage(NvmPage),
    /// 0xFF acknowledgement (device -> host).
    Ack(Ack),
}

/// Why a payload with a verified CRC was still rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PayloadError {
    /// An NVM page number above 249.
    PageOutOfRange(u8),
}

// The field readers take the payload as a fixed-size array, so with the constant offsets of the
// decode below every index is checked at compile time and the decode has no run-time bounds checks.
#[inline]
fn u16_at<const N: usize>(p: &[u8; N], i: usize) -> u16 {
    u16::from_le_bytes([p[i], p[i + 1]])
}
#[inline]
fn i16_at<const N: usize>(p: &[u8; N], i: usize) -> i16 {
    i16::from_le_bytes([p[i], p[i + 1]])
}
#[inline]
fn u32_at<const N: usize>(p: &[u8; N], i: usize) -> u32 {
    u32::from_le_bytes([p[i], p[i + 1], p[i + 2], p[i + 3]])
}
#[inline]
fn u64_at<const N: usize>(p: &[u8; N], i: usize) -> u64 {
    u64::from_le_bytes([
        p[i],
        p[i + 1],
        p[i + 2],
        p[i + 3],
        p[i + 4],
        p[i + 5],
        p[i + 6],
        p[i + 7],
    ])
}

/// The documented payload length of `msg_type` (0 for types without a layout), for the array
/// types of [`Message::decode_payload`].
const fn len_of(msg_type: u8) -> usize {
    match super::frame::layout(msg_type) {
        Some(l) => l.payload_len,
        None => 0,
    }
}

impl Message {
    /// The message type byte.
    pub const fn type_id(&self) -> u8 {
        match self {
            Message::Inertial(_) => 0x01,
            Message::Navigation(_) => 0x02,
            Message::Accuracy(_) => 0x03,
            Message::NavigationTime(_) => 0x04,
            Message::InertialTime(_) => 0x05,
            Message::SyncPulseTime(_) => 0x06,
            Message::SoftwareVersion(_) => 0x0F,
            Message::HardwareVersion(_) => 0x1F,
            Message::EnterDiagnostics => 0xF0,
            Message::ExitDiagnostics => 0xF1,
            Message::ReadNvmPage { .. } => 0xF2,
            Message::NvmPage(_) => 0xF3,
            Message::Ack(_) => 0xFF,
        }
    }

    /// The sequence counter, for the messages that have one.
    pub const fn seq(&self) -> Option<u8> {
        match self {
            Message::Inertial(m) => Some(m.seq),
            Message::Navigation(m) => Some(m.seq),
            Message::Accuracy(m) => Some(m.seq),
            Message::NavigationTime(m) | Message::InertialTime(m) => Some(m.seq),
            Message::SyncPulseTime(m) => Some(m.seq),
            _ => None,
        }
    }

    /// Decodes the payload of a message of type `msg_type`.
    ///
    /// The caller guarantees `p.len()` equals the type's documented payload length (the frame
    /// layer only hands over payloads of that length); anything else gives `None`.
    #[inline]
    pub fn decode_payload(msg_type: u8, p: &[u8]) -> Option<Result<Message, PayloadError>> {
        // Each arm takes the payload as an array of the type's documented length (a wrong length
        // gives `None`), so the reads below need no bounds checks.
        macro_rules! payload {
            ($t:literal) => {{
                let a: &[u8; len_of($t)] = p.try_into().ok()?;
                a
            }};
        }
        let data_time = |p: &[u8; len_of(0x04)]| DataTime {
            seq: p[0],
            data_seq: p[1],
            mcu_time_us: u64_at(p, 2),
        };
        let m = match msg_type {
            0x01 => {
                let p = payload!(0x01);
                Message::Inertial(Inertial {
                    seq: p[0],
                    specific_force_raw: [i16_at(p, 1), i16_at(p, 3), i16_at(p, 5)],
                    angular_rate_raw: [i16_at(p, 7), i16_at(p, 9), i16_at(p, 11)],
                    health: InertialHealth(u16_at(p, 13)),
                })
            }
            0x02 => {
                let p = payload!(0x02);
                Message::Navigation(Navigation {
                    seq: p[0],
                    pressure_height_raw: u16_at(p, 1),
                    velocity_down_raw: i16_at(p, 3),
                    roll_raw: i16_at(p, 5),
                    pitch_raw: i16_at(p, 7),
                    heading_raw: u16_at(p, 9),
                    health: NavigationHealth(u16_at(p, 11)),
                })
            }
            0x03 => {
                let p = payload!(0x03);
                Message::Accuracy(Accuracy {
                    seq: p[0],
                    std_north_raw: u16_at(p, 1),
                    std_east_raw: u16_at(p, 3),
                    std_heading_raw: u16_at(p, 5),
                    mcu_time_us: u64_at(p, 7),
                })
            }
            0x04 => Message::NavigationTime(data_time(payload!(0x04))),
            0x05 => Message::InertialTime(data_time(payload!(0x05))),
            0x06 => {
                let p = payload!(0x06);
                Message::SyncPulseTime(SyncPulseTime {
                    seq: p[0],
                    mcu_time_us: u64_at(p, 1),
                })
            }
            0x0F => {
                let p = payload!(0x0F);
                Message::SoftwareVersion(SoftwareVersion {
                    project_code: [p[0], p[1], p[2]],
                    major: u16_at(p, 3),
                    minor: u16_at(p, 5),
                })
            }
            0x1F => {
                let p = payload!(0x1F);
                Message::HardwareVersion(HardwareVersion {
                    mcu_id: u16_at(p, 0),
                    unique_id: [u32_at(p, 2), u32_at(p, 6), u32_at(p, 10)],
                })
            }
            0xF0 => {
                payload!(0xF0);
                Message::EnterDiagnostics
            }
            0xF1 => {
                payload!(0xF1);
                Message::ExitDiagnostics
            }
            0xF2 => {
                let p = payload!(0xF2);
                if p[0] > MAX_NVM_PAGE {
                    return Some(Err(PayloadError::PageOutOfRange(p[0])));
                }
                Message::ReadNvmPage { page: p[0] }
            }
            0xF3 => {
                let p = payload!(0xF3);
                if p[0] > MAX_NVM_PAGE {
                    return Some(Err(PayloadError::PageOutOfRange(p[0])));
                }
                let mut data = [0u8; 32];
                data.copy_from_slice(&p[1..33]);
                Message::NvmPage(NvmPage { page: p[0], data })
            }
            0xFF => {
                let p = payload!(0xFF);
                Message::Ack(Ack {
                    acked_type: p[0],
                    status: p[1],
                })
            }
            _ => return None,
        };
        Some(Ok(m))
    }

    /// Appends the payload bytes of this message to `out`.
    pub fn write_payload(&self, out: &mut Vec<u8>) {
        let data_time = |m: &DataTime, out: &mut Vec<u8>| {
            out.push(m.seq);
            out.push(m.data_seq);
            out.extend_from_slice(&m.mcu_time_us.to_le_bytes());
        };
        match self {
            Message::Inertial(m) => {
                out.push(m.seq);
                for v in m.specific_force_raw.iter().chain(&m.angular_rate_raw) {
                    out.extend_from_slice(&v.to_le_bytes());
                }
                out.extend_from_slice(&m.health.0.to_le_bytes());
            }
            Message::Navigation(m) => {
                out.push(m.seq);
                out.extend_from_slice(&m.pressure_height_raw.to_le_bytes());
                out.extend_from_slice(&m.velocity_down_raw.to_le_bytes());
                out.extend_from_slice(&m.roll_raw.to_le_bytes());
                out.extend_from_slice(&m.pitch_raw.to_le_bytes());
                out.extend_from_slice(&m.heading_raw.to_le_bytes());
                out.extend_from_slice(&m.health.0.to_le_bytes());
            }
            Message::Accuracy(m) => {
                out.push(m.seq);
                out.extend_from_slice(&m.std_north_raw.to_le_bytes());
                out.extend_from_slice(&m.std_east_raw.to_le_bytes());
                out.extend_from_slice(&m.std_heading_raw.to_le_bytes());
                out.extend_from_slice(&m.mcu_time_us.to_le_bytes());
            }
            Message::NavigationTime(m) | Message::InertialTime(m) => data_time(m, out),
            Message::SyncPulseTime(m) => {
                out.push(m.seq);
                out.extend_from_slice(&m.mcu_time_us.to_le_bytes());
            }
            Message::SoftwareVersion(m) => {
                out.extend_from_slice(&m.project_code);
                out.extend_from_slice(&m.major.to_le_bytes());
                out.extend_from_slice(&m.minor.to_le_bytes());
            }
            Message::HardwareVersion(m) => {
                out.extend_from_slice(&m.mcu_id.to_le_bytes());
                for w in m.unique_id {
                    out.extend_from_slice(&w.to_le_bytes());
                }
            }
            Message::EnterDiagnostics | Message::ExitDiagnostics => {}
            Message::ReadNvmPage { page } => out.push(*page),
            Message::NvmPage(m) => {
                out.push(m.page);
                out.extend_from_slice(&m.data);
            }
            Message::Ack(m) => {
                out.push(m.acked_type);
                out.push(m.status);
            }
        }
    }

    /// Appends the complete frame of this message (protocol 2.0) to `out`.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let mut payload = Vec::with_capacity(33);
        self.write_payload(&mut payload);
        super::frame::write_frame(
            self.type_id(),
            super::frame::PROTOCOL_VERSION,
            &payload,
            out,
        );
    }

    /// The complete frame of this message as a new vector.
    pub fn to_frame(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(super::frame::MAX_FRAME_LEN);
        self.encode(&mut out);
        out
    }
}
