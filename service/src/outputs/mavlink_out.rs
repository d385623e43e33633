//! MAVLink traffic output (issue 26): every fused target as `ADSB_VEHICLE`, plus a `HEARTBEAT`,
//! as UDP datagrams to a configured address (`[outputs.mavlink]`), so an autopilot (ArduPilot,
//! PX4) or a ground station (QGroundControl, Mission Planner, MAVProxy) shows vigil's traffic.
//!
//! [`MavlinkTraffic`] is sans-IO: it turns a traffic picture into frames; [`MavlinkUdp`] sends
//! them. Field mapping (MAVLink common dialect, ADSB_VEHICLE #246):
//!
//! | field | from the fused target |
//! |---|---|
//! | `ICAO_address` | the 24-bit address (any address space: the message has no address type) |
//! | `lat`, `lon` | extrapolated position, degE7; flag `VALID_COORDS` |
//! | `altitude`, `altitude_type` | the intruder's altitude the geometry used, mm: pressure altitude (1013.25 hPa datum) as type 0 with `BARO_VALID`, geometric as type 1; flag `VALID_ALTITUDE`. Decision: when the geometry compared unlike altitudes (`mixed`) the target does not say which kind its altitude is, so none is sent rather than a guess |
//! | `heading`, `hor_velocity` | course over ground (cdeg, 0..36000) and ground speed (cm/s) from the reported velocity; flags `VALID_HEADING`, `VALID_VELOCITY` |
//! | `ver_velocity` | vertical rate, cm/s up; flag `VERTICAL_VELOCITY_VALID` |
//! | `callsign` | when known; flag `VALID_CALLSIGN` |
//! | `tslc` | age of the newest report, whole seconds (saturating at 255) |
//! | `emitter_type` | the reported emitter category: MAVLink's `ADSB_EMITTER_TYPE` numbers DO-260B's categories as GDL90 does (0..19); beyond 19 (obstacles GDL90 adds) or not reported: 0, no information |
//! | `squawk` | not carried by the fused picture: 0, no flag |
//!
//! Each target is sent at most once per second (of GPS time); the heartbeat once per second.
//! Unknown stays unknown: a field without its validity flag carries 0.

use std::collections::HashMap;
use vigil_drivers::ttmrf::mavlink::adsb_vehicle::{
    FLAG_BARO_VALID, FLAG_VALID_ALTITUDE, FLAG_VALID_CALLSIGN, FLAG_VALID_COORDS,
    FLAG_VALID_HEADING, FLAG_VALID_VELOCITY, FLAG_VERTICAL_VELOCITY_VALID,
};
use vigil_drivers::ttmrf::mavlink::{
    AdsbVehicle, FrameInfo, encode_adsb_heartbeat, encode_adsb_vehicle,
};
use vigil_fusion::pipeline::TrafficPicture;
use vigil_fusion::traffic::{AltitudeKind, Target};

use crate::Outputs;
use crate::config::MavlinkSection;
use crate::outputs::udp_out::UdpSink;

/// Shortest interval between two messages about one target, and between heartbeats, ns.
const MIN_INTERVAL_NS: i64 = 1_000_000_000;

/// The sans-IO encoder: traffic pictures in, MAVLink frames out.
#[derive(Debug)]
pub struct MavlinkTraffic {
    system_id: u8,
    component_id: u8,
    sequence: u8,
    /// GPS time each target (by address) was last sent, ns.
    last_sent: HashMap<u32, i64>,
    last_heartbeat_ns: Option<i64>,
}

impl MavlinkTraffic {
    /// An encoder sending as MAVLink system `system_id`, component `component_id`.
    pub fn new(system_id: u8, component_id: u8) -> Self {
        Self {
            system_id,
            component_id,
            sequence: 0,
            last_sent: HashMap::new(),
            last_heartbeat_ns: None,
        }
    }

    fn frame(&mut self) -> FrameInfo {
        let f = FrameInfo {
            version: 2,
            sequence: self.sequence,
            system_id: self.system_id,
            component_id: self.component_id,
            signed: false,
        };
        self.sequence = self.sequence.wrapping_add(1);
        f
    }

