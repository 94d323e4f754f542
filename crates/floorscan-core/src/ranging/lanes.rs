//! Column-lane kernels of the edge ranger: one image row step of the incremental box filter for
//! many columns at once, on 8-bit pixels with 16-bit running sums.
//!
//! The ranger keeps one running sum S per sampled column and moves all of them up one row at a
//! time (see [`crate::edge`]): `S(k) = S(k-1) + I(k+d) - I(k) - I(k-1) + I(k-1-d)`. For 8-bit
//! pixels |S| <= 255 d, so with d <= [`MAX_HALF_WIDTH_I16`] the sums fit an i16 and a 256-bit
//! register advances 16 columns per instruction. Each step also tests |S| > t per column and
//! writes, per chunk of [`LANES`] columns, a bit mask of the columns that crossed (bits 2i and
//! 2i + 1 for lane i, the layout of `pmovmskb` on 16-bit lanes).
//!
//! Four implementations give identical results (integer arithmetic, checked against each
//! other below): AVX2 (chosen at run time where the CPU has it), SSE2 (every x86-64 CPU), NEON
//! (every aarch64 CPU: the Raspberry Pi 3 and later, Jetson boards) and a portable one (other
//! targets, and the tail of a row shorter than a chunk). The prefilter is plain Rust that the
//! compiler vectorises for the target (compiled once more with AVX2 enabled, chosen at run time).

/// Columns per chunk (one mask word).
pub const LANES: usize = 16;

/// Largest half-width whose raw sums of 8-bit pixels fit an i16 with room for one row step.
pub const MAX_HALF_WIDTH_I16: usize = 126;

/// Which implementation of the kernels runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kernel {
    /// Plain Rust, any target.
    Portable,
    /// 128-bit SSE2 (x86-64 only).
    Sse2,
    /// 256-bit AVX2 (x86-64 CPUs that have it).
    Avx2,
    /// 128-bit NEON (every aarch64 CPU).
    Neon,
}

impl Kernel {
    /// The fastest kernel this CPU runs.
    pub fn detect() -> Self {
        [Self::Avx2, Self::Sse2, Self::Neon]
            .into_iter()
            .find(|k| k.is_supported())
            .unwrap_or(Self::Portable)
    }

    /// Whether this CPU runs the kernel.
    pub fn is_supported(self) -> bool {
        match self {
            Self::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Self::Sse2 => true,
            #[cfg(target_arch = "x86_64")]
            Self::Avx2 => std::arch::is_x86_feature_detected!("avx2"),
            #[cfg(target_arch = "aarch64")]
            Self::Neon => std::arch::is_aarch64_feature_detected!("neon"),
            #[allow(unreachable_patterns)]
            _ => false,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Portable => "portable",
            Self::Sse2 => "sse2",
            Self::Avx2 => "avx2",
            Self::Neon => "neon",
        }
    }
}

/// The mask of lane `i` in a chunk's mask word.
#[inline(always)]
pub fn lane_bits(i: usize) -> u32 {
    3 << (2 * i)
}

/// Advances `sums[i] += e[i] - c[i] - b[i] + a[i]` for every column i (with `rows = [a, b, c,
/// e]`, the rows k-1-d, k-1, k and k+d), then writes `masks[i / LANES]` with the columns whose
/// new |sum| exceeds `thresholds[i]`. Returns whether any column did.
///
/// Panics unless `thresholds` has the length of `sums`, every row at least that length, and
/// `masks` one word per started chunk.
pub fn advance_u8(
    kernel: Kernel,
    sums: &mut [i16],
    thresholds: &[i16],
    rows: [&[u8]; 4],
    masks: &mut [u32],
) -> bool {
    let n = sums.len();
    assert!(
        thresholds.len() == n
            && rows.iter().all(|r| r.len() >= n)
            && masks.len() >= n.div_ceil(LANES),
        "lane kernel: mismatched buffers"
    );
    let chunks = n / LANES;
    let mut any = false;
    // Columns done by a vector kernel; the portable one does the rest.
    let done = match kernel {
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 if std::arch::is_x86_feature_detected!("avx2") => {
            // SAFETY: AVX2 is present (checked above); every pointer offset the kernel reads or
            // writes is below chunks * LANES <= n (sums, thresholds, rows) or below chunks
            // (masks), within the lengths asserted above.
            any = unsafe { x86::advance_avx2(sums, thresholds, rows, masks, chunks) };
            chunks * LANES
        }
        #[cfg(target_arch = "x86_64")]
        Kernel::Sse2 | Kernel::Avx2 => {
            // SAFETY: SSE2 is part of x86-64; bounds as above.
            any = unsafe { x86::advance_sse2(sums, thresholds, rows, masks, chunks) };
            chunks * LANES
        }
        #[cfg(target_arch = "aarch64")]
        Kernel::Neon if std::arch::is_aarch64_feature_detected!("neon") => {
            // SAFETY: NEON is present (checked above); bounds as above.
            any = unsafe { arm::advance_neon(sums, thresholds, rows, masks, chunks) };
            chunks * LANES
        }
        _ => 0,
    };
    if done < n {
        any |= advance_portable(sums, thresholds, rows, masks, done);
    }
    any
}

