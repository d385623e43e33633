//! TT-Multi-RF GDL90 output (manual 7.2.1 "ADS-B GDL90 protocol"; GDL 90 Data Interface
//! Specification 560-1058-00 Rev A, sections 2 and 3).
//!
//! With `ADSB_RX_PROTOCOL_DECODED=GDL90` the module sends, once per second, a Heartbeat (ID 0),
//! an Ownship Report (ID 10), an Ownship Geometric Altitude (ID 11) and one Traffic Report
//! (ID 20) per ADS-B target. FLARM targets are never sent over GDL90 (manual).
//!
//! One module per piece: [`crc`] (FCS), [`framing`] (flags and escaping), [`heartbeat`],
//! [`report`] (the target layout shared by IDs 10 and 20), [`ownship`], [`traffic`],
//! [`geo_altitude`]. [`Gdl90Decoder`] is the [`DeviceDecoder`]; [`encode_frame`] builds frames.
//!
//! Decisions:
//! - **Traffic altitude.** GDL90 defines the Traffic Report altitude as pressure altitude, but the
//!   manual says the module fills it with *geometric altitude first, barometric as fallback* when
//!   its altitude-priority setting is 0, and barometric first when it is 1, without marking which
//!   one a report carries. The decoder therefore takes a [`TrafficAltitude`] that the caller sets
//!   from the module's configuration; the default is [`TrafficAltitude::Pressure`] (the GDL90
//!   definition; the configuration client should select barometric priority so that it holds).
//! - **Magnetic heading** (track type 2) is not put into [`TrafficReport::heading_deg`] (which is
//!   true heading); it stays in the decoded [`report::TargetReport`].
//! - **Saturated speeds** (0xFFE kt, 0x1FE/0xE02 fpm) are not exact values and become `None` in
//!   the [`TrafficReport`]; the decoded report keeps the code.
//! - **Shared flags.** Frames normally carry their own opening and closing flags; if a frame
//!   follows the previous closing flag directly (one flag shared between two frames), that flag
//!   opens it. A run of idle flags is skipped (and counted as skipped bytes).
//! - Frames whose content between flags exceeds [`framing::MAX_ESCAPED_LEN`] are skipped.
//!   Valid frames of other GDL90 messages (uplink, HAT, ...) and IDs above 127 (which the
//!   specification, 2.2.2, says to discard) count as `unknown_types`; a known ID with the wrong
//!   length counts as `malformed`.

pub mod crc;
pub mod framing;
pub mod geo_altitude;
pub mod heartbeat;
pub mod ownship;
pub mod report;
pub mod traffic;

#[cfg(test)]
mod spec_examples;
#[cfg(test)]
mod tests;

use bytes::BytesMut;
use serde::Serialize;

use crate::traffic::{AddressType, Link, Protocol, TrafficFlags, TrafficReport};
use crate::{DecodeStats, DeviceDecoder};
use framing::{FLAG, FrameError, MAX_ESCAPED_LEN, unframe};
use geo_altitude::GeoAltitude;
use heartbeat::Heartbeat;
use report::{AddressKind, TargetReport, TrackType};

/// One decoded GDL90 message.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Gdl90Message {
    /// ID 0.
    Heartbeat(Heartbeat),
    /// ID 10.
    OwnshipReport(TargetReport),
    /// ID 11.
    OwnshipGeoAltitude(GeoAltitude),
    /// ID 20.
    TrafficReport(TargetReport),
}

impl Gdl90Message {
    /// Decodes a clear message (ID + data, FCS already checked). `Err(true)` for a known ID with
    /// the wrong length, `Err(false)` for an ID this decoder does not handle.
    pub fn parse(m: &[u8]) -> Result<Self, bool> {
        let id = *m.first().ok_or(false)?;
        match id {
            heartbeat::ID => Heartbeat::decode(m).map(Self::Heartbeat).ok_or(true),
            ownship::ID => TargetReport::decode(m).map(Self::OwnshipReport).ok_or(true),
            geo_altitude::ID => GeoAltitude::decode(m)
                .map(Self::OwnshipGeoAltitude)
                .ok_or(true),
            traffic::ID => TargetReport::decode(m).map(Self::TrafficReport).ok_or(true),
            _ => Err(false),
        }
    }

