//! Unclamped evidence: beside its clamped i16 log-odds, a grid may keep, per cell, the plain
//! sum of every log-odds increment it received (i32, in the same units of 1/1000 nat).
//!
//! Why: the clamped value is a saturating walk, so it depends on the order of the
//! observations (a cell seen free 20 times then occupied 3 times is not the same as the other
//! way round), and two clamped maps cannot be combined exactly. The sum of increments is
//! order-free, so maps of the same building made separately (several robots, several days)
//! merge exactly: `merge(A, B) == merge(B, A) == A + B`, cell for cell, and equal to the
//! evidence of one grid that received both recordings' scans. The merged occupancy map is the
//! sum clamped once at the end ([`EvidenceRaster::clamped`]); a sequential run instead clamps
//! after every scan, which lets recent observations override old ones (a changing world).
//!
//! The layer is additive whatever the increments are (fixed per sensor today, per reading
//! later): each scan adds its own hit or miss to each cell it touches, at most once per scan.
//! Sums saturate at the i32 range (at least 134 000 observations of 16 nats in one cell).

use crate::error::{invalid_option, Error, Result};
use crate::grid::{CellRect, EvidenceTile, Grid, Tile, TILE_BITS, TILE_CELLS, TILE_SIZE};
use crate::grid_options::CellLimits;
use crate::pose::Point2;
use crate::raycast::CellIndex;

/// Most cells a merged raster may hold (2^28: 1 GiB of i32).
pub const MAX_RASTER_CELLS: usize = 1 << 28;

impl Grid {
    /// Starts keeping the evidence layer. Only on a grid that has not been written yet (the
    /// layer must hold every increment the clamped map received).
    pub fn keep_evidence(&mut self) -> Result<()> {
        if self.keeps_evidence {
            return Ok(());
        }
        if self.allocated > 0 {
            return Err(invalid_option(
                "keep_evidence",
                "evidence must be kept from the first update: this map already holds cells",
            ));
        }
        self.keeps_evidence = true;
        self.evidence.clear();
        self.evidence.resize_with(self.tiles.len(), || None);
        Ok(())
    }

    /// Whether the grid keeps the evidence layer.
    pub fn keeps_evidence(&self) -> bool {
        self.keeps_evidence
    }

    /// The summed increments of a cell [1/1000 nat] (0 if never observed or not kept).
    pub fn evidence(&self, c: CellIndex) -> i32 {
        let (tx, ty, local) = crate::grid::tile_of(c);
        self.dir_index(tx, ty)
            .and_then(|i| self.evidence.get(i))
            .and_then(|t| t.as_ref())
            .map_or(0, |t| t[local])
    }

    /// The grid tile and, if kept, the evidence tile at a directory index (both allocated).
    #[inline(always)]
    pub(crate) fn tile_and_evidence_mut(
        &mut self,
        dir_index: usize,
    ) -> (&mut Tile, Option<&mut EvidenceTile>) {
        let slot = &mut self.tiles[dir_index];
        if slot.is_none() {
            self.allocated += 1;
        }
        let tile = slot.get_or_insert_with(|| Box::new([0; TILE_CELLS]));
        let ev = if self.keeps_evidence {
            Some(&mut **self.evidence[dir_index].get_or_insert_with(|| Box::new([0; TILE_CELLS])))
        } else {
            None
        };
        (&mut **tile, ev)
    }

