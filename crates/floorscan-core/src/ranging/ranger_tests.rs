//! Tests of the visual range sensor against independent expectations: a column-by-column
//! brute-force scan with the direct sum of eq. (1), and synthetic images with known edges.

use proptest::prelude::*;

use crate::edge::{direct_response, refine_crossing, sharpest_step, threshold_to_sum, Refinement};
use crate::error::Error;
use crate::ground_table::GroundTable;
use crate::image::ImageView;
use crate::pose::Point2;
use crate::ranger::VisualRanger;
use crate::ranger_options::{ColumnSelection, ColumnStart, RangerOptions};
use crate::scan::{ColumnOutcome, ColumnStatus, Scan};

/// A table with ground below `horizon_row` (rows v >= horizon_row): x grows upwards, y to the left.
fn table(width: usize, height: usize, horizon_row: f64) -> GroundTable {
    GroundTable::from_fn(width, height, 4, |u, v| {
        (v >= horizon_row).then(|| {
            Point2::new(
                0.2 + (height as f64 - 1.0 - v) * 0.01,
                (width as f64 / 2.0 - u) * 0.005,
            )
        })
    })
    .unwrap()
}

/// Floor intensity below the edge (rows v >= floor_from_row), obstacle above.
fn step_image(
    width: usize,
    height: usize,
    floor_from_row: &[usize],
    floor: u8,
    obstacle: u8,
) -> Vec<u8> {
    let mut img = vec![0u8; width * height];
    for v in 0..height {
        for u in 0..width {
            img[v * width + u] = if v >= floor_from_row[u] {
                floor
            } else {
                obstacle
            };
        }
    }
    img
}

fn options(
    d: usize,
    threshold: f64,
    refinement: Refinement,
    columns: ColumnSelection,
) -> RangerOptions {
    RangerOptions {
        half_width_px: d,
        threshold,
        noise_multiple: 0.0,
        contrast: 0.0,
        mid_contrast: 0.0,
        mid_range_m: vec![0.0, 0.0],
        refinement,
        columns,
        start: ColumnStart::BottomMargin(0),
        max_range_m: None,
        floor_line_width_m: 0.0,
    }
}

const REFINEMENTS: [Refinement; 4] = [
    Refinement::FirstCrossing,
    Refinement::Peak,
    Refinement::SubPixel,
    Refinement::Step,
];

/// Column-by-column reference: direct sums, first crossing, same refinement, independent plan.
fn brute_force(
    table: &GroundTable,
    o: &RangerOptions,
    img: &[u8],
    width: usize,
    height: usize,
) -> Vec<(u32, ColumnStatus, f64)> {
    let d = o.half_width_px;
    let margin = match o.start {
        ColumnStart::BottomMargin(m) => m,
        _ => unreachable!(),
    };
    let start = height - 1 - margin;
    // Per column: its pixels (k from the bottom) and its test window, if any.
    type Column = (u32, Vec<i32>, Option<(usize, usize)>);
    let columns: Vec<Column> = o
        .column_indices(table)
        .unwrap()
        .into_iter()
        .map(|c| {
            let u = c as f64;
            let column: Vec<i32> = (0..height)
                .rev()
                .map(|v| img[v * width + c as usize] as i32)
                .collect();
            // Scanned from the start row, placed from the lowest row with ground above it.
            let Some(first) = (0..=start)
                .rev()
                .find(|&v| table.lookup(u, v as f64).is_some())
            else {
                return (c, column, None);
            };
            let mut top = first;
            while top > 0 && table.lookup(u, (top - 1) as f64).is_some() {
                top -= 1;
            }
            // Below the first row with ground, two black rows at the start (at most 1/16 of
            // full scale and a quarter of the first ground row's pixel) are a lens's dark
            // rim: the column starts at its first row with ground.
            let px = |v: usize| img[v * width + c as usize] as i32;
            let rim = first < start
                && px(first) > 3
                && (start - 1..=start).all(|v| px(v) <= 15 && 4 * px(v) <= px(first));
            let from = if rim { first } else { start };
            let lo = (height - 1 - from) + d;
            let hi = (height - 1 - top).min(height - 1 - d);
            (c, column, (lo <= hi).then_some((lo, hi)))
        })
        .collect();
    // The frame's threshold: the responses of each window's first rows (the near-floor band),
    // sorted, median absolute deviation; each column's: at least `contrast` x the mean of the
    // pixels those windows read.
    let band = ((0.12 * height as f64).round() as usize).max(4 * d + 1);
    let mut threshold = o.threshold;
    if o.noise_multiple > 0.0 {
        let scannable = columns.iter().filter(|(_, _, w)| w.is_some()).count();
        let stride = scannable.div_ceil(64).max(1);
        let mut s: Vec<i64> = columns
            .iter()
            .filter_map(|(_, col, w)| w.map(|(lo, hi)| (col, lo, hi)))
            .step_by(stride)
            .flat_map(|(col, lo, hi)| {
                (lo..=hi.min(lo + band - 1)).map(|k| direct_response(col, k, d) as i64)
            })
            .collect();
        if !s.is_empty() {
            s.sort_unstable();
            let median = s[s.len() / 2];
            let mut dev: Vec<i64> = s.iter().map(|v| (v - median).abs()).collect();
            dev.sort_unstable();
            let sigma = 1.4826 * dev[dev.len() / 2] as f64 / (2 * d) as f64;
            threshold = threshold.max(o.noise_multiple * sigma);
        }
    }
    // Per column: the threshold on the sums outside and inside the `mid_range_m` band
    // (`mid_contrast`, never above `contrast`, x the same mean).
    let column_threshold = |column: &[i32], lo: usize, hi: usize| {
        let pixels = &column[lo - d..=hi.min(lo + band - 1) + d];
        let mean = pixels.iter().map(|&p| p as f64).sum::<f64>() / pixels.len() as f64;
        if o.contrast > 0.0 {
            (
                threshold_to_sum(threshold.max(o.contrast * mean), d),
                threshold_to_sum(threshold.max(o.mid_contrast.min(o.contrast) * mean), d),
            )
        } else {
            (
                threshold_to_sum(threshold, d),
                threshold_to_sum(threshold, d),
            )
        }
    };
    let (near_m, far_m) = (o.mid_range_m[0], o.mid_range_m[1]);
    let in_band = |u: f64, k: usize| {
        near_m < far_m
            && table
                .lookup(u, (height - 1 - k) as f64)
                .is_some_and(|p| (near_m..=far_m).contains(&p.norm()))
    };
    columns
        .into_iter()
        .map(|(c, column, window)| {
            let u = c as f64;
            let Some((lo, hi)) = window else {
                return (c, ColumnStatus::Invalid, f64::NAN);
            };
            let (thr_out, thr_band) = column_threshold(&column, lo, hi);
            for k in lo..=hi {
                let thr = if in_band(u, k) { thr_band } else { thr_out };
                if direct_response(&column, k, d).abs() > thr {
                    if k == lo {
                        // the column's start row (its first row with ground below a dark rim)
                        return (c, ColumnStatus::TooClose, (height - 1 - (lo - d)) as f64);
                    }
                    let k_max = height - 1 - d;
                    let response = |k| direct_response(&column, k, d);
                    let peak = match o.refinement {
                        Refinement::Step => {
                            let p =
                                refine_crossing(Refinement::SubPixel, k, d, lo, k_max, response);
                            let sign = if response(k) >= 0 { 1 } else { -1 };
                            // the ramp followed up to 4d rows above the window, by brute force
                            let top = ((k + d + 1).min(k_max) + d + 4 * d + 2).min(height - 1);
                            let start = (p.k + d as f64 / 2.0 - 0.5).floor() as usize;
                            let mut above = 0;
                            while above < 4 * d
                                && start + above + 2 <= top
                                && sign * (column[start + above + 2] - column[start + above]) > 0
                            {
                                above += 1;
                            }
                            sharpest_step(p.k, sign, d as f64 / 2.0, above, k - 1 - d, top, |j| {
                                column[j]
                            })
                        }
                        r => refine_crossing(r, k, d, lo, k_max, response).k,
                    };
                    if peak > hi as f64 {
                        return (c, ColumnStatus::NoBoundary, (height - 1 - hi) as f64);
                    }
                    let row = (height - 1) as f64 - peak;
                    return match table.lookup(u, row) {
                        Some(_) => (c, ColumnStatus::Boundary, row),
                        None => (c, ColumnStatus::Invalid, row),
                    };
                }
            }
            (c, ColumnStatus::NoBoundary, (height - 1 - hi) as f64)
        })
        .collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(120))]
    /// The row-major incremental scan of all columns equals the column-by-column direct scan.
    #[test]
    fn scan_equals_brute_force_reference(
        width in 8usize..40, height in 24usize..60, seed in any::<u64>(),
        d in 1usize..6, threshold in 0.0..60.0f64, refinement_i in 0usize..4, n_cols in 1usize..8,
        margin in 0usize..4, horizon in 0.0..20.0f64, noise_multiple in prop::sample::select(vec![0.0, 0.5, 3.0]),
        contrast in prop::sample::select(vec![0.0, 0.02, 0.1]),
        mid_contrast in prop::sample::select(vec![0.0, 0.01, 0.05, 0.2]),
        mid_range_m in prop::sample::select(vec![vec![0.0, 0.0], vec![0.3, 0.45], vec![0.2, 10.0], vec![0.25, 0.26]]),
    ) {
        let mut rng = seed;
        let mut next = || { rng ^= rng << 13; rng ^= rng >> 7; rng ^= rng << 17; rng };
        // Blocky random image: runs of constant intensity, so edges and plateaus both occur.
        let mut img = vec![0u8; width * height];
        for u in 0..width {
            let mut v = height;
            while v > 0 {
                let run = 1 + (next() % 12) as usize;
                let val = (next() % 256) as u8;
                for vv in v.saturating_sub(run)..v { img[vv * width + u] = val; }
                v = v.saturating_sub(run);
            }
        }
        let refinement = REFINEMENTS[refinement_i];
        let o = RangerOptions { start: ColumnStart::BottomMargin(margin), noise_multiple, contrast, mid_contrast, mid_range_m, ..options(d, threshold, refinement, ColumnSelection::Count(n_cols.min(width))) };
        let t = table(width, height, horizon);
        let reference = brute_force(&t, &o, &img, width, height);
        match VisualRanger::new(t, o) {
            Ok(mut ranger) => {
                let view = ImageView::new(&img, width, height).unwrap();
                let scan = ranger.scan(&view, 0.0).unwrap();
                let mut direct = Scan::default();
                ranger.scan_direct_into(&view, 0.0, &mut direct).unwrap();
                prop_assert_eq!(&scan, &direct);
                for (r, (c, status, row)) in scan.readings.iter().zip(reference) {
                    prop_assert_eq!(r.column, c);
                    prop_assert_eq!(r.status(), status, "column {}", c);
                    if status != ColumnStatus::Invalid || row.is_finite() {
                        prop_assert!((r.row() - row).abs() < 1e-9 || (r.row().is_nan() && row.is_nan()), "column {}: {} vs {}", c, r.row(), row);
                    }
                }
            }
            Err(Error::InvalidOption { name: "half_width", .. }) => prop_assert!(2 * d + 2 > height),
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }
}

