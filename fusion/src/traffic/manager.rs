//! The track manager.

use std::collections::HashMap;

use serde::Serialize;
use vigil_drivers::traffic::TrafficReport;

use super::alert_filter::AlertFilterParams;
use super::plausibility::{horizontal_distance_m, max_signal_dbm};
use super::track::{Fix, PlausibilityFlags, Source, TargetKey, Timed, Track, report_sigma_m};
use crate::geometry::wgs84::A_M;
use crate::geometry::{AircraftState, Geometry, IntruderEcef, OwnshipFrame};
use crate::ownship::Ownship;

/// Parameters of the traffic fusion, with units and defaults.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct TrafficParams {
    /// Most targets held.
    pub capacity: usize,
    /// Targets silent this long are dropped, s.
    pub timeout_s: f64,
    /// At a full table, a track older than this is evicted before any farther one, s.
    pub stale_evict_s: f64,
    /// Fastest plausible ground speed, m/s (350 m/s = 680 kt).
    pub max_speed_mps: f64,
    /// Fastest plausible vertical rate, m/s (60 m/s = 11 800 ft/min).
    pub max_vertical_rate_mps: f64,
    /// Highest transmitter EIRP considered (ADS-B class A3: 500 W = 57 dBm), dBm.
    pub max_eirp_dbm: f64,
    /// Margin above the free-space maximum before a signal is implausible, dB.
    pub signal_margin_db: f64,
    /// Sources disagree when their positions differ by more than this many combined sigmas (plus
    /// the distance the target can fly between the two reports).
    pub consistency_sigmas: f64,
    /// How long a plausibility finding stays active after it was last seen, s.
    pub flag_hold_s: f64,
    /// Live alert filter.
    pub alert: AlertFilterParams,
}

impl Default for TrafficParams {
    fn default() -> Self {
        Self {
            capacity: 1024,
            timeout_s: 20.0,
            stale_evict_s: 5.0,
            max_speed_mps: 350.0,
            max_vertical_rate_mps: 60.0,
            max_eirp_dbm: 57.0,
            signal_margin_db: 10.0,
            consistency_sigmas: 5.0,
            flag_hold_s: 60.0,
            alert: AlertFilterParams::default(),
        }
    }
}

/// Counters of the track manager.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct TrafficStats {
    /// Reports taken.
    pub reports: u64,
    /// Tracks created.
    pub tracks_created: u64,
    /// Tracks dropped after the timeout.
    pub tracks_timed_out: u64,
    /// Tracks evicted because the table was full.
    pub tracks_evicted: u64,
}

/// Which altitudes a target's vertical geometry compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AltitudeKind {
    /// Intruder barometric against ownship pressure altitude.
    Pressure,
    /// Intruder geometric against ownship geometric (the intruder has no barometric altitude).
    Geometric,
    /// No comparable pair: no vertical geometry.
    None,
}

/// One target of the traffic picture at a fusion time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Target {
    /// Merge key.
    pub key: TargetKey,
    /// Callsign.
    pub callsign: Option<String>,
    /// Sources that reported it, with their age at the fusion time, s.
    pub sources: Vec<(Source, f64)>,
    /// Age of the newest report, s.
    pub age_s: f64,
    /// Extrapolated latitude, deg.
    pub lat_deg: f64,
    /// Extrapolated longitude, deg.
    pub lon_deg: f64,
    /// Extrapolated altitude used, m.
    pub alt_m: Option<f64>,
    /// The intruder's velocity (north, east, down), m/s, from its reported track, ground speed
    /// and vertical rate (0 when none was reported); `None` without a reported velocity.
    pub velocity_ned_mps: Option<[f64; 3]>,
    /// Which altitudes were compared.
    pub altitude_kind: AltitudeKind,
    /// 1-sigma horizontal position uncertainty at the fusion time (grows with age), m.
    pub position_sigma_m: f64,
    /// Bearing from the ownship, deg true.
    pub bearing_true_deg: f64,
    /// Bearing relative to the ownship heading, deg, (-180, 180].
    pub bearing_relative_deg: f64,
    /// DO-365 geometry (None without a comparable altitude).
    pub geometry: Option<Geometry>,
    /// Raw alert level of this step.
    pub raw_alert_level: u8,
    /// Filtered alert level (M-of-N, persistence, hysteresis).
    pub alert_level: u8,
    /// FLARM alarm level carried through.
    pub flarm_alarm_level: Option<u8>,
    /// Active plausibility flags.
    pub flags: PlausibilityFlags,
    // --- issue 26 (traffic payload v2): the absolute state and accuracy consumers get ---
    /// What the reports say of the target beyond the geometry's inputs.
    pub reported: Reported,
}

