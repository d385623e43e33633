//! Mapping of a CAT021 record to the common [`TrafficReport`].
//!
//! Decisions (manual 8.2.1 "FLARM ASTERIX protocol" against CAT021 ed 2.1):
//! - **Link.** SAC 0 / SIC 161 marks a FLARM target (the manual's preferred way); otherwise
//!   I021/210 LTT = 1 means UAT, anything else 1090 MHz.
//! - **Emitter category.** Standard I021/020 ECAT values are mapped to the DO-260B/GDL90 set that
//!   [`TrafficReport::emitter_category`] uses ([`ecat_to_emitter`]). For FLARM targets the manual's
//!   table 28 fills I021/020 with the DO-260B numbers themselves (glider 9, rotorcraft 7, UAV 14
//!   ...; 7 and 9 are reserved ECAT values, so these are not ECAT codes): we follow the manual
//!   and take FLARM values as they are. The raw value stays in the record.
//! - **Address type.** ATP 3 (not ICAO-based) on a FLARM target can be a FLARM id or a random id
//!   (the manual uses 3 for both): it maps to [`AddressType::NonIcao`], never to a FLARM kind
//!   it cannot prove.
//! - **FLARM privacy markers.** A FLARM target whose I021/170 reads `STEALTH` or `NOTRACK` has
//!   no call sign; the marker stays in the record.
//! - Surface targets: the RE field's surface ground vector gives the ground speed, and the track
//!   or heading when referenced to true north, where I021/160 is absent; RE/TNH gives the true
//!   heading.
//! - Magnetic heading (I021/152) is not mapped (the report's heading is true); values flagged
//!   "range exceeded" are not exact and are left out; geometric height 0x7FFF ("greater than
//!   204793.75 ft") is left out.

use super::Cat021Record;
use super::kinematics::HEIGHT_LSB_FT;
use crate::traffic::{AddressType, Link, Protocol, SourceTime, TrafficFlags, TrafficReport};

/// ASTERIX CAT021 ed 2.1 ECAT to the DO-260B/GDL90 emitter category; `None` for reserved codes.
pub fn ecat_to_emitter(ecat: u8) -> Option<u8> {
    Some(match ecat {
        // No information, light, small, large, high vortex large, heavy, highly manoeuvrable:
        // the same numbers in both sets.
        0..=6 => ecat,
        10 => 7,  // rotorcraft
        11 => 9,  // glider / sailplane
        12 => 10, // lighter than air
        13 => 14, // unmanned aerial vehicle
        14 => 15, // space / trans-atmospheric
        15 => 12, // ultralight / hang glider / paraglider
        16 => 11, // parachutist / skydiver
        20 => 17, // surface emergency vehicle
        21 => 18, // surface service vehicle
        22 => 19, // fixed ground or tethered obstruction (point obstacle)
        23 => 20, // cluster obstacle
        24 => 21, // line obstacle
        _ => return None,
    })
}

/// The inverse of [`ecat_to_emitter`]: the I021/020 ECAT code of a DO-260B/GDL90 emitter category
/// (for encoders: the simulated module). `None` for categories ECAT has no code for (8, 13, 16).
pub fn emitter_to_ecat(emitter: u8) -> Option<u8> {
    (0..=24).find(|&ecat| ecat_to_emitter(ecat) == Some(emitter))
}

/// The emitter category of a record in the [`TrafficReport`] numbering (see the module doc).
pub fn emitter_category(r: &Cat021Record) -> Option<u8> {
    let raw = r.emitter_category?;
    if r.data_source.is_some_and(|s| s.is_flarm()) {
        Some(raw)
    } else {
        ecat_to_emitter(raw)
    }
}

/// Seconds of day to nanoseconds.
fn tod_ns(s: f64) -> u64 {
    (s * 1e9).round().max(0.0) as u64
}

/// The record's time: time of applicability for position (I021/071), else time of reception of
/// position refined by its high-precision item (I021/073 + 074), else I021/073 alone.
pub fn source_time(r: &Cat021Record) -> Option<SourceTime> {
    let s = r.time_applicability_position_s.or_else(|| {
        let coarse = r.time_reception_position_s?;
        Some(
            r.time_reception_position_hp
                .and_then(|hp| hp.full_time_s(coarse))
                .unwrap_or(coarse),
        )
    })?;
    Some(SourceTime::AsterixTodNs(tod_ns(s)))
}

