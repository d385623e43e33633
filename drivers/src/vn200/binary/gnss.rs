//! GNSS and GNSS2 groups (ICD 2.5 and 2.8, Tables 2.35 and 2.89): the two groups have the same
//! types, for the primary and the secondary receiver, so one struct serves both.
//!
//! GnssSatInfo (2.5.15, 2 + 8 x Count bytes) and GnssRawMeas (2.5.16, 12 + 28 x NumSats bytes)
//! are variable-length: their count is read to find the message length before the CRC check.
//! Offsets 16-18 follow the tables (bit 0-2 of the second type word): see `group.rs`.

use serde::Serialize;

use super::group::binary_group;
use super::wire::{GnssDop, GnssFix, GnssTimeInfo, Lla, Rd, TimeUtc, Wire, wire_struct};
use crate::vn200::status::GnssStatus;

wire_struct! {
    /// One satellite of GnssSatInfo (2.5.15).
    pub struct SatInfoEntry {
        /// Constellation (Table 2.52: 0 GPS, 1 SBAS, 2 Galileo, 3 BeiDou, 4 IMES, 5 QZSS,
        /// 6 GLONASS, 7 IRNSS, 8 L-Band, 255 unknown).
        pub sys: u8,
        /// Space vehicle id.
        pub sv_id: u8,
        /// Status flags (Table 2.53: bit 0 healthy, 1 almanac, 2 ephemeris, 3 differential,
        /// 4 used for PVT, 5 az/el valid, 6 used for RTK).
        pub flags: u8,
        /// Carrier-to-noise density, dB-Hz.
        pub cno_dbhz: u8,
        /// Quality indicator (Table 2.54, 0-7).
        pub qi: u8,
        /// Elevation, degrees.
        pub elevation_deg: i8,
        /// Azimuth, degrees.
        pub azimuth_deg: i16,
    }
}

/// GnssSatInfo (2.5.15): a 2-byte header (Count, reserved) then 8 bytes per satellite.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct SatInfo {
    /// The reserved header byte, kept as received.
    pub reserved: u8,
    /// One entry per satellite (at most 255: Count is one byte; the encoder writes no more).
    pub sats: Vec<SatInfoEntry>,
}

impl Wire for SatInfo {
    const SIZE: usize = 2 + SatInfoEntry::SIZE;
    const VARIABLE: bool = true;

    fn wire_len(bytes: &[u8]) -> Option<usize> {
        let count = usize::from(*bytes.first()?);
        Some(2 + SatInfoEntry::SIZE * count)
    }

    fn read(r: &mut Rd<'_>) -> Self {
        let count = u8::read(r);
        let reserved = u8::read(r);
        let sats = (0..count)
            .map_while(|_| (!r.is_short()).then(|| SatInfoEntry::read(r)))
            .collect();
        Self { reserved, sats }
    }

    fn write(&self, out: &mut Vec<u8>) {
        let n = self.sats.len().min(255);
        out.push(n as u8);
        out.push(self.reserved);
        for s in self.sats.iter().take(n) {
            s.write(out);
        }
    }
}

wire_struct! {
    /// One signal of GnssRawMeas (2.5.16).
    pub struct RawMeasEntry {
        /// Constellation (Table 2.56, as in [`SatInfoEntry::sys`]).
        pub sys: u8,
        /// Space vehicle id.
        pub sv_id: u8,
        /// Frequency (Table 2.57: 1 L1, 255 unknown).
        pub freq: u8,
        /// Channel (Table 2.58: 1 C/A, 255 unknown).
        pub chan: u8,
        /// GLONASS slot id.
        pub slot: i8,
        /// Carrier-to-noise density, dB-Hz.
        pub cno_dbhz: u8,
        /// Tracking flags (Table 2.59: bit 0 searching, 1 tracking, 2 time valid, 3 code lock,
        /// 4 phase lock, 5 half-cycle ambiguity, 6 half cycle subtracted, 7 slip, 8 smoothed).
        pub flags: u16,
        /// Pseudorange. The ICD gives no unit and says "in cycles"; kept as sent.
        pub pseudorange: f64,
        /// Carrier phase, cycles.
        pub carrier_phase_cycles: f64,
        /// Doppler, Hz (positive for approaching satellites).
        pub doppler_hz: f32,
    }
}

