//! The 27-byte target report layout shared by the GDL90 Ownship Report (ID 10) and Traffic Report
//! (ID 20) (GDL 90 Data Interface Specification 560-1058-00 Rev A, 3.4 and 3.5.1).
//!
//! ```text
//! byte 0      message ID (10 or 20)
//! byte 1      s (alert status, high nibble) | t (address type, low nibble)
//! bytes 2-4   aa aa aa  participant address, 24 bits
//! bytes 5-7   ll ll ll  latitude, 24-bit signed, LSB 180/2^23 deg
//! bytes 8-10  nn nn nn  longitude, 24-bit signed, LSB 180/2^23 deg
//! bytes 11-12 dd dm     altitude 12 bits, 25 ft steps, offset -1000 ft, 0xFFF invalid;
//!                       m = misc: b3 airborne, b2 extrapolated, b1..b0 track/heading type
//! byte 13     i a       NIC (high nibble), NACp (low nibble)
//! bytes 14-16 hh hv vv  horizontal velocity 12 bits unsigned, kt (0xFFF none, 0xFFE >= 4094);
//!                       vertical velocity 12 bits signed, 64 fpm (0x800 none,
//!                       0x1FE > +32576, 0xE02 < -32576, 0x1FF..0x7FF and 0x801..0xE01 unused)
//! byte 17     tt        track or heading, LSB 360/256 deg
//! byte 18     ee        emitter category
//! bytes 19-26 cc x 8    call sign, ASCII 0-9 A-Z and space
//! byte 27     p x       emergency/priority code (high nibble), spare (low nibble)
//! ```

use serde::{Serialize, Serializer};

/// Length of a clear Ownship or Traffic Report, ID included.
pub const LEN: usize = 28;

/// Latitude/longitude resolution, degrees per count (180 / 2^23).
pub const LAT_LON_LSB_DEG: f64 = 180.0 / 8_388_608.0;
/// Track/heading resolution, degrees per count (360 / 256).
pub const TRACK_LSB_DEG: f64 = 360.0 / 256.0;
/// Altitude resolution, ft.
pub const ALT_LSB_FT: i32 = 25;
/// Altitude offset, ft (code 0 is -1000 ft).
pub const ALT_OFFSET_FT: i32 = -1000;
/// Altitude code meaning "invalid or unavailable".
pub const ALT_INVALID: u16 = 0xFFF;
/// Vertical velocity resolution, ft/min.
pub const VVEL_LSB_FPM: i32 = 64;

/// Kind of the participant address (field t).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AddressKind {
    /// 0: ADS-B with ICAO address.
    AdsbIcao,
    /// 1: ADS-B with self-assigned address.
    AdsbSelfAssigned,
    /// 2: TIS-B with ICAO address.
    TisbIcao,
    /// 3: TIS-B with track file ID.
    TisbTrackFile,
    /// 4: surface vehicle.
    SurfaceVehicle,
    /// 5: ground station beacon.
    GroundStationBeacon,
    /// 6..15: reserved.
    Reserved(u8),
}

impl AddressKind {
    /// The kind of a 4-bit address type code.
    pub fn from_code(t: u8) -> Self {
        match t {
            0 => Self::AdsbIcao,
            1 => Self::AdsbSelfAssigned,
            2 => Self::TisbIcao,
            3 => Self::TisbTrackFile,
            4 => Self::SurfaceVehicle,
            5 => Self::GroundStationBeacon,
            other => Self::Reserved(other & 0x0F),
        }
    }

    /// The 4-bit code of this kind.
    pub fn code(self) -> u8 {
        match self {
            Self::AdsbIcao => 0,
            Self::AdsbSelfAssigned => 1,
            Self::TisbIcao => 2,
            Self::TisbTrackFile => 3,
            Self::SurfaceVehicle => 4,
            Self::GroundStationBeacon => 5,
            Self::Reserved(c) => c & 0x0F,
        }
    }
}

