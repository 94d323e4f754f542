//! Illumination of the floor, precomputed on a raster (ambient light plus ceiling lights, each
//! falling off as a point source: (h^2 / (h^2 + d^2))^1.5), looked up bilinearly.
//! No shadows: rooms are lit by many lights and by indirect light, and the world's baseboards
//! already darken the foot of the walls.

use floorscan_core::Point2;

use crate::cell_memo::CellMemo;
use crate::geometry::Aabb;
use crate::rng::fast_floor;
use crate::world::Lighting;

/// Raster resolution of the light map [m].
pub const LIGHT_CELL_M: f64 = 0.1;
/// Most (cell, light) pairs the light map evaluates (a bound on its build time).
pub const MAX_LIGHT_EVALUATIONS: f64 = 4.0e8;

#[derive(Debug, Clone)]
pub struct LightMap {
    origin: Point2,
    nx: usize,
    inv_cell: f64,
    /// (nx - 1, ny - 1) as floats: the raster's extent in cells (a conversion per lookup
    /// otherwise).
    extent: (f64, f64),
    values: Vec<f32>,
    ambient: f32,
    /// Median illumination over the raster: the exposure reference.
    pub typical: f32,
}

impl LightMap {
    /// Illumination over `bounds`; the exposure reference is the median over `reference`.
    pub fn new(lighting: &Lighting, bounds: Aabb, reference: Aabb) -> LightMap {
        let mut cell = LIGHT_CELL_M;
        let (w, h) = (bounds.max.x - bounds.min.x, bounds.max.y - bounds.min.y);
        // At most 4 M cells and 4e8 light evaluations: a huge world, or one with a light grid
        // of thousands of lights, gets a coarser (still smooth) light map, never minutes of work.
        let lights = lighting.lights.len().max(1) as f64;
        while (w / cell) * (h / cell) > 4.0e6
            || (w / cell) * (h / cell) * lights > MAX_LIGHT_EVALUATIONS
        {
            cell *= 2.0;
        }
        let nx = (w / cell).ceil() as usize + 2;
        let ny = (h / cell).ceil() as usize + 2;
        let mut values = vec![lighting.ambient as f32; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let p = Point2::new(
                    bounds.min.x + i as f64 * cell,
                    bounds.min.y + j as f64 * cell,
                );
                values[j * nx + i] += illuminance(lighting, p) as f32;
            }
        }
        let mut sorted: Vec<f32> = (0..nx * ny)
            .filter(|k| {
                let p = Point2::new(
                    bounds.min.x + (k % nx) as f64 * cell,
                    bounds.min.y + (k / nx) as f64 * cell,
                );
                reference.contains(p)
            })
            .map(|k| values[k])
            .collect();
        if sorted.is_empty() {
            sorted.push(lighting.ambient as f32);
        }
        sorted.sort_by(f32::total_cmp);
        let typical = sorted[sorted.len() / 2].max(1e-6);
        LightMap {
            origin: bounds.min,
            nx,
            inv_cell: 1.0 / cell,
            extent: ((nx - 1) as f64, (ny - 1) as f64),
            values,
            ambient: lighting.ambient as f32,
            typical,
        }
    }

    /// Floor illuminance at `p` (ambient outside the raster).
    pub fn at(&self, p: Point2) -> f32 {
        self.at_cached(p, &mut CellMemo::default())
    }

    /// [`Self::at`], remembering the corner values of the last cell in `memo`.
    #[inline(always)]
    pub fn at_cached(&self, p: Point2, memo: &mut CellMemo<[f32; 4]>) -> f32 {
        let gx = (p.x - self.origin.x) * self.inv_cell;
        let gy = (p.y - self.origin.y) * self.inv_cell;
        let corners = match memo.get(gx, gy) {
            Some(corners) => corners,
            None => match self.enter(gx, gy, memo) {
                Some(corners) => corners,
                None => return self.ambient,
            },
        };
        // The fractions (gx - floor(gx)), (gy - floor(gy)), with the remembered floors.
        let (x0, y0) = memo.corner();
        let (fx, fy) = ((gx - x0) as f32, (gy - y0) as f32);
        let [t0, t1, b0, b1] = corners;
        let top = t0 + (t1 - t0) * fx;
        let bottom = b0 + (b1 - b0) * fx;
        top + (bottom - top) * fy
    }

    /// The corner values of the cell holding raster coordinates (gx, gy), remembered in `memo`;
    /// None outside the raster (out of line: the rarer path).
    #[inline(never)]
    fn enter(&self, gx: f64, gy: f64, memo: &mut CellMemo<[f32; 4]>) -> Option<[f32; 4]> {
        if !(gx >= 0.0 && gy >= 0.0 && gx < self.extent.0 && gy < self.extent.1) {
            return None;
        }
        // In range (checked above), so the fast floor is exact and non-negative.
        let (i, j) = (fast_floor(gx), fast_floor(gy));
        let k = j as usize * self.nx + i as usize;
        // The cell's two rows of two corners (one bounds check each).
        let (t, b) = (
            &self.values[k..k + 2],
            &self.values[k + self.nx..k + self.nx + 2],
        );
        let corners = [t[0], t[1], b[0], b[1]];
        memo.set(i, j, corners);
        Some(corners)
    }
}

