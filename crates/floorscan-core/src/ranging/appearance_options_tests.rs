//! Tests of the `appearance_options` module.

use super::*;

#[test]
fn defaults_are_valid_and_every_bad_option_is_an_error() {
    AppearanceOptions::default().validate().unwrap();
    let d = AppearanceOptions::default;
    let bad = [
        AppearanceOptions {
            reference_fraction: 0.0,
            ..d()
        },
        AppearanceOptions {
            reference_fraction: 0.7,
            ..d()
        },
        AppearanceOptions {
            reference_width_fraction: 0.0,
            ..d()
        },
        AppearanceOptions {
            reference_width_fraction: 1.5,
            ..d()
        },
        AppearanceOptions {
            min_floor_share: 1.0,
            ..d()
        },
        AppearanceOptions {
            min_floor_share: f64::NAN,
            ..d()
        },
        AppearanceOptions {
            adaptation_rate: 0.0,
            ..d()
        },
        AppearanceOptions {
            driven_floor_radius_m: -0.1,
            ..d()
        },
        AppearanceOptions {
            driven_floor_radius_m: f64::NAN,
            ..d()
        },
        AppearanceOptions {
            driven_floor_samples: 0.5,
            ..d()
        },
        AppearanceOptions {
            driven_floor_half_life_frames: f64::INFINITY,
            ..d()
        },
        AppearanceOptions {
            intensity_reach_bins: 0,
            ..d()
        },
        AppearanceOptions {
            min_run_px: 0,
            ..d()
        },
        AppearanceOptions {
            patch_half_width_px: 10_000,
            ..d()
        },
        AppearanceOptions {
            columns: ColumnSelection::Count(0),
            ..d()
        },
        AppearanceOptions {
            max_range_m: Some(-1.0),
            ..d()
        },
    ];
    for o in bad {
        assert!(o.validate().is_err(), "{o:?}");
    }
}

#[test]
fn partial_serde_form_takes_defaults() {
    let o: AppearanceOptions = serde_json::from_str(r#"{"min_run_px": 5}"#).unwrap();
    assert_eq!(o.min_run_px, 5);
    assert_eq!(o.features, AppearanceFeatures::ColourAndTexture);
}
