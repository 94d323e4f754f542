//! The avoidance map itself (`floorscan.drive.AvoidanceMap` wraps it): a square window of
//! layers in the odometry frame (REP 103; row 0 = lowest y) that scrolls with the robot by
//! whole cells, takes visual and laser scans through [`AvoidanceUpdates`], forgets stale
//! evidence, keeps the bumper's marks apart, and gives the planner its classes and the map's
//! calibrated probabilities.
//!
//! The layers: the map's log odds (whose calibrated probabilities must mean what they say) and
//! `confirmed` (cells a hit from `confirm_range_m` or farther confirmed); the planner's copy of
//! the evidence (`plan_log_odds`, `plan_confirmed`, `plan_near_hits`: see [`PlanLayers`]); the
//! bumper's marks (`bumps`), which the camera cannot clear.

use super::{decay, AvoidanceUpdates, PlanLayers, VisualModel, VisualReadings};
use crate::avoidance_map_options::AvoidanceMapOptions;
use crate::error::{Error, Result};
use crate::pose::Pose2;

/// |log odds| below this: no evidence (unknown), whatever the calibration.
pub const NO_EVIDENCE_NATS: f32 = 0.05;

/// An ideal laser's evidence at its return (p = 0.9) and along its beam (p = 0.12): strong and
/// constant, the laser robot's default.
pub const LASER_HIT_NATS: f32 = 2.2;
pub const LASER_MISS_NATS: f32 = -2.0;

/// The avoidance map (see the module's docs).
#[derive(Debug, Clone)]
pub struct AvoidanceMap {
    options: AvoidanceMapOptions,
    side: usize,
    cell_m: f64,
    origin_cells: (i64, i64),
    /// The map's log odds (row major, `side` x `side`).
    pub log_odds: Vec<f32>,
    /// The bumper's marks (1 where a contact marked the cell, forgetting).
    pub bumps: Vec<f32>,
    /// 1 where a hit from `confirm_range_m` or farther confirmed the cell.
    pub confirmed: Vec<u8>,
    /// The planner's log odds, confirmed flags and near hits ([`PlanLayers`]).
    pub plan_log_odds: Vec<f32>,
    pub plan_confirmed: Vec<u8>,
    pub plan_near_hits: Vec<u8>,
    plan_occupied_nats: f32,
    plan_free_nats: f32,
    updates: AvoidanceUpdates,
    /// a laser scan's beam ends [cells] and returns, kept between scans (no allocation a scan)
    laser_ends: Vec<[f64; 2]>,
    laser_returned: Vec<bool>,
}

fn logit(p: f64) -> f64 {
    (p / (1.0 - p)).ln()
}

/// Moves `layer` (side x side) by (dx, dy) cells: cell (i, j) takes the old (i + dx, j + dy),
/// 0 where that lies outside.
fn scroll<T: Copy + Default>(layer: &mut [T], side: usize, dx: i64, dy: i64) {
    let n = side as i64;
    if dx.abs() >= n || dy.abs() >= n {
        layer.fill(T::default());
        return;
    }
    let old = layer.to_vec();
    layer.fill(T::default());
    let (i0, i1) = ((-dx).max(0), n + (-dx).min(0));
    let width = (i1 - i0) as usize;
    for j in (-dy).max(0)..n + (-dy).min(0) {
        let dst = (j * n + i0) as usize;
        let src = ((j + dy) * n + i0 + dx) as usize;
        layer[dst..dst + width].copy_from_slice(&old[src..src + width]);
    }
}

/// numpy's `interp`: linear between knots (x increasing), their end values beyond them.
fn interp(x: f64, knots: &[(f64, f64)]) -> f64 {
    let (first, last) = (knots[0], knots[knots.len() - 1]);
    if x.is_nan() {
        return f64::NAN;
    }
    if x < first.0 {
        return first.1;
    }
    if x >= last.0 {
        return last.1;
    }
    let j = knots.partition_point(|k| k.0 <= x) - 1;
    let (a, b) = (knots[j], knots[j + 1]);
    let slope = (b.1 - a.1) / (b.0 - a.0);
    slope * (x - a.0) + a.1
}

impl AvoidanceMap {
    /// An empty map of `options` whose window is centred near `center` [m, odometry frame].
    pub fn new(options: AvoidanceMapOptions, center: (f64, f64)) -> Result<Self> {
        options.validate()?;
        let cell_m = options.cell_size_m;
        let side = (options.size_m / cell_m).round_ties_even() as usize;
        let updates = AvoidanceUpdates::new(side, cell_m, options.clamp_nats)?;
        let mut map = Self {
            plan_occupied_nats: logit(options.occupied_threshold) as f32,
            plan_free_nats: logit(options.free_threshold) as f32,
            options,
            side,
            cell_m,
            origin_cells: (0, 0),
            log_odds: vec![0.0; side * side],
            bumps: vec![0.0; side * side],
            confirmed: vec![0; side * side],
            plan_log_odds: vec![0.0; side * side],
            plan_confirmed: vec![0; side * side],
            plan_near_hits: vec![0; side * side],
            updates,
            laser_ends: Vec::new(),
            laser_returned: Vec::new(),
        };
        map.recenter(center.0, center.1)?;
        Ok(map)
    }

