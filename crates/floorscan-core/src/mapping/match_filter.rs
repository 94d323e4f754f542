//! The scan matcher's filter: each correlative match fused with the odometry prediction as an
//! extended Kalman filter over five states, the pose (x [m], y [m], yaw [rad]) and two errors of
//! odometry that robots calibrate (the turn scale error, the heading drift per metre), estimated
//! from the matches and used to correct each prediction.
//!
//! The prediction's covariance grows with each wheel's travel (`odometry_wheel_sigma`
//! sqrt(|travel|)); the match's information is the curvature of the summed likelihood field at
//! the pose found ([`crate::match_information`]) over `match_variance_scale`, so a corridor
//! corrects across itself and not along it, and a narrow view of near walls corrects the heading
//! little. The 5 x 5 algebra is written out on floats in a fixed order, as the Python floats it
//! replaced were; the tests hold it to numpy's textbook form (the 5 x 5 inverses,
//! `tests/scan_matcher_reference.py`) to rounding.

use crate::pose::Pose2;
use crate::scan_matcher_options::ScanMatcherOptions;

/// A match as the matcher reports it: the pose (world_from_robot), its mean field value,
/// whether the pose was kept (the match found and not refused by the filter), and the number
/// of points matched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MatchResult {
    pub pose: Pose2,
    pub score: f64,
    pub accepted: bool,
    pub points: usize,
}

/// The filter's state.
#[derive(Debug, Clone, PartialEq)]
pub struct MatchFilter {
    /// The pose kept last (None before the first frame).
    pub last: Option<Pose2>,
    /// The covariance of the state's error: x [m], y [m], yaw [rad], the turn scale error,
    /// the heading drift [rad/m].
    pub covariance: [[f64; 5]; 5],
    /// Odometry's estimated errors: the turn scale error, the heading drift [rad/m].
    pub calibration: [f64; 2],
    /// The last fused match's innovation as a Mahalanobis distance (None before any).
    pub last_mahalanobis: Option<f64>,
}

/// `x` minus the multiple of `y` (> 0) nearest to it (ties to even), as IEEE 754's remainder
/// (and Python's `math.remainder`): the multiple subtracted by a fused multiply-add, exact for
/// the angles of a frame's motion; within half of `y` always (a quotient that rounds onto a
/// half is put right).
pub fn ieee_remainder(x: f64, y: f64) -> f64 {
    let n = (x / y).round_ties_even();
    let r = (-n).mul_add(y, x);
    if r > 0.5 * y {
        r - y
    } else if r < -0.5 * y {
        r + y
    } else {
        r
    }
}

/// The inverse of `a` by its adjugate.
fn inverse3(a: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let [[a00, a01, a02], [a10, a11, a12], [a20, a21, a22]] = a;
    let (c00, c01, c02) = (
        a11 * a22 - a12 * a21,
        a12 * a20 - a10 * a22,
        a10 * a21 - a11 * a20,
    );
    let inv_det = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02);
    [
        [
            c00 * inv_det,
            (a02 * a21 - a01 * a22) * inv_det,
            (a01 * a12 - a02 * a11) * inv_det,
        ],
        [
            c01 * inv_det,
            (a00 * a22 - a02 * a20) * inv_det,
            (a02 * a10 - a00 * a12) * inv_det,
        ],
        [
            c02 * inv_det,
            (a01 * a20 - a00 * a21) * inv_det,
            (a00 * a11 - a01 * a10) * inv_det,
        ],
    ]
}

impl MatchFilter {
    /// The state before the first frame: the calibration's variances its priors when the
    /// options estimate it, all else 0.
    pub fn new(o: &ScanMatcherOptions) -> Self {
        let mut covariance = [[0.0; 5]; 5];
        if o.calibrate_odometry {
            covariance[3][3] = o.turn_error_prior * o.turn_error_prior;
            covariance[4][4] = o.drift_prior_rad_per_m * o.drift_prior_rad_per_m;
        }
        Self {
            last: None,
            covariance,
            calibration: [0.0; 2],
            last_mahalanobis: None,
        }
    }

