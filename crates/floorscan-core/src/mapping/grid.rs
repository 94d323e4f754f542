//! Storage of an occupancy grid: i16 log-odds cells ([`crate::log_odds`]) in square tiles of
//! 128 x 128 cells allocated on demand, so a global map grows as the robot explores and costs
//! 2 bytes per cell of the tiles it touched; or fixed bounds on request.
//!
//! Geometry: cell `(i, j)` covers the world square `origin + cell_size * ([i, i+1) x [j, j+1))`
//! (x right, y up, REP 103). Cells never written hold 0 (p = 0.5, unknown).

use crate::error::{Error, Result};
use crate::grid_options::{CellLimits, GridOptions, Occupancy};
use crate::log_odds::LogOdds;
use crate::pose::Point2;
use crate::raycast::{CellIndex, FixedPoint};

/// log2 of the tile side.
pub const TILE_BITS: u32 = 7;
/// Tile side [cells].
pub const TILE_SIZE: i32 = 1 << TILE_BITS;
/// Cells per tile.
pub const TILE_CELLS: usize = 1 << (2 * TILE_BITS);
/// Most tile slots the directory may hold (2^24: 16 M tiles of 5.12 m at 4 cm, a square of
/// about 20 km; the directory then takes 128 MB).
pub const MAX_DIRECTORY_TILES: usize = 1 << 24;

/// One tile: row-major, `index = y_local * TILE_SIZE + x_local`.
pub type Tile = [i16; TILE_CELLS];

/// One tile of evidence, laid out as [`crate::grid::Tile`].
pub type EvidenceTile = [i32; TILE_CELLS];

/// A rectangle of cells, `min` included, `max` excluded.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CellRect {
    pub min: CellIndex,
    pub max: CellIndex,
}

impl CellRect {
    pub fn width(&self) -> usize {
        (self.max.x - self.min.x).max(0) as usize
    }
    pub fn height(&self) -> usize {
        (self.max.y - self.min.y).max(0) as usize
    }
    pub fn is_empty(&self) -> bool {
        self.width() == 0 || self.height() == 0
    }
    pub fn contains(&self, c: CellIndex) -> bool {
        c.x >= self.min.x && c.x < self.max.x && c.y >= self.min.y && c.y < self.max.y
    }
}

/// The tile holding a cell, and the cell's index inside it.
#[inline]
pub fn tile_of(c: CellIndex) -> (i32, i32, usize) {
    let (tx, ty) = (c.x >> TILE_BITS, c.y >> TILE_BITS);
    let local = (((c.y & (TILE_SIZE - 1)) << TILE_BITS) | (c.x & (TILE_SIZE - 1))) as usize;
    (tx, ty, local)
}

/// An occupancy grid of log-odds cells. Build with [`Grid::new`]; update with
/// [`crate::inserter::Inserter`].
#[derive(Clone)]
pub struct Grid {
    options: GridOptions,
    limits: CellLimits,
    /// Cells a fixed-bounds grid covers.
    fixed: Option<CellRect>,
    /// First tile of the directory, and its size [tiles].
    pub(crate) dir_min: (i32, i32),
    pub(crate) dir_w: usize,
    pub(crate) dir_h: usize,
    pub(crate) tiles: Vec<Option<Box<Tile>>>,
    pub(crate) allocated: usize,
    /// The unclamped evidence layer ([`crate::evidence`]), parallel to `tiles`; empty and
    /// off unless [`Grid::keep_evidence`] was called.
    pub(crate) evidence: Vec<Option<Box<EvidenceTile>>>,
    pub(crate) keeps_evidence: bool,
}

impl std::fmt::Debug for Grid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Grid")
            .field("cell_size_m", &self.options.cell_size_m)
            .field("fixed", &self.fixed)
            .field("allocated_tiles", &self.allocated)
            .finish()
    }
}