    pub fn options(&self) -> &AvoidanceMapOptions {
        &self.options
    }

    /// Cells on a side of the window.
    pub fn side(&self) -> usize {
        self.side
    }

    /// The world cell of the window's cell (0, 0) (world cell (i, j) spans [i, i + 1) x
    /// [j, j + 1) cells from the odometry frame's origin).
    pub fn origin_cells(&self) -> (i64, i64) {
        self.origin_cells
    }

    /// Scrolls by whole cells so (x, y) [m] lies within a quarter window of the centre; cells
    /// that enter are unknown.
    pub fn recenter(&mut self, x: f64, y: f64) -> Result<()> {
        if !(x.is_finite() && y.is_finite()) {
            return Err(Error::InvalidGeometry(format!(
                "the map's centre must be finite, got ({x}, {y})"
            )));
        }
        let n = self.side as i64;
        let half = n / 2;
        let cx = ((x / self.cell_m).floor() as i64).saturating_sub(half);
        let cy = ((y / self.cell_m).floor() as i64).saturating_sub(half);
        // in i128: the difference of two i64 (a centre 1e300 m away saturates) cannot overflow
        let dx = (cx as i128 - self.origin_cells.0 as i128).clamp(-(n as i128), n as i128) as i64;
        let dy = (cy as i128 - self.origin_cells.1 as i128).clamp(-(n as i128), n as i128) as i64;
        if dx.abs() <= n / 4 && dy.abs() <= n / 4 {
            return Ok(());
        }
        let side = self.side;
        scroll(&mut self.log_odds, side, dx, dy);
        scroll(&mut self.bumps, side, dx, dy);
        scroll(&mut self.confirmed, side, dx, dy);
        scroll(&mut self.plan_log_odds, side, dx, dy);
        scroll(&mut self.plan_confirmed, side, dx, dy);
        scroll(&mut self.plan_near_hits, side, dx, dy);
        self.origin_cells = (cx, cy);
        Ok(())
    }

    /// World (odometry frame) point [m] to the window's fractional cell coordinates.
    pub fn to_cells(&self, x: f64, y: f64) -> [f64; 2] {
        [
            x / self.cell_m - self.origin_cells.0 as f64,
            y / self.cell_m - self.origin_cells.1 as f64,
        ]
    }

    /// Forgets: the evidence shrinks by 2^(-dt / half_life_s), the bumper's marks by
    /// 2^(-dt / bump_half_life_s) (never without a half-life).
    pub fn decay(&mut self, dt_s: f64) {
        if dt_s.is_nan() || dt_s <= 0.0 {
            return;
        }
        if let Some(hl) = self.options.half_life_s {
            let f = 0.5f64.powf(dt_s / hl) as f32;
            decay(&mut self.log_odds, f);
            decay(&mut self.plan_log_odds, f);
        }
        if let Some(hl) = self.options.bump_half_life_s {
            decay(&mut self.bumps, 0.5f64.powf(dt_s / hl) as f32);
        }
    }

    /// Adds one visual scan seen by the camera at `camera` (world_from_camera, odometry
    /// frame) with the evidence of `model` ([`AvoidanceUpdates::insert_visual`], the planner's
    /// layers given).
    pub fn insert_visual(
        &mut self,
        camera: Pose2,
        readings: &VisualReadings<'_>,
        model: &VisualModel,
    ) -> Result<()> {
        let plan = PlanLayers {
            log_odds: &mut self.plan_log_odds,
            confirmed: &mut self.plan_confirmed,
            near_hits: &mut self.plan_near_hits,
        };
        self.updates.insert_visual(
            &mut self.log_odds,
            &mut self.confirmed,
            Some(plan),
            self.origin_cells,
            camera,
            readings,
            model,
        )
    }