    /// Appends the clear message (ID + data) to `out`.
    pub fn encode_clear(&self, out: &mut Vec<u8>) {
        match self {
            Self::Heartbeat(h) => out.extend_from_slice(&h.encode()),
            Self::OwnshipReport(r) => out.extend_from_slice(&r.encode(ownship::ID)),
            Self::OwnshipGeoAltitude(g) => out.extend_from_slice(&g.encode()),
            Self::TrafficReport(r) => out.extend_from_slice(&r.encode(traffic::ID)),
        }
    }

    /// The common traffic report of a Traffic Report message (other messages give `None`).
    pub fn to_traffic(&self, altitude: TrafficAltitude) -> Option<TrafficReport> {
        match self {
            Self::TrafficReport(r) => Some(target_to_traffic(r, altitude)),
            _ => None,
        }
    }
}

/// Appends the complete frame of `msg` (flags, escaping, FCS) to `out`.
pub fn encode_frame(msg: &Gdl90Message, out: &mut Vec<u8>) {
    let mut clear = Vec::with_capacity(report::LEN);
    msg.encode_clear(&mut clear);
    framing::frame(&clear, out);
}

/// `tokio_util` encoder of GDL90 frames (for the simulated module and `FramedWrite`).
#[derive(Debug, Clone, Copy, Default)]
pub struct Gdl90Encoder;

impl tokio_util::codec::Encoder<Gdl90Message> for Gdl90Encoder {
    type Error = std::io::Error;

    fn encode(&mut self, msg: Gdl90Message, dst: &mut BytesMut) -> Result<(), Self::Error> {
        let mut out = Vec::with_capacity(2 * report::LEN + 4);
        encode_frame(&msg, &mut out);
        dst.extend_from_slice(&out);
        Ok(())
    }
}

/// What the Traffic Report altitude field holds, per the module's altitude-priority setting
/// (manual 7.2.1): see the module doc.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TrafficAltitude {
    /// Barometric priority (setting 1) and the GDL90 definition: pressure altitude.
    #[default]
    Pressure,
    /// Geometric priority (setting 0): geometric altitude when the target sent one, else
    /// pressure altitude. Mapped to `alt_geometric_m`; the module does not say when it fell back.
    GeometricPreferred,
}

/// True when a Traffic or Ownship Report holds a value out of its range (issue 24).
fn record_invalid(m: &Gdl90Message, altitude: TrafficAltitude) -> bool {
    match m {
        Gdl90Message::TrafficReport(r) | Gdl90Message::OwnshipReport(r) => {
            target_to_traffic(r, altitude).check_values().is_err()
        }
        _ => false,
    }
}

/// Maps a GDL90 target report to the common [`TrafficReport`].
pub fn target_to_traffic(r: &TargetReport, altitude: TrafficAltitude) -> TrafficReport {
    let address_type = match r.address_type {
        AddressKind::AdsbIcao => AddressType::Icao,
        AddressKind::AdsbSelfAssigned => AddressType::NonIcao,
        AddressKind::TisbIcao => AddressType::TisbIcao,
        AddressKind::TisbTrackFile => AddressType::TisbOther,
        AddressKind::SurfaceVehicle | AddressKind::GroundStationBeacon => AddressType::Surface,
        AddressKind::Reserved(_) => AddressType::Unknown,
    };
    let (lat_deg, lon_deg) = if r.has_position() {
        (Some(r.lat_deg), Some(r.lon_deg))
    } else {
        (None, None)
    };
    let alt_m = r.altitude_ft.map(|ft| f64::from(ft) * 0.3048);
    let (alt_pressure_m, alt_geometric_m) = match altitude {
        TrafficAltitude::Pressure => (alt_m, None),
        TrafficAltitude::GeometricPreferred => (None, alt_m),
    };
    let (track_deg, heading_deg) = match r.track_type {
        TrackType::TrueTrack => (Some(r.track_deg), None),
        TrackType::TrueHeading => (None, Some(r.track_deg)),
        TrackType::MagneticHeading | TrackType::NotValid => (None, None),
    };
    TrafficReport {
        callsign: r.callsign_str(),
        emitter_category: Some(r.emitter_category),
        lat_deg,
        lon_deg,
        alt_pressure_m,
        alt_geometric_m,
        track_deg,
        heading_deg,
        ground_speed_mps: r
            .horizontal_velocity
            .kt()
            .map(|kt| f64::from(kt) * 1852.0 / 3600.0),
        vertical_rate_mps: r.vertical_velocity.fpm().map(|f| f64::from(f) * 0.00508),
        nic: Some(r.nic),
        nac_p: Some(r.nac_p),
        emergency_code: Some(r.emergency_code),
        flags: TrafficFlags {
            on_ground: !r.airborne,
            emergency: r.emergency_code != 0,
            relayed: matches!(
                r.address_type,
                AddressKind::TisbIcao | AddressKind::TisbTrackFile
            ),
            degraded: r.nic == 0,
            ..Default::default()
        },
        ..TrafficReport::new(Link::Adsb1090, Protocol::Gdl90, r.address, address_type)
    }
}

