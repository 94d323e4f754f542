//! Tests of the `match_information` module.

use super::*;

/// A field sampled at cell centres from `f(x, y)`, `w` x `h` cells of `cell` [m] from
/// `origin`.
fn sampled(
    w: usize,
    h: usize,
    origin: (f64, f64),
    cell: f64,
    f: impl Fn(f64, f64) -> f64,
) -> Vec<f32> {
    let mut v = Vec::with_capacity(w * h);
    for j in 0..h {
        for i in 0..w {
            let x = origin.0 + (i as f64 + 0.5) * cell;
            let y = origin.1 + (j as f64 + 0.5) * cell;
            v.push(f(x, y) as f32);
        }
    }
    v
}

fn close(a: [[f64; 3]; 3], b: [[f64; 3]; 3], tol: f64) -> bool {
    (0..3).all(|r| (0..3).all(|c| (a[r][c] - b[r][c]).abs() <= tol))
}

#[test]
fn a_quadratic_field_gives_its_analytic_hessian() {
    // f = 1 - (A x^2 + 2 B x y + C y^2) about (1, 1); whole-cell steps make the central
    // differences of its bilinear reading exact, wherever the points are; points at the
    // robot's origin do not move with yaw
    let (a, b, c) = (3.0, 1.0, 2.0);
    let values = sampled(40, 40, (0.0, 0.0), 0.05, |x, y| {
        let (x, y) = (x - 1.0, y - 1.0);
        1.0 - (a * x * x + 2.0 * b * x * y + c * y * y) / 8.0
    });
    let field = Field {
        values: &values,
        width: 40,
        height: 40,
        origin_m: (0.0, 0.0),
        cell_m: 0.05,
    };
    let points = [[0.0, 0.0]; 7];
    for pose in [
        Pose2::new(1.0, 1.0, 0.0),
        Pose2::new(0.93, 1.117, 0.4),
        Pose2::new(1.31, 0.72, -2.0),
    ] {
        let info = match_information(&field, &points, pose, 0.01).unwrap();
        let n = points.len() as f64 / 4.0;
        let want = [[n * a, n * b, 0.0], [n * b, n * c, 0.0], [0.0, 0.0, 0.0]];
        // float32 values: about 1e-7 of each reading, over h^2
        assert!(close(info, want, 1e-2), "{info:?}");
    }
}

#[test]
fn a_saddle_keeps_only_its_falling_direction() {
    // f = 0.5 + (x^2 - y^2) / 8 about (1, 1): -H = diag(-1/4, 1/4) per point
    let values = sampled(40, 40, (0.0, 0.0), 0.05, |x, y| {
        0.5 + ((x - 1.0).powi(2) - (y - 1.0).powi(2)) / 8.0
    });
    let field = Field {
        values: &values,
        width: 40,
        height: 40,
        origin_m: (0.0, 0.0),
        cell_m: 0.05,
    };
    let info = match_information(&field, &[[0.0, 0.0]; 4], Pose2::new(1.02, 0.97, 0.0), 0.01);
    let want = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 0.0]];
    assert!(close(info.unwrap(), want, 1e-3));
    // f = 0.5 + x y / 4: -H = [[0, -1/4], [-1/4, 0]] per point, eigenvalues -+1/4; what
    // is kept is 1/4 along (1, -1) / sqrt 2
    let values = sampled(40, 40, (0.0, 0.0), 0.05, |x, y| {
        0.5 + (x - 1.0) * (y - 1.0) / 4.0
    });
    let field = Field {
        values: &values,
        ..field
    };
    let info = match_information(&field, &[[0.0, 0.0]; 4], Pose2::new(0.99, 1.04, 1.0), 0.01);
    let want = [[0.5, -0.5, 0.0], [-0.5, 0.5, 0.0], [0.0, 0.0, 0.0]];
    assert!(close(info.unwrap(), want, 1e-3));
}

#[test]
fn a_sloped_field_curves_in_yaw_by_its_slope_along_the_arm() {
    // f = 0.5 + g . (x, y): bilinear reading reproduces it exactly; turning a point p of
    // the robot frame by yaw moves it along R p, so -d2 f / dyaw2 = g . R p, every other
    // second derivative 0 (cut to 0 where g . R p < 0)
    let g = (0.1, 0.2);
    let values = sampled(80, 80, (-2.0, -1.0), 0.05, |x, y| 0.5 + g.0 * x + g.1 * y);
    let field = Field {
        values: &values,
        width: 80,
        height: 80,
        origin_m: (-2.0, -1.0),
        cell_m: 0.05,
    };
    let points = [[0.6, 0.8], [0.1, 1.2], [-0.3, 0.4]];
    for yaw in [0.0, 0.3, 1.2, 2.5, -2.0] {
        let pose = Pose2::new(0.2, 0.7, yaw);
        let (s, c) = f64::sin_cos(yaw);
        let arm: f64 = points
            .iter()
            .map(|p| g.0 * (c * p[0] - s * p[1]) + g.1 * (s * p[0] + c * p[1]))
            .sum();
        // central differences of cos: (1 - h^2 / 12) of the curvature
        let want = arm.max(0.0) * (1.0 - 1e-4 / 12.0);
        let info = match_information(&field, &points, pose, 0.01).unwrap();
        let want = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, want]];
        // float32 readings: about 3e-8 each, over h^2
        assert!(close(info, want, 2e-3), "{yaw}: {info:?} {want:?}");
    }
}

