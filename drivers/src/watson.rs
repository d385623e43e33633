//! Watson Industries AHRS-E304 ASCII attitude string ("RS-232 output format", document of
//! 09/06/05, page 6).
//!
//! One line, 64 bytes, 9600 8N1, about 11.85 lines per second:
//!
//! ```text
//! offset 0  2       9     15    21    27    33    39    45    51    57    63
//!        I -012.3 +05.2 123.4  +0.01 -0.02 +1.00+01.5 -00.3 +10.0 +123.4\r
//!        |  bank  elev  head   acc X acc Y acc Z rateX rateY rateZ velocity CR
//! ```
//!
//! - byte 0: 'I' inertial or 'R' reference string; lower case ('i', 'r') flags an over-range
//!   error (kept as [`Line::over_range`], the values are still delivered);
//! - bank: sign, 3 digits, '.', 1 digit, space (deg); elevation: sign, 2.1 digits, space (deg);
//!   heading: 3.1 digits, space (deg, magnetic); accelerations X/Y/Z: space, sign, 1.2 digits (g);
//!   rates X/Y/Z: sign, 2.1 digits, space (deg/s); velocity: sign, 3.1 digits (km/h); CR.
//!   Taken literally, acceleration Z (no trailing space) runs straight into rate X (no leading
//!   space): `+1.00+01.5`. That is what the widths add up to (64 bytes with the CR), so the
//!   decoder expects exactly that.
//!
//! Decisions:
//! - Fields are checked for width, sign, digits and range; the document gives ranges "up to
//!   +-179.9" (bank) and "+-89.9" (elevation), but a device rounding 179.96 prints 180.0, so the
//!   limits accepted are +-180.0 and +-90.0; heading must be below 360.0.
//! - A line must end with CR at offset 63. An LF after the CR (some adapters add one) is skipped
//!   as a separator. Every CR that ends something other than a valid line counts one malformed
//!   line, so a truncated or garbled line is counted once and the next line decodes.

use bytes::BytesMut;
use serde::Serialize;

use crate::{DecodeStats, DeviceDecoder};

/// Length of one line including its CR.
pub const LINE_LEN: usize = 64;
/// Standard gravity used to convert g to m/s^2.
pub const STANDARD_GRAVITY_MPS2: f64 = 9.80665;
/// Nominal output rate, lines per second.
pub const NOMINAL_RATE_HZ: f64 = 11.85;
/// Baud rate of the output.
pub const BAUD: u32 = 9600;

/// Which string the line is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// 'I': inertial data string.
    Inertial,
    /// 'R': reference data string.
    Reference,
}

/// One decoded line, in the device's units (named in each field).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Line {
    /// Inertial or reference string.
    pub kind: Kind,
    /// Lower-case start letter: the unit reports an over-range error.
    pub over_range: bool,
    /// Bank angle, deg, +-180.
    pub bank_deg: f64,
    /// Elevation angle, deg, +-90.
    pub elevation_deg: f64,
    /// Magnetic heading, deg, 0 .. 360.
    pub heading_deg: f64,
    /// Acceleration X, Y, Z, g.
    pub accel_g: [f64; 3],
    /// Angular rate X, Y, Z, deg/s.
    pub rate_dps: [f64; 3],
    /// Velocity, km/h.
    pub velocity_kmh: f64,
}

impl Line {
    /// Bank, rad.
    pub fn bank_rad(&self) -> f64 {
        self.bank_deg.to_radians()
    }
    /// Elevation, rad.
    pub fn elevation_rad(&self) -> f64 {
        self.elevation_deg.to_radians()
    }
    /// Magnetic heading, rad.
    pub fn heading_mag_rad(&self) -> f64 {
        self.heading_deg.to_radians()
    }
    /// Accelerations, m/s^2.
    pub fn accel_mps2(&self) -> [f64; 3] {
        self.accel_g.map(|a| a * STANDARD_GRAVITY_MPS2)
    }
    /// Angular rates, rad/s.
    pub fn rate_radps(&self) -> [f64; 3] {
        self.rate_dps.map(f64::to_radians)
    }
    /// Velocity, m/s.
    pub fn velocity_mps(&self) -> f64 {
        self.velocity_kmh / 3.6
    }

