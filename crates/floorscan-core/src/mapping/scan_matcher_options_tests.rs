//! Tests of the `scan_matcher_options` module.

use super::*;

#[test]
fn defaults_are_valid() {
    ScanMatcherOptions::default().validate().unwrap();
}

#[test]
fn out_of_range_values_name_their_field() {
    let cases: [(&str, ScanMatcherOptions); 6] = [
        (
            "size_m",
            ScanMatcherOptions {
                size_m: 1.0,
                ..Default::default()
            },
        ),
        (
            "min_score",
            ScanMatcherOptions {
                min_score: 1.0,
                ..Default::default()
            },
        ),
        (
            "min_points",
            ScanMatcherOptions {
                min_points: 2,
                ..Default::default()
            },
        ),
        (
            "max_points",
            ScanMatcherOptions {
                max_points: 10,
                ..Default::default()
            },
        ),
        (
            "sigma_m",
            ScanMatcherOptions {
                sigma_m: f64::NAN,
                ..Default::default()
            },
        ),
        (
            "rejection_threshold",
            ScanMatcherOptions {
                rejection_threshold: Some(0.0),
                ..Default::default()
            },
        ),
    ];
    for (name, o) in cases {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
    let gate = ScanMatcherOptions {
        rejection_threshold: Some(f64::INFINITY),
        ..Default::default()
    };
    gate.validate().unwrap();
}
