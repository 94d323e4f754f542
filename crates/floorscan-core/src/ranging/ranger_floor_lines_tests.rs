//! Lines on the floor (`floor_line_width_m`) on synthetic columns whose every edge and every
//! line's width on the ground is known by construction.

use crate::ground_table::GroundTable;
use crate::image::ImageView;
use crate::pose::Point2;
use crate::ranger::VisualRanger;
use crate::ranger_options::{ColumnSelection, ColumnStart, RangerOptions};
use crate::scan::{ColumnStatus, Scan};

const W: usize = 8;
const H: usize = 120;

/// Ground at every row, `metres_per_row` of floor per pixel row (x grows up the image).
fn table(metres_per_row: f64) -> GroundTable {
    GroundTable::from_fn(W, H, 4, |u, v| {
        Some(Point2::new(
            0.2 + (H as f64 - 1.0 - v) * metres_per_row,
            (W as f64 / 2.0 - u) * 0.005,
        ))
    })
    .unwrap()
}

/// The paper's fixed threshold (10 on R: an edge changes the window means by more than 20).
fn options(line_width_m: f64) -> RangerOptions {
    RangerOptions {
        half_width_px: 4,
        threshold: 10.0,
        noise_multiple: 0.0,
        contrast: 0.0,
        columns: ColumnSelection::Count(W),
        start: ColumnStart::BottomMargin(0),
        max_range_m: None,
        floor_line_width_m: line_width_m,
        ..Default::default()
    }
}

/// Every column the same: `value(v)` at row v (from the top).
fn image(value: impl Fn(usize) -> u8) -> Vec<u8> {
    (0..H)
        .flat_map(|v| std::iter::repeat_n(value(v), W))
        .collect()
}

/// The rows (v) each column reports, by the row-major scan and by the direct reference scan
/// (which must agree), with their statuses.
fn rows(img: &[u8], metres_per_row: f64, line_width_m: f64) -> Vec<(ColumnStatus, f64)> {
    let view = ImageView::new(img, W, H).unwrap();
    let mut ranger = VisualRanger::new(table(metres_per_row), options(line_width_m)).unwrap();
    let scan = ranger.scan(&view, 0.0).unwrap();
    let mut direct = Scan::default();
    ranger.scan_direct_into(&view, 0.0, &mut direct).unwrap();
    let read = |s: &Scan| -> Vec<(ColumnStatus, f64)> {
        s.readings.iter().map(|r| (r.status(), r.row())).collect()
    };
    assert_eq!(read(&scan), read(&direct));
    read(&scan)
}

fn all_boundaries_at(readings: &[(ColumnStatus, f64)], row: f64) {
    for (status, r) in readings {
        assert_eq!(*status, ColumnStatus::Boundary);
        assert_eq!(*r, row);
    }
}

/// Floor 150 from the bottom; a 2-row dark grout line (60) at rows 88-89; floor again; a dark
/// obstacle (60) from row 59 up. The floor's last row below the obstacle is 60, so its base
/// lies at 59.5; the line's lower side at 89.5.
fn grout_then_obstacle(v: usize) -> u8 {
    match v {
        0..=59 => 60,
        88..=89 => 60,
        _ => 150,
    }
}

#[test]
fn a_grout_line_is_passed_and_the_obstacle_above_it_found() {
    let img = image(grout_then_obstacle);
    // off: the paper's first edge, the grout line
    all_boundaries_at(&rows(&img, 0.01, 0.0), 89.5);
    // 2 cm lines at 1 cm a row: the line (2 cm) is the floor's, the obstacle's base is found
    all_boundaries_at(&rows(&img, 0.01, 0.02), 59.5);
}

#[test]
fn a_line_wider_on_the_ground_than_the_width_stays_a_boundary() {
    // a 6-row band: 6 cm of floor at 1 cm a row (wider than 2 cm and the blur's 2 rows), 1.5
    // cm at 0.25 cm a row: the same image, the width read off the table
    let img = image(|v| match v {
        0..=39 => 60,
        84..=89 => 60,
        _ => 150,
    });
    all_boundaries_at(&rows(&img, 0.01, 0.02), 89.5);
    all_boundaries_at(&rows(&img, 0.0025, 0.02), 39.5);
}

#[test]
fn a_dark_baseboard_below_a_wall_brighter_than_the_floor_stays_the_boundary() {
    // carpet 85, a 3-row baseboard 30, a wall 120 above: the wall differs from the carpet by
    // more than an edge (35 > 20), so the baseboard is no line on the floor
    let img = image(|v| match v {
        60.. => 85,
        57..=59 => 30,
        _ => 120,
    });
    all_boundaries_at(&rows(&img, 0.01, 0.02), 59.5);
}

#[test]
fn lines_of_either_polarity_between_tiles_alike_leave_floor_to_the_top() {
    // tiles 150 and 160 (within an edge of each other) split by dark grout and a white painted
    // line, up to the top: no boundary anywhere
    let img = image(|v| match v {
        100..=101 | 70 | 40..=41 => 60,
        55..=56 => 250,
        0..=39 | 71..=99 => 160,
        _ => 150,
    });
    for (status, _) in rows(&img, 0.01, 0.02) {
        assert_eq!(status, ColumnStatus::NoBoundary);
    }
    // off: the lowest grout line's lower side
    all_boundaries_at(&rows(&img, 0.01, 0.0), 101.5);
}

#[test]
fn a_line_whose_far_side_is_a_different_floor_stays_a_boundary() {
    // grout between a 150 tile and a 100 tile: the far side is no longer the floor below
    let img = image(|v| match v {
        88..=89 => 60,
        0..=87 => 100,
        _ => 150,
    });
    all_boundaries_at(&rows(&img, 0.01, 0.02), 89.5);
}

#[test]
fn a_width_outside_zero_to_one_metre_is_an_error() {
    for bad in [-0.01, 1.5, f64::NAN, f64::INFINITY] {
        let err = VisualRanger::new(table(0.01), options(bad)).unwrap_err();
        assert!(err.to_string().contains("floor_line_width_m"), "{err}");
    }
}
