//! Checks every device decoder must pass, shared by the drivers' tests, the fuzz targets and the
//! integration tests: split invariance, accounting, and survival of arbitrary input.
//!
//! These are test utilities, but public so that other crates' tests and the fuzz crate use the
//! same checks rather than copies.

use std::fmt::Debug;

use bytes::BytesMut;

use crate::{DecodeStats, DeviceDecoder};

/// Feeds `bytes` to a fresh decoder in the given chunk sizes (cycled; a 0 is taken as 1), then
/// signals end of stream. Returns the messages and the final counters.
pub fn decode_chunked<D: DeviceDecoder>(
    mut decoder: D,
    bytes: &[u8],
    chunk_sizes: &[usize],
) -> (Vec<D::Message>, DecodeStats) {
    let mut buf = BytesMut::new();
    let mut out = Vec::new();
    let mut pos = 0;
    let mut sizes = chunk_sizes.iter().copied().cycle();
    while pos < bytes.len() {
        let n = sizes.next().unwrap_or(bytes.len()).max(1);
        let end = (pos + n).min(bytes.len());
        buf.extend_from_slice(&bytes[pos..end]);
        pos = end;
        while let Some(m) = decoder.decode(&mut buf) {
            out.push(m);
        }
    }
    while let Some(m) = decoder.decode_eof(&mut buf) {
        out.push(m);
    }
    let stats = *decoder.stats();
    // `stats_mut` must reach the same counters as `stats`: the default `decode_eof` and the
    // multiplexing decoders count through it.
    decoder.stats_mut().bytes_skipped += 1;
    assert_eq!(
        decoder.stats().bytes_skipped,
        stats.bytes_skipped + 1,
        "stats_mut does not reach stats"
    );
    (out, stats)
}

/// Asserts that splitting `bytes` into two reads at every possible point, and feeding it one byte
/// at a time, gives exactly the messages and counters of a single read.
pub fn assert_split_invariant<D, F>(make: F, bytes: &[u8])
where
    D: DeviceDecoder,
    D::Message: PartialEq + Debug,
    F: Fn() -> D,
{
    let (whole, whole_stats) = decode_chunked(make(), bytes, &[bytes.len().max(1)]);
    assert_accounting(&whole_stats, bytes.len());
    for split in 0..=bytes.len() {
        let mut d = make();
        let mut buf = BytesMut::from(&bytes[..split]);
        let mut out = Vec::new();
        while let Some(m) = d.decode(&mut buf) {
            out.push(m);
        }
        buf.extend_from_slice(&bytes[split..]);
        while let Some(m) = d.decode(&mut buf) {
            out.push(m);
        }
        while let Some(m) = d.decode_eof(&mut buf) {
            out.push(m);
        }
        assert!(
            same_messages(&out, &whole),
            "messages differ when split at byte {split}"
        );
        assert_eq!(
            *d.stats(),
            whole_stats,
            "counters differ when split at byte {split}"
        );
    }
    let (bytewise, bytewise_stats) = decode_chunked(make(), bytes, &[1]);
    assert!(
        same_messages(&bytewise, &whole),
        "messages differ when fed one byte at a time"
    );
    assert_eq!(
        bytewise_stats, whole_stats,
        "counters differ when fed one byte at a time"
    );
}

/// Message lists are the same: equal, or equal in their `Debug` form. Random bytes can pass a
/// 16-bit checksum and decode to NaN floats, and NaN != NaN under `PartialEq`.
fn same_messages<M: PartialEq + Debug>(a: &[M], b: &[M]) -> bool {
    a == b || format!("{a:?}") == format!("{b:?}")
}

/// Asserts the byte accounting of a decoder that has seen `len` bytes and the end of the stream.
pub fn assert_accounting(stats: &DecodeStats, len: usize) {
    assert_eq!(
        stats.bytes_consumed, len as u64,
        "after end of stream every byte is either decoded or skipped: {stats:?}"
    );
    assert!(stats.bytes_skipped <= stats.bytes_consumed, "{stats:?}");
}

/// Path of a file under `shared/data/` beside the repository (`../shared/data/<relative>`), if it
/// exists. When it does not, prints that the caller skips and why, and returns `None`: a fresh
/// clone without `../shared` still passes its tests (CI always has it).
pub fn shared_data(relative: &str) -> Option<std::path::PathBuf> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../shared/data")
        .join(relative);
    if path.exists() {
        Some(path)
    } else {
        eprintln!(
            "skipped: {} is absent (it lives in ../shared/data beside the repository)",
            path.display()
        );
        None
    }
}

/// A small deterministic pseudo-random generator (xorshift64*), so that random-input tests need
/// no extra dependency and every failure is reproducible from its seed.
#[derive(Debug, Clone)]
pub struct XorShift(u64);

impl XorShift {
    /// A generator from a seed (0 is replaced by a fixed non-zero value).
    pub fn new(seed: u64) -> Self {
        Self(if seed == 0 {
            0x9E37_79B9_7F4A_7C15
        } else {
            seed
        })
    }

