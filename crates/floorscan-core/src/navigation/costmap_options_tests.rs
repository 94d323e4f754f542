//! Tests of the `costmap_options` module.

use super::*;

#[test]
fn defaults_are_valid_and_bad_values_name_their_field() {
    CostmapOptions::default().validate().unwrap();
    let d = CostmapOptions::default;
    for (o, field) in [
        (
            CostmapOptions {
                robot_radius_m: 0.0,
                ..d()
            },
            "robot_radius_m",
        ),
        (
            CostmapOptions {
                footprint_padding_m: 1.0,
                ..d()
            },
            "footprint_padding_m",
        ),
        (
            CostmapOptions {
                inflation_radius_m: 0.1,
                ..d()
            },
            "inflation_radius_m",
        ),
        (
            CostmapOptions {
                unknown_cost: f64::NAN,
                ..d()
            },
            "unknown_cost",
        ),
    ] {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
}
