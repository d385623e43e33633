//! Measurement registers and the async ASCII outputs that carry them (ICD chapter 4; Register 6,
//! Table 3.6 maps each `VNxxx` header to its register).

use serde::Serialize;

use super::AsciiError;
use super::fields::{AsciiRecord, Fields, ascii_record};
use crate::vn200::binary::{DeltaTheta, GnssFix, Heave, Lla, Quaternion, Ypr};
use crate::vn200::status::InsStatus;

ascii_record! {
    /// Register 15: quaternion and compensated magnetic, acceleration, angular rate.
    pub struct QuatMagAccelGyro {
        /// Attitude quaternion.
        pub quaternion: Quaternion,
        /// Compensated magnetic field, body frame, gauss.
        pub mag_gauss: [f32; 3],
        /// Compensated acceleration, body frame, m/s^2.
        pub accel_mps2: [f32; 3],
        /// Compensated angular rate, body frame, rad/s.
        pub gyro_radps: [f32; 3],
    }
}

ascii_record! {
    /// Register 20: compensated magnetic, acceleration and angular rate.
    pub struct MagAccelGyro {
        /// Compensated magnetic field, body frame, gauss.
        pub mag_gauss: [f32; 3],
        /// Compensated acceleration, body frame, m/s^2.
        pub accel_mps2: [f32; 3],
        /// Compensated angular rate, body frame, rad/s.
        pub gyro_radps: [f32; 3],
    }
}

ascii_record! {
    /// Register 27: yaw/pitch/roll and compensated magnetic, acceleration, angular rate.
    pub struct YprMagAccelGyro {
        /// Attitude, degrees.
        pub ypr: Ypr,
        /// Compensated magnetic field, body frame, gauss.
        pub mag_gauss: [f32; 3],
        /// Compensated acceleration, body frame, m/s^2.
        pub accel_mps2: [f32; 3],
        /// Compensated angular rate, body frame, rad/s.
        pub gyro_radps: [f32; 3],
    }
}

ascii_record! {
    /// Registers 239 (linear acceleration in body frame) and 240 (in NED): yaw/pitch/roll,
    /// linear acceleration without gravity and angular rate.
    pub struct YprLinAccelGyro {
        /// Attitude, degrees.
        pub ypr: Ypr,
        /// Linear acceleration, m/s^2 (body frame for 239, NED for 240).
        pub lin_accel_mps2: [f32; 3],
        /// Compensated angular rate, body frame, rad/s.
        pub gyro_radps: [f32; 3],
    }
}

ascii_record! {
    /// Register 54: calibrated IMU measurements.
    pub struct ImuMeasurements {
        /// Uncompensated magnetic field, gauss.
        pub uncomp_mag_gauss: [f32; 3],
        /// Uncompensated acceleration, m/s^2.
        pub uncomp_accel_mps2: [f32; 3],
        /// Uncompensated angular rate, rad/s.
        pub uncomp_gyro_radps: [f32; 3],
        /// Temperature, degrees Celsius.
        pub temperature_c: f32,
        /// Pressure, kPa.
        pub pressure_kpa: f32,
    }
}

ascii_record! {
    /// Register 58: primary GNSS solution, LLA (the SPI padding is not on the UART).
    pub struct GnssSolutionLla {
        /// GPS time of week, s.
        pub gps_tow_s: f64,
        /// GPS week.
        pub gps_week: u16,
        /// Fix type.
        pub fix: GnssFix,
        /// Satellites tracked.
        pub num_sats: u8,
        /// Position.
        pub lla: Lla,
        /// Velocity NED, m/s.
        pub vel_ned_mps: [f32; 3],
        /// Position uncertainty N, E, D, m.
        pub pos_u_ned_m: [f32; 3],
        /// Velocity uncertainty, m/s.
        pub vel_u_mps: f32,
        /// Time uncertainty, s.
        pub time_u_s: f32,
    }
}

