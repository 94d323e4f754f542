//! A uniform 2-D grid over the world that lists, per cell, the items overlapping it (compressed
//! rows: one offsets array and one flat item array), and the cell walk of a ray's ground track
//! (Amanatides & Woo). The renderer tests only the items of the cells a ray crosses.

use floorscan_core::Point2;

use crate::geometry::Aabb;
use crate::rng::fast_floor;

/// Cell geometry of a uniform grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridShape {
    pub origin: Point2,
    pub cell_m: f64,
    pub nx: usize,
    pub ny: usize,
}

impl GridShape {
    /// A grid covering `bounds` with square cells of `cell_m`, at most `max_cells` cells (the
    /// cells grow if needed).
    pub fn covering(bounds: Aabb, cell_m: f64, max_cells: usize) -> GridShape {
        let w = (bounds.max.x - bounds.min.x).max(1e-6);
        let h = (bounds.max.y - bounds.min.y).max(1e-6);
        let mut cell = cell_m;
        while (w / cell).ceil() * (h / cell).ceil() > max_cells as f64 {
            cell *= 1.5;
        }
        GridShape {
            origin: bounds.min,
            cell_m: cell,
            nx: ((w / cell).ceil() as usize).max(1),
            ny: ((h / cell).ceil() as usize).max(1),
        }
    }

    pub fn cell_count(&self) -> usize {
        self.nx * self.ny
    }

    /// Cell (i, j) containing p, if inside.
    #[inline]
    pub fn cell_of(&self, p: Point2) -> Option<(usize, usize)> {
        let fx = (p.x - self.origin.x) / self.cell_m;
        let fy = (p.y - self.origin.y) / self.cell_m;
        if fx >= 0.0 && fy >= 0.0 && fx < self.nx as f64 && fy < self.ny as f64 {
            Some((fx as usize, fy as usize))
        } else {
            None
        }
    }

    pub fn bounds(&self) -> Aabb {
        Aabb {
            min: self.origin,
            max: Point2::new(
                self.origin.x + self.nx as f64 * self.cell_m,
                self.origin.y + self.ny as f64 * self.cell_m,
            ),
        }
    }

    /// Cells whose square overlaps the box (clamped to the grid).
    pub fn cells_overlapping(&self, b: Aabb) -> impl Iterator<Item = (usize, usize)> {
        let c = self.cell_m;
        let lo_x = (((b.min.x - self.origin.x) / c).floor().max(0.0) as usize).min(self.nx - 1);
        let lo_y = (((b.min.y - self.origin.y) / c).floor().max(0.0) as usize).min(self.ny - 1);
        let hi_x = (((b.max.x - self.origin.x) / c).floor().max(0.0) as usize).min(self.nx - 1);
        let hi_y = (((b.max.y - self.origin.y) / c).floor().max(0.0) as usize).min(self.ny - 1);
        (lo_y..=hi_y).flat_map(move |j| (lo_x..=hi_x).map(move |i| (i, j)))
    }
}

/// Per-cell item lists in compressed rows.
#[derive(Debug, Clone)]
pub struct CellLists {
    offsets: Vec<u32>,
    items: Vec<u32>,
}

impl CellLists {
    /// From (cell index, item) pairs; items keep their insertion order within a cell.
    pub fn build(cell_count: usize, pairs: &[(usize, u32)]) -> CellLists {
        let mut counts = vec![0u32; cell_count + 1];
        for &(c, _) in pairs {
            counts[c + 1] += 1;
        }
        for k in 0..cell_count {
            counts[k + 1] += counts[k];
        }
        let mut fill = counts.clone();
        let mut items = vec![0u32; pairs.len()];
        for &(c, it) in pairs {
            items[fill[c] as usize] = it;
            fill[c] += 1;
        }
        CellLists {
            offsets: counts,
            items,
        }
    }

    #[inline]
    pub fn get(&self, cell: usize) -> &[u32] {
        &self.items[self.offsets[cell] as usize..self.offsets[cell + 1] as usize]
    }
}

