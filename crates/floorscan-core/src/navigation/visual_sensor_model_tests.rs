//! Tests of the `visual_sensor_model` module.

use super::*;

#[test]
fn the_defaults_are_valid_and_each_rule_names_its_field() {
    VisualModel::default().validate().unwrap();
    let bad = [
        (
            VisualModel {
                free_a: f64::NAN,
                ..Default::default()
            },
            "free_a",
        ),
        (
            VisualModel {
                margin_sigmas: 11.0,
                ..Default::default()
            },
            "margin_sigmas",
        ),
        (
            VisualModel {
                default_error_m: 0.0,
                ..Default::default()
            },
            "default_error_m",
        ),
        (
            VisualModel {
                confirmed_clearing: 0.0,
                ..Default::default()
            },
            "confirmed_clearing",
        ),
        (
            VisualModel {
                fusion_weight: 1.5,
                ..Default::default()
            },
            "fusion_weight",
        ),
        (
            VisualModel {
                persist_range_m: -1.0,
                ..Default::default()
            },
            "persist_range_m",
        ),
    ];
    for (m, field) in bad {
        let e = m.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
}