impl Grid {
    pub fn new(options: GridOptions) -> Result<Grid> {
        options.validate()?;
        let fixed = options.bounds_m.map(|b| {
            let lo = options.to_cells(b.min);
            let hi = options.to_cells(b.max);
            CellRect {
                min: CellIndex::new(lo.0.floor() as i32, lo.1.floor() as i32),
                max: CellIndex::new(hi.0.ceil() as i32, hi.1.ceil() as i32),
            }
        });
        if let Some(r) = fixed {
            check_cell_range(r, options.max_cells)?;
        }
        Grid::build(options, fixed)
    }

    /// A grid whose fixed bounds are exactly the cells `rect` (used by the local map, whose
    /// window sits on whole cells).
    pub fn with_cell_bounds(mut options: GridOptions, rect: CellRect) -> Result<Grid> {
        options.validate()?;
        if rect.is_empty() {
            return Err(Error::InvalidOption {
                name: "bounds_m",
                reason: "the window is empty".into(),
            });
        }
        check_cell_range(rect, options.max_cells)?;
        let s = options.cell_size_m;
        let o = options.origin_m;
        options.bounds_m = Some(crate::grid_options::Bounds {
            min: Point2::new(
                o.x + s * f64::from(rect.min.x),
                o.y + s * f64::from(rect.min.y),
            ),
            max: Point2::new(
                o.x + s * f64::from(rect.max.x),
                o.y + s * f64::from(rect.max.y),
            ),
        });
        Grid::build(options, Some(rect))
    }

    fn build(options: GridOptions, fixed: Option<CellRect>) -> Result<Grid> {
        let limits = options.limits();
        let mut grid = Grid {
            options,
            limits,
            fixed,
            dir_min: (0, 0),
            dir_w: 0,
            dir_h: 0,
            tiles: Vec::new(),
            allocated: 0,
            evidence: Vec::new(),
            keeps_evidence: false,
        };
        if let Some(r) = fixed {
            let max = CellIndex::new(r.max.x - 1, r.max.y - 1);
            grid.reserve_tiles(tile_of(r.min), tile_of(max), false)?;
        }
        Ok(grid)
    }

    pub fn options(&self) -> &GridOptions {
        &self.options
    }
    pub fn limits(&self) -> CellLimits {
        self.limits
    }
    pub fn cell_size_m(&self) -> f64 {
        self.options.cell_size_m
    }
    pub fn origin_m(&self) -> Point2 {
        self.options.origin_m
    }
    /// The cells of a fixed-bounds grid; `None` if the grid grows.
    pub fn fixed_cells(&self) -> Option<CellRect> {
        self.fixed
    }

    /// World point [m] to fractional cell units.
    pub fn to_cells(&self, p: Point2) -> (f64, f64) {
        self.options.to_cells(p)
    }

    /// The cell containing a world point [m], `None` if not finite or absurdly far.
    pub fn cell_of(&self, p: Point2) -> Option<CellIndex> {
        let (u, v) = self.to_cells(p);
        FixedPoint::from_cells(u, v).map(FixedPoint::cell)
    }

    /// World position [m] of a cell's centre.
    pub fn cell_center(&self, c: CellIndex) -> Point2 {
        let s = self.options.cell_size_m;
        let o = self.options.origin_m;
        Point2::new(
            o.x + s * (f64::from(c.x) + 0.5),
            o.y + s * (f64::from(c.y) + 0.5),
        )
    }

    /// Whether the grid may hold this cell (always true for a growing grid).
    pub fn covers(&self, c: CellIndex) -> bool {
        match self.fixed {
            Some(r) => r.contains(c),
            None => true,
        }
    }

    /// The stored value of a cell (0, unknown, for cells never written or outside the grid).
    pub fn get(&self, c: CellIndex) -> LogOdds {
        let (tx, ty, local) = tile_of(c);
        match self.dir_index(tx, ty) {
            Some(i) => LogOdds(self.tiles[i].as_ref().map_or(0, |t| t[local])),
            None => LogOdds(0),
        }
    }

    /// What the thresholds say about a cell.
    pub fn occupancy(&self, c: CellIndex) -> Occupancy {
        self.limits.classify(self.get(c).0)
    }

