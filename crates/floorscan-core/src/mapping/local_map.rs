//! The local map (paper IV.A): a square window fixed to the robot, through which the world
//! moves, fed with pose *changes* only (odometry increments).
//!
//! The window is world-aligned inside: its cells sit on the lattice of the frame the
//! increments are integrated in (the odometry frame, called "local" here). When the robot
//! leaves the window's centre cell, the window scrolls by whole cells, so cell contents are
//! copied, never resampled, and the robot's sub-cell position is kept exactly: nothing drifts
//! or blurs however long the robot drives. Cells that scroll out are forgotten; cells that
//! scroll in are unknown. [`LocalMap::robot_view`] resamples the window in the robot's own
//! frame (rotated) on demand.
//!
//! Fed the same data, the local map holds exactly what a global map with the same lattice
//! holds over the window, for every cell that has not left the window (tested).

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Error, Result};
use crate::grid::{CellRect, Grid};
use crate::grid_options::GridOptions;
use crate::inserter::{Inserter, InserterOptions};
use crate::laser::LaserScan;
use crate::log_odds::Evidence;
use crate::pose::{Point2, Pose2};
use crate::ray_update::UpdateStats;
use crate::raycast::CellIndex;
use crate::scan::Scan;
use crate::sonar::SonarReading;

/// Options of [`LocalMap`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct LocalMapOptions {
    /// Side of the square window [m], at least 2 cells and at most 4096 cells. Default 3.84
    /// (the paper's 384 x 384 cm map at 4 cm: 96 x 96 cells). Rounded to whole cells.
    pub size_m: f64,
    /// Cell size, lattice origin, clamp bounds and thresholds. `bounds_m` must be `None`: the
    /// window is the bound.
    pub grid: GridOptions,
    /// What a visual reading adds to the local map's cells (its own: `[sensors.visual]` is
    /// the global map's). The robot avoids obstacles by this map, so it must settle within
    /// two frames: default hit +0.85 nats (one boundary makes a cell occupied at the default
    /// threshold, p 0.65 = +0.62 nats) and miss -0.75 (two consistent free readings make it
    /// free, p 0.196 = -1.41 nats; the global map's -0.4 needs four).
    pub visual: Evidence,
}

/// Default of [`LocalMapOptions::visual`].
pub const DEFAULT_LOCAL_VISUAL: Evidence = Evidence {
    hit_nats: 0.85,
    miss_nats: -0.75,
};

impl Default for LocalMapOptions {
    fn default() -> Self {
        Self {
            size_m: 3.84,
            grid: GridOptions::default(),
            visual: DEFAULT_LOCAL_VISUAL,
        }
    }
}

impl LocalMapOptions {
    pub fn validate(&self) -> Result<()> {
        self.grid.validate()?;
        self.visual.validate("visual")?;
        if self.grid.bounds_m.is_some() {
            return Err(invalid_option(
                "bounds_m",
                "a local map's bounds are its window: leave bounds_m unset",
            ));
        }
        let cells = self.size_m / self.grid.cell_size_m;
        if !(cells.is_finite() && (2.0..=4096.0).contains(&cells.round())) {
            return Err(invalid_option(
                "size_m",
                format!("must span 2 to 4096 cells, got {} m", self.size_m),
            ));
        }
        Ok(())
    }

    /// Cells per side of the window.
    pub fn side_cells(&self) -> i32 {
        (self.size_m / self.grid.cell_size_m).round() as i32
    }
}

/// A robot-centred, scrolling occupancy window.
#[derive(Debug, Clone)]
pub struct LocalMap {
    options: LocalMapOptions,
    inserter: Inserter,
    grid: Grid,
    side: i32,
    /// `local_from_robot`: the robot in the window's (odometry-aligned) frame.
    pose: Pose2,
    scratch: Vec<i16>,
}

impl LocalMap {
    /// An empty window centred on the robot at `local_from_robot` (the identity to start a
    /// fresh odometry frame at the robot). Visual scans take `options.visual`, not
    /// `inserter.visual` (the local map's evidence is its own); the rest of `inserter` applies.
    pub fn new(
        options: LocalMapOptions,
        inserter: InserterOptions,
        local_from_robot: Pose2,
    ) -> Result<LocalMap> {
        options.validate()?;
        check_pose(&local_from_robot, "local_from_robot")?;
        let side = options.side_cells();
        let probe = Grid::new(options.grid.clone())?;
        let centre = probe
            .cell_of(local_from_robot.translation())
            .ok_or_else(|| Error::InvalidGeometry("the pose is too far from the origin".into()))?;
        let grid = Grid::with_cell_bounds(options.grid.clone(), window_at(centre, side))?;
        let inserter = Inserter::new(InserterOptions {
            visual: options.visual,
            ..inserter
        })?;
        Ok(LocalMap {
            options,
            inserter,
            grid,
            side,
            pose: local_from_robot,
            scratch: Vec::new(),
        })
    }

