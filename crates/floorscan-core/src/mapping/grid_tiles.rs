//! The grid's tile storage: the directory of tiles grown to cover what is written (within
//! the options' cell limits), tiles reserved ahead of a write, and their lookup.

use super::*;

impl Grid {
    /// Makes the directory cover tiles `a..=b` (tile coordinates, local parts ignored),
    /// growing it geometrically; returns the directory index of `a`. With `allocate`, the tile
    /// at `a` is allocated too. Fails (changing nothing) past [`MAX_DIRECTORY_TILES`].
    pub(crate) fn reserve_tiles(
        &mut self,
        a: (i32, i32, usize),
        b: (i32, i32, usize),
        allocate: bool,
    ) -> Result<usize> {
        let (x0, y0) = (a.0.min(b.0), a.1.min(b.1));
        let (x1, y1) = (a.0.max(b.0), a.1.max(b.1));
        let covered = self.dir_w > 0
            && x0 >= self.dir_min.0
            && y0 >= self.dir_min.1
            && x1 < self.dir_min.0 + self.dir_w as i32
            && y1 < self.dir_min.1 + self.dir_h as i32;
        if !covered {
            self.grow_directory(x0, y0, x1, y1)?;
        }
        let i = self.dir_index(a.0, a.1).expect("covered after growing");
        if allocate {
            self.tile_mut(i);
        }
        Ok(i)
    }

    pub(super) fn grow_directory(&mut self, x0: i32, y0: i32, x1: i32, y1: i32) -> Result<()> {
        let (mut nx0, mut ny0, mut nx1, mut ny1) = (x0, y0, x1, y1);
        if self.dir_w > 0 {
            nx0 = nx0.min(self.dir_min.0);
            ny0 = ny0.min(self.dir_min.1);
            nx1 = nx1.max(self.dir_min.0 + self.dir_w as i32 - 1);
            ny1 = ny1.max(self.dir_min.1 + self.dir_h as i32 - 1);
        }
        let tiles_of = |x0: i32, y0: i32, x1: i32, y1: i32| {
            ((i64::from(x1) - i64::from(x0) + 1) as u64)
                .saturating_mul((i64::from(y1) - i64::from(y0) + 1) as u64)
        };
        let max_tiles = (self.options.max_cells / TILE_CELLS as u64).max(1);
        let needed = tiles_of(nx0, ny0, nx1, ny1);
        if self.fixed.is_none() && needed > max_tiles {
            let s = self.options.cell_size_m * f64::from(TILE_SIZE);
            return Err(Error::OutOfBounds(format!(
                "the map would span {:.0} m x {:.0} m ({} cells, more than max_cells = {}): is a pose wrong? (raise [map] max_cells for a larger site)",
                s * (f64::from(nx1) - f64::from(nx0) + 1.0),
                s * (f64::from(ny1) - f64::from(ny0) + 1.0),
                needed.saturating_mul(TILE_CELLS as u64),
                self.options.max_cells
            )));
        }
        if self.dir_w > 0 && self.fixed.is_none() {
            // Grow with slack on the sides that grew, so that exploring costs amortised O(1)
            // (as long as the slack keeps within max_cells).
            let (cx1, cy1) = (
                self.dir_min.0 + self.dir_w as i32 - 1,
                self.dir_min.1 + self.dir_h as i32 - 1,
            );
            let (sx, sy) = (
                (self.dir_w as i32 / 2).max(4),
                (self.dir_h as i32 / 2).max(4),
            );
            let mut slack = (nx0, ny0, nx1, ny1);
            if nx0 < self.dir_min.0 {
                slack.0 -= sx;
            }
            if ny0 < self.dir_min.1 {
                slack.1 -= sy;
            }
            if nx1 > cx1 {
                slack.2 += sx;
            }
            if ny1 > cy1 {
                slack.3 += sy;
            }
            if tiles_of(slack.0, slack.1, slack.2, slack.3) <= max_tiles {
                (nx0, ny0, nx1, ny1) = slack;
            }
        }
        let (w, h) = ((nx1 - nx0 + 1) as usize, (ny1 - ny0 + 1) as usize);
        if w.saturating_mul(h) > MAX_DIRECTORY_TILES {
            return Err(Error::OutOfBounds(format!(
                "the map would span {} x {} tiles of {} cells (more than {} tiles): is a pose wrong?",
                w, h, TILE_SIZE, MAX_DIRECTORY_TILES
            )));
        }
        let mut tiles: Vec<Option<Box<Tile>>> = Vec::new();
        tiles.resize_with(w * h, || None);
        for (i, t) in self.tiles.drain(..).enumerate() {
            if let Some(t) = t {
                let tx = self.dir_min.0 + (i % self.dir_w) as i32;
                let ty = self.dir_min.1 + (i / self.dir_w) as i32;
                tiles[(ty - ny0) as usize * w + (tx - nx0) as usize] = Some(t);
            }
        }
        self.tiles = tiles;
        if self.keeps_evidence {
            self.evidence = self.moved_evidence(nx0, ny0, w, h);
        }
        self.dir_min = (nx0, ny0);
        self.dir_w = w;
        self.dir_h = h;
        Ok(())
    }

    /// Directory index of a tile, `None` outside the directory.
    #[inline]
    pub(crate) fn dir_index(&self, tx: i32, ty: i32) -> Option<usize> {
        let (dx, dy) = (
            tx.wrapping_sub(self.dir_min.0),
            ty.wrapping_sub(self.dir_min.1),
        );
        ((dx as u32 as usize) < self.dir_w && (dy as u32 as usize) < self.dir_h)
            .then(|| dy as usize * self.dir_w + dx as usize)
    }

    /// The tile at a directory index, allocated (all zero) on first use.
    #[inline]
    pub(crate) fn tile_mut(&mut self, dir_index: usize) -> &mut Tile {
        let slot = &mut self.tiles[dir_index];
        if slot.is_none() {
            self.allocated += 1;
        }
        slot.get_or_insert_with(|| Box::new([0; TILE_CELLS]))
    }
}
