//! A planar laser scan (the fields of `sensor_msgs/LaserScan`) and its rays.
//!
//! Range rules (REP 117): a range in `[range_min, range_max)` is a hit at that range, with free
//! space from the laser to it; `+inf` or a range `>= range_max` is no return: free space up to
//! `range_max`, nothing marked; `-inf` or a range below `range_min` is ignored (too close to
//! measure); NaN is an error (an undefined measurement must not silently clear space).

use crate::error::{invalid_option, Error, Result};
use crate::pose::{Point2, Pose2};
use crate::ray_update::Ray;

/// Beam directions in the laser frame [rad, counter-clockwise from x].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BeamAngles<'a> {
    /// Beam `i` points at `min_rad + i * increment_rad`.
    Uniform { min_rad: f64, increment_rad: f64 },
    /// One angle per beam.
    Explicit(&'a [f64]),
}

/// One scan: a range per beam [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LaserScan<'a> {
    pub ranges_m: &'a [f64],
    pub angles: BeamAngles<'a>,
    /// Shortest valid range [m], finite, >= 0.
    pub range_min_m: f64,
    /// Longest valid range [m], finite, > `range_min_m`: readings at or beyond it clear up to
    /// it and mark nothing.
    pub range_max_m: f64,
}

impl LaserScan<'_> {
    /// Checks the layout and every range; the error names the first bad beam.
    pub fn check(&self) -> Result<()> {
        if !(self.range_min_m.is_finite() && self.range_min_m >= 0.0) {
            return Err(invalid_option(
                "range_min_m",
                format!("must be finite and >= 0, got {}", self.range_min_m),
            ));
        }
        if !(self.range_max_m.is_finite() && self.range_max_m > self.range_min_m) {
            return Err(invalid_option(
                "range_max_m",
                format!("must be finite and > range_min_m, got {}", self.range_max_m),
            ));
        }
        match self.angles {
            BeamAngles::Uniform {
                min_rad,
                increment_rad,
            } => {
                if !(min_rad.is_finite() && increment_rad.is_finite()) {
                    return Err(Error::InvalidGeometry("beam angles must be finite".into()));
                }
            }
            BeamAngles::Explicit(a) => {
                if a.len() != self.ranges_m.len() {
                    return Err(Error::LengthMismatch(format!(
                        "{} ranges but {} angles",
                        self.ranges_m.len(),
                        a.len()
                    )));
                }
                if let Some(i) = a.iter().position(|v| !v.is_finite()) {
                    return Err(Error::InvalidGeometry(format!(
                        "beam {i}: angle {} is not finite",
                        a[i]
                    )));
                }
            }
        }
        if let Some(i) = self.ranges_m.iter().position(|r| r.is_nan()) {
            return Err(Error::InvalidGeometry(format!(
                "beam {i}: range is NaN (use +inf for no return)"
            )));
        }
        Ok(())
    }

    /// The angle of beam `i` [rad].
    pub fn angle(&self, i: usize) -> f64 {
        match self.angles {
            BeamAngles::Uniform {
                min_rad,
                increment_rad,
            } => min_rad + i as f64 * increment_rad,
            BeamAngles::Explicit(a) => a[i],
        }
    }

    /// Unit vectors of the beams in the laser frame, `(cos, sin)` of each angle.
    pub fn beam_directions(&self) -> Vec<(f64, f64)> {
        (0..self.ranges_m.len())
            .map(|i| self.angle(i).sin_cos())
            .map(|(s, c)| (c, s))
            .collect()
    }

    /// Appends this scan's rays, placed with `world_from_laser`.
    pub fn rays(&self, world_from_laser: &Pose2, out: &mut Vec<Ray>) -> Result<()> {
        self.check()?;
        self.rays_along(&self.beam_directions(), world_from_laser, out);
        Ok(())
    }

    /// [`Self::rays`] with the beam directions computed beforehand (scans sharing a layout);
    /// the scan must have passed [`Self::check`] and `directions` be its own.
    pub fn rays_along(
        &self,
        directions: &[(f64, f64)],
        world_from_laser: &Pose2,
        out: &mut Vec<Ray>,
    ) {
        let origin = world_from_laser.translation();
        let (sy, cy) = world_from_laser.yaw.sin_cos();
        for (&r, &(c, s)) in self.ranges_m.iter().zip(directions) {
            if r < self.range_min_m {
                continue;
            }
            let hit = r < self.range_max_m;
            let range = if hit { r } else { self.range_max_m };
            let (dx, dy) = (range * (cy * c - sy * s), range * (sy * c + cy * s));
            out.push(Ray {
                from: origin,
                to: Point2::new(origin.x + dx, origin.y + dy),
                hit,
            });
        }
    }
}

#[cfg(test)]
#[path = "laser_tests.rs"]
mod tests;
