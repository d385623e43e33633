//! Encoders for the frames the simulator sends (DO-260B layouts as in the decoding modules):
//! DF17 identification, airborne position (CPR even/odd), airborne velocity (subtypes 1-4),
//! operational status (airborne), and DF11 all-call replies, each with its parity.
//! Every encoder refuses (returns `None`) values its field cannot carry rather than clamping.

use super::altitude::encode_ac12_q25;
use super::cpr;
use super::crc::set_parity;
use super::ident::Callsign;

/// A DF17 frame from CA, address and ME, with parity.
pub fn df17(ca: u8, icao: u32, me: u64) -> [u8; 14] {
    let mut f = [0u8; 14];
    f[0] = (17 << 3) | (ca & 7);
    f[1..4].copy_from_slice(&(icao & 0xFF_FFFF).to_be_bytes()[1..]);
    f[4..11].copy_from_slice(&(me & 0xFF_FFFF_FFFF_FFFF).to_be_bytes()[1..]);
    set_parity(&mut f, 0);
    f
}

/// A DF11 all-call reply; `ii` (0..=127) is the interrogator code overlaid on the parity.
pub fn df11(capability: u8, icao: u32, ii: u8) -> Option<[u8; 7]> {
    if ii > 127 {
        return None;
    }
    let mut f = [0u8; 7];
    f[0] = (11 << 3) | (capability & 7);
    f[1..4].copy_from_slice(&(icao & 0xFF_FFFF).to_be_bytes()[1..]);
    set_parity(&mut f, u32::from(ii));
    Some(f)
}

/// TC 1-4 identification: `typecode` 1..=4, `category` 0..=7, callsign of A-Z 0-9 space.
pub fn identification(icao: u32, typecode: u8, category: u8, callsign: &str) -> Option<[u8; 14]> {
    if !(1..=4).contains(&typecode) || category > 7 {
        return None;
    }
    let chars = Callsign::encode(callsign)?;
    let me = (u64::from(typecode) << 51) | (u64::from(category) << 48) | chars;
    Some(df17(5, icao, me))
}

/// Fields of an airborne position squitter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AirbornePositionFields {
    /// Type code 9..=18 or 20..=22.
    pub typecode: u8,
    /// Surveillance status 0..=3.
    pub surveillance_status: u8,
    /// NIC supplement-B.
    pub nic_b: bool,
    /// Altitude, ft (barometric for TC 9-18, GNSS height for 20-22); `None` = not available.
    pub altitude_ft: Option<i32>,
    /// Latitude, degrees.
    pub lat_deg: f64,
    /// Longitude, degrees.
    pub lon_deg: f64,
    /// Odd CPR format.
    pub odd: bool,
}

/// TC 9-18 / 20-22 airborne position, CPR encoded (altitude in 25 ft steps).
pub fn airborne_position(icao: u32, p: &AirbornePositionFields) -> Option<[u8; 14]> {
    if !matches!(p.typecode, 9..=18 | 20..=22)
        || p.surveillance_status > 3
        || !(-90.0..=90.0).contains(&p.lat_deg)
        || !p.lon_deg.is_finite()
    {
        return None;
    }
    let alt = match p.altitude_ft {
        Some(ft) => encode_ac12_q25(ft)?,
        None => 0,
    };
    let c = cpr::encode(p.lat_deg, p.lon_deg, p.odd, false);
    let me = (u64::from(p.typecode) << 51)
        | (u64::from(p.surveillance_status) << 49)
        | (u64::from(p.nic_b) << 48)
        | (u64::from(alt) << 36)
        | (u64::from(p.odd) << 34)
        | (u64::from(c.lat) << 17)
        | u64::from(c.lon);
    Some(df17(5, icao, me))
}

/// Vertical rate field (sign + 9 bits): `None` = not available.
fn vr_field(vr_fpm: Option<i32>) -> Option<u64> {
    match vr_fpm {
        None => Some(0),
        Some(v) => {
            let raw = (f64::from(v.unsigned_abs()) / 64.0).round() as u64 + 1;
            (raw <= 511).then_some((u64::from(v < 0) << 9) | raw)
        }
    }
}

