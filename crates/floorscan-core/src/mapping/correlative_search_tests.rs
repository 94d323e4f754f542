//! Tests of [`super`] (correlative_search.rs).

use super::*;

const CELL: f64 = 0.05;

/// A field of 1 on the cells of an L of walls (x = 1 m and y = 1 m, within 0..2 m), 0
/// elsewhere, 40 x 40 cells from the origin.
fn l_field() -> Vec<f32> {
    let mut v = vec![0.0f32; 40 * 40];
    for k in 0..40 {
        v[k * 40 + 20] = 1.0; // x = 1.0..1.05
        v[20 * 40 + k] = 1.0; // y = 1.0..1.05
    }
    v
}

fn window() -> SearchWindow {
    SearchWindow {
        xy_steps: 4,
        yaw_steps: 5,
        yaw_step_rad: 0.01,
        prior_xy_m: 1.0,
        prior_yaw_rad: 1.0,
    }
}

#[test]
fn recovers_a_shifted_pose_of_an_l_shaped_scan() {
    let values = l_field();
    let field = Field {
        values: &values,
        width: 40,
        height: 40,
        origin_m: (0.0, 0.0),
        cell_m: CELL,
    };
    // the robot truly at (0.4, 0.3, 0): points on both walls, in its frame
    let truth = Pose2::new(0.4, 0.3, 0.0);
    let mut pts = Vec::new();
    for k in 0..30 {
        let y = 0.0 + 0.05 * k as f64 + 0.025;
        pts.push([1.025 - truth.x, y - truth.y]);
        pts.push([y - truth.x, 1.025 - truth.y]);
    }
    let prior = Pose2::new(0.4 + 3.0 * CELL, 0.3 - 2.0 * CELL, 0.0);
    let r = search(&field, &pts, prior, &window()).unwrap();
    assert!((r.pose.x - truth.x).abs() < 1e-9 && (r.pose.y - truth.y).abs() < 1e-9);
    assert!(r.pose.yaw.abs() < 1e-12);
    assert!((r.mean - 1.0).abs() < 1e-9);
}

#[test]
fn the_score_is_the_mean_of_the_field_times_the_prior() {
    let values = vec![0.5f32; 16];
    let field = Field {
        values: &values,
        width: 4,
        height: 4,
        origin_m: (0.0, 0.0),
        cell_m: 1.0,
    };
    let r = search(
        &field,
        &[[0.0, 0.0], [10.0, 10.0]],
        Pose2::new(1.5, 1.5, 0.0),
        &window(),
    );
    let r = r.unwrap();
    // one point on the field (0.5), one off it (0): the unshifted pose wins by its prior
    assert!((r.mean - 0.25).abs() < 1e-12 && r.pose == Pose2::new(1.5, 1.5, 0.0));
}

/// The mean field value of `points` at `pose`, read cell by cell with bounds checks.
fn mean_at(field: &Field<'_>, points: &[[f64; 2]], pose: Pose2) -> f64 {
    let (sn, cs) = pose.yaw.sin_cos();
    let mut sum = 0.0;
    for p in points {
        let wx = pose.x + cs * p[0] - sn * p[1];
        let wy = pose.y + sn * p[0] + cs * p[1];
        let i = ((wx - field.origin_m.0) / field.cell_m).floor() as i64;
        let j = ((wy - field.origin_m.1) / field.cell_m).floor() as i64;
        if i >= 0 && j >= 0 && i < field.width as i64 && j < field.height as i64 {
            sum += field.values[j as usize * field.width + i as usize] as f64;
        }
    }
    sum / points.len() as f64
}

#[test]
fn the_search_finds_the_brute_force_best_on_random_fields_and_points_near_the_edges() {
    let mut stream = crate::test_rng::XorShift::new(99u64);
    let mut rnd = || stream.fraction(1_000_000);
    for _ in 0..10 {
        let (w, h) = (23, 17);
        let values: Vec<f32> = (0..w * h).map(|_| rnd() as f32).collect();
        let field = Field {
            values: &values,
            width: w,
            height: h,
            origin_m: (-0.3, 0.2),
            cell_m: 0.1,
        };
        // points around and beyond the field's edges, in the robot frame of the prior
        let pts: Vec<[f64; 2]> = (0..30)
            .map(|_| [rnd() * 3.4 - 0.9, rnd() * 2.6 - 0.9])
            .collect();
        let prior = Pose2::new(0.2, 0.9, 0.05);
        let win = SearchWindow {
            xy_steps: 3,
            yaw_steps: 2,
            yaw_step_rad: 0.02,
            prior_xy_m: 0.5,
            prior_yaw_rad: 0.5,
        };
        let r = search(&field, &pts, prior, &win).unwrap();
        let mut best = -1.0;
        for ky in -2..=2 {
            for ty in -3..=3 {
                for tx in -3..=3 {
                    let dyaw = ky as f64 * 0.02;
                    let pose =
                        Pose2::new(0.2 + tx as f64 * 0.1, 0.9 + ty as f64 * 0.1, 0.05 + dyaw);
                    let t = ((tx * tx + ty * ty) as f64).sqrt() * 0.1;
                    let score = mean_at(&field, &pts, pose)
                        * (-(t / 0.5f64).powi(2)).exp()
                        * (-(dyaw / 0.5f64).powi(2)).exp();
                    if score > best {
                        best = score;
                    }
                }
            }
        }
        assert!((r.score - best).abs() < 1e-9, "{} vs {best}", r.score);
        assert!((mean_at(&field, &pts, r.pose) - r.mean).abs() < 1e-9);
    }
}