    /// Writes a cell, clamped to the grid's bounds; [`Error::OutOfBounds`] outside a
    /// fixed-bounds grid.
    pub fn set(&mut self, c: CellIndex, value: LogOdds) -> Result<()> {
        if !self.covers(c) {
            return Err(Error::OutOfBounds(format!(
                "cell ({}, {}) is outside the map",
                c.x, c.y
            )));
        }
        let v = value.0.clamp(self.limits.clamp_min, self.limits.clamp_max);
        let (tx, ty, local) = tile_of(c);
        let i = self.reserve_tiles((tx, ty, 0), (tx, ty, 0), true)?;
        self.tile_mut(i)[local] = v;
        Ok(())
    }

    /// Tiles allocated so far.
    pub fn allocated_tiles(&self) -> usize {
        self.allocated
    }

    /// Bytes held by the grid: cell storage plus the tile directory.
    pub fn memory_bytes(&self) -> usize {
        self.allocated * std::mem::size_of::<Tile>()
            + self.tiles.capacity() * std::mem::size_of::<Option<Box<Tile>>>()
            + self.evidence_memory_bytes()
    }

    /// The smallest rectangle holding every cell with a non-zero value, `None` if all are 0.
    pub fn known_rect(&self) -> Option<CellRect> {
        let mut rect: Option<CellRect> = None;
        for (i, tile) in self.tiles.iter().enumerate() {
            let Some(tile) = tile else { continue };
            let tx = self.dir_min.0 + (i % self.dir_w) as i32;
            let ty = self.dir_min.1 + (i / self.dir_w) as i32;
            for (k, &v) in tile.iter().enumerate() {
                if v != 0 {
                    let c = CellIndex::new(
                        (tx << TILE_BITS) + (k & (TILE_SIZE as usize - 1)) as i32,
                        (ty << TILE_BITS) + (k >> TILE_BITS) as i32,
                    );
                    let r = rect.get_or_insert(CellRect {
                        min: c,
                        max: CellIndex::new(c.x + 1, c.y + 1),
                    });
                    r.min = CellIndex::new(r.min.x.min(c.x), r.min.y.min(c.y));
                    r.max = CellIndex::new(r.max.x.max(c.x + 1), r.max.y.max(c.y + 1));
                }
            }
        }
        rect
    }

    /// The rectangle exported by default: the fixed bounds, or the known cells of a growing
    /// grid (an empty rectangle if nothing is known).
    pub fn extent(&self) -> CellRect {
        self.fixed
            .or_else(|| self.known_rect())
            .unwrap_or(CellRect {
                min: CellIndex::default(),
                max: CellIndex::default(),
            })
    }

    /// The rectangle of `width` x `height` cells whose first cell is (`min_x`, `min_y`),
    /// checked: every corner within [`crate::raycast::MAX_CELL_INDEX`] of the lattice origin
    /// and at most [`GridOptions::max_cells`] cells ([`Error::OutOfBounds`] otherwise), so that
    /// reading or writing it allocates a bounded amount.
    pub fn checked_rect(
        &self,
        min_x: i64,
        min_y: i64,
        width: u64,
        height: u64,
    ) -> Result<CellRect> {
        let limit = crate::raycast::MAX_CELL_INDEX;
        let far = |v: i64| v.checked_abs().is_none_or(|a| a >= limit);
        let (w, h) = (i64::try_from(width), i64::try_from(height));
        let (Ok(w), Ok(h)) = (w, h) else {
            return Err(Error::OutOfBounds(format!(
                "a {width} x {height} rectangle is too large"
            )));
        };
        let (max_x, max_y) = (min_x.saturating_add(w), min_y.saturating_add(h));
        if [min_x, min_y, max_x, max_y].into_iter().any(far) {
            return Err(Error::OutOfBounds(format!(
                "cells ({min_x}, {min_y}) to ({max_x}, {max_y}) are more than 2^30 cells from the map origin"
            )));
        }
        let cells = width.saturating_mul(height);
        if cells > self.options.max_cells {
            return Err(Error::OutOfBounds(format!(
                "a {width} x {height} rectangle holds {cells} cells, more than max_cells = {} (raise it to read or write more at once)",
                self.options.max_cells
            )));
        }
        Ok(CellRect {
            min: CellIndex::new(min_x as i32, min_y as i32),
            max: CellIndex::new(max_x as i32, max_y as i32),
        })
    }