    /// Appends the 64-byte line (with CR) to `out`. Values are rounded to the field's resolution
    /// and clamped to its range, so the output always decodes.
    pub fn encode(&self, out: &mut Vec<u8>) {
        use std::io::Write as _;
        let letter = match (self.kind, self.over_range) {
            (Kind::Inertial, false) => 'I',
            (Kind::Inertial, true) => 'i',
            (Kind::Reference, false) => 'R',
            (Kind::Reference, true) => 'r',
        };
        let c = |v: f64, lim: f64| if v.is_nan() { 0.0 } else { v.clamp(-lim, lim) };
        let heading = if self.heading_deg.is_nan() {
            0.0
        } else {
            self.heading_deg.clamp(0.0, 359.9)
        };
        let [ax, ay, az] = self.accel_g.map(|a| c(a, 9.99));
        let [rx, ry, rz] = self.rate_dps.map(|r| c(r, 99.9));
        // Writing to a Vec cannot fail.
        let _ = write!(
            out,
            "{letter} {:+06.1} {:+05.1} {:05.1}  {:+05.2} {:+05.2} {:+05.2}{:+05.1} {:+05.1} {:+05.1} {:+06.1}\r",
            c(self.bank_deg, 180.0),
            c(self.elevation_deg, 90.0),
            heading,
            ax,
            ay,
            az,
            rx,
            ry,
            rz,
            c(self.velocity_kmh, 799.9),
        );
    }

    /// The encoded line as a new vector.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut out = Vec::with_capacity(LINE_LEN);
        self.encode(&mut out);
        out
    }
}

/// Parses a fixed-point decimal field: optional sign, exactly `int` digits, '.', exactly `frac`
/// digits. Returns the value, or `None` if any byte is out of place.
fn fixed(field: &[u8], signed: bool, int: usize, frac: usize) -> Option<f64> {
    let (neg, digits) = if signed {
        match field.split_first()? {
            (b'+', rest) => (false, rest),
            (b'-', rest) => (true, rest),
            _ => return None,
        }
    } else {
        (false, field)
    };
    if digits.len() != int + 1 + frac || digits[int] != b'.' {
        return None;
    }
    let mut n: i64 = 0;
    for (i, &b) in digits.iter().enumerate() {
        if i == int {
            continue;
        }
        if !b.is_ascii_digit() {
            return None;
        }
        n = n * 10 + i64::from(b - b'0');
    }
    let v = n as f64 / 10f64.powi(frac as i32);
    Some(if neg { -v } else { v })
}

/// Parses one 64-byte line (CR included). `None` if any field is out of place or out of range.
pub fn parse_line(line: &[u8]) -> Option<Line> {
    if line.len() != LINE_LEN || line[63] != b'\r' {
        return None;
    }
    let (kind, over_range) = match line[0] {
        b'I' => (Kind::Inertial, false),
        b'i' => (Kind::Inertial, true),
        b'R' => (Kind::Reference, false),
        b'r' => (Kind::Reference, true),
        _ => return None,
    };
    // Separators: the spaces that the document puts after or before each field.
    for pos in [1, 8, 14, 20, 21, 27, 33, 44, 50, 56] {
        if line[pos] != b' ' {
            return None;
        }
    }
    let bank = fixed(&line[2..8], true, 3, 1).filter(|v| v.abs() <= 180.0)?;
    let elevation = fixed(&line[9..14], true, 2, 1).filter(|v| v.abs() <= 90.0)?;
    let heading = fixed(&line[15..20], false, 3, 1).filter(|v| *v < 360.0)?;
    let accel = |at: usize| fixed(&line[at..at + 5], true, 1, 2);
    let rate = |at: usize| fixed(&line[at..at + 5], true, 2, 1);
    let velocity = fixed(&line[57..63], true, 3, 1).filter(|v| v.abs() <= 799.9)?;
    Some(Line {
        kind,
        over_range,
        bank_deg: bank,
        elevation_deg: elevation,
        heading_deg: heading,
        accel_g: [accel(22)?, accel(28)?, accel(34)?],
        rate_dps: [rate(39)?, rate(45)?, rate(51)?],
        velocity_kmh: velocity,
    })
}

#[inline]
fn is_start(b: u8) -> bool {
    matches!(b, b'I' | b'i' | b'R' | b'r')
}

/// Sans-IO decoder of the Watson line stream.
#[derive(Debug, Default, Clone)]
pub struct Decoder {
    stats: DecodeStats,
}

