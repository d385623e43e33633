//! GDL90 traffic output (issue 26): Heartbeat, Ownship Report, Ownship Geometric Altitude and a
//! Traffic Report per fused target, once a second, as UDP datagrams (`[outputs.gdl90]`), the form
//! electronic flight bags and traffic displays take (GDL 90 Data Interface Specification
//! 560-1058-00 Rev A; one framed message per datagram).
//!
//! [`Gdl90Traffic`] is sans-IO (pictures in, frames out); [`Gdl90Udp`] sends. Decisions where the
//! fused picture and the ICD do not meet:
//! - Traffic Report altitude is pressure altitude (ICD 3.5.1.4, 25 ft steps). A target whose
//!   geometry used a geometric or a mixed altitude sends 0xFFF ("invalid"): its pressure
//!   altitude is not in the picture, and a geometric altitude in that field would be read as a
//!   pressure altitude, off by the local pressure datum.
//! - Traffic alert status `s` is 1 while the DAA alert level is corrective or warning (the
//!   levels that call for a manoeuvre), else 0.
//! - Address type `t`: ICAO 0, non-ICAO / FLARM 1 (self-assigned), TIS-B track file 3, surface 4.
//! - NACp from the 1-sigma position uncertainty at the picture's time: EPU (95 % radius of a
//!   circular 2-D normal) = 2.448 sigma, then the ICD's table 3.5.1.6 bounds; when the source
//!   reported a NACp too, the lower (worse) of the two, because extrapolation since the report
//!   only loses accuracy. NIC as the source reported it (0..11), else 0 (unknown).
//! - Emitter category as reported when it is in the ICD's table (0..39), else 0 (no
//!   information).
//! - Misc: airborne unless the address is a surface vehicle's (the picture has no air/ground
//!   state); "extrapolated" when the newest report is more than a second old; track type "true
//!   track" when a velocity is known, else "not valid".
//! - The Ownship Report carries address 0 (vigil is not told the ownship's address), its pressure
//!   altitude (BAHRS) when known, and the GNSS track, speed and vertical rate; the geometric
//!   altitude (ellipsoid height, 5 ft steps) goes in message 11 with VFOM "not available".
//! - Heartbeat: GPS position valid when an ownship position is known; UTC OK while the leap
//!   second table vouches for the date; timestamp = UTC seconds since midnight.

use vigil_drivers::ttmrf::gdl90::geo_altitude::{GeoAltitude, Vfom};
use vigil_drivers::ttmrf::gdl90::heartbeat::Heartbeat;
use vigil_drivers::ttmrf::gdl90::report::{
    AddressKind, HorizontalVelocity, TargetReport, TrackType, VerticalVelocity,
};
use vigil_drivers::ttmrf::gdl90::{Gdl90Message, encode_frame};
use vigil_fusion::ownship::Ownship;
use vigil_fusion::pipeline::TrafficPicture;
use vigil_fusion::time::gps;
use vigil_fusion::traffic::track::AddressSpace;
use vigil_fusion::traffic::{AltitudeKind, Target};

use crate::Outputs;
use crate::config::Gdl90Section;
use crate::outputs::udp_out::UdpSink;

const FT_PER_M: f64 = 1.0 / 0.3048;
const KT_PER_MPS: f64 = 3600.0 / 1852.0;
const FPM_PER_MPS: f64 = 60.0 / 0.3048;
/// 95 % radius of a circular 2-D normal distribution, in sigmas (sqrt(-2 ln 0.05)).
const EPU_PER_SIGMA: f64 = 2.4477;

/// The sans-IO encoder: traffic pictures (with the ownship) in, framed GDL90 messages out.
#[derive(Debug, Default)]
pub struct Gdl90Traffic {
    last_second: Option<i64>,
}

