//! Exact integer grid walk: every cell a segment passes through, in order (Amanatides & Woo's
//! traversal in exact integer arithmetic).
//!
//! Positions are in grid fixed point ([`FixedPoint`]: cell units times [`SUBCELL`]). Cell
//! `(i, j)` is the half-open square `[i, i+1) x [j, j+1)` in cell units, so every point belongs
//! to exactly one cell, and the walk visits exactly `{ cell(p) : p on the closed segment }`,
//! each cell once, from `cell(start)` to `cell(end)`. Where the segment passes exactly through
//! a lattice corner, the half-open convention decides which of the corner's cells the corner
//! point itself is in (tested against a brute-force reference in exact rational arithmetic).
//!
//! How: a crossing of the x line `X` happens at time `t = (X - x0) / dx`; comparing two crossing
//! times is comparing two integer products. Entering a cell in the -x direction happens just
//! *after* the point reaches the line (the line belongs to the cell being left), so crossing
//! times are doubled and biased by one for negative directions: equal biased times (a corner
//! crossed in the same sense on both axes) step diagonally, and the order is exact otherwise.

/// Fractional bits of [`FixedPoint`]: 1/1024 of a cell (0.04 mm at 4 cm cells).
pub const SUBCELL_BITS: u32 = 10;
/// Fixed-point units per cell.
pub const SUBCELL: i64 = 1 << SUBCELL_BITS;
/// Longest segment the walk accepts, per axis [cells] (keeps every product inside i64).
pub const MAX_RAY_CELLS: i64 = 1 << 16;
/// Largest cell index magnitude accepted (positions beyond this are rejected upstream).
pub const MAX_CELL_INDEX: i64 = 1 << 30;

/// Index of a cell on the lattice: cell (i, j) covers `[i, i+1) x [j, j+1)` in cell units.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Default)]
pub struct CellIndex {
    pub x: i32,
    pub y: i32,
}

impl CellIndex {
    pub const fn new(x: i32, y: i32) -> Self {
        Self { x, y }
    }
}

/// A position in grid fixed point: cell units times [`SUBCELL`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub struct FixedPoint {
    pub x: i64,
    pub y: i64,
}

impl FixedPoint {
    pub const fn new(x: i64, y: i64) -> Self {
        Self { x, y }
    }

    /// From a position in (fractional) cell units, rounded to the nearest unit (halves up).
    /// `None` if not finite or farther than [`MAX_CELL_INDEX`] cells from the lattice origin.
    #[inline]
    pub fn from_cells(u: f64, v: f64) -> Option<FixedPoint> {
        let limit = MAX_CELL_INDEX as f64;
        if !(u.abs() < limit && v.abs() < limit) {
            return None; // also NaN
        }
        let s = SUBCELL as f64;
        Some(FixedPoint::new(round_half_up(u * s), round_half_up(v * s)))
    }

    /// The cell containing the point (floor of each coordinate).
    pub fn cell(self) -> CellIndex {
        CellIndex::new(
            (self.x >> SUBCELL_BITS) as i32,
            (self.y >> SUBCELL_BITS) as i32,
        )
    }
}

/// `floor(v + 0.5)` for |v| < 2^52, without a libm call (`f64::round` is one on baseline
/// x86-64).
#[inline]
fn round_half_up(v: f64) -> i64 {
    let w = v + 0.5;
    let t = w as i64; // towards zero
    t - i64::from((t as f64) > w)
}

/// Whether a segment's extent fits the walk ([`MAX_RAY_CELLS`] per axis).
#[inline]
pub fn segment_fits(start: FixedPoint, end: FixedPoint) -> bool {
    (end.x - start.x).abs() < MAX_RAY_CELLS * SUBCELL
        && (end.y - start.y).abs() < MAX_RAY_CELLS * SUBCELL
}

/// Whether `c` lies in the half-open box `[min, max)`.
#[inline]
pub(crate) fn inside(c: CellIndex, min: CellIndex, max: CellIndex) -> bool {
    c.x >= min.x && c.x < max.x && c.y >= min.y && c.y < max.y
}

