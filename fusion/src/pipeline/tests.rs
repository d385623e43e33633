//! The pipeline's step grid and bookkeeping, with TT-Multi-RF JSON messages (the manual's GNSS
//! example, section 6.6) as the only input: the ownship comes from the TT-Multi-RF GNSS and the
//! traffic from the JSON `adsb` array.

use vigil_drivers::decode_slice;
use vigil_drivers::ttmrf::text::{TextDecoder, TextMode};

use super::*;
use crate::magnetic::FixedDeclination;
use crate::time::{Aligned, NotAligned, TimeSource};
use approx::assert_relative_eq;

const S: i64 = 1_000_000_000;
const T0: i64 = 1_400_000_000 * S;

/// The manual's GNSS example with one ADS-B target 0.01 deg north of it (1.11 km), same
/// altitude; the target reports no velocity, the GNSS its `gndSpeed`.
const LINE: &str = concat!(
    r#"{"src":"ID-0000001","ts":69061337,"ver":1,"#,
    r#""adsb":[{"icao":"4D240E","lat":53.43854,"lon":14.55281,"altGeo":1640,"altBaro":1640}],"#,
    r#""gnss":{"fix":1,"lat":53.42854,"lon":14.55281,"altWgs84":499.6,"altMsl":508.6,"#,
    r#""track":127.3,"hvelo":10.5,"vVelo":25,"gndSpeed":[5.2,2.1],"#,
    r#""acc":{"lat":5.2,"lon":2.1,"alt":3.6},"nacp":12,"nacv":2,"nic":12}}"#,
    "\r\n"
);

fn message() -> Sample {
    let mut d = TextDecoder::new(TextMode::Auto);
    let mut m = decode_slice(&mut d, LINE.as_bytes());
    assert_eq!(m.len(), 1, "{m:?}");
    Sample::TtText(Box::new(m.remove(0)))
}

fn sample(index: u64, t: Option<i64>, status: ClockStatus) -> AlignedSample {
    AlignedSample {
        device: Device::Ttmrf,
        index,
        aligned: Aligned {
            message: message(),
            time: t
                .map(|t| AlignedTime {
                    t_gps_ns: t,
                    sigma_ns: 1e5,
                    source: TimeSource::HostClock,
                    status,
                })
                .ok_or(NotAligned::HostClockUnknown),
        },
    }
}

fn pipeline() -> Pipeline {
    let decl = FixedDeclination(crate::magnetic::Declination {
        declination_rad: 0.0,
        sigma_rad: 0.01,
        horizontal_nt: 20_000.0,
        zone: crate::magnetic::MagneticZone::Normal,
    });
    Pipeline::new(PipelineConfig::default(), Box::new(decl)).unwrap()
}

fn steps(out: &[Fused]) -> Vec<i64> {
    out.iter()
        .filter_map(|o| match o {
            Fused::Traffic(p) => Some((p.t_gps_ns - T0) / (S / 10)),
            _ => None,
        })
        .collect()
}

