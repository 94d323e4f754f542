//! Questions obstacle avoidance asks a grid: is this place free, and how far is the nearest
//! obstacle.

use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::grid_options::Occupancy;
use crate::pose::Point2;
use crate::raycast::CellIndex;

impl Grid {
    /// What the thresholds say about the cell holding the world point `p` [m] (unknown
    /// outside the map); [`Error::InvalidGeometry`] if `p` is not finite.
    pub fn occupancy_at(&self, p: Point2) -> Result<Occupancy> {
        let c = self.cell_of(p).ok_or_else(|| {
            Error::InvalidGeometry(format!("point ({}, {}) must be finite", p.x, p.y))
        })?;
        Ok(if self.covers(c) {
            self.occupancy(c)
        } else {
            Occupancy::Unknown
        })
    }

    /// Distance [m] from the world point `p` to the nearest occupied cell (to the nearest
    /// point of its square; 0 inside one), or `None` if there is none within `max_m`.
    /// Cost grows with (max_m / cell size)^2 in the worst case.
    pub fn distance_to_occupied(&self, p: Point2, max_m: f64) -> Result<Option<f64>> {
        if !(max_m.is_finite() && max_m >= 0.0) {
            return Err(Error::InvalidOption {
                name: "max_distance_m",
                reason: format!("must be finite and >= 0, got {max_m}"),
            });
        }
        let c0 = self.cell_of(p).ok_or_else(|| {
            Error::InvalidGeometry(format!("point ({}, {}) must be finite", p.x, p.y))
        })?;
        let s = self.cell_size_m();
        let o = self.origin_m();
        let max_ring = (max_m / s).ceil() as i32 + 1;
        let mut best = f64::INFINITY;
        let limits = self.limits();
        for k in 0..=max_ring {
            // Every cell of ring k is at least (k - 1) cells away from p.
            if f64::from(k - 1) * s > best.min(max_m) {
                break;
            }
            let mut consider = |x: i32, y: i32| {
                let c = CellIndex::new(c0.x + x, c0.y + y);
                if self.covers(c) && self.get(c).0 >= limits.occupied_at {
                    let (x0, y0) = (o.x + s * f64::from(c.x), o.y + s * f64::from(c.y));
                    let dx = (x0 - p.x).max(p.x - (x0 + s)).max(0.0);
                    let dy = (y0 - p.y).max(p.y - (y0 + s)).max(0.0);
                    best = best.min(dx.hypot(dy));
                }
            };
            if k == 0 {
                consider(0, 0);
                continue;
            }
            for i in -k..=k {
                consider(i, -k);
                consider(i, k);
            }
            for j in -k + 1..k {
                consider(-k, j);
                consider(k, j);
            }
        }
        Ok((best <= max_m).then_some(best))
    }
}

#[cfg(test)]
#[path = "queries_tests.rs"]
mod tests;
