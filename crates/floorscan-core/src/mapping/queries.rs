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
mod tests {
    use super::*;
    use crate::grid_options::GridOptions;
    use crate::log_odds::LogOdds;

    fn brute_force(g: &Grid, occupied: &[CellIndex], p: Point2) -> f64 {
        let s = g.cell_size_m();
        occupied
            .iter()
            .map(|c| {
                let (x0, y0) = (s * f64::from(c.x), s * f64::from(c.y));
                let dx = (x0 - p.x).max(p.x - (x0 + s)).max(0.0);
                let dy = (y0 - p.y).max(p.y - (y0 + s)).max(0.0);
                dx.hypot(dy)
            })
            .fold(f64::INFINITY, f64::min)
    }

    #[test]
    fn distance_matches_brute_force() {
        let mut g = Grid::new(GridOptions {
            cell_size_m: 0.1,
            ..Default::default()
        })
        .unwrap();
        let mut state = 12345u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 33) as f64 / (1u64 << 31) as f64
        };
        let mut occupied = Vec::new();
        for _ in 0..40 {
            let c = CellIndex::new((next() * 100.0) as i32 - 50, (next() * 100.0) as i32 - 50);
            g.set(c, LogOdds(3000)).unwrap();
            occupied.push(c);
            // Free and weakly occupied cells are not obstacles.
            g.set(CellIndex::new(c.x + 1, c.y), LogOdds(-2000)).unwrap();
            g.set(CellIndex::new(c.x, c.y + 1), LogOdds(100)).unwrap();
        }
        occupied.retain(|c| g.get(*c).0 == 3000);
        for _ in 0..300 {
            let p = Point2::new(next() * 12.0 - 6.0, next() * 12.0 - 6.0);
            let want = brute_force(&g, &occupied, p);
            let got = g.distance_to_occupied(p, 3.0).unwrap();
            if want <= 3.0 {
                assert!(
                    (got.unwrap() - want).abs() < 1e-12,
                    "{p:?}: {got:?} vs {want}"
                );
            } else {
                assert_eq!(got, None);
            }
        }
        assert_eq!(
            g.distance_to_occupied(g.cell_center(occupied[0]), 1.0)
                .unwrap(),
            Some(0.0)
        );
    }

    #[test]
    fn occupancy_and_bad_queries() {
        let mut g = Grid::new(GridOptions {
            cell_size_m: 1.0,
            ..Default::default()
        })
        .unwrap();
        g.set(CellIndex::new(0, 0), LogOdds(-1500)).unwrap();
        assert_eq!(
            g.occupancy_at(Point2::new(0.5, 0.5)).unwrap(),
            Occupancy::Free
        );
        assert_eq!(
            g.occupancy_at(Point2::new(5.5, 0.5)).unwrap(),
            Occupancy::Unknown
        );
        assert!(g.occupancy_at(Point2::new(f64::NAN, 0.5)).is_err());
        assert!(g
            .distance_to_occupied(Point2::new(0.0, 0.0), f64::NAN)
            .is_err());
        assert_eq!(
            g.distance_to_occupied(Point2::new(0.0, 0.0), 10.0).unwrap(),
            None
        );
    }
}
