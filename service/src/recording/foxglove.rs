//! Foxglove's well-known message schemas, in their JSON form, for the Map and Log panels (issue
//! 20): `foxglove.LocationFix` (ownship), `foxglove.GeoJSON` (traffic) and `foxglove.Log`
//! (alerts). The Foxglove and Lichtblick apps recognise a channel by its schema name; the fields
//! follow the Foxglove schema definitions (docs.foxglove.dev, "Message schemas"). The JSON
//! Schemas are generated from these types like the others.
//!
//! Decisions:
//! - Timestamps are the data's time of validity, GPS time converted to UTC with the leap-second
//!   table (the same timeline as the recording's log times).
//! - `LocationFix.altitude`: geometric (ellipsoid) altitude, else pressure altitude, else 0. The
//!   covariance: the 1-sigma horizontal uncertainty on both horizontal axes; the vertical one is not
//!   known, so it is widened to three times the horizontal, and the type is APPROXIMATED (1).
//! - `Log.level`: advisory INFO (2), caution WARNING (3), warning ERROR (4); a cleared alert INFO.

use schemars::JsonSchema;
use serde::Serialize;
use serde_json::json;
use vigil_fusion::time::gps;

use super::messages::{Alert, Ownship, Traffic};

/// `foxglove.Time`: seconds and nanoseconds since the Unix epoch (UTC).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, JsonSchema)]
pub struct Time {
    /// Seconds.
    pub sec: u32,
    /// Nanoseconds.
    pub nsec: u32,
}

impl Time {
    /// UTC of a GPS time (ns since 1980-01-06), `None` outside the u32 seconds range.
    pub fn of_gps(t_gps_ns: i64) -> Option<Self> {
        let approx_unix_s = t_gps_ns.div_euclid(gps::NS_PER_S) + gps::GPS_EPOCH_UNIX_S;
        let leap = gps::gps_minus_utc_s(approx_unix_s).gps_minus_utc_s;
        let unix_ns = gps::unix_ns_from_gps_ns(t_gps_ns, leap);
        Some(Self {
            sec: u32::try_from(unix_ns.div_euclid(gps::NS_PER_S)).ok()?,
            nsec: u32::try_from(unix_ns.rem_euclid(gps::NS_PER_S)).ok()?,
        })
    }
}

/// `foxglove.LocationFix`: a WGS-84 position.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(rename = "foxglove.LocationFix")]
pub struct LocationFix {
    /// Time of validity.
    pub timestamp: Time,
    /// Frame of reference (empty).
    pub frame_id: String,
    /// Latitude, deg.
    pub latitude: f64,
    /// Longitude, deg.
    pub longitude: f64,
    /// Altitude, m.
    pub altitude: f64,
    /// Position covariance (east, north, up), m^2, row-major.
    pub position_covariance: [f64; 9],
    /// 0 unknown, 1 approximated, 2 diagonal known, 3 known.
    pub position_covariance_type: u8,
}

impl LocationFix {
    /// The fix of an ownship message; `None` without a position or a time.
    pub fn of(o: &Ownship) -> Option<Self> {
        let (lat, lon) = (o.lat_deg?, o.lon_deg?);
        let s2 = o.position_sigma_m.map_or(0.0, |s| s * s);
        Some(Self {
            timestamp: Time::of_gps(o.t_gps_ns)?,
            frame_id: String::new(),
            latitude: lat,
            longitude: lon,
            altitude: o.alt_geometric_m.or(o.alt_pressure_m).unwrap_or(0.0),
            position_covariance: [s2, 0.0, 0.0, 0.0, s2, 0.0, 0.0, 0.0, 9.0 * s2],
            position_covariance_type: if o.position_sigma_m.is_some() { 1 } else { 0 },
        })
    }
}

/// `foxglove.GeoJSON`: a GeoJSON document as text.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(rename = "foxglove.GeoJSON")]
pub struct GeoJson {
    /// The GeoJSON text.
    pub geojson: String,
}

impl GeoJson {
    /// The targets of a traffic picture as a FeatureCollection of points with their address,
    /// callsign, alert level and distance.
    pub fn of(t: &Traffic) -> Self {
        let features: Vec<_> = t
            .targets
            .iter()
            .filter_map(|x| {
                let (lat, lon) = (x.lat_deg?, x.lon_deg?);
                Some(json!({
                    "type": "Feature",
                    "geometry": {"type": "Point", "coordinates": [lon, lat]},
                    "properties": {
                        "name": x.callsign.clone().unwrap_or_else(|| x.address.clone()),
                        "address": x.address,
                        "alert_level": x.alert_level,
                        "horizontal_distance_m": x.horizontal_distance_m,
                    },
                }))
            })
            .collect();
        Self {
            geojson: json!({"type": "FeatureCollection", "features": features}).to_string(),
        }
    }
}

/// `foxglove.Log`: a log line.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[schemars(rename = "foxglove.Log")]
pub struct Log {
    /// Time of the event.
    pub timestamp: Time,
    /// 0 unknown, 1 debug, 2 info, 3 warning, 4 error, 5 fatal.
    pub level: u8,
    /// The text.
    pub message: String,
    /// Source name.
    pub name: String,
    /// Source file (empty).
    pub file: String,
    /// Source line (0).
    pub line: u32,
}

impl Log {
    /// The log line of an alert transition; `None` without a time.
    pub fn of(a: &Alert) -> Option<Self> {
        use vigil_bus::payload::alerts::{SEVERITY_ADVISORY, SEVERITY_CAUTION};
        let level = match (a.state.as_str(), a.severity) {
            ("cleared", _) | (_, SEVERITY_ADVISORY) => 2,
            (_, SEVERITY_CAUTION) => 3,
            _ => 4,
        };
        Some(Self {
            timestamp: Time::of_gps(a.t_gps_ns)?,
            level,
            message: format!(
                "{} {}: {}",
                a.rule.as_deref().unwrap_or("alert"),
                a.state,
                a.reason
            ),
            name: "vigil.monitor".to_string(),
            file: String::new(),
            line: 0,
        })
    }
}
