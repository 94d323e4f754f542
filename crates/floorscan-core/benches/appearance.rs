//! Per-frame time of the appearance ranger on a 640x480 RGB image (a tiled floor with grout
//! and noise below a wavy boundary around row 240, a wall of another colour above): learning
//! the reference band plus scanning 64 and all 640 columns. The numpy/OpenCV side-by-side is
//! bench/appearance_vs_numpy.py.
//!
//! Run: `cargo bench -p floorscan-core --bench appearance`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use floorscan_core::{
    AppearanceOptions, AppearanceRanger, ColourView, ColumnSelection, GroundTable, Point2, Scan,
};
use std::hint::black_box;

const W: usize = 640;
const H: usize = 480;

fn frame() -> Vec<u8> {
    let mut s: u64 = 7;
    let mut img = vec![0u8; W * H * 3];
    for v in 0..H {
        for u in 0..W {
            let boundary = 240.0 + 20.0 * (u as f64 / 50.0).sin();
            let base: [i32; 3] = if (v as f64) < boundary {
                [60, 90, 170]
            } else if u % 40 < 2 || v % 40 < 2 {
                [90, 90, 88]
            } else if (u / 40 + v / 40) % 2 == 0 {
                [150, 135, 115]
            } else {
                [175, 160, 140]
            };
            for c in 0..3 {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                let noise = ((s >> 33) % 9) as i32 - 4;
                img[(v * W + u) * 3 + c] = (base[c] + noise).clamp(0, 255) as u8;
            }
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

fn appearance(c: &mut Criterion) {
    let img = frame();
    let view = ColourView::interleaved(&img, W, H).unwrap();
    let mut group = c.benchmark_group("appearance_640x480");
    for n in [64usize, 640] {
        let options = AppearanceOptions {
            columns: ColumnSelection::Count(n),
            max_range_m: None,
            ..AppearanceOptions::default()
        };
        let mut ranger = AppearanceRanger::new(table(), options).unwrap();
        let mut scan = Scan::default();
        group.bench_with_input(BenchmarkId::new("learn_and_scan", n), &n, |b, _| {
            b.iter(|| ranger.scan_into(black_box(&view), 0.0, &mut scan).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, appearance);
criterion_main!(benches);