    /// The smallest rectangle holding every cell of non-zero evidence, `None` if there is none.
    pub fn evidence_rect(&self) -> Option<CellRect> {
        let mut rect: Option<CellRect> = None;
        for (i, tile) in self.evidence.iter().enumerate() {
            let Some(tile) = tile else { continue };
            let tx = self.dir_min.0 + (i % self.dir_w) as i32;
            let ty = self.dir_min.1 + (i / self.dir_w) as i32;
            for (k, _) in tile.iter().enumerate().filter(|(_, &v)| v != 0) {
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
        rect
    }

    /// The evidence of `rect`, row-major with row 0 at `rect.min.y` (as [`Grid::read_rect`]).
    pub fn read_evidence_rect(&self, rect: CellRect, out: &mut Vec<i32>) {
        out.clear();
        out.resize(rect.width() * rect.height(), 0);
        let w = rect.width();
        for (row, y) in (rect.min.y..rect.max.y).enumerate() {
            for (col, x) in (rect.min.x..rect.max.x).enumerate() {
                out[row * w + col] = self.evidence(CellIndex::new(x, y));
            }
        }
    }

    /// The evidence layer as a raster over `rect` (world-placed, ready to save or merge).
    pub fn evidence_raster(&self, rect: CellRect) -> EvidenceRaster {
        let mut values = Vec::new();
        self.read_evidence_rect(rect, &mut values);
        let s = self.cell_size_m();
        let o = self.origin_m();
        EvidenceRaster {
            cell_size_m: s,
            origin_m: Point2::new(
                o.x + s * f64::from(rect.min.x),
                o.y + s * f64::from(rect.min.y),
            ),
            width: rect.width(),
            height: rect.height(),
            values,
        }
    }

    /// The evidence directory re-laid for a directory grown to `w x h` tiles from `(x0, y0)`.
    pub(crate) fn moved_evidence(
        &mut self,
        x0: i32,
        y0: i32,
        w: usize,
        h: usize,
    ) -> Vec<Option<Box<EvidenceTile>>> {
        let mut out: Vec<Option<Box<EvidenceTile>>> = Vec::new();
        out.resize_with(w * h, || None);
        for (i, t) in self.evidence.drain(..).enumerate() {
            if let Some(t) = t {
                let tx = self.dir_min.0 + (i % self.dir_w) as i32;
                let ty = self.dir_min.1 + (i / self.dir_w) as i32;
                out[(ty - y0) as usize * w + (tx - x0) as usize] = Some(t);
            }
        }
        out
    }

    pub(crate) fn evidence_memory_bytes(&self) -> usize {
        self.evidence.iter().flatten().count() * std::mem::size_of::<EvidenceTile>()
            + self.evidence.capacity() * std::mem::size_of::<Option<Box<EvidenceTile>>>()
    }
}

/// Evidence on a world-placed rectangle of cells: `values[row * width + col]` is the cell
/// whose lower-left corner is `origin_m + cell_size_m * (col, row)` (row 0 the lowest y).
#[derive(Debug, Clone, PartialEq)]
pub struct EvidenceRaster {
    pub cell_size_m: f64,
    pub origin_m: Point2,
    pub width: usize,
    pub height: usize,
    /// Summed increments [1/1000 nat].
    pub values: Vec<i32>,
}

impl EvidenceRaster {
    fn check(&self, k: usize) -> Result<()> {
        if self.values.len() != self.width.saturating_mul(self.height) {
            return Err(Error::LengthMismatch(format!(
                "evidence map {k}: {} values for {} x {} cells",
                self.values.len(),
                self.width,
                self.height
            )));
        }
        let finite = self.cell_size_m.is_finite() && self.cell_size_m > 0.0;
        if !(finite && self.origin_m.x.is_finite() && self.origin_m.y.is_finite()) {
            return Err(Error::InvalidGeometry(format!(
                "evidence map {k}: cell size and origin must be finite (cell size > 0)"
            )));
        }
        Ok(())
    }

    /// The occupancy values of a map built from this evidence: each sum clamped once to the
    /// grid's bounds (what [`Grid::write_rect`] takes).
    pub fn clamped(&self, limits: CellLimits) -> Vec<i16> {
        self.values
            .iter()
            .map(|&v| v.clamp(i32::from(limits.clamp_min), i32::from(limits.clamp_max)) as i16)
            .collect()
    }
}

/// Sums evidence rasters cell for cell over the union of their extents. They must share the
/// cell size (relative difference <= 1e-9) and one cell lattice (origins a whole number of
/// cells apart, within 1e-6 cell); anything else is refused, never resampled. The result is
/// exact and independent of the order of `rasters`.
pub fn merge(rasters: &[EvidenceRaster]) -> Result<EvidenceRaster> {
    let first = rasters
        .first()
        .ok_or_else(|| Error::LengthMismatch("no evidence maps to merge".into()))?;
    let s = first.cell_size_m;
    let mut offsets = Vec::with_capacity(rasters.len());
    for (k, r) in rasters.iter().enumerate() {
        r.check(k)?;
        if (r.cell_size_m - s).abs() > 1e-9 * s {
            return Err(invalid_option(
                "cell_size_m",
                format!(
                    "evidence map {k} has {} m cells, map 0 has {} m cells: maps of different cell sizes do not merge",
                    r.cell_size_m, s
                ),
            ));
        }
        let du = (r.origin_m.x - first.origin_m.x) / s;
        let dv = (r.origin_m.y - first.origin_m.y) / s;
        let (iu, iv) = (du.round(), dv.round());
        if (du - iu).abs() > 1e-6 || (dv - iv).abs() > 1e-6 || iu.abs() > 1e9 || iv.abs() > 1e9 {
            return Err(Error::InvalidGeometry(format!(
                "evidence map {k} is not on map 0's cell lattice (origins {:.6} x {:.6} cells apart): maps must share a grid origin",
                du, dv
            )));
        }
        offsets.push((iu as i64, iv as i64));
    }
    let x0 = offsets.iter().map(|o| o.0).min().unwrap_or(0);
    let y0 = offsets.iter().map(|o| o.1).min().unwrap_or(0);
    let x1 = offsets
        .iter()
        .zip(rasters)
        .map(|(o, r)| o.0 + r.width as i64)
        .max()
        .unwrap_or(0);
    let y1 = offsets
        .iter()
        .zip(rasters)
        .map(|(o, r)| o.1 + r.height as i64)
        .max()
        .unwrap_or(0);
    let (w, h) = ((x1 - x0) as usize, (y1 - y0) as usize);
    if w.saturating_mul(h) > MAX_RASTER_CELLS {
        return Err(Error::OutOfBounds(format!(
            "the merged map would be {w} x {h} cells (more than {MAX_RASTER_CELLS}): are the maps in one frame?"
        )));
    }
    let mut sum = vec![0i64; w * h];
    for (o, r) in offsets.iter().zip(rasters) {
        let (cx, cy) = ((o.0 - x0) as usize, (o.1 - y0) as usize);
        for row in 0..r.height {
            let dst = &mut sum[(cy + row) * w + cx..(cy + row) * w + cx + r.width];
            let src = &r.values[row * r.width..(row + 1) * r.width];
            for (d, &v) in dst.iter_mut().zip(src) {
                *d += i64::from(v);
            }
        }
    }
    let values = sum
        .iter()
        .map(|&v| i32::try_from(v))
        .collect::<std::result::Result<Vec<i32>, _>>()
        .map_err(|_| Error::OutOfBounds("a merged cell's evidence exceeds the i32 range".into()))?;
    Ok(EvidenceRaster {
        cell_size_m: s,
        origin_m: Point2::new(
            first.origin_m.x + s * x0 as f64,
            first.origin_m.y + s * y0 as f64,
        ),
        width: w,
        height: h,
        values,
    })
}
