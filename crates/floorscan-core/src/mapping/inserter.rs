//! Map updates (paper IV.B): visual scans, laser scans and sonar readings into a grid, each
//! sensor with its own evidence, all through the same once-per-scan engine
//! ([`crate::ray_update`]).
//!
//! Visual scan rules, per column reading (points in the camera ground frame, placed in the
//! world with `world_from_robot * robot_from_camera`):
//! - `Boundary { point }`: the boundary cell gets a hit; the cells from the column's near edge
//!   of view (`near`, the ground point of its start row) up to the boundary get a miss; cells
//!   beyond the boundary, and cells between the robot and `near` (which the camera cannot see),
//!   are untouched. Without a `near` point, free space starts at the camera.
//! - `NoBoundary { farthest }`: misses from `near` up to and including `farthest`.
//! - `TooClose`: a hit at `near` (the obstacle is at or inside the near edge of view), unless
//!   [`TooClosePolicy::Ignore`].
//! - `Invalid`: nothing.

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::grid::Grid;
use crate::laser::LaserScan;
use crate::log_odds::Evidence;
use crate::pose::{Point2, Pose2};
use crate::ray_update::{Ray, RayUpdater, UpdateStats};
use crate::scan::{ColumnOutcome, Scan};
use crate::sonar::SonarReading;

/// What a `too_close` column contributes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum TooClosePolicy {
    /// A hit at the near edge of the column's field of view (default).
    MarkNearEdge,
    /// Nothing.
    Ignore,
}

/// Options of [`Inserter`]: the evidence of each sensor and the visual scan rules.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct InserterOptions {
    /// Visual scans. Default hit +0.85 / miss -0.4 nats (p = 0.7 / 0.4, OctoMap's sensor
    /// model): a few consistent frames decide a cell. Lower both for a noisy floor texture.
    pub visual: Evidence,
    /// Laser scans. Default +0.85 / -0.4 nats, as OctoMap.
    pub laser: Evidence,
    /// Sonar readings. Default +0.4 / -0.2 nats: the echo comes from somewhere on the arc, so
    /// each arc cell gets weak evidence.
    pub sonar: Evidence,
    /// Visual `too_close` columns. Default: mark the near edge.
    pub too_close: TooClosePolicy,
    /// Floor left unobserved just before a visual boundary, in pixel rows of the boundary's
    /// footprint (beyond the paper), >= 0. The boundary row is uncertain by about half a pixel
    /// row, which far away is several cells of floor: clearing right up to the point clears
    /// the obstacle's own cells whenever the point lands beyond its face. Default 0.5; 0 gives
    /// the paper's rule (free right up to the boundary cell).
    pub boundary_margin_rows: f64,
}

impl Default for InserterOptions {
    fn default() -> Self {
        Self {
            visual: Evidence {
                hit_nats: 0.85,
                miss_nats: -0.4,
            },
            laser: Evidence {
                hit_nats: 0.85,
                miss_nats: -0.4,
            },
            sonar: Evidence {
                hit_nats: 0.4,
                miss_nats: -0.2,
            },
            too_close: TooClosePolicy::MarkNearEdge,
            boundary_margin_rows: 0.5,
        }
    }
}

impl InserterOptions {
    pub fn validate(&self) -> Result<()> {
        if !(self.boundary_margin_rows.is_finite() && self.boundary_margin_rows >= 0.0) {
            return Err(crate::error::invalid_option(
                "boundary_margin_rows",
                format!("must be finite and >= 0, got {}", self.boundary_margin_rows),
            ));
        }
        self.visual.validate("visual")?;
        self.laser.validate("laser")?;
        self.sonar.validate("sonar")
    }
}

/// Puts sensor data into grids. Holds scratch memory only: one inserter can serve any grid.
#[derive(Debug, Clone)]
pub struct Inserter {
    options: InserterOptions,
    updater: RayUpdater,
    rays: Vec<Ray>,
}

impl Inserter {
    pub fn new(options: InserterOptions) -> Result<Inserter> {
        options.validate()?;
        Ok(Inserter {
            options,
            updater: RayUpdater::default(),
            rays: Vec::new(),
        })
    }

