//! ASTERIX CAT021 edition 2.1, ADS-B target reports (EUROCONTROL-SPEC-0149-12 ed 2.1; manual
//! 7.2.1 "ADS-B ASTERIX protocol" and 8.2.1 "FLARM ASTERIX protocol").
//!
//! [`uap`] gives every item's length rule so that any record is walked exactly; the items a
//! traffic picture needs are decoded into [`Cat021Record`] by the item-group modules
//! [`identity`], [`status`], [`time`], [`kinematics`] and [`reserved`] (the RE field); the rest
//! (I021/230, 220, 146, 148, 110, 271, 250, 260, 400, 295, SP) are skipped and listed in
//! [`Cat021Record::undecoded`]. [`traffic`] maps a record to the common traffic report.
//!
//! A record must carry I021/010 (mandatory in the standard); the block decoder relies on it to
//! reject false synchronisation.

pub mod identity;
pub mod kinematics;
pub mod reserved;
pub mod status;
pub mod time;
pub mod traffic;
pub mod uap;

#[cfg(test)]
pub(crate) mod tests;

use serde::Serialize;

use super::common::{DataSource, decode_tod, encode_tod};
use super::item::{ItemError, fspec_len, item_len, push_fspec, set_bits};
use identity::{MopsVersion, OperationalStatus};
use kinematics::{AirSpeed, GroundVector, Position, TrueAirspeed, VerticalRate};
use reserved::ReservedExpansion;
use status::{QualityIndicators, TargetReportDescriptor, TargetStatus};
use time::HighPrecisionTime;

/// ASTERIX category number.
pub const CAT: u8 = 21;

/// One CAT021 record: every decoded item, `None` when absent.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Cat021Record {
    /// I021/010 Data Source Identification (SAC 0 / SIC 161 marks FLARM targets).
    pub data_source: Option<DataSource>,
    /// I021/040 Target Report Descriptor.
    pub descriptor: Option<TargetReportDescriptor>,
    /// I021/161 Track Number.
    pub track_number: Option<u16>,
    /// I021/015 Service Identification.
    pub service_id: Option<u8>,
    /// I021/071 Time of Applicability for Position, s since midnight UTC.
    pub time_applicability_position_s: Option<f64>,
    /// I021/130 Position in WGS-84 co-ordinates.
    pub position: Option<Position>,
    /// I021/131 High-resolution position in WGS-84 co-ordinates.
    pub position_high_res: Option<Position>,
    /// I021/072 Time of Applicability for Velocity, s since midnight UTC.
    pub time_applicability_velocity_s: Option<f64>,
    /// I021/150 Air Speed.
    pub air_speed: Option<AirSpeed>,
    /// I021/151 True Airspeed.
    pub true_airspeed: Option<TrueAirspeed>,
    /// I021/080 Target Address, 24 bits.
    pub target_address: Option<u32>,
    /// I021/073 Time of Message Reception for Position, s since midnight UTC.
    pub time_reception_position_s: Option<f64>,
    /// I021/074 Time of Message Reception of Position, high precision.
    pub time_reception_position_hp: Option<HighPrecisionTime>,
    /// I021/075 Time of Message Reception for Velocity, s since midnight UTC.
    pub time_reception_velocity_s: Option<f64>,
    /// I021/076 Time of Message Reception of Velocity, high precision.
    pub time_reception_velocity_hp: Option<HighPrecisionTime>,
    /// I021/140 Geometric Height, ft.
    pub geometric_height_ft: Option<f64>,
    /// I021/090 Quality Indicators.
    pub quality: Option<QualityIndicators>,
    /// I021/210 MOPS Version.
    pub mops: Option<MopsVersion>,
    /// I021/070 Mode 3/A code, four octal digits in decimal form.
    pub mode3a: Option<u16>,
    /// I021/145 Flight Level, FL (hundreds of ft, pressure altitude).
    pub flight_level: Option<f64>,
    /// I021/152 Magnetic Heading, degrees.
    pub magnetic_heading_deg: Option<f64>,
    /// I021/200 Target Status.
    pub target_status: Option<TargetStatus>,
    /// I021/155 Barometric Vertical Rate.
    pub baro_vertical_rate: Option<VerticalRate>,
    /// I021/157 Geometric Vertical Rate.
    pub geo_vertical_rate: Option<VerticalRate>,
    /// I021/160 Airborne Ground Vector.
    pub ground_vector: Option<GroundVector>,
    /// I021/165 Track Angle Rate, deg/s.
    pub track_angle_rate_dps: Option<f64>,
    /// I021/077 Time of ASTERIX Report Transmission, s since midnight UTC.
    pub time_report_transmission_s: Option<f64>,
    /// I021/170 Target Identification (call sign), trailing spaces removed.
    pub target_id: Option<String>,
    /// I021/020 Emitter Category, raw ECAT (see [`traffic::emitter_category`]).
    pub emitter_category: Option<u8>,
    /// I021/016 Service Management: report period, s (LSB 0.5 s).
    pub report_period_s: Option<f64>,
    /// I021/008 Aircraft Operational Status.
    pub operational_status: Option<OperationalStatus>,
    /// I021/132 Message Amplitude, dBm.
    pub amplitude_dbm: Option<i8>,
    /// I021/RE Reserved Expansion Field content, when it decodes (see [`reserved`]); the field
    /// is also listed in `undecoded` when it does not.
    pub reserved: Option<ReservedExpansion>,
    /// Items present in the record that are skipped, not decoded (by UAP name).
    pub undecoded: Vec<&'static str>,
}