/// Meaning of the track/heading byte (misc bits 1..0).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TrackType {
    /// 0: not valid.
    #[default]
    NotValid,
    /// 1: true track angle.
    TrueTrack,
    /// 2: magnetic heading.
    MagneticHeading,
    /// 3: true heading.
    TrueHeading,
}

impl TrackType {
    fn from_bits(b: u8) -> Self {
        match b & 3 {
            0 => Self::NotValid,
            1 => Self::TrueTrack,
            2 => Self::MagneticHeading,
            _ => Self::TrueHeading,
        }
    }

    fn bits(self) -> u8 {
        match self {
            Self::NotValid => 0,
            Self::TrueTrack => 1,
            Self::MagneticHeading => 2,
            Self::TrueHeading => 3,
        }
    }
}

/// Horizontal velocity field (12 bits, unsigned, kt).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum HorizontalVelocity {
    /// 0xFFF: no horizontal velocity information.
    Unavailable,
    /// 0..=4093 kt.
    Kt(u16),
    /// 0xFFE: 4094 kt or more.
    AtLeast4094Kt,
}

impl HorizontalVelocity {
    fn from_code(c: u16) -> Self {
        match c & 0xFFF {
            0xFFF => Self::Unavailable,
            0xFFE => Self::AtLeast4094Kt,
            v => Self::Kt(v),
        }
    }

    fn code(self) -> u16 {
        match self {
            Self::Unavailable => 0xFFF,
            Self::AtLeast4094Kt => 0xFFE,
            // Spec 3.5.1.7: 4,094 kt or more holds at 0xFFE.
            Self::Kt(v) => v.min(0xFFE),
        }
    }

    /// The speed in knots, when the field carries an exact value.
    pub fn kt(self) -> Option<u16> {
        match self {
            Self::Kt(v) => Some(v),
            _ => None,
        }
    }
}

/// Vertical velocity field (12 bits, two's complement, 64 ft/min units).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum VerticalVelocity {
    /// 0x800: no vertical velocity information.
    Unavailable,
    /// -32576..=+32576 ft/min in 64 ft/min steps (codes 0xE03..=0x1FD).
    Fpm(i32),
    /// 0x1FE: climbing faster than 32576 ft/min.
    ClimbOver32576Fpm,
    /// 0xE02: descending faster than 32576 ft/min.
    DescentOver32576Fpm,
    /// 0x1FF..=0x7FF or 0x801..=0xE01: codes the specification leaves unused (raw code kept).
    Unused(u16),
}

impl VerticalVelocity {
    fn from_code(c: u16) -> Self {
        let c = c & 0xFFF;
        match c {
            0x800 => Self::Unavailable,
            0x1FE => Self::ClimbOver32576Fpm,
            0xE02 => Self::DescentOver32576Fpm,
            0x000..=0x1FD => Self::Fpm(i32::from(c) * VVEL_LSB_FPM),
            0xE03..=0xFFF => Self::Fpm((i32::from(c) - 0x1000) * VVEL_LSB_FPM),
            other => Self::Unused(other),
        }
    }

    fn code(self) -> u16 {
        match self {
            Self::Unavailable => 0x800,
            Self::ClimbOver32576Fpm => 0x1FE,
            Self::DescentOver32576Fpm => 0xE02,
            // Spec 3.5.1.8: beyond +/-32,576 fpm the value holds at the code for +/-32,640
            // (0x1FE / 0xE02).
            Self::Fpm(f) => {
                let units = (f as f64 / f64::from(VVEL_LSB_FPM)).round() as i32;
                (units.clamp(-510, 510) & 0xFFF) as u16
            }
            Self::Unused(c) => c & 0xFFF,
        }
    }

    /// The rate in ft/min, positive up, when the field carries an exact value.
    pub fn fpm(self) -> Option<i32> {
        match self {
            Self::Fpm(f) => Some(f),
            _ => None,
        }
    }
}

fn callsign_as_str<S: Serializer>(c: &[u8; 8], s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&callsign_text(c))
}

