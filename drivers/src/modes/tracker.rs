//! Per-aircraft state: the addresses seen with verified parity (which AP replies are checked
//! against), the last even/odd CPR frames of each kind for global decoding, the last good
//! position for local decoding, and the version and NIC supplements that NIC needs.
//!
//! Bounded table, eviction policy: at most [`TrackerConfig::capacity`] aircraft. When a frame
//! with verified parity brings a new address and the table is full, the aircraft heard least
//! recently (by frame count, so the policy is the same with or without receive times) is
//! evicted; an evicted aircraft starts afresh when heard again. The table is allocated once.
//!
//! Positions (DO-260B A.1.7):
//! 1. global: the other format of the same kind (airborne or surface; never mixed) was received
//!    within [`TrackerConfig::pair_window_s`] (10 s). Without receive times, consecutive frames
//!    count as within the window. The frame just received is the "newest" (its format gives
//!    the output position). Surface pairs need a reference: the receiver, else the aircraft's
//!    last position. A pair rejected by the NL-zone check gives no position.
//! 2. local: else, against the aircraft's last good position of the same kind if no older than
//!    [`TrackerConfig::local_max_age_s`], or for surface frames against the receiver.
//! 3. else none.
//!
//! A decoded position is then checked for plausibility (a pair that straddles an NL boundary
//! is already refused by [`cpr::global_airborne`]): an airborne position farther than
//! [`TrackerConfig::max_range_m`] from a known receiver, or farther from the aircraft's recent
//! last position than [`TrackerConfig::jump_slack_m`] + [`TrackerConfig::max_speed_mps`] x the
//! elapsed time, is rejected and counted (`cpr_rejections`); a rejected global pair is not
//! tried again.

use std::collections::HashMap;
use std::hash::{BuildHasherDefault, Hasher};

use serde::Serialize;

use super::airborne_position::AirbornePosition;
use super::cpr::{self, CprFrame};
use super::df::{Content, ModeS, Parity};
use super::ident::Callsign;
use super::me::Me;
use super::nic::nic;
use super::squawk::Squawk;
use super::surface::SurfacePosition;
use crate::traffic::{AddressType, Link, Protocol, SourceTime, TrafficFlags, TrafficReport};
use crate::ttmrf::raw::RxMeta;

/// Tracker settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackerConfig {
    /// Maximum number of aircraft held.
    pub capacity: usize,
    /// Maximum time between the even and odd frames of a global pair, s.
    pub pair_window_s: f64,
    /// Maximum age of a last position used as a local-decoding reference, s.
    pub local_max_age_s: f64,
    /// Receiver position (lat_deg, lon_deg), for surface decoding.
    pub receiver: Option<(f64, f64)>,
    /// Build a [`TrafficReport`] on frames that update position or velocity.
    pub emit_reports: bool,
    /// Fastest plausible ground speed, m/s: a new position farther from the aircraft's recent
    /// last position than `jump_slack_m` + this speed x elapsed time is rejected.
    pub max_speed_mps: f64,
    /// Distance always allowed between consecutive positions, m (CPR and timing noise).
    pub jump_slack_m: f64,
    /// Farthest plausible airborne target from the receiver (when it is known), m.
    pub max_range_m: f64,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        TrackerConfig {
            capacity: 4096,
            pair_window_s: 10.0,
            local_max_age_s: 30.0,
            receiver: None,
            emit_reports: true,
            max_speed_mps: 1000.0,
            jump_slack_m: 5.0 * 1852.0,
            max_range_m: 600_000.0,
        }
    }
}

/// How a position was obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PositionMethod {
    /// Global decoding of an even/odd pair.
    Global,
    /// Local decoding against the aircraft's last position.
    LocalAircraft,
    /// Local decoding against the receiver position.
    LocalReceiver,
}

/// A decoded position.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Position {
    /// Latitude, degrees north.
    pub lat_deg: f64,
    /// Longitude, degrees east.
    pub lon_deg: f64,
    /// From surface position frames.
    pub surface: bool,
    /// How it was decoded.
    pub method: PositionMethod,
}

#[derive(Debug, Clone, Copy)]
struct Stamped {
    cpr: CprFrame,
    t: Option<f64>,
}