    /// The prediction for the frame whose odometry pose, carried by the last correction, is
    /// `prior` (the pose kept last composed with odometry's increment): the increment's turn
    /// corrected by the estimated turn scale error and heading drift per metre, the
    /// covariance grown as F P F^T + G M G^T (F the pose's dependence on the heading and the
    /// calibration, M the wheels' noise over the distance driven and the turn). Returns the
    /// corrected prior.
    pub fn predict(&mut self, o: &ScanMatcherOptions, prior: Pose2) -> Pose2 {
        let Some(a) = self.last else {
            self.last = Some(prior);
            return prior;
        };
        let (c, s) = (a.yaw.cos(), a.yaw.sin());
        let (mut wx, mut wy) = (prior.x - a.x, prior.y - a.y);
        let d = c * wx + s * wy; // signed distance driven (robot frame x)
        let dth = ieee_remainder(prior.yaw - a.yaw, std::f64::consts::TAU);
        let [g, k] = self.calibration;
        let extra = g * dth + k * d; // the turn odometry misses
        let (cr, sr) = ((0.5 * extra).cos(), (0.5 * extra).sin());
        (wx, wy) = (cr * wx - sr * wy, sr * wx + cr * wy);
        let pred = if o.calibrate_odometry && o.match_variance_scale > 0.0 {
            Pose2::new(a.x + wx, a.y + wy, a.yaw + dth + extra)
        } else {
            prior // nothing to correct: the caller's prior as it is
        };
        let b = o.odometry_wheelbase_m;
        let sw = o.odometry_wheel_sigma * o.odometry_wheel_sigma;
        let vl = sw * (d - 0.5 * b * dth).abs();
        let vr = sw * (d + 0.5 * b * dth).abs();
        let (m00, m01, m11) = (0.25 * (vl + vr), 0.5 * (vr - vl) / b, (vl + vr) / (b * b));
        let h = a.yaw + 0.5 * (dth + extra);
        let (ch, sh) = (h.cos(), h.sin());
        let (e02, e03, e04) = (-wy, -wy * 0.5 * dth, -wy * 0.5 * d);
        let (e12, e13, e14) = (wx, wx * 0.5 * dth, wx * 0.5 * d);
        let (e23, e24) = (dth, d);
        let p = &self.covariance;
        // F P, then (F P) F^T
        let mut fp = [[0.0; 5]; 5];
        for col in 0..5 {
            fp[0][col] = p[0][col] + e02 * p[2][col] + e03 * p[3][col] + e04 * p[4][col];
            fp[1][col] = p[1][col] + e12 * p[2][col] + e13 * p[3][col] + e14 * p[4][col];
            fp[2][col] = p[2][col] + e23 * p[3][col] + e24 * p[4][col];
        }
        fp[3] = p[3];
        fp[4] = p[4];
        let cov = fp.map(|r| {
            [
                r[0] + e02 * r[2] + e03 * r[3] + e04 * r[4],
                r[1] + e12 * r[2] + e13 * r[3] + e14 * r[4],
                r[2] + e23 * r[3] + e24 * r[4],
                r[3],
                r[4],
            ]
        });
        let mut cov = cov;
        let (q00, q01, q11) = (ch * m00 * ch, ch * m00 * sh, sh * m00 * sh);
        let (q02, q12) = (ch * m01, sh * m01);
        cov[0][0] += q00;
        cov[0][1] += q01;
        cov[1][0] += q01;
        cov[1][1] += q11;
        cov[0][2] += q02;
        cov[2][0] += q02;
        cov[1][2] += q12;
        cov[2][1] += q12;
        cov[2][2] += m11;
        let drift = o.calibration_drift * o.calibration_drift;
        cov[3][3] += drift * dth.abs();
        cov[4][4] += drift * d.abs();
        self.covariance = cov;
        self.last = Some(pred);
        pred
    }