/// A target's reported state and accuracy at the fusion time (issue 26): `None` where no report
/// of the track carried the quantity.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Reported {
    /// Pressure altitude (1013.25 hPa) extrapolated with the vertical rate, m.
    pub alt_pressure_m: Option<f64>,
    /// Geometric altitude extrapolated with the vertical rate, m.
    pub alt_geometric_m: Option<f64>,
    /// Reported vertical rate, m/s, up positive (the geometry uses 0 when none was reported).
    pub vertical_rate_mps: Option<f64>,
    /// Emitter category, DO-260B / GDL90 numbering (newest reported).
    pub emitter_category: Option<u8>,
    /// Navigation integrity category of the newest report carrying one.
    pub nic: Option<u8>,
    /// Navigation accuracy category for position of the newest report carrying one.
    pub nac_p: Option<u8>,
    /// Navigation accuracy category for velocity of the newest report carrying one.
    pub nac_v: Option<u8>,
    /// Source integrity level of the newest report carrying one.
    pub sil: Option<u8>,
    /// A source reported it as TIS-B (ground-radar rebroadcast), by its address type.
    pub tisb: bool,
}

impl Reported {
    /// Collects the accuracy fields from the track's newest report per source.
    fn from_track(t: &Track, alt_pressure_m: Option<f64>, alt_geometric_m: Option<f64>) -> Self {
        use vigil_drivers::traffic::AddressType;
        let mut by_age: Vec<&Timed<(Source, TrafficReport)>> = t.sources.iter().collect();
        by_age.sort_by_key(|s| std::cmp::Reverse(s.t_gps_ns));
        let newest =
            |f: fn(&TrafficReport) -> Option<u8>| by_age.iter().find_map(|s| f(&s.value.1));
        Self {
            alt_pressure_m,
            alt_geometric_m,
            vertical_rate_mps: t.vertical_rate.map(|v| v.value),
            emitter_category: t.emitter_category,
            nic: newest(|r| r.nic),
            nac_p: newest(|r| r.nac_p),
            nac_v: newest(|r| r.nac_v),
            sil: newest(|r| r.sil),
            tisb: t.sources.iter().any(|s| {
                matches!(
                    s.value.1.address_type,
                    AddressType::TisbIcao | AddressType::TisbOther
                )
            }),
        }
    }
}

/// Merges traffic reports into tracks and computes the picture against the ownship.
#[derive(Debug, Clone)]
pub struct TrackManager {
    params: TrafficParams,
    tracks: HashMap<TargetKey, Track>,
    ownship: Option<Ownship>,
    stats: TrafficStats,
}

/// Moves a position by a velocity for `dt_s` on the ellipsoid's local radii (small steps).
fn extrapolate(lat_deg: f64, lon_deg: f64, track_deg: f64, gs_mps: f64, dt_s: f64) -> (f64, f64) {
    let (s, c) = track_deg.to_radians().sin_cos();
    let (north, east) = (gs_mps * c * dt_s, gs_mps * s * dt_s);
    let lat = lat_deg.to_radians();
    let e2 = crate::geometry::wgs84::E2;
    let w = (1.0 - e2 * lat.sin().powi(2)).sqrt();
    let m = A_M * (1.0 - e2) / (w * w * w);
    let n = A_M / w;
    let dlat = north / m;
    let dlon = east / (n * lat.cos().max(1e-9));
    (lat_deg + dlat.to_degrees(), lon_deg + dlon.to_degrees())
}

