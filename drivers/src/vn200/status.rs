//! Status words of the binary outputs: TimeStatus (2.3.10), ImuStatus (2.4.1), SensSat (2.4.12),
//! GnssStatus (2.5.17), InsStatus (2.7.1).
//!
//! Each keeps the raw word, reserved bits included: real sensors set reserved bits (InsStatus
//! 0x8085 is normal), so nothing is rejected or masked away on decode; the documented bits are
//! exposed by accessors. Serialised as an object with `raw` and the documented fields.

use serde::ser::{Serialize, SerializeStruct, Serializer};

use super::binary::wire::{Rd, Wire};

macro_rules! raw_word {
    ($name:ident, $t:ty) => {
        impl Wire for $name {
            const SIZE: usize = std::mem::size_of::<$t>();
            #[inline(always)]
            fn read(r: &mut Rd<'_>) -> Self {
                Self(<$t>::read(r))
            }
            #[inline]
            fn write(&self, out: &mut Vec<u8>) {
                self.0.write(out)
            }
        }
    };
}

/// TimeStatus (Table 2.15): validity of time of week, date and UTC time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct TimeStatus(pub u8);
raw_word!(TimeStatus, u8);

impl TimeStatus {
    /// GPS time of week is valid (bit 0).
    pub fn tow_valid(self) -> bool {
        self.0 & 1 != 0
    }
    /// Date (GPS week) is valid (bit 1).
    pub fn date_valid(self) -> bool {
        self.0 & 2 != 0
    }
    /// UTC time is valid (bit 2).
    pub fn utc_valid(self) -> bool {
        self.0 & 4 != 0
    }
}

impl Serialize for TimeStatus {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("TimeStatus", 4)?;
        st.serialize_field("raw", &self.0)?;
        st.serialize_field("tow_valid", &self.tow_valid())?;
        st.serialize_field("date_valid", &self.date_valid())?;
        st.serialize_field("utc_valid", &self.utc_valid())?;
        st.end()
    }
}

/// State of one IMU subsystem (Tables 2.19 to 2.22).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum SensorState {
    /// Operating nominally; the output is a new measurement.
    NominalUpdated,
    /// Operating nominally; the output is not new (lower sampling rate).
    NominalNotUpdated,
    /// Saturated: the output is clamped to the sensor's maximum.
    Saturated,
    /// Failed: the output is not valid.
    Failed,
}

impl SensorState {
    fn from_bits(v: u16) -> Self {
        match v & 3 {
            0 => Self::NominalUpdated,
            1 => Self::NominalNotUpdated,
            2 => Self::Saturated,
            _ => Self::Failed,
        }
    }
}

/// ImuStatus (Table 2.18): two-bit states of gyro, accelerometer, magnetometer and
/// pressure/temperature; bits 8-15 reserved (kept in the raw word).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ImuStatus(pub u16);
raw_word!(ImuStatus, u16);

impl ImuStatus {
    /// Gyroscope state (bits 0-1).
    pub fn gyro(self) -> SensorState {
        SensorState::from_bits(self.0)
    }
    /// Accelerometer state (bits 2-3).
    pub fn accel(self) -> SensorState {
        SensorState::from_bits(self.0 >> 2)
    }
    /// Magnetometer state (bits 4-5).
    pub fn mag(self) -> SensorState {
        SensorState::from_bits(self.0 >> 4)
    }
    /// Pressure and temperature state (bits 6-7).
    pub fn pres_temp(self) -> SensorState {
        SensorState::from_bits(self.0 >> 6)
    }
}

impl Serialize for ImuStatus {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("ImuStatus", 5)?;
        st.serialize_field("raw", &self.0)?;
        st.serialize_field("gyro", &self.gyro())?;
        st.serialize_field("accel", &self.accel())?;
        st.serialize_field("mag", &self.mag())?;
        st.serialize_field("pres_temp", &self.pres_temp())?;
        st.end()
    }
}