    /// An ideal 2-D laser scan from `pose` (world_from_robot): `ranges_m` (REP 117: non-finite
    /// is no return, the beam free to `range_max_m`) at `angles_rad` (robot frame); free to
    /// each return, `hit_nats` at it ([`LASER_HIT_NATS`], [`LASER_MISS_NATS`] by default).
    pub fn insert_laser(
        &mut self,
        pose: Pose2,
        ranges_m: &[f64],
        angles_rad: &[f64],
        range_max_m: f64,
        nats: Option<(f32, f32)>,
    ) -> Result<()> {
        if ranges_m.len() != angles_rad.len() {
            return Err(Error::LengthMismatch(format!(
                "{} ranges but {} angles",
                ranges_m.len(),
                angles_rad.len()
            )));
        }
        let (hit, miss) = nats.unwrap_or((LASER_HIT_NATS, LASER_MISS_NATS));
        let (mut ends, mut returned) = (
            std::mem::take(&mut self.laser_ends),
            std::mem::take(&mut self.laser_returned),
        );
        ends.clear();
        ends.extend(ranges_m.iter().zip(angles_rad).map(|(&r, &a)| {
            let a = a + pose.yaw;
            let end = if r.is_finite() { r } else { range_max_m };
            self.to_cells(pose.x + end * a.cos(), pose.y + end * a.sin())
        }));
        returned.clear();
        returned.extend(ranges_m.iter().map(|r| r.is_finite()));
        let sensor = self.to_cells(pose.x, pose.y);
        let result = self.updates.insert_laser(
            &mut self.log_odds,
            Some(&mut self.plan_log_odds),
            sensor,
            &ends,
            &returned,
            hit,
            miss,
        );
        (self.laser_ends, self.laser_returned) = (ends, returned);
        result
    }

    /// A bumper contact: the cells on a straight face `2 bump_face_half_length_m` long, square
    /// to `bearing_rad` (robot frame) at `distance_m` from `pose`, become obstacles in the
    /// bumper's layer, which the camera cannot clear and which forgets with
    /// `bump_half_life_s`. A face, not the touched point: what a bumper meets is most often a
    /// flat side wider than the segment that felt it.
    pub fn mark_bump(&mut self, pose: Pose2, bearing_rad: f64, distance_m: f64) -> Result<()> {
        if !(pose.is_finite() && bearing_rad.is_finite() && distance_m.is_finite()) {
            return Err(Error::InvalidGeometry(
                "a bump's pose, bearing and distance must be finite".into(),
            ));
        }
        let h = self.options.bump_face_half_length_m;
        let a = pose.yaw + bearing_rad;
        // numpy's linspace(-h, h, num)
        let num = (4.0 * h / self.cell_m) as usize + 2;
        let step = 2.0 * h / (num - 1) as f64;
        let (bx, by) = (pose.x + distance_m * a.cos(), pose.y + distance_m * a.sin());
        let n = self.side as f64;
        for k in 0..num {
            let t = if k + 1 == num {
                h
            } else {
                k as f64 * step + -h
            };
            let [cx, cy] = self.to_cells(bx - t * a.sin(), by + t * a.cos());
            if cx >= 0.0 && cx < n && cy >= 0.0 && cy < n {
                self.bumps[cy as usize * self.side + cx as usize] = 1.0;
            }
        }
        Ok(())
    }

    /// Calibrated occupancy probabilities (`probability_knots`, or the Platt curve of
    /// `probability_scale` / `probability_offset`) of the map's log odds, into `out`; cells
    /// without evidence read 0.5.
    pub fn probabilities(&self, out: &mut Vec<f64>) {
        let (a, b) = (
            self.options.probability_scale,
            self.options.probability_offset,
        );
        let knots = self.options.probability_knots.as_deref();
        out.clear();
        out.extend(self.log_odds.iter().map(|&l| {
            if l.abs() < NO_EVIDENCE_NATS {
                return 0.5;
            }
            let l = l as f64;
            match knots {
                Some(k) if !k.is_empty() => interp(l, k),
                _ => 1.0 / (1.0 + (-(a * l + b)).exp()),
            }
        }));
    }

    /// Cells the planner has evidence for (either way).
    pub fn known(&self, cell: usize) -> bool {
        self.plan_log_odds[cell].abs() >= NO_EVIDENCE_NATS
    }

    /// The planner's obstacles: the planner's evidence above logit(occupied_threshold) (one
    /// confident reading suffices: for avoidance a missed obstacle costs more than a detour),
    /// or the bumper's marks.
    pub fn occupied(&self, cell: usize) -> bool {
        self.plan_log_odds[cell] > self.plan_occupied_nats || self.bumps[cell] > 0.5
    }

    /// The planner's decision of `cell`: 0 free (known, below logit(free_threshold)), 2
    /// occupied ([`Self::occupied`]), else 1 unknown.
    pub fn occupancy_class(&self, cell: usize) -> u8 {
        if self.occupied(cell) {
            2
        } else if self.known(cell) && self.plan_log_odds[cell] < self.plan_free_nats {
            0
        } else {
            1
        }
    }
}

#[cfg(test)]
#[path = "avoidance_map_layers_tests.rs"]
mod tests;
