//! The dynamic window's scoring (Fox, Burgard & Thrun 1997, as ROS's dwa_local_planner runs
//! it): every sampled velocity (v, omega) is rolled out at constant velocity, trajectories
//! that enter an inscribed or lethal costmap cell (or, beyond a blind radius, a cell without
//! evidence) are dropped, and the cheapest of
//!
//! ```text
//! path_distance_bias * nav(forward point) / cell + goal_distance_bias * nav(end) / cell
//!     + occdist_scale * (largest cost along the path)
//! ```
//!
//! is chosen, `nav` the navigation function [m] and the forward point
//! `forward_point_distance_m` ahead of the end pose. Where the plan does not reach a point its
//! value is 1000 plus the straight-line distance to the goal; within two forward-point
//! distances of the goal both terms are the end point's straight-line distance to the goal
//! (where the plan reaches it). The arithmetic follows the numpy original operation by
//! operation (tests/dynamic_window_reference.py), so the same samples score the same.

use crate::error::{invalid_option, Error, Result};

/// A row-major raster of values over the plane: cell (i, j) covers
/// `[origin_m[0] + i cell_m, + cell_m) x [origin_m[1] + j cell_m, + cell_m)`.
#[derive(Clone, Copy, Debug)]
pub struct Raster<'a, T> {
    pub data: &'a [T],
    pub width: usize,
    pub height: usize,
    pub origin_m: [f64; 2],
    pub cell_m: f64,
}

impl<'a, T: Copy> Raster<'a, T> {
    /// Checks the data length against the shape and the cell size.
    pub fn new(
        data: &'a [T],
        width: usize,
        height: usize,
        origin_m: [f64; 2],
        cell_m: f64,
    ) -> Result<Self> {
        if width.checked_mul(height) != Some(data.len()) {
            return Err(Error::LengthMismatch(format!(
                "a {width} x {height} raster needs {} values, got {}",
                width.saturating_mul(height),
                data.len()
            )));
        }
        if !(cell_m.is_finite() && cell_m > 0.0 && origin_m.iter().all(|v| v.is_finite())) {
            return Err(invalid_option(
                "raster",
                format!("cell size must be finite and > 0 and origin finite, got {cell_m} at {origin_m:?}"),
            ));
        }
        Ok(Self {
            data,
            width,
            height,
            origin_m,
            cell_m,
        })
    }

    /// The value of the cell holding (x, y) [m], `outside` beyond the raster.
    #[inline]
    pub fn at_or(&self, x: f64, y: f64, outside: T) -> T {
        let i = ((x - self.origin_m[0]) / self.cell_m).floor();
        let j = ((y - self.origin_m[1]) / self.cell_m).floor();
        // a NaN compares false: outside
        if i >= 0.0 && j >= 0.0 && i < self.width as f64 && j < self.height as f64 {
            self.data[j as usize * self.width + i as usize]
        } else {
            outside
        }
    }
}

/// The scoring weights and limits (`DwaOptions` in Python, dwa_local_planner's names).
#[derive(Clone, Copy, Debug)]
pub struct WindowScoring {
    pub path_distance_bias: f64,
    pub goal_distance_bias: f64,
    pub occdist_scale: f64,
    pub forward_point_distance_m: f64,
    /// Beyond this distance [m] from the start a trajectory may not enter an unknown cell.
    pub blind_radius_m: f64,
    /// Costs at or above this are not admissible (the costmap's inscribed cost).
    pub inscribed: u8,
}

/// Distance [m] added to the straight-line distance where the plan does not reach a point.
const UNREACHED_M: f64 = 1e3;
/// |omega| below this is a straight line.
const STRAIGHT_RAD_S: f64 = 1e-6;

