//! Tests of the `column_spacing` module.

use super::*;

/// A pinhole camera h above the floor, pitched down by `pitch` [rad], focal `f` [px].
fn pinhole(w: usize, h: usize, f: f64, height_m: f64, pitch: f64) -> GroundTable {
    let (cu, cv) = (w as f64 / 2.0, h as f64 / 2.0);
    GroundTable::from_fn(w, h, 4, |u, v| {
        // ray in the camera: forward 1, left -(u - cu) / f, down (v - cv) / f
        let (fx, ly, dz) = (1.0, -(u - cu) / f, (v - cv) / f);
        let (s, c) = pitch.sin_cos();
        let forward = c * fx - s * -dz;
        let down = s * fx + c * dz;
        (down > 1e-9).then(|| {
            let t = height_m / down;
            Point2::new(t * forward, t * ly)
        })
    })
    .unwrap()
}

/// Brute force: the largest bearing difference between consecutive chosen columns' points
/// nearest the range (every pixel row looked up), over the pairs whose pixels are not
/// adjacent (adjacent pixels cannot be split).
fn worst_gap_rad(table: &GroundTable, cols: &[u32], range_m: f64) -> f64 {
    let bearing = |u: u32| {
        (0..table.image_height())
            .filter_map(|v| table.lookup(u as f64, v as f64))
            .min_by(|a, b| {
                (a.norm() - range_m)
                    .abs()
                    .total_cmp(&(b.norm() - range_m).abs())
            })
            .map(|p| p.y.atan2(p.x))
            .unwrap()
    };
    cols.windows(2)
        .filter(|w| w[1] > w[0] + 1)
        .map(|w| (bearing(w[1]) - bearing(w[0])).abs())
        .fold(0.0, f64::max)
}

#[test]
fn no_obstacle_of_the_width_fits_between_columns() {
    let t = pinhole(640, 480, 300.0, 0.3, 0.5);
    for (width, range) in [(0.03, 1.0), (0.05, 2.0), (0.10, 1.0)] {
        let cols = spaced_columns(&t, width, range).unwrap();
        let reach = subtended_rad(width, range);
        assert!(
            worst_gap_rad(&t, &cols, range) <= reach,
            "{width} at {range}"
        );
        // at the range itself, the chord between neighbouring bearings is the width
        assert!((2.0 * range * (reach / 2.0).sin() - width).abs() < 1e-12);
        assert!(cols.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(cols[0], 0);
        assert_eq!(*cols.last().unwrap(), 639);
        // analytic count: at 1 m the floor spans range / f per pixel near the centre, so
        // about width / (range / f) pixels per column; the columns are no denser than
        // twice that (greedy takes the farthest column within reach)
        let px_per_col = width / (range / 300.0);
        let least = (640.0 / px_per_col / 1.5) as usize;
        assert!(
            cols.len() >= least && cols.len() <= 2 * 640 / px_per_col.max(1.0) as usize + 2,
            "{} columns for {px_per_col} px per column",
            cols.len()
        );
    }
    // Wider obstacles need fewer columns.
    let a = spaced_columns(&t, 0.03, 1.0).unwrap().len();
    let b = spaced_columns(&t, 0.10, 1.0).unwrap().len();
    assert!(b < a);
}

#[test]
fn a_table_short_of_the_range_keeps_the_ranges_angular_spacing() {
    // A calibration that covers the floor only to 0.6 m: the columns' bearings still lie
    // within the angle a 3 cm obstacle subtends at 1 m (a floor distance of 3 cm at 0.6 m
    // would allow 1.7 times that).
    let full = pinhole(640, 480, 300.0, 0.3, 0.5);
    let short = GroundTable::from_fn(640, 480, 4, |u, v| {
        full.lookup(u, v).filter(|p| p.norm() <= 0.6)
    })
    .unwrap();
    let b = spaced_columns(&short, 0.03, 1.0).unwrap();
    assert!(worst_gap_rad(&short, &b, 1.0) <= subtended_rad(0.03, 1.0));
    assert!(b.len() > spaced_columns(&short, 0.03 / 0.6, 1.0).unwrap().len());
}

#[test]
fn too_fine_a_spacing_takes_every_column() {
    let t = pinhole(64, 48, 30.0, 0.3, 0.5);
    let cols = spaced_columns(&t, 0.001, 1.0).unwrap();
    assert_eq!(cols, (0..64).collect::<Vec<u32>>());
}

#[test]
fn bad_arguments_and_groundless_tables_are_errors() {
    let t = pinhole(64, 48, 30.0, 0.3, 0.5);
    assert!(spaced_columns(&t, 0.0, 1.0).is_err());
    assert!(spaced_columns(&t, 0.03, f64::INFINITY).is_err());
    let none = GroundTable::from_fn(64, 48, 4, |_, _| None).unwrap();
    assert!(spaced_columns(&none, 0.03, 1.0).is_err());
}
