//! Tests of [`super`] (lanes.rs): every kernel against the plain recurrence, the prefilter
//! against the exact test.

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
