//! The ground table read backwards: the pixel that sees a ground point, by Newton's method on
//! the table's own bilinear interpolation (no camera model, no pinhole: whatever lens the table
//! was calibrated for).

use crate::ground_table::GroundTable;
use crate::pose::Point2;

/// Step [px] of the finite differences of [`GroundTable::jacobian`].
const STEP_PX: f64 = 0.5;
/// Newton iterations of [`GroundTable::pixel_of`] (each costs three lookups).
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
            let (p, [a, b, c, d]) = self.jacobian(u, v)?;
            let (ex, ey) = (ground.x - p.x, ground.y - p.y);
            if ex.hypot(ey) < TOLERANCE_M * 0.01 {
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
mod tests {
    use super::*;

    /// A pinhole camera 0.3 m above the floor, pitched 30 degrees down, 160 x 120: the ground
    /// point of each pixel in closed form.
    fn pinhole() -> (GroundTable, impl Fn(f64, f64) -> Option<Point2>) {
        let (f, cx, cy, h, pitch) = (120.0, 79.5, 59.5, 0.3, 30f64.to_radians());
        let ground = move |u: f64, v: f64| {
            // camera ray (x forward, y left, z up) for pixel (u, v)
            let (xc, yc, zc) = (1.0, -(u - cx) / f, -(v - cy) / f);
            let (s, c) = pitch.sin_cos();
            let dx = c * xc + s * zc;
            let dz = -s * xc + c * zc;
            (dz < -1e-6).then(|| {
                let t = h / -dz;
                Point2::new(t * dx, t * yc)
            })
        };
        let table = GroundTable::from_fn(160, 120, 4, &ground).unwrap();
        (table, ground)
    }

    #[test]
    fn pixel_of_inverts_the_table_to_a_fraction_of_a_pixel() {
        let (table, ground) = pinhole();
        let mut checked = 0;
        for v in (40..119).step_by(7) {
            for u in (2..157).step_by(9) {
                let (u, v) = (u as f64 + 0.37, v as f64 + 0.61);
                let Some(g) = table.lookup(u, v) else {
                    continue;
                };
                // the table agrees with the closed form, and its inverse finds the pixel back
                let exact = ground(u, v).unwrap();
                assert!((g.x - exact.x).hypot(g.y - exact.y) < 0.01 * exact.norm().max(0.1));
                let (pu, pv) = table
                    .pixel_of(g, (u + 6.0, v - 5.0))
                    .unwrap_or_else(|| panic!("{u} {v} {g:?} not found"));
                assert!(
                    (pu - u).abs() < 0.01 && (pv - v).abs() < 0.01,
                    "{u} {v}: {pu} {pv}"
                );
                checked += 1;
            }
        }
        assert!(checked > 50);
        // a point behind the camera is not seen
        assert!(table
            .pixel_of(Point2::new(-1.0, 0.0), (80.0, 100.0))
            .is_none());
    }
}