/// The call sign bytes as text, trailing spaces (and NULs) removed.
pub fn callsign_text(c: &[u8; 8]) -> String {
    let s: String = c.iter().map(|&b| char::from(b)).collect();
    s.trim_end_matches([' ', '\0']).to_string()
}

/// Ownship or traffic target report (every field of the 27 data bytes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TargetReport {
    /// Alert status s (4 bits): 0 no alert, 1 traffic alert active, 2..15 reserved.
    pub alert_status: u8,
    /// Address type t.
    pub address_type: AddressKind,
    /// Participant address, 24 bits.
    pub address: u32,
    /// Latitude, degrees (multiple of 180/2^23). 0 with lon 0 and NIC 0 means "no position".
    pub lat_deg: f64,
    /// Longitude, degrees (multiple of 180/2^23).
    pub lon_deg: f64,
    /// Altitude, ft (pressure altitude per GDL90; see the module doc of `gdl90` for the
    /// TT-Multi-RF's geometric-first option). `None` for the invalid code 0xFFF.
    pub altitude_ft: Option<i32>,
    /// Misc bit 3: airborne (false = on ground).
    pub airborne: bool,
    /// Misc bit 2: the report is extrapolated (false = updated).
    pub extrapolated: bool,
    /// Misc bits 1..0: meaning of `track_deg`.
    pub track_type: TrackType,
    /// Track or heading, degrees (multiple of 360/256), meaning per `track_type`.
    pub track_deg: f64,
    /// Navigation Integrity Category (4 bits).
    pub nic: u8,
    /// Navigation Accuracy Category for Position (4 bits).
    pub nac_p: u8,
    /// Horizontal velocity.
    pub horizontal_velocity: HorizontalVelocity,
    /// Vertical velocity.
    pub vertical_velocity: VerticalVelocity,
    /// Emitter category (GDL90 table 11: 0 no info, 1 light ... 21 line obstacle).
    pub emitter_category: u8,
    /// Call sign, 8 ASCII bytes padded with spaces.
    #[serde(serialize_with = "callsign_as_str")]
    pub callsign: [u8; 8],
    /// Emergency/priority code (4 bits): 0 none, 1 general, 2 medical, 3 minimum fuel, 4 no
    /// communication, 5 unlawful interference, 6 downed aircraft, 7..15 reserved.
    pub emergency_code: u8,
    /// The spare low nibble of the last byte, as received.
    pub spare: u8,
}

impl Default for TargetReport {
    fn default() -> Self {
        Self {
            alert_status: 0,
            address_type: AddressKind::AdsbIcao,
            address: 0,
            lat_deg: 0.0,
            lon_deg: 0.0,
            altitude_ft: None,
            airborne: false,
            extrapolated: false,
            track_type: TrackType::NotValid,
            track_deg: 0.0,
            nic: 0,
            nac_p: 0,
            horizontal_velocity: HorizontalVelocity::Unavailable,
            vertical_velocity: VerticalVelocity::Unavailable,
            emitter_category: 0,
            callsign: *b"        ",
            emergency_code: 0,
            spare: 0,
        }
    }
}

fn i24(b: [u8; 3]) -> i32 {
    // Sign-extend by placing the 24 bits in the top of an i32 and shifting back.
    i32::from_be_bytes([b[0], b[1], b[2], 0]) >> 8
}

fn deg_to_i24(deg: f64) -> [u8; 3] {
    let raw = (deg / LAT_LON_LSB_DEG).round() as i64;
    let raw = raw.clamp(-(1 << 23), (1 << 23) - 1) as i32;
    let b = raw.to_be_bytes();
    [b[1], b[2], b[3]]
}