/// Decodes one record from the start of `b`; returns it and its length in octets.
pub fn decode_record(b: &[u8]) -> Result<(Cat021Record, usize), ItemError> {
    let fl = fspec_len(b).ok_or(ItemError::Truncated("fspec"))?;
    let mut pos = fl;
    let mut r = Cat021Record::default();
    for index in set_bits(&b[..fl]) {
        let (name, rule) = uap::UAP
            .get(index)
            .copied()
            .flatten()
            .ok_or(ItemError::UndefinedFrn(index + 1))?;
        let rest = b.get(pos..).unwrap_or(&[]);
        let len = item_len(rule, rest, name)?;
        let item = &rest[..len];
        r.set_item(index, name, item)?;
        pos += len;
    }
    if r.data_source.is_none() {
        return Err(ItemError::Malformed("I021/010 missing"));
    }
    Ok((r, pos))
}

impl Cat021Record {
    fn set_item(&mut self, index: usize, name: &'static str, b: &[u8]) -> Result<(), ItemError> {
        match index {
            0 => self.data_source = Some(DataSource::decode(b)?),
            1 => self.descriptor = Some(TargetReportDescriptor::decode(b)?),
            2 => self.track_number = Some(identity::decode_track_number(b)?),
            3 => self.service_id = Some(identity::decode_u8(b, name)?),
            4 => self.time_applicability_position_s = Some(decode_tod(b)?),
            5 => self.position = Some(Position::decode_low(b)?),
            6 => self.position_high_res = Some(Position::decode_high(b)?),
            7 => self.time_applicability_velocity_s = Some(decode_tod(b)?),
            8 => self.air_speed = Some(AirSpeed::decode(b)?),
            9 => self.true_airspeed = Some(TrueAirspeed::decode(b)?),
            10 => self.target_address = Some(identity::decode_address(b)?),
            11 => self.time_reception_position_s = Some(decode_tod(b)?),
            12 => self.time_reception_position_hp = Some(HighPrecisionTime::decode(b)?),
            13 => self.time_reception_velocity_s = Some(decode_tod(b)?),
            14 => self.time_reception_velocity_hp = Some(HighPrecisionTime::decode(b)?),
            15 => {
                self.geometric_height_ft =
                    Some(kinematics::decode_i16(b, kinematics::HEIGHT_LSB_FT, name)?)
            }
            16 => self.quality = Some(QualityIndicators::decode(b)?),
            17 => self.mops = Some(MopsVersion::decode(b)?),
            18 => self.mode3a = Some(identity::decode_mode3a(b)?),
            20 => self.flight_level = Some(kinematics::decode_i16(b, kinematics::FL_LSB, name)?),
            21 => self.magnetic_heading_deg = Some(kinematics::decode_angle(b, name)?),
            22 => self.target_status = Some(TargetStatus::decode(b)?),
            23 => self.baro_vertical_rate = Some(VerticalRate::decode(b, name)?),
            24 => self.geo_vertical_rate = Some(VerticalRate::decode(b, name)?),
            25 => self.ground_vector = Some(GroundVector::decode(b)?),
            26 => self.track_angle_rate_dps = Some(kinematics::decode_track_angle_rate(b)?),
            27 => self.time_report_transmission_s = Some(decode_tod(b)?),
            28 => self.target_id = Some(identity::decode_target_id(b)?),
            29 => self.emitter_category = Some(identity::decode_u8(b, name)?),
            34 => self.report_period_s = Some(f64::from(identity::decode_u8(b, name)?) * 0.5),
            35 => self.operational_status = Some(OperationalStatus::decode(b)?),
            37 => self.amplitude_dbm = Some(identity::decode_amplitude(b)?),
            47 => match ReservedExpansion::decode(b) {
                Some(re) => self.reserved = Some(re),
                None => self.undecoded.push(name),
            },
            _ => self.undecoded.push(name),
        }
        Ok(())
    }