    /// The frames for picture `pic` (one `Vec` per frame: each goes in its own datagram): a
    /// heartbeat when one is due, and every target not sent in the last second.
    pub fn picture(&mut self, pic: &TrafficPicture) -> Vec<Vec<u8>> {
        let t = pic.t_gps_ns;
        let mut frames = Vec::new();
        if self
            .last_heartbeat_ns
            .is_none_or(|h| t.saturating_sub(h) >= MIN_INTERVAL_NS || t < h)
        {
            self.last_heartbeat_ns = Some(t);
            let mut buf = Vec::with_capacity(32);
            let f = self.frame();
            encode_adsb_heartbeat(&f, &mut buf);
            frames.push(buf);
        }
        for target in &pic.targets {
            let due = self
                .last_sent
                .get(&target.key.address)
                .is_none_or(|&s| t.saturating_sub(s) >= MIN_INTERVAL_NS || t < s);
            if !due {
                continue;
            }
            self.last_sent.insert(target.key.address, t);
            let mut buf = Vec::with_capacity(64);
            let f = self.frame();
            encode_adsb_vehicle(&f, &vehicle(target), &mut buf);
            frames.push(buf);
        }
        // Forget targets gone from the picture for a minute, so the map stays small.
        self.last_sent
            .retain(|_, s| t.saturating_sub(*s) < 60 * MIN_INTERVAL_NS);
        frames
    }
}

/// The ADSB_VEHICLE of one fused target (see the module's table).
pub fn vehicle(t: &Target) -> AdsbVehicle {
    let mut flags = FLAG_VALID_COORDS;
    let (altitude_m, altitude_type) = match (t.alt_m, t.altitude_kind) {
        (Some(a), AltitudeKind::Pressure) => {
            flags |= FLAG_VALID_ALTITUDE | FLAG_BARO_VALID;
            (a, 0)
        }
        (Some(a), AltitudeKind::Geometric) => {
            flags |= FLAG_VALID_ALTITUDE;
            (a, 1)
        }
        _ => (0.0, 0),
    };
    let (heading_deg, hor_velocity_mps) = match t.velocity_ne_mps {
        Some([n, e]) => {
            flags |= FLAG_VALID_HEADING | FLAG_VALID_VELOCITY;
            (e.atan2(n).to_degrees().rem_euclid(360.0), n.hypot(e))
        }
        None => (0.0, 0.0),
    };
    let ver_velocity_mps = match t.vertical_rate_mps {
        Some(v) => {
            flags |= FLAG_VERTICAL_VELOCITY_VALID;
            v
        }
        None => 0.0,
    };
    let callsign = match &t.callsign {
        Some(c) => {
            flags |= FLAG_VALID_CALLSIGN;
            c.clone()
        }
        None => String::new(),
    };
    AdsbVehicle {
        icao_address: t.key.address & 0x00FF_FFFF,
        lat_deg: t.lat_deg,
        lon_deg: t.lon_deg,
        altitude_m,
        altitude_type,
        // 360.00 deg does not fit the field's 0..35999: north is 0.
        heading_deg: if heading_deg >= 359.995 {
            0.0
        } else {
            heading_deg
        },
        hor_velocity_mps,
        ver_velocity_mps,
        flags,
        squawk: 0,
        callsign,
        emitter_type: t
            .reported
            .emitter_category
            .filter(|&c| c <= 19)
            .unwrap_or(0),
        tslc_s: t.age_s.clamp(0.0, 255.0) as u8,
    }
}

/// The MAVLink output on UDP: an [`Outputs`] sink that takes only traffic pictures.
pub struct MavlinkUdp {
    encoder: MavlinkTraffic,
    sink: UdpSink,
}

impl MavlinkUdp {
    /// Opens the output towards the section's address.
    pub fn open(section: &MavlinkSection) -> std::io::Result<Self> {
        Ok(Self {
            encoder: MavlinkTraffic::new(section.system_id, section.component_id),
            sink: UdpSink::open("MAVLink", &section.address)?,
        })
    }
}

impl Outputs for MavlinkUdp {
    fn publish<T: vigil_bus::Payload>(&mut self, _: &T) {}

    fn traffic_picture(
        &mut self,
        pic: &TrafficPicture,
        _own: Option<&vigil_fusion::ownship::Ownship>,
    ) {
        self.sink.send_all(&self.encoder.picture(pic));
    }
}

#[cfg(test)]
#[path = "mavlink_out_tests.rs"]
mod tests;
