//! Building the [`Ownship`] from the VN-200, the TT-Multi-RF GNSS, the BAHRS and the attitude
//! vote (issue 8, "Ownship").
//!
//! Decisions:
//! - The VN-200 is the position source only in mode Tracking (the rule; the manual also
//!   calls the position valid while Aligning, but the INS has not converged then) with a sample
//!   at most `max_age_s` old; otherwise the TT-Multi-RF GNSS with a fix, at most `max_age_s` old.
//! - TT-Multi-RF JSON `acc` gives per-axis position accuracies (m); they are taken as 1-sigma and
//!   the horizontal sigma is `sqrt(lat^2 + lon^2) / sqrt 2` (the RMS of the two). Without `acc`, the
//!   NACp bound (95 % horizontal, DO-260B table) is turned into a sigma by dividing by 2.45 (the
//!   95 % radius of a circular 2-D Gaussian). NMEA GGA has only HDOP: sigma = HDOP x
//!   `uere_m` (default 4 m).
//! - The heading is the voted true heading when the cross-check has one, else the VN-200 yaw when
//!   its attitude is valid, else the track.

use serde::Serialize;
use vigil_drivers::bahrs::Health;
use vigil_drivers::ttmrf::json::Gnss;
use vigil_drivers::ttmrf::nmea::{Gga, Rmc};

use super::{Ownship, PositionSource};
use crate::attitude::angles::{to_ypr, wrap_2pi};
use crate::attitude::record::AttitudeRecord;
use crate::attitude::samples::{BahrsSample, Vn200Sample};
use crate::geometry::wgs84::dead_reckon;
use crate::units::{M_PER_NM, MPS_PER_KT};

const DEG: f64 = std::f64::consts::PI / 180.0;

/// Parameters of the builder.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OwnshipParams {
    /// Oldest usable input, s.
    pub max_age_s: f64,
    /// GNSS user range error for the NMEA HDOP sigma, m.
    pub uere_m: f64,
}

impl Default for OwnshipParams {
    fn default() -> Self {
        Self {
            max_age_s: 1.5,
            uere_m: 4.0,
        }
    }
}

/// A GNSS fix from the TT-Multi-RF, in SI units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GnssFix {
    /// GPS time, ns.
    pub t_gps_ns: i64,
    /// Latitude, deg.
    pub lat_deg: f64,
    /// Longitude, deg.
    pub lon_deg: f64,
    /// Height above the ellipsoid, m.
    pub alt_wgs84_m: Option<f64>,
    /// Half-width of the band `alt_wgs84_m` lies in beyond its noise, m: 0, or
    /// [`GEOID_UNKNOWN_HALF_RANGE_M`] when it was made from MSL height without a geoid
    /// separation (issue 24).
    pub alt_band_m: f64,
    /// Track, deg true.
    pub track_deg: Option<f64>,
    /// Ground speed, m/s.
    pub ground_speed_mps: Option<f64>,
    /// Vertical rate, m/s up.
    pub vertical_rate_mps: Option<f64>,
    /// 1-sigma horizontal position, m.
    pub position_sigma_m: f64,
    /// NACp, when reported.
    pub nac_p: Option<u8>,
    /// NACv, when reported.
    pub nac_v: Option<u8>,
}

/// Decision (issue 24, one altitude reference): no geoid model is vendored (none could be
/// vetted offline here), so a GGA without its geoid-separation field gets the middle of the
/// geoid's worldwide range, EGM96 -106 .. +85 m, as the separation, m ...
pub const GEOID_UNKNOWN_MID_M: f64 = -10.5;
/// ... and half that range as a bound on the error, m: the traffic geometry widens the vertical
/// test by it (`alt_geometric_band_m`), and the ownship's vertical sigma is that of a uniform
/// error over the range (95.5 / sqrt 3 = 55 m).
pub const GEOID_UNKNOWN_HALF_RANGE_M: f64 = 95.5;

/// 95 % horizontal bound of a NACp value, m (DO-260B; 0 or unknown: none).
pub fn nacp_epu_m(nac_p: u8) -> Option<f64> {
    Some(match nac_p {
        11 => 3.0,
        10 => 10.0,
        9 => 30.0,
        8 => 0.05 * M_PER_NM,
        7 => 0.1 * M_PER_NM,
        6 => 0.3 * M_PER_NM,
        5 => 0.5 * M_PER_NM,
        4 => 1.0 * M_PER_NM,
        3 => 2.0 * M_PER_NM,
        2 => 4.0 * M_PER_NM,
        1 => 10.0 * M_PER_NM,
        _ => return None,
    })
}

