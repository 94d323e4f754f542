//! Ground table lookup throughput: bilinear interpolation of a 640x480 table (8 px spacing) at
//! 100,000 random pixels below the horizon, in the Rust core (the Python API's figure, with its
//! array copies, is in bench/calibration.py).
//!
//! Run: `cargo bench -p floorscan-core --bench ground_table`

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use floorscan_core::{GroundTable, Point2};
use std::hint::black_box;

const W: usize = 640;
const H: usize = 480;
const N: usize = 100_000;

fn bench_lookup(c: &mut Criterion) {
    // A perspective-like mapping with no ground above row 100.
    let table = GroundTable::from_fn(W, H, 8, |u, v| {
        (v > 100.0).then(|| {
            let d = (v - 90.0) / 100.0;
            Point2::new(0.4 / d, (W as f64 / 2.0 - u) * 0.004 / d)
        })
    })
    .unwrap();
    let mut s: u64 = 1;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64
    };
    let pts: Vec<(f64, f64)> = (0..N)
        .map(|_| (next() * (W - 1) as f64, 120.0 + next() * (H - 121) as f64))
        .collect();
    let mut g = c.benchmark_group("ground_table");
    g.throughput(Throughput::Elements(N as u64));
    g.bench_function("lookup_100k_points", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for &(u, v) in &pts {
                if let Some(p) = table.lookup(black_box(u), black_box(v)) {
                    acc += p.x;
                }
            }
            acc
        })
    });
    g.finish();
}

criterion_group!(benches, bench_lookup);
criterion_main!(benches);
