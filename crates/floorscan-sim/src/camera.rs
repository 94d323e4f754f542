//! The simulated camera: a lens model and mount from floorscan-core (the same ones a ground
//! table is built from), an image size, its place on the robot, and how it forms an image
//! (noise, blur, vignetting). [`CameraRays`] holds the per-pixel rays, computed once.
//!
//! Frames: the camera ground frame is the point on the floor below the optical centre, x along
//! the camera's heading, y left, z up. `robot_from_camera` places it on the robot base (a yaw
//! here is a pan of the camera). Tilt and roll belong to the [`CameraMount`].

use floorscan_core::mount::{ground_table_from_camera, pixel_to_ground};
use floorscan_core::{CameraMount, GroundTable, Lens, Point2, Pose2};
use serde::{Deserialize, Serialize};

use crate::error::{check_range, invalid_option, Result};
use crate::texture::Footprint;

/// How the sensor turns light into 8-bit grey values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Imaging {
    /// Standard deviation of the signal-independent (read) noise [DN], in [0, 50]. Default 1.5.
    pub read_noise_dn: f64,
    /// Shot noise: variance added per DN of signal [DN], in [0, 10]. Default 0.06 (about 2.4 DN
    /// of noise at 100 DN).
    pub shot_noise_gain: f64,
    /// Standard deviation of the optical blur [px], in [0, 10]; 0 disables it. Default 0.6.
    pub blur_sigma_px: f64,
    /// Brightness lost at the image corners relative to the centre, in [0, 1]. Default 0.35.
    pub vignetting: f64,
    /// Smooth edges between surfaces with four samples per edge pixel. Default true.
    pub antialias: bool,
}

impl Default for Imaging {
    fn default() -> Self {
        Self {
            read_noise_dn: 1.5,
            shot_noise_gain: 0.06,
            blur_sigma_px: 0.6,
            vignetting: 0.35,
            antialias: true,
        }
    }
}

impl Imaging {
    /// No noise, no blur, no vignetting, no anti-aliasing: the scene's radiance quantised.
    pub fn ideal() -> Self {
        Self {
            read_noise_dn: 0.0,
            shot_noise_gain: 0.0,
            blur_sigma_px: 0.0,
            vignetting: 0.0,
            antialias: false,
        }
    }

    pub fn validate(&self) -> Result<()> {
        check_range("read_noise_dn", self.read_noise_dn, 0.0, 50.0)?;
        check_range("shot_noise_gain", self.shot_noise_gain, 0.0, 10.0)?;
        check_range("blur_sigma_px", self.blur_sigma_px, 0.0, 10.0)?;
        check_range("vignetting", self.vignetting, 0.0, 1.0)
    }
}

/// A camera on the robot.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    pub lens: Lens,
    pub mount: CameraMount,
    /// Image width [px], 8..=8192. Default 320.
    pub width: usize,
    /// Image height [px], 8..=8192. Default 240.
    pub height: usize,
    /// Camera ground frame on the robot base [m, rad]. Default x = 0.12 m forward.
    pub robot_from_camera: Pose2,
    #[serde(default)]
    pub imaging: Imaging,
}

impl Default for Camera {
    fn default() -> Self {
        Camera::wide_angle(320, 240)
    }
}

impl Camera {
    /// The default camera at any resolution: a Kannala-Brandt fisheye of about 136 degrees
    /// horizontal field of view, 0.40 m above the floor, tilted down 0.6 rad so the floor just in
    /// front of the robot is at the bottom of the image (as on the paper's robot).
    pub fn wide_angle(width: usize, height: usize) -> Camera {
        let f = 135.0 * width as f64 / 320.0;
        Camera {
            lens: Lens::KannalaBrandt {
                fx: f,
                fy: f,
                cx: (width as f64 - 1.0) / 2.0,
                cy: (height as f64 - 1.0) / 2.0,
                k1: -0.012,
                k2: 0.002,
                k3: 0.0,
                k4: 0.0,
            },
            mount: CameraMount {
                height_m: 0.40,
                tilt_rad: 0.6,
                roll_rad: 0.0,
            },
            width,
            height,
            robot_from_camera: Pose2::new(0.12, 0.0, 0.0),
            imaging: Imaging::default(),
        }
    }

    pub fn validate(&self) -> Result<()> {
        self.lens.validate()?;
        self.mount.validate()?;
        self.imaging.validate()?;
        for (name, v) in [("width", self.width), ("height", self.height)] {
            if !(8..=8192).contains(&v) {
                return Err(invalid_option(
                    name,
                    format!("must be in 8..=8192 px, got {v}"),
                ));
            }
        }
        if !self.robot_from_camera.is_finite() {
            return Err(invalid_option("robot_from_camera", "must be finite"));
        }
        Ok(())
    }