/// Maps a CAT021 record to the common traffic report.
pub fn to_traffic(r: &Cat021Record) -> TrafficReport {
    let flarm = r.data_source.is_some_and(|s| s.is_flarm());
    let link = if flarm {
        Link::Flarm
    } else if r.mops.is_some_and(|m| m.ltt == 1) {
        Link::Uat978
    } else {
        Link::Adsb1090
    };
    // Without I021/080 there is no address to qualify: address 0 of unknown type.
    let address_type = match r.target_address.and(r.descriptor).map(|d| d.atp) {
        Some(0 | 1) => AddressType::Icao,
        Some(2) => AddressType::Surface,
        Some(3) => AddressType::NonIcao,
        _ => AddressType::Unknown,
    };
    let callsign = r
        .target_id
        .as_ref()
        .filter(|id| !id.is_empty() && !(flarm && (*id == "STEALTH" || *id == "NOTRACK")))
        .cloned();
    let position = r.position_high_res.or(r.position);
    let ext1 = r.descriptor.and_then(|d| d.ext1);
    let ext2 = r.descriptor.and_then(|d| d.ext2);
    let quality = r.quality;
    let status = r.target_status;
    let vrate = r
        .baro_vertical_rate
        .filter(|v| !v.range_exceeded)
        .or(r.geo_vertical_rate.filter(|v| !v.range_exceeded));
    let max_height = f64::from(i16::MAX) * HEIGHT_LSB_FT;
    // Surface ground vector (RE/SGV): used when the airborne vector I021/160 is absent; its
    // angle only when valid and referenced to true north.
    let sgv = r.reserved.as_ref().and_then(|re| re.surface_vector);
    let sgv_true = |ground_track: bool| {
        sgv.filter(|v| v.hgt_valid && !v.magnetic && v.is_ground_track == ground_track)
            .and_then(|v| v.hgt_deg)
    };
    TrafficReport {
        link,
        protocol: Protocol::Asterix,
        address: r.target_address.unwrap_or(0),
        address_type,
        callsign,
        squawk: r.mode3a,
        emitter_category: emitter_category(r),
        lat_deg: position.map(|p| p.lat_deg),
        lon_deg: position.map(|p| p.lon_deg),
        alt_pressure_m: r.flight_level.map(|fl| fl * 100.0 * 0.3048),
        alt_geometric_m: r
            .geometric_height_ft
            .filter(|&ft| ft < max_height)
            .map(|ft| ft * 0.3048),
        track_deg: r.ground_vector.map(|g| g.track_deg).or(sgv_true(true)),
        heading_deg: r
            .reserved
            .as_ref()
            .and_then(|re| re.true_heading_deg)
            .or(sgv_true(false)),
        ground_speed_mps: r
            .ground_vector
            .filter(|g| !g.range_exceeded)
            .map(|g| g.ground_speed_kt)
            .or(sgv.map(|v| v.ground_speed_kt))
            .map(|kt| kt * 1852.0 / 3600.0),
        vertical_rate_mps: vrate.map(|v| v.fpm * 0.00508),
        nic: quality.map(|q| q.nic),
        nac_p: quality.and_then(|q| q.ext1).map(|e| e.nac_p),
        nac_v: quality.map(|q| q.nac_v),
        sil: quality.and_then(|q| q.ext1).map(|e| e.sil),
        signal_dbm: r.amplitude_dbm.map(f64::from),
        emergency_code: status.map(|s| s.ps),
        flarm_alarm_level: None,
        flags: TrafficFlags {
            on_ground: ext1.is_some_and(|e| e.gbs),
            ident: status.is_some_and(|s| s.ss == 3),
            emergency: status.is_some_and(|s| s.ps != 0 || s.ss == 1),
            relayed: false,
            degraded: ext1.is_some_and(|e| e.cl == 1 || e.cl == 3)
                || ext2.is_some_and(|e| e.ipc || e.nogo || e.cpr || e.ldpj || e.rcf),
            test: ext1.is_some_and(|e| e.sim || e.tst),
        },
        source_time: source_time(r),
        data_age_s: data_age_s(r),
    }
}

