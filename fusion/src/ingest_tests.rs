//! The ingest stage with synthetic chunks (the simulator has no VN-200 model yet): VN-200
//! binary frames (the driver's encoder) at 40 Hz, one per read, on a host clock 4 s ahead of GPS
//! with a 1 ms link delay; Watson lines (the driver's encoder) every 100 ms, cut into two reads.

use crate::time::aligner::Device;
use crate::time::host_timed::tx_ns;
use vigil_drivers::vn200::binary::{BinaryOutput, CommonGroup};
use vigil_drivers::vn200::status::InsStatus;
use vigil_drivers::watson::{Kind, Line};

use super::*;

const MS: i64 = 1_000_000;
const S: i64 = 1_000_000_000;
const OFF: i64 = 4 * S;
const G0: i64 = 1_400_000_000 * S;

#[test]
fn vn200_and_watson_chunks_come_out_on_gps_time() {
    let mut r = Ingest::new();
    let mut got: Vec<AlignedSample> = Vec::new();
    let mut f = |s: &AlignedSample| -> Result<(), ()> {
        got.push(s.clone());
        Ok(())
    };
    let line = Line {
        kind: Kind::Inertial,
        over_range: false,
        bank_deg: 1.0,
        elevation_deg: -2.0,
        heading_deg: 90.0,
        accel_g: [0.0, 0.0, 1.0],
        rate_dps: [0.0; 3],
        velocity_kmh: 100.0,
    };
    let bytes = line.to_bytes();
    assert_eq!(bytes.len(), 64);
    let mut watson_truth = Vec::new();
    for k in 0..400 {
        let g = G0 + k * 25 * MS;
        let frame = BinaryOutput {
            common: Some(CommonGroup {
                time_gps_ns: Some(g as u64),
                ins_status: Some(InsStatus(0b110)),
                ..Default::default()
            }),
            ..Default::default()
        }
        .encode();
        let t = g + OFF + tx_ns(frame.len(), 921_600) + MS;
        r.feed("vn200", "", t as u64, &frame, &mut f).unwrap();
        if k % 4 == 1 {
            // Sample at g; first byte 1 ms later; the first 30 bytes read 31.25 ms after that
            // plus 1 ms, the rest when the line ends (66.67 ms) plus 1 ms.
            watson_truth.push(g);
            let start = g + MS + OFF;
            r.feed(
                "watson",
                "",
                (start + tx_ns(30, 9600) + MS) as u64,
                &bytes[..30],
                &mut f,
            )
            .unwrap();
            r.feed(
                "watson",
                "",
                (start + tx_ns(64, 9600) + MS) as u64,
                &bytes[30..],
                &mut f,
            )
            .unwrap();
        }
    }
    let summary = r.finish(&mut f).unwrap();
    assert!(matches!(summary["vn200"], PortSummary::Decoded(s) if s.frames_decoded == 400));
    let vn: Vec<&AlignedSample> = got.iter().filter(|s| s.device == Device::Vn200).collect();
    assert_eq!(vn.len(), 400);
    for s in &vn {
        let a = s.aligned.time.unwrap();
        assert_eq!(a.t_gps_ns, G0 + s.index as i64 * 25 * MS);
    }
    let w: Vec<&AlignedSample> = got.iter().filter(|s| s.device == Device::Watson).collect();
    assert_eq!(w.len(), watson_truth.len());
    for s in &w {
        // The first lines wait for the host clock (2 s of references); all come out aligned.
        let a = s.aligned.time.unwrap();
        let e = a.t_gps_ns - watson_truth[s.index as usize];
        assert!(e.abs() < 50_000, "line {}: {e} ns", s.index);
    }
    // The last of them: timed by the host clock model, locked by then.
    let last = w[w.len() - 1].aligned.time.unwrap();
    assert_eq!(last.source, crate::time::TimeSource::HostClock);
    assert_eq!(last.status, crate::time::ClockStatus::Locked);
}

#[test]
fn read_intervals_go_to_the_device_kind_of_the_protocol() {
    let mut r = Ingest::new();
    let cases = [
        ("bahrs", "bahrs-2.0", Some(Device::Bahrs)),
        ("watson", "watson-ahrs-e304", Some(Device::Watson)),
        ("ttmrf", "ttmrf-text", Some(Device::Ttmrf)),
        ("adsb", "ttmrf-gdl90", Some(Device::Ttmrf)),
        // No protocol named: the standard device names.
        ("bahrs", "", Some(Device::Bahrs)),
        ("ttmrf", "", Some(Device::Ttmrf)),
        // The VN-200's wait is not modelled; unknown ports have no aligner.
        ("vn200", "vn200-icd", None),
        ("gyro", "", None),
        // Exact protocol names only (drivers' protocol table): a name that merely starts like a
        // TT-Multi-RF one is no protocol vigil decodes.
        ("ttmrf", "ttmrf-beast", None),
    ];
    for (device, protocol, kind) in cases {
        assert_eq!(
            r.set_read_interval(device, protocol, 10_000_000),
            kind,
            "{device} {protocol}"
        );
    }
}