/// The search as first written (a padded copy of the field, one gather per point and
/// shift): the reference the row-wise sums must equal bit for bit.
fn padded_search(
    field: &Field<'_>,
    points: &[[f64; 2]],
    prior: Pose2,
    window: &SearchWindow,
) -> SearchResult {
    let mut best = SearchResult {
        pose: prior,
        mean: 0.0,
        score: -1.0,
    };
    let s = window.xy_steps as i64;
    let (w, h) = (field.width as i64, field.height as i64);
    let pad = 2 * s;
    let pw = w + 2 * pad;
    let mut padded = vec![0.0f32; (pw * (h + 2 * pad)) as usize];
    for j in 0..h {
        let src = &field.values[(j * w) as usize..((j + 1) * w) as usize];
        let at = ((j + pad) * pw + pad) as usize;
        padded[at..at + w as usize].copy_from_slice(src);
    }
    let inv_n = 1.0 / points.len() as f64;
    let mut bases: Vec<i64> = Vec::new();
    for ky in -(window.yaw_steps as i64)..=(window.yaw_steps as i64) {
        let dyaw = ky as f64 * window.yaw_step_rad;
        let yaw = prior.yaw + dyaw;
        let (sn, cs) = yaw.sin_cos();
        bases.clear();
        for p in points {
            let wx = prior.x + cs * p[0] - sn * p[1];
            let wy = prior.y + sn * p[0] + cs * p[1];
            let fi = ((wx - field.origin_m.0) / field.cell_m).floor();
            let fj = ((wy - field.origin_m.1) / field.cell_m).floor();
            let reach = |f: f64, n: i64| f >= -(s as f64) && f < (n + s) as f64;
            if reach(fi, w) && reach(fj, h) {
                bases.push((fj as i64 + pad) * pw + fi as i64 + pad);
            }
        }
        let yaw_prior = (-(dyaw / window.prior_yaw_rad).powi(2)).exp();
        for ty in -s..=s {
            for tx in -s..=s {
                let shift = ty * pw + tx;
                let mut sum = 0.0f64;
                for &b in &bases {
                    sum += padded[(b + shift) as usize] as f64;
                }
                let mean = sum * inv_n;
                let t = ((tx * tx + ty * ty) as f64).sqrt() * field.cell_m;
                let score = mean * (-(t / window.prior_xy_m).powi(2)).exp() * yaw_prior;
                if score > best.score {
                    best = SearchResult {
                        pose: Pose2::new(
                            prior.x + tx as f64 * field.cell_m,
                            prior.y + ty as f64 * field.cell_m,
                            yaw,
                        ),
                        mean,
                        score,
                    };
                }
            }
        }
    }
    best
}

#[test]
fn the_row_wise_sums_equal_the_padded_gathers_bit_for_bit() {
    let mut stream = crate::test_rng::XorShift::new(7u64);
    let mut rnd = || stream.fraction(1_000_000);
    for _ in 0..20 {
        let (w, h) = (31, 19);
        let values: Vec<f32> = (0..w * h).map(|_| rnd() as f32).collect();
        let field = Field {
            values: &values,
            width: w,
            height: h,
            origin_m: (-0.3, 0.2),
            cell_m: 0.1,
        };
        let pts: Vec<[f64; 2]> = (0..40)
            .map(|_| [rnd() * 4.4 - 1.4, rnd() * 3.0 - 1.4])
            .collect();
        let prior = Pose2::new(0.3, 0.8, -0.1);
        let win = SearchWindow {
            xy_steps: 4,
            yaw_steps: 3,
            yaw_step_rad: 0.02,
            prior_xy_m: 0.5,
            prior_yaw_rad: 0.5,
        };
        let fast = search(&field, &pts, prior, &win).unwrap();
        let slow = padded_search(&field, &pts, prior, &win);
        assert_eq!(fast.pose, slow.pose);
        assert_eq!(fast.mean.to_bits(), slow.mean.to_bits());
        assert_eq!(fast.score.to_bits(), slow.score.to_bits());
    }
}

