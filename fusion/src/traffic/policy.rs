//! The fail-safe policy (issue 24): what the traffic geometry does with each unknown quantity,
//! applied here and nowhere else. The README's traffic section has the same table.
//!
//! | unknown | what vigil does | flag |
//! |---|---|---|
//! | ownship velocity (no track or ground speed) | geometry from the present relative position alone: range, bearing, violated now or not; time-based quantities `None`; alert level from the present separation only (3 inside the DWC volume now, 1 inside the preventive volume now, else 0) | `ownship_velocity_unknown` |
//! | ownship vertical rate | the vertical test covers every rate within `own_max_vertical_rate_mps` | `ownship_vertical_rate_unknown` |
//! | intruder altitude | taken as co-altitude (the horizontal geometry decides), level capped at [`MAX_LEVEL_ALTITUDE_UNKNOWN`] (2, corrective) | `altitude_unknown` |
//! | intruder velocity | not stationary: position-only geometry as for an unknown ownship velocity, with the distance it may have flown since its report taken off the range | `velocity_unknown` |
//! | intruder vertical rate | the vertical test covers every rate its emitter category allows ([`max_vertical_rate_mps`]) | `vertical_rate_unknown` |
//! | which altitude the other compares with (pressure against geometric, no measured difference) | the separation is a band: the vertical test holds if any separation in it would | `altitude_reference_mixed` |
//! | a report older than the per-link limit | no geometry, level 0, counted (`TrafficStats::stale_dropped`) | `stale` |
//!
//! Why the cap at 2 for an intruder without altitude: TCAS II gives traffic advisories but no
//! resolution advisories against intruders that do not report altitude, since an avoidance
//! manoeuvre needs the vertical geometry. The DO-365 warning (3) calls for an immediate
//! manoeuvre, so vigil stops at the corrective alert (2): the DAA stack is told to act, and by
//! `altitude_unknown` why the vertical picture is missing. Never below: the unknown altitude is
//! taken as co-altitude, so such a target reaches 2 wherever a co-altitude one would reach 2 or 3.
//!
//! Non-finite or physically impossible inputs (beyond [`MAX_RANGE_M`], [`MAX_SPEED_MPS`], ...)
//! are unknown here too, so no NaN or infinity enters the arithmetic and every output is finite
//! or `None`.

use nalgebra::Vector2;
use serde::Serialize;

use crate::geometry::Geometry;
use crate::geometry::daa::{Relative, Thresholds};

/// The highest alert level of an intruder whose altitude is unknown (corrective; see the module
/// doc on why not warning).
pub const MAX_LEVEL_ALTITUDE_UNKNOWN: u8 = 2;
/// Largest relative horizontal position taken as known, m (about half the earth's circumference).
pub const MAX_RANGE_M: f64 = 2.0e7;
/// Largest horizontal speed taken as known, m/s (about Mach 6: beyond any ADS-B encoding).
pub const MAX_SPEED_MPS: f64 = 2_200.0;
/// Largest altitude difference taken as known, m.
pub const MAX_DZ_M: f64 = 1.0e5;
/// Largest vertical rate taken as known, m/s.
pub const MAX_VERTICAL_RATE_MPS: f64 = 500.0;

/// Which fail-safe rules applied to a target (each names an unknown, see the module table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct FailSafeFlags {
    /// The ownship's horizontal velocity is unknown: position-only geometry.
    pub ownship_velocity_unknown: bool,
    /// The ownship's vertical rate is unknown: the vertical test covers its possible rates.
    pub ownship_vertical_rate_unknown: bool,
    /// The intruder's altitude is unknown (or not comparable): co-altitude, level capped at 2.
    pub altitude_unknown: bool,
    /// The intruder's horizontal velocity is unknown: position-only geometry.
    pub velocity_unknown: bool,
    /// The intruder's vertical rate is unknown: the vertical test covers its category's rates.
    pub vertical_rate_unknown: bool,
    /// Pressure compared with geometric altitude without a measured difference: a band.
    pub altitude_reference_mixed: bool,
    /// The newest position is older than the link's limit: no geometry.
    pub stale: bool,
    /// The report's time is its arrival (the protocol carries no time of applicability), with the
    /// larger uncertainty that brings.
    pub time_from_receipt: bool,
}

impl FailSafeFlags {
    /// True when any rule applied.
    pub fn any(&self) -> bool {
        self.ownship_velocity_unknown
            || self.ownship_vertical_rate_unknown
            || self.altitude_unknown
            || self.velocity_unknown
            || self.vertical_rate_unknown
            || self.altitude_reference_mixed
            || self.stale
            || self.time_from_receipt
    }
}