impl Gdl90Traffic {
    /// The frames for picture `pic` and ownship `own` (one `Vec` per framed message), at most
    /// once per GPS second: heartbeat, ownship report and geometric altitude (when an ownship is
    /// known), then one traffic report per target.
    pub fn picture(&mut self, pic: &TrafficPicture, own: Option<&Ownship>) -> Vec<Vec<u8>> {
        let second = pic.t_gps_ns.div_euclid(1_000_000_000);
        if self.last_second.is_some_and(|s| s == second) {
            return Vec::new();
        }
        self.last_second = Some(second);
        let mut msgs = vec![Gdl90Message::Heartbeat(heartbeat(pic.t_gps_ns, own))];
        if let Some(o) = own {
            msgs.push(Gdl90Message::OwnshipReport(ownship_report(o)));
            if let Some(h) = o.alt_geometric_m {
                msgs.push(Gdl90Message::OwnshipGeoAltitude(GeoAltitude {
                    geo_altitude_ft: ((h * FT_PER_M / 5.0).round() as i32) * 5,
                    vertical_warning: false,
                    vfom: Vfom::Unavailable,
                }));
            }
        }
        msgs.extend(
            pic.targets
                .iter()
                .map(|t| Gdl90Message::TrafficReport(traffic_report(t))),
        );
        msgs.iter()
            .map(|m| {
                let mut frame = Vec::with_capacity(64);
                encode_frame(m, &mut frame);
                frame
            })
            .collect()
    }
}

/// The heartbeat at GPS time `t_gps_ns`.
fn heartbeat(t_gps_ns: i64, own: Option<&Ownship>) -> Heartbeat {
    let approx_unix_s = t_gps_ns.div_euclid(gps::NS_PER_S) + gps::GPS_EPOCH_UNIX_S;
    let leap = gps::gps_minus_utc_s(approx_unix_s);
    let unix_s = gps::unix_ns_from_gps_ns(t_gps_ns, leap.gps_minus_utc_s).div_euclid(gps::NS_PER_S);
    Heartbeat {
        gps_pos_valid: own.is_some(),
        uat_initialized: true,
        utc_ok: leap.table_valid,
        timestamp_s: unix_s.rem_euclid(86_400) as u32,
        ..Heartbeat::default()
    }
}

/// NACp (ICD table 3.5.1.6) from a 1-sigma horizontal uncertainty, m; 0 when unknown.
pub fn nac_p(sigma_m: Option<f64>) -> u8 {
    const NM: f64 = 1852.0;
    // (EPU below, m; NACp), best first.
    const BOUNDS: [(f64, u8); 11] = [
        (3.0, 11),
        (10.0, 10),
        (30.0, 9),
        (0.05 * NM, 8),
        (0.1 * NM, 7),
        (0.3 * NM, 6),
        (0.5 * NM, 5),
        (1.0 * NM, 4),
        (2.0 * NM, 3),
        (4.0 * NM, 2),
        (10.0 * NM, 1),
    ];
    let Some(s) = sigma_m.filter(|s| s.is_finite() && *s >= 0.0) else {
        return 0;
    };
    let epu = s * EPU_PER_SIGMA;
    BOUNDS.iter().find(|(b, _)| epu < *b).map_or(0, |&(_, n)| n)
}

fn callsign(c: Option<&str>) -> [u8; 8] {
    let mut out = *b"        ";
    for (d, s) in out.iter_mut().zip(
        c.unwrap_or("")
            .bytes()
            .filter(|b| b.is_ascii_alphanumeric() || *b == b' ')
            .map(|b| b.to_ascii_uppercase()),
    ) {
        *d = s;
    }
    out
}

fn velocity(ne_mps: Option<[f64; 2]>) -> (TrackType, f64, HorizontalVelocity) {
    match ne_mps {
        Some([n, e]) => {
            let kt = (n.hypot(e) * KT_PER_MPS).round();
            let h = if kt >= 4094.0 {
                HorizontalVelocity::AtLeast4094Kt
            } else {
                HorizontalVelocity::Kt(kt as u16)
            };
            (
                TrackType::TrueTrack,
                e.atan2(n).to_degrees().rem_euclid(360.0),
                h,
            )
        }
        None => (TrackType::NotValid, 0.0, HorizontalVelocity::Unavailable),
    }
}