/// SensSat (Table 2.34): saturation flags per sensor axis; bits 10-15 undocumented (kept raw).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SensSat(pub u16);
raw_word!(SensSat, u16);

impl SensSat {
    /// Names of the documented bits 0-9, in bit order.
    pub const NAMES: [&'static str; 10] = [
        "mag_x", "mag_y", "mag_z", "accel_x", "accel_y", "accel_z", "gyro_x", "gyro_y", "gyro_z",
        "pres",
    ];
    /// Whether documented bit `bit` (0-9, see [`SensSat::NAMES`]) is set.
    pub fn saturated(self, bit: u8) -> bool {
        bit < 10 && self.0 & (1 << bit) != 0
    }
    /// Whether any documented sensor is saturated.
    pub fn any(self) -> bool {
        self.0 & 0x03FF != 0
    }
}

impl Serialize for SensSat {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let sat: Vec<&str> = (0..10)
            .filter(|&b| self.saturated(b))
            .map(|b| Self::NAMES[usize::from(b)])
            .collect();
        let mut st = s.serialize_struct("SensSat", 2)?;
        st.serialize_field("raw", &self.0)?;
        st.serialize_field("saturated", &sat)?;
        st.end()
    }
}

/// GNSS receiver named by GnssStatus DataSource (Table 2.62).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum GnssDataSource {
    /// None.
    Disabled,
    /// Internal receiver A.
    InternalA,
    /// External receiver.
    External,
    /// An undocumented value (kept).
    Other(u8),
}

/// GnssStatus (Table 2.61).
///
/// The table gives DataSource at offset 8 and the next field at 11: DataSource is read as the
/// three bits 8-10. Resv1 spans bits 5-7 and bits 13-15 are undocumented (both kept raw).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct GnssStatus(pub u16);
raw_word!(GnssStatus, u16);

impl GnssStatus {
    /// Receiver enabled (bit 0).
    pub fn enabled(self) -> bool {
        self.0 & 1 != 0
    }
    /// Receiver operational (bit 1).
    pub fn operational(self) -> bool {
        self.0 & 2 != 0
    }
    /// Receiver has a fix (bit 2).
    pub fn fix(self) -> bool {
        self.0 & 4 != 0
    }
    /// Antenna signal error (bit 3).
    pub fn antenna_signal_error(self) -> bool {
        self.0 & 8 != 0
    }
    /// Used for the navigation solution, filtered (bit 4).
    pub fn used_for_nav(self) -> bool {
        self.0 & 0x10 != 0
    }
    /// Receiver this status is for (bits 8-10).
    pub fn data_source(self) -> GnssDataSource {
        match ((self.0 >> 8) & 7) as u8 {
            0 => GnssDataSource::Disabled,
            1 => GnssDataSource::InternalA,
            3 => GnssDataSource::External,
            v => GnssDataSource::Other(v),
        }
    }
    /// Used for the navigation solution, instantaneous (bit 11).
    pub fn used_for_nav_curr(self) -> bool {
        self.0 & 0x0800 != 0
    }
    /// This receiver's PPS was used for time (bit 12).
    pub fn pps_used_for_time(self) -> bool {
        self.0 & 0x1000 != 0
    }
}

impl Serialize for GnssStatus {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("GnssStatus", 9)?;
        st.serialize_field("raw", &self.0)?;
        st.serialize_field("enabled", &self.enabled())?;
        st.serialize_field("operational", &self.operational())?;
        st.serialize_field("fix", &self.fix())?;
        st.serialize_field("antenna_signal_error", &self.antenna_signal_error())?;
        st.serialize_field("used_for_nav", &self.used_for_nav())?;
        st.serialize_field("data_source", &self.data_source())?;
        st.serialize_field("used_for_nav_curr", &self.used_for_nav_curr())?;
        st.serialize_field("pps_used_for_time", &self.pps_used_for_time())?;
        st.end()
    }
}

