//! Decoding speed of the TT-Multi-RF binary protocols: GDL90, ASTERIX (CAT021 + CAT023) and
//! MAVLink, over streams that look like the module's once-per-second output with 50 targets.
//!
//! Each format is measured twice over the same stream: throughput in bytes (MB/s) and in
//! messages (the inverse is ns per message).

use std::hint::black_box;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use vigil_drivers::DeviceDecoder;
use vigil_drivers::testkit::decode_chunked;
use vigil_drivers::ttmrf::asterix::cat021::Cat021Record;
use vigil_drivers::ttmrf::asterix::cat021::kinematics::{GroundVector, Position, VerticalRate};
use vigil_drivers::ttmrf::asterix::cat021::status::{
    QualityExt1, QualityIndicators, TargetReportDescriptor,
};
use vigil_drivers::ttmrf::asterix::cat023::Cat023Record;
use vigil_drivers::ttmrf::asterix::common::DataSource;
use vigil_drivers::ttmrf::asterix::{AsterixDecoder, AsterixMessage, encode_block};
use vigil_drivers::ttmrf::gdl90::geo_altitude::{GeoAltitude, Vfom};
use vigil_drivers::ttmrf::gdl90::heartbeat::Heartbeat;
use vigil_drivers::ttmrf::gdl90::report::{
    HorizontalVelocity, TargetReport, TrackType, VerticalVelocity,
};
use vigil_drivers::ttmrf::gdl90::{Gdl90Decoder, Gdl90Message, encode_frame};
use vigil_drivers::ttmrf::mavlink::{AdsbVehicle, FrameInfo, MavlinkDecoder, encode_adsb_vehicle};

/// Seconds of output in each stream.
const SECONDS: usize = 200;
/// Targets per second.
const TARGETS: usize = 50;

fn gdl90_stream() -> (Vec<u8>, usize) {
    let mut out = Vec::new();
    let mut n = 0;
    for s in 0..SECONDS {
        let own = TargetReport {
            address: 0xABCDEF,
            lat_deg: 52.0,
            lon_deg: 21.0,
            altitude_ft: Some(1500),
            airborne: true,
            nic: 9,
            nac_p: 10,
            ..Default::default()
        };
        let mut msgs = vec![
            Gdl90Message::Heartbeat(Heartbeat {
                gps_pos_valid: true,
                uat_initialized: true,
                utc_ok: true,
                timestamp_s: s as u32,
                ..Default::default()
            }),
            Gdl90Message::OwnshipReport(own),
            Gdl90Message::OwnshipGeoAltitude(GeoAltitude {
                geo_altitude_ft: 1650,
                vertical_warning: false,
                vfom: Vfom::Meters(8),
            }),
        ];
        for t in 0..TARGETS {
            msgs.push(Gdl90Message::TrafficReport(TargetReport {
                address: 0x400000 + t as u32 * 0x1357,
                lat_deg: 52.0 + t as f64 * 0.01,
                lon_deg: 21.0 - t as f64 * 0.01,
                altitude_ft: Some(3000 + 100 * t as i32),
                airborne: true,
                track_type: TrackType::TrueTrack,
                track_deg: (t * 7 % 360) as f64,
                nic: 8,
                nac_p: 9,
                horizontal_velocity: HorizontalVelocity::Kt(120 + t as u16),
                vertical_velocity: VerticalVelocity::Fpm(-640),
                emitter_category: 1,
                callsign: *b"TEST123 ",
                ..own
            }));
        }
        for m in &msgs {
            encode_frame(m, &mut out);
        }
        n += msgs.len();
    }
    (out, n)
}

