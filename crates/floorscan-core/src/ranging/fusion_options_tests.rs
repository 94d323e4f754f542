//! Tests of the `fusion_options` module.

use super::*;

#[test]
fn defaults_are_valid_and_bad_values_name_their_field() {
    FusionOptions::default().validate().unwrap();
    for (o, field) in [
        (
            FusionOptions {
                snap_rows: -1.0,
                ..Default::default()
            },
            "snap_rows",
        ),
        (
            FusionOptions {
                snap_rows: f64::NAN,
                ..Default::default()
            },
            "snap_rows",
        ),
        (
            FusionOptions {
                snap_fraction: 1.5,
                ..Default::default()
            },
            "snap_fraction",
        ),
        (
            FusionOptions {
                texture_share: f64::NAN,
                ..Default::default()
            },
            "texture_share",
        ),
    ] {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
}

#[test]
fn the_snap_distance_is_the_larger_of_rows_and_share() {
    let o = FusionOptions::default();
    assert_eq!(o.snap_distance_rows(240), 0.08 * 240.0);
    assert_eq!(o.snap_distance_rows(20), 3.0);
}
