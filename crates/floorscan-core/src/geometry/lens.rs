//! Lens models: how a ray in the camera's optical frame lands on the image, and back.
//!
//! Optical frame (OpenCV convention): x right, y down, z along the optical axis. Pixel coordinates
//! (u, v) have their origin at the centre of the top-left pixel, v growing downwards.
//! The simulator renders with these same models, so a table built from a model and an image
//! rendered with it agree by construction.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// A ray direction in the optical frame (not necessarily unit length).
pub type Ray = [f64; 3];

/// A lens model. Every model is central (all rays pass through one point).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(tag = "model", rename_all = "snake_case")]
pub enum Lens {
    /// Ideal perspective projection: u = fx x/z + cx.
    Pinhole { fx: f64, fy: f64, cx: f64, cy: f64 },
    /// Perspective projection with OpenCV's `plumb_bob` radial-tangential distortion
    /// (k1, k2, p1, p2, k3).
    PinholeRadial {
        fx: f64,
        fy: f64,
        cx: f64,
        cy: f64,
        k1: f64,
        k2: f64,
        p1: f64,
        p2: f64,
        k3: f64,
    },
    /// Equidistant fisheye: image radius r = f * theta (theta: angle from the optical axis).
    Equidistant { f: f64, cx: f64, cy: f64 },
    /// Kannala-Brandt, OpenCV's `fisheye` model:
    /// theta_d = theta (1 + k1 theta^2 + k2 theta^4 + k3 theta^6 + k4 theta^8), r = f theta_d.
    KannalaBrandt {
        fx: f64,
        fy: f64,
        cx: f64,
        cy: f64,
        k1: f64,
        k2: f64,
        k3: f64,
        k4: f64,
    },
}

/// Largest angle from the optical axis [rad] for which the fisheye models are used; rays beyond
/// it do not reach the sensor (the models stop being monotonic around there).
const FISHEYE_MAX_THETA_RAD: f64 = 1.55;

impl Lens {
    /// Checks that focal lengths are positive and all parameters finite.
    pub fn validate(&self) -> Result<()> {
        let (fx, fy, cx, cy) = self.intrinsics();
        let finite = match *self {
            Lens::Pinhole { .. } | Lens::Equidistant { .. } => true,
            Lens::PinholeRadial {
                k1, k2, p1, p2, k3, ..
            } => [k1, k2, p1, p2, k3].iter().all(|v| v.is_finite()),
            Lens::KannalaBrandt { k1, k2, k3, k4, .. } => {
                [k1, k2, k3, k4].iter().all(|v| v.is_finite())
            }
        };
        if !(fx > 0.0 && fy > 0.0 && fx.is_finite() && fy.is_finite()) {
            return Err(invalid_option(
                "lens",
                "focal lengths must be positive and finite",
            ));
        }
        if !(cx.is_finite() && cy.is_finite() && finite) {
            return Err(invalid_option("lens", "parameters must be finite"));
        }
        Ok(())
    }

    /// (fx, fy, cx, cy); the equidistant model has fx = fy = f.
    pub fn intrinsics(&self) -> (f64, f64, f64, f64) {
        match *self {
            Lens::Pinhole { fx, fy, cx, cy }
            | Lens::PinholeRadial { fx, fy, cx, cy, .. }
            | Lens::KannalaBrandt { fx, fy, cx, cy, .. } => (fx, fy, cx, cy),
            Lens::Equidistant { f, cx, cy } => (f, f, cx, cy),
        }
    }

    /// Pixel where a ray lands, or `None` if the lens cannot image it (behind the camera, or
    /// beyond the fisheye's field of view).
    pub fn project(&self, ray: Ray) -> Option<[f64; 2]> {
        let [x, y, z] = ray;
        let (fx, fy, cx, cy) = self.intrinsics();
        match *self {
            Lens::Pinhole { .. } => {
                if z <= 0.0 {
                    return None;
                }
                Some([fx * x / z + cx, fy * y / z + cy])
            }
            Lens::PinholeRadial {
                k1, k2, p1, p2, k3, ..
            } => {
                if z <= 0.0 {
                    return None;
                }
                let (a, b) = (x / z, y / z);
                let (xd, yd) = plumb_bob(a, b, k1, k2, p1, p2, k3);
                Some([fx * xd + cx, fy * yd + cy])
            }
            Lens::Equidistant { .. } | Lens::KannalaBrandt { .. } => {
                let rxy = x.hypot(y);
                let theta = rxy.atan2(z);
                if theta > FISHEYE_MAX_THETA_RAD {
                    return None;
                }
                let theta_d = self.fisheye_distort(theta);
                if rxy == 0.0 {
                    return Some([cx, cy]);
                }
                Some([fx * theta_d * x / rxy + cx, fy * theta_d * y / rxy + cy])
            }
        }
    }