#[derive(Debug, Clone, Copy)]
struct LastPos {
    pos: Position,
    t: Option<f64>,
}

/// What the tracker knows about one aircraft.
#[derive(Debug, Clone, Default)]
pub struct Aircraft {
    last_seq: u64,
    /// Last CPR frames: [airborne, surface] x [even, odd].
    cpr: [[Option<Stamped>; 2]; 2],
    last_pos: Option<LastPos>,
    /// Address type.
    pub address_type: AddressType,
    /// Flight identification.
    pub callsign: Option<Callsign>,
    /// Emitter category (0..39).
    pub category: Option<u8>,
    /// Mode A code.
    pub squawk: Option<Squawk>,
    /// Barometric altitude, ft.
    pub altitude_baro_ft: Option<i32>,
    /// GNSS height, ft.
    pub altitude_gnss_ft: Option<i32>,
    /// Ground speed, kt.
    pub groundspeed_kt: Option<f64>,
    /// Track, degrees.
    pub track_deg: Option<f64>,
    /// Heading, degrees.
    pub heading_deg: Option<f64>,
    /// Vertical rate, ft/min.
    pub vertical_rate_fpm: Option<i32>,
    /// ADS-B version from TC 31.
    pub version: Option<u8>,
    /// NIC supplement-A (TC 31).
    pub nic_a: bool,
    /// NIC supplement-C (TC 31 surface).
    pub nic_c: bool,
    /// NIC of the last position.
    pub nic: Option<u8>,
    /// NACp (TC 31 or TC 29).
    pub nac_p: Option<u8>,
    /// NACv (TC 19 or TC 31 surface).
    pub nac_v: Option<u8>,
    /// SIL (TC 31 or TC 29).
    pub sil: Option<u8>,
    /// Emergency state (TC 28).
    pub emergency: Option<u8>,
    /// Last position decoded.
    pub position: Option<Position>,
    /// On the ground (surface position, or CA = 4).
    pub on_ground: bool,
}

/// A cheap hasher for 24-bit addresses (multiplicative; addresses are not attacker-chosen in a
/// way that matters for a bounded table).
#[derive(Default)]
pub struct AddrHasher(u64);

impl Hasher for AddrHasher {
    fn finish(&self) -> u64 {
        self.0
    }
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = (self.0 ^ u64::from(b)).wrapping_mul(0x100_0000_01B3);
        }
    }
    fn write_u32(&mut self, v: u32) {
        self.0 = u64::from(v).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    }
}

/// The result of feeding one frame to the tracker.
#[derive(Debug, Clone, Default)]
pub struct Update {
    /// The frame was accepted (false: AP frame from an unknown address).
    pub accepted: bool,
    /// Position completed by this frame.
    pub position: Option<Position>,
    /// Why a position frame gave no position (global pair rejected by the zone check).
    pub cpr_rejected: bool,
    /// NIC for this position frame.
    pub nic: Option<u8>,
    /// Traffic report, when the frame updated position or velocity of an aircraft whose
    /// position is known and no older than [`TrackerConfig::local_max_age_s`] (and reports
    /// are enabled).
    pub report: Option<TrafficReport>,
}

/// The per-aircraft table.
#[derive(Debug, Clone)]
pub struct Tracker {
    cfg: TrackerConfig,
    table: HashMap<u32, Aircraft, BuildHasherDefault<AddrHasher>>,
    seq: u64,
    /// Aircraft evicted so far.
    pub evictions: u64,
    /// Global pairs rejected by the NL-zone or latitude check.
    pub cpr_rejections: u64,
}

impl Tracker {
    /// A tracker with the given settings (capacity at least 1).
    pub fn new(cfg: TrackerConfig) -> Self {
        let cfg = TrackerConfig {
            capacity: cfg.capacity.max(1),
            ..cfg
        };
        Tracker {
            table: HashMap::with_capacity_and_hasher(cfg.capacity, Default::default()),
            cfg,
            seq: 0,
            evictions: 0,
            cpr_rejections: 0,
        }
    }

    /// The settings.
    pub fn config(&self) -> &TrackerConfig {
        &self.cfg
    }