/// Age of the position at the report's transmission, s: I021/077 minus I021/071 (times of day,
/// the difference taken across midnight); `None` without both, or when the difference is not in
/// [0, 60) s (a time that cannot be an age is not used).
pub fn data_age_s(r: &Cat021Record) -> Option<f64> {
    let (tx, app) = (
        r.time_report_transmission_s?,
        r.time_applicability_position_s?,
    );
    let d = (tx - app).rem_euclid(86_400.0);
    (d.is_finite() && d < 60.0).then_some(d)
}

#[cfg(test)]
mod tests {
    use super::super::reserved::{ReservedExpansion, SurfaceGroundVector};
    use super::super::status::{DescriptorExt1, DescriptorExt2, TargetReportDescriptor};
    use super::*;

    #[test]
    fn surface_vector_fallbacks() {
        let sgv = SurfaceGroundVector {
            stopped: false,
            hgt_valid: true,
            is_ground_track: true,
            magnetic: false,
            ground_speed_kt: 8.0,
            hgt_deg: Some(45.0),
        };
        let mut r = Cat021Record {
            reserved: Some(ReservedExpansion {
                surface_vector: Some(sgv),
                ..Default::default()
            }),
            ..Default::default()
        };
        let t = to_traffic(&r);
        // 8 kt = 8 * 1852 / 3600 m/s; a true-north ground track is a track.
        assert!((t.ground_speed_mps.unwrap() - 8.0 * 1852.0 / 3600.0).abs() < 1e-12);
        assert_eq!((t.track_deg, t.heading_deg), (Some(45.0), None));
        // A true heading is a heading; RE/TNH wins over it.
        let heading = SurfaceGroundVector {
            is_ground_track: false,
            ..sgv
        };
        r.reserved = Some(ReservedExpansion {
            surface_vector: Some(heading),
            ..Default::default()
        });
        assert_eq!(to_traffic(&r).heading_deg, Some(45.0));
        r.reserved = Some(ReservedExpansion {
            surface_vector: Some(heading),
            true_heading_deg: Some(50.0),
            ..Default::default()
        });
        assert_eq!(to_traffic(&r).heading_deg, Some(50.0));
        // Not valid: no angle at all.
        r.reserved = Some(ReservedExpansion {
            surface_vector: Some(SurfaceGroundVector {
                hgt_valid: false,
                ..sgv
            }),
            ..Default::default()
        });
        assert_eq!(to_traffic(&r).track_deg, None);
    }

    #[test]
    fn ecat_table() {
        // Every ECAT code of CAT021 ed 2.1 I021/020 against the DO-260B / GDL 90 (3.5.1.10)
        // emitter category of the same meaning, by name.
        for (ecat, emitter, name) in [
            (0, 0, "no information"),
            (1, 1, "light"),
            (2, 2, "small"),
            (3, 3, "medium / large"),
            (4, 4, "high vortex large"),
            (5, 5, "heavy"),
            (6, 6, "highly manoeuvrable"),
            (10, 7, "rotorcraft"),
            (11, 9, "glider / sailplane"),
            (12, 10, "lighter than air"),
            (13, 14, "unmanned aerial vehicle"),
            (14, 15, "space / trans-atmospheric"),
            (15, 12, "ultralight / hang glider / paraglider"),
            (16, 11, "parachutist / skydiver"),
            (20, 17, "surface emergency vehicle"),
            (21, 18, "surface service vehicle"),
            (22, 19, "point obstacle"),
            (23, 20, "cluster obstacle"),
            (24, 21, "line obstacle"),
        ] {
            assert_eq!(ecat_to_emitter(ecat), Some(emitter), "{name}");
        }
        for reserved in [7, 8, 9, 17, 18, 19, 25, 255] {
            assert_eq!(ecat_to_emitter(reserved), None);
        }
    }

