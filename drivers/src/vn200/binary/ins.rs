//! INS group (ICD 2.7, Table 2.75).

use super::group::binary_group;
use super::wire::Lla;
use crate::vn200::status::InsStatus;

binary_group! {
    /// INS group (group offset 5).
    pub struct InsGroup {
        /// InsStatus: mode, fix and error flags.
        0 => pub ins_status: InsStatus,
        /// PosLla: position (latitude, longitude degrees; altitude above WGS-84 m).
        1 => pub pos_lla: Lla,
        /// PosEcef: position in ECEF, m.
        2 => pub pos_ecef_m: [f64; 3],
        /// VelBody: velocity in body frame, m/s.
        3 => pub vel_body_mps: [f32; 3],
        /// VelNed: velocity in NED, m/s.
        4 => pub vel_ned_mps: [f32; 3],
        /// VelEcef: velocity in ECEF, m/s.
        5 => pub vel_ecef_mps: [f32; 3],
        /// MagEcef: compensated magnetic field in ECEF, gauss.
        6 => pub mag_ecef_gauss: [f32; 3],
        /// AccelEcef: acceleration with gravity in ECEF, m/s^2.
        7 => pub accel_ecef_mps2: [f32; 3],
        /// LinAccelEcef: linear acceleration without gravity in ECEF, m/s^2.
        8 => pub lin_accel_ecef_mps2: [f32; 3],
        /// PosU: 1-sigma position uncertainty, m.
        9 => pub pos_u_m: f32,
        /// VelU: 1-sigma velocity uncertainty, m/s.
        10 => pub vel_u_mps: f32,
    }
}
