//! Little-endian wire primitives of the binary output messages (ICD 2.1.3: "all data is directly
//! concatenated, with no padding bytes", little-endian except the CRC).
//!
//! Every binary type implements [`Wire`]: its size, how to read it from a checked cursor and how
//! to append it to an output buffer. Composite types are declared with `wire_struct!`, which
//! derives the size as the sum of the field sizes, so that the test against Table 2.2 compares
//! the table with each type's own field list (2.2 to 2.8).

use serde::Serialize;

/// A cursor over a byte slice. Reads never panic and never fail: reading past the end yields
/// zeros and marks the cursor short ([`Rd::is_short`]). Callers check the length before reading
/// (the message length is validated before decoding) and check `is_short` after, which keeps
/// the per-field path free of error plumbing (it is the decoder's hot path).
#[derive(Debug, Clone, Copy)]
pub struct Rd<'a> {
    buf: &'a [u8],
    short: bool,
}

impl<'a> Rd<'a> {
    /// A cursor over `buf`.
    #[inline(always)]
    pub fn new(buf: &'a [u8]) -> Self {
        Self { buf, short: false }
    }

    /// Takes the next `N` bytes (zeros, and the cursor marked short, past the end).
    #[inline(always)]
    pub fn take<const N: usize>(&mut self) -> [u8; N] {
        match self.buf.split_first_chunk::<N>() {
            Some((head, tail)) => {
                self.buf = tail;
                *head
            }
            None => {
                self.short = true;
                self.buf = &[];
                [0; N]
            }
        }
    }

    /// Whether a read went past the end.
    #[inline(always)]
    pub fn is_short(&self) -> bool {
        self.short
    }

    /// Bytes left.
    #[inline(always)]
    pub fn remaining(&self) -> usize {
        self.buf.len()
    }
}

/// A binary output type (or a field of one): fixed or variable size, read and written
/// little-endian.
pub trait Wire: Sized {
    /// Size in bytes. For the variable-length GNSS types this is the size with one entry, which
    /// is what Table 2.2 lists (GnssSatInfo 10 = 2 + 8, GnssRawMeas 40 = 12 + 28).
    const SIZE: usize;
    /// Whether the size depends on a count inside the type.
    const VARIABLE: bool = false;

    /// Length of this type at the start of `bytes`, or `None` when `bytes` is too short to tell
    /// (only variable types look at the bytes).
    #[inline(always)]
    fn wire_len(_bytes: &[u8]) -> Option<usize> {
        Some(Self::SIZE)
    }

