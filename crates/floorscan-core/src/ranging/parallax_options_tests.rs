//! Tests of the `parallax_options` module.

use super::*;

type Change = Box<dyn Fn(&mut ParallaxOptions)>;

#[test]
fn the_defaults_are_valid_and_each_rule_names_its_field() {
    ParallaxOptions::default().validate().unwrap();
    let cases: Vec<(&str, Change)> = vec![
        ("min_baseline_m", Box::new(|o| o.min_baseline_m = 0.0)),
        (
            "min_turn_baseline_m",
            Box::new(|o| o.min_turn_baseline_m = o.min_baseline_m + 0.01),
        ),
        (
            "min_turn_baseline_m",
            Box::new(|o| o.min_turn_baseline_m = 0.0),
        ),
        (
            "min_turn_baseline_m",
            Box::new(|o| o.min_turn_baseline_m = f64::NAN),
        ),
        ("history_frames", Box::new(|o| o.history_frames = 65)),
        ("history_frames", Box::new(|o| o.history_frames = 0)),
        (
            "rows_above_fraction",
            Box::new(|o| o.rows_above_fraction = 0.6),
        ),
        (
            "min_texture_grey",
            Box::new(|o| o.min_texture_grey = f64::NAN),
        ),
        ("blur_sigma_px", Box::new(|o| o.blur_sigma_px = -1.0)),
        (
            "refine_range_m",
            Box::new(|o| o.refine_range_m = f64::INFINITY),
        ),
        (
            "min_log_likelihood_ratio",
            Box::new(|o| o.min_log_likelihood_ratio = f64::NAN),
        ),
        ("max_vetoes", Box::new(|o| o.max_vetoes = 0)),
        ("memory_min_frames", Box::new(|o| o.memory_min_frames = 101)),
        ("memory_cell_m", Box::new(|o| o.memory_cell_m = 0.0)),
        (
            "memory_radius_m",
            Box::new(|o| o.memory_radius_m = f64::NAN),
        ),
        ("warp_error_px", Box::new(|o| o.warp_error_px = -0.5)),
        (
            "min_separation_px",
            Box::new(|o| o.min_separation_px = f64::NAN),
        ),
        ("base_line_gap_m", Box::new(|o| o.base_line_gap_m = -0.1)),
    ];
    for (name, change) in cases {
        let mut o = ParallaxOptions::default();
        change(&mut o);
        let e = o.validate().unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
    }
}
