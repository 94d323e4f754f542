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
mod tests {
    use super::*;

    /// Bellman-Ford relaxation to a fixed point: the brute-force reference.
    fn brute(
        w: usize,
        h: usize,
        blocked: &[bool],
        weight: &[f64],
        seeds: &[(usize, f64)],
    ) -> Vec<f64> {
        let n = w * h;
        let mut d = vec![f64::INFINITY; n];
        for &(i, c) in seeds {
            if !blocked[i] {
                d[i] = d[i].min(c);
            }
        }
        loop {
            let mut changed = false;
            for k in 0..n {
                if blocked[k] || !d[k].is_finite() {
                    continue;
                }
                let (j, i) = ((k / w) as isize, (k % w) as isize);
                for dj in -1isize..=1 {
                    for di in -1isize..=1 {
                        if dj == 0 && di == 0 {
                            continue;
                        }
                        let (jn, inn) = (j + dj, i + di);
                        if jn < 0 || inn < 0 || jn >= h as isize || inn >= w as isize {
                            continue;
                        }
                        let kn = jn as usize * w + inn as usize;
                        if blocked[kn] {
                            continue;
                        }
                        let len = if dj != 0 && di != 0 { 2f64.sqrt() } else { 1.0 };
                        let nd = d[k] + len * 0.1 * 0.5 * (weight[k] + weight[kn]);
                        if nd < d[kn] - 1e-12 {
                            d[kn] = nd;
                            changed = true;
                        }
                    }
                }
            }
            if !changed {
                return d;
            }
        }
    }

    #[test]
    fn dijkstra_equals_relaxation_on_random_grids() {
        let mut stream = crate::test_rng::XorShift::new(12345);
        let mut rnd = || stream.fraction(10_000);
        for _ in 0..20 {
            let (w, h) = (17, 11);
            let blocked: Vec<bool> = (0..w * h).map(|_| rnd() < 0.25).collect();
            let weight: Vec<f64> = (0..w * h).map(|_| 1.0 + 3.0 * rnd()).collect();
            let seeds = vec![((rnd() * (w * h) as f64) as usize, 0.0), (3, 0.7)];
            let fast = geodesic_distances(w, h, &blocked, &weight, &seeds, 0.1).unwrap();
            let slow = brute(w, h, &blocked, &weight, &seeds);
            for (a, b) in fast.iter().zip(&slow) {
                assert!(
                    (a.is_infinite() && b.is_infinite()) || (a - b).abs() < 1e-9,
                    "{a} {b}"
                );
            }
        }
    }

    #[test]
    fn open_grid_of_unit_weight_gives_octile_distance() {
        let (w, h) = (9, 7);
        let d = geodesic_distances(
            w,
            h,
            &vec![false; w * h],
            &vec![1.0; w * h],
            &[(0, 0.0)],
            0.5,
        )
        .unwrap();
        for j in 0..h {
            for i in 0..w {
                let (a, b) = (i.max(j) as f64, i.min(j) as f64);
                let octile = 0.5 * ((a - b) + b * 2f64.sqrt());
                assert!((d[j * w + i] - octile).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn a_wall_without_a_gap_leaves_the_far_side_unreachable() {
        let (w, h) = (6, 4);
        let blocked: Vec<bool> = (0..w * h).map(|k| k % w == 3).collect();
        let d = geodesic_distances(w, h, &blocked, &vec![1.0; w * h], &[(0, 0.0)], 1.0).unwrap();
        assert!(d[5].is_infinite() && d[2].is_finite());
    }

    #[test]
    fn bad_arguments_are_errors() {
        assert!(geodesic_distances(2, 2, &[false; 3], &[1.0; 4], &[], 1.0).is_err());
        assert!(geodesic_distances(2, 2, &[false; 4], &[1.0; 4], &[(9, 0.0)], 1.0).is_err());
        assert!(geodesic_distances(2, 2, &[false; 4], &[f64::NAN; 4], &[], 1.0).is_err());
        assert!(geodesic_distances(1 << 13, 1 << 13, &[], &[], &[], 1.0).is_err());
        assert!(geodesic_distances(2, 2, &[false; 4], &[1.0; 4], &[], 0.0).is_err());
    }

    #[test]
    fn coarse_blocks_take_the_least_cost_and_the_mean() {
        // 4 x 2 costs in blocks of 2: [[0, 254], [253, 253]] and [[10, 20], [30, 40]]
        let cost = [0, 254, 10, 20, 253, 253, 30, 40];
        let known = [true, true, false, true, true, true, false, false];
        let (mut blocked, mut weight) = (Vec::new(), Vec::new());
        let wh = coarse_grid(
            &cost,
            4,
            2,
            Some(&known),
            2,
            253,
            2.0,
            &mut blocked,
            &mut weight,
        );
        assert_eq!(wh.unwrap(), (2, 1));
        assert_eq!(blocked, vec![false, false]);
        assert_eq!(weight[0], 1.0 + 190.0 / 64.0);
        assert_eq!(weight[1], 1.0 + 25.0 / 64.0 + 2.0 * 0.75);
        let cost = [253u8; 4];
        coarse_grid(&cost, 2, 2, None, 2, 253, 2.0, &mut blocked, &mut weight).unwrap();
        assert_eq!((blocked[0], weight[0]), (true, 1.0 + 253.0 / 64.0));
        assert!(coarse_grid(&cost, 2, 2, None, 0, 253, 2.0, &mut blocked, &mut weight).is_err());
        assert!(coarse_grid(&cost, 3, 2, None, 1, 253, 2.0, &mut blocked, &mut weight).is_err());
    }
}