impl GnssFix {
    /// From the TT-Multi-RF JSON `gnss` section at GPS time `t_gps_ns`; `None` without a fix or
    /// a position, or without any uncertainty.
    pub fn from_json(t_gps_ns: i64, g: &Gnss) -> Option<Self> {
        if g.fix != Some(1) {
            return None;
        }
        let (lat, lon) = (g.lat_deg?, g.lon_deg?);
        let sigma = match g.acc {
            Some(a) if a.lat_m.is_some() && a.lon_m.is_some() => {
                let (la, lo) = (a.lat_m.unwrap_or(0.0), a.lon_m.unwrap_or(0.0));
                ((la * la + lo * lo) / 2.0).sqrt()
            }
            _ => nacp_epu_m(g.nac_p?)? / 2.45,
        };
        let (gs, track) = match (g.gnd_speed_en_kt, g.velh_kt, g.track_deg) {
            (Some([e, n]), _, _) => (
                Some(e.hypot(n) * MPS_PER_KT),
                Some(wrap_2pi(e.atan2(n)) / DEG),
            ),
            (None, v, t) => (v.map(|v| v * MPS_PER_KT), t),
        };
        Some(Self {
            t_gps_ns,
            lat_deg: lat,
            lon_deg: lon,
            // MSL only: the geoid's middle and range (see GEOID_UNKNOWN_MID_M).
            alt_wgs84_m: g
                .alt_wgs84_m
                .or(g.alt_msl_m.map(|a| a + GEOID_UNKNOWN_MID_M)),
            alt_band_m: if g.alt_wgs84_m.is_none() && g.alt_msl_m.is_some() {
                GEOID_UNKNOWN_HALF_RANGE_M
            } else {
                0.0
            },
            track_deg: track,
            ground_speed_mps: gs,
            vertical_rate_mps: g.velv_mps,
            position_sigma_m: sigma,
            nac_p: g.nac_p,
            nac_v: g.nac_v,
        })
    }

    /// From NMEA GGA (and the RMC of the same epoch, for track and speed) at `t_gps_ns`; `None`
    /// without a fix (quality 0), a position or an HDOP.
    pub fn from_nmea(t_gps_ns: i64, gga: &Gga, rmc: Option<&Rmc>, uere_m: f64) -> Option<Self> {
        if gga.quality.unwrap_or(0) == 0 {
            return None;
        }
        let rmc = rmc.filter(|r| r.valid == Some(true));
        Some(Self {
            t_gps_ns,
            lat_deg: gga.lat_deg?,
            lon_deg: gga.lon_deg?,
            alt_wgs84_m: gga
                .alt_msl_m
                .map(|a| a + gga.geoid_sep_m.unwrap_or(GEOID_UNKNOWN_MID_M)),
            alt_band_m: if gga.alt_msl_m.is_some() && gga.geoid_sep_m.is_none() {
                GEOID_UNKNOWN_HALF_RANGE_M
            } else {
                0.0
            },
            track_deg: rmc.and_then(|r| r.course_deg),
            ground_speed_mps: rmc.and_then(|r| r.speed_kt).map(|v| v * MPS_PER_KT),
            vertical_rate_mps: None,
            position_sigma_m: gga.hdop? * uere_m,
            nac_p: None,
            nac_v: None,
        })
    }
}

/// The ownship with what the traffic contract does not carry.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct OwnshipSolution {
    /// Always "ownship" (JSON Lines of `vigil replay --emit fused`).
    pub kind: &'static str,
    /// The state used by the traffic fusion (flattened into the JSON line: `t_gps_ns`, `lat_deg`,
    /// ...).
    #[serde(flatten)]
    pub ownship: Ownship,
    /// 1-sigma velocity, m/s (VelU, or from NACv's 95 % bound / 2).
    pub velocity_sigma_mps: Option<f64>,
    /// NACp of the GNSS fallback.
    pub nac_p: Option<u8>,
    /// Voted (or VN-200) roll, deg.
    pub roll_deg: Option<f64>,
    /// Voted (or VN-200) pitch, deg.
    pub pitch_deg: Option<f64>,
    /// Where the heading came from: "vote", "vn200", "track" or "none" (unknown).
    pub heading_source: &'static str,
}