/// Direct illuminance on the floor at `p` from the lights (no ambient).
pub fn illuminance(lighting: &Lighting, p: Point2) -> f64 {
    lighting
        .lights
        .iter()
        .map(|l| {
            let d2 = (p.x - l.position.x).powi(2) + (p.y - l.position.y).powi(2);
            let h2 = l.height_m * l.height_m;
            let r = h2 / (h2 + d2);
            l.power * r * r.sqrt()
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world::Light;

    #[test]
    fn light_map_matches_the_point_source_formula() {
        let lighting = Lighting {
            ambient: 0.3,
            lights: vec![Light {
                position: Point2::new(2.0, 1.0),
                height_m: 2.5,
                power: 0.8,
            }],
            exposure: 1.0,
            exposure_jitter: 0.0,
            wall_factor: 0.7,
            ceiling_brightness: 0.5,
        };
        let b = Aabb {
            min: Point2::new(0.0, 0.0),
            max: Point2::new(5.0, 4.0),
        };
        let m = LightMap::new(&lighting, b, b);
        // Right below the light: ambient + power.
        assert!((m.at(Point2::new(2.0, 1.0)) - 1.1).abs() < 1e-4);
        for p in [Point2::new(0.33, 0.71), Point2::new(4.2, 3.3)] {
            let exact = 0.3 + illuminance(&lighting, p);
            assert!((m.at(p) as f64 - exact).abs() < 2e-3, "{p:?}");
        }
        assert_eq!(m.at(Point2::new(-10.0, 0.0)), 0.3);
    }

    #[test]
    fn a_huge_world_with_a_light_grid_gets_a_bounded_light_map() {
        // Issue 12 fuzzing: a 2 km region in the lab world with its light grid took 38 s to
        // build. The work (cells x lights) is now bounded, whatever the world.
        let lights: Vec<Light> = (0..10_000)
            .map(|k| Light {
                position: Point2::new((k % 100) as f64 * 40.0, (k / 100) as f64 * 40.0),
                height_m: 2.5,
                power: 0.1,
            })
            .collect();
        let lighting = Lighting {
            ambient: 0.3,
            lights,
            exposure: 1.0,
            exposure_jitter: 0.0,
            wall_factor: 0.7,
            ceiling_brightness: 0.5,
        };
        let b = Aabb {
            min: Point2::new(-2000.0, -2000.0),
            max: Point2::new(2000.0, 2000.0),
        };
        let m = LightMap::new(&lighting, b, b);
        let evaluations = m.values.len() as f64 * lighting.lights.len() as f64;
        // The bound, plus the two border rows and columns of cells.
        assert!(evaluations <= MAX_LIGHT_EVALUATIONS * 1.1, "{evaluations}");
        assert!(m.at(Point2::new(0.0, 0.0)) >= 0.3);
    }
}
