//! Tests of the `pose_graph_options` module.

use super::*;

#[test]
fn the_defaults_pass_and_each_rule_names_its_field() {
    PoseGraphOptions::default().validate().unwrap();
    let cases: [(&str, PoseGraphOptions); 5] = [
        (
            "keyframe_distance_m",
            PoseGraphOptions {
                keyframe_distance_m: 0.0,
                ..Default::default()
            },
        ),
        (
            "loop_min_score",
            PoseGraphOptions {
                loop_min_score: 1.0,
                ..Default::default()
            },
        ),
        (
            "sigma_m",
            PoseGraphOptions {
                sigma_m: f64::NAN,
                ..Default::default()
            },
        ),
        (
            "loop_candidates",
            PoseGraphOptions {
                loop_candidates: 0,
                ..Default::default()
            },
        ),
        (
            "cell_size_m",
            PoseGraphOptions {
                cell_size_m: 0.01,
                range_max_m: 100.0,
                ..Default::default()
            },
        ),
    ];
    for (name, o) in cases {
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
}
