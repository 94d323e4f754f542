//! The information matrix of a correlative scan match: how sharply the summed likelihood field
//! at the scan's points falls off around the pose found, over (x, y, yaw). floorscan's drive
//! fuses each match with the odometry prediction as an extended Kalman filter does, with this
//! matrix (times a scale) as the match's inverse covariance.
//!
//! The field is read bilinearly between cell centres, as [`crate::correlative_search::refine`]
//! reads it, except at its border: a point any of whose four cells lies off the field reads 0
//! there (the drive's field covers the search window with a margin, so none do in a drive).

use crate::correlative_search::Field;
use crate::error::{invalid_option, Error, Result};
use crate::pose::Pose2;

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
#[path = "match_information_tests.rs"]
mod tests;