    /// The exact ground point (camera ground frame) seen at pixel (u, v): floorscan-core's
    /// `pixel_to_ground` with this lens and mount, limited to `max_range_m`.
    pub fn pixel_to_ground(&self, u: f64, v: f64, max_range_m: f64) -> Option<Point2> {
        pixel_to_ground(&self.lens, &self.mount, u, v, max_range_m)
    }

    /// The exact ground table of this camera (for scoring calibrations).
    pub fn ground_table(&self, spacing_px: usize, max_range_m: f64) -> Result<GroundTable> {
        Ok(ground_table_from_camera(
            &self.lens,
            &self.mount,
            self.width,
            self.height,
            spacing_px,
            max_range_m,
        )?)
    }

    /// Ray direction (camera ground frame, unit length) through pixel (u, v), or `None`.
    pub fn ray(&self, u: f64, v: f64) -> Option<[f64; 3]> {
        let r = self.lens.unproject([u, v])?;
        let d = self.mount.ground_from_optical(r);
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        Some([d[0] / n, d[1] / n, d[2] / n])
    }
}

/// Per-pixel rays and constants of a camera, row-major (v outer).
#[derive(Debug, Clone)]
pub struct CameraRays {
    pub camera: Camera,
    /// Unit ray directions in the camera ground frame; NaN where the lens has no ray.
    pub dirs: Vec<[f64; 3]>,
    /// Angle subtended by one pixel [rad] (footprint at distance t is about t times this).
    pub pixel_angle: Vec<f32>,
    /// Vignetting gain in (0, 1].
    pub gain: Vec<f32>,
    /// Azimuth of each ray in the camera ground frame [rad], and the length of its horizontal
    /// part (for the clearance shortcut of the renderer).
    pub azimuth: Vec<f64>,
    pub horizontal: Vec<f64>,
    /// Footprint of each pixel on the floor [m] (it stretches along the ray as
    /// 1 / sqrt(sin(depression)) on average); meaningless for rays that miss the floor.
    pub floor_footprint: Vec<Footprint>,
    /// Where each ray meets the floor, `t` along its unit direction [m] (height / -d_z, the
    /// same in every pose: poses turn about the vertical); NaN for rays that do not go down.
    pub floor_t: Vec<f64>,
}

impl CameraRays {
    pub fn new(camera: Camera) -> Result<CameraRays> {
        camera.validate()?;
        let (w, h) = (camera.width, camera.height);
        let mut dirs = Vec::with_capacity(w * h);
        for v in 0..h {
            for u in 0..w {
                dirs.push(camera.ray(u as f64, v as f64).unwrap_or([f64::NAN; 3]));
            }
        }
        let mut pixel_angle = vec![0f32; w * h];
        for v in 0..h {
            for u in 0..w {
                let k = v * w + u;
                let nb = if u + 1 < w { k + 1 } else { k - 1 };
                let (a, b) = (dirs[k], dirs[nb]);
                let dot = (a[0] * b[0] + a[1] * b[1] + a[2] * b[2]).clamp(-1.0, 1.0);
                let angle = dot.acos();
                pixel_angle[k] = if angle.is_finite() {
                    angle as f32
                } else {
                    0.01
                };
            }
        }
        let (_, _, cx, cy) = camera.lens.intrinsics();
        let r_max = cx
            .max(w as f64 - 1.0 - cx)
            .hypot(cy.max(h as f64 - 1.0 - cy))
            .max(1.0);
        let vig = camera.imaging.vignetting;
        let mut gain = Vec::with_capacity(w * h);
        for v in 0..h {
            for u in 0..w {
                let r = (u as f64 - cx).hypot(v as f64 - cy) / r_max;
                gain.push((1.0 - vig * r * r) as f32);
            }
        }
        let azimuth = dirs.iter().map(|d| d[1].atan2(d[0])).collect();
        let horizontal = dirs.iter().map(|d| d[0].hypot(d[1])).collect();
        let height = camera.mount.height_m;
        let floor_footprint = dirs
            .iter()
            .zip(&pixel_angle)
            .map(|(d, a)| {
                let down = (-d[2]).max(0.02);
                Footprint::new(height / down * *a as f64 / down.sqrt())
            })
            .collect();
        // As Scene::limit computes it for a camera at this height.
        let floor_t = dirs
            .iter()
            .map(|d| {
                if d[2] < -1e-12 && height > 0.0 {
                    height / -d[2]
                } else {
                    f64::NAN
                }
            })
            .collect();
        Ok(CameraRays {
            camera,
            dirs,
            pixel_angle,
            gain,
            azimuth,
            horizontal,
            floor_footprint,
            floor_t,
        })
    }

