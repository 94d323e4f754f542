//! Tests of the `edge` module.

use super::*;
use proptest::prelude::*;

proptest! {
    /// The recurrence reproduces the direct sum of eq. (1) at every row.
    #[test]
    fn incremental_response_equals_direct_sum(
        column in proptest::collection::vec(0i32..=65535, 3..300),
        d in 1usize..40,
    ) {
        prop_assume!(2 * d < column.len());
        let mut s = direct_response(&column, d, d);
        for k in d..column.len() - d - 1 {
            prop_assert_eq!(s, direct_response(&column, k, d), "row {}", k);
            s = next_response(s, column[k - d], column[k], column[k + 1], column[k + d + 1]);
        }
        prop_assert_eq!(s, direct_response(&column, column.len() - d - 1, d));
    }

    /// The integer threshold test agrees with |R| > T on the mean difference.
    #[test]
    fn integer_threshold_matches_real_threshold(s in -100000i32..100000, d in 1usize..64, t in 0.0..300.0f64) {
        let r = s as f64 / (2.0 * d as f64);
        prop_assert_eq!(s.abs() > threshold_to_sum(t, d), r.abs() > t);
    }
}

#[test]
fn printed_recurrence_of_the_paper_is_wrong() {
    // A step column: the paper's eq. (3) drifts away from the direct sum, ours does not.
    let column: Vec<i32> = (0..20).map(|k| if k < 10 { 50 } else { 200 }).collect();
    let d = 3;
    let mut ours = direct_response(&column, d, d);
    let mut paper = ours;
    let mut paper_diverged = false;
    for k in d..column.len() - d - 1 {
        ours = next_response(
            ours,
            column[k - d],
            column[k],
            column[k + 1],
            column[k + d + 1],
        );
        paper -= column[k] - column[k + 1] + column[k - d] + column[k + d + 1];
        assert_eq!(ours, direct_response(&column, k + 1, d));
        paper_diverged |= paper != ours;
    }
    assert!(paper_diverged);
}

#[test]
fn sharp_step_peaks_at_the_edge_between_pixels() {
    // Floor (k < 20) then obstacle: the edge lies between k = 19 and k = 20, at 19.5.
    let column: Vec<i32> = (0..60).map(|k| if k < 20 { 80 } else { 160 }).collect();
    for d in 1..8 {
        let thr = threshold_to_sum(10.0, d);
        let k_cross = (d..60 - d)
            .find(|&k| direct_response(&column, k, d).abs() > thr)
            .unwrap();
        for refinement in [Refinement::Peak, Refinement::SubPixel] {
            let p = refine_crossing(refinement, k_cross, d, d, 60 - d - 1, |k| {
                direct_response(&column, k, d)
            });
            assert!((p.k - 19.5).abs() < 1e-9, "d={d} {refinement:?}: {}", p.k);
        }
    }
}
