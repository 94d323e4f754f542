//! The true occupancy raster of a world at any resolution, in nav_msgs/OccupancyGrid values:
//! 100 occupied, 0 free, -1 unknown; row 0 is the lowest y (the map_server PGM is written
//! top row first, flipped, by the Python writer).
//!
//! A cell is occupied when the footprint of a solid whose base is below the robot's height
//! touches it (so a table top the robot fits under is not an obstacle, its legs are). Free cells
//! are those the robot's start cell reaches through unoccupied cells (4-connected); the rest
//! (inside walls, outside the building) is unknown.

use std::collections::VecDeque;

use floorscan_core::Point2;
use serde::{Deserialize, Serialize};

use crate::error::{check_range, invalid_option, Result};
use crate::geometry::{point_in_polygon, Aabb};
use crate::grid_index::{segment_cells, GridShape};
use crate::world::World;

pub const OCCUPIED: i8 = 100;
pub const FREE: i8 = 0;
pub const UNKNOWN: i8 = -1;

/// Options of the occupancy raster.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OccupancyOptions {
    /// Cell size [m], in [0.005, 10]. Default 0.05.
    pub resolution_m: f64,
    /// Height of the robot [m], > 0: solids whose base is at or above it do not block it.
    /// Default 0.5 (a robot that fits under tables, not under chairs' seats... whose legs block).
    pub robot_height_m: f64,
    /// Margin around the world's bounds [m], in [0, 100]. Default 0.5.
    pub margin_m: f64,
}

impl Default for OccupancyOptions {
    fn default() -> Self {
        Self {
            resolution_m: 0.05,
            robot_height_m: 0.5,
            margin_m: 0.5,
        }
    }
}

/// A raster of cells, row-major from the lowest y.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct OccupancyRaster {
    /// World position of the lower-left corner of cell (0, 0) [m].
    pub origin: Point2,
    pub resolution_m: f64,
    pub width: usize,
    pub height: usize,
    /// OCCUPIED, FREE or UNKNOWN per cell; index j * width + i (i along x, j along y).
    pub cells: Vec<i8>,
}

impl OccupancyRaster {
    /// The value at a world point (UNKNOWN outside).
    pub fn at(&self, p: Point2) -> i8 {
        let i = ((p.x - self.origin.x) / self.resolution_m).floor();
        let j = ((p.y - self.origin.y) / self.resolution_m).floor();
        if i < 0.0 || j < 0.0 || i >= self.width as f64 || j >= self.height as f64 {
            return UNKNOWN;
        }
        self.cells[j as usize * self.width + i as usize]
    }
}

