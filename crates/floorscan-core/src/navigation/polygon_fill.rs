//! Filling polygons on a grid of cells exactly as OpenCV's `fillPoly` (4.x / 5.0) does with
//! 8-connected outlines and sub-cell vertices (`lineType = LINE_8`, `shift` bits of fraction):
//! each edge drawn as an 8-connected line between the cells its rounded end points fall in,
//! then each row filled between pairs of crossings of all edges (the edges walked in 16.16
//! fixed point from their upper end point's cell). The avoidance map fills its floor quadrilaterals
//! with it, so the map the Rust core builds equals the one OpenCV built before.
//!
//! Grid cell (i, j) is OpenCV's pixel (x = i, y = j), centred on integer coordinates; rows
//! outside `0..height` and columns outside `0..width` are clipped.

const XY_SHIFT: u32 = 16;
const XY_ONE: i64 = 1 << XY_SHIFT;

/// The largest |vertex coordinate| [cells] the fill accepts; vertices beyond are moved onto
/// this square (far outside any grid the bindings allow), so fixed-point products cannot
/// overflow.
pub const MAX_COORDINATE: i64 = 1 << 24;

/// A `width` x `height` grid of cells (row major) being filled with `value`.
pub struct Canvas<'a, T: Copy> {
    pub cells: &'a mut [T],
    pub width: usize,
    pub height: usize,
}

impl<T: Copy> Canvas<'_, T> {
    fn set(&mut self, x: i64, y: i64, value: T) {
        if x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height {
            self.cells[y as usize * self.width + x as usize] = value;
        }
    }

    fn span(&mut self, y: i64, x1: i64, x2: i64, value: T) {
        let w = self.width as i64;
        if y < 0 || y >= self.height as i64 || x1 >= w || x2 < 0 {
            return;
        }
        let (a, b) = (x1.max(0), x2.min(w - 1));
        if a > b {
            return;
        }
        let row = y as usize * self.width;
        self.cells[row + a as usize..=row + b as usize].fill(value);
    }
}

/// Cohen-Sutherland clipping of the segment to the cells `0..w` x `0..h` (OpenCV's
/// `clipLine`: the crossing computed in `f64`, truncated); false when nothing of it is inside.
fn clip_line(w: i64, h: i64, p1: &mut [i64; 2], p2: &mut [i64; 2]) -> bool {
    let (right, bottom) = (w - 1, h - 1);
    if w <= 0 || h <= 0 {
        return false;
    }
    let code = |p: &[i64; 2]| {
        (p[0] < 0) as i32
            + (p[0] > right) as i32 * 2
            + (p[1] < 0) as i32 * 4
            + (p[1] > bottom) as i32 * 8
    };
    let (mut c1, mut c2) = (code(p1), code(p2));
    if (c1 & c2) == 0 && (c1 | c2) != 0 {
        if c1 & 12 != 0 {
            let a = if c1 < 8 { 0 } else { bottom };
            p1[0] += ((a - p1[1]) as f64 * (p2[0] - p1[0]) as f64 / (p2[1] - p1[1]) as f64) as i64;
            p1[1] = a;
            c1 = (p1[0] < 0) as i32 + (p1[0] > right) as i32 * 2;
        }
        if c2 & 12 != 0 {
            let a = if c2 < 8 { 0 } else { bottom };
            p2[0] += ((a - p2[1]) as f64 * (p2[0] - p1[0]) as f64 / (p2[1] - p1[1]) as f64) as i64;
            p2[1] = a;
            c2 = (p2[0] < 0) as i32 + (p2[0] > right) as i32 * 2;
        }
        if (c1 & c2) == 0 && (c1 | c2) != 0 {
            if c1 != 0 {
                let a = if c1 == 1 { 0 } else { right };
                p1[1] +=
                    ((a - p1[0]) as f64 * (p2[1] - p1[1]) as f64 / (p2[0] - p1[0]) as f64) as i64;
                p1[0] = a;
                c1 = 0;
            }
            if c2 != 0 {
                let a = if c2 == 1 { 0 } else { right };
                p2[1] +=
                    ((a - p2[0]) as f64 * (p2[1] - p1[1]) as f64 / (p2[0] - p1[0]) as f64) as i64;
                p2[0] = a;
                c2 = 0;
            }
        }
    }
    (c1 | c2) == 0
}

