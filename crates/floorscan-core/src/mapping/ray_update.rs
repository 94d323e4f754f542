//! The update engine shared by every sensor: one batch of rays (one scan) into a grid, with
//! the once-per-scan rule.
//!
//! Contract: within one batch each cell changes at most once, and an occupied observation
//! wins over a free one in the same cell. Many rays cross the same cells near the sensor;
//! counting each crossing would weigh free space by the number of rays rather than by the
//! number of scans.
//!
//! How, without clearing anything per scan: every tile the batch touches gets a slot of
//! generation stamps (u16, one per cell) from a pool; a cell is updated only if its stamp is
//! not the current generation, and then stamped. Hits are applied first, so the free pass
//! finds their cells stamped and leaves them alone. The pool is only zeroed when the
//! generation counter wraps (every 65 535 batches).

use crate::branchless::free_update;
use crate::error::{Error, Result};
use crate::grid::EvidenceTile;
use crate::grid::{tile_of, Grid, Tile, TILE_BITS, TILE_CELLS, TILE_SIZE};
use crate::grid_options::RayWalk;
use crate::log_odds::Evidence;
use crate::pose::Point2;
use crate::raycast::{segment_fits, CellIndex, CellWalk, FixedPoint, GridWalk, SUBCELL};
use crate::thin_walk::ThinWalk;

/// One ray in world coordinates [m]: free space from `from` to `to`; if `hit`, the cell at
/// `to` is an obstacle (and is not counted free). A hit with `from == to` marks one cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub from: Point2,
    pub to: Point2,
    pub hit: bool,
}

/// What one batch did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct UpdateStats {
    /// Rays walked (after clipping to a fixed-bounds map).
    pub rays: u64,
    /// Cells visited by the walks, counting repeats (the work done).
    pub cells_traversed: u64,
    /// Cells marked occupied (each at most once per batch).
    pub cells_hit: u64,
}

impl std::ops::AddAssign for UpdateStats {
    fn add_assign(&mut self, o: UpdateStats) {
        self.rays += o.rays;
        self.cells_traversed += o.cells_traversed;
        self.cells_hit += o.cells_hit;
    }
}

const NO_SLOT: u32 = u32::MAX;

/// Reusable scratch memory of the engine (stamps, quantised rays, the per-batch tile table).
#[derive(Debug, Clone, Default)]
pub struct RayUpdater {
    generation: u16,
    /// Stamp slots, `TILE_CELLS` stamps each.
    pool: Vec<u16>,
    slots_used: usize,
    /// For each tile of the batch's tile rectangle: its stamp slot, or `NO_SLOT`.
    table: Vec<u32>,
    table_min: (i32, i32),
    table_w: usize,
    quantised: Vec<(FixedPoint, FixedPoint, bool)>,
}

impl RayUpdater {
    /// Bytes of scratch memory held (stamp pool and buffers).
    pub fn memory_bytes(&self) -> usize {
        self.pool.capacity() * 2
            + self.table.capacity() * 4
            + self.quantised.capacity() * std::mem::size_of::<(FixedPoint, FixedPoint, bool)>()
    }

    /// Applies one batch. Checks every ray first: on error the grid is unchanged.
    pub fn apply(
        &mut self,
        grid: &mut Grid,
        rays: &[Ray],
        evidence: Evidence,
    ) -> Result<UpdateStats> {
        self.quantise(grid, rays)?;
        let Some((lo, hi)) = self.cell_bounds() else {
            return Ok(UpdateStats::default());
        };
        grid.reserve_tiles(tile_of(lo), tile_of(hi), false)?;
        self.start_batch(tile_of(lo), tile_of(hi));
        let (hit, miss) = evidence.units();
        let limits = grid.limits();
        let (lo_v, hi_v) = (limits.clamp_min, limits.clamp_max);
        let generation = self.generation;
        let mut stats = UpdateStats {
            rays: self.quantised.len() as u64,
            ..Default::default()
        };

        // Hits first: an occupied observation wins over a free one.
        for k in 0..self.quantised.len() {
            let (_, to, is_hit) = self.quantised[k];
            if !is_hit {
                continue;
            }
            let (tile, evidence, stamps, local) = self.tile_and_stamps(grid, to.cell());
            if stamps[local] != generation {
                stamps[local] = generation;
                tile[local] = (tile[local] + hit).min(hi_v);
                if let Some(ev) = evidence {
                    ev[local] = ev[local].saturating_add(i32::from(hit));
                }
                stats.cells_hit += 1;
            }
        }

        // Then free space along every ray.
        let thin = grid.options().ray_walk == RayWalk::Thin;
        for k in 0..self.quantised.len() {
            let (from, to, _) = self.quantised[k];
            stats.cells_traversed += if thin {
                let walk = ThinWalk::new(from, to).expect("length checked when quantised");
                self.clear_along(grid, walk, generation, miss, lo_v)
            } else {
                let walk = GridWalk::new(from, to).expect("length checked when quantised");
                self.clear_along(grid, walk, generation, miss, lo_v)
            };
        }
        Ok(stats)
    }