fn cat021(t: usize) -> Cat021Record {
    Cat021Record {
        data_source: Some(DataSource { sac: 0, sic: 129 }),
        descriptor: Some(TargetReportDescriptor::default()),
        track_number: Some(t as u16),
        time_applicability_position_s: Some(36_000.5),
        position_high_res: Some(Position {
            lat_deg: 52.0 + t as f64 * 0.01,
            lon_deg: 21.0,
        }),
        target_address: Some(0x400000 + t as u32),
        time_reception_position_s: Some(36_000.5),
        geometric_height_ft: Some(3150.0),
        quality: Some(QualityIndicators {
            nac_v: 2,
            nic: 8,
            ext1: Some(QualityExt1 {
                nic_baro: true,
                sil: 3,
                nac_p: 9,
            }),
            ..Default::default()
        }),
        mode3a: Some(7000),
        flight_level: Some(30.0),
        baro_vertical_rate: Some(VerticalRate {
            range_exceeded: false,
            fpm: -500.0,
        }),
        ground_vector: Some(GroundVector {
            range_exceeded: false,
            ground_speed_kt: 120.0,
            track_deg: 90.0,
        }),
        target_id: Some("TEST123".into()),
        emitter_category: Some(1),
        amplitude_dbm: Some(-70),
        ..Default::default()
    }
}

fn asterix_stream() -> (Vec<u8>, usize) {
    let mut out = Vec::new();
    let mut n = 0;
    for s in 0..SECONDS {
        AsterixMessage::Cat023(Box::new(Cat023Record {
            data_source: Some(DataSource { sac: 0, sic: 129 }),
            report_type: Some(1),
            time_of_day_s: Some(s as f64),
            ..Default::default()
        }))
        .encode_block(&mut out);
        n += 1;
        // Targets in blocks of 10 records.
        for chunk in 0..TARGETS / 10 {
            let mut recs = Vec::new();
            for t in 0..10 {
                cat021(chunk * 10 + t).encode(&mut recs);
            }
            encode_block(21, &recs, &mut out);
            n += 10;
        }
    }
    (out, n)
}

fn mavlink_stream() -> (Vec<u8>, usize) {
    let mut out = Vec::new();
    let mut n = 0;
    for s in 0..SECONDS {
        for t in 0..TARGETS {
            let frame = FrameInfo {
                version: 2,
                sequence: (s * TARGETS + t) as u8,
                system_id: 1,
                component_id: 156,
                signed: false,
            };
            let v = AdsbVehicle {
                icao_address: 0x400000 + t as u32,
                lat_deg: 52.0,
                lon_deg: 21.0,
                altitude_m: 900.0,
                altitude_type: 0,
                heading_deg: 90.0,
                hor_velocity_mps: 60.0,
                ver_velocity_mps: -2.5,
                flags: 0x01FF,
                squawk: 7000,
                callsign: "TEST123".into(),
                emitter_type: 1,
                tslc_s: 1,
            };
            encode_adsb_vehicle(&frame, &v, &mut out);
            n += 1;
        }
    }
    (out, n)
}

fn bench_format<D: DeviceDecoder>(
    c: &mut Criterion,
    name: &str,
    make: impl Fn() -> D,
    (bytes, n): (Vec<u8>, usize),
) {
    // The stream decodes completely, without skipping (checked once, outside the timing).
    let (msgs, stats) = decode_chunked(make(), &bytes, &[4096]);
    assert_eq!(msgs.len(), n, "{name}");
    assert_eq!(stats.bytes_skipped, 0, "{name}");
    for (unit, throughput) in [
        ("bytes", Throughput::Bytes(bytes.len() as u64)),
        ("messages", Throughput::Elements(n as u64)),
    ] {
        let mut g = c.benchmark_group(format!("ttmrf_{name}_{unit}"));
        g.throughput(throughput);
        g.bench_function("decode_4k_chunks", |b| {
            b.iter(|| {
                let (msgs, _) = decode_chunked(make(), black_box(&bytes), &[4096]);
                black_box(msgs.len())
            })
        });
        g.finish();
    }
}

fn benches(c: &mut Criterion) {
    bench_format(c, "gdl90", Gdl90Decoder::default, gdl90_stream());
    bench_format(c, "asterix", AsterixDecoder::default, asterix_stream());
    bench_format(c, "mavlink", MavlinkDecoder::new, mavlink_stream());
}

criterion_group!(ttmrf_binary, benches);
criterion_main!(ttmrf_binary);