    /// Appends the record (FSPEC and every decoded item present, in UAP order). Items listed in
    /// `undecoded` and the RE field are not reproduced.
    pub fn encode(&self, out: &mut Vec<u8>) {
        let mut items: Vec<(usize, Vec<u8>)> = Vec::new();
        let mut put = |index: usize, f: &dyn Fn(&mut Vec<u8>)| {
            let mut v = Vec::new();
            f(&mut v);
            items.push((index, v));
        };
        if let Some(x) = self.data_source {
            put(0, &|o| x.encode(o));
        }
        if let Some(x) = self.descriptor {
            put(1, &|o| x.encode(o));
        }
        if let Some(x) = self.track_number {
            put(2, &|o| identity::encode_track_number(x, o));
        }
        if let Some(x) = self.service_id {
            put(3, &|o| o.push(x));
        }
        if let Some(x) = self.time_applicability_position_s {
            put(4, &|o| encode_tod(x, o));
        }
        if let Some(x) = self.position {
            put(5, &|o| x.encode_low(o));
        }
        if let Some(x) = self.position_high_res {
            put(6, &|o| x.encode_high(o));
        }
        if let Some(x) = self.time_applicability_velocity_s {
            put(7, &|o| encode_tod(x, o));
        }
        if let Some(x) = self.air_speed {
            put(8, &|o| x.encode(o));
        }
        if let Some(x) = self.true_airspeed {
            put(9, &|o| x.encode(o));
        }
        if let Some(x) = self.target_address {
            put(10, &|o| identity::encode_address(x, o));
        }
        if let Some(x) = self.time_reception_position_s {
            put(11, &|o| encode_tod(x, o));
        }
        if let Some(x) = self.time_reception_position_hp {
            put(12, &|o| x.encode(o));
        }
        if let Some(x) = self.time_reception_velocity_s {
            put(13, &|o| encode_tod(x, o));
        }
        if let Some(x) = self.time_reception_velocity_hp {
            put(14, &|o| x.encode(o));
        }
        if let Some(x) = self.geometric_height_ft {
            put(15, &|o| {
                kinematics::encode_i16(x, kinematics::HEIGHT_LSB_FT, o)
            });
        }
        if let Some(x) = self.quality {
            put(16, &|o| x.encode(o));
        }
        if let Some(x) = self.mops {
            put(17, &|o| x.encode(o));
        }
        if let Some(x) = self.mode3a {
            put(18, &|o| identity::encode_mode3a(x, o));
        }
        if let Some(x) = self.flight_level {
            put(20, &|o| kinematics::encode_i16(x, kinematics::FL_LSB, o));
        }
        if let Some(x) = self.magnetic_heading_deg {
            put(21, &|o| kinematics::encode_angle(x, o));
        }
        if let Some(x) = self.target_status {
            put(22, &|o| x.encode(o));
        }
        if let Some(x) = self.baro_vertical_rate {
            put(23, &|o| x.encode(o));
        }
        if let Some(x) = self.geo_vertical_rate {
            put(24, &|o| x.encode(o));
        }
        if let Some(x) = self.ground_vector {
            put(25, &|o| x.encode(o));
        }
        if let Some(x) = self.track_angle_rate_dps {
            put(26, &|o| kinematics::encode_track_angle_rate(x, o));
        }
        if let Some(x) = self.time_report_transmission_s {
            put(27, &|o| encode_tod(x, o));
        }
        if let Some(x) = &self.target_id {
            put(28, &|o| identity::encode_target_id(x, o));
        }
        if let Some(x) = self.emitter_category {
            put(29, &|o| o.push(x));
        }
        if let Some(x) = self.report_period_s {
            put(34, &|o| o.push((x / 0.5).round().clamp(0.0, 255.0) as u8));
        }
        if let Some(x) = self.operational_status {
            put(35, &|o| x.encode(o));
        }
        if let Some(x) = self.amplitude_dbm {
            put(37, &|o| o.push(x as u8));
        }
        let indices: Vec<usize> = items.iter().map(|(i, _)| *i).collect();
        push_fspec(&indices, out);
        for (_, v) in items {
            out.extend_from_slice(&v);
        }
    }
}