impl TrackManager {
    /// An empty picture.
    pub fn new(params: TrafficParams) -> Self {
        Self {
            params,
            tracks: HashMap::with_capacity(params.capacity),
            ownship: None,
            stats: TrafficStats::default(),
        }
    }

    /// Counters.
    pub fn stats(&self) -> &TrafficStats {
        &self.stats
    }

    /// Number of tracks held.
    pub fn len(&self) -> usize {
        self.tracks.len()
    }

    /// True when no track is held.
    pub fn is_empty(&self) -> bool {
        self.tracks.is_empty()
    }

    /// The track of a key.
    pub fn track(&self, key: &TargetKey) -> Option<&Track> {
        self.tracks.get(key)
    }

    /// Sets the latest ownship state (used for eviction by range and the signal test).
    pub fn set_ownship(&mut self, own: Ownship) {
        self.ownship = Some(own);
    }

    /// Takes one report whose GPS time (ns) is `t_gps_ns`.
    pub fn update(&mut self, t_gps_ns: i64, r: &TrafficReport) {
        self.stats.reports += 1;
        let key = TargetKey {
            space: r.address_type.into(),
            address: r.address & 0xFF_FFFF,
        };
        if !self.tracks.contains_key(&key) {
            if self.tracks.len() >= self.params.capacity.max(1) {
                self.evict(t_gps_ns);
            }
            self.tracks
                .insert(key, Track::new(key, r.address_type, t_gps_ns));
            self.stats.tracks_created += 1;
        }
        let p = self.params;
        let own = self.ownship;
        let Some(track) = self.tracks.get_mut(&key) else {
            return;
        };
        let source = Source {
            link: r.link,
            protocol: r.protocol,
        };
        check_and_merge(track, source, t_gps_ns, r, &p, own.as_ref());
    }

    fn evict(&mut self, t_ns: i64) {
        let stale_ns = (self.params.stale_evict_s * 1e9) as i64;
        let oldest = self
            .tracks
            .values()
            .min_by_key(|t| (t.last_update_ns, t.key))
            .map(|t| (t.key, t.last_update_ns));
        let victim = match oldest {
            Some((key, last)) if t_ns.saturating_sub(last) > stale_ns => Some(key),
            _ => {
                let own = self.ownship;
                self.tracks
                    .values()
                    .max_by(|a, b| {
                        let ra = range_to(own.as_ref(), a);
                        let rb = range_to(own.as_ref(), b);
                        ra.total_cmp(&rb)
                            .then(b.last_update_ns.cmp(&a.last_update_ns))
                            .then(a.key.cmp(&b.key))
                    })
                    .map(|t| t.key)
            }
        };
        if let Some(k) = victim {
            self.tracks.remove(&k);
            self.stats.tracks_evicted += 1;
        }
    }