impl TargetReport {
    /// Decodes the clear message (ID included; the ID itself is not checked here). `None` when
    /// the length is not [`LEN`].
    pub fn decode(m: &[u8]) -> Option<Self> {
        let m: &[u8; LEN] = m.try_into().ok()?;
        let alt_code = (u16::from(m[11]) << 4) | u16::from(m[12] >> 4);
        let misc = m[12] & 0x0F;
        let hvel = (u16::from(m[14]) << 4) | u16::from(m[15] >> 4);
        let vvel = (u16::from(m[15] & 0x0F) << 8) | u16::from(m[16]);
        let mut callsign = [0u8; 8];
        callsign.copy_from_slice(&m[19..27]);
        Some(Self {
            alert_status: m[1] >> 4,
            address_type: AddressKind::from_code(m[1] & 0x0F),
            address: u32::from_be_bytes([0, m[2], m[3], m[4]]),
            lat_deg: f64::from(i24([m[5], m[6], m[7]])) * LAT_LON_LSB_DEG,
            lon_deg: f64::from(i24([m[8], m[9], m[10]])) * LAT_LON_LSB_DEG,
            altitude_ft: (alt_code != ALT_INVALID)
                .then(|| i32::from(alt_code) * ALT_LSB_FT + ALT_OFFSET_FT),
            airborne: misc & 0x8 != 0,
            extrapolated: misc & 0x4 != 0,
            track_type: TrackType::from_bits(misc),
            track_deg: f64::from(m[17]) * TRACK_LSB_DEG,
            nic: m[13] >> 4,
            nac_p: m[13] & 0x0F,
            horizontal_velocity: HorizontalVelocity::from_code(hvel),
            vertical_velocity: VerticalVelocity::from_code(vvel),
            emitter_category: m[18],
            callsign,
            emergency_code: m[27] >> 4,
            spare: m[27] & 0x0F,
        })
    }

    /// Encodes the clear message with the given message ID. Values are rounded to the field
    /// resolution and clamped to the field range (an altitude outside -1000..=101350 ft becomes
    /// the nearest end; `None` becomes 0xFFF).
    pub fn encode(&self, id: u8) -> [u8; LEN] {
        let mut m = [0u8; LEN];
        m[0] = id;
        m[1] = (self.alert_status & 0x0F) << 4 | self.address_type.code();
        m[2..5].copy_from_slice(&(self.address & 0xFF_FFFF).to_be_bytes()[1..]);
        m[5..8].copy_from_slice(&deg_to_i24(self.lat_deg));
        m[8..11].copy_from_slice(&deg_to_i24(self.lon_deg));
        let alt_code = match self.altitude_ft {
            None => ALT_INVALID,
            Some(ft) => {
                let units = ((f64::from(ft) - f64::from(ALT_OFFSET_FT)) / f64::from(ALT_LSB_FT))
                    .round() as i64;
                units.clamp(0, 0xFFE) as u16
            }
        };
        let misc = u8::from(self.airborne) << 3
            | u8::from(self.extrapolated) << 2
            | self.track_type.bits();
        m[11] = (alt_code >> 4) as u8;
        m[12] = ((alt_code & 0xF) as u8) << 4 | misc;
        m[13] = (self.nic & 0x0F) << 4 | (self.nac_p & 0x0F);
        let h = self.horizontal_velocity.code();
        let v = self.vertical_velocity.code();
        m[14] = (h >> 4) as u8;
        m[15] = ((h & 0xF) as u8) << 4 | (v >> 8) as u8;
        m[16] = (v & 0xFF) as u8;
        let track = (self.track_deg.rem_euclid(360.0) / TRACK_LSB_DEG).round() as u32;
        // A track that rounds up to 360 deg (256 counts) is 0: the cast keeps the count modulo
        // 256.
        m[17] = track as u8;
        m[18] = self.emitter_category;
        m[19..27].copy_from_slice(&self.callsign);
        m[27] = (self.emergency_code & 0x0F) << 4 | (self.spare & 0x0F);
        m
    }

    /// The call sign as text (trailing padding removed); `None` when blank.
    pub fn callsign_str(&self) -> Option<String> {
        let s = callsign_text(&self.callsign);
        let s = s.trim().to_string();
        (!s.is_empty()).then_some(s)
    }