/// Sans-IO decoder of a GDL90 byte stream.
#[derive(Debug, Clone, Default)]
pub struct Gdl90Decoder {
    stats: DecodeStats,
    /// Scratch buffer for the unescaped message (reused, never grows past the maximum frame).
    clear: Vec<u8>,
    /// The last thing consumed was a frame with its closing flag (that flag may open the next).
    after_flag: bool,
    altitude: TrafficAltitude,
}

impl Gdl90Decoder {
    /// A decoder whose traffic reports map the altitude field as `altitude` says.
    pub fn new(altitude: TrafficAltitude) -> Self {
        Self {
            altitude,
            clear: Vec::with_capacity(framing::MAX_CLEAR_LEN + 2),
            ..Default::default()
        }
    }

    /// How this decoder maps the Traffic Report altitude.
    pub fn traffic_altitude(&self) -> TrafficAltitude {
        self.altitude
    }
}

impl DeviceDecoder for Gdl90Decoder {
    type Message = Gdl90Message;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<Gdl90Message> {
        loop {
            let first = *buf.first()?;
            let start = if first == FLAG {
                1
            } else if self.after_flag {
                0
            } else {
                let n = buf.iter().position(|&b| b == FLAG).unwrap_or(buf.len());
                self.stats.skip(buf, n);
                continue;
            };
            let limit = buf.len().min(start + MAX_ESCAPED_LEN + 1);
            let Some(rel) = buf[start..limit].iter().position(|&b| b == FLAG) else {
                if buf.len() > start + MAX_ESCAPED_LEN {
                    // No closing flag within the longest possible frame: not a frame. Every
                    // byte searched goes (here `limit` is `start + MAX_ESCAPED_LEN + 1`).
                    self.after_flag = false;
                    self.stats.skip(buf, limit);
                    continue;
                }
                return None;
            };
            let end = start + rel;
            if end == start {
                // An idle flag (two flags in a row).
                self.after_flag = false;
                self.stats.skip(buf, 1);
                continue;
            }
            let parsed = match unframe(&buf[start..end], &mut self.clear) {
                Ok(m) => Ok(Gdl90Message::parse(m)),
                Err(e) => Err(e),
            };
            match parsed {
                Err(e) => {
                    match e {
                        FrameError::Fcs { .. } => self.stats.checksum_failures += 1,
                        FrameError::DanglingEscape | FrameError::TooShort(_) => {
                            self.stats.malformed += 1
                        }
                    }
                    // Leave the closing flag: it may open the next frame.
                    self.after_flag = false;
                    self.stats.skip(buf, end);
                }
                // Issue 24: a Traffic or Ownship Report is one record; an impossible value drops
                // it alone (bytes counted as skipped) and counts it.
                Ok(Ok(msg)) if record_invalid(&msg, self.altitude) => {
                    self.stats.invalid_values += 1;
                    self.after_flag = true;
                    self.stats.skip(buf, end + 1);
                }
                Ok(Ok(msg)) => {
                    self.after_flag = true;
                    self.stats.take_frame(buf, end + 1);
                    return Some(msg);
                }
                Ok(Err(known_id)) => {
                    if known_id {
                        self.stats.malformed += 1;
                    } else {
                        self.stats.unknown_types += 1;
                    }
                    self.after_flag = true;
                    self.stats.skip(buf, end + 1);
                }
            }
        }
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}
