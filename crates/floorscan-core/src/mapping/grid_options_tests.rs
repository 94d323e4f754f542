//! Tests of the `grid_options` module.

use super::*;

#[test]
fn defaults_are_valid_and_match_the_documented_probabilities() {
    let o = GridOptions::default();
    o.validate().unwrap();
    let l = o.limits();
    assert_eq!((l.clamp_min, l.clamp_max), (-2000, 3500));
    assert!(LogOdds(l.occupied_at).probability() >= 0.65);
    assert!(LogOdds(l.occupied_at - 1).probability() < 0.65);
    assert!(LogOdds(l.free_at).probability() <= 0.196);
    assert!(LogOdds(l.free_at + 1).probability() > 0.196);
}

#[test]
fn classification_follows_the_thresholds() {
    let l = GridOptions::default().limits();
    assert_eq!(l.classify(0), Occupancy::Unknown);
    assert_eq!(l.classify(l.occupied_at), Occupancy::Occupied);
    assert_eq!(l.classify(l.occupied_at - 1), Occupancy::Unknown);
    assert_eq!(l.classify(l.free_at), Occupancy::Free);
    assert_eq!(l.classify(l.free_at + 1), Occupancy::Unknown);
}

#[test]
fn each_invalid_field_is_named() {
    let cases: Vec<(GridOptions, &str)> = vec![
        (
            GridOptions {
                cell_size_m: 0.0,
                ..Default::default()
            },
            "cell_size_m",
        ),
        (
            GridOptions {
                cell_size_m: f64::NAN,
                ..Default::default()
            },
            "cell_size_m",
        ),
        (
            GridOptions {
                origin_m: Point2::new(f64::INFINITY, 0.0),
                ..Default::default()
            },
            "origin_m",
        ),
        (
            GridOptions {
                bounds_m: Some(Bounds {
                    min: Point2::new(1.0, 0.0),
                    max: Point2::new(0.0, 1.0),
                }),
                ..Default::default()
            },
            "bounds_m",
        ),
        (
            GridOptions {
                clamp_min_nats: 0.5,
                ..Default::default()
            },
            "clamp_min_nats",
        ),
        (
            GridOptions {
                clamp_max_nats: 25.0,
                ..Default::default()
            },
            "clamp_max_nats",
        ),
        (
            GridOptions {
                occupied_threshold: 0.4,
                ..Default::default()
            },
            "occupied_threshold",
        ),
        (
            GridOptions {
                free_threshold: 0.6,
                ..Default::default()
            },
            "free_threshold",
        ),
        (
            GridOptions {
                occupied_threshold: 0.99,
                ..Default::default()
            },
            "occupied_threshold",
        ),
        (
            GridOptions {
                free_threshold: 0.01,
                ..Default::default()
            },
            "free_threshold",
        ),
        (
            GridOptions {
                max_cells: 0,
                ..Default::default()
            },
            "max_cells",
        ),
    ];
    for (o, name) in cases {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(name), "{e} should name {name}");
    }
}
