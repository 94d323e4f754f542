//! The ground table read backwards: the pixel that sees a ground point, by Newton's method on
//! the table's own bilinear interpolation (no camera model, no pinhole: whatever lens the table
//! was calibrated for).

use crate::ground_table::GroundTable;
use crate::pose::Point2;

/// Step [px] of the finite differences of [`GroundTable::jacobian`].
const STEP_PX: f64 = 0.5;
/// Newton iterations of [`GroundTable::pixel_of`] (each reads one cell: the point and its
/// slopes, [`GroundTable::lookup_with_derivatives`]).
const ITERATIONS: usize = 8;
/// How near [m] the ground point of the pixel found must come to the one asked for.
const TOLERANCE_M: f64 = 1e-3;
/// Largest Newton step [px]: the table is bilinear per cell, so a far guess walks there.
const MAX_STEP_PX: f64 = 20.0;

/// The table's derivatives at a pixel: `[dx/du, dx/dv, dy/du, dy/dv]` [m/px].
pub type Jacobian = [f64; 4];

impl GroundTable {
    /// The ground point at pixel (u, v) and the table's derivatives there (forward
    /// differences of [`STEP_PX`], backward at the image's right and bottom edges); `None`
    /// where a point of the stencil has no ground.
    pub fn jacobian(&self, u: f64, v: f64) -> Option<(Point2, Jacobian)> {
        let p = self.lookup(u, v)?;
        let su = if u + STEP_PX <= (self.image_width() - 1) as f64 {
            STEP_PX
        } else {
            -STEP_PX
        };
        let sv = if v + STEP_PX <= (self.image_height() - 1) as f64 {
            STEP_PX
        } else {
            -STEP_PX
        };
        let pu = self.lookup(u + su, v)?;
        let pv = self.lookup(u, v + sv)?;
        Some((
            p,
            [
                (pu.x - p.x) / su,
                (pv.x - p.x) / sv,
                (pu.y - p.y) / su,
                (pv.y - p.y) / sv,
            ],
        ))
    }

    /// The pixel (u, v) whose ground point is `ground` [m], searched from `guess` (the nearer
    /// the faster; a pixel seeing a nearby point). `None` when the search leaves the table's
    /// ground or does not come within 1 mm (the point is not seen).
    pub fn pixel_of(&self, ground: Point2, guess: (f64, f64)) -> Option<(f64, f64)> {
        let max_u = (self.image_width() - 1) as f64;
        let max_v = (self.image_height() - 1) as f64;
        if !(guess.0.is_finite() && guess.1.is_finite()) {
            return None;
        }
        let (mut u, mut v) = (guess.0.clamp(0.0, max_u), guess.1.clamp(0.0, max_v));
        for _ in 0..ITERATIONS {
            let (p, [a, b, c, d]) = self.lookup_with_derivatives(u, v)?;
            let (ex, ey) = (ground.x - p.x, ground.y - p.y);
            // |e| < TOLERANCE_M / 100, squared (no libm call)
            if ex * ex + ey * ey < TOLERANCE_M * TOLERANCE_M * 1e-4 {
                return Some((u, v));
            }
            let det = a * d - b * c;
            if !(det.is_finite() && det.abs() > 1e-15) {
                return None;
            }
            let du = ((d * ex - b * ey) / det).clamp(-MAX_STEP_PX, MAX_STEP_PX);
            let dv = ((-c * ex + a * ey) / det).clamp(-MAX_STEP_PX, MAX_STEP_PX);
            u = (u + du).clamp(0.0, max_u);
            v = (v + dv).clamp(0.0, max_v);
        }
        let p = self.lookup(u, v)?;
        ((p.x - ground.x).hypot(p.y - ground.y) < TOLERANCE_M).then_some((u, v))
    }
}

#[cfg(test)]
#[path = "ground_table_inverse_tests.rs"]
mod tests;