    /// Applies the free update to every cell of one walk, tile by tile; returns the cells
    /// visited.
    #[inline(always)]
    fn clear_along<W: CellWalk>(
        &mut self,
        grid: &mut Grid,
        mut walk: W,
        generation: u16,
        miss: i16,
        lo_v: i16,
    ) -> u64 {
        let mut visited = 0;
        loop {
            let c = walk.cell();
            let (tx, ty, local) = tile_of(c);
            let min = CellIndex::new(tx << TILE_BITS, ty << TILE_BITS);
            let stop =
                walk.last_cell_inside(min, CellIndex::new(min.x + TILE_SIZE, min.y + TILE_SIZE));
            let (tile, evidence, stamps, _) = self.tile_and_stamps(grid, c);
            visited += match evidence {
                // No overflow: |values| and |miss| are at most 16 000 (log_odds).
                None => walk.run_to(stop, local, TILE_SIZE as usize, move |i| {
                    let i = i & (TILE_CELLS - 1);
                    tile[i] = free_update(tile[i], stamps[i], generation, miss, lo_v);
                    stamps[i] = generation;
                }),
                // The same, plus the unclamped sum (crate::evidence).
                Some(ev) => walk.run_to(stop, local, TILE_SIZE as usize, move |i| {
                    let i = i & (TILE_CELLS - 1);
                    let fresh = i32::from(stamps[i] != generation);
                    ev[i] = ev[i].saturating_add(fresh * i32::from(miss));
                    tile[i] = free_update(tile[i], stamps[i], generation, miss, lo_v);
                    stamps[i] = generation;
                }),
            };
            if walk.is_at_end() {
                return visited;
            }
            walk.step();
        }
    }

    /// Converts rays to fixed point, clipped to a fixed-bounds grid; refuses non-finite or
    /// over-long rays.
    fn quantise(&mut self, grid: &Grid, rays: &[Ray]) -> Result<()> {
        self.quantised.clear();
        let fixed = grid.fixed_cells();
        for (k, r) in rays.iter().enumerate() {
            let (a, b) = (grid.to_cells(r.from), grid.to_cells(r.to));
            if ![a.0, a.1, b.0, b.1].iter().all(|v| v.is_finite()) {
                return Err(Error::InvalidGeometry(format!(
                    "ray {k} has a non-finite end point"
                )));
            }
            let (a, b, hit) = match fixed {
                None => (a, b, r.hit),
                Some(rect) => {
                    let lo = (f64::from(rect.min.x), f64::from(rect.min.y));
                    // Stay one fixed-point unit inside the upper edges (cells are half-open).
                    let hi = (
                        f64::from(rect.max.x) - 1.0 / SUBCELL as f64,
                        f64::from(rect.max.y) - 1.0 / SUBCELL as f64,
                    );
                    match clip_segment(a, b, lo, hi) {
                        None => continue,
                        Some((a2, b2)) => (a2, b2, r.hit && b2 == b),
                    }
                }
            };
            let too_far =
                || Error::InvalidGeometry(format!("ray {k} ends too far from the map origin"));
            let mut fa = FixedPoint::from_cells(a.0, a.1).ok_or_else(too_far)?;
            let mut fb = FixedPoint::from_cells(b.0, b.1).ok_or_else(too_far)?;
            if let Some(rect) = fixed {
                // Rounding must not carry a clipped point out of the bounds.
                let clamp = |p: FixedPoint| {
                    FixedPoint::new(
                        p.x.clamp(
                            i64::from(rect.min.x) * SUBCELL,
                            i64::from(rect.max.x) * SUBCELL - 1,
                        ),
                        p.y.clamp(
                            i64::from(rect.min.y) * SUBCELL,
                            i64::from(rect.max.y) * SUBCELL - 1,
                        ),
                    )
                };
                fa = clamp(fa);
                fb = clamp(fb);
            }
            if !segment_fits(fa, fb) {
                let len_m = (r.to.x - r.from.x).hypot(r.to.y - r.from.y);
                return Err(Error::InvalidGeometry(format!(
                    "ray {k} is {len_m:.1} m long, more than {} cells",
                    crate::raycast::MAX_RAY_CELLS
                )));
            }
            self.quantised.push((fa, fb, hit));
        }
        Ok(())
    }

