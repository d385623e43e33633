//! IMU group (ICD 2.4, Table 2.16).

use super::group::binary_group;
use super::wire::DeltaTheta;
use crate::vn200::status::{ImuStatus, SensSat};

binary_group! {
    /// IMU group (group offset 2).
    pub struct ImuGroup {
        /// ImuStatus: per-subsystem states.
        0 => pub imu_status: ImuStatus,
        /// UncompMag: magnetic field without the HSI estimator, body frame, gauss.
        1 => pub uncomp_mag_gauss: [f32; 3],
        /// UncompAccel: acceleration without dynamic bias compensation, body frame, m/s^2.
        2 => pub uncomp_accel_mps2: [f32; 3],
        /// UncompGyro: angular rate without dynamic bias compensation, body frame, rad/s.
        3 => pub uncomp_gyro_radps: [f32; 3],
        /// Temperature: sensor temperature, degrees Celsius.
        4 => pub temperature_c: f32,
        /// Pressure: absolute barometric pressure, kPa.
        5 => pub pressure_kpa: f32,
        /// DeltaTheta: integrated rotation and its interval.
        6 => pub delta_theta: DeltaTheta,
        /// DeltaVel: integrated velocity, m/s.
        7 => pub delta_vel_mps: [f32; 3],
        /// Mag: compensated magnetic field, body frame, gauss.
        8 => pub mag_gauss: [f32; 3],
        /// Accel: compensated acceleration, body frame, m/s^2.
        9 => pub accel_mps2: [f32; 3],
        /// AngularRate: compensated angular rate, body frame, rad/s.
        10 => pub angular_rate_radps: [f32; 3],
        /// SensSat: saturation flags.
        11 => pub sens_sat: SensSat,
    }
}