    /// The match `found` fused with the prediction `prior` ([`Self::predict`] first) in
    /// information form, the match's information `information` / `match_variance_scale`;
    /// refused (the prediction kept) when its innovation's Mahalanobis distance exceeds
    /// `rejection_threshold`. A match not accepted, or options without fusion, keep
    /// `found` as it is.
    pub fn fuse(
        &mut self,
        o: &ScanMatcherOptions,
        found: MatchResult,
        prior: Pose2,
        information: &[[f64; 3]; 3],
    ) -> MatchResult {
        if !found.accepted || o.match_variance_scale == 0.0 {
            self.last = Some(found.pose);
            return found;
        }
        // post = (P^-1 + J)^-1 = (I + P J)^-1 P with J the match's information in the pose's
        // 3 x 3 block: I + P J = [[A, 0], [P21 J, I]], A = I + P11 J (its eigenvalues those of
        // I plus a product of two positive semi-definite matrices: >= 1), so only A is inverted
        let scale = o.match_variance_scale;
        let j = information.map(|r| r.map(|v| v / scale));
        // a floor under the prediction's variances keeps it positive definite at the start
        let mut p = self.covariance;
        p[0][0] += 1e-8;
        p[1][1] += 1e-8;
        p[2][2] += 1e-10;
        let pj = p.map(|r| [0, 1, 2].map(|c| r[0] * j[0][c] + r[1] * j[1][c] + r[2] * j[2][c]));
        let ainv = inverse3(
            [0, 1, 2].map(|r| [0, 1, 2].map(|c| pj[r][c] + if r == c { 1.0 } else { 0.0 })),
        );
        let mut post = [[0.0; 5]; 5];
        for (row, a) in ainv.iter().enumerate() {
            for c in 0..5 {
                post[row][c] = a[0] * p[0][c] + a[1] * p[1][c] + a[2] * p[2][c];
            }
        }
        for r in 3..5 {
            let q = pj[r];
            for c in 0..5 {
                post[r][c] = p[r][c] - (q[0] * post[0][c] + q[1] * post[1][c] + q[2] * post[2][c]);
            }
        }
        let post0 = post;
        for (r, row) in post.iter_mut().enumerate() {
            for (c, v) in row.iter_mut().enumerate() {
                *v = 0.5 * (post0[r][c] + post0[c][r]);
            }
        }
        let z = [
            found.pose.x - prior.x,
            found.pose.y - prior.y,
            ieee_remainder(found.pose.yaw - prior.yaw, std::f64::consts::TAU),
        ];
        let u = j.map(|r| r[0] * z[0] + r[1] * z[1] + r[2] * z[2]);
        // the innovation's squared Mahalanobis distance z^T (P + J^-1)^-1 z, written
        // z^T J (I + P J)^-1 z so that a J without full rank (a corridor) needs no inverse
        let w = ainv.map(|a| a[0] * z[0] + a[1] * z[1] + a[2] * z[2]);
        let m2 = (0..3).fold(0.0, |acc, r| {
            acc + z[r] * (j[r][0] * w[0] + j[r][1] * w[1] + j[r][2] * w[2])
        });
        let mahalanobis = m2.max(0.0).sqrt();
        self.last_mahalanobis = Some(mahalanobis);
        if mahalanobis > o.rejection_threshold.unwrap_or(f64::INFINITY) {
            self.last = Some(prior);
            return MatchResult {
                pose: prior,
                accepted: false,
                ..found
            };
        }
        let step = post.map(|r| r[0] * u[0] + r[1] * u[1] + r[2] * u[2]);
        let pose = Pose2::new(prior.x + step[0], prior.y + step[1], prior.yaw + step[2]);
        if o.calibrate_odometry {
            self.calibration = [
                (self.calibration[0] + step[3]).clamp(-0.5, 0.5),
                (self.calibration[1] + step[4]).clamp(-0.5, 0.5),
            ];
        } else {
            for (r, row) in post.iter_mut().enumerate() {
                for (c, v) in row.iter_mut().enumerate() {
                    if r >= 3 || c >= 3 {
                        *v = 0.0;
                    }
                }
            }
        }
        self.covariance = post;
        self.last = Some(pose);
        MatchResult {
            pose,
            accepted: true,
            ..found
        }
    }
}

#[cfg(test)]
#[path = "match_filter_tests.rs"]
mod tests;
