//! The correlative scan matcher's persistent map of where its scans ended
//! (`floorscan.mapping.scan_matcher.ScanMatcher`): hit counts on a fixed `side` x `side` grid
//! (row major, row 0 = lowest y, cell (0, 0)'s corner at `origin_m`), and the likelihood field
//! cached over part of it, raised around each newly stored hit to its Gaussian stamp.
//!
//! Storing a scan: its points within `range_max_m` (robot frame) are moved by the pose onto
//! the grid; with `novel_only`, a point is stored only when no cell of the novelty disc around
//! its cell already holds a hit (every point is tested against the map as it was before this
//! scan, the disc cut at the grid's edges); counts saturate at 255. The discs' offsets (and
//! the stamp's values) are the caller's, made once.

use crate::error::{invalid_option, Error, Result};
use crate::pose::Pose2;

/// The largest grid side [cells] (the options' 400 m at 1 cm would be 40 000; they bound the
/// cells to 64 M, 8 000 squared).
pub const MAX_SIDE: usize = 1 << 16;

/// The most cells a disc (novelty or stamp) may hold.
pub const MAX_DISC_CELLS: usize = 1 << 20;

/// The most points one scan may store.
pub const MAX_POINTS: usize = 1 << 20;

/// The likelihood field cached over part of the grid: `width` x `height` values whose cell
/// (0, 0) is the grid's cell (`i0`, `j0`).
pub struct FieldMut<'a> {
    pub values: &'a mut [f32],
    pub width: usize,
    pub height: usize,
    pub i0: i64,
    pub j0: i64,
}

/// The grid's geometry and discs, and scratch space for one scan's cells.
#[derive(Debug, Clone)]
pub struct HitMap {
    side: usize,
    cell_m: f64,
    origin_m: (f64, f64),
    range_max_m: f64,
    novelty: Vec<(i64, i64)>,
    stamp: Vec<(i64, i64, f32)>,
    cells: Vec<(i64, i64)>,
}

impl HitMap {
    /// A grid of `side` x `side` cells of `cell_m` [m] from `origin_m`; points beyond
    /// `range_max_m` [m] are ignored; `novelty` the cell offsets (di, dj) of the novelty disc
    /// (empty: every point is new), `stamp` the offsets and values of the field's stamp.
    pub fn new(
        side: usize,
        cell_m: f64,
        origin_m: (f64, f64),
        range_max_m: f64,
        novelty: Vec<(i64, i64)>,
        stamp: Vec<(i64, i64, f32)>,
    ) -> Result<Self> {
        if !(1..=MAX_SIDE).contains(&side) {
            return Err(invalid_option(
                "side",
                format!("must be in 1..={MAX_SIDE}, got {side}"),
            ));
        }
        if !(cell_m.is_finite() && cell_m > 0.0) {
            return Err(invalid_option(
                "cell_size_m",
                format!("must be > 0, got {cell_m}"),
            ));
        }
        if !(origin_m.0.is_finite() && origin_m.1.is_finite()) {
            return Err(Error::InvalidGeometry("origin not finite".into()));
        }
        if range_max_m.is_nan() {
            return Err(invalid_option("range_max_m", "must be a number"));
        }
        if novelty.len() > MAX_DISC_CELLS || stamp.len() > MAX_DISC_CELLS {
            return Err(invalid_option(
                "disc",
                format!("more than {MAX_DISC_CELLS} cells"),
            ));
        }
        let bound = side as i64;
        if novelty
            .iter()
            .map(|&(a, b)| (a, b))
            .chain(stamp.iter().map(|&(a, b, _)| (a, b)))
            .any(|(a, b)| a.abs() > bound || b.abs() > bound)
        {
            return Err(invalid_option("disc", "offsets beyond the grid's side"));
        }
        Ok(Self {
            side,
            cell_m,
            origin_m,
            range_max_m,
            novelty,
            stamp,
            cells: Vec::new(),
        })
    }

