//! Exact unit conversions (DOMAIN-NOTES: 1 ft = 0.3048 m, 1 NM = 1852 m, 1 kt = 1852/3600 m/s,
//! 1 ft/min = 0.00508 m/s). Inside vigil everything is SI; these are used at the edges.

/// Metres per foot.
pub const M_PER_FT: f64 = 0.3048;
/// Metres per nautical mile.
pub const M_PER_NM: f64 = 1852.0;
/// Metres per second per knot.
pub const MPS_PER_KT: f64 = 1852.0 / 3600.0;
/// Metres per second per foot per minute.
pub const MPS_PER_FPM: f64 = 0.00508;
