//! The TT-Multi-RF model's once-per-second messages: the JSON `gnss` section (manual 9.2.2), NMEA
//! GGA/RMC (9.2.1), the GDL90 Heartbeat / Ownship Report / Ownship Geometric Altitude and the
//! ASTERIX CAT023 status (7.2.1). A child module of [`super`], so it shares the model's state.

use serde_json::json;
use vigil_drivers::ttmrf::json::{Gnss, GnssAccuracy, JsonMessage};
use vigil_drivers::ttmrf::nmea::{Date as NmeaDate, Gga, NmeaBody, NmeaSentence, Rmc};

use super::super::ttmrf_binary::{self, OwnFix};
use super::super::{Emission, FaultSchedule};
use super::{
    GNSS_H_SIGMA_M, GNSS_V_SIGMA_M, KT_PER_MPS, SERIAL, TtmrfModel, obj, round_to, utc_ns_of_day,
};
use crate::truth::World;
use crate::units::NS_PER_S;

impl TtmrfModel {
    pub(super) fn gnss(
        &mut self,
        t: i64,
        world: &World,
        faults: &FaultSchedule,
    ) -> Option<Emission> {
        let lost = faults.gnss_lost("ttmrf", world.elapsed_s(t));
        let o = world.ownship(t);
        let g = if lost {
            Gnss {
                fix: Some(0),
                ..Default::default()
            }
        } else {
            let n = &mut self.noise;
            let (dn, de, dd) = (
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_V_SIGMA_M),
            );
            let [vn, ve, vd] = o.vel_ned_mps;
            let h = round_to(o.height_m - dd, 0.1);
            Gnss {
                fix: Some(1),
                lat_deg: Some(round_to(
                    o.lat_deg + (dn / world.frame.radius_north_m).to_degrees(),
                    1e-7,
                )),
                lon_deg: Some(round_to(
                    o.lon_deg + (de / world.frame.radius_east_m).to_degrees(),
                    1e-7,
                )),
                alt_wgs84_m: Some(h),
                // The simulated geoid is the ellipsoid.
                alt_msl_m: Some(h),
                // Issue 24: `gnss_velocity = false` models a receiver that leaves them out.
                track_deg: self
                    .cfg
                    .gnss_velocity
                    .then(|| round_to(ve.atan2(vn).to_degrees().rem_euclid(360.0), 0.1) % 360.0),
                velh_kt: self
                    .cfg
                    .gnss_velocity
                    .then(|| round_to(vn.hypot(ve) * KT_PER_MPS, 0.1)),
                velv_mps: Some(round_to(-vd, 0.1)),
                acc: Some(GnssAccuracy {
                    lat_m: Some(GNSS_H_SIGMA_M),
                    lon_m: Some(GNSS_H_SIGMA_M),
                    alt_m: Some(GNSS_V_SIGMA_M),
                }),
                nac_p: Some(9),
                nac_v: Some(1),
                nic: Some(8),
                ..Default::default()
            }
        };
        let ts_ms = self.ts_ms(t);
        let m = JsonMessage {
            src: Some(SERIAL.into()),
            ts_ms: Some(ts_ms),
            ver: Some(1),
            gnss: Some(g),
            ..Default::default()
        };
        let bytes = self.send_line(m.to_wire().as_bytes())?;
        let v = json!({
            "fix": !lost,
            "lat_deg": o.lat_deg,
            "lon_deg": o.lon_deg,
            "height_m": o.height_m,
            "vel_ned_mps": o.vel_ned_mps,
            "ts_ms": ts_ms,
        });
        Some(Emission {
            t_ready_gps_ns: t,
            bytes,
            kind: "gnss",
            t_gps_ns: t,
            values: obj(v),
        })
    }

    /// GGA then RMC (manual 9.2.1, NMEA output of the GNSS section) for CSV mode.
    pub(super) fn nmea(
        &mut self,
        t: i64,
        world: &World,
        faults: &FaultSchedule,
        out: &mut Vec<Emission>,
    ) {
        let lost = faults.gnss_lost("ttmrf", world.elapsed_s(t));
        let o = world.ownship(t);
        let utc_s = utc_ns_of_day(t) as f64 / 1e9;
        let d = crate::units::gps_ns_to_utc_date(t);
        let date = NmeaDate {
            year: d.year() as u16,
            month: d.month() as u8,
            day: d.day(),
        };
        let [vn, ve, _] = o.vel_ned_mps;
        let (lat, lon, h) = if lost {
            (None, None, None)
        } else {
            let n = &mut self.noise;
            let (dn, de, dd) = (
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_H_SIGMA_M),
                n.gauss(GNSS_V_SIGMA_M),
            );
            (
                Some(o.lat_deg + (dn / world.frame.radius_north_m).to_degrees()),
                Some(o.lon_deg + (de / world.frame.radius_east_m).to_degrees()),
                Some(round_to(o.height_m - dd, 0.1)),
            )
        };
        let gga = Gga {
            time_s: Some(utc_s),
            lat_deg: lat,
            lon_deg: lon,
            quality: Some(u8::from(!lost)),
            satellites: Some(if lost { 0 } else { 10 }),
            hdop: (!lost).then_some(0.9),
            alt_msl_m: h,
            // The simulated geoid is the ellipsoid; `nmea_geoid_separation = false` (issue 24)
            // leaves the field empty, as some receivers do.
            geoid_sep_m: (!lost && self.cfg.nmea_geoid_separation).then_some(0.0),
            ..Default::default()
        };
        let rmc = Rmc {
            time_s: Some(utc_s),
            valid: Some(!lost),
            lat_deg: lat,
            lon_deg: lon,
            speed_kt: (!lost && self.cfg.gnss_velocity)
                .then(|| round_to(vn.hypot(ve) * KT_PER_MPS, 0.1)),
            course_deg: (!lost && self.cfg.gnss_velocity)
                .then(|| round_to(ve.atan2(vn).to_degrees().rem_euclid(360.0), 0.1) % 360.0),
            date: Some(date),
            mode: Some(if lost { 'N' } else { 'A' }),
            ..Default::default()
        };
        for (kind, body) in [
            ("nmea_gga", NmeaBody::Gga(gga)),
            ("nmea_rmc", NmeaBody::Rmc(rmc)),
        ] {
            let line = NmeaSentence {
                talker: "GP".into(),
                body,
            }
            .to_line();
            let Some(bytes) = self.send_line(line.as_bytes()) else {
                return;
            };
            let v = json!({
                "fix": !lost,
                "lat_deg": o.lat_deg,
                "lon_deg": o.lon_deg,
                "height_m": o.height_m,
                "vel_ned_mps": o.vel_ned_mps,
                "utc_s_of_day": utc_s,
            });
            out.push(Emission {
                t_ready_gps_ns: t,
                bytes,
                kind,
                t_gps_ns: t,
                values: obj(v),
            });
        }
    }

    /// The GNSS fix with the model's noise (three draws, as `gnss`), `None` during an outage.
    fn own_fix(&mut self, t: i64, world: &World, faults: &FaultSchedule) -> Option<OwnFix> {
        if faults.gnss_lost("ttmrf", world.elapsed_s(t)) {
            return None;
        }
        let o = world.ownship(t);
        let n = &mut self.noise;
        let (dn, de, dd) = (
            n.gauss(GNSS_H_SIGMA_M),
            n.gauss(GNSS_H_SIGMA_M),
            n.gauss(GNSS_V_SIGMA_M),
        );
        Some(OwnFix {
            lat_deg: o.lat_deg + (dn / world.frame.radius_north_m).to_degrees(),
            lon_deg: o.lon_deg + (de / world.frame.radius_east_m).to_degrees(),
            height_m: o.height_m - dd,
            vel_ned_mps: o.vel_ned_mps,
        })
    }

    /// GDL90 Heartbeat, Ownship Report and Ownship Geometric Altitude at a whole second.
    pub(super) fn gdl90_second(
        &mut self,
        t: i64,
        world: &World,
        faults: &FaultSchedule,
        out: &mut Vec<Emission>,
    ) {
        let fix = self.own_fix(t, world, faults);
        let o = world.ownship(t);
        let own_address = self
            .module
            .stored("ADSB_TX_ICAO")
            .and_then(|v| u32::from_str_radix(v.trim(), 16).ok())
            .unwrap_or(0)
            & 0xFF_FFFF;
        let own_ecat = self
            .module
            .stored("ADSB_TX_EMITTER_CAT")
            .and_then(|v| v.trim().parse().ok())
            .unwrap_or(0);
        let utc_s = (utc_ns_of_day(t) / NS_PER_S as u64) as u32;
        for (kind, frame) in ttmrf_binary::gdl90_second(utc_s, own_address, own_ecat, fix) {
            let Some(bytes) = self.send_line(&frame) else {
                return;
            };
            let mut v = ttmrf_binary::ownship_values(
                fix.is_some(),
                o.lat_deg,
                o.lon_deg,
                o.height_m,
                o.vel_ned_mps,
            );
            v.insert("utc_s_of_day".into(), json!(utc_s));
            out.push(Emission {
                t_ready_gps_ns: t,
                bytes,
                kind,
                t_gps_ns: t,
                values: v,
            });
        }
    }

    /// The ASTERIX CAT023 ground station status at a whole second.
    pub(super) fn asterix_status(&mut self, t: i64) -> Option<Emission> {
        let tod_s = utc_ns_of_day(t) as f64 / 1e9;
        let source = self.asterix_source();
        let bytes = self.send_line(&ttmrf_binary::asterix_status(tod_s, source))?;
        Some(Emission {
            t_ready_gps_ns: t,
            bytes,
            kind: "asterix_status",
            t_gps_ns: t,
            values: obj(json!({ "tod_s": tod_s, "sac": source.sac, "sic": source.sic })),
        })
    }
}