    /// The traffic picture at GPS time `t_ns` against `own`: drops timed-out targets, extrapolates
    /// the rest, computes geometry and alert levels, and returns targets in priority order (alert
    /// level, then time to loss of well-clear, then range).
    pub fn picture(&mut self, t_ns: i64, own: &Ownship) -> Vec<Target> {
        self.ownship = Some(*own);
        let timeout_ns = (self.params.timeout_s * 1e9) as i64;
        let before = self.tracks.len();
        self.tracks
            .retain(|_, t| t_ns.saturating_sub(t.last_update_ns) <= timeout_ns);
        self.stats.tracks_timed_out += (before - self.tracks.len()) as u64;
        let hold_ns = (self.params.flag_hold_s * 1e9) as i64;
        let p = self.params;
        let frame_baro = own.alt_pressure_m.map(|a| OwnshipFrame::new(&own.state(a)));
        let frame_geo = own
            .alt_geometric_m
            .map(|a| OwnshipFrame::new(&own.state(a)));
        let mut out: Vec<Target> = Vec::with_capacity(self.tracks.len());
        for t in self.tracks.values_mut() {
            let Some(pos) = t.position else { continue };
            let dt_pos = t_ns.saturating_sub(pos.t_gps_ns) as f64 * 1e-9;
            let (track_deg, gs) = t.velocity.map_or((0.0, 0.0), |v| v.value);
            let (lat, lon) =
                extrapolate(pos.value.lat_deg, pos.value.lon_deg, track_deg, gs, dt_pos);
            let vs = t.vertical_rate.map_or(0.0, |v| v.value);
            let alt_at = |a: Option<Timed<f64>>| {
                a.map(|a| a.value + vs * t_ns.saturating_sub(a.t_gps_ns) as f64 * 1e-9)
            };
            let (alt_pressure, alt_geometric) = (alt_at(t.alt_pressure), alt_at(t.alt_geometric));
            let (kind, alt, frame) = match (
                alt_at(t.alt_pressure),
                frame_baro,
                alt_at(t.alt_geometric),
                frame_geo,
            ) {
                (Some(a), Some(f), _, _) => (AltitudeKind::Pressure, Some(a), Some(f)),
                // Baro missing on either side (the intruder sent none, or the ownship has no
                // BAHRS pressure altitude): geometric against geometric.
                (_, _, Some(a), Some(f)) => (AltitudeKind::Geometric, Some(a), Some(f)),
                _ => (AltitudeKind::None, None, None),
            };
            // Velocity uncertainty is not reported per target here; position uncertainty grows
            // with the age of the fix at 1 m/s/s of unknown acceleration (0.5 a t^2).
            let sigma = pos.value.sigma_m + 0.5 * dt_pos.abs().powi(2);
            let state = AircraftState {
                lat_deg: lat,
                lon_deg: lon,
                alt_m: alt.unwrap_or(0.0),
                track_deg,
                ground_speed_mps: gs,
                vertical_rate_mps: vs,
            };
            let intruder = IntruderEcef::new(&state);
            let any_frame = frame
                .or(frame_baro)
                .or(frame_geo)
                .unwrap_or_else(|| OwnshipFrame::new(&own.state(0.0)));
            let rel = any_frame.relative(&intruder);
            let bearing = rel.s.x.atan2(rel.s.y).to_degrees().rem_euclid(360.0);
            let geometry = frame.map(|_| rel.geometry());
            let raw = geometry.map_or(0, |g| g.alert_level);
            let filtered = t.alert.update(raw, t_ns, &p.alert);
            out.push(Target {
                key: t.key,
                callsign: t.callsign.clone(),
                sources: t
                    .sources
                    .iter()
                    .map(|s| (s.value.0, t_ns.saturating_sub(s.t_gps_ns) as f64 * 1e-9))
                    .collect(),
                age_s: t.age_s(t_ns),
                lat_deg: lat,
                lon_deg: lon,
                alt_m: alt,
                velocity_ned_mps: t.velocity.map(|_| {
                    let (s, c) = track_deg.to_radians().sin_cos();
                    [gs * c, gs * s, -vs]
                }),
                altitude_kind: kind,
                position_sigma_m: sigma,
                bearing_true_deg: bearing,
                bearing_relative_deg: crate::attitude::angles::wrap_pi(
                    (bearing - own.heading_deg).to_radians(),
                )
                .to_degrees(),
                geometry,
                raw_alert_level: raw,
                alert_level: filtered,
                flarm_alarm_level: t.flarm_alarm_level,
                flags: t.findings.active(t_ns, hold_ns),
                reported: Reported::from_track(t, alt_pressure, alt_geometric),
            });
        }
        out.sort_by(|a, b| {
            let tl = |x: &Target| {
                x.geometry
                    .and_then(|g| g.loss_of_well_clear_interval_s)
                    .map_or(f64::INFINITY, |iv| iv.0)
            };
            let r = |x: &Target| {
                x.geometry
                    .map_or(f64::INFINITY, |g| g.horizontal_distance_m)
            };
            b.alert_level
                .cmp(&a.alert_level)
                .then(tl(a).total_cmp(&tl(b)))
                .then(r(a).total_cmp(&r(b)))
                .then(a.key.cmp(&b.key))
        });
        out
    }
}

fn range_to(own: Option<&Ownship>, t: &Track) -> f64 {
    match (own, t.position) {
        (Some(o), Some(p)) => {
            horizontal_distance_m(o.lat_deg, o.lon_deg, p.value.lat_deg, p.value.lon_deg)
        }
        _ => f64::INFINITY,
    }
}

