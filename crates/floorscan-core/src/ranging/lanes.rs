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

/// Largest half-width the prefilter handles (a power of two up to this).
pub const MAX_PREFILTER_HALF_WIDTH: usize = 16;

/// Columns per prefilter block.
pub const BLOCK: usize = 32;

/// The prefilter's per-column byte threshold for raw-sum threshold `threshold_sum` and
/// half-width d, or `None` where the prefilter cannot help (d not a power of two up to
/// [`MAX_PREFILTER_HALF_WIDTH`], or a threshold so low that every pixel would be flagged).
///
/// The prefilter approximates the mean of the d rows above and the d rows below each pixel by
/// a balanced tree of rounding-up byte averages (`pavgb`): with d = 2^m, each approximate mean
/// M~ lies in [M, M + m/2], so |M~a - M~b| >= |Ma - Mb| - m/2. A crossing, |S| = d |Ma - Mb| >
/// t, therefore implies d (2 |M~a - M~b| + m) > 2t: a column is flagged when its byte
/// difference is at least the smallest D with d (2D + m) > 2t, and only flagged columns get the
/// exact test. Returned: that D - 1 (the test is `difference > value`).
pub fn prefilter_threshold(half_width: usize, threshold_sum: i32) -> Option<u8> {
    if !half_width.is_power_of_two() || half_width > MAX_PREFILTER_HALF_WIDTH {
        return None;
    }
    let (d, m) = (half_width as i64, half_width.trailing_zeros() as i64);
    let t = threshold_sum as i64;
    let d_min = (0..=255i64).find(|&diff| d * (2 * diff + m) > 2 * t)?;
    (d_min >= 1).then(|| (d_min - 1) as u8)
}

