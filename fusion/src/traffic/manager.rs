//! The track manager.

use std::collections::HashMap;

use serde::Serialize;
use vigil_drivers::traffic::{AddressType, TrafficReport};

use super::alert_filter::AlertFilterParams;
use super::plausibility::{horizontal_distance_m, max_signal_dbm};
use super::policy::{self, Encounter, FailSafeFlags};
use super::track::{Fix, PlausibilityFlags, Source, TargetKey, Timed, Track, report_sigma_m};
use crate::geometry::wgs84::dead_reckon as extrapolate;
use crate::geometry::{AircraftState, Geometry, IntruderEcef, OwnshipFrame};
use crate::ownship::Ownship;
use nalgebra::Vector2;

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
    /// A plausibility flag stays set until the target's reports have been consistent (no new
    /// finding) for this long, s. A silent target stays flagged: only consistent reports clear.
    pub flag_hold_s: f64,
    /// Live alert filter.
    pub alert: AlertFilterParams,
    // --- issue 24: fail-safe unknowns, report age, slow-drift plausibility ---
    /// Newest position older than this (per link: ADS-B 1090, UAT 978, FLARM) is dropped from the
    /// geometry and counted, s. Decision: 1090 and UAT targets report every second (the module's
    /// list), so 5 s is four missed reports; FLARM sends 1 Hz with short range, 3 s.
    pub stale_limit_s: [f64; 3],
    /// Largest ownship climb or descent rate assumed when its vertical rate is unknown, m/s
    /// (3000 ft/min: a small UAS's envelope with margin).
    pub own_max_vertical_rate_mps: f64,
    /// Window of the position-against-velocity consistency test, s.
    pub drift_window_s: f64,
    /// Allowance of that test for velocity error and rounding, m/s over the window.
    pub drift_velocity_error_mps: f64,
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
            stale_limit_s: [5.0, 5.0, 3.0],
            own_max_vertical_rate_mps: 3_000.0 * 0.00508,
            drift_window_s: 10.0,
            drift_velocity_error_mps: 2.0,
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
    // --- issue 24 ---
    /// Targets left out of the geometry because their newest position was older than the link's
    /// limit (counted once per target and picture).
    pub stale_dropped: u64,
}

/// Which altitudes a target's vertical geometry compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AltitudeKind {
    /// Intruder barometric against ownship pressure altitude.
    Pressure,
    /// Intruder geometric against ownship geometric (the intruder has no barometric altitude).
    Geometric,
    /// One pressure and one geometric altitude, with no measured difference between them: the
    /// separation is a band (issue 24, see [`super::policy`]).
    Mixed,
    /// No altitude to compare: the fail-safe policy takes the intruder as co-altitude.
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
    /// The intruder's horizontal velocity (north, east), m/s, from its reported track and ground
    /// speed; `None` without them.
    pub velocity_ne_mps: Option<[f64; 2]>,
    /// The intruder's vertical rate, m/s up; `None` when not reported.
    pub vertical_rate_mps: Option<f64>,
    /// Which altitudes were compared.
    pub altitude_kind: AltitudeKind,
    /// 1-sigma horizontal position uncertainty at the fusion time (grows with age), m.
    pub position_sigma_m: f64,
    /// Bearing from the ownship, deg true.
    pub bearing_true_deg: f64,
    /// Bearing relative to the ownship heading, deg, (-180, 180]; `None` when the heading is.
    pub bearing_relative_deg: Option<f64>,
    /// DO-365 geometry under the fail-safe policy; `None` only for a stale target (see
    /// `fail_safe`).
    pub geometry: Option<Geometry>,
    /// Raw alert level of this step.
    pub raw_alert_level: u8,
    /// Filtered alert level (M-of-N, persistence, hysteresis).
    pub alert_level: u8,
    /// FLARM alarm level carried through.
    pub flarm_alarm_level: Option<u8>,
    /// Active plausibility flags.
    pub flags: PlausibilityFlags,
    /// The fail-safe rules that applied (issue 24): which quantities were unknown.
    pub fail_safe: FailSafeFlags,
    /// The intruder's own state as reported (issue 26: what a DAA or a display needs beside the
    /// relative geometry).
    pub reported: Reported,
}

