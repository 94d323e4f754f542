//! Value noise at many points at once: the renderer collects the texture noise a row of pixels
//! needs and evaluates it here, four points per step in AVX2 lanes where the CPU has them (the
//! lattice hash needs 32-bit lane multiplies), one at a time otherwise.
//!
//! Every lane does the operations of [`crate::rng::value_noise`] in the same order (IEEE
//! additions, multiplications and conversions, no fused multiply-add, no reassociation), so the
//! values are the same bits whichever kernel runs (tested below on random points).

use crate::rng::{blend, fast_floor, lattice_corners};

/// Which implementation evaluates the noise.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoiseKernel {
    /// Plain Rust, one point at a time, any target.
    Portable,
    /// Four points per step in 256-bit AVX2 registers (x86-64 CPUs that have it).
    Avx2,
}

impl NoiseKernel {
    /// The fastest kernel this CPU runs.
    pub fn detect() -> Self {
        if Self::Avx2.is_supported() {
            Self::Avx2
        } else {
            Self::Portable
        }
    }

    /// Whether this CPU runs the kernel.
    pub fn is_supported(self) -> bool {
        match self {
            Self::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(not(target_arch = "x86_64"))]
            Self::Avx2 => false,
        }
    }
}

/// Noise requests and their values: [`NoiseBatch::start`] with room for the requests to come,
/// push points, [`NoiseBatch::evaluate`], read the values by the indices `push` returned.
#[derive(Debug, Clone, Default)]
pub struct NoiseBatch {
    /// Requests: the first `n` of each (the rest is room).
    x: Vec<f64>,
    y: Vec<f64>,
    seed: Vec<u32>,
    n: usize,
    values: Vec<f32>,
}

impl NoiseBatch {
    /// Forgets the requests and makes room for `room` of them (at least).
    #[inline]
    pub fn start(&mut self, room: usize) {
        if self.x.len() < room {
            self.x.resize(room, 0.0);
            self.y.resize(room, 0.0);
            self.seed.resize(room, 0);
            self.values.resize(room, 0.0);
        }
        self.n = 0;
    }

    /// Asks for the value noise at (x, y) in lattice units with the 32-bit seed `seed` (the
    /// `seed32` of the noise's seed); returns the index of its value. Past the room made by
    /// [`NoiseBatch::start`] it grows the buffers.
    #[inline(always)]
    pub fn push(&mut self, x: f64, y: f64, seed: u32) -> u32 {
        let i = self.n;
        if i >= self.x.len().min(self.y.len()).min(self.seed.len()) {
            self.start_more();
        }
        self.x[i] = x;
        self.y[i] = y;
        self.seed[i] = seed;
        self.n = i + 1;
        i as u32
    }

    #[cold]
    #[inline(never)]
    fn start_more(&mut self) {
        let n = self.n;
        self.start(2 * n + 16);
        self.n = n;
    }

    /// How many points were asked for since the last start.
    pub fn len(&self) -> usize {
        self.n
    }

    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Evaluates every requested point with `kernel` (the portable one where the CPU lacks it).
    pub fn evaluate(&mut self, kernel: NoiseKernel) {
        let n = self.n;
        self.values.resize(self.values.len().max(n), 0.0);
        value_noise_lanes(
            kernel,
            &self.x[..n],
            &self.y[..n],
            &self.seed[..n],
            &mut self.values[..n],
        );
    }

    /// The value of request `i` (after [`NoiseBatch::evaluate`]; 0 for an index never
    /// pushed).
    #[inline(always)]
    pub fn value(&self, i: u32) -> f32 {
        self.values.get(i as usize).copied().unwrap_or(0.0)
    }
}

/// The value noise at one point, with a 32-bit seed: [`crate::rng::value_noise`] after its
/// seed folding.
#[inline(always)]
fn value_noise_s32(x: f64, y: f64, s: u32) -> f32 {
    let (ix, iy) = (fast_floor(x), fast_floor(y));
    blend(&lattice_corners(ix, iy, s), x, y, ix, iy)
}

/// `out[i]` = the value noise at (`x[i]`, `y[i]`) with 32-bit seed `seeds[i]`, for i below the
/// shortest of the four lengths.
pub fn value_noise_lanes(
    kernel: NoiseKernel,
    x: &[f64],
    y: &[f64],
    seeds: &[u32],
    out: &mut [f32],
) {
    let n = out.len().min(x.len()).min(y.len()).min(seeds.len());
    let (x, y, seeds, out) = (&x[..n], &y[..n], &seeds[..n], &mut out[..n]);
    // Points done by a vector kernel; the portable loop does the rest.
    let done = match kernel {
        #[cfg(target_arch = "x86_64")]
        NoiseKernel::Avx2 if std::arch::is_x86_feature_detected!("avx2") => {
            let chunks = n / 4;
            // SAFETY: AVX2 is present (checked above); the kernel reads x, y, seeds and writes
            // out at indices below chunks * 4 <= n, the length of all four slices.
            unsafe { x86::noise_avx2(x, y, seeds, out, chunks) };
            chunks * 4
        }
        _ => 0,
    };
    for i in done..n {
        out[i] = value_noise_s32(x[i], y[i], seeds[i]);
    }
}

