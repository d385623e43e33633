//! Compact Position Reporting (DO-260B Appendix A, A.1.7): the number of longitude zones,
//! global decoding of an even/odd pair, local decoding against a reference, and encoding.
//!
//! A CPR frame carries 17-bit fractions of a latitude zone and of a longitude zone. Even frames
//! (format i = 0) use 60 latitude zones, odd frames (i = 1) 59. Airborne zones span 360 deg,
//! surface zones 90 deg (four times the resolution, same 17 bits).
//!
//! Checks (a wrong position is worse than none):
//! - global: both frames must be of the same kind (the caller keeps airborne and surface apart)
//!   and received within 10 s (the caller checks the time); the two latitudes must lie in the same
//!   longitude-zone count NL, else the aircraft crossed a zone boundary between the frames and the
//!   pair is rejected ([`CprError::ZoneMismatch`]); a latitude beyond +-90 deg is rejected.
//! - local: the reference must be within half a zone of the target (the caller's job: the last
//!   good position of the same aircraft, or the receiver for surface targets).

/// 2^17, the CPR fraction denominator.
const CPR_MAX: f64 = 131_072.0;

/// Latitudes (deg) where NL drops by one: NL = 59 below the first, 58 from the first to the
/// second, ..., 2 from the last entry up to 87 deg; NL = 1 above 87 deg. Computed from the
/// DO-260B closed form NL(lat) = floor(2 pi / acos(1 - (1 - cos(pi / 30)) / cos^2(lat))); the
/// test `table_matches_closed_form` recomputes them.
static NL_TRANSITIONS: [f64; 57] = [
    10.470471299968,
    14.828174368687,
    18.186263570713,
    21.029394926028,
    23.545044865571,
    25.829247070588,
    27.938987101219,
    29.911356857318,
    31.772097076811,
    33.539934362985,
    35.228995977964,
    36.850251075935,
    38.412418924123,
    39.922566843339,
    41.386518322602,
    42.809140122436,
    44.194549514193,
    45.546267226602,
    46.867332524987,
    48.160391280966,
    49.427764392557,
    50.671501655538,
    51.893424691688,
    53.095161527960,
    54.278174722729,
    55.443784444950,
    56.593187562059,
    57.727473538661,
    58.847637761485,
    59.954592766940,
    61.049177742464,
    62.132166592103,
    63.204274793819,
    64.266165225674,
    65.318453096821,
    66.361710083826,
    67.396467740847,
    68.423220220833,
    69.442426311440,
    70.454510749876,
    71.459864730290,
    72.458845447289,
    73.451774416679,
    74.438934157251,
    75.420562566534,
    76.396843907945,
    77.367894613282,
    78.333740829227,
    79.294282254569,
    80.249232132805,
    81.198013492719,
    82.139569805106,
    83.071994447198,
    83.991735629806,
    84.891661907021,
    85.755416209444,
    86.535369975121,
];

/// Number of longitude zones at latitude `lat_deg` (1..=59). NaN gives 1.
#[inline]
pub fn nl(lat_deg: f64) -> u32 {
    let a = lat_deg.abs();
    if a > 87.0 || a.is_nan() {
        return 1;
    }
    59 - NL_TRANSITIONS.partition_point(|&t| t <= a) as u32
}

/// Positive modulo (the "MOD" of DO-260B: always in `[0, y)`).
#[inline]
fn modp(x: f64, y: f64) -> f64 {
    x - y * (x / y).floor()
}

/// The position-relevant part of a CPR frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct CprFrame {
    /// Format: false = even (i = 0), true = odd (i = 1).
    pub odd: bool,
    /// 17-bit encoded latitude.
    pub lat: u32,
    /// 17-bit encoded longitude.
    pub lon: u32,
}