/// What is known of one encounter at the picture time, each quantity `None` when unknown.
/// Horizontal vectors are (east, north) in the ownship's tangent plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Encounter {
    /// Intruder position relative to the ownship, m (required: no position, no geometry).
    pub s_m: Vector2<f64>,
    /// Ownship horizontal velocity over ground, m/s.
    pub own_velocity_mps: Option<Vector2<f64>>,
    /// Ownship vertical rate, m/s up.
    pub own_vertical_rate_mps: Option<f64>,
    /// Largest climb or descent rate the ownship may have when its rate is unknown, m/s.
    pub own_max_vertical_rate_mps: f64,
    /// Intruder horizontal velocity over ground, m/s.
    pub intruder_velocity_mps: Option<Vector2<f64>>,
    /// Intruder altitude minus ownship altitude, m.
    pub dz_m: Option<f64>,
    /// Half-width of the band `dz_m` lies in when the altitudes are not like with like, m (0
    /// when comparable).
    pub dz_band_m: f64,
    /// Intruder vertical rate, m/s up.
    pub intruder_vertical_rate_mps: Option<f64>,
    /// Largest climb or descent rate the intruder's category allows, m/s.
    pub intruder_max_vertical_rate_mps: f64,
    /// Distance the intruder may have flown since its position report, m, taken off the range
    /// when its velocity is unknown (0 when known: the position is then extrapolated).
    pub position_margin_m: f64,
}

/// A quantity usable in the arithmetic: finite and within `limit` in magnitude.
fn usable(x: Option<f64>, limit: f64) -> Option<f64> {
    x.filter(|v| v.is_finite() && v.abs() <= limit)
}

fn usable_vec(v: Option<Vector2<f64>>, limit: f64) -> Option<Vector2<f64>> {
    v.filter(|v| v.x.is_finite() && v.y.is_finite() && v.norm() <= limit)
}

fn non_negative(x: f64, limit: f64) -> f64 {
    if x.is_finite() {
        x.clamp(0.0, limit)
    } else {
        limit
    }
}

/// The geometry of one encounter under the fail-safe policy, with the rules that applied;
/// `None` when the relative position itself is unusable (non-finite or beyond [`MAX_RANGE_M`]).
pub fn assess(e: &Encounter) -> Option<(Geometry, FailSafeFlags)> {
    let s = usable_vec(Some(e.s_m), MAX_RANGE_M)?;
    let own_v = usable_vec(e.own_velocity_mps, MAX_SPEED_MPS);
    let int_v = usable_vec(e.intruder_velocity_mps, MAX_SPEED_MPS);
    let dz = usable(e.dz_m, MAX_DZ_M);
    let own_vz = usable(e.own_vertical_rate_mps, MAX_VERTICAL_RATE_MPS);
    let int_vz = usable(e.intruder_vertical_rate_mps, MAX_VERTICAL_RATE_MPS);
    let own_vz_max = non_negative(e.own_max_vertical_rate_mps, MAX_VERTICAL_RATE_MPS);
    let int_vz_max = non_negative(e.intruder_max_vertical_rate_mps, MAX_VERTICAL_RATE_MPS);
    let dz_band = non_negative(e.dz_band_m, MAX_DZ_M);
    let margin = non_negative(e.position_margin_m, MAX_RANGE_M);
    let flags = FailSafeFlags {
        ownship_velocity_unknown: own_v.is_none(),
        ownship_vertical_rate_unknown: own_vz.is_none(),
        altitude_unknown: dz.is_none(),
        velocity_unknown: int_v.is_none(),
        vertical_rate_unknown: int_vz.is_none(),
        altitude_reference_mixed: dz.is_some() && dz_band > 0.0,
        ..FailSafeFlags::default()
    };
    // Vertical: an unknown altitude is co-altitude at all times (separation 0, rate 0, no band);
    // an unknown rate widens the rate band by what that aircraft may fly.
    let (dz_m, dz_spread_m, vz_mps, vz_spread_mps) = match dz {
        None => (0.0, 0.0, 0.0, 0.0),
        Some(dz) => (
            dz,
            dz_band,
            int_vz.unwrap_or(0.0) - own_vz.unwrap_or(0.0),
            if int_vz.is_none() { int_vz_max } else { 0.0 }
                + if own_vz.is_none() { own_vz_max } else { 0.0 },
        ),
    };
    let mut g = match (own_v, int_v) {
        (Some(o), Some(i)) => Relative {
            s,
            v: i - o,
            dz_m,
            dz_spread_m,
            vz_mps,
            vz_spread_mps,
        }
        .geometry(),
        _ => present_only(s, margin, dz_m, dz_spread_m),
    };
    if dz.is_none() {
        g.vertical_separation_m = None;
        g.alert_level = g.alert_level.min(MAX_LEVEL_ALTITUDE_UNKNOWN);
    }
    // Defence in depth: a quantity that came out non-finite (it cannot with the bounds above) is
    // reported unknown rather than passed on.
    g.tau_mod_s = g.tau_mod_s.filter(|t| t.is_finite());
    g.tcpa_s = g.tcpa_s.filter(|t| t.is_finite());
    g.hmd_m = g.hmd_m.filter(|t| t.is_finite());
    g.range_rate_mps = g.range_rate_mps.filter(|t| t.is_finite());
    g.loss_of_well_clear_interval_s = g
        .loss_of_well_clear_interval_s
        .filter(|iv| iv.0.is_finite() && iv.1.is_finite());
    Some((g, flags))
}

