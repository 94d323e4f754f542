//! Tests of the `navigation_function` module.

use super::*;

/// Bellman-Ford relaxation to a fixed point: the brute-force reference.
fn brute(w: usize, h: usize, blocked: &[bool], weight: &[f64], seeds: &[(usize, f64)]) -> Vec<f64> {
    let n = w * h;
    let mut d = vec![f64::INFINITY; n];
    for &(i, c) in seeds {
        if !blocked[i] {
            d[i] = d[i].min(c);
        }
    }
    loop {
        let mut changed = false;
        for k in 0..n {
            if blocked[k] || !d[k].is_finite() {
                continue;
            }
            let (j, i) = ((k / w) as isize, (k % w) as isize);
            for dj in -1isize..=1 {
                for di in -1isize..=1 {
                    if dj == 0 && di == 0 {
                        continue;
                    }
                    let (jn, inn) = (j + dj, i + di);
                    if jn < 0 || inn < 0 || jn >= h as isize || inn >= w as isize {
                        continue;
                    }
                    let kn = jn as usize * w + inn as usize;
                    if blocked[kn] {
                        continue;
                    }
                    let len = if dj != 0 && di != 0 { 2f64.sqrt() } else { 1.0 };
                    let nd = d[k] + len * 0.1 * 0.5 * (weight[k] + weight[kn]);
                    if nd < d[kn] - 1e-12 {
                        d[kn] = nd;
                        changed = true;
                    }
                }
            }
        }
        if !changed {
            return d;
        }
    }
}

#[test]
fn dijkstra_equals_relaxation_on_random_grids() {
    let mut stream = crate::test_rng::XorShift::new(12345);
    let mut rnd = || stream.fraction(10_000);
    for _ in 0..20 {
        let (w, h) = (17, 11);
        let blocked: Vec<bool> = (0..w * h).map(|_| rnd() < 0.25).collect();
        let weight: Vec<f64> = (0..w * h).map(|_| 1.0 + 3.0 * rnd()).collect();
        let seeds = vec![((rnd() * (w * h) as f64) as usize, 0.0), (3, 0.7)];
        let fast = geodesic_distances(w, h, &blocked, &weight, &seeds, 0.1).unwrap();
        let slow = brute(w, h, &blocked, &weight, &seeds);
        for (a, b) in fast.iter().zip(&slow) {
            assert!(
                (a.is_infinite() && b.is_infinite()) || (a - b).abs() < 1e-9,
                "{a} {b}"
            );
        }
    }
}

#[test]
fn open_grid_of_unit_weight_gives_octile_distance() {
    let (w, h) = (9, 7);
    let d = geodesic_distances(
        w,
        h,
        &vec![false; w * h],
        &vec![1.0; w * h],
        &[(0, 0.0)],
        0.5,
    )
    .unwrap();
    for j in 0..h {
        for i in 0..w {
            let (a, b) = (i.max(j) as f64, i.min(j) as f64);
            let octile = 0.5 * ((a - b) + b * 2f64.sqrt());
            assert!((d[j * w + i] - octile).abs() < 1e-12);
        }
    }
}

#[test]
fn a_wall_without_a_gap_leaves_the_far_side_unreachable() {
    let (w, h) = (6, 4);
    let blocked: Vec<bool> = (0..w * h).map(|k| k % w == 3).collect();
    let d = geodesic_distances(w, h, &blocked, &vec![1.0; w * h], &[(0, 0.0)], 1.0).unwrap();
    assert!(d[5].is_infinite() && d[2].is_finite());
}

#[test]
fn bad_arguments_are_errors() {
    assert!(geodesic_distances(2, 2, &[false; 3], &[1.0; 4], &[], 1.0).is_err());
    assert!(geodesic_distances(2, 2, &[false; 4], &[1.0; 4], &[(9, 0.0)], 1.0).is_err());
    assert!(geodesic_distances(2, 2, &[false; 4], &[f64::NAN; 4], &[], 1.0).is_err());
    assert!(geodesic_distances(1 << 13, 1 << 13, &[], &[], &[], 1.0).is_err());
    assert!(geodesic_distances(2, 2, &[false; 4], &[1.0; 4], &[], 0.0).is_err());
}

#[test]
fn coarse_blocks_take_the_least_cost_and_the_mean() {
    // 4 x 2 costs in blocks of 2: [[0, 254], [253, 253]] and [[10, 20], [30, 40]]
    let cost = [0, 254, 10, 20, 253, 253, 30, 40];
    let known = [true, true, false, true, true, true, false, false];
    let (mut blocked, mut weight) = (Vec::new(), Vec::new());
    let wh = coarse_grid(
        &cost,
        4,
        2,
        Some(&known),
        2,
        253,
        2.0,
        &mut blocked,
        &mut weight,
    );
    assert_eq!(wh.unwrap(), (2, 1));
    assert_eq!(blocked, vec![false, false]);
    assert_eq!(weight[0], 1.0 + 190.0 / 64.0);
    assert_eq!(weight[1], 1.0 + 25.0 / 64.0 + 2.0 * 0.75);
    let cost = [253u8; 4];
    coarse_grid(&cost, 2, 2, None, 2, 253, 2.0, &mut blocked, &mut weight).unwrap();
    assert_eq!((blocked[0], weight[0]), (true, 1.0 + 253.0 / 64.0));
    assert!(coarse_grid(&cost, 2, 2, None, 0, 253, 2.0, &mut blocked, &mut weight).is_err());
    assert!(coarse_grid(&cost, 3, 2, None, 1, 253, 2.0, &mut blocked, &mut weight).is_err());
}