    /// Ray through a pixel (unit length, z > 0 for the perspective models), or `None` where the
    /// model cannot be inverted (beyond the fisheye's field of view).
    pub fn unproject(&self, pixel: [f64; 2]) -> Option<Ray> {
        let (fx, fy, cx, cy) = self.intrinsics();
        let (mx, my) = ((pixel[0] - cx) / fx, (pixel[1] - cy) / fy);
        let ray = match *self {
            Lens::Pinhole { .. } => [mx, my, 1.0],
            Lens::PinholeRadial {
                k1, k2, p1, p2, k3, ..
            } => {
                let (a, b) = undistort_plumb_bob(mx, my, k1, k2, p1, p2, k3)?;
                [a, b, 1.0]
            }
            Lens::Equidistant { .. } | Lens::KannalaBrandt { .. } => {
                let theta_d = mx.hypot(my);
                if theta_d == 0.0 {
                    [0.0, 0.0, 1.0]
                } else {
                    let theta = self.fisheye_undistort(theta_d)?;
                    let s = theta.sin();
                    [s * mx / theta_d, s * my / theta_d, theta.cos()]
                }
            }
        };
        let n = (ray[0] * ray[0] + ray[1] * ray[1] + ray[2] * ray[2]).sqrt();
        Some([ray[0] / n, ray[1] / n, ray[2] / n])
    }

    fn fisheye_distort(&self, theta: f64) -> f64 {
        match *self {
            Lens::KannalaBrandt { k1, k2, k3, k4, .. } => {
                let t2 = theta * theta;
                theta * (1.0 + t2 * (k1 + t2 * (k2 + t2 * (k3 + t2 * k4))))
            }
            _ => theta,
        }
    }

    /// Inverts `fisheye_distort` by Newton's method on [0, FISHEYE_MAX_THETA_RAD].
    fn fisheye_undistort(&self, theta_d: f64) -> Option<f64> {
        let max_d = self.fisheye_distort(FISHEYE_MAX_THETA_RAD);
        if theta_d > max_d {
            return None;
        }
        let mut theta = theta_d.min(FISHEYE_MAX_THETA_RAD);
        for _ in 0..50 {
            let f = self.fisheye_distort(theta) - theta_d;
            let h = 1e-7;
            let df =
                (self.fisheye_distort(theta + h) - self.fisheye_distort(theta - h)) / (2.0 * h);
            if df <= 0.0 {
                return None;
            }
            let step = f / df;
            theta = (theta - step).clamp(0.0, FISHEYE_MAX_THETA_RAD);
            if step.abs() < 1e-12 {
                break;
            }
        }
        ((self.fisheye_distort(theta) - theta_d).abs() < 1e-8).then_some(theta)
    }
}

fn plumb_bob(a: f64, b: f64, k1: f64, k2: f64, p1: f64, p2: f64, k3: f64) -> (f64, f64) {
    let r2 = a * a + b * b;
    let radial = 1.0 + r2 * (k1 + r2 * (k2 + r2 * k3));
    (
        a * radial + 2.0 * p1 * a * b + p2 * (r2 + 2.0 * a * a),
        b * radial + p1 * (r2 + 2.0 * b * b) + 2.0 * p2 * a * b,
    )
}

/// Fixed-point inversion of plumb_bob (as OpenCV's `undistortPoints`), checked at the end.
fn undistort_plumb_bob(
    xd: f64,
    yd: f64,
    k1: f64,
    k2: f64,
    p1: f64,
    p2: f64,
    k3: f64,
) -> Option<(f64, f64)> {
    let (mut a, mut b) = (xd, yd);
    for _ in 0..200 {
        let (fa, fb) = plumb_bob(a, b, k1, k2, p1, p2, k3);
        let (ea, eb) = (fa - xd, fb - yd);
        if ea.abs() < 1e-13 && eb.abs() < 1e-13 {
            break;
        }
        // Newton step with a numeric Jacobian: converges where the fixed point iteration stalls.
        let h = 1e-7;
        let (fa_x, fb_x) = plumb_bob(a + h, b, k1, k2, p1, p2, k3);
        let (fa_y, fb_y) = plumb_bob(a, b + h, k1, k2, p1, p2, k3);
        let (j00, j10, j01, j11) = (
            (fa_x - fa) / h,
            (fb_x - fb) / h,
            (fa_y - fa) / h,
            (fb_y - fb) / h,
        );
        let det = j00 * j11 - j01 * j10;
        if det.abs() < 1e-12 {
            return None;
        }
        a -= (j11 * ea - j01 * eb) / det;
        b -= (-j10 * ea + j00 * eb) / det;
    }
    let (fa, fb) = plumb_bob(a, b, k1, k2, p1, p2, k3);
    ((fa - xd).abs() < 1e-9 && (fb - yd).abs() < 1e-9).then_some((a, b))
}

#[cfg(test)]
#[path = "lens_tests.rs"]
mod tests;