ascii_record! {
    /// Register 59: primary GNSS solution, ECEF.
    pub struct GnssSolutionEcef {
        /// GPS time of week, s.
        pub gps_tow_s: f64,
        /// GPS week.
        pub gps_week: u16,
        /// Fix type.
        pub fix: GnssFix,
        /// Satellites tracked.
        pub num_sats: u8,
        /// Position ECEF, m.
        pub pos_ecef_m: [f64; 3],
        /// Velocity ECEF, m/s.
        pub vel_ecef_mps: [f32; 3],
        /// Position uncertainty X, Y, Z, m.
        pub pos_u_ecef_m: [f32; 3],
        /// Velocity uncertainty, m/s.
        pub vel_u_mps: f32,
        /// Time uncertainty, s.
        pub time_u_s: f32,
    }
}

ascii_record! {
    /// Register 63: INS solution, LLA.
    pub struct InsSolutionLla {
        /// GPS time of week, s.
        pub gps_tow_s: f64,
        /// GPS week.
        pub gps_week: u16,
        /// INS status (four hex digits on the wire).
        pub ins_status: InsStatus,
        /// Attitude, degrees.
        pub ypr: Ypr,
        /// Position.
        pub lla: Lla,
        /// Velocity NED, m/s.
        pub vel_ned_mps: [f32; 3],
        /// Attitude uncertainty, degrees.
        pub att_u_deg: f32,
        /// Position uncertainty, m.
        pub pos_u_m: f32,
        /// Velocity uncertainty, m/s.
        pub vel_u_mps: f32,
    }
}

ascii_record! {
    /// Register 64: INS solution, ECEF.
    pub struct InsSolutionEcef {
        /// GPS time of week, s.
        pub gps_tow_s: f64,
        /// GPS week.
        pub gps_week: u16,
        /// INS status (four hex digits on the wire).
        pub ins_status: InsStatus,
        /// Attitude, degrees.
        pub ypr: Ypr,
        /// Position ECEF, m.
        pub pos_ecef_m: [f64; 3],
        /// Velocity ECEF, m/s.
        pub vel_ecef_mps: [f32; 3],
        /// Attitude uncertainty, degrees.
        pub att_u_deg: f32,
        /// Position uncertainty, m.
        pub pos_u_m: f32,
        /// Velocity uncertainty, m/s.
        pub vel_u_mps: f32,
    }
}

ascii_record! {
    /// Register 72: INS state, LLA.
    pub struct InsStateLla {
        /// Attitude, degrees.
        pub ypr: Ypr,
        /// Position.
        pub lla: Lla,
        /// Velocity NED, m/s.
        pub vel_ned_mps: [f32; 3],
        /// Compensated acceleration, body frame, m/s^2.
        pub accel_mps2: [f32; 3],
        /// Compensated angular rate, body frame, rad/s.
        pub gyro_radps: [f32; 3],
    }
}

ascii_record! {
    /// Register 73: INS state, ECEF.
    pub struct InsStateEcef {
        /// Attitude, degrees.
        pub ypr: Ypr,
        /// Position ECEF, m.
        pub pos_ecef_m: [f64; 3],
        /// Velocity ECEF, m/s.
        pub vel_ecef_mps: [f32; 3],
        /// Compensated acceleration, body frame, m/s^2.
        pub accel_mps2: [f32; 3],
        /// Compensated angular rate, body frame, rad/s.
        pub gyro_radps: [f32; 3],
    }
}

impl AsciiRecord for DeltaTheta {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(DeltaTheta {
            delta_time_s: f.f32()?,
            delta_theta_deg: <[f32; 3]>::parse(f)?,
        })
    }
    fn format(&self, out: &mut String) {
        self.delta_time_s.format(out);
        self.delta_theta_deg.format(out);
    }
}

impl AsciiRecord for Heave {
    fn parse(f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(Heave {
            heave_m: f.f32()?,
            heave_rate_mps: f.f32()?,
            delayed_heave_m: f.f32()?,
        })
    }
    fn format(&self, out: &mut String) {
        [self.heave_m, self.heave_rate_mps, self.delayed_heave_m].format(out);
    }
}