#[cfg(target_arch = "x86_64")]
pub(crate) mod x86 {
    use std::arch::x86_64::*;

    use crate::rng::{FLOOR_MAGIC, HASH_MIX, HX, HY, UNIT_SCALE};

    /// Floors of four f64 lanes, as [`crate::rng::fast_floor`] computes them: the floors as
    /// f64 (exact) and their low 32 bits (the hash's `ix as u32`).
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(crate) fn floor4(v: __m256d) -> (__m256d, __m128i) {
        let magic = _mm256_set1_pd(FLOOR_MAGIC);
        // The low 32-bit half of each 64-bit lane, packed into the low 128 bits.
        let low_halves = _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6);
        let t = _mm256_add_pd(v, magic);
        let nearest = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
            _mm256_castpd_si256(t),
            low_halves,
        ));
        // (t - MAGIC) > x: all ones where the nearest integer is above x (false for NaN, as
        // the scalar comparison).
        let above = _mm256_cmp_pd::<_CMP_GT_OQ>(_mm256_sub_pd(t, magic), v);
        let above_i32 = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(
            _mm256_castpd_si256(above),
            low_halves,
        ));
        // nearest - 1 where above (all ones is -1), in 32-bit lanes (wrapping, as `as u32`);
        // as f64: the i32 converted exactly, minus 1.0 where above (exact: the scalar's i64).
        let floor_i32 = _mm_add_epi32(nearest, above_i32);
        let floor_f64 = _mm256_sub_pd(
            _mm256_cvtepi32_pd(nearest),
            _mm256_and_pd(above, _mm256_set1_pd(1.0)),
        );
        (floor_f64, floor_i32)
    }

    /// The lattice hash of eight lanes (`mix` in crate::rng) mapped to [-1, 1] (`to_unit`).
    #[inline]
    #[target_feature(enable = "avx2")]
    fn hash_unit8(h: __m256i) -> __m256 {
        let [m1, m2] = HASH_MIX;
        let mut h = h;
        h = _mm256_xor_si256(h, _mm256_srli_epi32::<15>(h));
        h = _mm256_mullo_epi32(h, _mm256_set1_epi32(m1 as i32));
        h = _mm256_xor_si256(h, _mm256_srli_epi32::<12>(h));
        h = _mm256_mullo_epi32(h, _mm256_set1_epi32(m2 as i32));
        h = _mm256_xor_si256(h, _mm256_srli_epi32::<15>(h));
        let u = _mm256_cvtepi32_ps(_mm256_srli_epi32::<8>(h));
        _mm256_sub_ps(
            _mm256_mul_ps(u, _mm256_set1_ps(UNIT_SCALE)),
            _mm256_set1_ps(1.0),
        )
    }

    /// The smoothstep weight t t (3 - 2 t), in the scalar's order.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn smooth4(t: __m128) -> __m128 {
        _mm_mul_ps(
            _mm_mul_ps(t, t),
            _mm_sub_ps(_mm_set1_ps(3.0), _mm_mul_ps(_mm_set1_ps(2.0), t)),
        )
    }

    /// Value noise of `chunks` groups of four points.
    ///
    /// # Safety
    /// The CPU must have AVX2, and `x`, `y`, `seeds` and `out` must hold at least `chunks * 4`
    /// elements.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn noise_avx2(
        x: &[f64],
        y: &[f64],
        seeds: &[u32],
        out: &mut [f32],
        chunks: usize,
    ) {
        let hx = _mm_set1_epi32(HX as i32);
        let hy = _mm_set1_epi32(HY as i32);
        for c in 0..chunks {
            let i = c * 4;
            // SAFETY: i + 4 <= chunks * 4, within every slice (the caller's contract);
            // unaligned loads and stores.
            let (xv, yv, s) = unsafe {
                (
                    _mm256_loadu_pd(x.as_ptr().add(i)),
                    _mm256_loadu_pd(y.as_ptr().add(i)),
                    _mm_loadu_si128(seeds.as_ptr().add(i) as *const __m128i),
                )
            };
            let (fx, ix) = floor4(xv);
            let (fy, iy) = floor4(yv);
            // Corner hashes: lanes [a | b] = (x0, y0) | (x1, y0) and [c | d] = (x0, y1) |
            // (x1, y1), four points each.
            let x0 = _mm_mullo_epi32(ix, hx);
            let y0 = _mm_mullo_epi32(iy, hy);
            let x1 = _mm_add_epi32(x0, hx);
            let y1 = _mm_add_epi32(y0, hy);
            let xs = _mm256_set_m128i(x1, x0);
            let ss = _mm256_set_m128i(s, s);
            let ab = hash_unit8(_mm256_xor_si256(
                _mm256_xor_si256(xs, _mm256_set_m128i(y0, y0)),
                ss,
            ));
            let cd = hash_unit8(_mm256_xor_si256(
                _mm256_xor_si256(xs, _mm256_set_m128i(y1, y1)),
                ss,
            ));
            let (a, b) = (_mm256_castps256_ps128(ab), _mm256_extractf128_ps::<1>(ab));
            let (cc, d) = (_mm256_castps256_ps128(cd), _mm256_extractf128_ps::<1>(cd));
            // blend: fractions in f32, smoothstep, bilinear in the scalar's order.
            let tx = _mm256_cvtpd_ps(_mm256_sub_pd(xv, fx));
            let ty = _mm256_cvtpd_ps(_mm256_sub_pd(yv, fy));
            let (sx, sy) = (smooth4(tx), smooth4(ty));
            let top = _mm_add_ps(a, _mm_mul_ps(_mm_sub_ps(b, a), sx));
            let bottom = _mm_add_ps(cc, _mm_mul_ps(_mm_sub_ps(d, cc), sx));
            let v = _mm_add_ps(top, _mm_mul_ps(_mm_sub_ps(bottom, top), sy));
            // SAFETY: as the loads.
            unsafe { _mm_storeu_ps(out.as_mut_ptr().add(i), v) };
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::{seed32, value_noise, Rng};

    /// Random points: small and large, negative, on lattice lines, beyond the fast floor's
    /// exact range (where it wraps), with random seeds.
    fn points(n: usize, rng: &mut Rng) -> (Vec<f64>, Vec<f64>, Vec<u64>) {
        let mut coord = |i: usize| match i % 6 {
            0 => 20.0 * rng.uniform() - 10.0,
            1 => 2e4 * rng.uniform() - 1e4,
            2 => (200.0 * rng.uniform() - 100.0).floor(),
            3 => 6e9 * rng.uniform() - 3e9,
            4 => 1e-3 * rng.uniform() - 5e-4,
            _ => 2.0f64.powi(31) * (if rng.uniform() < 0.5 { -1.0 } else { 1.0 }) + rng.uniform(),
        };
        let x: Vec<f64> = (0..n).map(|i| coord(i * 7 / 5)).collect();
        let y: Vec<f64> = (0..n).map(|i| coord(i + 3)).collect();
        let seeds = (0..n).map(|_| rng.next_u64()).collect();
        (x, y, seeds)
    }

    fn check(kernel: NoiseKernel) {
        let mut rng = Rng::new(17);
        for n in [0, 1, 3, 4, 5, 8, 63, 4096] {
            let (x, y, seeds) = points(n, &mut rng);
            let s32: Vec<u32> = seeds.iter().map(|&s| seed32(s)).collect();
            let mut out = vec![f32::NAN; n];
            value_noise_lanes(kernel, &x, &y, &s32, &mut out);
            for i in 0..n {
                let want = value_noise(x[i], y[i], seeds[i]);
                assert_eq!(
                    out[i].to_bits(),
                    want.to_bits(),
                    "{kernel:?} point {i} of {n}: ({}, {})",
                    x[i],
                    y[i]
                );
            }
        }
    }

    #[test]
    fn the_portable_kernel_equals_value_noise_bit_for_bit() {
        check(NoiseKernel::Portable);
    }

    #[test]
    fn the_detected_kernel_equals_value_noise_bit_for_bit() {
        // AVX2 where the CPU has it (the lanes), else the portable kernel again.
        check(NoiseKernel::detect());
        check(NoiseKernel::Avx2);
    }

    #[test]
    fn a_batch_returns_each_requests_value_and_short_slices_are_cut() {
        let mut batch = NoiseBatch::default();
        let mut rng = Rng::new(3);
        let (x, y, seeds) = points(37, &mut rng);
        for kernel in [NoiseKernel::Portable, NoiseKernel::detect()] {
            batch.start(4);
            let ids: Vec<u32> = (0..37)
                .map(|i| batch.push(x[i], y[i], seed32(seeds[i])))
                .collect();
            assert_eq!(batch.len(), 37);
            batch.evaluate(kernel);
            for (i, &id) in ids.iter().enumerate() {
                assert_eq!(batch.value(id), value_noise(x[i], y[i], seeds[i]));
            }
        }
        // Mismatched lengths: only the common prefix is written.
        let mut out = [9.0f32; 5];
        value_noise_lanes(NoiseKernel::detect(), &x[..3], &y, &[1, 2, 3, 4], &mut out);
        assert_eq!(out[3..], [9.0, 9.0]);
    }
}