    pub fn options(&self) -> &InserterOptions {
        &self.options
    }

    /// Bytes of scratch memory held.
    pub fn memory_bytes(&self) -> usize {
        self.updater.memory_bytes() + self.rays.capacity() * std::mem::size_of::<Ray>()
    }

    /// One visual scan (readings in the camera ground frame) seen from `world_from_robot`,
    /// with the camera at `robot_from_camera` on the robot.
    pub fn insert_scan(
        &mut self,
        grid: &mut Grid,
        scan: &Scan,
        world_from_robot: &Pose2,
        robot_from_camera: &Pose2,
    ) -> Result<UpdateStats> {
        let world_from_camera = sensor_pose(
            grid,
            world_from_robot,
            robot_from_camera,
            "robot_from_camera",
        )?;
        let origin = world_from_camera.translation();
        self.rays.clear();
        for (k, r) in scan.readings.iter().enumerate() {
            let to_world = |p: Point2| -> Result<Point2> {
                if p.x.is_finite() && p.y.is_finite() {
                    Ok(world_from_camera.transform_point(p))
                } else {
                    Err(Error::InvalidGeometry(format!(
                        "reading {k} (column {}) has a non-finite point",
                        r.column
                    )))
                }
            };
            let near = r.near.map(to_world).transpose()?;
            match r.outcome {
                ColumnOutcome::Boundary {
                    point, footprint_m, ..
                } => {
                    let from = near.unwrap_or(origin);
                    let to = to_world(point)?;
                    let margin_m = self.options.boundary_margin_rows * footprint_m.max(0.0);
                    if margin_m > 0.0 {
                        // Free up to `margin_m` short of the boundary, then the hit alone.
                        let (dx, dy) = (to.x - from.x, to.y - from.y);
                        let len = dx.hypot(dy);
                        if len > margin_m {
                            let s = (len - margin_m) / len;
                            let clear_to = Point2::new(from.x + s * dx, from.y + s * dy);
                            self.rays.push(Ray {
                                from,
                                to: clear_to,
                                hit: false,
                            });
                        }
                        self.rays.push(Ray {
                            from: to,
                            to,
                            hit: true,
                        });
                    } else {
                        self.rays.push(Ray {
                            from,
                            to,
                            hit: true,
                        });
                    }
                }
                ColumnOutcome::NoBoundary { farthest, .. } => {
                    self.rays.push(Ray {
                        from: near.unwrap_or(origin),
                        to: to_world(farthest)?,
                        hit: false,
                    });
                }
                ColumnOutcome::TooClose => {
                    if let (TooClosePolicy::MarkNearEdge, Some(n)) = (self.options.too_close, near)
                    {
                        self.rays.push(Ray {
                            from: n,
                            to: n,
                            hit: true,
                        });
                    }
                }
                ColumnOutcome::Invalid { .. } => {}
            }
        }
        self.updater.apply(grid, &self.rays, self.options.visual)
    }

    /// One laser scan from a laser at `robot_from_laser` on the robot (see
    /// [`crate::laser`] for the range rules).
    pub fn insert_laser(
        &mut self,
        grid: &mut Grid,
        laser: &LaserScan<'_>,
        world_from_robot: &Pose2,
        robot_from_laser: &Pose2,
    ) -> Result<UpdateStats> {
        let world_from_laser =
            sensor_pose(grid, world_from_robot, robot_from_laser, "robot_from_laser")?;
        self.rays.clear();
        laser.rays(&world_from_laser, &mut self.rays)?;
        self.updater.apply(grid, &self.rays, self.options.laser)
    }