    pub fn options(&self) -> &LocalMapOptions {
        &self.options
    }
    /// The robot's pose in the window's frame.
    pub fn pose(&self) -> Pose2 {
        self.pose
    }
    /// The cells the window covers now.
    pub fn window(&self) -> CellRect {
        self.grid
            .fixed_cells()
            .expect("a local map has fixed bounds")
    }
    /// The window's cells (a fixed-bounds grid in the local frame).
    pub fn grid(&self) -> &Grid {
        &self.grid
    }

    /// Moves the robot by an odometry increment `robot_before_from_robot_after` and scrolls.
    pub fn move_by(&mut self, delta: &Pose2) -> Result<()> {
        check_pose(delta, "delta")?;
        self.move_to(&self.pose.compose(delta))
    }

    /// Places the robot at `local_from_robot` (e.g. the odometry pose) and scrolls.
    pub fn move_to(&mut self, local_from_robot: &Pose2) -> Result<()> {
        check_pose(local_from_robot, "local_from_robot")?;
        let centre = self
            .grid
            .cell_of(local_from_robot.translation())
            .ok_or_else(|| Error::InvalidGeometry("the pose is too far from the origin".into()))?;
        let target = window_at(centre, self.side);
        if target != self.window() {
            self.scroll_to(target)?;
        }
        self.pose = *local_from_robot;
        Ok(())
    }

    fn scroll_to(&mut self, target: CellRect) -> Result<()> {
        let mut next = Grid::with_cell_bounds(self.options.grid.clone(), target)?;
        let old = self.window();
        let overlap = CellRect {
            min: CellIndex::new(old.min.x.max(target.min.x), old.min.y.max(target.min.y)),
            max: CellIndex::new(old.max.x.min(target.max.x), old.max.y.min(target.max.y)),
        };
        if overlap.width() > 0 && overlap.height() > 0 {
            self.grid.read_rect(overlap, &mut self.scratch);
            next.write_rect(overlap, &self.scratch)?;
        }
        self.grid = next;
        Ok(())
    }

    /// A visual scan seen from the current pose.
    pub fn insert_scan(&mut self, scan: &Scan, robot_from_camera: &Pose2) -> Result<UpdateStats> {
        self.inserter
            .insert_scan(&mut self.grid, scan, &self.pose, robot_from_camera)
    }

    /// A laser scan seen from the current pose.
    pub fn insert_laser(
        &mut self,
        laser: &LaserScan<'_>,
        robot_from_laser: &Pose2,
    ) -> Result<UpdateStats> {
        self.inserter
            .insert_laser(&mut self.grid, laser, &self.pose, robot_from_laser)
    }

    /// Sonar readings taken at the current pose.
    pub fn insert_sonar(
        &mut self,
        readings: &[SonarReading],
        robot_from_sonar: &[Pose2],
    ) -> Result<UpdateStats> {
        self.inserter
            .insert_sonar(&mut self.grid, readings, &self.pose, robot_from_sonar)
    }

    /// The window resampled in the robot's frame (x forward, y left): `width` x `height`
    /// cells of the map's cell size centred on the robot, row-major, row 0 at the most
    /// negative robot y (the robot's right), column 0 at the most negative x (behind).
    /// Nearest-cell sampling; outside the window reads 0 (unknown).
    pub fn robot_view(&self, width: usize, height: usize, out: &mut Vec<i16>) {
        out.clear();
        let s = self.grid.cell_size_m();
        for j in 0..height {
            for i in 0..width {
                let p = Point2::new(
                    (i as f64 - width as f64 / 2.0 + 0.5) * s,
                    (j as f64 - height as f64 / 2.0 + 0.5) * s,
                );
                let q = self.pose.transform_point(p);
                out.push(self.grid.cell_of(q).map_or(0, |c| self.grid.get(c).0));
            }
        }
    }
}

/// The window of `side` cells with the robot's cell at its centre (index side / 2).
fn window_at(centre: CellIndex, side: i32) -> CellRect {
    let min = CellIndex::new(centre.x - side / 2, centre.y - side / 2);
    CellRect {
        min,
        max: CellIndex::new(min.x + side, min.y + side),
    }
}

fn check_pose(p: &Pose2, name: &str) -> Result<()> {
    if p.is_finite() {
        Ok(())
    } else {
        Err(Error::InvalidGeometry(format!(
            "{name} must be finite, got {p:?}"
        )))
    }
}