/// The true occupancy raster of `world`.
pub fn occupancy_raster(world: &World, options: &OccupancyOptions) -> Result<OccupancyRaster> {
    check_range("resolution_m", options.resolution_m, 0.005, 10.0)?;
    check_range("robot_height_m", options.robot_height_m, 1e-6, 1e3)?;
    check_range("margin_m", options.margin_m, 0.0, 100.0)?;
    let b = world.bounds();
    let m = options.margin_m;
    let bounds = Aabb {
        min: Point2::new(b.min.x - m, b.min.y - m),
        max: Point2::new(b.max.x + m, b.max.y + m),
    };
    let res = options.resolution_m;
    let shape = GridShape {
        origin: bounds.min,
        cell_m: res,
        nx: (((bounds.max.x - bounds.min.x) / res).ceil() as usize).max(1),
        ny: (((bounds.max.y - bounds.min.y) / res).ceil() as usize).max(1),
    };
    if shape.nx * shape.ny > 200_000_000 {
        return Err(invalid_option(
            "resolution_m",
            format!("gives {} x {} cells (too many)", shape.nx, shape.ny),
        ));
    }
    let mut cells = vec![UNKNOWN; shape.nx * shape.ny];
    for s in world
        .solids
        .iter()
        .filter(|s| s.base_m < options.robot_height_m)
    {
        let n = s.polygon.len();
        for e in 0..n {
            for (i, j) in segment_cells(&shape, s.polygon[e], s.polygon[(e + 1) % n]) {
                cells[j * shape.nx + i] = OCCUPIED;
            }
        }
        for (i, j) in shape.cells_overlapping(Aabb::of_points(&s.polygon)) {
            let c = Point2::new(
                shape.origin.x + (i as f64 + 0.5) * res,
                shape.origin.y + (j as f64 + 0.5) * res,
            );
            if point_in_polygon(c, &s.polygon) {
                cells[j * shape.nx + i] = OCCUPIED;
            }
        }
    }
    if let Some((i0, j0)) = shape.cell_of(world.start.translation()) {
        let mut queue = VecDeque::new();
        if cells[j0 * shape.nx + i0] == UNKNOWN {
            cells[j0 * shape.nx + i0] = FREE;
            queue.push_back((i0, j0));
        }
        while let Some((i, j)) = queue.pop_front() {
            let mut visit = |i: usize, j: usize| {
                let k = j * shape.nx + i;
                if cells[k] == UNKNOWN {
                    cells[k] = FREE;
                    queue.push_back((i, j));
                }
            };
            if i > 0 {
                visit(i - 1, j);
            }
            if i + 1 < shape.nx {
                visit(i + 1, j);
            }
            if j > 0 {
                visit(i, j - 1);
            }
            if j + 1 < shape.ny {
                visit(i, j + 1);
            }
        }
    }
    Ok(OccupancyRaster {
        origin: shape.origin,
        resolution_m: res,
        width: shape.nx,
        height: shape.ny,
        cells,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::world_file::parse_world;

    #[test]
    fn a_closed_room_matches_a_hand_drawn_grid() {
        // A square room of 5 cm walls, on 0.25 m cells: the walls lie inside the border cells.
        let w = parse_world(
            r#"
name = "cell"
[start]
x = 0.6
y = 0.6
[[walls]]
from = [0.125, 0.125]
to = [1.225, 0.125]
thickness_m = 0.05
[[walls]]
from = [1.225, 0.125]
to = [1.225, 1.225]
thickness_m = 0.05
[[walls]]
from = [1.225, 1.225]
to = [0.125, 1.225]
thickness_m = 0.05
[[walls]]
from = [0.125, 1.225]
to = [0.125, 0.125]
thickness_m = 0.05
"#,
            "t",
        )
        .unwrap();
        let r = occupancy_raster(
            &w,
            &OccupancyOptions {
                resolution_m: 0.25,
                robot_height_m: 0.5,
                margin_m: 0.0,
            },
        )
        .unwrap();
        // Bounds: walls extend 0.025 m past their ends: [0.1, 1.25]; 5 x 5 cells from (0.1, 0.1).
        assert_eq!((r.width, r.height), (5, 5));
        let expected = [
            "#####", //
            "#...#", //
            "#...#", //
            "#...#", //
            "#####",
        ];
        for (j, row) in expected.iter().enumerate() {
            for (i, ch) in row.chars().enumerate() {
                let v = r.cells[j * 5 + i];
                let want = if ch == '#' { OCCUPIED } else { FREE };
                assert_eq!(v, want, "cell ({i}, {j})");
            }
        }
    }

    #[test]
    fn tables_block_with_their_legs_only_for_a_low_robot() {
        let w = parse_world(
            "name = \"t\"\n[start]\nx = 0\ny = 0\n[[tables]]\ncenter = [2, 0]\nsize = [1.0, 1.0]\n",
            "t",
        )
        .unwrap();
        let low = occupancy_raster(&w, &OccupancyOptions::default()).unwrap();
        assert_eq!(low.at(Point2::new(2.0, 0.0)), FREE);
        assert_eq!(
            low.at(Point2::new(2.0 - 0.5 + 0.075, 0.5 - 0.075)),
            OCCUPIED
        );
        let tall = occupancy_raster(
            &w,
            &OccupancyOptions {
                robot_height_m: 1.0,
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(tall.at(Point2::new(2.0, 0.0)), OCCUPIED);
        assert!(occupancy_raster(
            &w,
            &OccupancyOptions {
                resolution_m: 0.0,
                ..Default::default()
            }
        )
        .is_err());
    }
}