#[test]
fn points_whose_cells_leave_the_field_read_zero() {
    let values = vec![1.0f32; 10 * 8];
    let field = Field {
        values: &values,
        width: 10,
        height: 8,
        origin_m: (0.0, 0.0),
        cell_m: 1.0,
    };
    let at = |x: f64, y: f64| reading(&field, x, y);
    assert_eq!(at(0.5, 0.5), 1.0); // a cell centre: its four cells on the field
    assert_eq!(at(9.49, 7.49), 1.0);
    assert_eq!(at(0.49, 3.0), 0.0); // its left cells off the field
    assert_eq!(at(9.5, 3.0), 0.0); // right
    assert_eq!(at(3.0, 7.5), 0.0); // top
    assert_eq!(at(-50.0, 1e300), 0.0);
    assert_eq!(at(f64::NAN, 1.0), 0.0);
    assert_eq!(at(f64::INFINITY, 1.0), 0.0);
    // a flat field has no curvature; no points, none on the field: zeros
    let zero = [[0.0; 3]; 3];
    let info = match_information(&field, &[[0.0, 0.0]], Pose2::new(4.0, 4.0, 0.3), 0.01);
    assert!(close(info.unwrap(), zero, 1e-9));
    let info = match_information(&field, &[], Pose2::new(4.0, 4.0, 0.3), 0.01);
    assert_eq!(info.unwrap(), zero);
    let info = match_information(&field, &[[0.0, 0.0]], Pose2::new(-40.0, 4.0, 0.3), 0.01);
    assert_eq!(info.unwrap(), zero);
    let empty = Field {
        values: &[],
        width: 0,
        height: 0,
        ..field
    };
    let info = match_information(&empty, &[[0.0, 0.0]], Pose2::IDENTITY, 0.01);
    assert_eq!(info.unwrap(), zero);
}

#[test]
fn the_eigen_decomposition_rebuilds_random_symmetric_matrices() {
    let mut stream = crate::test_rng::XorShift::new(5u64);
    let mut rnd = || stream.fraction(1_000_000) * 2.0 - 1.0;
    for k in 0..200 {
        let scale = 10f64.powi(k % 7 - 3);
        let mut a = [[0.0; 3]; 3];
        for (r, c) in [(0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2)] {
            a[r][c] = scale * rnd();
            a[c][r] = a[r][c];
        }
        let (w, v) = symmetric_eigen(a);
        let mut back = [[0.0; 3]; 3];
        let mut gram = [[0.0; 3]; 3];
        for r in 0..3 {
            for c in 0..3 {
                for (q, wq) in w.iter().enumerate() {
                    back[r][c] += wq * v[r][q] * v[c][q];
                    gram[r][c] += v[q][r] * v[q][c];
                }
            }
        }
        assert!(close(back, a, 1e-13 * scale), "{a:?} {back:?}");
        let eye = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(close(gram, eye, 1e-13));
        // the positive part: a minus it is negative semi-definite, and both commute
        let p = positive_part(a);
        let (wp, _) = symmetric_eigen(p);
        assert!(wp.iter().all(|&x| x >= -1e-13 * scale));
        let mut rest = a;
        for r in 0..3 {
            for c in 0..3 {
                rest[r][c] -= p[r][c];
            }
        }
        let (wr, _) = symmetric_eigen(rest);
        assert!(wr.iter().all(|&x| x <= 1e-13 * scale));
    }
    // diagonal already, zeros, NaN: no rotation or a bounded number
    assert_eq!(
        symmetric_eigen([[2.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 0.0]]).0,
        [2.0, -1.0, 0.0]
    );
    assert_eq!(positive_part([[0.0; 3]; 3]), [[0.0; 3]; 3]);
    let nan = [[f64::NAN, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
    let _ = positive_part(nan);
}

#[test]
fn bad_arguments_are_errors() {
    let values = vec![0.0f32; 4];
    let field = Field {
        values: &values,
        width: 2,
        height: 2,
        origin_m: (0.0, 0.0),
        cell_m: 1.0,
    };
    let p = Pose2::IDENTITY;
    assert!(match_information(&Field { width: 3, ..field }, &[], p, 0.01).is_err());
    assert!(match_information(
        &Field {
            cell_m: 0.0,
            ..field
        },
        &[],
        p,
        0.01
    )
    .is_err());
    assert!(match_information(&field, &[], p, 0.0).is_err());
    assert!(match_information(&field, &[], p, f64::NAN).is_err());
    assert!(match_information(&field, &[], Pose2::new(0.0, f64::INFINITY, 0.0), 0.01).is_err());
}