#[test]
fn sharp_step_edges_give_exact_rows_for_both_polarities() {
    let (w, h) = (64, 120);
    let floor_from: Vec<usize> = (0..w).map(|u| 40 + u).collect(); // one edge row per column
    for (floor, obstacle) in [(80u8, 170u8), (170, 80)] {
        let img = step_image(w, h, &floor_from, floor, obstacle);
        for refinement in [Refinement::Peak, Refinement::SubPixel, Refinement::Step] {
            let mut r = VisualRanger::new(
                table(w, h, 0.0),
                options(4, 20.0, refinement, ColumnSelection::Count(w)),
            )
            .unwrap();
            let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
            for reading in &scan.readings {
                let u = reading.column as usize;
                assert_eq!(reading.status(), ColumnStatus::Boundary, "u={u}");
                // The edge line lies between the first floor row and the obstacle row above it.
                assert_eq!(
                    reading.row(),
                    floor_from[u] as f64 - 0.5,
                    "u={u} {refinement:?}"
                );
                let expected = r
                    .table()
                    .lookup(u as f64, floor_from[u] as f64 - 0.5)
                    .unwrap();
                assert_eq!(reading.point(), Some(expected));
            }
        }
    }
}

#[test]
fn first_crossing_depends_on_contrast_and_peak_does_not() {
    let (w, h) = (8, 80);
    let floor_from = vec![40; w];
    let rows = |contrast: u8, refinement| {
        let img = step_image(w, h, &floor_from, 100, 100 + contrast);
        let mut r = VisualRanger::new(
            table(w, h, 0.0),
            options(6, 6.0, refinement, ColumnSelection::Count(1)),
        )
        .unwrap();
        r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0)
            .unwrap()
            .readings[0]
            .row()
    };
    // R = (sum above - sum below) / 2d; on the ramp below an edge at k = 39.5 with contrast C,
    // S(k) = (k + d - 39) C for k <= 39, crossing 2dT = 72 first at k = 38 (C = 15, row 41) and
    // at k = 34 (C = 120, row 45): the paper's rule places strong edges lower in the image.
    assert_eq!(rows(15, Refinement::FirstCrossing), 41.0);
    assert_eq!(rows(120, Refinement::FirstCrossing), 45.0);
    assert_eq!(rows(15, Refinement::SubPixel), 39.5);
    assert_eq!(rows(120, Refinement::SubPixel), 39.5);
}

#[test]
fn noisy_step_edges_are_found_within_a_pixel() {
    let (w, h) = (64, 120);
    let floor_from: Vec<usize> = (0..w).map(|u| 30 + (u * 7) % 60).collect();
    let mut img = step_image(w, h, &floor_from, 90, 150);
    let mut s: u64 = 12345;
    for p in img.iter_mut() {
        // Uniform noise in [-6, 6]: well below the 60-level step.
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        *p = (*p as i32 + ((s >> 33) % 13) as i32 - 6) as u8;
    }
    let mut r = VisualRanger::new(
        table(w, h, 0.0),
        options(4, 20.0, Refinement::SubPixel, ColumnSelection::Count(w)),
    )
    .unwrap();
    let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
    for reading in &scan.readings {
        let truth = floor_from[reading.column as usize] as f64 - 0.5;
        assert_eq!(reading.status(), ColumnStatus::Boundary);
        assert!(
            (reading.row() - truth).abs() <= 1.0,
            "u={} row {} truth {truth}",
            reading.column,
            reading.row()
        );
    }
}