/// The walk of a ray's ground track through the grid: yields each cell with the ray parameter
/// at which the track leaves it. `t` is the ray's own parameter (the ground track moves by
/// `d` per unit t), so the 3-D ray and its track share it.
pub struct CellWalk {
    i: i64,
    j: i64,
    step_i: i64,
    step_j: i64,
    t_max_x: f64,
    t_max_y: f64,
    t_delta_x: f64,
    t_delta_y: f64,
    nx: i64,
    ny: i64,
    done: bool,
}

impl CellWalk {
    /// Starts at the cell containing `o` (or where the track enters the grid).
    pub fn new(shape: &GridShape, o: Point2, d: Point2) -> CellWalk {
        CellWalk::starting_at(shape, o, d, 0.0)
    }

    /// Starts at the cell containing `o + t0 d` (t0 >= 0), for a track known to meet nothing
    /// before t0; exit parameters still count from `o`.
    pub fn starting_at(shape: &GridShape, o: Point2, d: Point2, t0: f64) -> CellWalk {
        let c = shape.cell_m;
        let inside = shape
            .cell_of(Point2::new(o.x + t0 * d.x, o.y + t0 * d.y))
            .is_some();
        // Entry into the grid box (slab test), unless the track starts inside.
        let mut t_start: f64 = t0;
        let mut t_end = f64::INFINITY;
        if !inside {
            let b = shape.bounds();
            for (oo, dd, lo, hi) in [(o.x, d.x, b.min.x, b.max.x), (o.y, d.y, b.min.y, b.max.y)] {
                if dd.abs() < 1e-300 {
                    if oo < lo || oo >= hi {
                        t_end = -1.0;
                    }
                } else {
                    let (t0, t1) = ((lo - oo) / dd, (hi - oo) / dd);
                    t_start = t_start.max(t0.min(t1));
                    t_end = t_end.min(t0.max(t1));
                }
            }
        }
        let mut walk = CellWalk {
            i: 0,
            j: 0,
            step_i: 0,
            step_j: 0,
            t_max_x: f64::INFINITY,
            t_max_y: f64::INFINITY,
            t_delta_x: f64::INFINITY,
            t_delta_y: f64::INFINITY,
            nx: shape.nx as i64,
            ny: shape.ny as i64,
            done: t_end < t_start,
        };
        if walk.done {
            return walk;
        }
        let px = o.x + t_start * d.x;
        let py = o.y + t_start * d.y;
        walk.i = fast_floor((px - shape.origin.x) / c).clamp(0, walk.nx - 1);
        walk.j = fast_floor((py - shape.origin.y) / c).clamp(0, walk.ny - 1);
        if d.x > 0.0 {
            walk.step_i = 1;
            walk.t_delta_x = c / d.x;
            walk.t_max_x = (shape.origin.x + (walk.i + 1) as f64 * c - o.x) / d.x;
        } else if d.x < 0.0 {
            walk.step_i = -1;
            walk.t_delta_x = -c / d.x;
            walk.t_max_x = (shape.origin.x + walk.i as f64 * c - o.x) / d.x;
        }
        if d.y > 0.0 {
            walk.step_j = 1;
            walk.t_delta_y = c / d.y;
            walk.t_max_y = (shape.origin.y + (walk.j + 1) as f64 * c - o.y) / d.y;
        } else if d.y < 0.0 {
            walk.step_j = -1;
            walk.t_delta_y = -c / d.y;
            walk.t_max_y = (shape.origin.y + walk.j as f64 * c - o.y) / d.y;
        }
        walk
    }