/// Runs the plausibility tests of a report against the track, then merges it.
fn check_and_merge(
    track: &mut Track,
    source: Source,
    t: i64,
    r: &TrafficReport,
    p: &TrafficParams,
    own: Option<&Ownship>,
) {
    let f = &mut track.findings;
    if r.ground_speed_mps.is_some_and(|v| v > p.max_speed_mps) {
        f.impossible_speed = Some(t);
    }
    if let (Some(lat), Some(lon)) = (r.lat_deg, r.lon_deg) {
        let sigma = report_sigma_m(r);
        if let Some(prev) = track.position {
            let dt = (t.saturating_sub(prev.t_gps_ns) as f64 * 1e-9).abs();
            let d = horizontal_distance_m(prev.value.lat_deg, prev.value.lon_deg, lat, lon);
            let allowed = p.max_speed_mps * dt
                + p.consistency_sigmas
                    * (sigma * sigma + prev.value.sigma_m * prev.value.sigma_m).sqrt();
            if d > allowed {
                if prev.value.source == source {
                    f.position_jump = Some(t);
                } else {
                    f.inconsistent_sources = Some(t);
                }
            }
        }
        if let (Some(o), Some(sig)) = (own, r.signal_dbm) {
            let range = horizontal_distance_m(o.lat_deg, o.lon_deg, lat, lon);
            if sig > max_signal_dbm(p.max_eirp_dbm, range) + p.signal_margin_db {
                f.range_vs_signal = Some(t);
            }
        }
        if track.position.is_none_or(|prev| t >= prev.t_gps_ns) {
            track.position = Some(Timed {
                t_gps_ns: t,
                value: Fix {
                    lat_deg: lat,
                    lon_deg: lon,
                    sigma_m: sigma,
                    source,
                },
            });
        }
    }
    for (new, slot) in [
        (r.alt_pressure_m, &mut track.alt_pressure),
        (r.alt_geometric_m, &mut track.alt_geometric),
    ] {
        if let Some(a) = new {
            if let Some(prev) = *slot {
                let dt = (t.saturating_sub(prev.t_gps_ns) as f64 * 1e-9).abs();
                // 50 m covers altitude quantisation (25/100 ft) and source differences.
                if (a - prev.value).abs() > p.max_vertical_rate_mps * dt + 50.0 {
                    track.findings.altitude_jump = Some(t);
                }
            }
            if slot.is_none_or(|prev| t >= prev.t_gps_ns) {
                *slot = Some(Timed {
                    t_gps_ns: t,
                    value: a,
                });
            }
        }
    }
    if let (Some(trk), Some(gs)) = (r.track_deg, r.ground_speed_mps)
        && track.velocity.is_none_or(|v| t >= v.t_gps_ns)
    {
        track.velocity = Some(Timed {
            t_gps_ns: t,
            value: (trk, gs),
        });
    }
    if let Some(vs) = r.vertical_rate_mps
        && track.vertical_rate.is_none_or(|v| t >= v.t_gps_ns)
    {
        track.vertical_rate = Some(Timed {
            t_gps_ns: t,
            value: vs,
        });
    }
    if r.callsign.is_some() {
        track.callsign.clone_from(&r.callsign);
    }
    track.emitter_category = r.emitter_category.or(track.emitter_category);
    track.squawk = r.squawk.or(track.squawk);
    track.signal_dbm = r.signal_dbm.or(track.signal_dbm);
    if r.flarm_alarm_level.is_some() {
        track.flarm_alarm_level = r.flarm_alarm_level;
    }
    track.address_type = r.address_type;
    track.last_update_ns = track.last_update_ns.max(t);
    match track.sources.iter_mut().find(|s| s.value.0 == source) {
        Some(s) if t >= s.t_gps_ns => {
            *s = Timed {
                t_gps_ns: t,
                value: (source, r.clone()),
            }
        }
        Some(_) => {}
        None => track.sources.push(Timed {
            t_gps_ns: t,
            value: (source, r.clone()),
        }),
    }
}

#[cfg(test)]
mod tests;