/// An 8-connected line between two cells (Bresenham, drawn left to right, as OpenCV's
/// `LineIterator`), clipped to the canvas.
fn line<T: Copy>(canvas: &mut Canvas<'_, T>, a: [i64; 2], b: [i64; 2], value: T) {
    let (w, h) = (canvas.width as i64, canvas.height as i64);
    let (mut p1, mut p2) = (a, b);
    let outside = |p: &[i64; 2]| p[0] < 0 || p[1] < 0 || p[0] >= w || p[1] >= h;
    if (outside(&p1) || outside(&p2)) && !clip_line(w, h, &mut p1, &mut p2) {
        return;
    }
    if p2[0] < p1[0] {
        std::mem::swap(&mut p1, &mut p2);
    }
    let mut dx = p2[0] - p1[0];
    let mut dy = p2[1] - p1[1];
    let step_y = if dy < 0 { -1 } else { 1 };
    dy = dy.abs();
    let vertical = dy > dx;
    if vertical {
        std::mem::swap(&mut dx, &mut dy);
    }
    let mut err = dx - 2 * dy;
    let (mut x, mut y) = (p1[0], p1[1]);
    for _ in 0..=dx {
        // the clipped ends lie on the canvas but for rounding at a corner: checked
        canvas.set(x, y, value);
        let minor = err < 0;
        err += -2 * dy + if minor { 2 * dx } else { 0 };
        if vertical {
            y += step_y;
            if minor {
                x += 1;
            }
        } else {
            x += 1;
            if minor {
                y += step_y;
            }
        }
    }
}

/// One edge of the scanline fill: active on rows `y0..y1`, at 16.16 fixed-point x = `x`
/// on row `y0`, moving `dx` per row.
#[derive(Debug, Clone, Copy)]
struct Edge {
    y0: i64,
    y1: i64,
    x: i64,
    dx: i64,
}

/// Fills polygons as one `fillPoly` call does: every polygon's 8-connected outline, then on
/// each row the cells between pairs of crossings of *all* the polygons' edges, sorted by x
/// (even-odd over the whole collection: where two polygons overlap, the overlap is filled only
/// by their outlines). Edge lists are kept between calls (no allocation once they are large
/// enough).
#[derive(Debug, Clone, Default)]
pub struct PolygonFill {
    edges: Vec<Edge>,
    active: Vec<(i64, usize)>,
    starting: Vec<(i64, usize)>,
    merged: Vec<(i64, usize)>,
}