/// The portable kernel from column `from` (a multiple of [`LANES`]) to the end.
fn advance_portable(
    sums: &mut [i16],
    thresholds: &[i16],
    [a, b, c, e]: [&[u8]; 4],
    masks: &mut [u32],
    from: usize,
) -> bool {
    let n = sums.len();
    let mut any = 0u32;
    for start in (from..n).step_by(LANES) {
        let mut m = 0u32;
        for i in start..(start + LANES).min(n) {
            let v = sums[i]
                .wrapping_add(e[i] as i16)
                .wrapping_sub(c[i] as i16)
                .wrapping_sub(b[i] as i16)
                .wrapping_add(a[i] as i16);
            sums[i] = v;
            if v.wrapping_abs() > thresholds[i] {
                m |= lane_bits(i - start);
            }
        }
        masks[start / LANES] = m;
        any |= m;
    }
    any != 0
}

/// Writes the masks of |sums[i]| > thresholds[i] without advancing; returns whether any is set.
pub fn test_sums(sums: &[i16], thresholds: &[i16], masks: &mut [u32]) -> bool {
    let mut any = 0u32;
    for (chunk, (s, t)) in sums.chunks(LANES).zip(thresholds.chunks(LANES)).enumerate() {
        let m = s.iter().zip(t).enumerate().fold(0u32, |m, (i, (s, t))| {
            m | if s.wrapping_abs() > *t {
                lane_bits(i)
            } else {
                0
            }
        });
        masks[chunk] = m;
        any |= m;
    }
    any != 0
}

/// `sums[i] += row[i]` (`add`) or `-= row[i]`, for building the first sums row-major.
pub fn accumulate_row(sums: &mut [i16], row: &[u8], add: bool) {
    let row = &row[..sums.len()];
    if add {
        for (s, &p) in sums.iter_mut().zip(row) {
            *s = s.wrapping_add(p as i16);
        }
    } else {
        for (s, &p) in sums.iter_mut().zip(row) {
            *s = s.wrapping_sub(p as i16);
        }
    }
}

#[path = "lanes_prefilter.rs"]
mod prefilter;
pub use prefilter::{prefilter_threshold, prefilter_u8, BLOCK, MAX_PREFILTER_HALF_WIDTH};

#[cfg(target_arch = "x86_64")]
mod x86 {
    use std::arch::x86_64::*;

    use super::LANES;

    /// # Safety
    /// The CPU has AVX2; `chunks * LANES` is at most the length of `sums`, `thresholds` and
    /// every row, and `chunks` at most the length of `masks`.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn advance_avx2(
        sums: &mut [i16],
        thresholds: &[i16],
        rows: [&[u8]; 4],
        masks: &mut [u32],
        chunks: usize,
    ) -> bool {
        let [a, b, c, e] = rows.map(|r| r.as_ptr());
        let s_ptr = sums.as_mut_ptr();
        let t_ptr = thresholds.as_ptr();
        let m_ptr = masks.as_mut_ptr();
        let mut any = 0u32;
        for ch in 0..chunks {
            let o = ch * LANES;
            macro_rules! widen {
                ($p:expr) => {
                    _mm256_cvtepu8_epi16(_mm_loadu_si128($p.add(o) as *const __m128i))
                };
            }
            let s = _mm256_loadu_si256(s_ptr.add(o) as *const __m256i);
            let up = _mm256_sub_epi16(widen!(e), widen!(c));
            let down = _mm256_sub_epi16(widen!(a), widen!(b));
            let s = _mm256_add_epi16(s, _mm256_add_epi16(up, down));
            _mm256_storeu_si256(s_ptr.add(o) as *mut __m256i, s);
            let t = _mm256_loadu_si256(t_ptr.add(o) as *const __m256i);
            let hit = _mm256_cmpgt_epi16(_mm256_abs_epi16(s), t);
            let m = _mm256_movemask_epi8(hit) as u32;
            *m_ptr.add(ch) = m;
            any |= m;
        }
        any != 0
    }

    /// # Safety
    /// As [`advance_avx2`], on any x86-64 CPU.
    #[target_feature(enable = "sse2")]
    pub(super) unsafe fn advance_sse2(
        sums: &mut [i16],
        thresholds: &[i16],
        rows: [&[u8]; 4],
        masks: &mut [u32],
        chunks: usize,
    ) -> bool {
        let zero = _mm_setzero_si128();
        let [a, b, c, e] = rows.map(|r| r.as_ptr());
        let s_ptr = sums.as_mut_ptr();
        let t_ptr = thresholds.as_ptr();
        let m_ptr = masks.as_mut_ptr();
        let mut any = 0u32;
        for ch in 0..chunks {
            let o = ch * LANES;
            macro_rules! load {
                ($p:expr) => {{
                    let x = _mm_loadu_si128($p.add(o) as *const __m128i);
                    (_mm_unpacklo_epi8(x, zero), _mm_unpackhi_epi8(x, zero))
                }};
            }
            let (a0, a1) = load!(a);
            let (b0, b1) = load!(b);
            let (c0, c1) = load!(c);
            let (e0, e1) = load!(e);
            let s0 = _mm_loadu_si128(s_ptr.add(o) as *const __m128i);
            let s1 = _mm_loadu_si128(s_ptr.add(o + 8) as *const __m128i);
            let s0 = _mm_add_epi16(
                s0,
                _mm_add_epi16(_mm_sub_epi16(e0, c0), _mm_sub_epi16(a0, b0)),
            );
            let s1 = _mm_add_epi16(
                s1,
                _mm_add_epi16(_mm_sub_epi16(e1, c1), _mm_sub_epi16(a1, b1)),
            );
            _mm_storeu_si128(s_ptr.add(o) as *mut __m128i, s0);
            _mm_storeu_si128(s_ptr.add(o + 8) as *mut __m128i, s1);
            let abs0 = _mm_max_epi16(s0, _mm_sub_epi16(zero, s0));
            let abs1 = _mm_max_epi16(s1, _mm_sub_epi16(zero, s1));
            let t0 = _mm_loadu_si128(t_ptr.add(o) as *const __m128i);
            let t1 = _mm_loadu_si128(t_ptr.add(o + 8) as *const __m128i);
            let m0 = _mm_movemask_epi8(_mm_cmpgt_epi16(abs0, t0)) as u32;
            let m1 = _mm_movemask_epi8(_mm_cmpgt_epi16(abs1, t1)) as u32;
            let m = m0 | (m1 << 16);
            *m_ptr.add(ch) = m;
            any |= m;
        }
        any != 0
    }
}