/// A stated transmit buffer reaches the aligner from a TT-Multi-RF port of any output
/// protocol, and from no other port (only the TT-Multi-RF's line is watched).
#[test]
fn output_buffers_go_to_the_ttmrf_only() {
    let mut r = Ingest::new();
    for (device, protocol) in [
        ("bahrs", "bahrs-2.0"),
        ("watson", ""),
        ("vn200", "vn200-icd"),
        ("gyro", ""),
    ] {
        assert_eq!(r.set_output_buffer(device, protocol, Some(512)), None);
        assert_eq!(r.aligner().ttmrf_output_buffer_bytes(), None, "{device}");
    }
    for (k, (device, protocol)) in [("ttmrf", ""), ("adsb", "ttmrf-gdl90"), ("tt", "ttmrf-hex")]
        .into_iter()
        .enumerate()
    {
        let bytes = Some(1000 + k as u32);
        assert_eq!(
            r.set_output_buffer(device, protocol, bytes),
            Some(Device::Ttmrf)
        );
        assert_eq!(r.aligner().ttmrf_output_buffer_bytes(), bytes, "{device}");
    }
    r.set_output_buffer("ttmrf", "", None);
    assert_eq!(r.aligner().ttmrf_output_buffer_bytes(), None);
    // A buffer of nothing (a damaged recording's metadata) is no statement.
    r.set_output_buffer("ttmrf", "", Some(4096));
    r.set_output_buffer("ttmrf", "", Some(0));
    assert_eq!(r.aligner().ttmrf_output_buffer_bytes(), None);
}

#[test]
fn a_port_of_an_unknown_protocol_is_counted_not_decoded() {
    // Two reads of a channel whose protocol only starts like the VN-200's (before the protocol
    // table the aligned replay decoded it as one; the decoded replay did not).
    let mut r = Ingest::new();
    let mut n = 0;
    let mut f = |_: &AlignedSample| -> Result<(), ()> {
        n += 1;
        Ok(())
    };
    r.feed("vn200", "vn200-binary", 1, &[0xFA, 1, 2], &mut f)
        .unwrap();
    r.feed("vn200", "vn200-binary", 2, &[3, 4], &mut f).unwrap();
    assert_eq!(r.port_stats("vn200"), None);
    let summary = r.finish(&mut f).unwrap();
    assert_eq!(n, 0);
    assert_eq!(
        summary["vn200"],
        PortSummary::NoDecoder {
            no_decoder: true,
            chunks: 2,
            bytes: 5
        }
    );
}

/// A VN-200 binary frame at GPS time `g` (Common group: time and INS status).
fn vn_frame(g: i64, with_ypr: bool) -> Vec<u8> {
    BinaryOutput {
        common: Some(CommonGroup {
            time_gps_ns: Some(g as u64),
            ins_status: Some(InsStatus(0b110)),
            ypr: with_ypr.then_some(vigil_drivers::vn200::binary::Ypr {
                yaw_deg: 1.0,
                pitch_deg: 2.0,
                roll_deg: 3.0,
            }),
            ..Default::default()
        }),
        ..Default::default()
    }
    .encode()
}

#[test]
fn bytes_until_whole_message_after_a_steady_run_of_one_length_whatever_the_read_boundaries() {
    let mut r = Ingest::new();
    let mut f = |_: &AlignedSample| -> Result<(), ()> { Ok(()) };
    let mut t = 1u64;
    let mut feed = |r: &mut Ingest, b: &[u8]| {
        t += 1;
        r.feed("vn200", "", t, b, &mut f).unwrap();
    };
    let next = |r: &Ingest| r.bytes_until_whole_message("vn200");
    let short = vn_frame(G0, false);
    let long = vn_frame(G0, true);
    assert_eq!(long.len(), short.len() + 12, "YPR adds three f32");
    // Seven whole frames of one length, each in two reads: not steady yet.
    for _ in 0..7 {
        let (a, b) = short.split_at(10);
        feed(&mut r, a);
        assert_eq!(next(&r), None, "fewer than eight frames");
        feed(&mut r, b);
    }
    assert_eq!(next(&r), None, "seven frames");
    feed(&mut r, &short);
    assert_eq!(next(&r), Some(short.len()), "eight frames, on a boundary");
    // A late reader: the first 10 bytes of the next frame came with the last one.
    let (a, b) = short.split_at(10);
    feed(&mut r, a);
    assert_eq!(
        next(&r),
        Some(short.len() - 10),
        "the rest of the next frame"
    );
    feed(&mut r, &[b, a].concat());
    assert_eq!(
        next(&r),
        Some(short.len() - 10),
        "one frame, 10 bytes of the next"
    );
    feed(&mut r, b);
    assert_eq!(next(&r), Some(short.len()));
    // Two frames in one read, and two and a half: the run goes on.
    feed(&mut r, &[short.clone(), short.clone()].concat());
    assert_eq!(next(&r), Some(short.len()));
    feed(&mut r, &[&short[..], &short, a].concat());
    assert_eq!(next(&r), Some(short.len() - 10));
    feed(&mut r, b);
    // A frame of another length starts a new run, alone or after one of the run's length (a sum
    // that is not a whole number of run lengths).
    feed(&mut r, &long);
    assert_eq!(next(&r), None, "another length");
    for _ in 0..8 {
        feed(&mut r, &long);
    }
    assert_eq!(next(&r), Some(long.len()));
    feed(&mut r, &[long.clone(), short.clone()].concat());
    assert_eq!(next(&r), None, "two frames of two lengths");
    for _ in 0..8 {
        feed(&mut r, &long);
    }
    assert_eq!(next(&r), Some(long.len()));
    // Garbage before a frame (skipped bytes) ends it too.
    feed(&mut r, &[[0x55u8, 0x66].as_slice(), &long].concat());
    assert_eq!(next(&r), None, "skipped bytes");
    assert_eq!(
        r.bytes_until_whole_message("watson"),
        None,
        "a port never seen"
    );
}