fn vertical(rate_mps: Option<f64>) -> VerticalVelocity {
    match rate_mps {
        Some(v) => {
            let fpm = ((v * FPM_PER_MPS) / 64.0).round() as i32 * 64;
            if fpm > 32_576 {
                VerticalVelocity::ClimbOver32576Fpm
            } else if fpm < -32_576 {
                VerticalVelocity::DescentOver32576Fpm
            } else {
                VerticalVelocity::Fpm(fpm)
            }
        }
        None => VerticalVelocity::Unavailable,
    }
}

/// The Traffic Report of one fused target (see the module's decisions).
pub fn traffic_report(t: &Target) -> TargetReport {
    let (track_type, track_deg, horizontal_velocity) = velocity(t.velocity_ne_mps);
    let address_type = match t.key.space {
        AddressSpace::Icao => AddressKind::AdsbIcao,
        AddressSpace::TisbOther => AddressKind::TisbTrackFile,
        AddressSpace::Surface => AddressKind::SurfaceVehicle,
        _ => AddressKind::AdsbSelfAssigned,
    };
    TargetReport {
        alert_status: u8::from(t.alert_level >= 2),
        address_type,
        address: t.key.address & 0x00FF_FFFF,
        lat_deg: t.lat_deg,
        lon_deg: t.lon_deg,
        altitude_ft: match (t.alt_m, t.altitude_kind) {
            (Some(a), AltitudeKind::Pressure) => Some((a * FT_PER_M).round() as i32),
            _ => None,
        },
        airborne: t.key.space != AddressSpace::Surface,
        extrapolated: t.age_s > 1.0,
        track_type,
        track_deg,
        nic: t.reported.nic.filter(|&n| n <= 11).unwrap_or(0),
        nac_p: {
            let from_sigma = nac_p(Some(t.position_sigma_m));
            t.reported.nac_p.map_or(from_sigma, |r| r.min(from_sigma))
        },
        horizontal_velocity,
        vertical_velocity: vertical(t.vertical_rate_mps),
        emitter_category: t
            .reported
            .emitter_category
            .filter(|&c| c <= 39)
            .unwrap_or(0),
        callsign: callsign(t.callsign.as_deref()),
        emergency_code: 0,
        spare: 0,
    }
}

/// The Ownship Report (see the module's decisions).
pub fn ownship_report(o: &Ownship) -> TargetReport {
    let (track_type, track_deg, horizontal_velocity) =
        velocity(o.velocity_en_mps().map(|[e, n]| [n, e]));
    TargetReport {
        address_type: AddressKind::AdsbIcao,
        address: 0,
        lat_deg: o.lat_deg,
        lon_deg: o.lon_deg,
        altitude_ft: o.alt_pressure_m.map(|a| (a * FT_PER_M).round() as i32),
        airborne: true,
        track_type,
        track_deg,
        nac_p: nac_p(o.position_sigma_m),
        horizontal_velocity,
        vertical_velocity: vertical(o.vertical_rate_mps),
        ..TargetReport::default()
    }
}

/// The GDL90 output on UDP: an [`Outputs`] sink that takes only traffic pictures.
pub struct Gdl90Udp {
    encoder: Gdl90Traffic,
    sink: UdpSink,
}

impl Gdl90Udp {
    /// Opens the output towards the section's address (EFBs usually listen on the broadcast
    /// address, port 4000).
    pub fn open(section: &Gdl90Section) -> std::io::Result<Self> {
        Ok(Self {
            encoder: Gdl90Traffic::default(),
            sink: UdpSink::open("GDL90", &section.address)?,
        })
    }
}

impl Outputs for Gdl90Udp {
    fn publish<T: vigil_bus::Payload>(&mut self, _: &T) {}

    fn traffic_picture(&mut self, pic: &TrafficPicture, own: Option<&Ownship>) {
        self.sink.send_all(&self.encoder.picture(pic, own));
    }
}

#[cfg(test)]
#[path = "gdl90_out_tests.rs"]
mod tests;
