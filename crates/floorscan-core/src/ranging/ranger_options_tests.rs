//! Tests of the `ranger_options` module.

use super::*;
use crate::pose::Point2;

/// A table of a 640-pixel-wide camera: ground at every pixel.
fn table_640() -> GroundTable {
    GroundTable::from_fn(640, 480, 8, |u, v| {
        Some(Point2::new(1.0 + (479.0 - v) * 0.01, (320.0 - u) * 0.002))
    })
    .unwrap()
}

#[test]
fn evenly_spaced_columns_are_strip_centres() {
    let o = RangerOptions {
        columns: ColumnSelection::Count(4),
        ..Default::default()
    };
    assert_eq!(
        o.column_indices(&table_640()).unwrap(),
        vec![80, 240, 400, 560]
    );
    let all = RangerOptions {
        columns: ColumnSelection::Count(640),
        ..Default::default()
    };
    assert_eq!(
        all.column_indices(&table_640()).unwrap(),
        (0..640).collect::<Vec<u32>>()
    );
}

#[test]
fn every_bad_option_is_an_error() {
    let bad = [
        RangerOptions {
            half_width_px: 0,
            ..Default::default()
        },
        RangerOptions {
            threshold: f64::NAN,
            ..Default::default()
        },
        RangerOptions {
            threshold: -1.0,
            ..Default::default()
        },
        RangerOptions {
            mid_contrast: -0.1,
            ..Default::default()
        },
        RangerOptions {
            mid_range_m: vec![1.2, 0.6],
            ..Default::default()
        },
        RangerOptions {
            mid_range_m: vec![0.0, f64::INFINITY],
            ..Default::default()
        },
        RangerOptions {
            mid_range_m: vec![0.5],
            ..Default::default()
        },
        RangerOptions {
            noise_multiple: -1.0,
            ..Default::default()
        },
        RangerOptions {
            noise_multiple: f64::INFINITY,
            ..Default::default()
        },
        RangerOptions {
            contrast: f64::NAN,
            ..Default::default()
        },
        RangerOptions {
            columns: ColumnSelection::Count(0),
            ..Default::default()
        },
        RangerOptions {
            columns: ColumnSelection::Explicit(vec![]),
            ..Default::default()
        },
        RangerOptions {
            max_range_m: Some(0.0),
            ..Default::default()
        },
        RangerOptions {
            columns: ColumnSelection::Spacing {
                obstacle_width_m: 0.0,
                range_m: 1.0,
            },
            ..Default::default()
        },
        RangerOptions {
            columns: ColumnSelection::Spacing {
                obstacle_width_m: 0.03,
                range_m: f64::NAN,
            },
            ..Default::default()
        },
    ];
    for o in bad {
        assert!(o.validate().is_err(), "{o:?}");
    }
    let o = RangerOptions {
        columns: ColumnSelection::Explicit(vec![3, 700]),
        ..Default::default()
    };
    assert!(o.column_indices(&table_640()).is_err());
    let o = RangerOptions {
        columns: ColumnSelection::Count(641),
        ..Default::default()
    };
    assert!(o.column_indices(&table_640()).is_err());
}