/// The chosen sample of the grid `vs` x `omegas` (index `k = iw * vs.len() + iv`, the order
/// of numpy's `meshgrid(vs, omegas)` raveled), or `None` when no sample is admissible.
/// `pose` is (x, y, yaw) [m, rad] in the rasters' frame; `times_s` the roll-out's sample
/// times (> 0, the last one its horizon); `cost` the costmap (0 outside); `unknown` the cells
/// without evidence (false outside); `nav` the navigation function [m] (infinite outside or
/// where unreached); `goal` (x, y) [m]; `cell_size_m` divides the navigation terms (the
/// costmap's cell).
#[allow(clippy::too_many_arguments)]
pub fn best_sample(
    pose: [f64; 3],
    vs: &[f64],
    omegas: &[f64],
    times_s: &[f64],
    cost: &Raster<u8>,
    unknown: Option<&Raster<bool>>,
    nav: &Raster<f64>,
    goal: [f64; 2],
    cell_size_m: f64,
    scoring: &WindowScoring,
) -> Result<Option<usize>> {
    if times_s.is_empty() || vs.is_empty() || omegas.is_empty() {
        return Err(invalid_option(
            "dynamic window",
            "needs at least one speed, turn rate and roll-out time",
        ));
    }
    let [x0, y0, th0] = pose;
    let [gx, gy] = goal;
    let (s0, c0) = th0.sin_cos();
    let arriving = (x0 - gx).hypot(y0 - gy) < scoring.forward_point_distance_m * 2.0;
    let fpd = scoring.forward_point_distance_m;
    // numpy's argmin over every sample, the inadmissible ones infinite: the first least
    let (mut best_k, mut best_value, mut any_admissible) = (0usize, f64::NAN, false);
    for (iw, &w) in omegas.iter().enumerate() {
        let straight = w.abs() < STRAIGHT_RAD_S;
        for (iv, &v) in vs.iter().enumerate() {
            let k = iw * vs.len() + iv;
            let radius = v / if straight { 1.0 } else { w };
            let mut worst = 0u8;
            let mut admissible = true;
            let (mut ex, mut ey, mut eth) = (x0, y0, th0);
            for &t in times_s {
                let th = th0 + w * t;
                let (x, y) = if straight {
                    (x0 + v * t * c0, y0 + v * t * s0)
                } else {
                    (x0 + radius * (th.sin() - s0), y0 - radius * (th.cos() - c0))
                };
                worst = worst.max(cost.at_or(x, y, 0));
                if let Some(u) = unknown {
                    if u.at_or(x, y, false) && (x - x0).hypot(y - y0) > scoring.blind_radius_m {
                        admissible = false;
                    }
                }
                (ex, ey, eth) = (x, y, th);
            }
            admissible &= worst < scoring.inscribed;
            any_admissible |= admissible;
            let value = if admissible {
                let to_goal = |x: f64, y: f64| (x - gx).hypot(y - gy);
                // the plan's cost, or (where it does not reach) 1000 + the straight line
                let plan = |x: f64, y: f64| {
                    let n = nav.at_or(x, y, f64::INFINITY);
                    (
                        if n.is_finite() {
                            n
                        } else {
                            UNREACHED_M + to_goal(x, y)
                        },
                        n.is_finite(),
                    )
                };
                let (mut n_end, end_reached) = plan(ex, ey);
                let (mut n_fwd, _) = plan(ex + fpd * eth.cos(), ey + fpd * eth.sin());
                if arriving {
                    if end_reached {
                        n_end = to_goal(ex, ey);
                    }
                    n_fwd = n_end;
                }
                scoring.path_distance_bias * n_fwd / cell_size_m
                    + scoring.goal_distance_bias * n_end / cell_size_m
                    + scoring.occdist_scale * f64::from(worst)
            } else {
                f64::INFINITY
            };
            if k == 0 || value < best_value {
                (best_k, best_value) = (k, value);
            }
        }
    }
    Ok(any_admissible.then_some(best_k))
}

#[cfg(test)]
#[path = "dynamic_window_tests.rs"]
mod tests;
