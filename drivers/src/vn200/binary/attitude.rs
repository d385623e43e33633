//! Attitude group (ICD 2.6, Table 2.64). Offsets 0 and 9-11 are not defined by this ICD (a
//! VN-100 uses 0 for VpeStatus); a message selecting them is counted as an unknown type.

use super::group::binary_group;
use super::wire::{Heave, Quaternion, Ypr};

binary_group! {
    /// Attitude group (group offset 4).
    pub struct AttitudeGroup {
        /// Ypr: yaw, pitch, roll (3-2-1, body relative to NED), degrees.
        1 => pub ypr: Ypr,
        /// Quaternion: attitude quaternion (x, y, z, scalar).
        2 => pub quaternion: Quaternion,
        /// Dcm: direction cosine matrix mapping NED into body, column-major order as sent
        /// (C00, C01, C02, C10, ...; 2.6.3).
        3 => pub dcm: [f32; 9],
        /// MagNed: compensated magnetic field in NED, gauss.
        4 => pub mag_ned_gauss: [f32; 3],
        /// AccelNed: acceleration with gravity in NED, m/s^2.
        5 => pub accel_ned_mps2: [f32; 3],
        /// LinBodyAcc: linear acceleration without gravity, body frame, m/s^2.
        6 => pub lin_body_acc_mps2: [f32; 3],
        /// LinAccelNed: linear acceleration without gravity in NED, m/s^2.
        7 => pub lin_accel_ned_mps2: [f32; 3],
        /// YprU: 1-sigma yaw, pitch, roll uncertainty, degrees.
        8 => pub ypr_u: Ypr,
        /// Heave: heave, heave rate and delayed heave.
        12 => pub heave: Heave,
        /// AttU: 1-sigma attitude uncertainty, degrees.
        13 => pub att_u_deg: f32,
    }
}