impl Decoder {
    /// A decoder at the start of a stream.
    pub fn new() -> Self {
        Self::default()
    }

    /// Skips `n` bytes, counting one malformed line for every CR among them.
    fn skip_counting_lines(&mut self, buf: &mut BytesMut, n: usize) {
        let n = n.min(buf.len());
        self.stats.malformed += memchr::memchr_iter(b'\r', &buf[..n]).count() as u64;
        self.stats.skip(buf, n);
    }
}

impl DeviceDecoder for Decoder {
    type Message = Line;

    fn decode(&mut self, buf: &mut BytesMut) -> Option<Line> {
        loop {
            match buf.iter().position(|&b| is_start(b)) {
                Some(0) => {}
                Some(p) => self.skip_counting_lines(buf, p),
                None => {
                    let n = buf.len();
                    self.skip_counting_lines(buf, n);
                    return None;
                }
            }
            let window = &buf[..buf.len().min(LINE_LEN)];
            match memchr::memchr(b'\r', window) {
                Some(63) => {
                    if let Some(line) = parse_line(&buf[..LINE_LEN]) {
                        self.stats.take_frame(buf, LINE_LEN);
                        return Some(line);
                    }
                    self.skip_counting_lines(buf, LINE_LEN);
                }
                // A line that ends early: truncated or garbled.
                Some(p) => self.skip_counting_lines(buf, p + 1),
                // No CR where it must be: a false start (or a line that lost its CR, which is
                // counted when its later CR is skipped). Rescan from the next byte.
                None if buf.len() >= LINE_LEN => self.stats.skip(buf, 1),
                None => return None,
            }
        }
    }

    fn decode_eof(&mut self, buf: &mut BytesMut) -> Option<Line> {
        if let Some(line) = self.decode(buf) {
            return Some(line);
        }
        if !buf.is_empty() {
            // A line cut off by the end of the stream.
            self.stats.malformed += 1;
            let n = buf.len();
            self.stats.skip(buf, n);
        }
        None
    }

    fn stats(&self) -> &DecodeStats {
        &self.stats
    }

    fn stats_mut(&mut self) -> &mut DecodeStats {
        &mut self.stats
    }
}

#[cfg(test)]
mod tests {
    use proptest::prelude::*;

    use super::*;
    use crate::decode_slice;
    use crate::testkit::{
        XorShift, assert_accounting, assert_split_invariant, assert_survives_random,
        decode_chunked, flip_bits,
    };

    /// A line built by hand from the document's field descriptions.
    const EXAMPLE: &[u8; 64] = b"I -012.3 +05.2 123.4  +0.01 -0.02 +1.00+01.5 -00.3 +10.0 +123.4\r";

    #[test]
    fn example_line_by_hand() {
        assert_eq!(EXAMPLE.len(), 64);
        let l = parse_line(EXAMPLE).expect("valid line");
        assert_eq!(l.kind, Kind::Inertial);
        assert!(!l.over_range);
        assert_eq!(l.bank_deg, -12.3);
        assert_eq!(l.elevation_deg, 5.2);
        assert_eq!(l.heading_deg, 123.4);
        assert_eq!(l.accel_g, [0.01, -0.02, 1.0]);
        assert_eq!(l.rate_dps, [1.5, -0.3, 10.0]);
        assert_eq!(l.velocity_kmh, 123.4);
        // 1 g = 9.80665 m/s^2; 123.4 km/h = 34.2777... m/s.
        assert!((l.accel_mps2()[2] - 9.80665).abs() < 1e-12);
        assert!((l.velocity_mps() - 34.277_777_777_777_78).abs() < 1e-9);
        assert!((l.bank_rad() + 0.214_675_497_995_7).abs() < 1e-12);
        // Degrees to radians by hand: 5.2 deg = 13 pi / 450, 123.4 deg = 617 pi / 900; rates
        // 1.5, -0.3 and 10.0 deg/s = pi / 120, -pi / 600 and pi / 18 rad/s.
        use std::f64::consts::PI;
        assert!((l.elevation_rad() - 13.0 * PI / 450.0).abs() < 1e-12);
        assert!((l.heading_mag_rad() - 617.0 * PI / 900.0).abs() < 1e-12);
        let rate = l.rate_radps();
        for (got, want) in rate.iter().zip([PI / 120.0, -PI / 600.0, PI / 18.0]) {
            assert!((got - want).abs() < 1e-12, "{rate:?}");
        }
        // The encoder writes the same bytes.
        assert_eq!(l.to_bytes(), EXAMPLE.to_vec());
    }