/// GnssRawMeas (2.5.16): a 12-byte header then 28 bytes per signal.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct RawMeas {
    /// GPS time of week, s.
    pub tow_s: f64,
    /// GPS week.
    pub week: u16,
    /// The reserved header byte, kept as received.
    pub reserved: u8,
    /// One entry per signal (at most 255; the encoder writes no more).
    pub meas: Vec<RawMeasEntry>,
}

impl Wire for RawMeas {
    const SIZE: usize = 12 + RawMeasEntry::SIZE;
    const VARIABLE: bool = true;

    fn wire_len(bytes: &[u8]) -> Option<usize> {
        let count = usize::from(*bytes.get(10)?);
        Some(12 + RawMeasEntry::SIZE * count)
    }

    fn read(r: &mut Rd<'_>) -> Self {
        let tow_s = f64::read(r);
        let week = u16::read(r);
        let count = u8::read(r);
        let reserved = u8::read(r);
        let meas = (0..count)
            .map_while(|_| (!r.is_short()).then(|| RawMeasEntry::read(r)))
            .collect();
        Self {
            tow_s,
            week,
            reserved,
            meas,
        }
    }

    fn write(&self, out: &mut Vec<u8>) {
        let n = self.meas.len().min(255);
        self.tow_s.write(out);
        self.week.write(out);
        out.push(n as u8);
        out.push(self.reserved);
        for m in self.meas.iter().take(n) {
            m.write(out);
        }
    }
}

binary_group! {
    /// GNSS group (group offset 3) or GNSS2 group (group offset 6).
    pub struct GnssGroup {
        /// TimeUtc: UTC date and time.
        0 => pub time_utc: TimeUtc,
        /// GpsTow: GPS time of week, ns.
        1 => pub gps_tow_ns: u64,
        /// GpsWeek: GPS week.
        2 => pub gps_week: u16,
        /// NumSats: satellites tracked.
        3 => pub num_sats: u8,
        /// GnssFix: fix type.
        4 => pub fix: GnssFix,
        /// GnssPosLla: receiver position.
        5 => pub pos_lla: Lla,
        /// GnssPosEcef: receiver position in ECEF, m.
        6 => pub pos_ecef_m: [f64; 3],
        /// GnssVelNed: velocity in NED, m/s.
        7 => pub vel_ned_mps: [f32; 3],
        /// GnssVelEcef: velocity in ECEF, m/s.
        8 => pub vel_ecef_mps: [f32; 3],
        /// GnssPosUncertainty: position uncertainty N, E, D, m.
        9 => pub pos_u_ned_m: [f32; 3],
        /// GnssVelUncertainty: scalar velocity uncertainty, m/s.
        10 => pub vel_u_mps: f32,
        /// GnssTimeUncertainty: time uncertainty, s.
        11 => pub time_u_s: f32,
        /// GnssTimeInfo: time validity and leap seconds.
        12 => pub time_info: GnssTimeInfo,
        /// GnssDop: dilutions of precision.
        13 => pub dop: GnssDop,
        /// GnssSatInfo: per-satellite information (variable length).
        14 => pub sat_info: SatInfo,
        /// GnssRawMeas: per-signal raw measurements (variable length; offset 16 = bit 0 of the
        /// second type word).
        16 => pub raw_meas: RawMeas,
        /// GnssStatus: receiver status flags.
        17 => pub status: GnssStatus,
        /// GnssAltMSL: altitude above mean sea level, m.
        18 => pub alt_msl_m: f64,
    }
}
