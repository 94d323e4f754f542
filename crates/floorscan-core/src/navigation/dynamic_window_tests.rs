//! Tests of the `dynamic_window` module.

use super::*;

const CELL: f64 = 0.05;
const N: usize = 80;
const ORIGIN: [f64; 2] = [-2.0, -2.0];

/// The chosen sample from the origin facing +x, a goal 2 m ahead, over an 80 x 80 grid
/// of 5 cm cells from (-2, -2) m.
fn choose(cost: &[u8], nav: &[f64], vs: &[f64], omegas: &[f64]) -> Option<usize> {
    let scoring = WindowScoring {
        path_distance_bias: 32.0,
        goal_distance_bias: 24.0,
        occdist_scale: 0.01,
        forward_point_distance_m: 0.325,
        blind_radius_m: 0.35,
        inscribed: 253,
    };
    let times: Vec<f64> = (1..=20).map(|i| 1.7 * i as f64 / 20.0).collect();
    let cost = Raster::new(cost, N, N, ORIGIN, CELL).unwrap();
    let nav = Raster::new(nav, N, N, ORIGIN, CELL).unwrap();
    best_sample(
        [0.0, 0.0, 0.0],
        vs,
        omegas,
        &times,
        &cost,
        None,
        &nav,
        [2.0, 0.0],
        CELL,
        &scoring,
    )
    .unwrap()
}

#[test]
fn heads_for_the_goal_on_an_empty_costmap() {
    // the navigation function is the straight-line distance to the goal
    let nav: Vec<f64> = (0..N * N)
        .map(|c| {
            let x = ORIGIN[0] + ((c % N) as f64 + 0.5) * CELL;
            let y = ORIGIN[1] + ((c / N) as f64 + 0.5) * CELL;
            (x - 2.0).hypot(y)
        })
        .collect();
    let vs = [0.0, 0.1, 0.2, 0.3];
    let k = choose(&[0; N * N], &nav, &vs, &[-0.5, 0.0, 0.5]).unwrap();
    // fastest straight ahead: omega index 1, speed index 3
    assert_eq!(k, vs.len() + 3);
}

#[test]
fn a_wall_ahead_forbids_driving_into_it() {
    // a lethal wall across x in [0.3, 0.4) m; 0.3 m/s for 1.7 s reaches 0.51 m
    let mut cost = vec![0u8; N * N];
    for row in cost.chunks_mut(N) {
        row[46..48].fill(254);
    }
    let nav = vec![1.0f64; N * N];
    assert_eq!(choose(&cost, &nav, &[0.3], &[0.0]), None);
    // standing still stays admissible
    assert_eq!(choose(&cost, &nav, &[0.0, 0.3], &[0.0]), Some(0));
}

#[test]
fn bad_shapes_are_errors() {
    let d = [0u8; 5];
    assert!(Raster::new(&d, 2, 2, [0.0, 0.0], 0.1).is_err());
    assert!(Raster::new(&d[..4], 2, 2, [0.0, 0.0], 0.0).is_err());
    assert!(Raster::new(&d[..4], 2, 2, [f64::NAN, 0.0], 0.1).is_err());
}