#[test]
fn sub_pixel_refinement_finds_a_blurred_edge_centre() {
    let (w, h) = (16, 100);
    let erf = |x: f64| {
        // Abramowitz-Stegun 7.1.26, |error| < 1.5e-7.
        let t = 1.0 / (1.0 + 0.3275911 * x.abs());
        let y = 1.0
            - (((((1.061405429 * t - 1.453152027) * t) + 1.421413741) * t - 0.284496736) * t
                + 0.254829592)
                * t
                * (-x * x).exp();
        y.copysign(x)
    };
    for (i, centre) in [40.0, 40.25, 47.5, 52.8, 61.1].into_iter().enumerate() {
        for sigma in [0.8, 1.5, 2.5] {
            // Pixel v covers [v - 0.5, v + 0.5]; the floor (dark) is below the edge centre.
            let value = |v: f64| {
                let cdf =
                    |x: f64| 0.5 * (1.0 + erf((x - centre) / (sigma * std::f64::consts::SQRT_2)));
                // Mean over the pixel of the obstacle share (obstacle above, i.e. at smaller v).
                let share = (1..=20)
                    .map(|s| 1.0 - cdf(v - 0.5 + (s as f64 - 0.5) / 20.0))
                    .sum::<f64>()
                    / 20.0;
                (70.0 + 120.0 * share).round() as u8
            };
            let img: Vec<u8> = (0..h)
                .flat_map(|v| std::iter::repeat_n(value(v as f64), w))
                .collect();
            let mut r = VisualRanger::new(
                table(w, h, 0.0),
                options(5, 15.0, Refinement::SubPixel, ColumnSelection::Count(2)),
            )
            .unwrap();
            let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
            let row = scan.readings[0].row();
            assert!(
                (row - centre).abs() < 0.5,
                "case {i}: centre {centre} sigma {sigma}: row {row}"
            );
        }
    }
}

#[test]
fn obstacle_in_the_first_window_is_too_close_and_no_edge_is_no_boundary() {
    let (w, h) = (16, 60);
    // Column 0..8: obstacle from the very bottom; 8..16: plain floor everywhere.
    let floor_from: Vec<usize> = (0..w).map(|u| if u < 8 { h } else { 0 }).collect();
    let mut img = step_image(w, h, &floor_from, 90, 180);
    // The obstacle of the left half meets floor two rows from the bottom: inside the first window.
    for v in h - 2..h {
        for u in 0..8 {
            img[v * w + u] = 90;
        }
    }
    let t = table(w, h, 10.0);
    let mut r = VisualRanger::new(
        t,
        options(
            4,
            20.0,
            Refinement::SubPixel,
            ColumnSelection::Explicit(vec![2, 12]),
        ),
    )
    .unwrap();
    let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
    assert_eq!(scan.readings[0].status(), ColumnStatus::TooClose);
    assert_eq!(scan.readings[0].range_m(), f64::NEG_INFINITY);
    match scan.readings[1].outcome {
        ColumnOutcome::NoBoundary { top_row, farthest } => {
            // Highest row with ground: nodes every 4 px, the first node at or below the horizon
            // row 10 with ground is v = 12 (the cell from v = 8 has a no-ground corner).
            assert_eq!(top_row, 12.0);
            assert_eq!(Some(farthest), r.table().lookup(12.0, 12.0));
        }
        other => panic!("expected no boundary, got {other:?}"),
    }
}

#[test]
fn columns_without_ground_are_invalid() {
    let (w, h) = (16, 60);
    // No ground in the left half at all; ground above row 30 only in the right half.
    let t = GroundTable::from_fn(w, h, 1, |u, v| {
        (u >= 8.0 && v >= 30.0).then(|| Point2::new(1.0 + (59.0 - v) * 0.01, 0.0))
    })
    .unwrap();
    let floor_from = vec![20usize; w]; // the edge lies above the calibrated region
    let img = step_image(w, h, &floor_from, 90, 180);
    let mut r = VisualRanger::new(
        t,
        options(
            3,
            20.0,
            Refinement::SubPixel,
            ColumnSelection::Explicit(vec![2, 12]),
        ),
    )
    .unwrap();
    let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
    assert_eq!(scan.readings[0].status(), ColumnStatus::Invalid);
    assert!(scan.readings[0].near.is_none());
    // Column 12 scans only up to row 30 and the edge at row 19.5 is beyond: free up to row 30.
    assert_eq!(scan.readings[1].status(), ColumnStatus::NoBoundary);
    // A mask start above the floor makes the column invalid, not too close.
    let mut starts = vec![59u32; w];
    starts[12] = 25;
    let o = RangerOptions {
        start: ColumnStart::PerColumn(starts),
        ..options(
            3,
            20.0,
            Refinement::SubPixel,
            ColumnSelection::Explicit(vec![12]),
        )
    };
    let mut r = VisualRanger::new(r.table().clone(), o).unwrap();
    let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
    assert_eq!(scan.readings[0].status(), ColumnStatus::Invalid);
}

#[test]
fn columns_whose_bottom_rows_have_no_ground_scan_from_the_bottom_and_place_from_the_first_ground() {
    // A fisheye's bottom corners: the table trusts ground only from node row 40 up in
    // columns 0..8; columns 8..16 have ground from the bottom. Each column of the left half
    // has its own scene: an edge in the covered rows, an edge in the uncovered rows, an
    // obstacle from the bottom, plain floor.
    let (w, h) = (16, 60);
    let t = GroundTable::from_fn(w, h, 1, |u, v| {
        (v >= 5.0 && (u >= 8.0 || v <= 40.0)).then(|| Point2::new(0.2 + (59.0 - v) * 0.01, 0.0))
    })
    .unwrap();
    let floor_from = [20, 20, 50, 50, 0, 0, 58, 58, 20, 20, 20, 20, 20, 20, 20, 20];
    let img = step_image(w, h, &floor_from, 90, 180);
    for refinement in REFINEMENTS {
        let o = options(
            3,
            20.0,
            refinement,
            ColumnSelection::Explicit(vec![1, 3, 5, 7, 12]),
        );
        let mut r = VisualRanger::new(t.clone(), o.clone()).unwrap();
        let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
        // The lowest row with ground is 39: row 40's lookup interpolates towards node row 41.
        let first_ground = t.lookup(1.0, 39.0);
        assert!(first_ground.is_some() && t.lookup(1.0, 40.0).is_none());
        // Edge at row 19.5, inside the covered rows: placed, free space from row 39's ground.
        assert_eq!(
            scan.readings[0].status(),
            ColumnStatus::Boundary,
            "{refinement:?}"
        );
        // (within the filter's half-width: the first crossing comes up to d rows early)
        assert!(
            (scan.readings[0].row() - 19.5).abs() <= 3.5,
            "{refinement:?}"
        );
        assert_eq!(scan.readings[0].near, first_ground);
        // Edge at row 49.5, below the first row with ground: seen, but not placeable.
        assert_eq!(
            scan.readings[1].status(),
            ColumnStatus::Invalid,
            "{refinement:?}"
        );
        assert!(
            (scan.readings[1].row() - 49.5).abs() <= 3.5,
            "{refinement:?}"
        );
        // Plain floor: free from row 39's ground to the last row with ground.
        assert_eq!(scan.readings[2].status(), ColumnStatus::NoBoundary);
        assert_eq!(scan.readings[2].near, t.lookup(5.0, 39.0));
        // An obstacle meeting the floor two rows above the bottom (inside the first window):
        // too close; it covers the column up to row 39, so it stands on that row's ray at or
        // before `near`, where the map marks a too-close column.
        assert_eq!(scan.readings[3].status(), ColumnStatus::TooClose);
        assert_eq!(scan.readings[3].near, t.lookup(7.0, 39.0));
        // A column with ground from the bottom is as before.
        assert_eq!(scan.readings[4].near, t.lookup(12.0, 59.0));
        // The column-by-column reference agrees on every column.
        let mut all = o.clone();
        all.columns = ColumnSelection::Explicit((0..w as u32).collect());
        let mut r = VisualRanger::new(t.clone(), all.clone()).unwrap();
        let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
        let expected = brute_force(&t, &all, &img, w, h);
        for (reading, (c, status, row)) in scan.readings.iter().zip(&expected) {
            assert_eq!(reading.column, *c);
            assert_eq!(reading.status(), *status, "column {c} {refinement:?}");
            if row.is_finite() {
                assert!(
                    (reading.row() - row).abs() < 1e-9,
                    "column {c} {refinement:?}"
                );
            }
        }
    }
}