    fn cell_bounds(&self) -> Option<(CellIndex, CellIndex)> {
        let mut it = self
            .quantised
            .iter()
            .flat_map(|&(a, b, _)| [a.cell(), b.cell()]);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), c| {
            (
                CellIndex::new(lo.x.min(c.x), lo.y.min(c.y)),
                CellIndex::new(hi.x.max(c.x), hi.y.max(c.y)),
            )
        }))
    }

    fn start_batch(&mut self, lo: (i32, i32, usize), hi: (i32, i32, usize)) {
        self.generation = self.generation.wrapping_add(1);
        if self.generation == 0 {
            // Wrapped: old stamps could equal new generations. Zero them, once per 65 535.
            self.pool.fill(0);
            self.generation = 1;
        }
        self.slots_used = 0;
        self.table_min = (lo.0, lo.1);
        self.table_w = (hi.0 - lo.0 + 1) as usize;
        let h = (hi.1 - lo.1 + 1) as usize;
        self.table.clear();
        self.table.resize(self.table_w * h, NO_SLOT);
    }

    /// The grid tile holding `c` (allocated if new), its stamp slot, and `c`'s local index.
    #[inline(always)]
    fn tile_and_stamps<'a>(
        &'a mut self,
        grid: &'a mut Grid,
        c: CellIndex,
    ) -> (
        &'a mut Tile,
        Option<&'a mut EvidenceTile>,
        &'a mut [u16; TILE_CELLS],
        usize,
    ) {
        let (tx, ty, local) = tile_of(c);
        let t = (ty - self.table_min.1) as usize * self.table_w + (tx - self.table_min.0) as usize;
        if self.table[t] == NO_SLOT {
            self.assign_slot(t);
        }
        let s = self.table[t] as usize * TILE_CELLS;
        let stamps: &mut [u16; TILE_CELLS] = (&mut self.pool[s..s + TILE_CELLS])
            .try_into()
            .expect("slot size");
        let d = grid
            .dir_index(tx, ty)
            .expect("tiles reserved for the batch");
        let (tile, evidence) = grid.tile_and_evidence_mut(d);
        (tile, evidence, stamps, local)
    }

    /// Gives tile-table entry `t` the next stamp slot (first touch of a tile in this batch).
    #[cold]
    fn assign_slot(&mut self, t: usize) {
        if (self.slots_used + 1) * TILE_CELLS > self.pool.len() {
            self.pool.resize((self.slots_used + 1) * TILE_CELLS, 0);
        }
        self.table[t] = self.slots_used as u32;
        self.slots_used += 1;
    }
}

/// Clips the segment `a`-`b` (cell units) to the closed box `lo`..`hi` (Liang-Barsky); `None`
/// if it misses the box. End points inside the box are returned unchanged.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    lo: (f64, f64),
    hi: (f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - lo.0),
        (dx, hi.0 - a.0),
        (-dy, a.1 - lo.1),
        (dy, hi.1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
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
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}
