//! The calibration scene: the robot's camera looking at a pattern on the floor, described in the
//! camera ground frame exactly as `calibration/pattern.toml` describes it (docs/dataset-format.md):
//! a checkerboard, or the paper's dark lines at 20 cm intervals.
//!
//! Pattern axes: "away" is +x rotated by `yaw`; "across" is -y rotated by `yaw` (left to right in
//! the image). `near_left` is the inner corner (or line crossing) nearest the camera and
//! furthest left.

use floorscan_core::mount::ground_to_pixel;
use floorscan_core::{Point2, Pose2};
use serde::{Deserialize, Serialize};

use crate::camera::Camera;
use crate::error::{check_range, invalid_option, Result};
use crate::texture::{Covering, CoveringClass, FloorPattern};
use crate::world::{FloorRegion, World};

/// Which pattern lies on the floor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum PatternKind {
    Checkerboard,
    Lines,
}

/// A floor pattern, in the camera ground frame (the fields of pattern.toml).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PatternSpec {
    pub kind: PatternKind,
    /// Nearest-left inner corner / crossing [m], camera ground frame.
    pub near_left: Point2,
    /// Rotation of the "away" axis from +x [rad], counter-clockwise.
    pub yaw: f64,
    /// Checkerboard: inner corners [across, away].
    pub inner_corners: [u32; 2],
    /// Checkerboard square side [m].
    pub square_m: f64,
    /// Lines: spacing [m].
    pub spacing_m: f64,
    /// Lines: [running away (counted across), running across (counted away)].
    pub lines: [u32; 2],
    /// Lines: width [m].
    pub line_width_m: f64,
}

impl PatternSpec {
    /// The default pattern of a kind: a 9 x 7 inner-corner checkerboard of 10 cm squares, or
    /// 7 x 9 dark lines 2 cm wide at 20 cm (the paper), at `near_left`.
    pub fn new(kind: PatternKind, near_left: Point2) -> PatternSpec {
        PatternSpec {
            kind,
            near_left,
            yaw: 0.0,
            inner_corners: [9, 7],
            square_m: 0.10,
            spacing_m: 0.20,
            lines: [7, 9],
            line_width_m: 0.02,
        }
    }

    pub fn validate(&self) -> Result<()> {
        if !(self.near_left.x.is_finite() && self.near_left.y.is_finite() && self.yaw.is_finite()) {
            return Err(invalid_option(
                "near_left",
                "pattern placement must be finite",
            ));
        }
        match self.kind {
            PatternKind::Checkerboard => {
                check_range("square", self.square_m, 1e-3, 10.0)?;
                if self.inner_corners.iter().any(|&n| !(2..=100).contains(&n)) {
                    return Err(invalid_option(
                        "inner_corners",
                        "each count must be in 2..=100",
                    ));
                }
            }
            PatternKind::Lines => {
                check_range("spacing", self.spacing_m, 1e-3, 10.0)?;
                check_range("line_width", self.line_width_m, 1e-4, self.spacing_m / 2.0)?;
                if self.lines.iter().any(|&n| !(2..=100).contains(&n)) {
                    return Err(invalid_option("lines", "each count must be in 2..=100"));
                }
            }
        }
        Ok(())
    }

    /// (across, away) unit axes.
    pub fn axes(&self) -> (Point2, Point2) {
        let (s, c) = self.yaw.sin_cos();
        (Point2::new(s, -c), Point2::new(c, s))
    }

    fn at(&self, i: f64, j: f64, step: f64) -> Point2 {
        let (across, away) = self.axes();
        Point2::new(
            self.near_left.x + (i * across.x + j * away.x) * step,
            self.near_left.y + (i * across.y + j * away.y) * step,
        )
    }

    /// Inner corners / crossings [m], camera ground frame: row by row away from the camera
    /// (j), left to right within a row (i).
    pub fn points(&self) -> Vec<Point2> {
        let (n_i, n_j, step) = match self.kind {
            PatternKind::Checkerboard => {
                (self.inner_corners[0], self.inner_corners[1], self.square_m)
            }
            PatternKind::Lines => (self.lines[0], self.lines[1], self.spacing_m),
        };
        (0..n_j)
            .flat_map(|j| (0..n_i).map(move |i| (i, j)))
            .map(|(i, j)| self.at(i as f64, j as f64, step))
            .collect()
    }