    #[test]
    fn lower_case_is_over_range_and_r_is_reference() {
        let mut line = *EXAMPLE;
        line[0] = b'r';
        let l = parse_line(&line).unwrap();
        assert_eq!((l.kind, l.over_range), (Kind::Reference, true));
        line[0] = b'i';
        assert!(parse_line(&line).unwrap().over_range);
        line[0] = b'X';
        assert!(parse_line(&line).is_none());
    }

    #[test]
    fn fields_are_checked_for_width_sign_and_range() {
        let bad = |pos: usize, b: u8| {
            let mut line = *EXAMPLE;
            line[pos] = b;
            parse_line(&line)
        };
        assert!(bad(2, b' ').is_none(), "bank without sign");
        assert!(bad(3, b'x').is_none(), "digit replaced");
        assert!(bad(6, b'5').is_none(), "decimal point moved");
        assert!(bad(8, b'0').is_none(), "separator lost");
        assert!(bad(15, b'+').is_none(), "heading has no sign");
        assert!(bad(22, b' ').is_none(), "acceleration without sign");
        assert!(bad(63, b'\n').is_none(), "no CR");
        // Range: bank 181.0, elevation 91.0, heading 360.0, velocity 800.0.
        let with = |at: usize, text: &[u8]| {
            let mut line = *EXAMPLE;
            line[at..at + text.len()].copy_from_slice(text);
            parse_line(&line)
        };
        assert!(with(2, b"+181.0").is_none());
        assert!(with(2, b"-180.0").is_some());
        assert!(with(9, b"-91.0").is_none());
        assert!(with(9, b"+90.0").is_some());
        assert!(with(15, b"360.0").is_none());
        assert!(with(15, b"359.9").is_some());
        assert!(with(57, b"-800.0").is_none());
        assert!(with(57, b"-799.9").is_some());
    }

    fn stream(n: usize) -> (Vec<u8>, Vec<Line>) {
        let mut bytes = Vec::new();
        let mut lines = Vec::new();
        for i in 0..n {
            let l = Line {
                kind: if i % 5 == 0 {
                    Kind::Reference
                } else {
                    Kind::Inertial
                },
                over_range: i % 7 == 0,
                bank_deg: (i as f64 * 3.7).rem_euclid(359.0).round() / 1.0 - 179.0,
                elevation_deg: (i as f64 * 1.3 % 170.0).round() - 85.0,
                heading_deg: (i as f64 * 12.1).rem_euclid(359.0).round(),
                accel_g: [0.01 * i as f64 % 9.0, -0.5, 1.0],
                rate_dps: [0.0, -1.5, 99.9],
                velocity_kmh: -12.5,
            };
            // Round to the field grids, as a decoded line would be.
            let l = parse_line(&l.to_bytes()).expect("encoder output decodes");
            l.encode(&mut bytes);
            lines.push(l);
        }
        (bytes, lines)
    }

    #[test]
    fn stream_decodes_and_splits_anywhere() {
        let (bytes, lines) = stream(5);
        let mut d = Decoder::new();
        assert_eq!(decode_slice(&mut d, &bytes), lines);
        assert_eq!(d.stats().malformed, 0);
        let mut hostile = b"\n7 +1\rI +00".to_vec();
        hostile.extend_from_slice(&bytes);
        hostile.extend_from_slice(b"\r\nR +001.0");
        assert_split_invariant(Decoder::new, &hostile);
    }

    #[test]
    fn truncated_and_garbled_lines_are_counted_and_skipped() {
        let (bytes, lines) = stream(4);
        // Line 1 loses 10 bytes in its middle; line 2 gets a letter in a digit; CRLF after line 3.
        let mut s = bytes[..64].to_vec();
        s.extend_from_slice(&bytes[64..64 + 30]);
        s.extend_from_slice(&bytes[64 + 40..128]);
        let mut l2 = bytes[128..192].to_vec();
        l2[4] = b'Z';
        s.extend_from_slice(&l2);
        s.extend_from_slice(&bytes[192..256]);
        s.push(b'\n');
        let mut d = Decoder::new();
        let got = decode_slice(&mut d, &s);
        assert_eq!(got, vec![lines[0], lines[3]]);
        assert_eq!(d.stats().malformed, 2);
        assert_eq!(d.stats().bytes_skipped, (54 + 64 + 1) as u64);
        assert_accounting(d.stats(), s.len());
    }

