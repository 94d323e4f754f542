//! The navigation function of a grid planner: geodesic cost-to-goal over a weighted,
//! 8-connected grid (Dijkstra's wavefront, as ROS navfn computes its potential).
//!
//! A step between neighbouring cells a and b costs its length (1 or sqrt 2 cells, times the
//! cell size [m]) times the mean of the two cells' weights; blocked cells are never entered.
//! Seeds start at their given cost (the goal's cell at 0, or border cells at their straight-line
//! distance to a goal outside the grid).

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::error::{invalid_option, Error, Result};

/// The largest grid [cells] a navigation function is computed over (16 M cells, 128 MB of
/// distances): bounds the allocation an argument can ask for.
pub const MAX_CELLS: usize = 1 << 24;

#[derive(PartialEq)]
struct Entry(f64, usize);

impl Eq for Entry {}

impl Ord for Entry {
    fn cmp(&self, other: &Self) -> Ordering {
        // min-heap on cost; ties by index for a deterministic order
        other
            .0
            .partial_cmp(&self.0)
            .unwrap_or(Ordering::Equal)
            .then_with(|| other.1.cmp(&self.1))
    }
}

impl PartialOrd for Entry {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

/// Geodesic cost [m, weighted] from the seeds to every cell of a `width` x `height` grid (row
/// major, row 0 first); `f64::INFINITY` where no path reaches. `blocked` and `weight` (>= 0,
/// finite) hold one value per cell; `seeds` are (cell index, starting cost); `step_m` is the
/// side of a cell [m].
pub fn geodesic_distances(
    width: usize,
    height: usize,
    blocked: &[bool],
    weight: &[f64],
    seeds: &[(usize, f64)],
    step_m: f64,
) -> Result<Vec<f64>> {
    let n = width
        .checked_mul(height)
        .filter(|&n| n <= MAX_CELLS)
        .ok_or_else(|| invalid_option("grid", format!("more than {MAX_CELLS} cells")))?;
    if blocked.len() != n || weight.len() != n {
        return Err(Error::LengthMismatch(format!(
            "{width} x {height} grid needs {n} cells, got blocked {} and weight {}",
            blocked.len(),
            weight.len()
        )));
    }
    if !(step_m.is_finite() && step_m > 0.0) {
        return Err(invalid_option(
            "step_m",
            format!("must be > 0, got {step_m}"),
        ));
    }
    if weight.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(invalid_option(
            "weight",
            "every weight must be finite and >= 0",
        ));
    }
    let mut dist = vec![f64::INFINITY; n];
    let mut heap = BinaryHeap::with_capacity(seeds.len().min(n) + 64);
    for &(i, d) in seeds {
        if i >= n || !d.is_finite() {
            return Err(Error::InvalidGeometry(format!(
                "seed ({i}, {d}) outside the grid or not finite"
            )));
        }
        if !blocked[i] && d < dist[i] {
            dist[i] = d;
            heap.push(Entry(d, i));
        }
    }
    const DIAG: f64 = std::f64::consts::SQRT_2;
    let nbrs: [(isize, isize, f64); 8] = [
        (-1, 0, 1.0),
        (1, 0, 1.0),
        (0, -1, 1.0),
        (0, 1, 1.0),
        (-1, -1, DIAG),
        (-1, 1, DIAG),
        (1, -1, DIAG),
        (1, 1, DIAG),
    ];
    while let Some(Entry(d, k)) = heap.pop() {
        if d > dist[k] {
            continue;
        }
        let (j, i) = ((k / width) as isize, (k % width) as isize);
        for &(dj, di, len) in &nbrs {
            let (jn, inn) = (j + dj, i + di);
            if jn < 0 || inn < 0 || jn >= height as isize || inn >= width as isize {
                continue;
            }
            let kn = jn as usize * width + inn as usize;
            if blocked[kn] {
                continue;
            }
            let nd = d + len * step_m * 0.5 * (weight[k] + weight[kn]);
            if nd < dist[kn] {
                dist[kn] = nd;
                heap.push(Entry(nd, kn));
            }
        }
    }
    Ok(dist)
}

/// The coarse grid a navigation function runs on, from a `width` x `height` costmap (row
/// major, costs 0..=254) in blocks of `factor` x `factor` cells (the last partial row and
/// column of blocks left out): a block is `blocked` when every one of its cells costs
/// `blocked_from` or more (optimistic: the local planner checks the fine costmap), and its
/// `weight` is 1 + min(mean cost, blocked_from) / 64, plus `unknown_cost` times its share of
/// cells without evidence when `known` (one flag per cell) is given. Returns the coarse
/// (width, height); `blocked` and `weight` are refilled.
#[allow(clippy::too_many_arguments)]
pub fn coarse_grid(
    cost: &[u8],
    width: usize,
    height: usize,
    known: Option<&[bool]>,
    factor: usize,
    blocked_from: u8,
    unknown_cost: f64,
    blocked: &mut Vec<bool>,
    weight: &mut Vec<f64>,
) -> Result<(usize, usize)> {
    let n = width
        .checked_mul(height)
        .filter(|&n| n <= MAX_CELLS)
        .ok_or_else(|| invalid_option("grid", format!("more than {MAX_CELLS} cells")))?;
    if cost.len() != n || known.is_some_and(|k| k.len() != n) {
        return Err(Error::LengthMismatch(format!(
            "a {width} x {height} costmap needs {n} cells, got {} costs and {:?} flags",
            cost.len(),
            known.map(<[bool]>::len)
        )));
    }
    if factor == 0 || factor > width.max(height).max(1) {
        return Err(invalid_option(
            "plan_cell_m",
            format!(
                "the coarse cell must span 1..={} map cells, got {factor}",
                width.max(height)
            ),
        ));
    }
    if !unknown_cost.is_finite() {
        return Err(invalid_option("unknown_cost", "must be finite"));
    }
    let (w, h) = (width / factor, height / factor);
    blocked.clear();
    weight.clear();
    let count = (factor * factor) as f64;
    for bj in 0..h {
        for bi in 0..w {
            let (mut sum, mut seen, mut lowest) = (0.0f64, 0.0f64, u8::MAX);
            for j in bj * factor..(bj + 1) * factor {
                let row = j * width;
                for i in bi * factor..(bi + 1) * factor {
                    let c = cost[row + i];
                    sum += c as f64;
                    lowest = lowest.min(c);
                    if let Some(k) = known {
                        seen += k[row + i] as u8 as f64;
                    }
                }
            }
            blocked.push(lowest >= blocked_from);
            let mut wgt = 1.0 + (sum / count).min(blocked_from as f64) / 64.0;
            if known.is_some() {
                wgt += unknown_cost * (1.0 - seen / count);
            }
            weight.push(wgt);
        }
    }
    Ok((w, h))
}

#[cfg(test)]
#[path = "navigation_function_tests.rs"]
mod tests;
