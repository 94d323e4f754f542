//! Tests of the `avoidance_map_options` module.

use super::*;

#[test]
fn the_defaults_are_valid_and_bad_options_name_their_field() {
    AvoidanceMapOptions::default().validate().unwrap();
    let d = AvoidanceMapOptions::default;
    let bad = [
        (AvoidanceMapOptions { size_m: 0.5, ..d() }, "size_m"),
        (
            AvoidanceMapOptions {
                clamp_nats: (1.0, 2.0),
                ..d()
            },
            "clamp_nats",
        ),
        (
            AvoidanceMapOptions {
                half_life_s: Some(0.0),
                ..d()
            },
            "half_life_s",
        ),
        (
            AvoidanceMapOptions {
                probability_knots: Some(vec![(1.0, 0.5), (0.0, 0.6)]),
                ..d()
            },
            "probability_knots",
        ),
        (
            AvoidanceMapOptions {
                probability_knots: Some(vec![(0.0, 0.5)]),
                ..d()
            },
            "probability_knots",
        ),
        (
            AvoidanceMapOptions {
                free_threshold: 0.6,
                ..d()
            },
            "free_threshold",
        ),
    ];
    for (o, field) in bad {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(field), "{e}");
    }
    // Unset half-lives and knots are valid (never forget; the Platt curve).
    AvoidanceMapOptions {
        half_life_s: None,
        bump_half_life_s: None,
        probability_knots: None,
        ..d()
    }
    .validate()
    .unwrap();
}