impl PolygonFill {
    /// Fills `polygons` (vertices [cells, as integers with `shift` (0..=16) bits of
    /// fraction; OpenCV's pixel coordinates]) with `value`.
    pub fn fill<T: Copy, const N: usize>(
        &mut self,
        canvas: &mut Canvas<'_, T>,
        polygons: &[[[i64; 2]; N]],
        shift: u32,
        value: T,
    ) {
        let shift = shift.min(XY_SHIFT);
        let (w, h) = (canvas.width as i64, canvas.height as i64);
        let limit = MAX_COORDINATE << shift;
        let delta = (1i64 << shift) >> 1;
        let fixed = |v: [i64; 2]| {
            let (x, y) = (v[0].clamp(-limit, limit), v[1].clamp(-limit, limit));
            [x << (XY_SHIFT - shift), (y + delta) >> shift]
        };
        self.edges.clear();
        for vertices in polygons {
            if N == 0 {
                continue;
            }
            let mut pt0 = fixed(vertices[N - 1]);
            for v in vertices {
                let pt1 = fixed(*v);
                let mut t0 = [(pt0[0] + (XY_ONE >> 1)) >> XY_SHIFT, pt0[1]];
                let mut t1 = [(pt1[0] + (XY_ONE >> 1)) >> XY_SHIFT, pt1[1]];
                line(canvas, t0, t1, value);
                let (mut c0, mut c1) = (pt0, pt1);
                let outside = |p: &[i64; 2]| p[0] < 0 || p[1] < 0 || p[0] >= w || p[1] >= h;
                if outside(&t0) || outside(&t1) {
                    // an edge leaving the grid follows its clipped end points' rows, as
                    // OpenCV's does (whether or not any of it is inside)
                    clip_line(w, h, &mut t0, &mut t1);
                    if t0[1] != t1[1] {
                        c0[1] = t0[1];
                        c1[1] = t1[1];
                    }
                }
                // the edge runs between its end points' (clipped) cells, as OpenCV's
                c0[0] = t0[0] << XY_SHIFT;
                c1[0] = t1[0] << XY_SHIFT;
                if pt0[1] != pt1[1] {
                    let dx = (c1[0] - c0[0]) / (c1[1] - c0[1]);
                    self.edges.push(if pt0[1] < pt1[1] {
                        Edge {
                            y0: pt0[1],
                            y1: pt1[1],
                            x: c0[0] + (pt0[1] - c0[1]) * dx,
                            dx,
                        }
                    } else {
                        Edge {
                            y0: pt1[1],
                            y1: pt0[1],
                            x: c1[0] + (pt1[1] - c1[1]) * dx,
                            dx,
                        }
                    });
                }
                pt0 = pt1;
            }
        }
        if self.edges.len() < 2 {
            return;
        }
        self.edges.sort_unstable_by_key(|e| e.y0);
        let y_hi = self.edges.iter().map(|e| e.y1).max().unwrap_or(0).min(h);
        let mut y = self.edges[0].y0.max(0);
        // edges that end above the first drawn row never become active
        let mut next = 0;
        self.active.clear();
        while y < y_hi {
            let edges = &self.edges;
            self.active.retain(|&(_, k)| y < edges[k].y1);
            for a in self.active.iter_mut() {
                let e = &edges[a.1];
                a.0 = e.x + (y - e.y0) * e.dx;
            }
            // the active edges stay nearly sorted from row to row; the edges starting on this
            // row are sorted apart and merged in
            insertion_sort(&mut self.active);
            self.starting.clear();
            while next < edges.len() && edges[next].y0 <= y {
                let e = &edges[next];
                if e.y1 > y {
                    self.starting.push((e.x + (y - e.y0) * e.dx, next));
                }
                next += 1;
            }
            if !self.starting.is_empty() {
                self.starting.sort_unstable();
                self.merged.clear();
                let (mut a, mut b) = (0, 0);
                while a < self.active.len() || b < self.starting.len() {
                    let take_a = b == self.starting.len()
                        || (a < self.active.len() && self.active[a].0 < self.starting[b].0);
                    if take_a {
                        self.merged.push(self.active[a]);
                        a += 1;
                    } else {
                        self.merged.push(self.starting[b]);
                        b += 1;
                    }
                }
                std::mem::swap(&mut self.active, &mut self.merged);
            }
            for pair in self.active.chunks_exact(2) {
                // the cells whose centres lie between the two crossings
                canvas.span(
                    y,
                    (pair[0].0 + XY_ONE - 1) >> XY_SHIFT,
                    pair[1].0 >> XY_SHIFT,
                    value,
                );
            }
            if self.active.is_empty() {
                // jump to the next edge's first row
                match self.edges.get(next) {
                    Some(e) => y = e.y0.max(y + 1),
                    None => break,
                }
            } else {
                y += 1;
            }
        }
    }
}

/// Sorts by x (stable), fast on the nearly sorted lists consecutive rows give.
fn insertion_sort(v: &mut [(i64, usize)]) {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1].0 > v[j].0 {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
}

#[cfg(test)]
#[path = "polygon_fill_tests.rs"]
mod tests;