#[test]
fn steps_fall_on_the_grid_once_a_locked_sample_reaches_them() {
    let mut p = pipeline();
    let mut out = Vec::new();
    // The first sample at T0 + 0.3 s: the first grid point at or after it is T0 + 1 s, not yet.
    p.handle(
        &sample(0, Some(T0 + 3 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert!(steps(&out).is_empty());
    // T0 + 1.2 s: the step at 1 s (in tenths of a second after T0: 10), taken before the sample
    // at 1.2 s is used; T0 + 2.5 s: the step at 2 s (the fix of 1.2 s is 0.8 s old).
    p.handle(
        &sample(1, Some(T0 + 12 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(steps(&out), [10]);
    p.handle(
        &sample(2, Some(T0 + 25 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(steps(&out), [10, 20]);
    // No step without a fresh ownship (older than max_age_s = 1.5 s): at 4 s the newest fix is
    // from 2.5 s.
    p.handle(
        &sample(3, Some(T0 + 41 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(steps(&out), [10, 20, 30, 40]);
    p.handle(
        &sample(4, Some(T0 + 62 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    // 5 s: the fix of 4.1 s is 0.9 s old; 6 s: 1.9 s, too old.
    assert_eq!(steps(&out), [10, 20, 30, 40, 50]);
    // Each step gives the ownship, then the picture.
    let kinds: Vec<_> = out
        .iter()
        .map(|o| match o {
            Fused::Ownship(_) => 'o',
            Fused::Traffic(_) => 't',
            Fused::Attitude(_) | Fused::Prompt(_) => 'a',
        })
        .collect();
    assert_eq!(kinds, ['o', 't'].repeat(5));
}

#[test]
fn unlocked_and_unaligned_samples_do_not_move_the_clock_and_are_counted() {
    let mut p = pipeline();
    let mut out = Vec::new();
    p.handle(&sample(0, Some(T0 + S / 2), ClockStatus::Locked), &mut out);
    // An unlocked guess 100 s ahead, and a sample without a time.
    p.handle(
        &sample(1, Some(T0 + 100 * S), ClockStatus::Unlocked),
        &mut out,
    );
    p.handle(&sample(2, None, ClockStatus::Locked), &mut out);
    assert!(steps(&out).is_empty());
    p.handle(
        &sample(3, Some(T0 + 15 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(steps(&out), [10]);
    let act = p
        .activity()
        .iter()
        .find(|(d, _)| *d == Device::Ttmrf)
        .unwrap()
        .1;
    assert_eq!((act.samples, act.not_aligned, act.unlocked), (4, 1, 1));
    assert_eq!(act.last_t_gps_ns, Some(T0 + 15 * S / 10));
}

#[test]
fn a_jump_restarts_the_grid_instead_of_emitting_every_step() {
    let mut p = pipeline();
    let mut out = Vec::new();
    p.handle(&sample(0, Some(T0 + S / 2), ClockStatus::Locked), &mut out);
    p.handle(
        &sample(1, Some(T0 + 15 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(steps(&out), [10]);
    // 60 s later (beyond max_step_gap_s = 10 s): the grid restarts at 60 s (no ownship there:
    // the fix is 59 s old), then goes on from 61 s; not the 59 steps in between.
    p.handle(
        &sample(2, Some(T0 + 605 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    p.handle(
        &sample(3, Some(T0 + 612 * S / 10), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(steps(&out), [10, 610]);
}

#[test]
fn the_picture_holds_the_json_target_with_its_geometry() {
    let mut p = pipeline();
    let mut out = Vec::new();
    p.handle(&sample(0, Some(T0 + S / 2), ClockStatus::Locked), &mut out);
    p.handle(
        &sample(1, Some(T0 + 3 * S / 2), ClockStatus::Locked),
        &mut out,
    );
    assert_eq!(p.reports(), 2);
    let own = out
        .iter()
        .find_map(|o| match o {
            Fused::Ownship(o) => Some(o),
            _ => None,
        })
        .unwrap();
    assert_eq!(
        own.ownship.source,
        crate::ownship::PositionSource::TtMultiRfGnss
    );
    // The fix of T0 + 0.5 s carried to the step at T0 + 1 s along its `gndSpeed` (east 5.2,
    // north 2.1 kt): 0.5402 m north and 1.3376 m east; by hand with the WGS-84 radii at
    // 53.43 deg (M = 6 376 694.9 m, N = 6 391 951.6 m): +4.8535e-6 deg of latitude and
    // +1.2252e-5 deg of longitude.
    assert_relative_eq!(own.ownship.lat_deg, 53.428_544_853_5, epsilon = 1e-9);
    assert_relative_eq!(own.ownship.lon_deg, 14.552_830_122_5, epsilon = 1e-9);
    // Its sigma: the fix's sqrt((5.2^2 + 2.1^2) / 2) = sqrt(15.725) = 3.96548 m and NACv 2's
    // 1.5 m/s over the 0.5 s, 0.75 m, root-sum-square: sqrt(16.2875) = 4.03578 m.
    assert_relative_eq!(
        own.ownship.position_sigma_m.unwrap(),
        4.035_78,
        epsilon = 1e-5
    );
    let pic = out
        .iter()
        .find_map(|o| match o {
            Fused::Traffic(p) => Some(p),
            _ => None,
        })
        .unwrap();
    assert_eq!(pic.targets.len(), 1);
    let t = &pic.targets[0];
    assert_eq!(t.key.address, 0x4D240E);
    // 0.01 deg of latitude at 53.4 deg on WGS-84: meridian radius M = a (1 - e^2) / W^3 with
    // W = sqrt(1 - e^2 sin^2 lat) = 0.997 813; M = 6 383 000 m; 0.01 deg -> 1114.0 m due north.
    assert!((t.bearing_true_deg - 0.0).abs() < 0.1 || (t.bearing_true_deg - 360.0).abs() < 0.1);
    let g = t.geometry.as_ref().unwrap_or_else(|| panic!("{t:?}"));
    assert!(
        (g.horizontal_distance_m - 1114.0).abs() < 2.0,
        "{}",
        g.horizontal_distance_m
    );
}

#[test]
fn extreme_and_disordered_times_do_not_panic() {
    let mut p = pipeline();
    let mut out = Vec::new();
    let times = [
        T0,
        i64::MAX,
        i64::MIN,
        0,
        -1,
        T0 - 100 * S,
        i64::MAX - 1,
        T0 + 1,
        i64::MIN + 1,
    ];
    for (i, &t) in times.iter().enumerate() {
        for status in [
            ClockStatus::Locked,
            ClockStatus::Coasting,
            ClockStatus::Locking,
        ] {
            p.handle(&sample(i as u64, Some(t), status), &mut out);
        }
    }
    p.finish(&mut out);
    // Every step the pipeline took lies on the 1 s grid.
    assert!(
        out.iter()
            .all(|o| o.t_gps_ns().rem_euclid(S) == 0 || matches!(o, Fused::Attitude(_)))
    );
}
