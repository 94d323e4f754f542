//! Value noise for runs of nearby samples: a [`NoiseCell`] keeps the corner values of the last
//! lattice cell it evaluated, so consecutive pixels that fall in the same cell (most of them
//! when the noise is coarser than a pixel's footprint) skip the four hashes. The values are
//! those of [`crate::rng::value_noise`], bit for bit.

use crate::rng::{blend, fast_floor, lattice_corners, seed32};

/// The last lattice cell (and seed) evaluated, with its corner values.
#[derive(Debug, Clone)]
pub struct NoiseCell {
    ix: i64,
    iy: i64,
    seed: u32,
    corners: [f32; 4],
}

impl Default for NoiseCell {
    fn default() -> Self {
        // `fast_floor` never returns i64::MIN: the first call always evaluates its cell.
        NoiseCell {
            ix: i64::MIN,
            iy: i64::MIN,
            seed: 0,
            corners: [0.0; 4],
        }
    }
}

impl NoiseCell {
    /// [`crate::rng::value_noise`] at (x, y), reusing the corners of the previous call's cell.
    #[inline]
    pub fn value_noise(&mut self, x: f64, y: f64, seed: u64) -> f32 {
        let (ix, iy, s) = (fast_floor(x), fast_floor(y), seed32(seed));
        if ix != self.ix || iy != self.iy || s != self.seed {
            self.corners = lattice_corners(ix, iy, s);
            (self.ix, self.iy, self.seed) = (ix, iy, s);
        }
        blend(&self.corners, x, y, ix, iy)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{value_noise, Rng};

    #[test]
    fn equals_value_noise_bit_for_bit_along_random_walks_and_jumps() {
        let mut rng = Rng::new(4);
        let mut cell = NoiseCell::default();
        let (mut x, mut y) = (0.0f64, 0.0f64);
        for i in 0..200_000 {
            // Mostly small steps (same cell, as neighbouring pixels), sometimes a jump, a
            // negative coordinate or another seed.
            if i % 97 == 0 {
                (x, y) = (200.0 * rng.uniform() - 100.0, 200.0 * rng.uniform() - 100.0);
            } else {
                x += 0.2 * rng.uniform() - 0.1;
                y += 0.2 * rng.uniform() - 0.1;
            }
            let seed = if i % 13 == 0 { 77 } else { 5 };
            let want = value_noise(x, y, seed);
            assert_eq!(
                cell.value_noise(x, y, seed).to_bits(),
                want.to_bits(),
                "{x} {y}"
            );
        }
    }

    #[test]
    fn seeds_differing_only_in_their_high_bits_still_differ() {
        // seed32 folds the high half in: 1 and 1 | 1 << 32 are different noise.
        let mut cell = NoiseCell::default();
        let a = cell.value_noise(0.3, 0.4, 1);
        let b = cell.value_noise(0.3, 0.4, 1 | 1 << 32);
        assert_eq!(a, value_noise(0.3, 0.4, 1));
        assert_eq!(b, value_noise(0.3, 0.4, 1 | 1 << 32));
    }
}