/// INS filter mode (Table 2.78).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub enum InsMode {
    /// Not operational; outputs invalid (attitude from the AHRS if aiding is on).
    NotTracking,
    /// Initialised: position and velocity valid, attitude not yet.
    Aligning,
    /// Tracking: attitude, position and velocity all valid.
    Tracking,
    /// Extended GNSS outage: attitude valid, position and velocity not.
    GnssLost,
}

/// InsStatus (Table 2.77): mode, GNSS fix and error flags. Bits 3, 7 and 8-15 are reserved and
/// kept in the raw word (bit 7 "may toggle during runtime": values such as 0x8085 are normal).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct InsStatus(pub u16);
raw_word!(InsStatus, u16);

impl InsStatus {
    /// Filter mode (bits 0-1).
    pub fn mode(self) -> InsMode {
        match self.0 & 3 {
            0 => InsMode::NotTracking,
            1 => InsMode::Aligning,
            2 => InsMode::Tracking,
            _ => InsMode::GnssLost,
        }
    }
    /// GNSS has a valid fix (bit 2).
    pub fn gnss_fix(self) -> bool {
        self.0 & 4 != 0
    }
    /// Gyro or accelerometer error (bit 4).
    pub fn imu_error(self) -> bool {
        self.0 & 0x10 != 0
    }
    /// Magnetometer or pressure error (bit 5).
    pub fn mag_pres_error(self) -> bool {
        self.0 & 0x20 != 0
    }
    /// GNSS communication error or no valid PPS (bit 6).
    pub fn gnss_error(self) -> bool {
        self.0 & 0x40 != 0
    }
    /// Whether attitude outputs are valid (modes Tracking and GnssLost).
    pub fn attitude_valid(self) -> bool {
        matches!(self.mode(), InsMode::Tracking | InsMode::GnssLost)
    }
    /// Whether position and velocity outputs are valid (modes Aligning and Tracking).
    pub fn position_valid(self) -> bool {
        matches!(self.mode(), InsMode::Aligning | InsMode::Tracking)
    }
}

impl Serialize for InsStatus {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut st = s.serialize_struct("InsStatus", 6)?;
        st.serialize_field("raw", &self.0)?;
        st.serialize_field("mode", &self.mode())?;
        st.serialize_field("gnss_fix", &self.gnss_fix())?;
        st.serialize_field("imu_error", &self.imu_error())?;
        st.serialize_field("mag_pres_error", &self.mag_pres_error())?;
        st.serialize_field("gnss_error", &self.gnss_error())?;
        st.end()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ins_status_with_reserved_bits_is_kept_and_read() {
        // 0x8085 = 1000 0000 1000 0101: mode 1 (Aligning), GnssFix (bit 2), Resv2 (bit 7) and
        // bit 15 reserved.
        let s = InsStatus(0x8085);
        assert_eq!(s.mode(), InsMode::Aligning);
        assert!(s.gnss_fix());
        assert!(!s.imu_error() && !s.mag_pres_error() && !s.gnss_error());
        let mut out = Vec::new();
        s.write(&mut out);
        assert_eq!(out, [0x85, 0x80], "raw word kept, reserved bits included");
        // 0x0072: mode 2 Tracking, ImuErr, MagPresErr, GnssErr.
        let t = InsStatus(0x0072);
        assert_eq!(t.mode(), InsMode::Tracking);
        assert!(t.imu_error() && t.mag_pres_error() && t.gnss_error() && !t.gnss_fix());
        assert!(t.attitude_valid() && t.position_valid());
        assert!(InsStatus(3).attitude_valid() && !InsStatus(3).position_valid());
    }

    #[test]
    fn imu_status_fields() {
        // gyro=Failed(3), accel=Saturated(2), mag=NominalNotUpdated(1), prestemp=Nominal(0):
        // 00 01 10 11 = 0x1B, plus reserved 0xFF00.
        let s = ImuStatus(0xFF1B);
        assert_eq!(s.gyro(), SensorState::Failed);
        assert_eq!(s.accel(), SensorState::Saturated);
        assert_eq!(s.mag(), SensorState::NominalNotUpdated);
        assert_eq!(s.pres_temp(), SensorState::NominalUpdated);
    }