    /// Number of aircraft held.
    pub fn len(&self) -> usize {
        self.table.len()
    }

    /// True when no aircraft is held.
    pub fn is_empty(&self) -> bool {
        self.table.is_empty()
    }

    /// State of one aircraft (table key: the address, plus 1 << 24 for non-ICAO DF18 addresses).
    pub fn aircraft(&self, key: u32) -> Option<&Aircraft> {
        self.table.get(&key)
    }

    fn entry(&mut self, key: u32) -> &mut Aircraft {
        if !self.table.contains_key(&key)
            && self.table.len() >= self.cfg.capacity
            && let Some(old) = self
                .table
                .iter()
                .min_by_key(|(_, a)| a.last_seq)
                .map(|(k, _)| *k)
        {
            self.table.remove(&old);
            self.evictions += 1;
        }
        self.table.entry(key).or_default()
    }

    /// Feeds one decoded frame with its receive metadata.
    ///
    /// The steps: the sender's table key; a frame accepted but not tracked (coarse TIS-B,
    /// management); an address-parity reply, which only updates an aircraft already known; then
    /// for a frame with verified parity, the aircraft's entry (created, evicting when full), the
    /// ME contents applied to it, and the traffic report when it moved.
    pub fn update(&mut self, msg: &ModeS, meta: &RxMeta) -> Update {
        self.seq += 1;
        let seq = self.seq;
        let t = meta.time_s();
        let accepted = Update {
            accepted: true,
            ..Update::default()
        };
        let (key, addr_type) = track_key(msg);
        if msg.df == 18 && msg.content == Content::NotDecoded {
            // Coarse TIS-B / management: the address field may be a track number, so it must
            // not vouch for AP replies; accepted (parity checked) but not tracked.
            return accepted;
        }
        if msg.parity == Parity::AddressParity {
            return self.update_known(key, seq, msg);
        }
        let cfg = self.cfg;
        let a = self.entry(key);
        a.last_seq = seq;
        a.address_type = addr_type;
        let mut up = accepted;
        let me = match msg.content {
            Content::Extended { me, ca_cf, .. } => {
                if msg.df == 17 {
                    a.on_ground = ca_cf == 4;
                }
                me
            }
            Content::AllCall { capability } => {
                a.on_ground = capability == 4;
                return up;
            }
            _ => return up,
        };
        let moved = Self::apply_me(&cfg, a, me, t, &mut up);
        // A report never carries a stale position: the last position must be no older than
        // `local_max_age_s` (always true without receive times).
        let fresh = a
            .last_pos
            .is_some_and(|l| Self::within_static(l.t, t, cfg.local_max_age_s));
        if cfg.emit_reports && moved && fresh {
            up.report = Some(report(key, a, msg, meta));
        }
        if up.cpr_rejected {
            self.cpr_rejections += 1;
        }
        up
    }

    /// An address-parity reply: its parity is checked against an address already in the table
    /// (heard with verified parity), so an unknown one is not accepted and creates nothing; a
    /// known one updates its altitude, squawk and callsign.
    fn update_known(&mut self, key: u32, seq: u64, msg: &ModeS) -> Update {
        let Some(a) = self.table.get_mut(&key) else {
            return Update::default();
        };
        a.last_seq = seq;
        if let Content::Surveillance {
            altitude_ft,
            squawk,
            callsign,
            ..
        } = msg.content
        {
            if altitude_ft.is_some() {
                a.altitude_baro_ft = altitude_ft;
            }
            if squawk.is_some() {
                a.squawk = squawk;
            }
            if callsign.is_some() {
                a.callsign = callsign;
            }
        }
        Update {
            accepted: true,
            ..Update::default()
        }
    }