#[test]
fn a_dark_lens_rim_below_the_first_ground_row_is_not_an_obstacle() {
    // A circular fisheye's unlit corners: columns 0..8 have ground only from row 39 up, and
    // the bottom of the image is black there (outside the image circle). The step from black
    // to floor is the lens's rim, not an obstacle: those columns start at their first row
    // with ground, as a ranger told so by its start rows. Column 1's rim reaches row 41 (the
    // step was an unplaceable edge), column 3's only the bottom 5 rows (the step lay in the
    // first window: a phantom obstacle touching the robot); column 5's bottom rows are floor,
    // scanned from the bottom as before; columns 12 and 14 have ground from the bottom.
    let (w, h) = (16, 60);
    let t = GroundTable::from_fn(w, h, 1, |u, v| {
        (v >= 5.0 && (u >= 8.0 || v <= 40.0)).then(|| Point2::new(0.2 + (59.0 - v) * 0.01, 0.0))
    })
    .unwrap();
    let floor_from = [20; 16];
    let mut img = step_image(w, h, &floor_from, 90, 180);
    let mut blacken = |u: usize, rows: std::ops::RangeInclusive<usize>| {
        for v in rows {
            img[v * w + u] = 2;
        }
    };
    blacken(0, 41..=59);
    blacken(1, 41..=59);
    blacken(2, 55..=59);
    blacken(3, 55..=59);
    blacken(14, 55..=59); // ground from the bottom: black there is an obstacle, not a rim
    let cols = vec![1, 3, 5, 12, 14];
    for refinement in REFINEMENTS {
        let o = options(3, 20.0, refinement, ColumnSelection::Explicit(cols.clone()));
        let mut r = VisualRanger::new(t.clone(), o.clone()).unwrap();
        let view = ImageView::new(&img, w, h).unwrap();
        let scan = r.scan(&view, 0.0).unwrap();
        let ColumnStart::BottomMargin(margin) = o.start else {
            unreachable!()
        };
        let bottom = (h - 1 - margin) as u32;
        let mut starts: Vec<u32> = vec![bottom; w];
        starts[1] = 39;
        starts[3] = 39;
        let mut told = o.clone();
        told.start = ColumnStart::PerColumn(starts);
        let expected = VisualRanger::new(t.clone(), told)
            .unwrap()
            .scan(&view, 0.0)
            .unwrap();
        for (k, c) in cols.iter().enumerate() {
            let (got, want) = (&scan.readings[k], &expected.readings[k]);
            assert_eq!(got.status(), want.status(), "column {c} {refinement:?}");
            assert_eq!(got.start_row, want.start_row, "column {c} {refinement:?}");
            if want.row().is_finite() {
                assert!(
                    (got.row() - want.row()).abs() < 1e-9,
                    "column {c} {refinement:?}"
                );
            }
        }
        for k in 0..2 {
            assert_eq!(
                scan.readings[k].status(),
                ColumnStatus::Boundary,
                "{refinement:?}"
            );
            assert!(
                (scan.readings[k].row() - 19.5).abs() <= 3.5,
                "{refinement:?}"
            );
        }
        assert_eq!(scan.readings[2].start_row, bottom as f64);
        assert_eq!(scan.readings[4].status(), ColumnStatus::TooClose);
        // The direct filter and the column-by-column reference agree on every column, at
        // half-widths of every kernel path (2 and 4: the 8-bit prefilter), with the frame's
        // noise threshold and a mid-range band.
        let mut all = o.clone();
        all.columns = ColumnSelection::Explicit((0..w as u32).collect());
        for (d, noise, band) in [
            (2, 4.0, [0.3, 0.5]),
            (4, 4.0, [0.0, 0.0]),
            (4, 0.0, [0.3, 0.5]),
        ] {
            let mut other = all.clone();
            other.half_width_px = d;
            other.noise_multiple = noise;
            other.mid_contrast = 0.05;
            other.contrast = 0.1;
            other.mid_range_m = band.to_vec();
            let mut r = VisualRanger::new(t.clone(), other.clone()).unwrap();
            // a lit frame first: the plans move on the second
            r.scan(
                &ImageView::new(&step_image(w, h, &floor_from, 90, 180), w, h).unwrap(),
                0.0,
            )
            .unwrap();
            let scan = r.scan(&view, 0.0).unwrap();
            let reference = brute_force(&t, &other, &img, w, h);
            for (a, (c, status, row)) in scan.readings.iter().zip(&reference) {
                assert_eq!(a.status(), *status, "column {c} d {d} {refinement:?}");
                if row.is_finite() {
                    assert!(
                        (a.row() - row).abs() < 1e-9,
                        "column {c} d {d} {refinement:?}"
                    );
                }
            }
        }
        let mut r = VisualRanger::new(t.clone(), all.clone()).unwrap();
        let mut direct = Scan::default();
        r.scan_direct_into(&view, 0.0, &mut direct).unwrap();
        let scan = r.scan(&view, 0.0).unwrap();
        let reference = brute_force(&t, &all, &img, w, h);
        for ((a, b), (c, status, row)) in scan.readings.iter().zip(&direct.readings).zip(&reference)
        {
            assert_eq!(a.status(), *status, "column {c} {refinement:?}");
            assert_eq!(b.status(), *status, "column {c} {refinement:?}");
            if row.is_finite() {
                assert!((a.row() - row).abs() < 1e-9, "column {c} {refinement:?}");
            }
        }
        // 16-bit pixels (x 257, threshold alike) and a strided copy read the same rim.
        let wide: Vec<u16> = img.iter().map(|&p| p as u16 * 257).collect();
        let mut o16 = all.clone();
        o16.threshold *= 257.0;
        let mut r16 = VisualRanger::new(t.clone(), o16).unwrap();
        let b = r16
            .scan(&ImageView::new(&wide, w, h).unwrap(), 0.0)
            .unwrap();
        let mut strided = vec![0u8; 2 * w * h];
        for v in 0..h {
            for u in 0..w {
                strided[v * 2 * w + 2 * u] = img[v * w + u];
            }
        }
        let view2 = ImageView::with_strides(&strided, w, h, 2 * w, 2).unwrap();
        let c = r.scan(&view2, 0.0).unwrap();
        assert_eq!(scan, b, "{refinement:?}");
        assert_eq!(scan, c, "{refinement:?}");
        // Once the rim is lit (a frame without it), the columns start at the bottom again.
        let lit = step_image(w, h, &floor_from, 90, 180);
        let again = r.scan(&ImageView::new(&lit, w, h).unwrap(), 0.0).unwrap();
        assert!(again.readings.iter().all(|x| x.start_row == bottom as f64));
    }
}

