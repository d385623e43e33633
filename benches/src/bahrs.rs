//! BAHRS stream builder for the benchmarks.

use vigil_drivers::bahrs::{
    DataTime, Health, Inertial, InertialHealth, Message, Navigation, NavigationHealth,
    SyncPulseTime,
};

/// A BAHRS stream at the device's default rates (0x01 + 0x05 at 100 Hz, 0x02 + 0x04 at 50 Hz,
/// 0x06 at 1 Hz; the 1 Hz 0x03 is left out) covering `seconds` of output, with varying values:
/// 301 frames and 7,020 bytes a second (frames of 28, 20, 24, 20 and 20 bytes).
pub fn bahrs_stream(seconds: u32) -> (Vec<u8>, usize) {
    let mut out = Vec::new();
    let mut frames = 0;
    let safe = Health::Safe;
    for k in 0..seconds as u64 * 100 {
        let t_us = 1_000_000 + k * 10_000;
        let seq = k as u8;
        let phase = k as f64 * 0.01;
        let msgs = [
            Some(Message::Inertial(Inertial::from_si(
                seq,
                [0.1 * phase.sin(), 0.2, -9.81],
                [0.01, -0.02 * phase.cos(), 0.05],
                InertialHealth::new([safe; 3], [safe; 3]),
            ))),
            Some(Message::InertialTime(DataTime {
                seq,
                data_seq: seq,
                mcu_time_us: t_us,
            })),
            (k % 2 == 0).then(|| {
                Message::Navigation(Navigation::from_si(
                    (k / 2) as u8,
                    500.0 + phase,
                    -1.0,
                    0.2 * phase.sin(),
                    0.05,
                    phase % std::f64::consts::TAU,
                    NavigationHealth::new(safe, safe, safe, safe, safe),
                ))
            }),
            (k % 2 == 0).then_some(Message::NavigationTime(DataTime {
                seq: (k / 2) as u8,
                data_seq: (k / 2) as u8,
                mcu_time_us: t_us,
            })),
            (k % 100 == 0).then_some(Message::SyncPulseTime(SyncPulseTime {
                seq: (k / 100) as u8,
                mcu_time_us: t_us,
            })),
        ];
        for m in msgs.into_iter().flatten() {
            m.encode(&mut out);
            frames += 1;
        }
    }
    (out, frames)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The sizes the doc comment and the benches state, by hand from section 5's layouts: per
    /// second 100 x (28 + 20) + 50 x (24 + 20) + 20 bytes and 100 x 2 + 50 x 2 + 1 frames.
    #[test]
    fn the_stream_holds_the_stated_frames_and_bytes() {
        let (stream, frames) = bahrs_stream(10);
        assert_eq!(stream.len(), 70_200);
        assert_eq!(frames, 3_010);
    }
}