/// Why a segment cannot be walked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayTooLong;

/// The crossing clock of a segment, shared by the exact walk and the thin one
/// ([`crate::thin_walk`]): the start and end cells, the step directions (-1, 0, 1), the biased
/// time of the first x / y crossing (`i64::MAX` if the axis never steps) and the biased time
/// between two crossings of each axis.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Clock {
    pub start: CellIndex,
    pub end: CellIndex,
    pub step_x: i32,
    pub step_y: i32,
    pub t_x: i64,
    pub t_y: i64,
    pub dt_x: i64,
    pub dt_y: i64,
}

impl Clock {
    #[inline]
    pub fn new(start: FixedPoint, end: FixedPoint) -> Result<Clock, RayTooLong> {
        if !segment_fits(start, end) {
            return Err(RayTooLong);
        }
        let (dx, dy) = (end.x - start.x, end.y - start.y);
        let (adx, ady) = (dx.abs(), dy.abs());
        let (c0, c1) = (start.cell(), end.cell());
        // Distance [units] from the start to the first line crossed, per axis; times are
        // scaled by 2 * adx * ady so that both axes share one integer clock.
        let first = |p: i64, c: i32, d: i64| {
            if d > 0 {
                (i64::from(c) + 1) * SUBCELL - p
            } else {
                p - i64::from(c) * SUBCELL
            }
        };
        let (t_x, dt_x) = if dx == 0 {
            (i64::MAX, 0)
        } else {
            (
                2 * first(start.x, c0.x, dx) * ady + i64::from(dx < 0),
                2 * SUBCELL * ady,
            )
        };
        let (t_y, dt_y) = if dy == 0 {
            (i64::MAX, 0)
        } else {
            (
                2 * first(start.y, c0.y, dy) * adx + i64::from(dy < 0),
                2 * SUBCELL * adx,
            )
        };
        Ok(Clock {
            start: c0,
            end: c1,
            step_x: dx.signum() as i32,
            step_y: dy.signum() as i32,
            t_x,
            t_y,
            dt_x,
            dt_y,
        })
    }
}

/// The state of an exact walk from `cell(start)` to `cell(end)`.
#[derive(Debug, Clone)]
pub struct GridWalk {
    cell: CellIndex,
    end: CellIndex,
    step_x: i32,
    step_y: i32,
    /// Biased time of the next x / y crossing (`i64::MAX` if the axis never steps).
    t_x: i64,
    t_y: i64,
    /// Biased time between two x / y crossings.
    dt_x: i64,
    dt_y: i64,
    /// No lattice corner lies on the segment's line, so the walk never steps diagonally and
    /// [`GridWalk::run_to`] may use its one-decision loop.
    corner_free: bool,
}

impl GridWalk {
    /// The walk along the segment from `start` to `end`; [`RayTooLong`] if it spans more than
    /// [`MAX_RAY_CELLS`] cells on an axis.
    pub fn new(start: FixedPoint, end: FixedPoint) -> Result<GridWalk, RayTooLong> {
        let clock = Clock::new(start, end)?;
        let (dx, dy) = (end.x - start.x, end.y - start.y);
        let c0 = clock.start;
        // A lattice point (1024 i, 1024 j) relative to the start cell lies on the line only if
        // 1024 (dy i - dx j) = dy x0 - dx y0 (x0, y0: the start inside its cell, in units).
        let (x0, y0) = (
            start.x - i64::from(c0.x) * SUBCELL,
            start.y - i64::from(c0.y) * SUBCELL,
        );
        let corner_free = dx == 0 || dy == 0 || (dy * x0 - dx * y0) % SUBCELL != 0;
        Ok(GridWalk {
            corner_free,
            cell: c0,
            end: clock.end,
            step_x: clock.step_x,
            step_y: clock.step_y,
            t_x: clock.t_x,
            t_y: clock.t_y,
            dt_x: clock.dt_x,
            dt_y: clock.dt_y,
        })
    }

    /// The last cell of the walk.
    pub fn end(&self) -> CellIndex {
        self.end
    }
}