#[test]
fn max_range_limits_how_far_columns_scan() {
    let (w, h) = (8, 100);
    let img = step_image(w, h, &[20; 8], 90, 180); // edge at row 19.5, x = 0.2 + 80 * 0.01 = 1.0 m
    let base = options(
        3,
        20.0,
        Refinement::SubPixel,
        ColumnSelection::Explicit(vec![4]),
    );
    let mut near = VisualRanger::new(
        table(w, h, 0.0),
        RangerOptions {
            max_range_m: Some(0.8),
            ..base.clone()
        },
    )
    .unwrap();
    let mut far = VisualRanger::new(table(w, h, 0.0), base).unwrap();
    let view = ImageView::new(&img, w, h).unwrap();
    assert_eq!(
        near.scan(&view, 0.0).unwrap().readings[0].status(),
        ColumnStatus::NoBoundary
    );
    assert_eq!(
        far.scan(&view, 0.0).unwrap().readings[0].status(),
        ColumnStatus::Boundary
    );
}

#[test]
fn sixteen_bit_and_strided_images_scan_like_their_8_bit_copies() {
    let (w, h) = (32, 80);
    let floor_from: Vec<usize> = (0..w).map(|u| 20 + u).collect();
    let img = step_image(w, h, &floor_from, 60, 200);
    let wide: Vec<u16> = img.iter().map(|&p| p as u16 * 257).collect();
    // Every other column of a 2w-wide buffer holds the image.
    let mut strided = vec![0u8; 2 * w * h];
    for v in 0..h {
        for u in 0..w {
            strided[v * 2 * w + 2 * u] = img[v * w + u];
        }
    }
    let o = options(4, 20.0, Refinement::SubPixel, ColumnSelection::Count(w));
    let mut r8 = VisualRanger::new(table(w, h, 0.0), o.clone()).unwrap();
    let mut r16 = VisualRanger::new(
        table(w, h, 0.0),
        RangerOptions {
            threshold: 20.0 * 257.0,
            ..o
        },
    )
    .unwrap();
    let a = r8.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
    let b = r16
        .scan(&ImageView::new(&wide, w, h).unwrap(), 0.0)
        .unwrap();
    let c = r8
        .scan(
            &ImageView::with_strides(&strided, w, h, 2 * w, 2).unwrap(),
            0.0,
        )
        .unwrap();
    assert_eq!(a, b);
    assert_eq!(a, c);
}

#[test]
fn wrong_image_size_and_impossible_options_are_errors() {
    let t = table(32, 40, 0.0);
    let mut r =
        VisualRanger::new(t.clone(), RangerOptions::default().clone_with_columns(8)).unwrap();
    let img = vec![0u8; 31 * 40];
    assert!(matches!(
        r.scan(&ImageView::new(&img, 31, 40).unwrap(), 0.0),
        Err(Error::InvalidImage(_))
    ));
    assert!(VisualRanger::new(
        t.clone(),
        RangerOptions {
            half_width_px: 20,
            ..RangerOptions::default().clone_with_columns(8)
        }
    )
    .is_err());
    assert!(VisualRanger::new(
        t.clone(),
        RangerOptions {
            start: ColumnStart::BottomMargin(40),
            ..RangerOptions::default().clone_with_columns(8)
        }
    )
    .is_err());
    assert!(VisualRanger::new(
        t,
        RangerOptions {
            start: ColumnStart::PerColumn(vec![3; 5]),
            ..RangerOptions::default().clone_with_columns(8)
        }
    )
    .is_err());
}

impl RangerOptions {
    fn clone_with_columns(self, n: usize) -> Self {
        RangerOptions {
            columns: ColumnSelection::Count(n),
            ..self
        }
    }
}

/// Blocky random columns: runs of constant intensity (edges and plateaus both occur), plus
/// noise of amplitude `noise`.
fn blocky_image(width: usize, height: usize, seed: u64, noise: u64) -> Vec<u8> {
    let mut rng = seed | 1;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let mut img = vec![0u8; width * height];
    for u in 0..width {
        let mut v = height;
        while v > 0 {
            let run = 1 + (next() % 40) as usize;
            let val = (next() % 256) as u8;
            for vv in v.saturating_sub(run)..v {
                let n = if noise > 0 {
                    (next() % (2 * noise + 1)) as i32 - noise as i32
                } else {
                    0
                };
                img[vv * width + u] = (val as i32 + n).clamp(0, 255) as u8;
            }
            v = v.saturating_sub(run);
        }
    }
    img
}

fn all_kernels() -> Vec<crate::lanes::Kernel> {
    use crate::lanes::Kernel;
    [Kernel::Portable, Kernel::Sse2, Kernel::Avx2, Kernel::Neon]
        .into_iter()
        .filter(|k| k.is_supported())
        .collect()
}

/// Scans with every kernel and checks each against the direct filter and the brute force.
fn check_every_kernel(
    t: &GroundTable,
    o: &RangerOptions,
    img: &[u8],
    width: usize,
    height: usize,
) -> Scan {
    let reference = brute_force(t, o, img, width, height);
    let mut ranger = VisualRanger::new(t.clone(), o.clone()).unwrap();
    let view = ImageView::new(img, width, height).unwrap();
    let mut direct = Scan::default();
    ranger.scan_direct_into(&view, 0.0, &mut direct).unwrap();
    for (r, (c, status, row)) in direct.readings.iter().zip(&reference) {
        assert_eq!((r.column, r.status()), (*c, *status));
        if *status != ColumnStatus::Invalid || row.is_finite() {
            assert!(
                (r.row() - row).abs() < 1e-9,
                "column {c}: {} vs {row}",
                r.row()
            );
        }
    }
    for kernel in all_kernels() {
        ranger.set_kernel(kernel).unwrap();
        let scan = ranger.scan(&view, 0.0).unwrap();
        assert_eq!(scan, direct, "{kernel:?}");
    }
    direct
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(150))]
    /// Wider images, many columns (all of them: the contiguous path; a count or an unordered
    /// list: the gathered path), every lane kernel: the same readings as the direct filter of
    /// eq. (1) column by column and as the brute-force scan.
    #[test]
    fn lane_kernels_scan_like_the_direct_filter(
        width in 17usize..100, height in 24usize..80, seed in any::<u64>(), noise in 0u64..6,
        d in 1usize..8, threshold in 0.0..60.0f64, refinement_i in 0usize..4,
        mode in 0usize..3, n_cols in 1usize..100, margin in 0usize..4, horizon in 0.0..20.0f64,
        noise_multiple in prop::sample::select(vec![0.0, 1.0, 5.0]),
        contrast in prop::sample::select(vec![0.0, 0.01, 0.12]),
        mid_contrast in prop::sample::select(vec![0.0, 0.03, 0.06]),
        mid_range_m in prop::sample::select(vec![vec![0.0, 0.0], vec![0.3, 0.6], vec![0.25, 0.4]]),
    ) {
        prop_assume!(2 * d + 2 <= height);
        let img = blocky_image(width, height, seed, noise);
        let refinement = REFINEMENTS[refinement_i];
        let columns = match mode {
            0 => ColumnSelection::Count(width),
            1 => ColumnSelection::Count(n_cols.min(width)),
            _ => ColumnSelection::Explicit(
                (0..n_cols).map(|i| ((seed >> (i % 40)) as usize + 7 * i) as u32 % width as u32).collect(),
            ),
        };
        let o = RangerOptions { start: ColumnStart::BottomMargin(margin), noise_multiple, contrast, mid_contrast, mid_range_m, ..options(d, threshold, refinement, columns) };
        check_every_kernel(&table(width, height, horizon), &o, &img, width, height);
    }
}