#[test]
fn refinement_finds_a_peak_between_cell_centres() {
    // a smooth ridge along y at x = 1.0 m, sampled at cell centres (0.025 + 0.05 k); the
    // scan's points spread over two cells, so their mean reading is smooth in x
    let (w, h) = (40, 10);
    let values: Vec<f32> = (0..w * h)
        .map(|k| {
            let x = ((k % w) as f64 + 0.5) * 0.05;
            (-((x - 1.0) / 0.2).powi(2)).exp() as f32
        })
        .collect();
    let field = Field {
        values: &values,
        width: w,
        height: h,
        origin_m: (0.0, 0.0),
        cell_m: 0.05,
    };
    let win = SearchWindow {
        xy_steps: 2,
        yaw_steps: 0,
        yaw_step_rad: 0.01,
        prior_xy_m: 1e6,
        prior_yaw_rad: 1e6,
    };
    let pts: Vec<[f64; 2]> = (0..21).map(|k| [-0.05 + 0.005 * k as f64, 0.2]).collect();
    let prior = Pose2::new(1.013, 0.0, 0.0);
    let r = search(&field, &pts, prior, &win).unwrap();
    let refined = refine(&field, &pts, r.pose, prior, &win);
    assert!((refined.pose.x - 1.0).abs() < 0.003, "{:?}", refined.pose);
    assert!((r.pose.x - 1.0).abs() > 0.01); // the whole-cell search alone stays off
                                            // it climbs the bilinear score it refines (the search reads whole cells)
    let (start, _) = smooth_score(&field, &pts, r.pose, prior, &win);
    assert!(refined.score >= start);
}

#[test]
fn bad_arguments_are_errors() {
    let values = vec![0.0f32; 3];
    let field = Field {
        values: &values,
        width: 2,
        height: 2,
        origin_m: (0.0, 0.0),
        cell_m: 1.0,
    };
    assert!(search(&field, &[], Pose2::IDENTITY, &window()).is_err());
    let values = vec![0.0f32; 4];
    let field = Field {
        values: &values,
        ..field
    };
    let mut w = window();
    w.yaw_step_rad = 0.0;
    assert!(search(&field, &[], Pose2::IDENTITY, &w).is_err());
    w = window();
    w.xy_steps = 100_000;
    assert!(search(&field, &[[0.0, 0.0]], Pose2::IDENTITY, &w).is_err());
    // few evaluations but a padded field of 4 x 10^8 cells: refused, not allocated
    w = window();
    w.xy_steps = 5_000;
    w.yaw_steps = 0;
    assert!(search(&field, &[[0.0, 0.0]], Pose2::IDENTITY, &w).is_err());
    w.xy_steps = u32::MAX;
    assert!(search(&field, &[[0.0, 0.0]], Pose2::IDENTITY, &w).is_err());
    assert!(search(&field, &[], Pose2::new(f64::NAN, 0.0, 0.0), &window()).is_err());
}

#[test]
fn the_inline_floor_is_floor() {
    for x in [
        0.0,
        -0.0,
        0.5,
        -0.5,
        1.0,
        -1.0,
        2.999,
        -2.999,
        1e15 + 0.5,
        -1e15 - 0.5,
        4.5e15,
        -7e300,
    ] {
        assert_eq!(floor(x), x.floor(), "{x}");
    }
    assert!(floor(f64::NAN).is_nan());
    assert_eq!(floor(f64::NEG_INFINITY), f64::NEG_INFINITY);
}

#[test]
fn the_dispatched_window_sums_equal_the_baseline_ones() {
    let (w, h) = (40usize, 30usize);
    let values: Vec<f32> = (0..w * h)
        .map(|k| ((k * 7919) % 1000) as f32 / 997.0)
        .collect();
    let field = Field {
        values: &values,
        width: w,
        height: h,
        origin_m: (0.0, 0.0),
        cell_m: 0.1,
    };
    // points inside, near every edge and off the field
    let cells: Vec<(i64, i64, bool)> = [(20, 15), (1, 2), (38, 28), (-3, 10), (25, 31), (8, 8)]
        .iter()
        .map(|&(i, j)| {
            (
                i,
                j,
                i - 4 >= 0 && j - 4 >= 0 && i + 4 + CHUNK as i64 <= 40 && j + 4 < 30,
            )
        })
        .collect();
    let (mut a, mut b) = (vec![0.0; 81], vec![0.0; 81]);
    window_sums(&field, &cells, 4, &mut a);
    window_sums_body(&field, &cells, 4, &mut b);
    assert_eq!(
        a.iter().map(|v| v.to_bits()).collect::<Vec<_>>(),
        b.iter().map(|v| v.to_bits()).collect::<Vec<_>>()
    );
}