impl CellWalk for GridWalk {
    /// The current cell.
    fn cell(&self) -> CellIndex {
        self.cell
    }

    fn is_at_end(&self) -> bool {
        self.cell == self.end
    }

    /// Moves to the next cell (must not be at the end).
    #[inline]
    fn step(&mut self) {
        let (sx, sy) = (self.t_x <= self.t_y, self.t_y <= self.t_x);
        if sx {
            self.t_x += self.dt_x;
            self.cell.x += self.step_x;
        }
        if sy {
            self.t_y += self.dt_y;
            self.cell.y += self.step_y;
        }
    }

    /// The last cell the walk visits before it leaves the half-open box `[min, max)` (cells),
    /// or the end cell if it ends inside. The current cell must be inside the box.
    fn last_cell_inside(&self, min: CellIndex, max: CellIndex) -> CellIndex {
        if inside(self.end, min, max) {
            return self.end; // the walk is monotone on each axis and the box convex
        }
        let rem_x = i64::from((self.end.x - self.cell.x).abs());
        let rem_y = i64::from((self.end.y - self.cell.y).abs());
        // Crossings needed to leave the box on each axis, if the walk gets that far.
        let exit = crossings_to_leave;
        let exit_x = exit(self.step_x, self.cell.x, min.x, max.x, rem_x)
            .map(|n| (n, self.t_x + (n - 1) * self.dt_x));
        let exit_y = exit(self.step_y, self.cell.y, min.y, max.y, rem_y)
            .map(|n| (n, self.t_y + (n - 1) * self.dt_y));
        // Crossings of one axis strictly before time `t_exit` happen inside the box.
        let before = |t: i64, dt: i64, rem: i64, t_exit: i64| -> i64 {
            if dt == 0 || t >= t_exit {
                0
            } else {
                ((t_exit - t - 1) / dt + 1).min(rem)
            }
        };
        // The axis that leaves first took all its crossings but the last: one division at most.
        let (nx, ny) = match (exit_x, exit_y) {
            (None, None) => return self.end,
            (Some((n, a)), None) => (n - 1, before(self.t_y, self.dt_y, rem_y, a)),
            (None, Some((n, b))) => (before(self.t_x, self.dt_x, rem_x, b), n - 1),
            (Some((n, a)), Some((m, b))) => match a.cmp(&b) {
                std::cmp::Ordering::Less => (n - 1, before(self.t_y, self.dt_y, rem_y, a)),
                std::cmp::Ordering::Greater => (before(self.t_x, self.dt_x, rem_x, b), m - 1),
                std::cmp::Ordering::Equal => (n - 1, m - 1),
            },
        };
        CellIndex::new(
            self.cell.x + self.step_x * nx as i32,
            self.cell.y + self.step_y * ny as i32,
        )
    }