/// The contents of a measurement register, as read with `$VNRRG` or sent as an async output.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "measurement", rename_all = "snake_case")]
pub enum Measurement {
    /// Register 8 (VNYPR): yaw, pitch, roll in degrees.
    Ypr(Ypr),
    /// Register 9 (VNQTN): quaternion.
    Quaternion(Quaternion),
    /// Register 15 (VNQMR).
    QuatMagAccelGyro(QuatMagAccelGyro),
    /// Register 17 (VNMAG): compensated magnetic field, gauss.
    Mag {
        /// Body frame x, y, z, gauss.
        mag_gauss: [f32; 3],
    },
    /// Register 18 (VNACC): compensated acceleration, m/s^2.
    Accel {
        /// Body frame x, y, z, m/s^2.
        accel_mps2: [f32; 3],
    },
    /// Register 19 (VNGYR): compensated angular rate, rad/s.
    Gyro {
        /// Body frame x, y, z, rad/s.
        gyro_radps: [f32; 3],
    },
    /// Register 20 (VNMAR).
    MagAccelGyro(MagAccelGyro),
    /// Register 27 (VNYMR).
    YprMagAccelGyro(YprMagAccelGyro),
    /// Register 239 (VNYBA): linear acceleration in the body frame.
    YprLinBodyAccelGyro(YprLinAccelGyro),
    /// Register 240 (VNYIA): linear acceleration in NED.
    YprLinNedAccelGyro(YprLinAccelGyro),
    /// Register 54 (VNIMU).
    Imu(ImuMeasurements),
    /// Register 58 (VNGPS).
    GnssLla(GnssSolutionLla),
    /// Register 59 (VNGPE).
    GnssEcef(GnssSolutionEcef),
    /// Register 63 (VNINS).
    InsLla(InsSolutionLla),
    /// Register 64 (VNINE).
    InsEcef(InsSolutionEcef),
    /// Register 72 (VNISL).
    InsStateLla(InsStateLla),
    /// Register 73 (VNISE).
    InsStateEcef(InsStateEcef),
    /// Register 80 (VNDTV): delta theta then delta velocity (m/s).
    DeltaThetaVel {
        /// Delta angles and interval.
        theta: DeltaTheta,
        /// Integrated velocity, m/s.
        delta_vel_mps: [f32; 3],
    },
    /// Register 115 (VNHVE).
    Heave(Heave),
}

/// (async header, register id) of every measurement (Table 3.6).
pub(crate) const MEASUREMENTS: [(&str, u8); 19] = [
    ("VNYPR", 8),
    ("VNQTN", 9),
    ("VNQMR", 15),
    ("VNMAG", 17),
    ("VNACC", 18),
    ("VNGYR", 19),
    ("VNMAR", 20),
    ("VNYMR", 27),
    ("VNYBA", 239),
    ("VNYIA", 240),
    ("VNIMU", 54),
    ("VNGPS", 58),
    ("VNGPE", 59),
    ("VNINS", 63),
    ("VNINE", 64),
    ("VNISL", 72),
    ("VNISE", 73),
    ("VNDTV", 80),
    ("VNHVE", 115),
];

impl Measurement {
    /// The register holding this measurement.
    pub fn register_id(&self) -> u8 {
        match self {
            Self::Ypr(_) => 8,
            Self::Quaternion(_) => 9,
            Self::QuatMagAccelGyro(_) => 15,
            Self::Mag { .. } => 17,
            Self::Accel { .. } => 18,
            Self::Gyro { .. } => 19,
            Self::MagAccelGyro(_) => 20,
            Self::YprMagAccelGyro(_) => 27,
            Self::YprLinBodyAccelGyro(_) => 239,
            Self::YprLinNedAccelGyro(_) => 240,
            Self::Imu(_) => 54,
            Self::GnssLla(_) => 58,
            Self::GnssEcef(_) => 59,
            Self::InsLla(_) => 63,
            Self::InsEcef(_) => 64,
            Self::InsStateLla(_) => 72,
            Self::InsStateEcef(_) => 73,
            Self::DeltaThetaVel { .. } => 80,
            Self::Heave(_) => 115,
        }
    }