    /// The next 64 pseudo-random bits.
    pub fn next_u64(&mut self) -> u64 {
        let mut x = self.0;
        x ^= x >> 12;
        x ^= x << 25;
        x ^= x >> 27;
        self.0 = x;
        x.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A pseudo-random value in `0..n` (`n` > 0).
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n.max(1)
    }

    /// Fills `out` with pseudo-random bytes.
    pub fn fill(&mut self, out: &mut [u8]) {
        for b in out {
            *b = self.next_u64() as u8;
        }
    }
}

/// Flips `count` pseudo-random bits of `bytes` (bit errors on a link).
pub fn flip_bits(bytes: &mut [u8], count: usize, rng: &mut XorShift) {
    if bytes.is_empty() {
        return;
    }
    for _ in 0..count {
        let i = rng.below(bytes.len() as u64) as usize;
        bytes[i] ^= 1 << rng.below(8);
    }
}

/// Decodes `rounds` buffers of random bytes (of random lengths up to `max_len`), each also fed in
/// random chunk sizes, and checks that nothing panics and the accounting holds. Returns the total
/// number of messages decoded (random input rarely forms valid frames, but it can).
pub fn assert_survives_random<D, F>(make: F, seed: u64, rounds: usize, max_len: usize) -> usize
where
    D: DeviceDecoder,
    F: Fn() -> D,
{
    let mut rng = XorShift::new(seed);
    let mut decoded = 0;
    let mut bytes = vec![0u8; max_len];
    for _ in 0..rounds {
        let len = rng.below(max_len as u64 + 1) as usize;
        rng.fill(&mut bytes[..len]);
        let chunk = 1 + rng.below(64) as usize;
        let (msgs, stats) = decode_chunked(make(), &bytes[..len], &[chunk]);
        assert_accounting(&stats, len);
        decoded += msgs.len();
    }
    decoded
}

/// The property every fuzz target checks on arbitrary `data`: decoding it whole, and decoding it in
/// chunks whose size is taken from the data itself, give the same messages and counters, and every
/// byte is accounted for. Panics (which the fuzzer reports) on any violation.
pub fn check_arbitrary_input<D, F>(make: F, data: &[u8])
where
    D: DeviceDecoder,
    D::Message: PartialEq + Debug,
    F: Fn() -> D,
{
    let (whole, whole_stats) = decode_chunked(make(), data, &[data.len().max(1)]);
    assert_accounting(&whole_stats, data.len());
    let chunk = data.first().map_or(1, |&b| usize::from(b % 31) + 1);
    let (chunked, chunked_stats) = decode_chunked(make(), data, &[chunk]);
    // Random bytes can pass a 16-bit checksum and decode to NaN floats, and NaN != NaN: messages
    // that differ under `PartialEq` are compared by their `Debug` form before calling it a
    // difference.
    assert!(
        same_messages(&chunked, &whole),
        "chunk size {chunk} changed the messages:\n{chunked:?}\n{whole:?}"
    );
    assert_eq!(
        chunked_stats, whole_stats,
        "chunk size {chunk} changed the counters"
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Yields one NaN per byte 'x' (and skips everything else), like a decoder whose checksum
    /// random input happened to pass.
    #[derive(Default)]
    struct NanDecoder(DecodeStats);

    impl DeviceDecoder for NanDecoder {
        type Message = f64;
        fn decode(&mut self, buf: &mut BytesMut) -> Option<f64> {
            while let Some(&b) = buf.first() {
                if b == b'x' {
                    self.0.take_frame(buf, 1);
                    return Some(f64::NAN);
                }
                self.0.skip(buf, 1);
            }
            None
        }
        fn stats(&self) -> &DecodeStats {
            &self.0
        }
        fn stats_mut(&mut self) -> &mut DecodeStats {
            &mut self.0
        }
    }

    #[test]
    fn regression_nan_messages_compare_equal() {
        // Found by the vn200 fuzz target: identical NaN-carrying messages failed `PartialEq`.
        check_arbitrary_input(NanDecoder::default, b"axbxxc");
        assert_split_invariant(NanDecoder::default, b"axbxxc");
    }

    #[test]
    fn xorshift_is_deterministic_and_spread() {
        let mut a = XorShift::new(42);
        let mut b = XorShift::new(42);
        let xs: Vec<u64> = (0..100).map(|_| a.next_u64()).collect();
        let ys: Vec<u64> = (0..100).map(|_| b.next_u64()).collect();
        assert_eq!(xs, ys);
        // Every bit position takes both values within 100 draws.
        let or = xs.iter().fold(0u64, |acc, x| acc | x);
        let and = xs.iter().fold(u64::MAX, |acc, x| acc & x);
        assert_eq!(or, u64::MAX);
        assert_eq!(and, 0);
    }
}
