//! Common group (ICD 2.2, Table 2.3): copies and concatenations of types from the other groups.

use super::group::binary_group;
use super::wire::{Deltas, ImuPair, Lla, MagPres, Quaternion, Ypr};
use crate::vn200::status::InsStatus;

binary_group! {
    /// Common group (group offset 0).
    pub struct CommonGroup {
        /// TimeStartup: time since start-up, ns.
        0 => pub time_startup_ns: u64,
        /// TimeGps: absolute GPS time since 1980-01-06, ns.
        1 => pub time_gps_ns: u64,
        /// TimeSyncIn: time since the last SyncIn trigger, ns.
        2 => pub time_sync_in_ns: u64,
        /// Ypr: attitude as yaw, pitch, roll (degrees).
        3 => pub ypr: Ypr,
        /// Quaternion: attitude quaternion.
        4 => pub quaternion: Quaternion,
        /// AngularRate: compensated angular rate, body frame, rad/s.
        5 => pub angular_rate_radps: [f32; 3],
        /// PosLla: INS position.
        6 => pub pos_lla: Lla,
        /// VelNed: INS velocity, NED, m/s.
        7 => pub vel_ned_mps: [f32; 3],
        /// Accel: compensated acceleration, body frame, m/s^2.
        8 => pub accel_mps2: [f32; 3],
        /// Imu: uncompensated acceleration and angular rate.
        9 => pub imu: ImuPair,
        /// MagPres: compensated magnetic field, temperature and pressure.
        10 => pub mag_pres: MagPres,
        /// Deltas: delta angles and delta velocity.
        11 => pub deltas: Deltas,
        /// InsStatus: INS status word.
        12 => pub ins_status: InsStatus,
        /// SyncInCnt: number of SyncIn events.
        13 => pub sync_in_cnt: u32,
        /// TimeGpsPps: time since the last GPS PPS, ns.
        14 => pub time_gps_pps_ns: u64,
    }
}
