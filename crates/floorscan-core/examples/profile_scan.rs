//! Runs the ranging benchmark frame many times, for profilers (callgrind, perf):
//! `cargo run --release -p floorscan-core --example profile_scan -- 64 2000`
use floorscan_core::{
    ColumnSelection, GroundTable, ImageView, Point2, RangerOptions, Scan, VisualRanger,
};

fn main() {
    let args: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse().unwrap())
        .collect();
    let (n, reps) = (
        args.first().copied().unwrap_or(64),
        args.get(1).copied().unwrap_or(1000),
    );
    let (w, h) = (640usize, 480usize);
    let mut s: u64 = 7;
    let mut img = vec![0u8; w * h];
    for v in 0..h {
        for u in 0..w {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let noise = ((s >> 33) % 9) as i32 - 4;
            let boundary = 240.0 + 20.0 * (u as f64 / 50.0).sin();
            img[v * w + u] = ((if (v as f64) < boundary { 170 } else { 90 }) + noise) as u8;
        }
    }
    let table = GroundTable::from_fn(w, h, 8, |u, v| {
        (v > 20.0).then(|| Point2::new(0.3 + (h as f64 - v) * 0.01, (w as f64 / 2.0 - u) * 0.004))
    })
    .unwrap();
    let options = RangerOptions {
        columns: ColumnSelection::Count(n),
        ..RangerOptions::default()
    };
    let mut ranger = VisualRanger::new(table, options).unwrap();
    let view = ImageView::new(&img, w, h).unwrap();
    let mut scan = Scan::default();
    let t0 = std::time::Instant::now();
    for _ in 0..reps {
        ranger.scan_into(&view, 0.0, &mut scan).unwrap();
    }
    println!(
        "{n} columns: {:.2} us per frame",
        t0.elapsed().as_secs_f64() * 1e6 / reps as f64
    );
}