    /// Walks from the current cell to `stop` (a later cell of the walk, or the current one),
    /// calling `visit` with the storage index of every cell, both ends included; returns the
    /// number of cells visited. `index` is the current cell's index in the caller's row-major
    /// storage of row length `row_stride`; the cells up to `stop` must all lie in that storage.
    ///
    /// The hot loop of map updates: no bounds checks and no branch but the loop's own (the
    /// axis order is data, not predictable, so it is chosen with masks). A walk that cannot
    /// meet a lattice corner (all but about one ray in a thousand) needs one decision per cell.
    #[inline(always)]
    fn run_to(
        &mut self,
        stop: CellIndex,
        index: usize,
        row_stride: usize,
        mut visit: impl FnMut(usize),
    ) -> u64 {
        let stride = row_stride as isize;
        let step_ix = self.step_x as isize;
        let step_iy = self.step_y as isize * stride;
        let (nx, ny) = ((stop.x - self.cell.x).abs(), (stop.y - self.cell.y).abs());
        let mut idx = index as isize;
        let stop_idx =
            idx + (stop.x - self.cell.x) as isize + (stop.y - self.cell.y) as isize * stride;
        let (dt_x, dt_y) = (self.dt_x, self.dt_y);
        let visited;
        if self.corner_free {
            // e = t_x - t_y is never 0: x steps when e < 0, y steps when e > 0.
            let mut e = self.t_x - self.t_y;
            let (dt_sum, step_diff) = (dt_x + dt_y, step_ix - step_iy);
            loop {
                visit(idx as usize);
                if idx == stop_idx {
                    break;
                }
                let m = e >> 63; // all ones iff x steps
                e = e - dt_y + (m & dt_sum);
                idx += step_iy + (m as isize & step_diff);
            }
            visited = u64::from(nx.unsigned_abs() + ny.unsigned_abs()) + 1;
            self.t_x += i64::from(nx) * dt_x;
            self.t_y += i64::from(ny) * dt_y;
        } else {
            let (mut t_x, mut t_y) = (self.t_x, self.t_y);
            let mut n = 0u64;
            loop {
                visit(idx as usize);
                n += 1;
                if idx == stop_idx {
                    break;
                }
                let d = t_x - t_y;
                let mx = (d - 1) >> 63; // all ones iff t_x <= t_y
                let my = !(d >> 63); // all ones iff t_y <= t_x
                t_x += mx & dt_x;
                t_y += my & dt_y;
                idx += (mx as isize & step_ix) + (my as isize & step_iy);
            }
            visited = n;
            self.t_x = t_x;
            self.t_y = t_y;
        }
        self.cell = stop;
        visited
    }
}

/// A walk over the cells of a segment, in order, that map updates run tile by tile: the exact
/// [`GridWalk`] and the thin [`crate::thin_walk::ThinWalk`].
pub trait CellWalk {
    /// The current cell.
    fn cell(&self) -> CellIndex;
    /// Whether the current cell is the last.
    fn is_at_end(&self) -> bool;
    /// Moves to the next cell (must not be at the end).
    fn step(&mut self);
    /// The last cell the walk visits before it leaves the half-open box `[min, max)` (cells),
    /// or the end cell if it ends inside. The current cell must be inside the box.
    fn last_cell_inside(&self, min: CellIndex, max: CellIndex) -> CellIndex;
    /// Walks from the current cell to `stop` (a later cell of the walk, or the current one),
    /// calling `visit` with the storage index of every cell, both ends included; returns the
    /// number of cells visited. `index` is the current cell's index in the caller's row-major
    /// storage of row length `row_stride`; the cells up to `stop` must all lie in that storage.
    fn run_to(
        &mut self,
        stop: CellIndex,
        index: usize,
        row_stride: usize,
        visit: impl FnMut(usize),
    ) -> u64;
}

/// The cells of a walk as an iterator (the simple form; map updates use
/// [`CellWalk::run_to`]).
pub struct WalkCells<W> {
    walk: W,
    done: bool,
}

impl<W: CellWalk> WalkCells<W> {
    pub fn new(walk: W) -> Self {
        Self { walk, done: false }
    }
}

impl<W: CellWalk> Iterator for WalkCells<W> {
    type Item = CellIndex;
    fn next(&mut self) -> Option<CellIndex> {
        if self.done {
            return None;
        }
        let c = self.walk.cell();
        if self.walk.is_at_end() {
            self.done = true;
        } else {
            self.walk.step();
        }
        Some(c)
    }
}

/// Every cell the segment from `start` to `end` passes through, in order.
pub fn cells_on_segment(
    start: FixedPoint,
    end: FixedPoint,
) -> Result<WalkCells<GridWalk>, RayTooLong> {
    Ok(WalkCells::new(GridWalk::new(start, end)?))
}

/// Crossings of one axis that a walk at cell coordinate `c`, stepping `step` (-1, 0, 1) with
/// `remaining` crossings left, needs to leave `[lo, hi)`; `None` if it ends inside.
#[inline]
pub(crate) fn crossings_to_leave(
    step: i32,
    c: i32,
    lo: i32,
    hi: i32,
    remaining: i64,
) -> Option<i64> {
    let n = match step {
        1 => i64::from(hi - c),
        -1 => i64::from(c - lo) + 1,
        _ => return None,
    };
    (n <= remaining).then_some(n)
}