    #[test]
    fn status_words_with_the_other_bits_set() {
        // The complements of the words above, so that every documented flag is seen both set and
        // clear. TimeStatus 0b010: date valid only (Table 2.15).
        let t = TimeStatus(0b010);
        assert!(!t.tow_valid() && t.date_valid() && !t.utc_valid());
        // GnssStatus 0x030C: fix (bit 2) and antenna error (bit 3), DataSource 3 = external
        // (Table 2.62), nothing else.
        let g = GnssStatus(0x030C);
        assert!(!g.enabled() && !g.operational() && g.fix() && g.antenna_signal_error());
        assert!(!g.used_for_nav() && !g.used_for_nav_curr() && !g.pps_used_for_time());
        assert_eq!(g.data_source(), GnssDataSource::External);
        // DataSource 2 is not in Table 2.62: kept as Other(2); bits 8-10 all set: Other(7).
        assert_eq!(GnssStatus(0x0200).data_source(), GnssDataSource::Other(2));
        assert_eq!(GnssStatus(0x0700).data_source(), GnssDataSource::Other(7));
        // ImuStatus: pres/temp Failed (3), mag Saturated (2), accel NominalNotUpdated (1), gyro
        // NominalUpdated (0): 11 10 01 00 = 0xE4.
        let s = ImuStatus(0x00E4);
        assert_eq!(s.gyro(), SensorState::NominalUpdated);
        assert_eq!(s.accel(), SensorState::NominalNotUpdated);
        assert_eq!(s.mag(), SensorState::Saturated);
        assert_eq!(s.pres_temp(), SensorState::Failed);
        // SensSat bits 10-15 are undocumented: never reported as a saturated sensor.
        let u = SensSat(0xFC00);
        assert!((0..16).all(|b| !u.saturated(b)) && !u.any());
        assert!(SensSat(0x0200).any() && SensSat(0x0001).any());
        // InsStatus (Table 2.78): attitude is valid only in Tracking and GnssLost, position and
        // velocity only in Aligning and Tracking.
        let valid = |mode: u16| {
            let s = InsStatus(mode);
            (s.attitude_valid(), s.position_valid())
        };
        assert_eq!(valid(0), (false, false), "NotTracking");
        assert_eq!(valid(1), (false, true), "Aligning");
        assert_eq!(valid(2), (true, true), "Tracking");
        assert_eq!(valid(3), (true, false), "GnssLost");
        assert_eq!(InsStatus(0).mode(), InsMode::NotTracking);
        assert_eq!(InsStatus(3).mode(), InsMode::GnssLost);
    }

    #[test]
    fn gnss_time_sens_sat_fields() {
        // 0x1913 = bits 0,1,4 set; DataSource (8-10) = 1; bit 11 and 12 set.
        let g = GnssStatus(0x1913);
        assert!(g.enabled() && g.operational() && !g.fix() && !g.antenna_signal_error());
        assert!(g.used_for_nav() && g.used_for_nav_curr() && g.pps_used_for_time());
        assert_eq!(g.data_source(), GnssDataSource::InternalA);
        assert_eq!(GnssStatus(0x0300).data_source(), GnssDataSource::External);
        let t = TimeStatus(0b101);
        assert!(t.tow_valid() && !t.date_valid() && t.utc_valid());
        let s = SensSat(0b10_0000_1001 | 0x8000);
        assert!(s.saturated(0) && s.saturated(3) && s.saturated(9) && !s.saturated(1));
        assert!(s.any() && !SensSat(0x8000).any());
        let json = serde_json::to_value(s).unwrap();
        assert_eq!(
            json["saturated"],
            serde_json::json!(["mag_x", "accel_x", "pres"])
        );
    }
}