    /// Applies an extended squitter's ME field to aircraft `a` (at receive time `t`, s); returns
    /// whether its position or velocity changed (what a traffic report is emitted for). A field
    /// the message leaves unknown keeps the aircraft's previous value.
    fn apply_me(
        cfg: &TrackerConfig,
        a: &mut Aircraft,
        me: Me,
        t: Option<f64>,
        up: &mut Update,
    ) -> bool {
        match me {
            Me::Identification(id) => {
                a.callsign = Some(id.callsign);
                a.category = Some(id.emitter_category());
            }
            Me::AirbornePosition(p) => return Self::airborne_position(cfg, a, p, t, up),
            Me::SurfacePosition(s) => return Self::surface_position(cfg, a, s, t, up),
            Me::Velocity(v) => {
                a.nac_v = Some(v.nac_v);
                if v.groundspeed_kt.is_some() {
                    a.groundspeed_kt = v.groundspeed_kt;
                    a.track_deg = v.track_deg;
                }
                if v.heading_deg.is_some() {
                    a.heading_deg = v.heading_deg;
                }
                a.vertical_rate_fpm = v.vertical_rate_fpm;
                return true;
            }
            Me::Status(s) => {
                if s.emergency.is_some() {
                    a.emergency = s.emergency;
                }
                if s.squawk.is_some() {
                    a.squawk = s.squawk;
                }
            }
            Me::TargetState(ts) => {
                a.nac_p = Some(ts.nac_p);
                a.sil = Some(ts.sil);
            }
            Me::OperationalStatus(os) => {
                a.version = Some(os.version);
                a.nic_a = os.nic_a.unwrap_or(false);
                a.nic_c = os.nic_c.unwrap_or(false);
                if os.nac_p.is_some() {
                    a.nac_p = os.nac_p;
                }
                if os.nac_v.is_some() {
                    a.nac_v = os.nac_v;
                }
                if os.sil.is_some() {
                    a.sil = os.sil;
                }
            }
            Me::Other { .. } => {}
        }
        false
    }

    /// An airborne position message: altitudes, NIC (from the type code and the supplements of
    /// the aircraft's version; NIC-B only in version 2), then the CPR position. Returns whether a
    /// position was decoded.
    fn airborne_position(
        cfg: &TrackerConfig,
        a: &mut Aircraft,
        p: AirbornePosition,
        t: Option<f64>,
        up: &mut Update,
    ) -> bool {
        if p.altitude_baro_ft.is_some() {
            a.altitude_baro_ft = p.altitude_baro_ft;
        }
        if p.altitude_gnss_ft.is_some() {
            a.altitude_gnss_ft = p.altitude_gnss_ft;
        }
        a.on_ground = false;
        let version = a.version.unwrap_or(0);
        let n = nic(p.typecode, version, a.nic_a, version == 2 && p.nic_b, false);
        up.nic = Some(n);
        a.nic = Some(n);
        Self::position(cfg, a, p.cpr, false, t, up)
    }

    /// A surface position message: ground speed and track, NIC (with the NIC-C supplement),
    /// then the CPR position. Returns whether a position was decoded.
    fn surface_position(
        cfg: &TrackerConfig,
        a: &mut Aircraft,
        s: SurfacePosition,
        t: Option<f64>,
        up: &mut Update,
    ) -> bool {
        a.on_ground = true;
        if let Some(b) = s.speed {
            a.groundspeed_kt = Some(b.min_kt);
        }
        if s.track_deg.is_some() {
            a.track_deg = s.track_deg;
        }
        let n = nic(s.typecode, a.version.unwrap_or(0), a.nic_a, false, a.nic_c);
        up.nic = Some(n);
        a.nic = Some(n);
        Self::position(cfg, a, s.cpr, true, t, up)
    }

