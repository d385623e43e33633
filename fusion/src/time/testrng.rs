//! A tiny deterministic generator for the time tests (no dependency, reproducible).

/// 64-bit LCG (Knuth's MMIX constants); `unit` takes the top 53 bits.
#[derive(Debug, Clone)]
pub struct Lcg(pub u64);

impl Lcg {
    /// A uniform value in [0, 1).
    pub fn unit(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}
