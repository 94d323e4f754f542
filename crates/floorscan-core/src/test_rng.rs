//! The tests' fixed pseudo-random stream (xorshift64): the same numbers on every machine,
//! no dependency.

/// xorshift64 (Marsaglia 2003) from a non-zero seed.
pub(crate) struct XorShift(u64);

impl XorShift {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }

    /// `next_u64() % n` scaled to [0, 1) in steps of 1 / n.
    pub(crate) fn fraction(&mut self, n: u64) -> f64 {
        (self.next_u64() % n) as f64 / n as f64
    }
}