    /// The values of `rect`, row-major with row 0 at `rect.min.y` (the lowest y, as in
    /// `nav_msgs/OccupancyGrid`).
    pub fn read_rect(&self, rect: CellRect, out: &mut Vec<i16>) {
        out.clear();
        out.resize(rect.width() * rect.height(), 0);
        let w = rect.width();
        for (row, y) in (rect.min.y..rect.max.y).enumerate() {
            let mut x = rect.min.x;
            while x < rect.max.x {
                // Copy the part of this row that lies in one tile at once.
                let (tx, ty, local) = tile_of(CellIndex::new(x, y));
                let run = ((tx + 1) * TILE_SIZE).min(rect.max.x) - x;
                if let Some(Some(tile)) = self.dir_index(tx, ty).map(|i| &self.tiles[i]) {
                    let start = row * w + (x - rect.min.x) as usize;
                    out[start..start + run as usize]
                        .copy_from_slice(&tile[local..local + run as usize]);
                }
                x += run;
            }
        }
    }

    /// Writes `values` (laid out as [`Grid::read_rect`] returns them) into `rect`, clamped.
    /// Tiles that would stay all zero are not allocated.
    pub fn write_rect(&mut self, rect: CellRect, values: &[i16]) -> Result<()> {
        if values.len() != rect.width() * rect.height() {
            return Err(Error::LengthMismatch(format!(
                "{} values for a {} x {} rectangle",
                values.len(),
                rect.width(),
                rect.height()
            )));
        }
        if let Some(f) = self.fixed {
            let inside = rect.is_empty()
                || (f.contains(rect.min)
                    && f.contains(CellIndex::new(rect.max.x - 1, rect.max.y - 1)));
            if !inside {
                return Err(Error::OutOfBounds(
                    "the rectangle is not inside the map's fixed bounds".into(),
                ));
            }
        }
        let w = rect.width();
        for (row, y) in (rect.min.y..rect.max.y).enumerate() {
            for (col, x) in (rect.min.x..rect.max.x).enumerate() {
                let v = values[row * w + col];
                let c = CellIndex::new(x, y);
                if v != 0 || self.get(c).0 != 0 {
                    self.set(c, LogOdds(v))?;
                }
            }
        }
        Ok(())
    }
}

fn check_cell_range(r: CellRect, max_cells: u64) -> Result<()> {
    let limit = crate::raycast::MAX_CELL_INDEX;
    let ok = [r.min.x, r.min.y, r.max.x, r.max.y]
        .iter()
        .all(|&v| i64::from(v).abs() < limit);
    let tiles = (r.width() >> TILE_BITS)
        .saturating_add(2)
        .saturating_mul((r.height() >> TILE_BITS).saturating_add(2));
    let cells = (r.width() as u64).saturating_mul(r.height() as u64);
    if !ok || tiles > MAX_DIRECTORY_TILES || cells > max_cells {
        return Err(Error::InvalidOption {
            name: "bounds_m",
            reason: format!(
                "the bounds hold {} x {} cells, more than max_cells = {max_cells} (raise max_cells, or use larger cells)",
                r.width(),
                r.height()
            ),
        });
    }
    Ok(())
}

impl GridOptions {
    /// World point [m] to fractional cell units of this lattice.
    pub fn to_cells(&self, p: Point2) -> (f64, f64) {
        let inv = 1.0 / self.cell_size_m;
        ((p.x - self.origin_m.x) * inv, (p.y - self.origin_m.y) * inv)
    }
}

#[path = "grid_tiles.rs"]
mod tiles;
