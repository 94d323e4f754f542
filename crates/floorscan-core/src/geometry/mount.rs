//! How a camera sits above the floor, and the exact image-to-ground mapping of a lens model at
//! that mount. This is the model-based way to build a [`GroundTable`] (for users who have OpenCV
//! intrinsics); the simulator uses it as ground truth.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};
use crate::ground_table::GroundTable;
use crate::lens::{Lens, Ray};
use crate::pose::Point2;

/// Camera pose relative to its ground frame (origin on the floor below the camera, x along the
/// camera's heading, z up).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct CameraMount {
    /// Height of the optical centre above the floor [m], > 0.
    pub height_m: f64,
    /// Downward tilt of the optical axis below the horizontal [rad]; 0 looks at the horizon.
    pub tilt_rad: f64,
    /// Rotation about the optical axis [rad], positive turns the image clockwise as seen by the
    /// camera (its x axis towards its y axis).
    #[serde(default)]
    pub roll_rad: f64,
}

impl CameraMount {
    pub fn validate(&self) -> Result<()> {
        if !(self.height_m > 0.0 && self.height_m.is_finite()) {
            return Err(invalid_option(
                "height_m",
                format!("must be > 0, got {}", self.height_m),
            ));
        }
        if !(self.tilt_rad.is_finite() && self.tilt_rad.abs() < std::f64::consts::FRAC_PI_2 + 1e-9)
        {
            return Err(invalid_option(
                "tilt_rad",
                "must be finite, within [-pi/2, pi/2]",
            ));
        }
        if !self.roll_rad.is_finite() {
            return Err(invalid_option("roll_rad", "must be finite"));
        }
        Ok(())
    }

    /// Rotates a ray from the optical frame (x right, y down, z forward) into the ground frame
    /// (x forward, y left, z up).
    pub fn ground_from_optical(&self, ray: Ray) -> [f64; 3] {
        let (st, ct) = self.tilt_rad.sin_cos();
        let (sr, cr) = self.roll_rad.sin_cos();
        // Optical axes expressed in the ground frame, before roll.
        let z_axis = [ct, 0.0, -st];
        let x_axis0 = [0.0, -1.0, 0.0];
        let y_axis0 = [-st, 0.0, -ct];
        let x_axis = add(scale(x_axis0, cr), scale(y_axis0, sr));
        let y_axis = add(scale(x_axis0, -sr), scale(y_axis0, cr));
        add(
            add(scale(x_axis, ray[0]), scale(y_axis, ray[1])),
            scale(z_axis, ray[2]),
        )
    }

    /// Inverse of [`Self::ground_from_optical`].
    pub fn optical_from_ground(&self, d: [f64; 3]) -> Ray {
        let ex = self.ground_from_optical([1.0, 0.0, 0.0]);
        let ey = self.ground_from_optical([0.0, 1.0, 0.0]);
        let ez = self.ground_from_optical([0.0, 0.0, 1.0]);
        [dot(ex, d), dot(ey, d), dot(ez, d)]
    }

    /// Where a ray (optical frame) meets the floor, in the ground frame, or `None` if it points
    /// at or above the horizon.
    pub fn ray_to_ground(&self, ray: Ray) -> Option<Point2> {
        let d = self.ground_from_optical(ray);
        if d[2] >= -1e-12 {
            return None;
        }
        let t = self.height_m / -d[2];
        Some(Point2::new(t * d[0], t * d[1]))
    }

    /// Optical-frame ray from the camera to a point in the ground frame at height `z_m`.
    pub fn ray_to_point(&self, x_m: f64, y_m: f64, z_m: f64) -> Ray {
        self.optical_from_ground([x_m, y_m, z_m - self.height_m])
    }
}

/// Exact ground point seen at a pixel through `lens` at `mount`, within `max_range_m`.
pub fn pixel_to_ground(
    lens: &Lens,
    mount: &CameraMount,
    u: f64,
    v: f64,
    max_range_m: f64,
) -> Option<Point2> {
    let ray = lens.unproject([u, v])?;
    mount.ray_to_ground(ray).filter(|p| p.norm() <= max_range_m)
}

/// Pixel at which a ground point appears, or `None` if the lens cannot see it.
pub fn ground_to_pixel(lens: &Lens, mount: &CameraMount, p: Point2) -> Option<[f64; 2]> {
    lens.project(mount.ray_to_point(p.x, p.y, 0.0))
}

/// A ground table from a lens model and mount: "no ground" above the horizon and beyond
/// `max_range_m` (far floor is imaged by too few pixels to be worth trusting).
pub fn ground_table_from_camera(
    lens: &Lens,
    mount: &CameraMount,
    image_width: usize,
    image_height: usize,
    spacing_px: usize,
    max_range_m: f64,
) -> Result<GroundTable> {
    lens.validate()?;
    mount.validate()?;
    if max_range_m.is_nan() || max_range_m <= 0.0 {
        return Err(invalid_option("max_range_m", "must be > 0"));
    }
    let mut table = GroundTable::from_fn(image_width, image_height, spacing_px, |u, v| {
        pixel_to_ground(lens, mount, u, v, max_range_m)
    })?;
    table.metadata.insert(
        "source".into(),
        serde_json::json!({ "camera_model": lens, "mount": mount, "max_range_m": max_range_m }),
    );
    Ok(table)
}

fn scale(a: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] * s, a[1] * s, a[2] * s]
}
fn add(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
#[path = "mount_tests.rs"]
mod tests;