/// What the sources reported of a target, brought to the picture's time where it moves (each
/// `None` when no source gave it), for the consumers that need absolute state and its quality.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Reported {
    /// Pressure altitude (1013.25 hPa datum), m, moved on by the reported vertical rate.
    pub alt_pressure_m: Option<f64>,
    /// Geometric altitude as the track holds it (above the WGS-84 ellipsoid unless the protocol
    /// gave MSL), m, moved on by the reported vertical rate.
    pub alt_geometric_m: Option<f64>,
    /// Track over ground, deg true, [0, 360).
    pub track_deg: Option<f64>,
    /// Ground speed, m/s.
    pub ground_speed_mps: Option<f64>,
    /// Navigation integrity category (0..11) of the newest report that carried one.
    pub nic: Option<u8>,
    /// Navigation accuracy category for position (0..11), newest report that carried one.
    pub nac_p: Option<u8>,
    /// Navigation accuracy category for velocity (0..4), newest report that carried one.
    pub nac_v: Option<u8>,
    /// Emitter category (DO-260B / GDL90 set, 0 = no information given).
    pub emitter_category: Option<u8>,
    /// Where the reports came from.
    pub origins: Origins,
}

/// The links that heard a target directly, and whether a ground station relayed it, from the
/// newest report of each source (a track keeps one report per link and protocol: a TIS-B relay
/// on 1090 MHz replaces that source's direct report).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Origins {
    /// Heard on 1090 MHz from the aircraft itself (ADS-B, Mode S).
    pub adsb: bool,
    /// Heard on 978 MHz (UAT) from the aircraft itself.
    pub uat: bool,
    /// Heard by FLARM.
    pub flarm: bool,
    /// Relayed by a ground station (TIS-B or ADS-R): a report flagged relayed, or a TIS-B
    /// address.
    pub relayed: bool,
}

impl Origins {
    fn of(t: &Track) -> Self {
        use vigil_drivers::traffic::Link;
        t.sources.iter().fold(Self::default(), |mut o, s| {
            let r = &s.value.1;
            if r.flags.relayed
                || matches!(
                    r.address_type,
                    AddressType::TisbIcao | AddressType::TisbOther
                )
            {
                o.relayed = true;
            } else {
                match s.value.0.link {
                    Link::Adsb1090 => o.adsb = true,
                    Link::Uat978 => o.uat = true,
                    Link::Flarm => o.flarm = true,
                }
            }
            o
        })
    }
}