#[test]
fn every_column_of_a_640x480_frame_every_status_every_kernel() {
    let (w, h) = (640, 480);
    let mut img = blocky_image(w, h, 42, 3);
    // Columns 100-139: an obstacle from the bottom (too close); 200-239: plain floor (no edge).
    for v in 0..h {
        for u in 100..140 {
            img[v * w + u] = if v > h - 4 { 40 } else { 200 };
        }
        for u in 200..240 {
            img[v * w + u] = 90;
        }
    }
    // Ground below a horizon that climbs across the image; none at all right of u = 600.
    let t = GroundTable::from_fn(w, h, 8, |u, v| {
        (u < 600.0 && v >= 100.0 + u * 0.3)
            .then(|| Point2::new(0.2 + (h as f64 - v) * 0.01, (320.0 - u) * 0.004))
    })
    .unwrap();
    for (d, refinement) in [
        (1, Refinement::SubPixel),
        (4, Refinement::SubPixel),
        (4, Refinement::Peak),
        (4, Refinement::FirstCrossing),
        (4, Refinement::Step),
        (21, Refinement::SubPixel),
        (21, Refinement::Step),
    ] {
        let o = options(d, 10.0, refinement, ColumnSelection::Count(w));
        let scan = check_every_kernel(&t, &o, &img, w, h);
        for status in ColumnStatus::ALL {
            assert!(
                scan.readings.iter().any(|r| r.status() == status),
                "d={d}: no {status:?} column"
            );
        }
        let o = options(d, 10.0, refinement, ColumnSelection::Count(64));
        check_every_kernel(&t, &o, &img, w, h);
        let adaptive = RangerOptions {
            threshold: 2.0,
            noise_multiple: 4.0,
            contrast: 0.12,
            ..options(d, 10.0, refinement, ColumnSelection::Count(w))
        };
        check_every_kernel(&t, &adaptive, &img, w, h);
    }
}

#[test]
fn half_widths_past_the_16_bit_sums_scan_like_the_direct_filter() {
    // d = 127 > MAX_HALF_WIDTH_I16: 8-bit images take the 32-bit path.
    let (w, h) = (48, 300);
    let img = blocky_image(w, h, 5, 0);
    for d in [
        crate::lanes::MAX_HALF_WIDTH_I16,
        crate::lanes::MAX_HALF_WIDTH_I16 + 1,
    ] {
        let o = options(d, 2.0, Refinement::SubPixel, ColumnSelection::Count(w));
        check_every_kernel(&table(w, h, 0.0), &o, &img, w, h);
    }
}