    /// Tries to decode a position from a CPR frame; returns true when one was found.
    fn position(
        cfg: &TrackerConfig,
        a: &mut Aircraft,
        cpr_frame: CprFrame,
        surface: bool,
        t: Option<f64>,
        up: &mut Update,
    ) -> bool {
        let kind = usize::from(surface);
        let this = usize::from(cpr_frame.odd);
        a.cpr[kind][this] = Some(Stamped { cpr: cpr_frame, t });
        let tracker_within =
            |x: Option<f64>, y: Option<f64>, lim: f64| Tracker::within_static(x, y, lim);
        let last_ref = a
            .last_pos
            .filter(|l| l.pos.surface == surface && tracker_within(l.t, t, cfg.local_max_age_s))
            .map(|l| (l.pos.lat_deg, l.pos.lon_deg));
        let mut result = None;
        if let Some(other) = a.cpr[kind][1 - this]
            && tracker_within(other.t, t, cfg.pair_window_s)
        {
            let (even, odd) = if cpr_frame.odd {
                (other.cpr, cpr_frame)
            } else {
                (cpr_frame, other.cpr)
            };
            let r = if surface {
                cfg.receiver
                    .or(last_ref)
                    .map(|(rl, rn)| cpr::global_surface(even, odd, cpr_frame.odd, rl, rn))
            } else {
                Some(cpr::global_airborne(even, odd, cpr_frame.odd))
            };
            match r {
                Some(Ok(p)) => result = Some((p, PositionMethod::Global)),
                Some(Err(_)) => {
                    up.cpr_rejected = true;
                    // Do not pair these two again.
                    a.cpr[kind][1 - this] = None;
                }
                None => {}
            }
        }
        if result.is_none() && !up.cpr_rejected {
            let reference = match (last_ref, surface, cfg.receiver) {
                (Some(r), _, _) => Some((r, PositionMethod::LocalAircraft)),
                (None, true, Some(r)) => Some((r, PositionMethod::LocalReceiver)),
                _ => None,
            };
            if let Some(((rl, rn), m)) = reference
                && let Ok(p) = cpr::local(cpr_frame, surface, rl, rn)
            {
                result = Some((p, m));
            }
        }
        let Some(((lat_deg, lon_deg), method)) = result else {
            return false;
        };
        if !Self::plausible(cfg, a.last_pos, surface, t, (lat_deg, lon_deg)) {
            up.cpr_rejected = true;
            if method == PositionMethod::Global {
                a.cpr[kind][1 - this] = None;
            }
            return false;
        }
        let pos = Position {
            lat_deg,
            lon_deg,
            surface,
            method,
        };
        a.last_pos = Some(LastPos { pos, t });
        a.position = Some(pos);
        up.position = Some(pos);
        true
    }

    /// Plausibility of a new position: within range of the receiver (airborne) and reachable
    /// from the aircraft's recent last position of the same kind at `max_speed_mps`. A
    /// mis-paired CPR decode lands a whole zone (hundreds of km) away, which this catches.
    fn plausible(
        cfg: &TrackerConfig,
        last: Option<LastPos>,
        surface: bool,
        t: Option<f64>,
        p: (f64, f64),
    ) -> bool {
        if !surface
            && let Some(r) = cfg.receiver
            && !within_distance(r, p, cfg.max_range_m)
        {
            return false;
        }
        match last {
            Some(l) if l.pos.surface == surface => match (l.t, t) {
                (Some(a), Some(b)) if Self::within_static(l.t, t, cfg.local_max_age_s) => {
                    let mut dt = (a - b).abs();
                    if dt > 43_200.0 {
                        dt = (86_400.0 - dt).abs();
                    }
                    within_distance(
                        (l.pos.lat_deg, l.pos.lon_deg),
                        p,
                        cfg.jump_slack_m + cfg.max_speed_mps * dt,
                    )
                }
                _ => true,
            },
            _ => true,
        }
    }

    fn within_static(a: Option<f64>, b: Option<f64>, limit: f64) -> bool {
        match (a, b) {
            (Some(a), Some(b)) => {
                let mut d = (a - b).abs();
                if d > 43_200.0 {
                    d = (86_400.0 - d).abs();
                }
                d <= limit
            }
            _ => true,
        }
    }
}

/// Great-circle distance between two (lat_deg, lon_deg) points on a sphere of the WGS-84
/// mean radius, m (good to 0.5 %, plenty for plausibility checks).
/// The table key of the frame's sender and its address type: the 24-bit address, with the
/// address type of a DF 18 (CF field) in bits 24-25 so that a non-ICAO or TIS-B address never
/// merges with the ICAO aircraft of the same number.
fn track_key(msg: &ModeS) -> (u32, AddressType) {
    match msg.content {
        Content::Extended { ca_cf, .. } if msg.df == 18 => match ca_cf {
            0 => (msg.icao, AddressType::Icao),
            1 => (msg.icao | 1 << 24, AddressType::NonIcao),
            2 | 6 => (msg.icao | 2 << 24, AddressType::TisbIcao),
            _ => (msg.icao | 3 << 24, AddressType::TisbOther),
        },
        _ => (msg.icao, AddressType::Icao),
    }
}