impl CprFrame {
    /// The CPR fields of a position ME field (airborne and surface share the layout): F at ME
    /// bit 22, 17-bit latitude at 23-39, 17-bit longitude at 40-56 (1-based, as [`crate::modes::bits`] numbers them).
    pub fn from_me(me: u64) -> Self {
        Self {
            odd: crate::modes::bits(me, 22, 1) == 1,
            lat: crate::modes::bits(me, 23, 17) as u32,
            lon: crate::modes::bits(me, 40, 17) as u32,
        }
    }
}

/// Why a CPR decode gave no position.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum CprError {
    /// The even and odd latitudes fall in different NL zones.
    #[error("cpr pair straddles a longitude-zone boundary")]
    ZoneMismatch,
    /// The decoded latitude is outside +-90 deg (corrupt or mismatched pair).
    #[error("cpr latitude out of range")]
    LatitudeOutOfRange,
    /// Both frames have the same format.
    #[error("cpr pair has two frames of the same format")]
    SameFormat,
}

/// Zone span: 360 deg airborne, 90 deg surface.
#[inline]
fn span(surface: bool) -> f64 {
    if surface { 90.0 } else { 360.0 }
}

/// The two latitudes of a pair (even, odd), in `[-90, 90]` for airborne frames; in `[0, 90)`
/// for surface frames (the hemisphere is resolved by the caller).
fn pair_latitudes(even: CprFrame, odd: CprFrame, surface: bool) -> (f64, f64) {
    let s = span(surface);
    let (lat0, lat1) = (f64::from(even.lat) / CPR_MAX, f64::from(odd.lat) / CPR_MAX);
    let j = (59.0 * lat0 - 60.0 * lat1 + 0.5).floor();
    let mut r0 = s / 60.0 * (modp(j, 60.0) + lat0);
    let mut r1 = s / 59.0 * (modp(j, 59.0) + lat1);
    if !surface {
        if r0 >= 270.0 {
            r0 -= 360.0;
        }
        if r1 >= 270.0 {
            r1 -= 360.0;
        }
    }
    (r0, r1)
}

/// Longitude of a pair given the decoded latitude of the newest frame, in `[0, span)`.
fn pair_longitude(
    even: CprFrame,
    odd: CprFrame,
    newest_odd: bool,
    rlat: f64,
    surface: bool,
) -> f64 {
    let (lon0, lon1) = (f64::from(even.lon) / CPR_MAX, f64::from(odd.lon) / CPR_MAX);
    let nl_lat = f64::from(nl(rlat));
    let i = if newest_odd { 1.0 } else { 0.0 };
    let ni = (nl_lat - i).max(1.0);
    let m = (lon0 * (nl_lat - 1.0) - lon1 * nl_lat + 0.5).floor();
    let lon_i = if newest_odd { lon1 } else { lon0 };
    span(surface) / ni * (modp(m, ni) + lon_i)
}

/// Global airborne decoding of an even/odd pair; the position is that of the newest frame
/// (`newest_odd` says which). Returns (lat_deg, lon_deg), lon in `[-180, 180)`.
pub fn global_airborne(
    even: CprFrame,
    odd: CprFrame,
    newest_odd: bool,
) -> Result<(f64, f64), CprError> {
    if even.odd || !odd.odd {
        return Err(CprError::SameFormat);
    }
    let (r0, r1) = pair_latitudes(even, odd, false);
    if !(-90.0..=90.0).contains(&r0) || !(-90.0..=90.0).contains(&r1) {
        return Err(CprError::LatitudeOutOfRange);
    }
    if nl(r0) != nl(r1) {
        return Err(CprError::ZoneMismatch);
    }
    let rlat = if newest_odd { r1 } else { r0 };
    let mut rlon = pair_longitude(even, odd, newest_odd, rlat, false);
    if rlon >= 180.0 {
        rlon -= 360.0;
    }
    Ok((rlat, rlon))
}