/// Gaussian samples from a fixed stream (Box-Muller over xorshift).
fn gaussian_stream(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed | 1;
    move || {
        let mut uniform = || {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            ((s >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let (a, b) = (uniform(), uniform());
        (-2.0 * a.ln()).sqrt() * (2.0 * std::f64::consts::PI * b).cos()
    }
}

/// A synthetic frame: a floor of mean `floor` with Gaussian texture `sigma` below row
/// `edge_row`, an obstacle `contrast` brighter above it (same texture), seen through `gain`
/// and `offset`, rounded to 8 bits.
struct TexturedStep {
    w: usize,
    h: usize,
    edge_row: usize,
    floor: f64,
    contrast: f64,
    sigma: f64,
}

impl TexturedStep {
    fn image(&self, gain: f64, offset: f64, seed: u64) -> Vec<u8> {
        let mut g = gaussian_stream(seed);
        (0..self.h * self.w)
            .map(|i| {
                let base = if i / self.w < self.edge_row {
                    self.floor + self.contrast
                } else {
                    self.floor
                };
                (offset + gain * (base + self.sigma * g()))
                    .round()
                    .clamp(0.0, 255.0) as u8
            })
            .collect()
    }
}

#[test]
fn noise_threshold_finds_the_same_edge_under_gain_and_offset() {
    // A step of 40 grey levels over a floor textured with sigma 4 (R's sigma: 4 / sqrt(2d) =
    // 1.4, the threshold 4 x 1.4 = 5.7); then the light dims to 0.3 (12 levels; a fixed threshold
    // of 10 misses it) or the camera adds an offset of 60 and a gain of 1.5.
    let (w, h, edge) = (64, 120, 50);
    let fixed = options(4, 10.0, Refinement::SubPixel, ColumnSelection::Count(w));
    let adaptive = RangerOptions {
        threshold: 0.0,
        noise_multiple: 4.0,
        ..fixed.clone()
    };
    for (gain, offset) in [(1.0, 0.0), (0.3, 0.0), (1.5, 60.0)] {
        let scene = TexturedStep {
            w,
            h,
            edge_row: edge,
            floor: 80.0,
            contrast: 40.0,
            sigma: 4.0,
        };
        let img = scene.image(gain, offset, 7);
        let view = ImageView::new(&img, w, h).unwrap();
        let mut r = VisualRanger::new(table(w, h, 0.0), adaptive.clone()).unwrap();
        let scan = r.scan(&view, 0.0).unwrap();
        let expected = 4.0 * 4.0 * gain / 8f64.sqrt();
        assert!(
            (r.frame_threshold() / expected - 1.0).abs() < 0.15,
            "gain {gain}: threshold {} expected {expected}",
            r.frame_threshold()
        );
        let found = scan
            .readings
            .iter()
            .filter(|c| c.status() == ColumnStatus::Boundary && (c.row() - 49.5).abs() <= 1.0)
            .count();
        // The texture crosses 4 sigma somewhere in ~0.6 % of the columns (see the noise-only
        // test below); allowed: 5 %.
        assert!(
            found * 20 >= w * 19,
            "gain {gain} offset {offset}: {found} of {w}"
        );
        let mut f = VisualRanger::new(table(w, h, 0.0), fixed.clone()).unwrap();
        let fixed_found = f
            .scan(&view, 0.0)
            .unwrap()
            .readings
            .iter()
            .filter(|c| c.status() == ColumnStatus::Boundary && (c.row() - 49.5).abs() <= 1.0)
            .count();
        if gain < 1.0 {
            assert!(
                fixed_found < w / 2,
                "the fixed threshold found {fixed_found}"
            );
        }
    }
}

#[test]
fn noise_only_images_give_no_boundary_at_four_sigma() {
    // Pure Gaussian noise (no edge), the default noise multiple 4 and nothing else: |R| > 4
    // sigma has probability 6e-5 per row for Gaussian R, at most 0.6 % of the columns of ~100
    // rows (fewer: neighbouring rows' responses share pixels). Allowed: 1 % of the columns (the
    // stated rate), at any noise level and brightness.
    let (w, h) = (64, 120);
    let o = RangerOptions {
        threshold: 0.0,
        noise_multiple: RangerOptions::default().noise_multiple,
        ..options(4, 0.0, Refinement::Step, ColumnSelection::Count(w))
    };
    let mut columns = 0;
    let mut false_boundaries = 0;
    for frame in 0..40u64 {
        let (mean, sigma) = (
            [40.0, 120.0][frame as usize % 2],
            [2.0, 6.0, 12.0][frame as usize % 3],
        );
        let scene = TexturedStep {
            w,
            h,
            edge_row: 0,
            floor: mean,
            contrast: 0.0,
            sigma,
        };
        let img = scene.image(1.0, 0.0, 100 + frame);
        let mut r = VisualRanger::new(table(w, h, 0.0), o.clone()).unwrap();
        let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
        columns += scan.readings.len();
        false_boundaries += scan
            .readings
            .iter()
            .filter(|c| c.status() != ColumnStatus::NoBoundary)
            .count();
    }
    assert!(
        false_boundaries * 100 <= columns,
        "{false_boundaries} of {columns} columns"
    );
}

#[test]
fn step_refinement_lands_on_the_base_below_a_thin_dark_strip() {
    // Carpet (85) below row 60, a 3-row dark baseboard (30), a bright wall (120) above: the
    // box filter's peak is pulled towards the robot by the bright wall inside its window; the
    // sharpest step is the carpet-baseboard line at row 59.5.
    let (w, h) = (8, 100);
    let img: Vec<u8> = (0..h)
        .flat_map(|v| {
            let value = if v >= 60 {
                85
            } else if v >= 57 {
                30
            } else {
                120
            };
            std::iter::repeat_n(value, w)
        })
        .collect();
    let row = |refinement| {
        let mut r = VisualRanger::new(
            table(w, h, 0.0),
            options(4, 10.0, refinement, ColumnSelection::Count(1)),
        )
        .unwrap();
        r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0)
            .unwrap()
            .readings[0]
            .row()
    };
    assert_eq!(row(Refinement::Step), 59.5);
    assert!(
        row(Refinement::SubPixel) > 60.0,
        "{}",
        row(Refinement::SubPixel)
    );
}

#[test]
fn contrast_threshold_follows_each_columns_floor_brightness() {
    // Left half: floor 40, obstacle 52 (a 30 % change); right half: floor 160, obstacle 172
    // (7.5 %). With contrast 0.05 (a change of more than 10 % of the floor's brightness) the
    // dim half's edge is an edge and the bright half's is not; a fixed threshold of 5 (a step
    // of 10 levels) takes both.
    let (w, h) = (32, 100);
    let img: Vec<u8> = (0..h)
        .flat_map(|v| {
            (0..w).map(move |u| {
                let floor = if u < w / 2 { 40 } else { 160 };
                if v < 50 {
                    floor + 12
                } else {
                    floor
                }
            })
        })
        .collect();
    let view = ImageView::new(&img, w, h).unwrap();
    // every column in order (their bands' brightness summed row by row), the columns in
    // reverse and every other one (column by column), and starts that differ between the
    // halves (each column its own band rows): the same brightness, the same outcomes
    let all: Vec<u32> = (0..w as u32).collect();
    let reversed: Vec<u32> = all.iter().rev().copied().collect();
    let every_other: Vec<u32> = all.iter().step_by(2).copied().collect();
    let starts: Vec<u32> = (0..w).map(|u| (h - 1 - u % 2) as u32).collect();
    let selections = [
        (ColumnSelection::Count(w), ColumnStart::BottomMargin(0)),
        (
            ColumnSelection::Explicit(reversed),
            ColumnStart::BottomMargin(0),
        ),
        (
            ColumnSelection::Explicit(every_other),
            ColumnStart::BottomMargin(0),
        ),
        (ColumnSelection::Count(w), ColumnStart::PerColumn(starts)),
    ];
    for (columns, start) in selections {
        let scan = |threshold, contrast| {
            let o = RangerOptions {
                contrast,
                start: start.clone(),
                ..options(4, threshold, Refinement::Step, columns.clone())
            };
            VisualRanger::new(table(w, h, 0.0), o)
                .unwrap()
                .scan(&view, 0.0)
                .unwrap()
        };
        let relative = scan(0.0, 0.05);
        for r in &relative.readings {
            if (r.column as usize) < w / 2 {
                assert_eq!(r.status(), ColumnStatus::Boundary, "column {}", r.column);
                assert_eq!(r.row(), 49.5);
            } else {
                assert_eq!(r.status(), ColumnStatus::NoBoundary, "column {}", r.column);
            }
        }
        let fixed = scan(5.0, 0.0);
        assert!(fixed
            .readings
            .iter()
            .all(|r| r.status() == ColumnStatus::Boundary));
    }
}

#[test]
fn an_edge_at_the_robots_feet_in_every_column_stays_too_close_by_default() {
    // A bright bumper in the bottom 8 rows of every column (an edge inside every column's
    // first window and inside the near-floor band the noise is measured on): the band's
    // robust spread must not swallow the edge.
    let (w, h) = (64, 240);
    let scene = TexturedStep {
        w,
        h,
        edge_row: 0,
        floor: 90.0,
        contrast: 0.0,
        sigma: 3.0,
    };
    let mut img = scene.image(1.0, 0.0, 3);
    img[(h - 8) * w..].fill(250);
    let o = RangerOptions {
        start: ColumnStart::BottomMargin(0),
        ..RangerOptions::default()
    };
    let t = table(w, h, 0.0);
    let scan = VisualRanger::new(t, o)
        .unwrap()
        .scan(&ImageView::new(&img, w, h).unwrap(), 0.0)
        .unwrap();
    assert!(scan
        .readings
        .iter()
        .all(|r| r.status() == ColumnStatus::TooClose));
}

#[test]
fn step_refinement_lands_on_the_base_not_the_start_of_a_soft_contact_shadow() {
    // Floor 100 below row 70; a contact shadow darkening it by 3 levels a row up to the base
    // at row 60 (edge line 59.5); a dark obstacle (40) above. The box filter's peak is the
    // centre of mass of shadow and base together, below the base; the sharpest step is the
    // base.
    let (w, h) = (8, 100);
    let img: Vec<u8> = (0..h)
        .flat_map(|v| {
            let value = if v >= 70 {
                100
            } else if v >= 60 {
                100 - 3 * (70 - v as i32)
            } else {
                40
            };
            std::iter::repeat_n(value as u8, w)
        })
        .collect();
    let row = |refinement| {
        let mut r = VisualRanger::new(
            table(w, h, 0.0),
            options(4, 10.0, refinement, ColumnSelection::Count(1)),
        )
        .unwrap();
        r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0)
            .unwrap()
            .readings[0]
            .row()
    };
    // The parabola through the base's step and the shadow's (3 levels) moves it by 0.03 rows.
    assert!(
        (row(Refinement::Step) - 59.5).abs() < 0.05,
        "{}",
        row(Refinement::Step)
    );
    // The box filter's sub-pixel peak: 0.4 rows towards the robot.
    assert!(
        row(Refinement::SubPixel) > 59.8,
        "{}",
        row(Refinement::SubPixel)
    );
}

#[test]
fn step_refinement_follows_a_long_contact_shadow_to_the_base() {
    // A contact shadow longer than the filter's window: the floor (100) darkens as
    // 100 (1 - 0.5 exp(-r / 5)) at r rows below the base (edge line 59.5), ever faster towards
    // it, so the box filter crosses where the shadow starts, rows below the base. Above the
    // base, a dark (40) or a bright (150) obstacle. The step refinement follows the ramp up
    // and lands on the base (the parabola through the steps moves it by 0.2 rows; with the
    // bright obstacle the sharpest darkening step is the shadow's last, between the two floor
    // pixels below the brightening base, and the parabola leans further down: 1.5 rows).
    let (w, h) = (8, 100);
    for (obstacle, tolerance) in [(40.0, 0.25), (150.0, 1.6)] {
        let img: Vec<u8> = (0..h)
            .flat_map(|v| {
                let value = if v >= 60 {
                    let r = v as f64 - 59.5;
                    100.0 * (1.0 - 0.5 * (-r / 5.0).exp())
                } else {
                    obstacle
                };
                std::iter::repeat_n(value.round() as u8, w)
            })
            .collect();
        let row = |refinement| {
            let mut r = VisualRanger::new(
                table(w, h, 0.0),
                options(4, 3.0, refinement, ColumnSelection::Count(1)),
            )
            .unwrap();
            let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
            assert_eq!(scan.readings[0].status(), ColumnStatus::Boundary);
            scan.readings[0].row()
        };
        let (step, sub) = (row(Refinement::Step), row(Refinement::SubPixel));
        assert!(
            sub > 63.0,
            "obstacle {obstacle}: the filter's peak {sub} is on the shadow"
        );
        assert!(
            (step - 59.5).abs() <= tolerance,
            "obstacle {obstacle}: {step}"
        );
    }
}

#[test]
fn the_step_refinement_does_not_climb_past_a_sharp_base() {
    // A sharp base (floor 200, obstacle 150 above row 60: a 50-level step) with a second,
    // stronger darkening 6 rows up the obstacle (to 30: 120 levels), inside the ramp's reach:
    // the column stops darkening right above the base, so the refinement stays on it.
    let (w, h) = (8, 100);
    let img: Vec<u8> = (0..h)
        .flat_map(|v| {
            let value = if v >= 60 {
                200
            } else if v >= 54 {
                150
            } else {
                30
            };
            std::iter::repeat_n(value as u8, w)
        })
        .collect();
    let mut r = VisualRanger::new(
        table(w, h, 0.0),
        options(4, 10.0, Refinement::Step, ColumnSelection::Count(1)),
    )
    .unwrap();
    let scan = r.scan(&ImageView::new(&img, w, h).unwrap(), 0.0).unwrap();
    assert_eq!(scan.readings[0].row(), 59.5);
}

#[test]
fn a_low_contrast_edge_is_found_only_inside_the_mid_range_band() {
    // Floor 100, obstacle 108 above row 50 (an 8 % step: |R| = 4); `contrast` 0.06 asks for
    // |R| > 6, `mid_contrast` 0.03 for |R| > 3. The edge's ground lies 0.69-0.70 m away (the
    // test table: x = 0.2 + 0.01 per row from the bottom, y within +-0.04 m).
    let (w, h) = (16, 100);
    let floor_from = vec![50; w];
    let img = step_image(w, h, &floor_from, 100, 108);
    let view = ImageView::new(&img, w, h).unwrap();
    let scan = |mid_range_m: [f64; 2]| {
        let o = RangerOptions {
            contrast: 0.06,
            mid_contrast: 0.03,
            mid_range_m: mid_range_m.to_vec(),
            ..options(4, 0.0, Refinement::Step, ColumnSelection::Count(w))
        };
        VisualRanger::new(table(w, h, 0.0), o)
            .unwrap()
            .scan(&view, 0.0)
            .unwrap()
    };
    for r in &scan([0.6, 0.8]).readings {
        assert_eq!(r.status(), ColumnStatus::Boundary, "column {}", r.column);
        assert_eq!(r.row(), 49.5);
    }
    for band in [[0.0, 0.0], [0.2, 0.5], [0.75, 2.0]] {
        for r in &scan(band).readings {
            assert_eq!(r.status(), ColumnStatus::NoBoundary, "band {band:?}");
        }
    }
}

/// The frame's noise threshold computed the slow way: every stride-th scannable column (plan
/// order), the direct sum of eq. (1) at each row of its near-floor band, their robust spread.
fn brute_force_frame_threshold<P: crate::image::Pixel>(
    r: &VisualRanger,
    image: &ImageView<P>,
) -> f64 {
    let d = r.options.half_width_px;
    let band = crate::noise_threshold::near_band_rows(image.height(), d);
    let scannable: Vec<_> = r.plans.iter().filter(|p| p.window.is_some()).collect();
    let stride = scannable
        .len()
        .div_ceil(crate::noise_threshold::NOISE_COLUMNS)
        .max(1);
    let mut samples = Vec::new();
    for p in scannable.iter().step_by(stride) {
        let (lo, hi) = p.window.unwrap();
        for k in lo..=hi.min(lo + band - 1) {
            samples.push(crate::edge::direct_response_at(
                image,
                p.column as usize,
                k,
                d,
            ));
        }
    }
    let sigma = crate::noise_threshold::robust_sigma(&mut samples)
        .map_or(0.0, |s| r.options.noise_multiple * s / (2 * d) as f64);
    r.options.threshold.max(sigma)
}

#[test]
fn the_frame_noise_threshold_is_the_brute_force_one_for_every_column_layout() {
    // Consecutive columns (96: every other one pooled), a few with a margin, reversed, every
    // other one, starts that differ between columns (no shared band rows); 8-bit, strided
    // 8-bit and 16-bit images
    let (w, h) = (96, 120);
    for seed in [3, 11] {
        let img8 = blocky_image(w, h, seed, 25);
        let img16: Vec<u16> = img8
            .iter()
            .map(|&p| p as u16 * 256 + (p as u16 & 7))
            .collect();
        let strided: Vec<u8> = img8.iter().flat_map(|&p| [p, 0]).collect();
        let all: Vec<u32> = (0..w as u32).collect();
        let starts: Vec<u32> = (0..w).map(|u| (h - 1 - u % 3) as u32).collect();
        let selections = [
            (ColumnSelection::Count(w), ColumnStart::BottomMargin(0)),
            (ColumnSelection::Count(20), ColumnStart::BottomMargin(2)),
            (
                ColumnSelection::Explicit(all.iter().rev().copied().collect()),
                ColumnStart::BottomMargin(0),
            ),
            (
                ColumnSelection::Explicit(all.iter().step_by(2).copied().collect()),
                ColumnStart::BottomMargin(0),
            ),
            (ColumnSelection::Count(w), ColumnStart::PerColumn(starts)),
        ];
        for (columns, start) in selections {
            let o = RangerOptions {
                noise_multiple: 4.0,
                contrast: 0.1,
                start,
                ..options(4, 0.5, Refinement::Step, columns)
            };
            let mut r = VisualRanger::new(table(w, h, 0.0), o).unwrap();
            let view8 = ImageView::new(&img8, w, h).unwrap();
            r.scan(&view8, 0.0).unwrap();
            let expected = brute_force_frame_threshold(&r, &view8);
            assert!(
                expected > 0.5,
                "the noise sets the threshold here: {expected}"
            );
            assert_eq!(r.frame_threshold(), expected);
            let view = ImageView::with_strides(&strided, w, h, 2 * w, 2).unwrap();
            r.scan(&view, 0.0).unwrap();
            assert_eq!(r.frame_threshold(), expected);
            let view16 = ImageView::new(&img16, w, h).unwrap();
            r.scan(&view16, 0.0).unwrap();
            assert_eq!(
                r.frame_threshold(),
                brute_force_frame_threshold(&r, &view16)
            );
        }
    }
}