impl Reported {
    /// The reported state of track `t` at `t_ns`; `vs` is its vertical rate, m/s, if known.
    fn of(t: &Track, t_ns: i64, vs: Option<f64>) -> Self {
        let alt_at = |a: Option<Timed<f64>>| {
            a.map(|a| a.value + vs.unwrap_or(0.0) * t_ns.saturating_sub(a.t_gps_ns) as f64 * 1e-9)
        };
        // The newest report carrying a field gives it (sources are kept in arrival order per
        // source; the newest time wins across sources).
        let newest = |f: fn(&TrafficReport) -> Option<u8>| {
            t.sources
                .iter()
                .filter_map(|s| f(&s.value.1).map(|v| (s.t_gps_ns, v)))
                .max_by_key(|&(t, _)| t)
                .map(|(_, v)| v)
        };
        Self {
            alt_pressure_m: alt_at(t.alt_pressure),
            alt_geometric_m: alt_at(t.alt_geometric),
            track_deg: t.velocity.map(|v| v.value.0.rem_euclid(360.0)),
            ground_speed_mps: t.velocity.map(|v| v.value.1),
            nic: newest(|r| r.nic),
            nac_p: newest(|r| r.nac_p),
            nac_v: newest(|r| r.nac_v),
            emitter_category: t.emitter_category,
            origins: Origins::of(t),
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

    /// Takes one report whose GPS time (ns) is `t_gps_ns`: its time of applicability when the
    /// report carries one, else its arrival (then `r.source_time` is `None`, and the target says
    /// so). See [`TrackManager::update_at`].
    pub fn update(&mut self, t_gps_ns: i64, r: &TrafficReport) {
        self.update_at(t_gps_ns, r, r.source_time.is_none());
    }

    /// Takes one report whose data apply at GPS time `t_gps_ns` (ns); `from_receipt` says that
    /// time is only the arrival (issue 24: every report at its own time).
    pub fn update_at(&mut self, t_gps_ns: i64, r: &TrafficReport, from_receipt: bool) {
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
        if let Some(pos) = track.position.as_mut()
            && pos.t_gps_ns == t_gps_ns
            && pos.value.source == source
        {
            pos.value.time_from_receipt = from_receipt;
            // Decision: a time from the arrival (or MAVLink's whole-second `tslc`) may be off by
            // up to about half a second (the module reports its list once a second): the
            // position sigma grows by the distance flown in that time.
            if from_receipt {
                pos.value.sigma_m += 0.5 * r.ground_speed_mps.unwrap_or(p.max_speed_mps);
            }
        }
        check_drift(track, t_gps_ns, r, &p);
        track
            .findings
            .close_report(t_gps_ns, (p.flag_hold_s * 1e9) as i64);
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
    /// the rest from each one's own time, computes geometry and alert levels under the fail-safe
    /// policy ([`super::policy`]), and returns targets in priority order (alert level, then time
    /// to loss of well-clear, then range).
    pub fn picture(&mut self, t_ns: i64, own: &Ownship) -> Vec<Target> {
        self.ownship = Some(*own);
        let timeout_ns = (self.params.timeout_s * 1e9) as i64;
        let before = self.tracks.len();
        self.tracks
            .retain(|_, t| t_ns.saturating_sub(t.last_update_ns) <= timeout_ns);
        self.stats.tracks_timed_out += (before - self.tracks.len()) as u64;
        let frames = Frames {
            baro: own.alt_pressure_m.map(|a| own.frame(a)),
            geo: own.alt_geometric_m.map(|a| own.frame(a)),
            any: own.frame(own.alt_geometric_m.or(own.alt_pressure_m).unwrap_or(0.0)),
        };
        let mut out: Vec<Target> = Vec::with_capacity(self.tracks.len());
        let mut stale = 0;
        for t in self.tracks.values_mut() {
            if let Some(target) = target_at(t, t_ns, own, &frames, &self.params) {
                stale += u64::from(target.fail_safe.stale);
                out.push(target);
            }
        }
        self.stats.stale_dropped += stale;
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

/// The ownship's planes of one picture: at its pressure altitude, at its geometric altitude, and
/// one at whatever altitude it has (for horizontal quantities).
struct Frames {
    baro: Option<OwnshipFrame>,
    geo: Option<OwnshipFrame>,
    any: OwnshipFrame,
}

/// Which altitudes to compare: like with like when both sides have one; else pressure against
/// geometric through the ownship's measured difference (it has both); else a band.
fn vertical_pair(r: &Reported, own: &Ownship) -> (AltitudeKind, Option<f64>, Option<f64>, f64) {
    let (ip, ig) = (r.alt_pressure_m, r.alt_geometric_m);
    let band_g = own.alt_geometric_band_m;
    match (ip, own.alt_pressure_m, ig, own.alt_geometric_m) {
        (Some(a), Some(o), _, _) => (AltitudeKind::Pressure, Some(a), Some(a - o), 0.0),
        (_, _, Some(a), Some(o)) => (AltitudeKind::Geometric, Some(a), Some(a - o), band_g),
        // Intruder pressure only, ownship geometric only (no BAHRS): no measured GNSS-baro
        // difference. Decision: the two differ by the ISA temperature deviation (about 4 % of
        // the height per 10 K) and the pressure datum (about 8 m/hPa, 250 m at 30 hPa): the band
        // is 250 m + 10 % of the height, wide but honest.
        (Some(a), None, None, Some(o)) => (
            AltitudeKind::Mixed,
            Some(a),
            Some(a - o),
            250.0 + 0.1 * o.abs() + band_g,
        ),
        // Intruder geometric only, ownship pressure only: the same band.
        (None, Some(o), Some(a), None) => (
            AltitudeKind::Mixed,
            Some(a),
            Some(a - o),
            250.0 + 0.1 * a.abs(),
        ),
        _ => (AltitudeKind::None, None, None, 0.0),
    }
}

/// One target of the picture at `t_ns`; `None` for a track without a position.
fn target_at(
    t: &mut Track,
    t_ns: i64,
    own: &Ownship,
    frames: &Frames,
    p: &TrafficParams,
) -> Option<Target> {
    let pos = t.position?;
    let dt_pos = t_ns.saturating_sub(pos.t_gps_ns) as f64 * 1e-9;
    let velocity = t.velocity.map(|v| v.value);
    let (track_deg, gs) = velocity.unwrap_or((0.0, 0.0));
    let (lat, lon) = extrapolate(pos.value.lat_deg, pos.value.lon_deg, track_deg, gs, dt_pos);
    let vs = t.vertical_rate.map(|v| v.value);
    let reported = Reported::of(t, t_ns, vs);
    let (kind, alt, dz, mut dz_band) = vertical_pair(&reported, own);
    let category = t.emitter_category;
    let vz_max = policy::max_vertical_rate_mps(category, p.max_vertical_rate_mps);
    if vs.is_none() {
        // The altitude was not moved on from its report: it may have changed by the category's
        // rate since.
        dz_band += vz_max * dt_pos.abs();
    }
    let margin = if velocity.is_none() {
        policy::max_speed_mps(category, p.max_speed_mps) * dt_pos.abs()
    } else {
        0.0
    };
    // Position uncertainty grows with the age of the fix at 1 m/s/s of unknown acceleration
    // (0.5 a t^2), and by the distance it may have flown when its velocity is unknown.
    let sigma = pos.value.sigma_m + 0.5 * dt_pos.abs().powi(2) + margin;
    let intruder = IntruderEcef::new(&AircraftState {
        lat_deg: lat,
        lon_deg: lon,
        alt_m: alt.unwrap_or(0.0),
        track_deg,
        ground_speed_mps: gs,
        vertical_rate_mps: vs.unwrap_or(0.0),
    });
    let frame = match kind {
        AltitudeKind::Pressure => frames.baro.as_ref(),
        AltitudeKind::Geometric => frames.geo.as_ref(),
        _ => None,
    }
    .unwrap_or(&frames.any);
    let rel = frame.position_of(&intruder);
    let bearing = rel.x.atan2(rel.y).to_degrees().rem_euclid(360.0);
    let stale = dt_pos > p.stale_limit_s[link_slot(pos.value.source.link)];
    let own_v = own.velocity_en_mps().map(|v| Vector2::new(v[0], v[1]));
    let assessed = policy::assess(&Encounter {
        s_m: Vector2::new(rel.x, rel.y),
        own_velocity_mps: own_v,
        own_vertical_rate_mps: own.vertical_rate_mps,
        own_max_vertical_rate_mps: p.own_max_vertical_rate_mps,
        intruder_velocity_mps: velocity.map(|_| frame.velocity_of(&intruder)),
        dz_m: dz,
        dz_band_m: dz_band,
        intruder_vertical_rate_mps: vs,
        intruder_max_vertical_rate_mps: vz_max,
        position_margin_m: margin,
    });
    let (geometry, mut fail_safe) = match assessed {
        Some((g, f)) if !stale => (Some(g), f),
        Some((_, f)) => (None, f),
        None => (None, FailSafeFlags::default()),
    };
    fail_safe.stale = stale;
    fail_safe.time_from_receipt = pos.value.time_from_receipt;
    let raw = geometry.map_or(0, |g| g.alert_level);
    let filtered = t.alert.update(raw, t_ns, &p.alert);
    let hold_ns = (p.flag_hold_s * 1e9) as i64;
    Some(Target {
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
        velocity_ne_mps: velocity.map(|_| {
            let (s, c) = track_deg.to_radians().sin_cos();
            [gs * c, gs * s]
        }),
        vertical_rate_mps: vs,
        altitude_kind: kind,
        position_sigma_m: sigma,
        bearing_true_deg: bearing,
        bearing_relative_deg: own
            .heading_deg
            .map(|h| crate::attitude::angles::wrap_pi((bearing - h).to_radians()).to_degrees()),
        geometry,
        raw_alert_level: raw,
        alert_level: filtered,
        flarm_alarm_level: t.flarm_alarm_level,
        flags: t.findings.active(t_ns, hold_ns),
        fail_safe,
        reported,
    })
}

/// Index of a link in [`TrafficParams::stale_limit_s`].
fn link_slot(l: vigil_drivers::traffic::Link) -> usize {
    use vigil_drivers::traffic::Link;
    match l {
        Link::Adsb1090 => 0,
        Link::Uat978 => 1,
        Link::Flarm => 2,
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

/// Runs the plausibility tests of a report against the track, then merges it: speed, position,
/// altitudes, then the fields without a test. A value older than the track's is tested but not
/// merged (reports of several sources arrive out of order).
fn check_and_merge(
    track: &mut Track,
    source: Source,
    t: i64,
    r: &TrafficReport,
    p: &TrafficParams,
    own: Option<&Ownship>,
) {
    if r.ground_speed_mps.is_some_and(|v| v > p.max_speed_mps) {
        track.findings.impossible_speed = Some(t);
    }
    check_and_merge_position(track, source, t, r, p, own);
    check_and_merge_altitudes(track, t, r, p);
    merge_untested(track, source, t, r);
}

/// The report's position, when it has one: a jump beyond the maximum speed over the time since
/// the track's position (plus the combined sigmas) is a position jump from the same source, or
/// inconsistent sources from another; a signal stronger than the maximum EIRP allows at the
/// range from the ownship is a range-versus-signal finding.
fn check_and_merge_position(
    track: &mut Track,
    source: Source,
    t: i64,
    r: &TrafficReport,
    p: &TrafficParams,
    own: Option<&Ownship>,
) {
    let f = &mut track.findings;
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
                    time_from_receipt: false,
                },
            });
        }
    }
}

/// The pressure and geometric altitudes: a change beyond the maximum vertical rate over the
/// time since the track's value (plus 50 m) is an altitude jump.
fn check_and_merge_altitudes(track: &mut Track, t: i64, r: &TrafficReport, p: &TrafficParams) {
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
}

/// The fields without a plausibility test: velocity and vertical rate (when newer); callsign,
/// category, squawk, signal and FLARM alarm level (an unknown value keeps the known one); the
/// address type; and the source's latest report.
fn merge_untested(track: &mut Track, source: Source, t: i64, r: &TrafficReport) {
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

/// The position-against-velocity test over [`TrafficParams::drift_window_s`] (issue 24): a
/// residual beyond 5 combined position sigmas plus the velocity allowance over the span is a
/// drift finding. Needs position and velocity in the same report.
fn check_drift(track: &mut Track, t: i64, r: &TrafficReport, p: &TrafficParams) {
    let (Some(lat), Some(lon), Some(trk), Some(gs)) =
        (r.lat_deg, r.lon_deg, r.track_deg, r.ground_speed_mps)
    else {
        if r.lat_deg.is_some() {
            track.drift.clear();
        }
        return;
    };
    let (sn, cs) = trk.to_radians().sin_cos();
    let sigma = report_sigma_m(r);
    let sample = super::track::DriftSample {
        t_gps_ns: t,
        lat_deg: lat,
        lon_deg: lon,
        velocity_en_mps: [gs * sn, gs * cs],
        sigma_m: sigma,
    };
    let window_ns = (p.drift_window_s * 1e9) as i64;
    if let Some((residual, span_s, base_sigma)) = track.drift.push(sample, window_ns) {
        let allowed = p.consistency_sigmas * (sigma * sigma + base_sigma * base_sigma).sqrt()
            + p.drift_velocity_error_mps * span_s;
        if residual > allowed {
            track.findings.position_drift = Some(t);
        }
    }
}

#[cfg(test)]
mod tests;