    #[test]
    fn flight_level_degraded_flags_and_data_age() {
        // FL 50 = 5,000 ft = 1,524 m.
        let r = Cat021Record {
            flight_level: Some(50.0),
            ..Default::default()
        };
        assert!((to_traffic(&r).alt_pressure_m.unwrap() - 1524.0).abs() < 1e-9);
        // I021/140 up to 0x7FFE counts (204,787.5 ft) is a height: 40,000 ft = 12,192 m; 0x7FFF
        // (204,793.75 ft) means "greater than that" and is left out.
        let geo = |ft: f64| {
            to_traffic(&Cat021Record {
                geometric_height_ft: Some(ft),
                ..Default::default()
            })
            .alt_geometric_m
        };
        assert!((geo(40_000.0).unwrap() - 12_192.0).abs() < 1e-9);
        assert!((geo(204_787.5).unwrap() - 204_787.5 * 0.3048).abs() < 1e-9);
        assert_eq!(geo(204_793.75), None);
        // Each failed check of I021/040's second extension alone marks the report degraded.
        let degraded = |ext2: DescriptorExt2| {
            to_traffic(&Cat021Record {
                descriptor: Some(TargetReportDescriptor {
                    ext1: Some(DescriptorExt1::default()),
                    ext2: Some(ext2),
                    ..Default::default()
                }),
                ..Default::default()
            })
            .flags
            .degraded
        };
        let none = DescriptorExt2::default();
        assert!(!degraded(none));
        for one in [
            DescriptorExt2 { ipc: true, ..none },
            DescriptorExt2 { nogo: true, ..none },
            DescriptorExt2 { cpr: true, ..none },
            DescriptorExt2 { ldpj: true, ..none },
            DescriptorExt2 { rcf: true, ..none },
        ] {
            assert!(degraded(one), "{one:?}");
        }
        // Data age = I021/077 (transmission) - I021/071 (position applicability), seconds of
        // day, across midnight; not an age when negative or 60 s or more.
        let age = |tx: Option<f64>, app: Option<f64>| {
            data_age_s(&Cat021Record {
                time_report_transmission_s: tx,
                time_applicability_position_s: app,
                ..Default::default()
            })
        };
        assert_eq!(age(Some(45_000.5), Some(45_000.0)), Some(0.5));
        assert_eq!(age(Some(45_000.0), Some(45_000.0)), Some(0.0));
        assert_eq!(age(Some(45_059.75), Some(45_000.0)), Some(59.75));
        assert_eq!(age(Some(45_060.0), Some(45_000.0)), None);
        assert_eq!(
            age(Some(45_000.0), Some(45_000.5)),
            None,
            "position after the report"
        );
        assert_eq!(
            age(Some(0.25), Some(86_399.75)),
            Some(0.5),
            "across midnight"
        );
        assert_eq!(age(None, Some(45_000.0)), None);
        assert_eq!(age(Some(45_000.0), None), None);
        assert_eq!(age(Some(f64::NAN), Some(45_000.0)), None);
        assert_eq!(
            to_traffic(&Cat021Record {
                time_report_transmission_s: Some(45_000.5),
                time_applicability_position_s: Some(45_000.0),
                ..Default::default()
            })
            .data_age_s,
            Some(0.5)
        );
    }

    #[test]
    fn emitter_to_ecat_inverts_the_table() {
        // CAT021 ed 2.1 I021/020: rotorcraft 10, glider 11, UAV 13, parachutist 16.
        assert_eq!(emitter_to_ecat(7), Some(10));
        assert_eq!(emitter_to_ecat(9), Some(11));
        assert_eq!(emitter_to_ecat(14), Some(13));
        assert_eq!(emitter_to_ecat(11), Some(16));
        assert_eq!(emitter_to_ecat(3), Some(3));
        // DO-260B 8, 13, 16 are unassigned: no ECAT code.
        for e in [8, 13, 16, 22] {
            assert_eq!(emitter_to_ecat(e), None);
        }
        for e in 0..=21 {
            if let Some(c) = emitter_to_ecat(e) {
                assert_eq!(ecat_to_emitter(c), Some(e));
            }
        }
    }
}
