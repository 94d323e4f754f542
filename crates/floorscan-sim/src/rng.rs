//! Deterministic randomness, defined here (not by an external crate whose algorithms may change
//! between versions) so that the same seed gives the same bytes on every machine and build.
//!
//! - [`Rng`]: xoshiro256** seeded through SplitMix64, for sequences (noise, odometry errors).
//! - [`hash2`] / [`value_noise`]: stateless hashing of lattice points, for textures fixed to
//!   the world (the carpet looks the same every time the robot passes).

/// SplitMix64 step: a well-mixed 64-bit value from a counter.
#[inline]
pub fn splitmix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A seed for stream `stream` derived from `seed` (independent sequences per frame, per run).
pub fn derive_seed(seed: u64, stream: u64) -> u64 {
    splitmix64(splitmix64(seed) ^ stream.wrapping_mul(0xD1B5_4A32_D192_ED03))
}

/// xoshiro256** pseudo-random generator.
#[derive(Debug, Clone)]
pub struct Rng {
    s: [u64; 4],
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        let mut z = seed;
        let mut s = [0u64; 4];
        for v in &mut s {
            z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
            *v = splitmix64(z);
        }
        Self { s }
    }

    #[inline]
    pub fn next_u64(&mut self) -> u64 {
        let result = self.s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = self.s[1] << 17;
        self.s[2] ^= self.s[0];
        self.s[3] ^= self.s[1];
        self.s[1] ^= self.s[2];
        self.s[0] ^= self.s[3];
        self.s[2] ^= t;
        self.s[3] = self.s[3].rotate_left(45);
        result
    }

    /// Uniform in [0, 1).
    #[inline]
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Standard normal (Box-Muller; exact distribution, for the odometry and exposure).
    pub fn normal(&mut self) -> f64 {
        let u1 = 1.0 - self.uniform(); // (0, 1]
        let u2 = self.uniform();
        (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
    }

    /// Approximately standard normal, fast: the Irwin-Hall sum of four 16-bit uniforms, scaled
    /// to unit variance (tails end at +-3.46). Used for per-pixel sensor noise.
    #[inline]
    pub fn normal_fast(&mut self) -> f32 {
        let r = self.next_u64();
        let sum = (r & 0xFFFF) + ((r >> 16) & 0xFFFF) + ((r >> 32) & 0xFFFF) + (r >> 48);
        // Mean 4 * 32767.5, variance 4 * (65536^2 - 1) / 12.
        const MEAN: f32 = 131_070.0;
        const INV_STD: f32 = 1.0 / 37_837.227;
        (sum as f32 - MEAN) * INV_STD
    }
}

/// 32-bit hash of a lattice point and a seed (multiply-xorshift mixing).
#[inline(always)]
fn mix(hx: u32, hy: u32, seed: u32) -> u32 {
    let mut h = hx ^ hy ^ seed;
    h ^= h >> 15;
    h = h.wrapping_mul(HASH_MIX[0]);
    h ^= h >> 12;
    h = h.wrapping_mul(HASH_MIX[1]);
    h ^ (h >> 15)
}

/// The multipliers of [`mix`] and of the lattice coordinates (shared with the lane kernels of
/// [`crate::noise_lanes`]).
pub(crate) const HASH_MIX: [u32; 2] = [0x2C1B_3C6D, 0x297A_2D39];
pub(crate) const HX: u32 = 0x8DA6_B343;
pub(crate) const HY: u32 = 0xD816_3841;
/// The scale of [`to_unit`]: 24 hash bits to [0, 2).
pub(crate) const UNIT_SCALE: f32 = 2.0 / (1u32 << 24) as f32;
/// 1.5 * 2^52: adding it rounds an f64 to an integer held in the low mantissa bits.
pub(crate) const FLOOR_MAGIC: f64 = 6_755_399_441_055_744.0;

