//! Stream builders for the Mode S benchmark: the real Beast capture (read in place from
//! `shared/data/adsb`, never copied) or, when it is absent, a synthetic stream built with the
//! drivers' encoders.

use bytes::BytesMut;
use vigil_drivers::modes::encode::{self, AirbornePositionFields};
use vigil_drivers::ttmrf::raw::{
    BeastDecoder, ModeSFrame, RawFrame, RxMeta, beast::encode_beast, hex::encode_hex,
};

/// The Beast capture `ulss7_beast.bin`, or a synthetic Beast stream (with a note on stderr).
pub fn beast_capture() -> Vec<u8> {
    if let Some(p) = vigil_drivers::testkit::shared_data("adsb/ulss7_beast.bin")
        && let Ok(b) = std::fs::read(p)
    {
        return b;
    }
    eprintln!("modes bench: capture absent, using synthetic frames");
    let mut out = BytesMut::new();
    for f in synthetic_df17(4000) {
        encode_beast(&f, &mut out);
    }
    out.to_vec()
}

/// The Mode S frames of a Beast stream.
pub fn mode_s_frames(beast: &[u8]) -> Vec<RawFrame> {
    vigil_drivers::decode_slice(&mut BeastDecoder::new(), beast)
        .into_iter()
        .filter(|f| matches!(f, RawFrame::ModeS(_)))
        .collect()
}

/// Only the DF17 frames of a list, with their metadata.
pub fn df17_only(frames: &[RawFrame]) -> Vec<RawFrame> {
    frames
        .iter()
        .filter(|f| matches!(f, RawFrame::ModeS(m) if m.len == 14 && m.bytes[0] >> 3 == 17))
        .cloned()
        .collect()
}

/// Frames re-encoded as a Beast stream.
pub fn to_beast(frames: &[RawFrame]) -> Vec<u8> {
    let mut out = BytesMut::new();
    for f in frames {
        encode_beast(f, &mut out);
    }
    out.to_vec()
}

/// Frames re-encoded as HEX lines with extended fields.
pub fn to_hex(frames: &[RawFrame]) -> Vec<u8> {
    let mut out = BytesMut::new();
    for f in frames {
        let mut f = f.clone();
        if let RawFrame::ModeS(m) = &mut f {
            let t = m.meta.mlat_ticks.unwrap_or(0);
            m.meta = RxMeta {
                signal_dbm: Some(-70),
                signal_quality: Some(3),
                ts_pps_ns: Some(t % 1_000_000_000),
                ts_utc_ns: Some(t * 1000 / 12),
                ..RxMeta::default()
            };
        }
        encode_hex(&f, true, &mut out);
    }
    out.to_vec()
}

/// `n` synthetic DF17 frames: 50 aircraft sending identification, even/odd positions and
/// velocities, 0.1 s apart on the MLAT clock.
pub fn synthetic_df17(n: usize) -> Vec<RawFrame> {
    (0..n)
        .map(|i| {
            let icao = 0x400000 + (i % 50) as u32;
            let k = i / 50;
            let lat = 52.0 + (i % 50) as f64 * 0.01 + k as f64 * 1e-4;
            let bytes = match k % 4 {
                0 => encode::identification(icao, 4, 3, "TEST123"),
                1 | 2 => encode::airborne_position(
                    icao,
                    &AirbornePositionFields {
                        typecode: 11,
                        surveillance_status: 0,
                        nic_b: false,
                        altitude_ft: Some(30_000),
                        lat_deg: lat,
                        lon_deg: 4.5,
                        odd: k % 4 == 2,
                    },
                ),
                _ => encode::velocity_ground(icao, 100, 300, Some(-640), true, 1),
            }
            .unwrap_or([0; 14]);
            RawFrame::ModeS(ModeSFrame {
                bytes,
                len: 14,
                meta: RxMeta {
                    mlat_ticks: Some(1 + i as u64 * 1_200_000),
                    rssi: Some(100),
                    ..RxMeta::default()
                },
            })
        })
        .collect()
}