    /// The async output header (`VNYPR` ...).
    pub fn async_header(&self) -> &'static str {
        let id = self.register_id();
        MEASUREMENTS
            .iter()
            .find(|(_, r)| *r == id)
            .map_or("VN???", |(h, _)| h)
    }

    /// Whether `id` is a measurement register this crate decodes.
    pub fn is_measurement_register(id: u8) -> bool {
        MEASUREMENTS.iter().any(|(_, r)| *r == id)
    }

    /// Parses the fields of measurement register `id`.
    pub(crate) fn parse_register(id: u8, f: &mut Fields<'_>) -> Result<Self, AsciiError> {
        Ok(match id {
            8 => Self::Ypr(Ypr::parse(f)?),
            9 => Self::Quaternion(Quaternion::parse(f)?),
            15 => Self::QuatMagAccelGyro(QuatMagAccelGyro::parse(f)?),
            17 => Self::Mag {
                mag_gauss: <[f32; 3]>::parse(f)?,
            },
            18 => Self::Accel {
                accel_mps2: <[f32; 3]>::parse(f)?,
            },
            19 => Self::Gyro {
                gyro_radps: <[f32; 3]>::parse(f)?,
            },
            20 => Self::MagAccelGyro(MagAccelGyro::parse(f)?),
            27 => Self::YprMagAccelGyro(YprMagAccelGyro::parse(f)?),
            239 => Self::YprLinBodyAccelGyro(YprLinAccelGyro::parse(f)?),
            240 => Self::YprLinNedAccelGyro(YprLinAccelGyro::parse(f)?),
            54 => Self::Imu(ImuMeasurements::parse(f)?),
            58 => Self::GnssLla(GnssSolutionLla::parse(f)?),
            59 => Self::GnssEcef(GnssSolutionEcef::parse(f)?),
            63 => Self::InsLla(InsSolutionLla::parse(f)?),
            64 => Self::InsEcef(InsSolutionEcef::parse(f)?),
            72 => Self::InsStateLla(InsStateLla::parse(f)?),
            73 => Self::InsStateEcef(InsStateEcef::parse(f)?),
            80 => Self::DeltaThetaVel {
                theta: DeltaTheta::parse(f)?,
                delta_vel_mps: <[f32; 3]>::parse(f)?,
            },
            115 => Self::Heave(Heave::parse(f)?),
            _ => return Err(f.bad("not a measurement register")),
        })
    }

    /// Parses an async output with sentence header `header`, or `None` if the header is not an
    /// async output.
    pub(crate) fn parse_async(
        header: &str,
        f: &mut Fields<'_>,
    ) -> Result<Option<Self>, AsciiError> {
        match MEASUREMENTS.iter().find(|(h, _)| *h == header) {
            Some(&(_, id)) => Self::parse_register(id, f).map(Some),
            None => Ok(None),
        }
    }

    /// Appends the fields, each preceded by a comma.
    pub(crate) fn format(&self, out: &mut String) {
        match self {
            Self::Ypr(v) => v.format(out),
            Self::Quaternion(v) => v.format(out),
            Self::QuatMagAccelGyro(v) => v.format(out),
            Self::Mag { mag_gauss: v }
            | Self::Accel { accel_mps2: v }
            | Self::Gyro { gyro_radps: v } => v.format(out),
            Self::MagAccelGyro(v) => v.format(out),
            Self::YprMagAccelGyro(v) => v.format(out),
            Self::YprLinBodyAccelGyro(v) | Self::YprLinNedAccelGyro(v) => v.format(out),
            Self::Imu(v) => v.format(out),
            Self::GnssLla(v) => v.format(out),
            Self::GnssEcef(v) => v.format(out),
            Self::InsLla(v) => v.format(out),
            Self::InsEcef(v) => v.format(out),
            Self::InsStateLla(v) => v.format(out),
            Self::InsStateEcef(v) => v.format(out),
            Self::DeltaThetaVel {
                theta,
                delta_vel_mps,
            } => {
                theta.format(out);
                delta_vel_mps.format(out);
            }
            Self::Heave(v) => v.format(out),
        }
    }
}

/// An asynchronous ASCII output (Register 6) with the optional appended status and counter of
/// Register 30.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AsyncOutput {
    /// The measurement.
    #[serde(flatten)]
    pub data: Measurement,
    /// Appended status (`S` + 4 hex digits), if Register 30 enables it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub appended_status: Option<u16>,
    /// Appended counter or time (`T` + decimal), if Register 30 enables it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub appended_count: Option<u32>,
}

impl AsyncOutput {
    /// The sentence body. Appended fields follow the ICD's example order: count, then status.
    pub fn body(&self) -> String {
        let mut s = self.data.async_header().to_string();
        self.data.format(&mut s);
        if let Some(c) = self.appended_count {
            s.push_str(&format!(",T{c}"));
        }
        if let Some(st) = self.appended_status {
            s.push_str(&format!(",S{st:04X}"));
        }
        s
    }
}