#[inline(always)]
pub(crate) fn seed32(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

#[inline(always)]
fn to_unit(h: u32) -> f32 {
    // Through i32: a signed conversion is one instruction, an unsigned one is several.
    ((h >> 8) as i32) as f32 * UNIT_SCALE - 1.0
}

/// A hash of a lattice point and a seed, mapped to [-1, 1].
#[inline]
pub fn hash2(ix: i64, iy: i64, seed: u64) -> f32 {
    to_unit(mix(
        (ix as u32).wrapping_mul(HX),
        (iy as u32).wrapping_mul(HY),
        seed32(seed),
    ))
}

/// `x.floor()` as an integer, without a call into libm (x86-64's baseline has no rounding
/// instruction) nor a saturating conversion: adding 1.5 * 2^52 rounds to the nearest integer,
/// which sits in the low mantissa bits. Exact for |x| < 2^31; wraps (without any undefined
/// behaviour) beyond, which callers avoid (texture lattices, grid cells, sectors).
#[inline(always)]
pub fn fast_floor(x: f64) -> i64 {
    let t = x + FLOOR_MAGIC;
    let nearest = t.to_bits() as i32 as i64;
    nearest - ((t - FLOOR_MAGIC) > x) as i64
}

/// Smooth value noise in [-1, 1] at (x, y) in lattice units: hashed lattice values, blended with
/// a smoothstep. Its standard deviation is about 0.42 (measured in the tests).
#[inline]
pub fn value_noise(x: f64, y: f64, seed: u64) -> f32 {
    let (ix, iy) = (fast_floor(x), fast_floor(y));
    blend(&lattice_corners(ix, iy, seed32(seed)), x, y, ix, iy)
}

/// The hashed values at the corners of lattice cell (ix, iy) for the 32-bit seed `s`
/// (`seed32` of the noise's seed): (ix, iy), (ix + 1, iy), (ix, iy + 1), (ix + 1, iy + 1).
#[inline(always)]
pub(crate) fn lattice_corners(ix: i64, iy: i64, s: u32) -> [f32; 4] {
    let (x0, y0) = ((ix as u32).wrapping_mul(HX), (iy as u32).wrapping_mul(HY));
    let (x1, y1) = (x0.wrapping_add(HX), y0.wrapping_add(HY));
    [
        to_unit(mix(x0, y0, s)),
        to_unit(mix(x1, y0, s)),
        to_unit(mix(x0, y1, s)),
        to_unit(mix(x1, y1, s)),
    ]
}

/// [`value_noise`] at (x, y) from the corners of its lattice cell (ix, iy) = floor(x, y).
#[inline(always)]
pub(crate) fn blend(corners: &[f32; 4], x: f64, y: f64, ix: i64, iy: i64) -> f32 {
    let (tx, ty) = ((x - ix as f64) as f32, (y - iy as f64) as f32);
    let sx = tx * tx * (3.0 - 2.0 * tx);
    let sy = ty * ty * (3.0 - 2.0 * ty);
    let [a, b, c, d] = *corners;
    let top = a + (b - a) * sx;
    let bottom = c + (d - c) * sx;
    top + (bottom - top) * sy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn same_seed_same_sequence_and_streams_differ() {
        let (mut a, mut b) = (Rng::new(7), Rng::new(7));
        for _ in 0..100 {
            assert_eq!(a.next_u64(), b.next_u64());
        }
        assert_ne!(derive_seed(7, 0), derive_seed(7, 1));
        assert_ne!(
            Rng::new(derive_seed(7, 0)).next_u64(),
            Rng::new(derive_seed(7, 1)).next_u64()
        );
    }

    fn mean_var(v: &[f64]) -> (f64, f64) {
        let n = v.len() as f64;
        let m = v.iter().sum::<f64>() / n;
        (
            m,
            v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (n - 1.0),
        )
    }

    #[test]
    fn normals_have_zero_mean_and_unit_variance() {
        let mut r = Rng::new(1);
        let exact: Vec<f64> = (0..200_000).map(|_| r.normal()).collect();
        let fast: Vec<f64> = (0..200_000).map(|_| r.normal_fast() as f64).collect();
        for v in [exact, fast] {
            let (m, var) = mean_var(&v);
            // Standard errors: 0.0022 for the mean, 0.0032 for the variance.
            assert!(m.abs() < 0.01, "mean {m}");
            assert!((var - 1.0).abs() < 0.015, "variance {var}");
        }
    }

    #[test]
    fn fast_floor_matches_floor() {
        for x in [
            -2.5,
            -2.0,
            -1e-300,
            0.0,
            0.3,
            1.0,
            7.999,
            -7.999,
            0.5,
            1.5,
            -0.5,
            -1e-9,
            2e9 + 0.5,
            -2e9 - 0.5,
        ] {
            assert_eq!(fast_floor(x), x.floor() as i64, "{x}");
        }
    }

    #[test]
    fn uniform_is_in_the_unit_interval() {
        let mut r = Rng::new(3);
        let v: Vec<f64> = (0..100_000).map(|_| r.uniform()).collect();
        assert!(v.iter().all(|&x| (0.0..1.0).contains(&x)));
        let (m, var) = mean_var(&v);
        assert!((m - 0.5).abs() < 0.005 && (var - 1.0 / 12.0).abs() < 0.002);
    }

    #[test]
    fn value_noise_is_continuous_bounded_and_matches_lattice_values() {
        for i in 0..1000 {
            let x = i as f64 * 0.137 - 50.0;
            let y = i as f64 * 0.071 + 3.0;
            let n = value_noise(x, y, 5);
            assert!((-1.0..=1.0).contains(&n));
            assert!((value_noise(x + 1e-6, y, 5) - n).abs() < 1e-3);
        }
        assert_eq!(value_noise(3.0, -2.0, 9), hash2(3, -2, 9));
        let samples: Vec<f64> = (0..40_000)
            .map(|i| value_noise((i % 200) as f64 * 0.31, (i / 200) as f64 * 0.29, 1) as f64)
            .collect();
        let (m, var) = mean_var(&samples);
        assert!(
            m.abs() < 0.03 && (var.sqrt() - 0.42).abs() < 0.05,
            "mean {m} std {}",
            var.sqrt()
        );
    }
}
