//! TT-Multi-RF text protocol decoding: CSV (`#A` lines), JSON (`adsb` messages with ten targets),
//! the auto-detecting decoder on a mixed stream, and the port decoder (`ttmrf::mixed`) on CSV
//! lines interleaved with raw HEX lines (four per CSV line, as the simulator sends per target).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use std::hint::black_box;
use vigil_drivers::decode_slice;
use vigil_drivers::ttmrf::csv::{
    AdsbAircraft, AircraftFlags, AircraftState, CsvDecoder, CsvMessage, NicNac,
};
use vigil_drivers::ttmrf::json::JsonDecoder;
use vigil_drivers::ttmrf::mixed::MixedDecoder;
use vigil_drivers::ttmrf::raw::{ModeSFrame, RawFrame, RxMeta, hex};
use vigil_drivers::ttmrf::text::{TextDecoder, TextMode};

/// The CSV stream with four HEX lines (extended fields) after every CSV line.
fn csv_with_hex(csv: &[u8]) -> Vec<u8> {
    let mut out = bytes::BytesMut::new();
    for (i, line) in csv.split_inclusive(|&b| b == b'\n').enumerate() {
        out.extend_from_slice(line);
        for k in 0..4u64 {
            let mut bytes = [0u8; 14];
            bytes[0] = 0x8D;
            bytes[1..4].copy_from_slice(&(0x4D2400 + i as u32).to_be_bytes()[1..]);
            bytes[4] = 0x58 + k as u8;
            let f = RawFrame::ModeS(ModeSFrame {
                bytes,
                len: 14,
                meta: RxMeta {
                    signal_dbm: Some(-70),
                    signal_quality: Some(12),
                    ts_pps_ns: Some(123_456_789 + k),
                    ts_utc_ns: Some(47_655_123_456_789 + k),
                    ..RxMeta::default()
                },
            });
            hex::encode_hex(&f, true, &mut out);
        }
    }
    out.to_vec()
}

/// 1000 `#A` lines with varying values and valid CRCs.
fn csv_stream() -> Vec<u8> {
    let mut s = String::new();
    for i in 0..1000u32 {
        let m = CsvMessage::Adsb(AdsbAircraft {
            state: AircraftState {
                icao: 0x4D2400 + i,
                flags: Some(AircraftFlags::from_raw(0x3F00)),
                callsign: Some(format!("TST{i:04}")),
                squawk: Some(7273),
                lat_deg: Some(53.0 + f64::from(i) * 1e-4),
                lon_deg: Some(14.0 + f64::from(i) * 1e-4),
                alt_baro_ft: Some(f64::from(1000 + i * 25)),
                track_deg: Some(f64::from(i % 360)),
                velh_kt: Some(f64::from(100 + i % 400)),
                velv_fpm: Some(f64::from(i % 64) * 64.0 - 2048.0),
                sig_dbm: Some(-71.0),
                sig_q: Some(5.0),
                fps: Some(9),
                nicnac: Some(NicNac::from_raw(0x938)),
                alt_geo_ft: Some(f64::from(1100 + i * 25)),
                ecat: Some(3),
            },
            extra_fields: vec![],
        });
        s.push_str(&m.to_line());
    }
    s.into_bytes()
}

/// 100 JSON messages, each with ten `adsb` targets in the manual's layout.
fn json_stream() -> Vec<u8> {
    let mut s = String::new();
    for m in 0..100u32 {
        s.push_str(&format!(
            r#"{{"src":"33-0000683","ts":{},"ver":1,"adsb":["#,
            69_061_337 + m * 1000
        ));
        for t in 0..10u32 {
            if t > 0 {
                s.push(',');
            }
            s.push_str(&format!(
                r#"{{"icao":"{:06X}","flags":{{"groundState":false,"updAltBaro":true,"updAltGeo":true,"updPosition":true,"updTrack":true,"updVeloH":true,"updVeloV":true}},"sigStr":-67,"sigQ":9,"lat":34.39696,"lon":-85.1055,"altBaro":{},"geoAlt":36975,"track":143.78,"velH":528,"velV":0,"call":"CPA{:04}","ecat":5,"squawk":"5730","nacp":9,"nacv":1,"nicBaro":1,"nic":8}}"#,
                0x780A00 + m * 10 + t,
                30000 + t * 100,
                t
            ));
        }
        s.push_str("]}\r\n");
    }
    s.into_bytes()
}

fn bench(c: &mut Criterion) {
    let csv = csv_stream();
    let json = json_stream();
    let mut mixed = csv.clone();
    mixed.extend_from_slice(&json);

    let mut g = c.benchmark_group("ttmrf_text");
    g.throughput(Throughput::Bytes(csv.len() as u64));
    g.bench_function("csv_1000_adsb_lines", |b| {
        b.iter(|| {
            let mut d = CsvDecoder::new();
            let out = decode_slice(&mut d, black_box(&csv));
            assert_eq!(out.len(), 1000);
            out
        })
    });
    g.throughput(Throughput::Bytes(json.len() as u64));
    g.bench_function("json_100_messages_x10_targets", |b| {
        b.iter(|| {
            let mut d = JsonDecoder::new();
            let out = decode_slice(&mut d, black_box(&json));
            assert_eq!(out.len(), 100);
            out
        })
    });
    g.throughput(Throughput::Bytes(mixed.len() as u64));
    g.bench_function("auto_mixed_csv_json", |b| {
        b.iter(|| {
            let mut d = TextDecoder::new(TextMode::Auto);
            let out = decode_slice(&mut d, black_box(&mixed));
            assert_eq!(out.len(), 1100);
            out
        })
    });
    let port = csv_with_hex(&csv);
    g.throughput(Throughput::Bytes(port.len() as u64));
    g.bench_function("mixed_port_1000_csv_4000_hex", |b| {
        b.iter(|| {
            let mut d = MixedDecoder::new();
            let out = decode_slice(&mut d, black_box(&port));
            assert_eq!(out.len(), 5000);
            out
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