#[cfg(target_arch = "aarch64")]
mod arm {
    use std::arch::aarch64::*;

    use super::LANES;

    /// Lane i's weight in a half-chunk's mask: bits 2i and 2i + 1 (the x86 kernels' layout).
    const WEIGHTS: [u16; 8] = [
        0x3,
        0x3 << 2,
        0x3 << 4,
        0x3 << 6,
        0x3 << 8,
        0x3 << 10,
        0x3 << 12,
        0x3 << 14,
    ];

    /// # Safety
    /// The CPU has NEON; `chunks * LANES` is at most the length of `sums`, `thresholds` and
    /// every row, and `chunks` at most the length of `masks`.
    #[target_feature(enable = "neon")]
    pub(super) unsafe fn advance_neon(
        sums: &mut [i16],
        thresholds: &[i16],
        rows: [&[u8]; 4],
        masks: &mut [u32],
        chunks: usize,
    ) -> bool {
        let [a, b, c, e] = rows.map(|r| r.as_ptr());
        let s_ptr = sums.as_mut_ptr();
        let t_ptr = thresholds.as_ptr();
        let m_ptr = masks.as_mut_ptr();
        let weights = vld1q_u16(WEIGHTS.as_ptr());
        let mut any = 0u32;
        for ch in 0..chunks {
            let o = ch * LANES;
            macro_rules! load {
                ($p:expr) => {{
                    let x = vld1q_u8($p.add(o));
                    (
                        vreinterpretq_s16_u16(vmovl_u8(vget_low_u8(x))),
                        vreinterpretq_s16_u16(vmovl_high_u8(x)),
                    )
                }};
            }
            let (a0, a1) = load!(a);
            let (b0, b1) = load!(b);
            let (c0, c1) = load!(c);
            let (e0, e1) = load!(e);
            // Wrapping i16 arithmetic, as the other kernels.
            let s0 = vaddq_s16(
                vld1q_s16(s_ptr.add(o)),
                vaddq_s16(vsubq_s16(e0, c0), vsubq_s16(a0, b0)),
            );
            let s1 = vaddq_s16(
                vld1q_s16(s_ptr.add(o + 8)),
                vaddq_s16(vsubq_s16(e1, c1), vsubq_s16(a1, b1)),
            );
            vst1q_s16(s_ptr.add(o), s0);
            vst1q_s16(s_ptr.add(o + 8), s1);
            // vabsq_s16 wraps at i16::MIN as `wrapping_abs` and `_mm256_abs_epi16` do.
            let hit0 = vcgtq_s16(vabsq_s16(s0), vld1q_s16(t_ptr.add(o)));
            let hit1 = vcgtq_s16(vabsq_s16(s1), vld1q_s16(t_ptr.add(o + 8)));
            // Distinct bits per lane: their sum is their OR.
            let m0 = vaddvq_u16(vandq_u16(hit0, weights)) as u32;
            let m1 = vaddvq_u16(vandq_u16(hit1, weights)) as u32;
            let m = m0 | (m1 << 16);
            *m_ptr.add(ch) = m;
            any |= m;
        }
        any != 0
    }
}

#[cfg(test)]
#[path = "lanes_tests.rs"]
mod tests;
