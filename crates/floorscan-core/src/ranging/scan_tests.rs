//! Tests of the `scan` module.

use super::*;

fn reading(column: u32, outcome: ColumnOutcome) -> ColumnReading {
    ColumnReading {
        column,
        start_row: 230.0,
        near: Some(Point2::new(0.3, 0.0)),
        outcome,
        confidence: 1.0,
    }
}

fn boundary_at(column: u32, x: f64, y: f64) -> ColumnReading {
    reading(
        column,
        ColumnOutcome::Boundary {
            row: 100.0,
            point: Point2::new(x, y),
            footprint_m: 0.0,
        },
    )
}

#[test]
fn status_names_and_codes_round_trip() {
    for s in ColumnStatus::ALL {
        assert_eq!(ColumnStatus::parse(s.as_str()), Some(s));
        assert_eq!(ColumnStatus::from_code(s.code()), Some(s));
    }
    assert_eq!(ColumnStatus::from_code(4), None);
}

#[test]
fn ranges_follow_rep_117() {
    let b = boundary_at(0, 3.0, 4.0);
    assert_eq!(b.range_m(), 5.0);
    let nb = reading(
        1,
        ColumnOutcome::NoBoundary {
            top_row: 60.0,
            farthest: Point2::new(4.0, 0.0),
        },
    );
    assert_eq!(nb.range_m(), f64::INFINITY);
    assert_eq!(
        reading(2, ColumnOutcome::TooClose).range_m(),
        f64::NEG_INFINITY
    );
    assert!(reading(3, ColumnOutcome::Invalid { row: None })
        .range_m()
        .is_nan());
}

#[test]
fn laser_bins_keep_the_nearest_point_per_bin() {
    let d = 0.1f64;
    let scan = Scan {
        timestamp_s: 1.0,
        readings: vec![
            boundary_at(0, 2.0 * (0.01f64).cos(), 2.0 * (0.01f64).sin()), // bin 0 (bearing 0.01)
            boundary_at(1, 1.5 * (0.02f64).cos(), 1.5 * (0.02f64).sin()), // bin 0, nearer
            boundary_at(2, 1.0 * (0.21f64).cos(), 1.0 * (0.21f64).sin()), // bin 2
            reading(
                3,
                ColumnOutcome::NoBoundary {
                    top_row: 50.0,
                    farthest: Point2::new((0.1f64).cos() * 3.0, (0.1f64).sin() * 3.0),
                },
            ),
            boundary_at(4, 1.0, 5.0), // bearing 1.37: outside the range, ignored
        ],
    };
    let bins = scan.to_laser_bins(0.0, 0.3, d).unwrap();
    assert_eq!(bins.ranges_m.len(), 4);
    assert!((bins.ranges_m[0] - 1.5).abs() < 1e-12);
    assert_eq!(bins.ranges_m[1], f64::INFINITY);
    assert!((bins.ranges_m[2] - 1.0).abs() < 1e-12);
    assert_eq!(bins.ranges_m[3], f64::INFINITY);
    assert!((bins.range_min_m - 1.0).abs() < 1e-12);
    assert!(scan.to_laser_bins(0.3, 0.0, d).is_err());
    assert!(scan.to_laser_bins(0.0, 0.3, 0.0).is_err());
}

#[test]
fn csv_lines_have_the_header_fields_in_order() {
    let scan = Scan {
        timestamp_s: 0.5,
        readings: vec![
            boundary_at(7, 3.0, 4.0),
            reading(8, ColumnOutcome::TooClose),
        ],
    };
    let mut s = String::new();
    scan.write_csv_lines(&mut s);
    let lines: Vec<&str> = s.lines().collect();
    assert_eq!(lines[0], "0.5,7,100,boundary,3,4,5,0.9272952180016122");
    assert_eq!(lines[1], "0.5,8,230,too_close,0.3,0,-inf,0");
    assert_eq!(
        SCAN_CSV_HEADER.split(',').count(),
        lines[0].split(',').count()
    );
}