    /// A ray between pixel centres (bilinear interpolation of the four neighbouring rays,
    /// renormalised): used for anti-aliasing samples only, never for ground truth.
    pub fn interpolated(&self, u: f64, v: f64) -> [f64; 3] {
        let (w, h) = (self.camera.width, self.camera.height);
        let u = u.clamp(0.0, (w - 1) as f64);
        let v = v.clamp(0.0, (h - 1) as f64);
        let (i, j) = ((u as usize).min(w - 2), (v as usize).min(h - 2));
        let (fu, fv) = (u - i as f64, v - j as f64);
        let k = j * w + i;
        let ds = [
            self.dirs[k],
            self.dirs[k + 1],
            self.dirs[k + w],
            self.dirs[k + w + 1],
        ];
        let ws = [
            (1.0 - fu) * (1.0 - fv),
            fu * (1.0 - fv),
            (1.0 - fu) * fv,
            fu * fv,
        ];
        let mut d = [0.0; 3];
        for (dd, ww) in ds.iter().zip(ws) {
            if dd[0].is_nan() {
                return self.dirs[(v.round() as usize) * w + u.round() as usize];
            }
            for c in 0..3 {
                d[c] += ww * dd[c];
            }
        }
        let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        [d[0] / n, d[1] / n, d[2] / n]
    }
}

/// Where the camera is: its optical centre and the rotation of its ground frame.
#[derive(Debug, Clone, Copy)]
pub struct CameraPlacement {
    pub origin: [f64; 3],
    pub cos_yaw: f64,
    pub sin_yaw: f64,
    /// world_from_camera (the camera ground frame in the world).
    pub world_from_camera: Pose2,
}

impl CameraPlacement {
    pub fn new(rays: &CameraRays, world_from_robot: Pose2) -> CameraPlacement {
        let wc = world_from_robot.compose(&rays.camera.robot_from_camera);
        let (s, c) = wc.yaw.sin_cos();
        CameraPlacement {
            origin: [wc.x, wc.y, rays.camera.mount.height_m],
            cos_yaw: c,
            sin_yaw: s,
            world_from_camera: wc,
        }
    }

    /// A camera-ground-frame direction rotated into the world.
    #[inline]
    pub fn to_world(&self, d: [f64; 3]) -> [f64; 3] {
        [
            self.cos_yaw * d[0] - self.sin_yaw * d[1],
            self.sin_yaw * d[0] + self.cos_yaw * d[1],
            d[2],
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_camera_sees_the_floor_at_the_bottom_and_the_horizon_near_the_top() {
        let cam = Camera::default();
        cam.validate().unwrap();
        let near = cam.pixel_to_ground(159.5, 239.0, 100.0).unwrap();
        assert!(near.x > 0.0 && near.x < 0.15, "bottom row sees {near:?}");
        assert!(
            cam.pixel_to_ground(159.5, 0.0, 1e9).is_none(),
            "top row sees the floor"
        );
        // The horizontal field of view is wide: a ray at the left edge is more than 60 degrees off.
        let left = cam.ray(0.0, 119.5).unwrap();
        assert!(left[1].atan2(left[0]) > 60f64.to_radians());
    }

    #[test]
    fn rays_agree_with_pixel_to_ground() {
        let rays = CameraRays::new(Camera::default()).unwrap();
        let cam = &rays.camera;
        for (u, v) in [(10usize, 230usize), (160, 200), (300, 150)] {
            let d = rays.dirs[v * cam.width + u];
            let t = cam.mount.height_m / -d[2];
            let g = cam.pixel_to_ground(u as f64, v as f64, 1e9).unwrap();
            assert!((t * d[0] - g.x).abs() < 1e-9 && (t * d[1] - g.y).abs() < 1e-9);
        }
    }

    #[test]
    fn invalid_cameras_are_errors() {
        let c = Camera {
            width: 2,
            ..Default::default()
        };
        assert!(c.validate().is_err());
        let c = Camera {
            imaging: Imaging {
                vignetting: 2.0,
                ..Imaging::default()
            },
            ..Default::default()
        };
        assert!(c.validate().is_err());
        let c = Camera {
            mount: CameraMount {
                height_m: -1.0,
                tilt_rad: 0.6,
                roll_rad: 0.0,
            },
            ..Default::default()
        };
        assert!(CameraRays::new(c).is_err());
    }
}