    /// Reads the value from the cursor (see [`Rd`] for reads past the end).
    fn read(r: &mut Rd<'_>) -> Self;

    /// Appends the value's bytes.
    fn write(&self, out: &mut Vec<u8>);
}

macro_rules! wire_prim {
    ($($t:ty),*) => {$(
        impl Wire for $t {
            const SIZE: usize = std::mem::size_of::<$t>();
            #[inline(always)]
            fn read(r: &mut Rd<'_>) -> Self {
                <$t>::from_le_bytes(r.take())
            }
            #[inline]
            fn write(&self, out: &mut Vec<u8>) {
                out.extend_from_slice(&self.to_le_bytes());
            }
        }
    )*};
}
wire_prim!(u8, i8, u16, i16, u32, u64, f32, f64);

impl<T: Wire + Copy + Default, const N: usize> Wire for [T; N] {
    const SIZE: usize = T::SIZE * N;
    #[inline(always)]
    fn read(r: &mut Rd<'_>) -> Self {
        std::array::from_fn(|_| T::read(r))
    }
    #[inline]
    fn write(&self, out: &mut Vec<u8>) {
        for x in self {
            x.write(out);
        }
    }
}

/// Declares a fixed-size composite wire type: a struct whose size is the sum of its fields'.
macro_rules! wire_struct {
    ($(#[$m:meta])* pub struct $name:ident { $($(#[$fm:meta])* pub $f:ident : $t:ty,)* }) => {
        $(#[$m])*
        #[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize)]
        pub struct $name { $($(#[$fm])* pub $f: $t,)* }

        impl $crate::vn200::binary::wire::Wire for $name {
            const SIZE: usize = 0 $(+ <$t as $crate::vn200::binary::wire::Wire>::SIZE)*;
            #[inline(always)]
            fn read(r: &mut $crate::vn200::binary::wire::Rd<'_>) -> Self {
                Self { $($f: <$t as $crate::vn200::binary::wire::Wire>::read(r),)* }
            }
            #[inline]
            fn write(&self, out: &mut Vec<u8>) {
                $($crate::vn200::binary::wire::Wire::write(&self.$f, out);)*
            }
        }
    };
}
pub(crate) use wire_struct;

wire_struct! {
    /// Yaw, pitch, roll: a 3-2-1 Euler sequence of the body relative to local NED (2.6.1).
    pub struct Ypr {
        /// Yaw angle, degrees.
        pub yaw_deg: f32,
        /// Pitch angle, degrees.
        pub pitch_deg: f32,
        /// Roll angle, degrees.
        pub roll_deg: f32,
    }
}

wire_struct! {
    /// Attitude quaternion (2.6.2), ordered vector part then scalar.
    pub struct Quaternion {
        /// First vector component.
        pub x: f32,
        /// Second vector component.
        pub y: f32,
        /// Third vector component.
        pub z: f32,
        /// Scalar component.
        pub s: f32,
    }
}

wire_struct! {
    /// Geodetic position (2.7.2, 2.5.6): latitude and longitude in degrees, altitude above the
    /// WGS-84 ellipsoid in metres.
    pub struct Lla {
        /// Geodetic latitude, degrees.
        pub lat_deg: f64,
        /// Longitude, degrees.
        pub lon_deg: f64,
        /// Altitude above the WGS-84 ellipsoid, metres.
        pub alt_m: f64,
    }
}

wire_struct! {
    /// UTC date and time (2.3.7, 2.5.1).
    pub struct TimeUtc {
        /// Years after 2000 (signed).
        pub year_offset: i8,
        /// Month, 1 to 12.
        pub month: u8,
        /// Day of the month, 1 to 31.
        pub day: u8,
        /// Hour, 0 to 23.
        pub hour: u8,
        /// Minute, 0 to 59.
        pub minute: u8,
        /// Second, 0 to 59.
        pub second: u8,
        /// Fraction of the second, milliseconds. The Time group (2.3.7) says uint16 0..999, the
        /// GNSS groups (2.5.1) say int16 "typically positive, but may be negative": both agree on
        /// 0..999, so one signed reading serves both (the bytes round-trip either way).
        pub frac_ms: i16,
    }
}

wire_struct! {
    /// Delta angles over an integration interval (2.4.7).
    pub struct DeltaTheta {
        /// Duration of the integration interval, seconds.
        pub delta_time_s: f32,
        /// Integrated rotation vector, degrees (x, y, z).
        pub delta_theta_deg: [f32; 3],
    }
}

wire_struct! {
    /// Common group Imu (2.2, offset 9): IMU group UncompAccel then UncompGyro.
    pub struct ImuPair {
        /// Uncompensated acceleration, body frame, m/s^2.
        pub uncomp_accel_mps2: [f32; 3],
        /// Uncompensated angular rate, body frame, rad/s.
        pub uncomp_gyro_radps: [f32; 3],
    }
}

wire_struct! {
    /// Common group MagPres (2.2, offset 10): IMU group Mag, Temperature and Pressure.
    pub struct MagPres {
        /// Compensated magnetic field, body frame, gauss.
        pub mag_gauss: [f32; 3],
        /// Sensor temperature, degrees Celsius.
        pub temperature_c: f32,
        /// Barometric pressure, kPa.
        pub pressure_kpa: f32,
    }
}

wire_struct! {
    /// Common group Deltas (2.2, offset 11): IMU group DeltaTheta then DeltaVel.
    pub struct Deltas {
        /// Delta angles and their interval.
        pub theta: DeltaTheta,
        /// Integrated velocity, m/s (x, y, z).
        pub delta_vel_mps: [f32; 3],
    }
}

wire_struct! {
    /// GNSS time validity and leap seconds (2.5.13).
    pub struct GnssTimeInfo {
        /// Time validity flags (same layout as TimeStatus).
        pub status: crate::vn200::status::TimeStatus,
        /// Current GPS-UTC leap seconds, seconds.
        pub leap_seconds: i8,
    }
}

wire_struct! {
    /// Dilutions of precision (2.5.14), dimensionless.
    pub struct GnssDop {
        /// Geometric DOP.
        pub gdop: f32,
        /// Position DOP.
        pub pdop: f32,
        /// Time DOP.
        pub tdop: f32,
        /// Vertical DOP.
        pub vdop: f32,
        /// Horizontal DOP.
        pub hdop: f32,
        /// North DOP.
        pub ndop: f32,
        /// East DOP.
        pub edop: f32,
    }
}

wire_struct! {
    /// Heave estimates (2.6.9).
    pub struct Heave {
        /// Real-time heave, metres.
        pub heave_m: f32,
        /// Real-time heave rate, m/s.
        pub heave_rate_mps: f32,
        /// Delayed heave (about 50 s old, more accurate), metres.
        pub delayed_heave_m: f32,
    }
}

/// GNSS fix type (2.5.5), kept raw so that undocumented values survive; see [`GnssFix::kind`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
#[serde(transparent)]
pub struct GnssFix(pub u8);

/// Documented GNSS fix types (Table 2.41).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum GnssFixKind {
    /// Not tracking.
    NoFix,
    /// Time only.
    TimeOnly,
    /// Time and 2D position.
    Fix2D,
    /// Time and 3D position.
    Fix3D,
    /// 3D with SBAS corrections.
    Sbas,
    /// Approximate RTK solution.
    RtkFloat,
    /// Fixed RTK solution.
    RtkFix,
}

impl GnssFix {
    /// The documented meaning, or `None` for an undocumented value.
    pub fn kind(self) -> Option<GnssFixKind> {
        Some(match self.0 {
            0 => GnssFixKind::NoFix,
            1 => GnssFixKind::TimeOnly,
            2 => GnssFixKind::Fix2D,
            3 => GnssFixKind::Fix3D,
            4 => GnssFixKind::Sbas,
            7 => GnssFixKind::RtkFloat,
            8 => GnssFixKind::RtkFix,
            _ => return None,
        })
    }
}

impl Wire for GnssFix {
    const SIZE: usize = 1;
    #[inline(always)]
    fn read(r: &mut Rd<'_>) -> Self {
        Self(u8::read(r))
    }
    fn write(&self, out: &mut Vec<u8>) {
        out.push(self.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitives_are_little_endian() {
        let mut out = Vec::new();
        0x0102_0304u32.write(&mut out);
        assert_eq!(out, [4, 3, 2, 1]);
        let mut r = Rd::new(&[0x93, 0x50, 0x2E, 0x42, 0x01]);
        // Figure A.2: 0x422E5093 = +43.578686.
        let yaw = f32::read(&mut r);
        assert!((yaw - 43.578686).abs() < 1e-5);
        assert!(!r.is_short());
        assert_eq!(u16::read(&mut r), 0, "past the end: zero, and marked short");
        assert!(r.is_short());
    }

    #[test]
    fn composite_sizes_are_sums_of_fields() {
        assert_eq!(Ypr::SIZE, 12);
        assert_eq!(Lla::SIZE, 24);
        assert_eq!(TimeUtc::SIZE, 8);
        assert_eq!(Deltas::SIZE, 28);
        assert_eq!(MagPres::SIZE, 20);
        assert_eq!(GnssDop::SIZE, 28);
    }
}