/// The vote at a time: GPS ns, roll, pitch, true heading (deg).
type VoteAt = (i64, Option<f64>, Option<f64>, Option<f64>);

/// Collects the latest inputs and builds the ownship at a time.
#[derive(Debug, Clone, Default)]
pub struct OwnshipBuilder {
    params: OwnshipParams,
    vn: Option<Vn200Sample>,
    gnss: Option<GnssFix>,
    pressure: Option<(i64, f64)>,
    vote: Option<VoteAt>,
}

fn age_ok(t: i64, t_sample: i64, max_s: f64) -> bool {
    let age = t.saturating_sub(t_sample);
    age >= -1_000_000_000 && (age as f64) * 1e-9 <= max_s
}

impl OwnshipBuilder {
    /// A builder with the given parameters.
    pub fn new(params: OwnshipParams) -> Self {
        Self {
            params,
            ..Default::default()
        }
    }

    /// The latest VN-200 sample.
    pub fn update_vn200(&mut self, s: &Vn200Sample) {
        self.vn = Some(*s);
    }

    /// The latest TT-Multi-RF GNSS fix.
    pub fn update_gnss(&mut self, f: GnssFix) {
        self.gnss = Some(f);
    }

    /// The latest BAHRS sample (pressure altitude when its health is safe).
    pub fn update_bahrs(&mut self, b: &BahrsSample) {
        if b.health.pressure_height() == Health::Safe && b.pressure_height_m.is_finite() {
            self.pressure = Some((b.t_gps_ns, b.pressure_height_m));
        }
    }

    /// The latest cross-check record (its voted attitude).
    pub fn update_attitude(&mut self, r: &AttitudeRecord) {
        self.vote = Some((
            r.t_gps_ns,
            r.voted.roll.as_ref().map(|v| v.value_deg),
            r.voted.pitch.as_ref().map(|v| v.value_deg),
            r.voted.heading.as_ref().map(|v| v.value_deg),
        ));
    }

    /// A position (lat deg, lon deg, height m) from the current source, for the declination.
    pub fn position(&self, t: i64) -> Option<[f64; 3]> {
        self.state(t).map(|s| {
            let o = s.ownship;
            [o.lat_deg, o.lon_deg, o.alt_geometric_m.unwrap_or(0.0)]
        })
    }