    /// The next cell index (j * nx + i) and the parameter at which the track leaves it.
    #[inline]
    pub fn next_cell(&mut self) -> Option<(usize, f64)> {
        if self.done {
            return None;
        }
        let cell = (self.j * self.nx + self.i) as usize;
        let t_exit;
        if self.t_max_x < self.t_max_y {
            t_exit = self.t_max_x;
            self.t_max_x += self.t_delta_x;
            self.i += self.step_i;
            if self.i < 0 || self.i >= self.nx {
                self.done = true;
            }
        } else {
            t_exit = self.t_max_y;
            self.t_max_y += self.t_delta_y;
            self.j += self.step_j;
            if self.j < 0 || self.j >= self.ny {
                self.done = true;
            }
        }
        if !t_exit.is_finite() {
            self.done = true;
        }
        Some((cell, t_exit))
    }
}

/// Whether the segment a-b meets the box (Liang-Barsky clipping).
pub fn segment_meets_box(a: Point2, b: Point2, bx: Aabb) -> bool {
    let d = Point2::new(b.x - a.x, b.y - a.y);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-d.x, a.x - bx.min.x),
        (d.x, bx.max.x - a.x),
        (-d.y, a.y - bx.min.y),
        (d.y, bx.max.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    t0 <= t1
}

/// Cells touched by the segment a-b (every cell the segment passes through or grazes; cells
/// are padded by a hair so that a segment on a cell border registers on both sides).
pub fn segment_cells(shape: &GridShape, a: Point2, b: Point2) -> Vec<(usize, usize)> {
    let pad = 1e-9 * shape.cell_m;
    let c = shape.cell_m;
    shape
        .cells_overlapping(Aabb::of_points(&[a, b]))
        .filter(|&(i, j)| {
            let lo = Point2::new(
                shape.origin.x + i as f64 * c - pad,
                shape.origin.y + j as f64 * c - pad,
            );
            let hi = Point2::new(lo.x + c + 2.0 * pad, lo.y + c + 2.0 * pad);
            segment_meets_box(a, b, Aabb { min: lo, max: hi })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape() -> GridShape {
        GridShape {
            origin: Point2::new(0.0, 0.0),
            cell_m: 1.0,
            nx: 10,
            ny: 10,
        }
    }

    #[test]
    fn walk_visits_the_cells_of_a_diagonal_in_order() {
        let mut w = CellWalk::new(&shape(), Point2::new(0.5, 0.5), Point2::new(1.0, 0.5));
        let mut cells = vec![];
        while let Some((c, t)) = w.next_cell() {
            cells.push((c % 10, c / 10, t));
        }
        assert_eq!(cells[0].0, 0);
        assert_eq!((cells[1].0, cells[1].1), (1, 0));
        assert_eq!((cells[2].0, cells[2].1), (1, 1));
        assert_eq!(cells.last().unwrap().0, 9);
        assert!((cells[0].2 - 0.5).abs() < 1e-12);
    }

    #[test]
    fn walk_from_outside_enters_the_grid() {
        let mut w = CellWalk::new(&shape(), Point2::new(-5.0, 2.5), Point2::new(1.0, 0.0));
        let (c, _) = w.next_cell().unwrap();
        assert_eq!((c % 10, c / 10), (0, 2));
        let mut miss = CellWalk::new(&shape(), Point2::new(-5.0, 20.0), Point2::new(1.0, 0.0));
        assert!(miss.next_cell().is_none());
    }

    #[test]
    fn segment_cells_match_brute_force_sampling() {
        let s = shape();
        let (a, b) = (Point2::new(0.3, 0.7), Point2::new(7.9, 4.2));
        let cells = segment_cells(&s, a, b);
        for k in 0..=10_000 {
            let t = k as f64 / 10_000.0;
            let p = Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y));
            let c = s.cell_of(p).unwrap();
            assert!(cells.contains(&c), "{c:?} missing");
        }
        assert!(cells.len() <= 14, "{}", cells.len());
    }

    #[test]
    fn cell_lists_keep_items_per_cell() {
        let l = CellLists::build(3, &[(2, 7), (0, 1), (2, 9)]);
        assert_eq!(l.get(0), &[1]);
        assert!(l.get(1).is_empty());
        assert_eq!(l.get(2), &[7, 9]);
    }
}
