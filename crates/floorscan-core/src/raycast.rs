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

/// Why a segment cannot be walked.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RayTooLong;

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
            end: c1,
            step_x: dx.signum() as i32,
            step_y: dy.signum() as i32,
            t_x,
            t_y,
            dt_x,
            dt_y,
        })
    }

    /// The current cell.
    pub fn cell(&self) -> CellIndex {
        self.cell
    }

    /// The last cell of the walk.
    pub fn end(&self) -> CellIndex {
        self.end
    }

    pub fn is_at_end(&self) -> bool {
        self.cell == self.end
    }

    /// Moves to the next cell (must not be at the end).
    #[inline]
    pub fn step(&mut self) {
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
    pub fn last_cell_inside(&self, min: CellIndex, max: CellIndex) -> CellIndex {
        let rem_x = i64::from((self.end.x - self.cell.x).abs());
        let rem_y = i64::from((self.end.y - self.cell.y).abs());
        // Crossings needed to leave the box on each axis, if the walk gets that far.
        let exit = |step: i32, c: i32, lo: i32, hi: i32, rem: i64| -> Option<i64> {
            let n = match step {
                1 => i64::from(hi - c),
                -1 => i64::from(c - lo) + 1,
                _ => return None,
            };
            (n <= rem).then_some(n)
        };
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
    pub fn run_to(
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

impl Iterator for GridWalkCells {
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

/// The cells of a walk as an iterator (the simple form; map updates use
/// [`GridWalk::run_to`]).
pub struct GridWalkCells {
    walk: GridWalk,
    done: bool,
}

/// Every cell the segment from `start` to `end` passes through, in order.
pub fn cells_on_segment(start: FixedPoint, end: FixedPoint) -> Result<GridWalkCells, RayTooLong> {
    Ok(GridWalkCells {
        walk: GridWalk::new(start, end)?,
        done: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::BTreeSet;

    /// A rational bound `num / den` (den > 0) on the segment parameter t, open or closed.
    #[derive(Clone, Copy)]
    struct Bound {
        num: i128,
        den: i128,
        closed: bool,
    }

    fn cmp(a: Bound, b: Bound) -> std::cmp::Ordering {
        (a.num * b.den).cmp(&(b.num * a.den))
    }

    /// Brute force: does the closed segment meet the half-open cell [i, i+1) x [j, j+1)?
    /// Intersects the parameter intervals of both axes with [0, 1], exactly.
    fn segment_meets_cell(a: FixedPoint, b: FixedPoint, c: CellIndex) -> bool {
        let mut lo = Bound {
            num: 0,
            den: 1,
            closed: true,
        };
        let mut hi = Bound {
            num: 1,
            den: 1,
            closed: true,
        };
        for (p0, p1, i) in [(a.x, b.x, c.x), (a.y, b.y, c.y)] {
            let (p0, d) = (p0 as i128, (p1 - p0) as i128);
            let (lo_line, hi_line) = (
                i as i128 * SUBCELL as i128,
                (i as i128 + 1) * SUBCELL as i128,
            );
            if d == 0 {
                if !(lo_line <= p0 && p0 < hi_line) {
                    return false;
                }
                continue;
            }
            // p0 + t d in [lo_line, hi_line): solve for t.
            let (t_lo_line, t_hi_line) = ((lo_line - p0, d), (hi_line - p0, d));
            let norm = |(n, d): (i128, i128)| if d < 0 { (-n, -d) } else { (n, d) };
            let (l, h) = (norm(t_lo_line), norm(t_hi_line));
            let (enter, leave) = if d > 0 {
                (
                    Bound {
                        num: l.0,
                        den: l.1,
                        closed: true,
                    },
                    Bound {
                        num: h.0,
                        den: h.1,
                        closed: false,
                    },
                )
            } else {
                (
                    Bound {
                        num: h.0,
                        den: h.1,
                        closed: false,
                    },
                    Bound {
                        num: l.0,
                        den: l.1,
                        closed: true,
                    },
                )
            };
            match cmp(enter, lo) {
                std::cmp::Ordering::Greater => lo = enter,
                std::cmp::Ordering::Equal => lo.closed &= enter.closed,
                _ => {}
            }
            match cmp(leave, hi) {
                std::cmp::Ordering::Less => hi = leave,
                std::cmp::Ordering::Equal => hi.closed &= leave.closed,
                _ => {}
            }
        }
        match cmp(lo, hi) {
            std::cmp::Ordering::Less => true,
            std::cmp::Ordering::Equal => lo.closed && hi.closed,
            std::cmp::Ordering::Greater => false,
        }
    }

    fn brute_force(a: FixedPoint, b: FixedPoint) -> BTreeSet<CellIndex> {
        let (c0, c1) = (a.cell(), b.cell());
        let mut out = BTreeSet::new();
        for x in c0.x.min(c1.x) - 1..=c0.x.max(c1.x) + 1 {
            for y in c0.y.min(c1.y) - 1..=c0.y.max(c1.y) + 1 {
                if segment_meets_cell(a, b, CellIndex::new(x, y)) {
                    out.insert(CellIndex::new(x, y));
                }
            }
        }
        out
    }

    fn check_walk(a: FixedPoint, b: FixedPoint) {
        let cells: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
        assert_eq!(cells.first(), Some(&a.cell()));
        assert_eq!(cells.last(), Some(&b.cell()));
        for w in cells.windows(2) {
            let (dx, dy) = ((w[1].x - w[0].x).abs(), (w[1].y - w[0].y).abs());
            assert!(
                dx <= 1 && dy <= 1 && dx + dy >= 1,
                "jump {:?} -> {:?}",
                w[0],
                w[1]
            );
        }
        let set: BTreeSet<CellIndex> = cells.iter().copied().collect();
        assert_eq!(
            set.len(),
            cells.len(),
            "a cell visited twice on {a:?} -> {b:?}"
        );
        assert_eq!(set, brute_force(a, b), "{a:?} -> {b:?}");
    }

    #[test]
    fn hand_worked_walks() {
        let p = |x: f64, y: f64| FixedPoint::from_cells(x, y).unwrap();
        let walk = |a, b| {
            cells_on_segment(a, b)
                .unwrap()
                .map(|c| (c.x, c.y))
                .collect::<Vec<_>>()
        };
        assert_eq!(
            walk(p(0.5, 0.5), p(3.5, 0.5)),
            vec![(0, 0), (1, 0), (2, 0), (3, 0)]
        );
        assert_eq!(
            walk(p(3.5, 0.5), p(0.5, 0.5)),
            vec![(3, 0), (2, 0), (1, 0), (0, 0)]
        );
        // Through the corner (1, 1) going up-right: the corner belongs to cell (1, 1).
        assert_eq!(walk(p(0.5, 0.5), p(1.5, 1.5)), vec![(0, 0), (1, 1)]);
        // Going down-left through the same corner: the corner point is in (1, 1), which the
        // walk starts in, then both coordinates drop below 1 at once.
        assert_eq!(walk(p(1.5, 1.5), p(0.5, 0.5)), vec![(1, 1), (0, 0)]);
        // Going down-right through corner (1, 1): x reaches 1 (cell x = 1) before y drops below.
        assert_eq!(walk(p(0.5, 1.5), p(1.5, 0.5)), vec![(0, 1), (1, 1), (1, 0)]);
        // A shallow line.
        assert_eq!(
            walk(p(0.5, 0.5), p(4.5, 1.5)),
            vec![(0, 0), (1, 0), (2, 0), (2, 1), (3, 1), (4, 1)]
        );
        // Along a cell boundary: the line y = 1 belongs to row 1.
        assert_eq!(walk(p(0.5, 1.0), p(2.5, 1.0)), vec![(0, 1), (1, 1), (2, 1)]);
        assert_eq!(walk(p(-0.5, -0.5), p(-0.5, -0.5)), vec![(-1, -1)]);
    }

    #[test]
    fn corner_and_boundary_cases_match_brute_force() {
        // Every segment between lattice-aligned points of a small neighbourhood, including
        // quarter-cell positions: all corner and boundary coincidences.
        let q = SUBCELL / 4;
        let pts: Vec<FixedPoint> = (-3..=3)
            .flat_map(|x| (-3..=3).map(move |y| FixedPoint::new(x * q * 3, y * q * 2)))
            .collect();
        for &a in &pts {
            for &b in &pts {
                check_walk(a, b);
            }
        }
    }

    #[test]
    fn fixed_point_rounds_to_the_nearest_unit() {
        let u = 1.0 / SUBCELL as f64;
        for (v, want) in [
            (0.0, 0),
            (0.49 * u, 0),
            (0.5 * u, 1),
            (-0.5 * u, 0),
            (-0.51 * u, -1),
            (-3.7, -3789),
            (2.25, 2304),
        ] {
            assert_eq!(FixedPoint::from_cells(v, 0.0).unwrap().x, want, "{v}");
        }
        assert_eq!(
            FixedPoint::from_cells(-0.001, 0.0).unwrap().cell(),
            CellIndex::new(-1, 0)
        );
        assert!(FixedPoint::from_cells(f64::NAN, 0.0).is_none());
        assert!(FixedPoint::from_cells(0.0, 2e9).is_none());
    }

    #[test]
    fn too_long_rays_are_refused() {
        let a = FixedPoint::new(0, 0);
        assert!(GridWalk::new(a, FixedPoint::new(MAX_RAY_CELLS * SUBCELL, 0)).is_err());
        assert!(GridWalk::new(a, FixedPoint::new(0, MAX_RAY_CELLS * SUBCELL - 1)).is_ok());
    }

    fn collect_in_boxes(a: FixedPoint, b: FixedPoint, tile: i32) -> Vec<CellIndex> {
        // Splits the walk at the boundaries of `tile`-sized boxes, as tiled storage does.
        let mut walk = GridWalk::new(a, b).unwrap();
        let mut out = Vec::new();
        loop {
            let c = walk.cell();
            let min = CellIndex::new(c.x.div_euclid(tile) * tile, c.y.div_euclid(tile) * tile);
            let max = CellIndex::new(min.x + tile, min.y + tile);
            let stop = walk.last_cell_inside(min, max);
            let (w, h) = (tile as usize, tile as usize);
            let local = ((c.y - min.y) as usize) * w + (c.x - min.x) as usize;
            walk.run_to(stop, local, w, |i| {
                assert!(i < w * h, "index left the box");
                out.push(CellIndex::new(
                    min.x + (i % w) as i32,
                    min.y + (i / w) as i32,
                ));
            });
            if walk.is_at_end() {
                return out;
            }
            walk.step();
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(3000))]

        #[test]
        fn random_walks_match_brute_force(ax in -40_000i64..40_000, ay in -40_000i64..40_000,
                                          dx in -30_000i64..30_000, dy in -30_000i64..30_000) {
            check_walk(FixedPoint::new(ax, ay), FixedPoint::new(ax + dx, ay + dy));
        }

        #[test]
        fn tiled_runs_visit_the_same_cells_in_order(ax in -40_000i64..40_000, ay in -40_000i64..40_000,
                                                    dx in -60_000i64..60_000, dy in -60_000i64..60_000,
                                                    tile in prop::sample::select(vec![1, 2, 3, 8, 64])) {
            let (a, b) = (FixedPoint::new(ax, ay), FixedPoint::new(ax + dx, ay + dy));
            let simple: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
            prop_assert_eq!(collect_in_boxes(a, b, tile), simple);
        }

        #[test]
        fn grid_aligned_tiled_runs_match_the_simple_walk(ax in -40i64..40, ay in -40i64..40, bx in -40i64..40, by in -40i64..40,
                                                          tile in prop::sample::select(vec![1, 2, 3, 8])) {
            // Quarter-cell lattice: corners on the line, diagonal steps, the exact loop.
            let q = SUBCELL / 4;
            let (a, b) = (FixedPoint::new(ax * q, ay * q), FixedPoint::new(bx * q, by * q));
            let simple: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
            prop_assert_eq!(collect_in_boxes(a, b, tile), simple);
        }

        #[test]
        fn grid_aligned_walks_match_brute_force(ax in -12i64..12, ay in -12i64..12, bx in -12i64..12, by in -12i64..12) {
            // Coordinates on a half-cell lattice: many exact corner passages.
            let h = SUBCELL / 2;
            check_walk(FixedPoint::new(ax * h, ay * h), FixedPoint::new(bx * h, by * h));
        }
    }
}