    /// The ownship at GPS time `t` (ns), or `None` without a usable position source.
    pub fn state(&self, t: i64) -> Option<OwnshipSolution> {
        let max = self.params.max_age_s;
        let vn = self.vn.filter(|v| {
            v.ins_status.mode() == vigil_drivers::vn200::status::InsMode::Tracking
                && !v.ins_status.imu_error()
                && v.lla.is_some()
                && v.vel_ned_mps.is_some()
                && age_ok(t, v.t_gps_ns, max)
        });
        let vn_att = self
            .vn
            .filter(|v| v.ins_status.attitude_valid() && age_ok(t, v.t_gps_ns, max))
            .map(|v| to_ypr(&v.attitude));
        let vote = self.vote.filter(|v| age_ok(t, v.0, max));
        let pressure = self.pressure.filter(|p| age_ok(t, p.0, max)).map(|p| p.1);
        let (mut own, vel_sigma, nac_p) = if let (Some(v), Some(lla), Some(vel)) =
            (vn, vn.and_then(|v| v.lla), vn.and_then(|v| v.vel_ned_mps))
        {
            (
                Ownship {
                    t_gps_ns: t,
                    lat_deg: lla[0],
                    lon_deg: lla[1],
                    alt_pressure_m: pressure,
                    alt_geometric_m: Some(lla[2]),
                    track_deg: Some(wrap_2pi(vel[1].atan2(vel[0])) / DEG),
                    ground_speed_mps: Some(vel[0].hypot(vel[1])),
                    vertical_rate_mps: Some(-vel[2]),
                    heading_deg: None,
                    position_sigma_m: v.pos_u_m.filter(|s| s.is_finite()),
                    source: PositionSource::Vn200Ins,
                    alt_geometric_band_m: 0.0,
                },
                v.vel_u_mps,
                None,
            )
        } else {
            let g = self.gnss.filter(|g| age_ok(t, g.t_gps_ns, max))?;
            let nacv_sigma = g.nac_v.and_then(|n| match n {
                4 => Some(0.3 / 2.0),
                3 => Some(1.0 / 2.0),
                2 => Some(3.0 / 2.0),
                1 => Some(10.0 / 2.0),
                _ => None,
            });
            // Unknown stays unknown (issue 24): no NaN, no guessed 0 climb rate. Track and
            // speed are only used together.
            let ground = g.track_deg.zip(g.ground_speed_mps);
            // The fix carried to `t` along its own velocity: a 1 Hz fix is up to a second older
            // than the step (40 m at 40 m/s). Its sigma grows by the velocity's over that age;
            // decision: a velocity without a stated accuracy (NMEA RMC) is taken at NACv 1's,
            // the loosest NACv bounds (10 m/s at 95 %), not as exact. Without a velocity the
            // position stays the fix's (the solution says its velocity is unknown); without a
            // vertical rate, so does the height.
            let age_s = (t - g.t_gps_ns) as f64 * 1e-9;
            let (lat_deg, lon_deg) = ground.map_or((g.lat_deg, g.lon_deg), |(trk, gs)| {
                dead_reckon(g.lat_deg, g.lon_deg, trk, gs, age_s)
            });
            let climbed_m = g.vertical_rate_mps.map_or(0.0, |v| v * age_s);
            let moved_sigma_m = match ground {
                Some(_) => nacv_sigma.unwrap_or(10.0 / 2.0) * age_s.abs(),
                None => 0.0,
            };
            (
                Ownship {
                    t_gps_ns: t,
                    lat_deg,
                    lon_deg,
                    alt_pressure_m: pressure,
                    alt_geometric_m: g.alt_wgs84_m.map(|h| h + climbed_m),
                    track_deg: ground.map(|(trk, _)| trk),
                    ground_speed_mps: ground.map(|(_, gs)| gs),
                    vertical_rate_mps: g.vertical_rate_mps,
                    heading_deg: None,
                    position_sigma_m: Some(g.position_sigma_m.hypot(moved_sigma_m)),
                    source: PositionSource::TtMultiRfGnss,
                    alt_geometric_band_m: g.alt_band_m,
                },
                nacv_sigma,
                g.nac_p,
            )
        };
        let (heading, source) = match (vote.and_then(|v| v.3), vn_att) {
            (Some(h), _) => (Some(h), "vote"),
            (None, Some((y, _, _))) => (Some(wrap_2pi(y) / DEG), "vn200"),
            (None, None) if own.track_deg.is_some() => (own.track_deg, "track"),
            (None, None) => (None, "none"),
        };
        own.heading_deg = heading;
        Some(OwnshipSolution {
            kind: "ownship",
            ownship: own,
            velocity_sigma_mps: vel_sigma,
            nac_p,
            roll_deg: vote.and_then(|v| v.1).or(vn_att.map(|a| a.2 / DEG)),
            pitch_deg: vote.and_then(|v| v.2).or(vn_att.map(|a| a.1 / DEG)),
            heading_source: source,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::synthetic::{Event, Scenario, Stream};
    use vigil_drivers::ttmrf::json::GnssAccuracy;

    fn json_fix() -> Gnss {
        Gnss {
            fix: Some(1),
            lat_deg: Some(47.41),
            lon_deg: Some(8.51),
            alt_wgs84_m: Some(650.0),
            gnd_speed_en_kt: Some([30.0, 40.0]),
            velv_mps: Some(1.5),
            acc: Some(GnssAccuracy {
                lat_m: Some(3.0),
                lon_m: Some(4.0),
                alt_m: Some(6.0),
            }),
            nac_p: Some(9),
            nac_v: Some(2),
            ..Default::default()
        }
    }

    #[test]
    fn gnss_fix_from_json_by_hand() {
        let f = GnssFix::from_json(5, &json_fix()).unwrap();
        // East 30 kt, north 40 kt: 50 kt = 25.722 m/s, track atan2(30, 40) = 36.87 deg.
        assert!((f.ground_speed_mps.unwrap() - 50.0 * 1852.0 / 3600.0).abs() < 1e-9);
        assert!((f.track_deg.unwrap() - 36.869_897_645_844).abs() < 1e-9);
        // sigma = sqrt((9 + 16) / 2) = 3.5355 m.
        assert!((f.position_sigma_m - 12.5f64.sqrt()).abs() < 1e-12);
        // No acc: NACp 9 (30 m at 95 %) gives 30 / 2.45 m.
        let g = Gnss {
            acc: None,
            ..json_fix()
        };
        let f = GnssFix::from_json(5, &g).unwrap();
        assert!((f.position_sigma_m - 30.0 / 2.45).abs() < 1e-12);
        // No fix: nothing.
        let g = Gnss {
            fix: Some(0),
            ..json_fix()
        };
        assert!(GnssFix::from_json(5, &g).is_none());
    }

    #[test]
    fn gnss_fix_from_nmea_by_hand() {
        let gga = Gga {
            lat_deg: Some(47.0),
            lon_deg: Some(8.0),
            quality: Some(1),
            hdop: Some(0.9),
            alt_msl_m: Some(500.0),
            geoid_sep_m: Some(48.0),
            ..Default::default()
        };
        let f = GnssFix::from_nmea(0, &gga, None, 4.0).unwrap();
        assert!((f.position_sigma_m - 3.6).abs() < 1e-12);
        assert_eq!(f.alt_wgs84_m, Some(548.0));
        let gga0 = Gga {
            quality: Some(0),
            ..gga
        };
        assert!(GnssFix::from_nmea(0, &gga0, None, 4.0).is_none());
    }

    #[test]
    fn vn200_when_tracking_else_the_ttmrf_gnss() {
        // The synthetic stream with GnssLost from t = 5 s.
        let sc = Scenario {
            duration_s: 8.0,
            gnss_lost_from_s: Some(5.0),
            ..Default::default()
        };
        let t0 = sc.t0_gps_ns;
        let mut b = OwnshipBuilder::new(OwnshipParams::default());
        let mut before = None;
        let mut after = None;
        for e in Stream::new(sc) {
            match e {
                Event::Vn200(v) => b.update_vn200(&v),
                Event::Bahrs(s) => {
                    b.update_bahrs(&s);
                    let t = s.t_gps_ns;
                    // The TT-Multi-RF GNSS at 1 Hz-ish: always fresh here.
                    b.update_gnss(GnssFix::from_json(t, &json_fix()).unwrap());
                    let st = b.state(t).unwrap();
                    let rel = (t - t0) as f64 * 1e-9;
                    if (4.0..4.02).contains(&rel) {
                        before = Some(st);
                    }
                    if (6.0..6.02).contains(&rel) {
                        after = Some(st);
                    }
                }
                Event::Watson(_) => {}
            }
        }
        let before = before.unwrap();
        assert_eq!(before.ownship.source, PositionSource::Vn200Ins);
        // Synthetic VN-200: north 0, east 40 m/s: track 90 deg, PosU 2 m.
        assert!((before.ownship.track_deg.unwrap() - 90.0).abs() < 1e-9);
        assert!((before.ownship.ground_speed_mps.unwrap() - 40.0).abs() < 1e-9);
        assert_eq!(before.ownship.position_sigma_m, Some(2.0));
        assert_eq!(before.velocity_sigma_mps, Some(0.1));
        // Pressure altitude from the BAHRS (truth height - 40 m, +- noise and LSB).
        assert!(before.ownship.alt_pressure_m.is_some());
        assert_eq!(before.heading_source, "vn200");
        let after = after.unwrap();
        assert_eq!(after.ownship.source, PositionSource::TtMultiRfGnss);
        assert_eq!(after.ownship.lat_deg, 47.41);
        assert_eq!(after.ownship.alt_geometric_m, Some(650.0));
        assert!((after.ownship.position_sigma_m.unwrap() - 12.5f64.sqrt()).abs() < 1e-12);
        assert_eq!(after.nac_p, Some(9));
        assert_eq!(after.velocity_sigma_mps, Some(1.5));
        // Attitude still valid in GnssLost: heading from the VN-200 yaw (about 90 deg true).
        assert_eq!(after.heading_source, "vn200");
        assert!((after.ownship.heading_deg.unwrap() - 90.0).abs() < 2.0);
    }

    #[test]
    fn no_source_no_ownship_and_stale_inputs_are_dropped() {
        let mut b = OwnshipBuilder::new(OwnshipParams::default());
        assert!(b.state(0).is_none());
        b.update_gnss(GnssFix::from_json(0, &json_fix()).unwrap());
        assert!(b.state(1_000_000_000).is_some());
        assert!(b.state(2_000_000_000).is_none()); // 2 s > 1.5 s
    }
}