/// Flags the columns whose approximate box difference at row k may cross (see
/// [`prefilter_threshold`]): `rows` are the 2d + 1 rows k - d ..= k + d (the middle one
/// unused), `thresholds[i]` the column's byte threshold (255: never flagged). Writes
/// `flags[i]` non-zero for a flagged column, 0 otherwise, and returns whether any is set.
pub fn prefilter_u8(kernel: Kernel, rows: &[&[u8]], thresholds: &[u8], flags: &mut [u8]) -> bool {
    let n = thresholds.len();
    let d = rows.len() / 2;
    assert!(
        rows.len() == 2 * d + 1
            && d.is_power_of_two()
            && d <= MAX_PREFILTER_HALF_WIDTH
            && flags.len() == n
            && rows.iter().all(|r| r.len() >= n),
        "prefilter: mismatched buffers"
    );
    match kernel {
        #[cfg(target_arch = "x86_64")]
        Kernel::Avx2 if std::arch::is_x86_feature_detected!("avx2") => {
            // SAFETY: AVX2 is present (checked above); the body is safe code.
            unsafe { prefilter_avx2(rows, thresholds, flags) }
        }
        _ => prefilter_body(rows, thresholds, flags),
    }
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn prefilter_avx2(rows: &[&[u8]], thresholds: &[u8], flags: &mut [u8]) -> bool {
    prefilter_body(rows, thresholds, flags)
}

#[inline(always)]
fn prefilter_body(rows: &[&[u8]], thresholds: &[u8], flags: &mut [u8]) -> bool {
    match rows.len() / 2 {
        1 => prefilter_d::<1>(rows, thresholds, flags),
        2 => prefilter_d::<2>(rows, thresholds, flags),
        4 => prefilter_d::<4>(rows, thresholds, flags),
        8 => prefilter_d::<8>(rows, thresholds, flags),
        _ => prefilter_d::<16>(rows, thresholds, flags),
    }
}

#[inline(always)]
fn avg(a: [u8; BLOCK], b: [u8; BLOCK]) -> [u8; BLOCK] {
    let mut out = [0u8; BLOCK];
    for i in 0..BLOCK {
        out[i] = ((a[i] as u16 + b[i] as u16 + 1) >> 1) as u8;
    }
    out
}

/// The balanced average tree of the blocks at `rows[i]`, i < D (pairs (2i, 2i + 1) first).
///
/// # Safety
/// Each `rows[i] + o` points to at least BLOCK readable bytes.
#[inline(always)]
unsafe fn tree_mean<const D: usize>(rows: &[*const u8], o: usize) -> [u8; BLOCK] {
    let mut level = [[0u8; BLOCK]; D];
    for i in 0..D {
        level[i] = core::ptr::read_unaligned(rows[i].add(o) as *const [u8; BLOCK]);
    }
    let mut len = D;
    while len > 1 {
        for i in 0..len / 2 {
            level[i] = avg(level[2 * i], level[2 * i + 1]);
        }
        len /= 2;
    }
    level[0]
}

/// Flags of one block: |mean above - mean below| > threshold as a non-zero byte (the excess);
/// returns their OR.
///
/// # Safety
/// `rows` holds 2D + 1 pointers, each + o to at least BLOCK readable bytes.
#[inline(always)]
unsafe fn flag_block<const D: usize>(
    rows: &[*const u8],
    o: usize,
    thresholds: &[u8; BLOCK],
    flags: &mut [u8; BLOCK],
) -> u8 {
    let (a, b) = (tree_mean::<D>(&rows[D + 1..], o), tree_mean::<D>(rows, o));
    let mut any = 0u8;
    for i in 0..BLOCK {
        let diff = a[i].max(b[i]) - a[i].min(b[i]);
        flags[i] = diff.saturating_sub(thresholds[i]);
        any |= flags[i];
    }
    any
}

#[inline(always)]
fn prefilter_d<const D: usize>(rows: &[&[u8]], thresholds: &[u8], flags: &mut [u8]) -> bool {
    let n = thresholds.len();
    assert!(rows.len() == 2 * D + 1 && rows.iter().all(|r| r.len() >= n) && flags.len() == n);
    let mut any = 0u8;
    let full = n / BLOCK * BLOCK;
    let mut at = [core::ptr::null::<u8>(); 2 * MAX_PREFILTER_HALF_WIDTH + 1];
    for (p, r) in at.iter_mut().zip(rows) {
        *p = r.as_ptr();
    }
    for (o, (t, f)) in thresholds
        .chunks_exact(BLOCK)
        .zip(flags.chunks_exact_mut(BLOCK))
        .enumerate()
        .map(|(b, tf)| (b * BLOCK, tf))
    {
        let t: &[u8; BLOCK] = t.try_into().unwrap();
        let f: &mut [u8; BLOCK] = f.try_into().unwrap();
        // SAFETY: o + BLOCK <= full <= n <= every row's length (asserted above).
        any |= unsafe { flag_block::<D>(&at[..2 * D + 1], o, t, f) };
    }
    if full < n {
        // The tail through zero-padded copies (padding columns: threshold 255, never flagged).
        let m = n - full;
        let mut padded = [[0u8; BLOCK]; 2 * MAX_PREFILTER_HALF_WIDTH + 1];
        for (p, r) in padded.iter_mut().zip(rows) {
            p[..m].copy_from_slice(&r[full..n]);
        }
        for (p, block) in at.iter_mut().zip(&padded) {
            *p = block.as_ptr();
        }
        let mut t = [u8::MAX; BLOCK];
        t[..m].copy_from_slice(&thresholds[full..]);
        let mut f = [0u8; BLOCK];
        // SAFETY: each pointer starts a BLOCK-long array.
        any |= unsafe { flag_block::<D>(&at[..2 * D + 1], 0, &t, &mut f) };
        flags[full..].copy_from_slice(&f[..m]);
    }
    any != 0
}

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
mod tests {
    use super::*;

    fn kernels() -> Vec<Kernel> {
        [Kernel::Portable, Kernel::Sse2, Kernel::Avx2, Kernel::Neon]
            .into_iter()
            .filter(|k| k.is_supported())
            .collect()
    }

    /// Every kernel equals the plain i32 recurrence and threshold test, for row lengths that
    /// end inside a chunk and sums near the i16 limits of d = MAX_HALF_WIDTH_I16.
    #[test]
    fn kernels_match_the_plain_recurrence() {
        let mut rng = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            rng
        };
        let limit = (255 * MAX_HALF_WIDTH_I16) as i32;
        for n in [1usize, 7, 15, 16, 17, 31, 33, 64, 100, 640] {
            for _ in 0..20 {
                let rows: Vec<Vec<u8>> = (0..4)
                    .map(|_| (0..n).map(|_| next() as u8).collect())
                    .collect();
                // Start sums whose next value stays within +-255 d (as in the ranger).
                let start: Vec<i16> = (0..n)
                    .map(|i| {
                        let delta = rows[3][i] as i32 - rows[2][i] as i32 - rows[1][i] as i32
                            + rows[0][i] as i32;
                        let target = (next() % (2 * limit as u64 + 1)) as i32 - limit;
                        (target - delta).clamp(-limit - 510, limit + 510) as i16
                    })
                    .collect();
                let thresholds: Vec<i16> = (0..n)
                    .map(|_| match next() % 4 {
                        0 => i16::MAX,
                        1 => 0,
                        _ => (next() % 32_768) as i16,
                    })
                    .collect();
                let expected: Vec<i32> = (0..n)
                    .map(|i| {
                        start[i] as i32 + rows[3][i] as i32 - rows[2][i] as i32 - rows[1][i] as i32
                            + rows[0][i] as i32
                    })
                    .collect();
                let mut expected_masks = vec![0u32; n.div_ceil(LANES)];
                for (i, &v) in expected.iter().enumerate() {
                    if v.abs() > thresholds[i] as i32 {
                        expected_masks[i / LANES] |= lane_bits(i % LANES);
                    }
                }
                for k in kernels() {
                    let mut sums = start.clone();
                    let mut masks = vec![0xdead_beef; n.div_ceil(LANES)];
                    let r = [&rows[0][..], &rows[1], &rows[2], &rows[3]];
                    let any = advance_u8(k, &mut sums, &thresholds, r, &mut masks);
                    let got: Vec<i32> = sums.iter().map(|&s| s as i32).collect();
                    assert_eq!(got, expected, "{k:?} n={n}");
                    assert_eq!(masks, expected_masks, "{k:?} n={n}");
                    assert_eq!(any, expected_masks.iter().any(|&m| m != 0));
                    let mut again = vec![0u32; n.div_ceil(LANES)];
                    assert_eq!(test_sums(&sums, &thresholds, &mut again), any);
                    assert_eq!(again, expected_masks);
                }
            }
        }
    }

    /// The prefilter never misses a crossing: on random rows, every column whose exact |S|
    /// exceeds the threshold is flagged, for every power-of-two d and threshold, every kernel;
    /// and it flags no inactive column.
    #[test]
    fn prefilter_flags_every_crossing() {
        let mut rng = 0x1234_5678_9abc_def1u64;
        let mut next = move || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            rng
        };
        let mut flagged_without_crossing = 0usize;
        for d in [1usize, 2, 4, 8, 16] {
            for n in [1usize, 5, 31, 32, 33, 64, 100] {
                for _ in 0..60 {
                    // Rows of a random level plus noise of a random amplitude: near-threshold
                    // differences are common.
                    let amp = 1 + next() % 64;
                    let rows: Vec<Vec<u8>> = (0..2 * d + 1)
                        .map(|_| {
                            let level = next() % 256;
                            (0..n)
                                .map(|_| (level + next() % amp).min(255) as u8)
                                .collect()
                        })
                        .collect();
                    let q = (next() % (255 * d as u64)) as i32;
                    let Some(t8) = prefilter_threshold(d, q) else {
                        continue;
                    };
                    let thresholds: Vec<u8> = (0..n)
                        .map(|_| if next() % 5 == 0 { 255 } else { t8 })
                        .collect();
                    let refs: Vec<&[u8]> = rows.iter().map(|r| &r[..]).collect();
                    for k in kernels() {
                        let mut flags = vec![7u8; n];
                        let mut reference = vec![7u8; n];
                        prefilter_u8(Kernel::Portable, &refs, &thresholds, &mut reference);
                        let any = prefilter_u8(k, &refs, &thresholds, &mut flags);
                        assert_eq!(any, flags.iter().any(|&f| f != 0));
                        assert_eq!(flags, reference, "{k:?}");
                        for i in 0..n {
                            let s: i32 = (1..=d)
                                .map(|t| rows[d + t][i] as i32 - rows[d - t][i] as i32)
                                .sum();
                            if thresholds[i] == 255 {
                                assert_eq!(flags[i], 0, "inactive column flagged");
                            } else if s.abs() > q {
                                assert_ne!(flags[i], 0, "{k:?} d={d} missed |{s}| > {q}");
                            } else if flags[i] != 0 {
                                flagged_without_crossing += 1;
                            }
                        }
                    }
                }
            }
        }
        // Conservative, not useless: some flags are false alarms, but only near the threshold.
        assert!(flagged_without_crossing > 0);
    }

    #[test]
    fn prefilter_threshold_applies_where_it_can_help() {
        assert_eq!(prefilter_threshold(3, 80), None);
        assert_eq!(prefilter_threshold(32, 80), None);
        // d = 4, t = 80 (threshold 10): flagged from a byte difference of 20.
        assert_eq!(prefilter_threshold(4, 80), Some(19));
        // Thresholds so low that everything is flagged, or beyond any 8-bit difference.
        assert_eq!(prefilter_threshold(4, 0), None);
        assert_eq!(prefilter_threshold(1, 255), None);
        assert_eq!(prefilter_threshold(1, 254), Some(254));
    }

    /// Every aarch64 CPU has NEON: the vector kernel runs there, not the portable one.
    #[cfg(target_arch = "aarch64")]
    #[test]
    fn neon_is_detected_on_aarch64() {
        assert_eq!(Kernel::detect(), Kernel::Neon);
    }

    #[test]
    fn detected_kernel_is_supported() {
        assert!(Kernel::detect().is_supported());
        assert!(Kernel::Portable.is_supported());
    }
}