    /// Stores the `points` [m, robot frame] seen from `pose` into `hits` (see the module's
    /// docs) and stamps the new hits into `field`; returns how many were stored.
    pub fn insert(
        &mut self,
        hits: &mut [u8],
        points: &[[f64; 2]],
        pose: Pose2,
        novel_only: bool,
        field: Option<FieldMut<'_>>,
    ) -> Result<usize> {
        let n = self.side;
        if hits.len() != n * n {
            return Err(Error::LengthMismatch(format!(
                "a {n} x {n} hit map needs {} cells, got {}",
                n * n,
                hits.len()
            )));
        }
        if points.len() > MAX_POINTS {
            return Err(Error::LengthMismatch(format!(
                "{} points > {MAX_POINTS}",
                points.len()
            )));
        }
        if let Some(f) = &field {
            if f.values.len() != f.width * f.height {
                return Err(Error::LengthMismatch(format!(
                    "field {} x {} needs {} values, got {}",
                    f.width,
                    f.height,
                    f.width * f.height,
                    f.values.len()
                )));
            }
        }
        let (c, s) = (pose.yaw.cos(), pose.yaw.sin());
        self.cells.clear();
        for p in points {
            if !(p[0].is_finite() && p[1].is_finite()) || p[0].hypot(p[1]) > self.range_max_m {
                continue;
            }
            let x = pose.x + c * p[0] - s * p[1];
            let y = pose.y + s * p[0] + c * p[1];
            let fi = ((x - self.origin_m.0) / self.cell_m).floor();
            let fj = ((y - self.origin_m.1) / self.cell_m).floor();
            if fi >= 0.0 && fi < n as f64 && fj >= 0.0 && fj < n as f64 {
                self.cells.push((fi as i64, fj as i64));
            }
        }
        if novel_only && !self.novelty.is_empty() {
            let last = n as i64 - 1;
            let novelty = &self.novelty;
            self.cells.retain(|&(i, j)| {
                !novelty.iter().any(|&(di, dj)| {
                    let (ii, jj) = ((i + di).clamp(0, last), (j + dj).clamp(0, last));
                    hits[jj as usize * n + ii as usize] > 0
                })
            });
        }
        if let Some(mut f) = field {
            for &(i, j) in &self.cells {
                self.stamp_at(&mut f, i, j);
            }
        }
        for &(i, j) in &self.cells {
            let k = j as usize * n + i as usize;
            hits[k] = hits[k].saturating_add(1);
        }
        Ok(self.cells.len())
    }

    /// Sets `field` to the likelihood field of the hits stored in `hits` over the field's
    /// cells alone: 0, raised around each cell holding a hit to the stamp. A field made afresh
    /// equals one kept up to date by [`Self::insert`]'s stamps except next to its border,
    /// where the kept one also holds the stamps of hits stored just outside it (as the
    /// distance transform of the field's cells alone did before).
    pub fn fill_field(&self, hits: &[u8], mut field: FieldMut<'_>) -> Result<()> {
        let n = self.side;
        if hits.len() != n * n || field.values.len() != field.width * field.height {
            return Err(Error::LengthMismatch(format!(
                "a {n} x {n} hit map and a {} x {} field, got {} and {} cells",
                field.width,
                field.height,
                hits.len(),
                field.values.len()
            )));
        }
        field.values.fill(0.0);
        let (i0, j0) = (field.i0.clamp(0, n as i64), field.j0.clamp(0, n as i64));
        let i1 = (field.i0.saturating_add(field.width as i64)).clamp(i0, n as i64);
        let j1 = (field.j0.saturating_add(field.height as i64)).clamp(j0, n as i64);
        for j in j0..j1 {
            let row = &hits[j as usize * n..(j as usize + 1) * n];
            for i in i0..i1 {
                if row[i as usize] > 0 {
                    self.stamp_at(&mut field, i, j);
                }
            }
        }
        Ok(())
    }

    /// Raises `field` to the stamp centred on grid cell (`i`, `j`) (NaN where either is NaN,
    /// as numpy's `maximum`).
    fn stamp_at(&self, f: &mut FieldMut<'_>, i: i64, j: i64) {
        let (w, h) = (f.width as i64, f.height as i64);
        for &(di, dj, v) in &self.stamp {
            let (ii, jj) = (i - f.i0 + di, j - f.j0 + dj);
            if ii >= 0 && ii < w && jj >= 0 && jj < h {
                let k = (jj * w + ii) as usize;
                let old = f.values[k];
                f.values[k] = if old.is_nan() || v.is_nan() {
                    f32::NAN
                } else if v > old {
                    v
                } else {
                    old
                };
            }
        }
    }
}

#[cfg(test)]
#[path = "hit_map_tests.rs"]
mod tests;
