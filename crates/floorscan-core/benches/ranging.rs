//! Per-frame ranging time on a 640x480 8-bit image with the boundary around mid-image:
//! incremental (row-major, all columns together; the 8-bit lane kernel this CPU runs, and at
//! 640 columns each kernel) vs the direct sum of eq. (1), for 32, 64 and 640 columns, and the
//! time to read every pixel once (the floor for the all-columns case), by a plain loop and by
//! the same loop compiled for AVX2, and by `vpsadbw` (one vector read at memory speed).
//!
//! Run: `cargo bench -p floorscan-core --bench ranging`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use floorscan_core::lanes::Kernel;
use floorscan_core::{
    ColumnSelection, GroundTable, ImageView, Point2, RangerOptions, Refinement, Scan, VisualRanger,
};
use std::hint::black_box;

const W: usize = 640;
const H: usize = 480;

/// Carpet-like noise below a wavy boundary around row 240, a brighter wall above.
fn frame() -> Vec<u8> {
    let mut s: u64 = 7;
    let mut img = vec![0u8; W * H];
    for v in 0..H {
        for u in 0..W {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((s >> 33) % 9) as i32 - 4;
            let boundary = 240.0 + 20.0 * (u as f64 / 50.0).sin();
            let base = if (v as f64) < boundary { 170 } else { 90 };
            img[v * W + u] = (base + noise) as u8;
        }
    }
    img
}

fn table() -> GroundTable {
    GroundTable::from_fn(W, H, 8, |u, v| {
        (v > 20.0).then(|| Point2::new(0.3 + (H as f64 - v) * 0.01, (W as f64 / 2.0 - u) * 0.004))
    })
    .unwrap()
}

fn ranging(c: &mut Criterion) {
    let img = frame();
    let view = ImageView::new(&img, W, H).unwrap();
    let mut group = c.benchmark_group("ranging_640x480");
    for n in [32usize, 64, 640] {
        let options = RangerOptions {
            columns: ColumnSelection::Count(n),
            refinement: Refinement::SubPixel,
            ..RangerOptions::default()
        };
        let mut ranger = VisualRanger::new(table(), options).unwrap();
        let mut scan = Scan::default();
        group.bench_with_input(BenchmarkId::new("incremental", n), &n, |b, _| {
            b.iter(|| ranger.scan_into(black_box(&view), 0.0, &mut scan).unwrap())
        });
        if n == 640 {
            for kernel in [Kernel::Portable, Kernel::Sse2, Kernel::Avx2, Kernel::Neon] {
                if ranger.set_kernel(kernel).is_ok() {
                    let id = format!("incremental_{}", kernel.name());
                    group.bench_with_input(BenchmarkId::new(id, n), &n, |b, _| {
                        b.iter(|| ranger.scan_into(black_box(&view), 0.0, &mut scan).unwrap())
                    });
                }
            }
            ranger.set_kernel(Kernel::detect()).unwrap();
        }
        group.bench_with_input(BenchmarkId::new("direct", n), &n, |b, _| {
            b.iter(|| {
                ranger
                    .scan_direct_into(black_box(&view), 0.0, &mut scan)
                    .unwrap()
            })
        });
    }
    group.bench_function("sum_all_pixels", |b| {
        b.iter(|| black_box(&img).iter().map(|&p| p as u32).sum::<u32>())
    });
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        group.bench_function("sum_all_pixels_avx2", |b| {
            // SAFETY: AVX2 checked above.
            b.iter(|| unsafe { sum_avx2(black_box(&img)) })
        });
        group.bench_function("read_image_psadbw_avx2", |b| {
            // SAFETY: AVX2 checked above.
            b.iter(|| unsafe { read_sad_avx2(black_box(&img)) })
        });
    }
    group.finish();
}

/// One read of the image, vectorised for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn sum_avx2(img: &[u8]) -> u32 {
    img.iter().map(|&p| p as u32).sum::<u32>()
}

/// One vector read of the image at memory speed: 32 bytes per `vpsadbw`, the fastest way to
/// touch every pixel (the yardstick for "near memory speed").
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn read_sad_avx2(img: &[u8]) -> u64 {
    use std::arch::x86_64::*;
    let mut acc = _mm256_setzero_si256();
    for c in img.chunks_exact(32) {
        let x = _mm256_loadu_si256(c.as_ptr() as *const __m256i);
        acc = _mm256_add_epi64(acc, _mm256_sad_epu8(x, _mm256_setzero_si256()));
    }
    let mut out = [0u64; 4];
    _mm256_storeu_si256(out.as_mut_ptr() as *mut __m256i, acc);
    out.iter().sum()
}

criterion_group!(benches, ranging);
criterion_main!(benches);
