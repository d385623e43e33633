//! Time group (ICD 2.3, Table 2.4).

use super::group::binary_group;
use super::wire::TimeUtc;
use crate::vn200::status::TimeStatus;

binary_group! {
    /// Time group (group offset 1).
    pub struct TimeGroup {
        /// TimeStartup: time since start-up (TCXO, 20 ppm), ns.
        0 => pub time_startup_ns: u64,
        /// TimeGps: absolute GPS time since 1980-01-06, ns.
        1 => pub time_gps_ns: u64,
        /// GpsTow: GPS time of week, ns.
        2 => pub gps_tow_ns: u64,
        /// GpsWeek: GPS week number.
        3 => pub gps_week: u16,
        /// TimeSyncIn: time since the last SyncIn trigger, ns.
        4 => pub time_sync_in_ns: u64,
        /// TimeGpsPps: time since the last GPS PPS, ns.
        5 => pub time_gps_pps_ns: u64,
        /// TimeUtc: UTC date and time.
        6 => pub time_utc: TimeUtc,
        /// SyncInCnt: number of SyncIn events.
        7 => pub sync_in_cnt: u32,
        /// SyncOutCnt: number of SyncOut events.
        8 => pub sync_out_cnt: u32,
        /// TimeStatus: time validity flags.
        9 => pub time_status: TimeStatus,
    }
}