fn distance_m(a: (f64, f64), b: (f64, f64)) -> f64 {
    const R: f64 = 6_371_008.8;
    let (p1, p2) = (a.0.to_radians(), b.0.to_radians());
    let dp = p2 - p1;
    let dl = (b.1 - a.1).to_radians();
    let h = (dp / 2.0).sin().powi(2) + p1.cos() * p2.cos() * (dl / 2.0).sin().powi(2);
    2.0 * R * h.sqrt().min(1.0).asin()
}

/// `distance_m(a, b) <= limit_m`, without trigonometry in the usual case: the flat-earth
/// distance with the longitude difference taken at the equator's scale is never shorter than
/// the great-circle distance (for the short distances where it decides), so when it is within
/// the limit the answer is yes; otherwise the exact distance decides.
fn within_distance(a: (f64, f64), b: (f64, f64), limit_m: f64) -> bool {
    const M_PER_DEG: f64 = 111_195.08;
    let dlat = (a.0 - b.0).abs() * M_PER_DEG;
    let dlon = ((a.1 - b.1 + 540.0).rem_euclid(360.0) - 180.0).abs() * M_PER_DEG;
    if dlat * dlat + dlon * dlon <= limit_m * limit_m {
        return true;
    }
    distance_m(a, b) <= limit_m
}

/// Builds the common traffic report from what the tracker knows. `signal_dbm` holds HEX SIGS
/// (dBm) when the frame has it, else the Beast RSSI in dBFS (the receiver's own unit, as the
/// report's field allows); altitudes, speeds and rates are converted to SI.
fn report(key: u32, a: &Aircraft, msg: &ModeS, meta: &RxMeta) -> TrafficReport {
    const FT: f64 = 0.3048;
    const KT: f64 = 1852.0 / 3600.0;
    const FPM: f64 = 0.00508;
    let relayed = msg.df == 18
        && matches!(
            msg.content,
            Content::Extended {
                ca_cf: 2 | 5 | 6,
                ..
            }
        );
    TrafficReport {
        link: Link::Adsb1090,
        protocol: Protocol::RawModeS,
        address: key & 0xFF_FFFF,
        address_type: a.address_type,
        callsign: a
            .callsign
            .filter(|c| c.valid)
            .map(|c| c.as_str().to_string()),
        squawk: a.squawk.map(Squawk::as_decimal),
        emitter_category: a.category,
        lat_deg: a.position.map(|p| p.lat_deg),
        lon_deg: a.position.map(|p| p.lon_deg),
        alt_pressure_m: a.altitude_baro_ft.map(|f| f64::from(f) * FT),
        alt_geometric_m: a.altitude_gnss_ft.map(|f| f64::from(f) * FT),
        track_deg: a.track_deg,
        heading_deg: a.heading_deg,
        ground_speed_mps: a.groundspeed_kt.map(|k| k * KT),
        vertical_rate_mps: a.vertical_rate_fpm.map(|v| f64::from(v) * FPM),
        nic: a.nic,
        nac_p: a.nac_p,
        nac_v: a.nac_v,
        sil: a.sil,
        signal_dbm: meta
            .signal_dbm
            .map(f64::from)
            .or_else(|| meta.signal_dbfs()),
        emergency_code: a.emergency,
        // The frame's own time (TS24h) is the report's time; no further age (issue 24).
        data_age_s: None,
        flarm_alarm_level: None,
        flags: TrafficFlags {
            on_ground: a.on_ground,
            emergency: a.emergency.is_some_and(|e| e != 0),
            relayed,
            ..TrafficFlags::default()
        },
        source_time: meta
            .ts_utc_ns
            .map(SourceTime::NsSinceUtcMidnight)
            .or(meta.mlat_ticks.map(SourceTime::Mlat12MHz))
            .or(meta.ts_pps_ns.map(SourceTime::NsSincePps)),
    }
}

#[cfg(test)]
#[path = "tracker_tests.rs"]
mod tests;
