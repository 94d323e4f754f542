//! A sonar reading (the paper's sonar head): one range over a beam of some width. The echo
//! comes from somewhere on the arc at that range, so every arc cell gets (weak) evidence of
//! occupancy, and the cone inside the arc is free.
//!
//! Range rules: `[0, range_max)` marks the arc and frees the cone; `+inf` or `>= range_max`
//! frees the cone up to `range_max` and marks nothing; `-inf` is ignored (too close); NaN and
//! negative ranges are errors.

use crate::error::{invalid_option, Error, Result};
use crate::pose::{Point2, Pose2};
use crate::ray_update::Ray;

/// One sonar reading, in the sonar's frame (beam centred on its x axis).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SonarReading {
    /// Measured range [m].
    pub range_m: f64,
    /// Full opening angle of the beam [rad], in (0, pi]. Typical Polaroid 6500 transducers:
    /// about 0.44 rad (25 deg).
    pub beam_width_rad: f64,
    /// Longest valid range [m], finite, > 0.
    pub range_max_m: f64,
}

impl SonarReading {
    pub fn check(&self) -> Result<()> {
        if !(self.beam_width_rad > 0.0 && self.beam_width_rad <= std::f64::consts::PI) {
            return Err(invalid_option(
                "beam_width_rad",
                format!("must be in (0, pi], got {}", self.beam_width_rad),
            ));
        }
        if !(self.range_max_m.is_finite() && self.range_max_m > 0.0) {
            return Err(invalid_option(
                "range_max_m",
                format!("must be finite and > 0, got {}", self.range_max_m),
            ));
        }
        if self.range_m.is_nan() || (self.range_m.is_finite() && self.range_m < 0.0) {
            return Err(Error::InvalidGeometry(format!(
                "sonar range must be >= 0 (+inf for no echo), got {}",
                self.range_m
            )));
        }
        Ok(())
    }

    /// Appends the rays of the beam placed with `world_from_sonar`: fanned across the beam so
    /// that neighbouring arc points are at most half a cell apart (`cell_size_m`), so the arc
    /// is continuous on the grid.
    pub fn rays(
        &self,
        world_from_sonar: &Pose2,
        cell_size_m: f64,
        out: &mut Vec<Ray>,
    ) -> Result<()> {
        self.check()?;
        if self.range_m == f64::NEG_INFINITY {
            return Ok(());
        }
        let hit = self.range_m < self.range_max_m;
        let range = self.range_m.min(self.range_max_m);
        let arc_m = range * self.beam_width_rad;
        let n = ((arc_m / (0.5 * cell_size_m)).ceil() as usize).clamp(1, 1 << 16) + 1;
        let origin = world_from_sonar.translation();
        for i in 0..n {
            let a = -0.5 * self.beam_width_rad + self.beam_width_rad * i as f64 / (n - 1) as f64;
            let (s, c) = a.sin_cos();
            let to = world_from_sonar.transform_point(Point2::new(range * c, range * s));
            out.push(Ray {
                from: origin,
                to,
                hit,
            });
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "sonar_tests.rs"]
mod tests;
