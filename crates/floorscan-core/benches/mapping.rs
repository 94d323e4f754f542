//! Map update speed: `cargo bench -p floorscan-core --bench mapping`.
//!
//! Workload (the same as bench/octomap): 10,000 scans of 64 rays, beams evenly spread over 360
//! degrees, ranges uniform in [0.2, 4] m, every ray a hit, robot on a random walk in a 40 m
//! square, 4 cm cells, once-per-scan rule in force. Criterion reports rays/s; the traversed
//! cell count printed first turns that into ns per traversed cell.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use floorscan_core::grid::Grid;
use floorscan_core::grid_options::GridOptions;
use floorscan_core::inserter::{Inserter, InserterOptions};
use floorscan_core::laser::{BeamAngles, LaserScan};
use floorscan_core::raycast::{cells_on_segment, FixedPoint};
use floorscan_core::{ColumnOutcome, ColumnReading, Point2, Pose2, Scan};
use std::hint::black_box;

const SCANS: usize = 10_000;
const BEAMS: usize = 64;

struct Workload {
    poses: Vec<Pose2>,
    ranges: Vec<f64>,
}

fn workload() -> Workload {
    let mut state = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut pose = Pose2::new(0.0, 0.0, 0.0);
    let mut poses = Vec::with_capacity(SCANS);
    let mut ranges = Vec::with_capacity(SCANS * BEAMS);
    for _ in 0..SCANS {
        let step = Pose2::new(0.1 * next(), 0.0, 0.4 * (next() - 0.5));
        pose = pose.compose(&step);
        if pose.x.abs() > 20.0 || pose.y.abs() > 20.0 {
            pose.yaw += std::f64::consts::PI;
            pose.x = pose.x.clamp(-20.0, 20.0);
            pose.y = pose.y.clamp(-20.0, 20.0);
        }
        poses.push(pose);
        ranges.extend((0..BEAMS).map(|_| 0.2 + 3.8 * next()));
    }
    Workload { poses, ranges }
}

fn layout(ranges: &[f64]) -> LaserScan<'_> {
    LaserScan {
        ranges_m: ranges,
        angles: BeamAngles::Uniform {
            min_rad: -std::f64::consts::PI,
            increment_rad: std::f64::consts::TAU / BEAMS as f64,
        },
        range_min_m: 0.0,
        range_max_m: 4.5,
    }
}

fn bench_laser(c: &mut Criterion) {
    let w = workload();
    let mut grid = Grid::new(GridOptions::default()).unwrap();
    let mut inserter = Inserter::new(InserterOptions::default()).unwrap();
    let zeros = [0.0; BEAMS];
    let stats = inserter
        .insert_lasers(
            &mut grid,
            &layout(&zeros),
            &w.ranges,
            &w.poses,
            &Pose2::IDENTITY,
        )
        .unwrap();
    eprintln!(
        "laser workload: {} rays, {} traversed cells ({:.1} per ray), {} cells hit; grid {} tiles, {} bytes ({:.3} bytes per allocated cell)",
        stats.rays,
        stats.cells_traversed,
        stats.cells_traversed as f64 / stats.rays as f64,
        stats.cells_hit,
        grid.allocated_tiles(),
        grid.memory_bytes(),
        grid.memory_bytes() as f64 / (grid.allocated_tiles() * floorscan_core::grid::TILE_CELLS) as f64,
    );
    let mut group = c.benchmark_group("mapping");
    group.sample_size(10);
    group.throughput(Throughput::Elements(stats.rays));
    group.bench_function("laser_10k_scans_64_rays_4m", |b| {
        b.iter(|| {
            inserter
                .insert_lasers(
                    &mut grid,
                    &layout(&zeros),
                    black_box(&w.ranges),
                    &w.poses,
                    &Pose2::IDENTITY,
                )
                .unwrap()
        })
    });

    // The bare walk, no storage: a floor for the per-cell cost.
    let segments: Vec<(FixedPoint, FixedPoint)> = w
        .poses
        .iter()
        .zip(w.ranges.chunks(BEAMS))
        .flat_map(|(p, rs)| {
            rs.iter().enumerate().map(move |(i, r)| {
                let a =
                    p.yaw - std::f64::consts::PI + i as f64 * std::f64::consts::TAU / BEAMS as f64;
                let fp = |x: f64, y: f64| FixedPoint::from_cells(x / 0.04, y / 0.04).unwrap();
                (fp(p.x, p.y), fp(p.x + r * a.cos(), p.y + r * a.sin()))
            })
        })
        .collect();
    group.bench_function("walk_only_640k_rays", |b| {
        b.iter(|| {
            let mut n = 0usize;
            for &(a, e) in &segments {
                n += cells_on_segment(a, e).unwrap().count();
            }
            black_box(n)
        })
    });
    group.finish();
}

fn bench_visual(c: &mut Criterion) {
    // 64 columns over a 90 degree field of view, near edge 0.3 m, boundaries up to 4 m.
    let w = workload();
    let scans: Vec<Scan> = w
        .ranges
        .chunks(BEAMS)
        .map(|rs| Scan {
            timestamp_s: 0.0,
            readings: rs
                .iter()
                .enumerate()
                .map(|(i, &r)| {
                    let a = -0.785 + 1.57 * i as f64 / (BEAMS - 1) as f64;
                    let (s, c) = a.sin_cos();
                    ColumnReading {
                        column: i as u32,
                        start_row: 470.0,
                        near: Some(Point2::new(0.3 * c, 0.3 * s)),
                        outcome: ColumnOutcome::Boundary {
                            row: 200.0,
                            point: Point2::new(r.max(0.3) * c, r.max(0.3) * s),
                            footprint_m: 0.0,
                        },
                        confidence: 1.0,
                    }
                })
                .collect(),
        })
        .collect();
    let mut grid = Grid::new(GridOptions::default()).unwrap();
    let mut inserter = Inserter::new(InserterOptions::default()).unwrap();
    let mount = Pose2::new(0.1, 0.0, 0.0);
    let mut stats = floorscan_core::UpdateStats::default();
    for (s, p) in scans.iter().zip(&w.poses) {
        stats += inserter.insert_scan(&mut grid, s, p, &mount).unwrap();
    }
    eprintln!(
        "visual workload: {} rays, {} traversed cells ({:.1} per ray)",
        stats.rays,
        stats.cells_traversed,
        stats.cells_traversed as f64 / stats.rays as f64
    );
    let mut group = c.benchmark_group("mapping");
    group.sample_size(10);
    group.throughput(Throughput::Elements((SCANS * BEAMS) as u64));
    group.bench_function("visual_10k_scans_64_columns_90deg", |b| {
        b.iter(|| {
            for (s, p) in scans.iter().zip(&w.poses) {
                inserter.insert_scan(&mut grid, s, p, &mount).unwrap();
            }
        })
    });
    group.finish();
}

criterion_group!(benches, bench_laser, bench_visual);
criterion_main!(benches);