/// Position-only geometry: range, vertical separation, violated now or not, and the alert level
/// from the present separation (3 inside the DWC volume, 1 inside the preventive volume, else 0);
/// `margin_m` (the distance an intruder of unknown velocity may have flown) is taken off the
/// range for the tests.
fn present_only(s: Vector2<f64>, margin_m: f64, dz_m: f64, dz_spread_m: f64) -> Geometry {
    let r = s.norm();
    let near = (r - margin_m).max(0.0);
    let vertical = |th: &Thresholds| dz_m.abs() - dz_spread_m <= th.zthr_m;
    let dwc = near <= Thresholds::DWC.dthr_m && vertical(&Thresholds::DWC);
    let preventive = near <= Thresholds::PREVENTIVE.dthr_m && vertical(&Thresholds::PREVENTIVE);
    let level = if dwc {
        3
    } else if preventive {
        1
    } else {
        0
    };
    Geometry {
        horizontal_distance_m: r,
        vertical_separation_m: Some(dz_m),
        range_rate_mps: None,
        tcpa_s: None,
        hmd_m: None,
        tau_mod_s: None,
        well_clear_violated_now: dwc,
        loss_of_well_clear_interval_s: None,
        alert_level: level,
    }
}

/// Largest climb or descent rate an emitter category allows, m/s, for the vertical test of an
/// intruder whose vertical rate is unknown. Categories as in DO-260B / the TT-Multi-RF `ECAT`
/// table. Decision (no document gives rates per category): typical maxima with margin, and the
/// traffic picture's `fallback_mps` (the plausibility limit) where the category says nothing.
pub fn max_vertical_rate_mps(emitter_category: Option<u8>, fallback_mps: f64) -> f64 {
    const FPM: f64 = 0.00508;
    match emitter_category {
        // Light: 2000 ft/min.
        Some(1) => 2_000.0 * FPM,
        // Small, large, high-vortex, heavy: 6000 ft/min.
        Some(2..=5) => 6_000.0 * FPM,
        // Rotorcraft: 3000 ft/min.
        Some(7) => 3_000.0 * FPM,
        // Glider: 2000 ft/min (strong thermals, spiral dives).
        Some(9) => 2_000.0 * FPM,
        // Lighter than air: 1500 ft/min.
        Some(10) => 1_500.0 * FPM,
        // Ultralight, hang-glider, paraglider: 2000 ft/min.
        Some(12) => 2_000.0 * FPM,
        // UAV: 3000 ft/min.
        Some(14) => 3_000.0 * FPM,
        // Surface vehicles and obstacles: they do not climb; 500 ft/min covers a towed balloon.
        Some(17..=21) => 500.0 * FPM,
        // High performance (6), parachutist (11, free fall ~ 55 m/s), space, unknown: the limit.
        _ => fallback_mps,
    }
}

/// Largest ground speed an emitter category allows, m/s: how far an intruder of unknown velocity
/// may have flown since its report. Decision as for [`max_vertical_rate_mps`]: typical maxima
/// with margin, `fallback_mps` where the category says nothing.
pub fn max_speed_mps(emitter_category: Option<u8>, fallback_mps: f64) -> f64 {
    const KT: f64 = 1852.0 / 3600.0;
    match emitter_category {
        // Light: 250 kt.
        Some(1) => 250.0 * KT,
        // Rotorcraft: 180 kt.
        Some(7) => 180.0 * KT,
        // Glider: 160 kt.
        Some(9) => 160.0 * KT,
        // Lighter than air, ultralight, paraglider: 80 kt.
        Some(10 | 12) => 80.0 * KT,
        // UAV: 150 kt.
        Some(14) => 150.0 * KT,
        // Surface vehicles and obstacles: 80 kt.
        Some(17..=21) => 80.0 * KT,
        _ => fallback_mps,
    }
}

#[cfg(test)]
mod tests;
