//! Tests of the appearance range sensor on synthetic colour images with exactly known
//! boundaries: a tiled, noisy floor (grout lines, two tile colours) and obstacles of another
//! colour, against a brute-force scan of the true obstacle mask with the same column rule.

use crate::appearance::AppearanceRanger;
use crate::appearance_options::{AppearanceFeatures, AppearanceOptions};
use crate::colour_image::ColourView;
use crate::error::Error;
use crate::ground_table::GroundTable;
use crate::image::ImageView;
use crate::pose::Point2;
use crate::ranger_options::{ColumnSelection, ColumnStart};
use crate::scan::{ColumnOutcome, ColumnStatus};

const W: usize = 160;
const H: usize = 120;

/// Ground below `horizon_row`: x grows upwards, y to the left.
fn table(horizon_row: f64) -> GroundTable {
    GroundTable::from_fn(W, H, 4, |u, v| {
        (v >= horizon_row).then(|| {
            Point2::new(
                0.2 + (H as f64 - 1.0 - v) * 0.01,
                (W as f64 / 2.0 - u) * 0.005,
            )
        })
    })
    .unwrap()
}

/// A small deterministic noise in -6..=6.
fn noise(u: usize, v: usize, seed: u64) -> i32 {
    let mut x = (u as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (v as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ seed.wrapping_mul(0x1656_67B1_9E37_79F9);
    x ^= x >> 29;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 32;
    (x % 13) as i32 - 6
}

/// Tiles of 12 px with 2 px grout, two tile colours, noise; obstacle pixels (mask true) red.
fn tiled_image(obstacle: &dyn Fn(usize, usize) -> bool, seed: u64) -> Vec<u8> {
    let mut img = vec![0u8; W * H * 3];
    for v in 0..H {
        for u in 0..W {
            let base: [i32; 3] = if obstacle(u, v) {
                [200, 40, 40]
            } else if u % 14 < 2 || v % 14 < 2 {
                [90, 90, 88]
            } else if (u / 14 + v / 14) % 2 == 0 {
                [150, 135, 115]
            } else {
                [175, 160, 140]
            };
            for c in 0..3 {
                let n = noise(u, v, seed * 3 + c as u64);
                img[(v * W + u) * 3 + c] = (base[c] + n).clamp(0, 255) as u8;
            }
        }
    }
    img
}

fn options(features: AppearanceFeatures) -> AppearanceOptions {
    AppearanceOptions {
        columns: ColumnSelection::Count(W),
        start: ColumnStart::BottomMargin(0),
        max_range_m: None,
        features,
        ..Default::default()
    }
}

/// Brute force on the true mask: per column, rows from the bottom; a row is not floor when most
/// patch pixels are obstacle; the lowest row of the first run of `run` such rows is the boundary.
fn expected(
    obstacle: &dyn Fn(usize, usize) -> bool,
    u: usize,
    w: usize,
    run: usize,
) -> ColumnStatus2 {
    let (a, b) = (u.saturating_sub(w), (u + w).min(W - 1));
    let not_floor = |v: usize| 2 * (a..=b).filter(|&x| obstacle(x, v)).count() > b - a + 1;
    let mut count = 0;
    for k in 0..H {
        let v = H - 1 - k;
        if not_floor(v) {
            count += 1;
            if count == run {
                let lowest = v + run - 1;
                return if lowest == H - 1 {
                    ColumnStatus2::TooClose
                } else {
                    ColumnStatus2::Boundary(lowest as f64 + 0.5)
                };
            }
        } else {
            count = 0;
        }
    }
    ColumnStatus2::NoBoundary
}

#[derive(Debug, PartialEq)]
enum ColumnStatus2 {
    Boundary(f64),
    NoBoundary,
    TooClose,
}

fn observed(outcome: &ColumnOutcome) -> ColumnStatus2 {
    match outcome {
        ColumnOutcome::Boundary { row, .. } => ColumnStatus2::Boundary(*row),
        ColumnOutcome::NoBoundary { .. } => ColumnStatus2::NoBoundary,
        ColumnOutcome::TooClose => ColumnStatus2::TooClose,
        ColumnOutcome::Invalid { .. } => panic!("invalid column"),
    }
}

/// A box whose base follows a staircase and slope, a thin leg, and one column band that touches
/// the bottom (too close), over a tiled floor.
fn scene(u: usize, v: usize) -> bool {
    let base = match u {
        0..=39 => 40 + u / 2,
        40..=79 => 70,
        80..=89 => 95, // a 10 px leg
        90..=129 => 30,
        130..=139 => H, // touches the bottom row
        _ => 0,         // free to the top
    };
    v < base
}

/// The scene without the obstacle that touches the bottom: the floor the robot learned from
/// before it came too close (an obstacle inside the reference band is learned as floor in
/// proportion to the adaptation rate).
fn earlier_scene(u: usize, v: usize) -> bool {
    !(130..=139).contains(&u) && scene(u, v)
}

/// Learns `earlier_scene` (seed 0), then scans `scene` with a slow adaptation rate.
fn scan_scene(o: &AppearanceOptions, seed: u64) -> crate::scan::Scan {
    let o = AppearanceOptions {
        adaptation_rate: 0.02,
        ..o.clone()
    };
    let mut r = AppearanceRanger::new(table(0.0), o).unwrap();
    let before = tiled_image(&earlier_scene, 0);
    r.scan(&ColourView::interleaved(&before, W, H).unwrap(), 0.0)
        .unwrap();
    let img = tiled_image(&scene, seed);
    r.scan(&ColourView::interleaved(&img, W, H).unwrap(), 0.1)
        .unwrap()
}

#[test]
fn colour_boundaries_match_brute_force_on_a_tiled_floor() {
    let o = options(AppearanceFeatures::Colour);
    let scan = scan_scene(&o, 1);
    assert_eq!(scan.len(), W);
    for reading in &scan.readings {
        let u = reading.column as usize;
        let want = expected(&scene, u, o.patch_half_width_px, o.min_run_px);
        assert_eq!(observed(&reading.outcome), want, "column {u}");
        assert!((0.0..=1.0).contains(&reading.confidence));
    }
    let statuses: Vec<_> = scan.readings.iter().map(|r| r.status()).collect();
    for s in [
        ColumnStatus::Boundary,
        ColumnStatus::TooClose,
        ColumnStatus::NoBoundary,
    ] {
        assert!(statuses.contains(&s), "{s:?} never seen");
    }
}

#[test]
fn texture_features_land_within_a_row_of_the_truth() {
    let o = options(AppearanceFeatures::ColourAndTexture);
    let scan = scan_scene(&o, 2);
    for reading in &scan.readings {
        let u = reading.column as usize;
        match (
            expected(&scene, u, o.patch_half_width_px, o.min_run_px),
            observed(&reading.outcome),
        ) {
            (ColumnStatus2::Boundary(a), ColumnStatus2::Boundary(b)) => {
                assert!((a - b).abs() <= 1.0, "column {u}: {a} vs {b}")
            }
            (want, got) => assert_eq!(got, want, "column {u}"),
        }
    }
}

#[test]
fn grey_input_reads_as_equal_channels_and_the_range_limit_sets_the_top() {
    // A grey floor of two tones below row 60, a dark obstacle above; the table has ground
    // from row 32 down (a node row; the no-boundary columns stop there).
    let mut grey = vec![0u8; W * H];
    for v in 0..H {
        for u in 0..W {
            grey[v * W + u] = if u >= 100 || v >= 60 {
                if (u / 5 + v / 5) % 2 == 0 {
                    120
                } else {
                    150
                }
            } else {
                20
            };
        }
    }
    let rgb: Vec<u8> = grey.iter().flat_map(|&g| [g, g, g]).collect();
    let o = options(AppearanceFeatures::Colour);
    let mut a = AppearanceRanger::new(table(32.0), o.clone()).unwrap();
    let mut b = AppearanceRanger::new(table(32.0), o).unwrap();
    let sa = a
        .scan(&ColourView::grey(ImageView::new(&grey, W, H).unwrap()), 0.0)
        .unwrap();
    let sb = b
        .scan(&ColourView::interleaved(&rgb, W, H).unwrap(), 0.0)
        .unwrap();
    assert_eq!(sa, sb);
    for r in &sa.readings {
        match r.outcome {
            ColumnOutcome::Boundary { row, .. } => {
                assert!(r.column < 100);
                assert_eq!(row, 59.5);
            }
            ColumnOutcome::NoBoundary { top_row, .. } => {
                assert!(r.column >= 100);
                assert_eq!(top_row, 32.0);
            }
            other => panic!("column {}: {other:?}", r.column),
        }
    }
}

#[test]
fn the_adaptation_rate_weighs_the_newest_reference() {
    // Frame 1 learns a grey floor; frame 2's floor is brown. With a tiny adaptation rate brown
    // has too small a share of the model to count as floor (the robot looks too close);
    // after a reset the brown frame is the whole model.
    let make = |floor: [u8; 3]| -> Vec<u8> {
        (0..W * H)
            .flat_map(|i| if i / W < 20 { [20, 200, 20] } else { floor })
            .collect()
    };
    let (grey, brown) = (make([128, 128, 128]), make([150, 100, 60]));
    let o = AppearanceOptions {
        adaptation_rate: 0.001,
        ..options(AppearanceFeatures::Colour)
    };
    let mut r = AppearanceRanger::new(table(0.0), o).unwrap();
    let (grey, brown) = (
        ColourView::interleaved(&grey, W, H).unwrap(),
        ColourView::interleaved(&brown, W, H).unwrap(),
    );
    let s1 = r.scan(&grey, 0.0).unwrap();
    assert!(s1.readings.iter().all(|x| x.row() == 19.5));
    let s2 = r.scan(&brown, 0.1).unwrap();
    assert!(s2
        .readings
        .iter()
        .all(|x| x.status() == ColumnStatus::TooClose));
    r.reset_model();
    let s3 = r.scan(&brown, 0.2).unwrap();
    assert!(s3.readings.iter().all(|x| x.row() == 19.5));
}

#[test]
fn wrong_size_and_columns_without_ground_are_reported() {
    let img = tiled_image(&scene, 3);
    let mut r = AppearanceRanger::new(table(0.0), options(AppearanceFeatures::Colour)).unwrap();
    let small = ColourView::interleaved(&img[..(W - 1) * H * 3], W - 1, H).unwrap();
    assert!(matches!(r.scan(&small, 0.0), Err(Error::InvalidImage(_))));
    // No ground anywhere: every column is invalid.
    let none = GroundTable::from_fn(W, H, 4, |_, _| None).unwrap();
    let mut r = AppearanceRanger::new(none, options(AppearanceFeatures::Colour)).unwrap();
    let scan = r
        .scan(&ColourView::interleaved(&img, W, H).unwrap(), 0.0)
        .unwrap();
    assert!(scan
        .readings
        .iter()
        .all(|x| x.status() == ColumnStatus::Invalid));
    let bad = AppearanceOptions {
        start: ColumnStart::BottomMargin(H),
        ..Default::default()
    };
    assert!(AppearanceRanger::new(table(0.0), bad).is_err());
}

/// The table of `scan_scene` without ground where `uncovered(u, v)` (a fisheye's bottom
/// corners near the robot).
fn table_without(uncovered: impl Fn(f64, f64) -> bool) -> GroundTable {
    let full = table(0.0);
    GroundTable::from_fn(W, H, 4, |u, v| {
        (!uncovered(u, v)).then(|| {
            full.lookup(u.min(W as f64 - 1.0), v.min(H as f64 - 1.0))
                .unwrap()
        })
    })
    .unwrap()
}

#[test]
fn columns_whose_bottom_rows_have_no_ground_are_scanned_from_the_bottom() {
    // The table of `scan_scene` without ground in two bottom corners (a fisheye's sides near
    // the robot): u < 40 below row 50 and u >= 120 below row 90. Every column reads as on the
    // full table, except that a boundary in rows without ground cannot be placed (invalid,
    // with its row) and free space starts at the column's lowest row with ground.
    let full = table(0.0);
    let cornered = table_without(|u, v| (u < 40.0 && v > 50.0) || (u >= 120.0 && v > 90.0));
    let o = AppearanceOptions {
        adaptation_rate: 0.02,
        ..options(AppearanceFeatures::Colour)
    };
    let scan_with = |t: &GroundTable| {
        let mut r = AppearanceRanger::new(t.clone(), o.clone()).unwrap();
        let before = tiled_image(&earlier_scene, 0);
        r.scan(&ColourView::interleaved(&before, W, H).unwrap(), 0.0)
            .unwrap();
        let img = tiled_image(&scene, 1);
        r.scan(&ColourView::interleaved(&img, W, H).unwrap(), 0.1)
            .unwrap()
    };
    let (a, b) = (scan_with(&full), scan_with(&cornered));
    let mut seen = [0usize; 4];
    for (x, y) in a.readings.iter().zip(&b.readings) {
        let u = x.column as f64;
        let first = (0..H)
            .rev()
            .find(|&v| cornered.lookup(u, v as f64).is_some());
        assert_eq!(y.near, first.and_then(|v| cornered.lookup(u, v as f64)));
        match (x.outcome, y.outcome) {
            (
                ColumnOutcome::Boundary { row, .. },
                ColumnOutcome::Boundary { row: r2, point, .. },
            ) => {
                assert_eq!(row, r2);
                assert_eq!(Some(point), cornered.lookup(u, row));
                seen[0] += 1;
            }
            (ColumnOutcome::Boundary { row, .. }, ColumnOutcome::Invalid { row: r2 }) => {
                assert_eq!(Some(row), r2);
                assert!(cornered.lookup(u, row).is_none());
                seen[1] += 1;
            }
            (ColumnOutcome::TooClose, ColumnOutcome::TooClose) => seen[2] += 1,
            (ColumnOutcome::NoBoundary { .. }, ColumnOutcome::NoBoundary { .. }) => seen[3] += 1,
            other => panic!("column {u}: {other:?}"),
        }
    }
    // Every case occurs.
    assert!(seen.iter().all(|&n| n > 0), "{seen:?}");
}

#[test]
fn row_by_row_scan_gives_the_column_by_column_readings() {
    // Dense columns go row by row (each pixel classified once); the readings must be those of
    // the column-by-column scan, whatever the start rows, range limit and features.
    let starts: Vec<u32> = (0..W).map(|u| (H - 1 - (u * 7) % 13) as u32).collect();
    for (features, start, max_range_m) in [
        (
            AppearanceFeatures::Colour,
            ColumnStart::BottomMargin(0),
            None,
        ),
        (
            AppearanceFeatures::ColourAndTexture,
            ColumnStart::BottomMargin(3),
            Some(0.9),
        ),
        (
            AppearanceFeatures::ColourAndTexture,
            ColumnStart::PerColumn(starts.clone()),
            None,
        ),
    ] {
        let o = AppearanceOptions {
            start,
            max_range_m,
            ..options(features)
        };
        let mut ranger = AppearanceRanger::new(table(10.0), o).unwrap();
        assert!(ranger.row_major_pays(W));
        for seed in 0..3 {
            let img = tiled_image(&scene, seed);
            let view = ColourView::interleaved(&img, W, H).unwrap();
            let mut by_column = ranger.clone();
            let scan = ranger.scan(&view, seed as f64).unwrap();
            by_column.learn(&view);
            for (j, reading) in scan.readings.iter().enumerate() {
                let (outcome, confidence, _) = by_column.scan_column(&view, j);
                assert_eq!(reading.outcome, outcome, "column {j}, seed {seed}");
                assert_eq!(reading.confidence, confidence, "column {j}, seed {seed}");
            }
        }
    }
}

/// Furniture that reaches the bottom corners of the very first frame (a camera that starts
/// beside a cabinet): with the reference band across the whole width its colour is learned as
/// floor and its columns read floor to the top; a band over the centre half learns only the
/// floor straight ahead, so those columns read `too_close` and every other column matches the
/// brute-force scan of the true mask.
#[test]
fn a_centred_reference_band_does_not_learn_furniture_at_the_bottom_corners() {
    let corners = |u: usize, _v: usize| !(24..W - 24).contains(&u);
    let img = tiled_image(&corners, 3);
    let view = ColourView::interleaved(&img, W, H).unwrap();
    let o = options(AppearanceFeatures::Colour);
    let scan_with = |fraction: f64| {
        let o = AppearanceOptions {
            reference_width_fraction: fraction,
            min_floor_share: 0.01,
            ..o.clone()
        };
        AppearanceRanger::new(table(0.0), o)
            .unwrap()
            .scan(&view, 0.0)
            .unwrap()
    };
    let centred = scan_with(0.5);
    for reading in &centred.readings {
        let u = reading.column as usize;
        let want = expected(&corners, u, o.patch_half_width_px, o.min_run_px);
        assert_eq!(observed(&reading.outcome), want, "column {u}");
    }
    let whole = scan_with(1.0);
    let corner_reading = |s: &crate::scan::Scan| observed(&s.readings[5].outcome);
    assert_eq!(corner_reading(&centred), ColumnStatus2::TooClose);
    assert_eq!(corner_reading(&whole), ColumnStatus2::NoBoundary);
}

#[test]
fn a_dark_lens_rim_below_the_first_ground_row_is_not_an_obstacle() {
    // A circular fisheye's unlit corners: columns u < 40 have ground only from row 50 up and
    // the bottom 20 rows of the image are black there. Black is not floor, so from the bottom
    // every such column read too close; they now read as a ranger told to start them at their
    // first row with ground. Columns with ground from the bottom keep their start.
    let cornered = table_without(|u, v| u < 40.0 && v > 50.0);
    let o = AppearanceOptions {
        adaptation_rate: 0.02,
        ..options(AppearanceFeatures::Colour)
    };
    let mut img = tiled_image(&scene, 1);
    for v in H - 20..H {
        for u in 0..40 {
            img[(v * W + u) * 3..(v * W + u) * 3 + 3].copy_from_slice(&[2, 2, 3]);
        }
    }
    let first = |u: usize| {
        (0..H)
            .rev()
            .find(|&v| cornered.lookup(u as f64, v as f64).is_some())
            .unwrap()
    };
    let starts: Vec<u32> = (0..W)
        .map(|u| if u < 40 { first(u) } else { H - 1 } as u32)
        .collect();
    let told = AppearanceOptions {
        start: ColumnStart::PerColumn(starts),
        ..o.clone()
    };
    let view = ColourView::interleaved(&img, W, H).unwrap();
    let before = tiled_image(&earlier_scene, 0);
    let scan_with = |opts: &AppearanceOptions| {
        let mut r = AppearanceRanger::new(cornered.clone(), opts.clone()).unwrap();
        r.scan(&ColourView::interleaved(&before, W, H).unwrap(), 0.0)
            .unwrap();
        r.scan(&view, 0.1).unwrap()
    };
    let (got, want) = (scan_with(&o), scan_with(&told));
    for (a, b) in got.readings.iter().zip(&want.readings) {
        assert_eq!(a.outcome, b.outcome, "column {}", a.column);
        assert_eq!(a.start_row, b.start_row, "column {}", a.column);
    }
    // Where the box's base stands well above the first row with ground (u < 8: rows 40-43
    // against 47-48), a boundary; the columns of black read too close without the rim rule.
    let clear: Vec<_> = got.readings.iter().filter(|r| r.column < 8).collect();
    assert!(!clear.is_empty());
    assert!(clear.iter().all(|r| r.status() == ColumnStatus::Boundary));
}

/// The tiled floor with a blue rug across `rows` (floor that looks unlike the reference band
/// unless it reaches the bottom rows) and a red obstacle in columns 60..100 above row 30.
fn rug_image(seed: u64, rows: std::ops::Range<usize>) -> Vec<u8> {
    let red = |u: usize, v: usize| (60..100).contains(&u) && v < 30;
    let mut img = tiled_image(&red, seed);
    for v in rows {
        for u in 0..W {
            let base = [60, 110, 200];
            for c in 0..3 {
                let n = noise(u, v, seed * 5 + c as u64);
                img[(v * W + u) * 3 + c] = (base[c] + n).clamp(0, 255) as u8;
            }
        }
    }
    img
}

/// Scans the rug from afar, then from on it (its floor in the reference band), and learns
/// the far boundaries' samples there; returns the samples learned.
fn drive_over_the_rug(ranger: &mut AppearanceRanger) -> usize {
    let far = rug_image(1, 50..70);
    let near = rug_image(2, 90..H);
    ranger
        .scan(&ColourView::interleaved(&far, W, H).unwrap(), 0.0)
        .unwrap();
    let samples: Vec<u32> = ranger
        .boundary_samples()
        .iter()
        .flatten()
        .copied()
        .collect();
    ranger
        .scan(&ColourView::interleaved(&near, W, H).unwrap(), 0.1)
        .unwrap();
    ranger.learn_driven_floor(&samples).unwrap()
}

#[test]
fn boundaries_driven_through_teach_the_model_their_floor() {
    use crate::appearance::{pack_sample, BOUNDARY_SAMPLES, NO_SAMPLE};
    use crate::floor_model::{colour_bin, TEXTURE_BINS};
    // relearn the reference every frame: the rug stays floor only as driven-over floor
    let o = AppearanceOptions {
        adaptation_rate: 1.0,
        ..options(AppearanceFeatures::ColourAndTexture)
    };
    let mut ranger = AppearanceRanger::new(table(0.0), o.clone()).unwrap();
    let img = rug_image(1, 50..70);
    let view = ColourView::interleaved(&img, W, H).unwrap();
    let first = ranger.scan(&view, 0.0).unwrap();
    // The rug stops every column at its lower edge (row 69.5).
    for r in &first.readings {
        assert_eq!(
            observed(&r.outcome),
            ColumnStatus2::Boundary(69.5),
            "{}",
            r.column
        );
    }
    // Each boundary's samples are its column's pixels in the run's lowest rows (brute force
    // on the colour part), the other slots empty.
    let rows = o.min_run_px.min(BOUNDARY_SAMPLES);
    for (r, s) in first.readings.iter().zip(ranger.boundary_samples()) {
        let u = r.column as usize;
        for (k, &slot) in s.iter().enumerate() {
            if k >= rows {
                assert_eq!(slot, NO_SAMPLE);
                continue;
            }
            let p = |c: usize| img[((69 - k) * W + u) * 3 + c] as i32;
            assert_eq!(slot as usize / TEXTURE_BINS, colour_bin([p(0), p(1), p(2)]));
        }
    }
    // Bad samples are refused whole; empty slots are skipped; samples the reference band
    // does not confirm now (it shows tiles, not the rug) teach nothing.
    let all: Vec<u32> = ranger
        .boundary_samples()
        .iter()
        .flatten()
        .copied()
        .collect();
    let mut bad = all.clone();
    bad.push(pack_sample(crate::floor_model::COLOUR_BINS, 0));
    assert!(matches!(
        ranger.learn_driven_floor(&bad),
        Err(Error::InvalidOption { .. })
    ));
    assert_eq!(
        ranger.learn_driven_floor(&[NO_SAMPLE, NO_SAMPLE]).unwrap(),
        0
    );
    assert_eq!(ranger.learn_driven_floor(&all).unwrap(), 0);
    let still = ranger.scan(&view, 0.05).unwrap();
    assert_eq!(
        observed(&still.readings[0].outcome),
        ColumnStatus2::Boundary(69.5)
    );
    assert!(ranger.driven_floor_columns().iter().all(|&d| !d));
    assert!(ranger.driven_floor_borders().iter().all(|b| b.is_nan()));
    // Driven over (the rug in the reference band when the robot got there): learned.
    // (most of them: the run's lowest row also shows the step down to the tiles below it, a
    // texture the rug's own floor does not have)
    let learned = drive_over_the_rug(&mut ranger);
    assert!(learned > rows * W / 2 && learned <= rows * W, "{learned}");
    // From the next frame on the rug is floor: the obstacle's columns stop at its base, the
    // others see floor to the top; every column crossed the rug's rows as driven-over floor.
    let second = ranger.scan(&view, 0.2).unwrap();
    assert!(ranger.driven_floor_columns().iter().all(|&d| d));
    // the rug's near edge (the tiles' last row 70, the rug's first 69) is each column's border
    assert!(ranger.driven_floor_borders().iter().all(|&b| b == 69.5));
    for r in &second.readings {
        let want = if (60..100).contains(&(r.column as usize)) {
            ColumnStatus2::Boundary(29.5)
        } else {
            ColumnStatus2::NoBoundary
        };
        assert_eq!(observed(&r.outcome), want, "column {}", r.column);
    }
    // The same through the column-by-column scan (few columns).
    let mut few = AppearanceRanger::new(
        table(0.0),
        AppearanceOptions {
            columns: ColumnSelection::Count(8),
            ..o.clone()
        },
    )
    .unwrap();
    assert!(drive_over_the_rug(&mut few) > rows * 8 / 2);
    few.scan(&view, 0.2).unwrap();
    assert!(few.driven_floor_columns().iter().all(|&d| d));
    // Forgotten at the half-life's pace: one frame's half-life, and the rug stops them again.
    let mut fast = AppearanceRanger::new(
        table(0.0),
        AppearanceOptions {
            driven_floor_half_life_frames: 1.0,
            ..o
        },
    )
    .unwrap();
    drive_over_the_rug(&mut fast);
    let taught = fast.scan(&view, 0.2).unwrap();
    assert_eq!(
        observed(&taught.readings[0].outcome),
        ColumnStatus2::NoBoundary
    );
    for k in 0..12 {
        fast.scan(&view, 0.3 + k as f64).unwrap();
    }
    let later = fast.scan(&view, 20.0).unwrap();
    assert_eq!(
        observed(&later.readings[0].outcome),
        ColumnStatus2::Boundary(69.5)
    );
}