/// Global surface decoding of an even/odd pair. A surface pair fixes the position only modulo
/// 90 deg: the receiver's position (`ref_lat_deg`, `ref_lon_deg`) picks the hemisphere and the
/// longitude quadrant nearest to it.
pub fn global_surface(
    even: CprFrame,
    odd: CprFrame,
    newest_odd: bool,
    ref_lat_deg: f64,
    ref_lon_deg: f64,
) -> Result<(f64, f64), CprError> {
    if even.odd || !odd.odd {
        return Err(CprError::SameFormat);
    }
    let (mut r0, mut r1) = pair_latitudes(even, odd, true);
    // Northern solution in [0, 90); the southern one is 90 deg less.
    if (r0 - 90.0 - ref_lat_deg).abs() < (r0 - ref_lat_deg).abs() {
        r0 -= 90.0;
        r1 -= 90.0;
    }
    if nl(r0) != nl(r1) {
        return Err(CprError::ZoneMismatch);
    }
    let rlat = if newest_odd { r1 } else { r0 };
    let base = pair_longitude(even, odd, newest_odd, rlat, true);
    Ok((rlat, nearest_quadrant(base, ref_lon_deg)))
}

/// The longitude among `base + k * 90 deg` nearest to `ref_lon_deg`, in `[-180, 180)`.
fn nearest_quadrant(base: f64, ref_lon_deg: f64) -> f64 {
    let mut best = base;
    let mut best_d = f64::INFINITY;
    for k in 0..4 {
        let cand = modp(base + 90.0 * f64::from(k) + 180.0, 360.0) - 180.0;
        let d = modp(cand - ref_lon_deg + 180.0, 360.0) - 180.0;
        if d.abs() < best_d {
            best_d = d.abs();
            best = cand;
        }
    }
    best
}

/// Local decoding of one frame against a reference position within half a zone of the target
/// (about 180 NM airborne, 45 NM surface). Returns (lat_deg, lon_deg), lon in `[-180, 180)`.
pub fn local(
    frame: CprFrame,
    surface: bool,
    ref_lat_deg: f64,
    ref_lon_deg: f64,
) -> Result<(f64, f64), CprError> {
    let s = span(surface);
    let i = if frame.odd { 1.0 } else { 0.0 };
    let (lat_c, lon_c) = (
        f64::from(frame.lat) / CPR_MAX,
        f64::from(frame.lon) / CPR_MAX,
    );
    let dlat = s / (60.0 - i);
    let j = (ref_lat_deg / dlat).floor() + (0.5 + modp(ref_lat_deg, dlat) / dlat - lat_c).floor();
    let rlat = dlat * (j + lat_c);
    if !(-90.0..=90.0).contains(&rlat) {
        return Err(CprError::LatitudeOutOfRange);
    }
    let ni = (f64::from(nl(rlat)) - i).max(1.0);
    let dlon = s / ni;
    let m = (ref_lon_deg / dlon).floor() + (0.5 + modp(ref_lon_deg, dlon) / dlon - lon_c).floor();
    let rlon = dlon * (m + lon_c);
    Ok((rlat, modp(rlon + 180.0, 360.0) - 180.0))
}

/// Encodes a position as a CPR frame of the given format and kind (DO-260B A.1.7.5).
pub fn encode(lat_deg: f64, lon_deg: f64, odd: bool, surface: bool) -> CprFrame {
    let s = span(surface);
    let i = if odd { 1.0 } else { 0.0 };
    let dlat = s / (60.0 - i);
    let yz = (CPR_MAX * modp(lat_deg, dlat) / dlat + 0.5).floor();
    let rlat = dlat * (yz / CPR_MAX + (lat_deg / dlat).floor());
    let ni = (f64::from(nl(rlat)) - i).max(1.0);
    let dlon = s / ni;
    let xz = (CPR_MAX * modp(lon_deg, dlon) / dlon + 0.5).floor();
    CprFrame {
        odd,
        lat: (yz as u32) & 0x1FFFF,
        lon: (xz as u32) & 0x1FFFF,
    }
}

#[cfg(test)]
#[path = "cpr_tests.rs"]
mod tests;