    #[test]
    fn a_false_start_without_cr_is_dropped_and_the_next_line_decodes_without_eof() {
        // An 'I' followed by 63 digits: no CR at offset 63, so not a line. The decoder must not
        // wait for more bytes (its buffer stays bounded by one line): it drops the false start
        // one byte at a time (no CR among them, so no malformed line) and finds the real line
        // behind it, without the end-of-stream flush.
        let mut bytes = vec![b'I'];
        bytes.extend_from_slice(&[b'0'; 63]);
        bytes.extend_from_slice(EXAMPLE);
        let mut buf = BytesMut::from(&bytes[..]);
        let mut d = Decoder::new();
        assert_eq!(d.decode(&mut buf), parse_line(EXAMPLE));
        assert!(buf.is_empty());
        assert_eq!(d.stats().bytes_skipped, 64);
        assert_eq!(d.stats().malformed, 0);
        assert_eq!(d.stats().frames_decoded, 1);
    }

    #[test]
    fn counters_written_through_stats_mut_are_the_ones_stats_reads() {
        let mut d = Decoder::new();
        d.stats_mut().malformed = 3;
        assert_eq!(d.stats().malformed, 3);
    }

    #[test]
    fn a_line_cut_by_the_end_of_stream_is_counted() {
        let (bytes, lines) = stream(2);
        let mut d = Decoder::new();
        assert_eq!(decode_slice(&mut d, &bytes[..100]), vec![lines[0]]);
        assert_eq!(d.stats().malformed, 1);
    }

    #[test]
    fn random_and_corrupted_input_never_panics() {
        assert_survives_random(Decoder::new, 11, 300, 2048);
        let (clean, _) = stream(50);
        let mut rng = XorShift::new(5);
        for _ in 0..100 {
            let mut bytes = clean.clone();
            flip_bits(&mut bytes, 1 + rng.below(30) as usize, &mut rng);
            let (_, stats) = decode_chunked(Decoder::new(), &bytes, &[1 + rng.below(80) as usize]);
            assert_accounting(&stats, bytes.len());
        }
        for _ in 0..100 {
            let mut bytes = clean.clone();
            flip_bits(&mut bytes, rng.below(8) as usize, &mut rng);
            bytes.truncate(rng.below(bytes.len() as u64 + 1) as usize);
            crate::testkit::check_arbitrary_input(Decoder::new, &bytes);
        }
        // Random ASCII made of the line's own alphabet is the hardest case for a text decoder.
        let alphabet = b"IiRr +-.0123456789\r\n";
        for _ in 0..100 {
            let bytes: Vec<u8> = (0..rng.below(3000))
                .map(|_| alphabet[rng.below(alphabet.len() as u64) as usize])
                .collect();
            let (_, stats) = decode_chunked(Decoder::new(), &bytes, &[1 + rng.below(80) as usize]);
            assert_accounting(&stats, bytes.len());
        }
    }

    proptest! {
        #[test]
        fn encode_then_decode_is_identity(
            bank in -1800i32..=1800, elev in -900i32..=900, head in 0i32..3600,
            acc in proptest::array::uniform3(-999i32..=999), rate in proptest::array::uniform3(-999i32..=999),
            vel in -7999i32..=7999, reference: bool, over: bool)
        {
            let line = Line {
                kind: if reference { Kind::Reference } else { Kind::Inertial },
                over_range: over,
                bank_deg: f64::from(bank) / 10.0,
                elevation_deg: f64::from(elev) / 10.0,
                heading_deg: f64::from(head) / 10.0,
                accel_g: acc.map(|a| f64::from(a) / 100.0),
                rate_dps: rate.map(|r| f64::from(r) / 10.0),
                velocity_kmh: f64::from(vel) / 10.0,
            };
            let bytes = line.to_bytes();
            prop_assert_eq!(bytes.len(), LINE_LEN);
            prop_assert_eq!(parse_line(&bytes), Some(line));
        }
    }
}