    /// Many laser scans with the same beam layout: `ranges_m` holds `poses.len()` scans of
    /// `beams` ranges each, row after row. All are checked before the first is inserted.
    pub fn insert_lasers(
        &mut self,
        grid: &mut Grid,
        layout: &LaserScan<'_>,
        ranges_m: &[f64],
        world_from_robot: &[Pose2],
        robot_from_laser: &Pose2,
    ) -> Result<UpdateStats> {
        let beams = layout.ranges_m.len();
        if beams == 0 || ranges_m.len() != beams * world_from_robot.len() {
            return Err(Error::LengthMismatch(format!(
                "{} ranges for {} poses of {} beams",
                ranges_m.len(),
                world_from_robot.len(),
                beams
            )));
        }
        for (k, p) in world_from_robot.iter().enumerate() {
            sensor_pose(grid, p, robot_from_laser, "robot_from_laser")
                .map_err(|e| prefix(e, &format!("scan {k}: ")))?;
            let scan = LaserScan {
                ranges_m: &ranges_m[k * beams..(k + 1) * beams],
                ..*layout
            };
            scan.check()
                .map_err(|e| prefix(e, &format!("scan {k}: ")))?;
        }
        let directions = layout.beam_directions();
        let mut stats = UpdateStats::default();
        for (k, p) in world_from_robot.iter().enumerate() {
            let scan = LaserScan {
                ranges_m: &ranges_m[k * beams..(k + 1) * beams],
                ..*layout
            };
            self.rays.clear();
            scan.rays_along(&directions, &p.compose(robot_from_laser), &mut self.rays);
            stats += self.updater.apply(grid, &self.rays, self.options.laser)?;
        }
        Ok(stats)
    }

    /// Sonar readings fired together (a ring), each from its own mount on the robot.
    pub fn insert_sonar(
        &mut self,
        grid: &mut Grid,
        readings: &[SonarReading],
        world_from_robot: &Pose2,
        robot_from_sonar: &[Pose2],
    ) -> Result<UpdateStats> {
        if readings.len() != robot_from_sonar.len() {
            return Err(Error::LengthMismatch(format!(
                "{} sonar readings but {} mounts",
                readings.len(),
                robot_from_sonar.len()
            )));
        }
        self.rays.clear();
        for (r, m) in readings.iter().zip(robot_from_sonar) {
            let world_from_sonar = sensor_pose(grid, world_from_robot, m, "robot_from_sonar")?;
            r.rays(&world_from_sonar, grid.cell_size_m(), &mut self.rays)?;
        }
        self.updater.apply(grid, &self.rays, self.options.sonar)
    }

    /// Any other range sensor: rays in world coordinates, with the given evidence.
    pub fn insert_rays(
        &mut self,
        grid: &mut Grid,
        rays: &[Ray],
        evidence: Evidence,
    ) -> Result<UpdateStats> {
        evidence.validate("evidence")?;
        self.updater.apply(grid, rays, evidence)
    }
}

/// `world_from_robot * robot_from_sensor`, after checking both poses and that the robot is
/// inside a fixed-bounds grid.
fn sensor_pose(
    grid: &Grid,
    world_from_robot: &Pose2,
    robot_from_sensor: &Pose2,
    mount_name: &str,
) -> Result<Pose2> {
    if !world_from_robot.is_finite() {
        return Err(Error::InvalidGeometry(format!(
            "world_from_robot must be finite, got {world_from_robot:?}"
        )));
    }
    if !robot_from_sensor.is_finite() {
        return Err(Error::InvalidGeometry(format!(
            "{mount_name} must be finite, got {robot_from_sensor:?}"
        )));
    }
    if grid.fixed_cells().is_some() {
        let inside = grid
            .cell_of(world_from_robot.translation())
            .is_some_and(|c| grid.covers(c));
        if !inside {
            return Err(Error::OutOfBounds(format!(
                "robot at ({:.3}, {:.3}) m is outside the map's fixed bounds",
                world_from_robot.x, world_from_robot.y
            )));
        }
    }
    Ok(world_from_robot.compose(robot_from_sensor))
}

fn prefix(e: Error, p: &str) -> Error {
    match e {
        Error::InvalidGeometry(m) => Error::InvalidGeometry(format!("{p}{m}")),
        Error::OutOfBounds(m) => Error::OutOfBounds(format!("{p}{m}")),
        Error::LengthMismatch(m) => Error::LengthMismatch(format!("{p}{m}")),
        other => other,
    }
}
