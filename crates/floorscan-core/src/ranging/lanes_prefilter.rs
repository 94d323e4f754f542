//! The byte-average prefilter of 8-bit columns (d a power of two): a balanced tree of rounding
//! byte averages flags every column whose box-filter response may cross its threshold, so the
//! exact sums run only where a crossing is possible.

use super::*;

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