    /// Whether the report carries a position: the specification sends lat = lon = 0 with NIC 0
    /// when no valid position is available.
    pub fn has_position(&self) -> bool {
        !(self.lat_deg == 0.0 && self.lon_deg == 0.0 && self.nic == 0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sign_extension() {
        assert_eq!(i24([0x7F, 0xFF, 0xFF]), 8_388_607);
        assert_eq!(i24([0x80, 0x00, 0x00]), -8_388_608);
        assert_eq!(i24([0xFF, 0xFF, 0xFF]), -1);
        assert_eq!(deg_to_i24(-LAT_LON_LSB_DEG), [0xFF, 0xFF, 0xFF]);
        // Beyond the 24-bit range a value saturates at its extreme count, keeping its sign:
        // 200 deg is 0x7FFFFF (2^23 - 1 counts), -200 deg 0x800000.
        assert_eq!(deg_to_i24(200.0), [0x7F, 0xFF, 0xFF]);
        assert_eq!(deg_to_i24(-200.0), [0x80, 0x00, 0x00]);
    }

    #[test]
    fn vertical_velocity_codes() {
        // 0x001 = +64 fpm, 0xFFF = -64 fpm, 0x1FD = 509 * 64 = 32576, 0xE03 = -509 * 64.
        assert_eq!(
            VerticalVelocity::from_code(0x001),
            VerticalVelocity::Fpm(64)
        );
        assert_eq!(
            VerticalVelocity::from_code(0xFFF),
            VerticalVelocity::Fpm(-64)
        );
        assert_eq!(
            VerticalVelocity::from_code(0x1FD),
            VerticalVelocity::Fpm(32576)
        );
        assert_eq!(
            VerticalVelocity::from_code(0xE03),
            VerticalVelocity::Fpm(-32576)
        );
        assert_eq!(
            VerticalVelocity::from_code(0x1FE),
            VerticalVelocity::ClimbOver32576Fpm
        );
        assert_eq!(
            VerticalVelocity::from_code(0xE02),
            VerticalVelocity::DescentOver32576Fpm
        );
        assert_eq!(
            VerticalVelocity::from_code(0x800),
            VerticalVelocity::Unavailable
        );
        assert_eq!(
            VerticalVelocity::from_code(0x1FF),
            VerticalVelocity::Unused(0x1FF)
        );
        assert_eq!(
            VerticalVelocity::from_code(0xE01),
            VerticalVelocity::Unused(0xE01)
        );
        for c in 0..0x1000u16 {
            assert_eq!(VerticalVelocity::from_code(c).code(), c);
        }
        // Encoding saturates at the "more than 32,576 fpm" codes.
        assert_eq!(VerticalVelocity::Fpm(40_000).code(), 0x1FE);
        assert_eq!(VerticalVelocity::Fpm(-40_000).code(), 0xE02);
        assert_eq!(VerticalVelocity::Fpm(100).code(), 0x002);
    }

    #[test]
    fn horizontal_velocity_codes() {
        assert_eq!(HorizontalVelocity::from_code(0), HorizontalVelocity::Kt(0));
        assert_eq!(
            HorizontalVelocity::from_code(0xFFD),
            HorizontalVelocity::Kt(4093)
        );
        assert_eq!(
            HorizontalVelocity::from_code(0xFFE),
            HorizontalVelocity::AtLeast4094Kt
        );
        assert_eq!(
            HorizontalVelocity::from_code(0xFFF),
            HorizontalVelocity::Unavailable
        );
        for c in 0..0x1000u16 {
            assert_eq!(HorizontalVelocity::from_code(c).code(), c);
        }
        // 4,094 kt or more holds at 0xFFE.
        assert_eq!(HorizontalVelocity::Kt(5000).code(), 0xFFE);
    }

    #[test]
    fn address_kind_codes() {
        for c in 0..16u8 {
            assert_eq!(AddressKind::from_code(c).code(), c);
        }
        assert_eq!(AddressKind::from_code(5), AddressKind::GroundStationBeacon);
        assert_eq!(AddressKind::from_code(9), AddressKind::Reserved(9));
    }
}
