//! The information matrix of a correlative scan match: how sharply the summed likelihood field
//! at the scan's points falls off around the pose found, over (x, y, yaw). floorscan's drive
//! fuses each match with the odometry prediction as an extended Kalman filter does, with this
//! matrix (times a scale) as the match's inverse covariance.
//!
//! The field is read bilinearly between cell centres, as [`crate::scan_matcher::refine`]
//! reads it, except at its border: a point any of whose four cells lies off the field reads 0
//! there (the drive's field covers the search window with a margin, so none do in a drive).

use crate::error::{invalid_option, Error, Result};
use crate::pose::Pose2;
use crate::scan_matcher::Field;

/// Minus the Hessian of the sum of `field`'s values at `points` (robot frame [m]) over the
/// pose (x [m], y [m], yaw [rad]) at `pose` (world_from_robot), by central differences of one
/// cell (`field.cell_m`) in x and y and of `yaw_step_rad` in yaw (19 poses), with its
/// negative eigenvalues cut to 0: a symmetric positive semi-definite 3 x 3 matrix [1/m^2,
/// 1/(m rad), 1/rad^2], each point on a wall of a field of width sigma adding about
/// 1 / sigma^2 across the wall. No points, or none on the field: zeros.
pub fn match_information(
    field: &Field<'_>,
    points: &[[f64; 2]],
    pose: Pose2,
    yaw_step_rad: f64,
) -> Result<[[f64; 3]; 3]> {
    field.validate()?;
    if !(yaw_step_rad.is_finite() && yaw_step_rad > 0.0) {
        return Err(invalid_option(
            "yaw_step_rad",
            format!("must be > 0, got {yaw_step_rad}"),
        ));
    }
    if !pose.is_finite() {
        return Err(Error::InvalidGeometry("pose not finite".into()));
    }
    let h = [field.cell_m, field.cell_m, yaw_step_rad];
    // the offsets: 0; +-h_i per axis; (+-h_i, +-h_j) per pair of axes
    let mut offsets = [[0.0f64; 3]; 19];
    for i in 0..3 {
        offsets[1 + 2 * i][i] = h[i];
        offsets[2 + 2 * i][i] = -h[i];
    }
    let mut k = 7;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        for si in [1.0, -1.0] {
            for sj in [1.0, -1.0] {
                offsets[k][i] = si * h[i];
                offsets[k][j] = sj * h[j];
                k += 1;
            }
        }
    }
    let v = field_sums(
        field,
        points,
        offsets.map(|o| Pose2::new(pose.x + o[0], pose.y + o[1], pose.yaw + o[2])),
    );
    let mut hess = [[0.0f64; 3]; 3];
    for i in 0..3 {
        hess[i][i] = (v[1 + 2 * i] - 2.0 * v[0] + v[2 + 2 * i]) / (h[i] * h[i]);
    }
    let mut k = 7;
    for (i, j) in [(0, 1), (0, 2), (1, 2)] {
        let (pp, pm, mp, mm) = (v[k], v[k + 1], v[k + 2], v[k + 3]);
        hess[i][j] = (pp - pm - mp + mm) / (4.0 * h[i] * h[j]);
        hess[j][i] = hess[i][j];
        k += 4;
    }
    Ok(positive_part(hess.map(|row| row.map(|x| -x))))
}

/// The sums of the field's readings at `points` seen from each of `poses` ([`reading`]),
/// each adding the points in their order. Point by point, all poses at once: a point's
/// readings from neighbouring poses share their cache lines.
fn field_sums<const K: usize>(
    field: &Field<'_>,
    points: &[[f64; 2]],
    poses: [Pose2; K],
) -> [f64; K] {
    let frames = poses.map(|p| {
        let (s, c) = p.yaw.sin_cos();
        (p.x, p.y, s, c)
    });
    let mut sums = [0.0f64; K];
    for p in points {
        for (sum, &(x0, y0, s, c)) in sums.iter_mut().zip(&frames) {
            *sum += reading(field, x0 + c * p[0] - s * p[1], y0 + s * p[0] + c * p[1]);
        }
    }
    sums
}

/// The field read bilinearly between cell centres at world point (x, y) [m]; 0 where its
/// four cells do not all lie on the field.
#[inline(always)]
fn reading(field: &Field<'_>, x: f64, y: f64) -> f64 {
    let fx = (x - field.origin_m.0) / field.cell_m - 0.5;
    let fy = (y - field.origin_m.1) / field.cell_m - 0.5;
    // floor(f) in 0..n - 1, the last cell whose right and upper neighbours are on the field
    // (false for NaN)
    if !(fx >= 0.0 && fx < field.width as f64 - 1.0 && fy >= 0.0 && fy < field.height as f64 - 1.0)
    {
        return 0.0;
    }
    // f >= 0: truncation is floor (and no call into libm, which the baseline x86-64 target
    // makes for `floor`)
    let (fi, fj) = (fx as usize, fy as usize);
    let (ax, ay) = (fx - fi as f64, fy - fj as f64);
    let at = fj * field.width + fi;
    let f = |k: usize| field.values[k] as f64;
    (1.0 - ax) * (1.0 - ay) * f(at)
        + ax * (1.0 - ay) * f(at + 1)
        + (1.0 - ax) * ay * f(at + field.width)
        + ax * ay * f(at + field.width + 1)
}

/// The positive semi-definite part of symmetric `a`: its eigen-decomposition (cyclic Jacobi
/// rotations) with the negative eigenvalues set to 0; exactly symmetric.
pub fn positive_part(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let (w, v) = symmetric_eigen(a);
    let mut out = [[0.0f64; 3]; 3];
    for k in 0..3 {
        let lambda = w[k].max(0.0);
        for r in 0..3 {
            for c in r..3 {
                out[r][c] += lambda * v[r][k] * v[c][k];
            }
        }
    }
    (out[1][0], out[2][0], out[2][1]) = (out[0][1], out[0][2], out[1][2]);
    out
}

/// Eigenvalues and eigenvectors (columns of the second) of symmetric `a`, by cyclic Jacobi
/// rotations (Golub & Van Loan 8.5) until the off-diagonal part is below rounding, at most 50
/// sweeps.
pub fn symmetric_eigen(mut a: [[f64; 3]; 3]) -> ([f64; 3], [[f64; 3]; 3]) {
    let mut v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    for _ in 0..50 {
        let off = a[0][1] * a[0][1] + a[0][2] * a[0][2] + a[1][2] * a[1][2];
        let diag = a[0][0] * a[0][0] + a[1][1] * a[1][1] + a[2][2] * a[2][2];
        let tol = 1e-36 * (diag + off);
        if off <= tol || off.is_nan() || tol.is_nan() {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][q] == 0.0 {
                continue;
            }
            let theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
            let t = if theta.abs() > 1e150 {
                0.5 / theta
            } else {
                theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt())
            };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            let apq = a[p][q];
            a[p][p] -= t * apq;
            a[q][q] += t * apq;
            a[p][q] = 0.0;
            a[q][p] = 0.0;
            let r = 3 - p - q; // the third index
            let (arp, arq) = (a[r][p], a[r][q]);
            a[r][p] = c * arp - s * arq;
            a[p][r] = a[r][p];
            a[r][q] = s * arp + c * arq;
            a[q][r] = a[r][q];
            for row in &mut v {
                let (vp, vq) = (row[p], row[q]);
                row[p] = c * vp - s * vq;
                row[q] = s * vp + c * vq;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], v)
}

#[cfg(test)]
mod tests {
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
}