/// TC 19 subtype 1/2 (ground speed) velocity. East/north components in kt (supersonic
/// subtype 2 is chosen when a component exceeds 1021 kt), vertical rate in ft/min; `baro_vr`
/// sets ME bit 36 (1 = barometric, as DO-260B reads it).
pub fn velocity_ground(
    icao: u32,
    v_east_kt: i32,
    v_north_kt: i32,
    vr_fpm: Option<i32>,
    baro_vr: bool,
    nac_v: u8,
) -> Option<[u8; 14]> {
    let max = v_east_kt.unsigned_abs().max(v_north_kt.unsigned_abs());
    let (subtype, scale) = if max <= 1021 { (1u64, 1u32) } else { (2, 4) };
    let comp = |v: i32| -> Option<u64> {
        let raw = (v.unsigned_abs() + scale / 2) / scale + 1;
        (raw <= 1023).then_some((u64::from(v < 0) << 10) | u64::from(raw))
    };
    if nac_v > 7 {
        return None;
    }
    let me = (19u64 << 51)
        | (subtype << 48)
        | (u64::from(nac_v) << 43)
        | (comp(v_east_kt)? << 32)
        | (comp(v_north_kt)? << 21)
        | (u64::from(baro_vr) << 20)
        | (vr_field(vr_fpm)? << 10);
    Some(df17(5, icao, me))
}

/// TC 19 subtype 3/4 (air speed) velocity: heading in degrees (`None` = not available),
/// air speed in kt (TAS when `tas`), vertical rate in ft/min.
pub fn velocity_air(
    icao: u32,
    heading_deg: Option<f64>,
    airspeed_kt: u32,
    tas: bool,
    vr_fpm: Option<i32>,
    baro_vr: bool,
) -> Option<[u8; 14]> {
    let (subtype, scale) = if airspeed_kt <= 1021 {
        (3u64, 1u32)
    } else {
        (4, 4)
    };
    let raw = (airspeed_kt + scale / 2) / scale + 1;
    if raw > 1023 {
        return None;
    }
    let hdg = match heading_deg {
        Some(h) if h.is_finite() => {
            (1u64 << 10) | ((h.rem_euclid(360.0) * 1024.0 / 360.0).round() as u64 & 0x3FF)
        }
        Some(_) => return None,
        None => 0,
    };
    let me = (19u64 << 51)
        | (subtype << 48)
        | (hdg << 32)
        | (u64::from(tas) << 31)
        | (u64::from(raw) << 21)
        | (u64::from(baro_vr) << 20)
        | (vr_field(vr_fpm)? << 10);
    Some(df17(5, icao, me))
}

/// Fields of an airborne operational status squitter (version 2 layout).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct OperationalStatusFields {
    /// ADS-B version 0..=2.
    pub version: u8,
    /// NIC supplement-A.
    pub nic_a: bool,
    /// NACp 0..=11.
    pub nac_p: u8,
    /// GVA 0..=3.
    pub gva: u8,
    /// SIL 0..=3.
    pub sil: u8,
    /// SIL per sample (else per hour).
    pub sil_per_sample: bool,
    /// NIC-baro.
    pub nic_baro: bool,
    /// Heading reference is magnetic north.
    pub hrd_magnetic: bool,
}

/// TC 31 subtype 0 (airborne) operational status.
pub fn operational_status(icao: u32, s: &OperationalStatusFields) -> Option<[u8; 14]> {
    if s.version > 2 || s.nac_p > 11 || s.gva > 3 || s.sil > 3 {
        return None;
    }
    let me = (31u64 << 51)
        | (u64::from(s.version) << 13)
        | (u64::from(s.nic_a) << 12)
        | (u64::from(s.nac_p) << 8)
        | (u64::from(s.gva) << 6)
        | (u64::from(s.sil) << 4)
        | (u64::from(s.nic_baro) << 3)
        | (u64::from(s.hrd_magnetic) << 2)
        | (u64::from(s.sil_per_sample) << 1);
    Some(df17(5, icao, me))
}

#[cfg(test)]
#[path = "encode_tests.rs"]
mod tests;