    /// Outline of the pattern sheet (with its margin or the lines' overhang), counter-clockwise.
    pub fn outline(&self) -> Vec<Point2> {
        let (lo_i, hi_i, lo_j, hi_j, step) = match self.kind {
            PatternKind::Checkerboard => {
                let m = 0.5; // margin: half a square of white around the board
                let (n_i, n_j) = (self.inner_corners[0] as f64, self.inner_corners[1] as f64);
                (-1.0 - m, n_i + m, -1.0 - m, n_j + m, self.square_m)
            }
            PatternKind::Lines => {
                let o = 0.5;
                let (n_i, n_j) = (self.lines[0] as f64 - 1.0, self.lines[1] as f64 - 1.0);
                (-o, n_i + o, -o, n_j + o, self.spacing_m)
            }
        };
        // Across runs to the right (-y), so this order is counter-clockwise.
        vec![
            self.at(lo_i, hi_j, step),
            self.at(lo_i, lo_j, step),
            self.at(hi_i, lo_j, step),
            self.at(hi_i, hi_j, step),
        ]
    }

    fn covering(&self) -> Covering {
        let (across, away) = self.axes();
        let pattern = match self.kind {
            PatternKind::Checkerboard => FloorPattern::Checkerboard {
                origin: self.near_left,
                across,
                away,
                square_m: self.square_m,
                corners: self.inner_corners,
                dark_albedo: 0.06,
                margin_m: 0.5 * self.square_m,
            },
            PatternKind::Lines => FloorPattern::Lines {
                origin: self.near_left,
                across,
                away,
                spacing_m: self.spacing_m,
                lines: self.lines,
                width_m: self.line_width_m,
                line_albedo: 0.06,
                overhang_m: 0.5 * self.spacing_m,
            },
        };
        let albedo = if self.kind == PatternKind::Checkerboard {
            0.85
        } else {
            0.34
        };
        Covering {
            name: "pattern".into(),
            class: CoveringClass::Other,
            albedo,
            pattern,
            seed: 0x5EED,
        }
    }
}

/// Places a default pattern of `kind` in front of `camera`: centred across the view, as near as
/// possible while every outline point and every inner point is inside the image (4 px margin).
pub fn default_pattern(kind: PatternKind, camera: &Camera) -> Result<PatternSpec> {
    let base = PatternSpec::new(kind, Point2::new(0.0, 0.0));
    let (n_i, step) = match kind {
        PatternKind::Checkerboard => (base.inner_corners[0], base.square_m),
        PatternKind::Lines => (base.lines[0], base.spacing_m),
    };
    let half_width = (n_i - 1) as f64 * step / 2.0;
    let margin = 4.0;
    // The outline's edges bow in a wide-angle image: check points along them.
    let along_outline = |spec: &PatternSpec| -> Vec<Point2> {
        let o = spec.outline();
        (0..4)
            .flat_map(|e| {
                let (a, b) = (o[e], o[(e + 1) % 4]);
                (0..32).map(move |k| {
                    let t = k as f64 / 32.0;
                    Point2::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))
                })
            })
            .collect()
    };
    let inside = |p: Point2| {
        ground_to_pixel(&camera.lens, &camera.mount, p).is_some_and(|px| {
            px[0] >= margin
                && px[1] >= margin
                && px[0] <= camera.width as f64 - 1.0 - margin
                && px[1] <= camera.height as f64 - 1.0 - margin
        })
    };
    for k in 0..300 {
        let spec = PatternSpec {
            near_left: Point2::new(0.05 + 0.02 * k as f64, half_width),
            ..base.clone()
        };
        if along_outline(&spec)
            .into_iter()
            .chain(spec.points())
            .all(inside)
        {
            return Ok(spec);
        }
    }
    Err(invalid_option(
        "camera",
        "the calibration pattern does not fit in this camera's view of the floor",
    ))
}

/// The room of the calibration scene: 8 x 8 m around the camera, evenly lit.
const CALIBRATION_ROOM: &str = r#"
name = "calibration"
description = "An evenly lit room with a calibration pattern on the carpet"
[start]
x = 0.0
y = 0.0
[lighting]
ambient = 0.5
exposure_jitter = 0.0
grid = { spacing_m = 2.0, power = 0.6, area = [-1.0, -3.0, 5.0, 3.0] }
[[walls]]
from = [-2.0, -4.0]
to = [6.0, -4.0]
[[walls]]
from = [6.0, -4.0]
to = [6.0, 4.0]
[[walls]]
from = [6.0, 4.0]
to = [-2.0, 4.0]
[[walls]]
from = [-2.0, 4.0]
to = [-2.0, -4.0]
"#;

/// The calibration scene: the pattern on the carpet of an evenly lit room, in the camera ground
/// frame of a robot at [`robot_pose`] (the world origin).
pub fn calibration_world(spec: &PatternSpec) -> Result<World> {
    spec.validate()?;
    let mut world = crate::world_file::parse_world(CALIBRATION_ROOM, "calibration")?;
    let index = world.coverings.len();
    world.coverings.push(spec.covering());
    world.regions.push(FloorRegion {
        polygon: spec.outline(),
        covering: index,
    });
    World::new(world)
}

/// The robot pose that puts the camera ground frame at the world origin.
pub fn robot_pose(camera: &Camera) -> Pose2 {
    camera.robot_from_camera.inverse()
}
