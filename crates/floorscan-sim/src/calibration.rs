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

/// Checkerboard sizes [`default_pattern`] tries, as fractions of the default 10 cm square,
/// largest first (down to 2.5 cm).
const PATTERN_SCALES: [f64; 5] = [1.0, 0.7, 0.5, 0.35, 0.25];

/// A placed checkerboard is legible when, between every two neighbouring points one row apart,
/// the image distance is at least this [px] or at least [`LEGIBLE_ROW_ASPECT`] times the
/// distance to the farther point's neighbour in its row. A camera low over the floor sees the
/// default board only far out, where its rows flatten (a Duckiebot-like lens 11 cm up: 3.2 px
/// against 26 px across) and the detector loses them; the default 320 x 240 camera's board has
/// 7.3 px rows, a 160 x 120 camera's 3.6 px rows at half their width, and both are found.
pub const LEGIBLE_ROW_STEP_PX: f64 = 7.0;
/// See [`LEGIBLE_ROW_STEP_PX`].
pub const LEGIBLE_ROW_ASPECT: f64 = 0.4;

/// Places a default pattern of `kind` in front of `camera`: centred across the view, as near as
/// possible while every outline point and every inner point is inside the image (4 px margin).
/// A checkerboard is the largest of [`PATTERN_SCALES`] that is legible there
/// ([`LEGIBLE_ROW_STEP_PX`]), or when none is the one with the widest rows ([`row_step_px`]);
/// the line grid keeps the paper's size.
pub fn default_pattern(kind: PatternKind, camera: &Camera) -> Result<PatternSpec> {
    // The line grid is the paper's pattern for the whole working range: its size stays.
    let scales: &[f64] = match kind {
        PatternKind::Checkerboard => &PATTERN_SCALES,
        PatternKind::Lines => &PATTERN_SCALES[..1],
    };
    let mut best: Option<(f64, PatternSpec)> = None;
    for &scale in scales {
        let mut base = PatternSpec::new(kind, Point2::new(0.0, 0.0));
        // Whole micrometres, so pattern.toml reads 0.035, not 0.034999999999999996.
        let um = |v: f64| (v * scale * 1e6).round() / 1e6;
        base.square_m = um(base.square_m);
        base.spacing_m = um(base.spacing_m);
        base.line_width_m = um(base.line_width_m);
        let Some(spec) = nearest_fit(base, scale, camera) else {
            continue;
        };
        if legible(&spec, camera) {
            return Ok(spec);
        }
        let step = row_step_px(&spec, camera).unwrap_or(0.0);
        if best.as_ref().is_none_or(|(b, _)| step > *b) {
            best = Some((step, spec));
        }
    }
    best.map(|(_, spec)| spec).ok_or_else(|| {
        invalid_option(
            "camera",
            "the calibration pattern does not fit in this camera's view of the floor",
        )
    })
}

/// The smallest image distance [px] between two points of `spec` one row apart (same column,
/// rows j and j + 1 away from the camera): how flat its farthest row looks. `None` when a
/// point is not seen.
pub fn row_step_px(spec: &PatternSpec, camera: &Camera) -> Option<f64> {
    let (n_i, px) = image_points(spec, camera)?;
    px.iter()
        .zip(px.iter().skip(n_i))
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]))
        .reduce(f64::min)
}

/// Whether every row step of `spec` is legible (see [`LEGIBLE_ROW_STEP_PX`]).
pub fn legible(spec: &PatternSpec, camera: &Camera) -> bool {
    let Some((n_i, px)) = image_points(spec, camera) else {
        return false;
    };
    let dist = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    (n_i..px.len()).all(|k| {
        let step = dist(px[k - n_i], px[k]);
        let i = k % n_i;
        let across = if i + 1 < n_i {
            dist(px[k], px[k + 1])
        } else {
            dist(px[k], px[k - 1])
        };
        step >= LEGIBLE_ROW_STEP_PX || step >= LEGIBLE_ROW_ASPECT * across
    })
}

/// The points of `spec` per row (n_i) and their pixels, row by row; `None` when a point is not
/// seen.
fn image_points(spec: &PatternSpec, camera: &Camera) -> Option<(usize, Vec<[f64; 2]>)> {
    let n_i = match spec.kind {
        PatternKind::Checkerboard => spec.inner_corners[0],
        PatternKind::Lines => spec.lines[0],
    } as usize;
    let px = spec
        .points()
        .into_iter()
        .map(|p| ground_to_pixel(&camera.lens, &camera.mount, p))
        .collect::<Option<Vec<_>>>()?;
    Some((n_i, px))
}

/// `base` (the default pattern at `scale`) moved away from the camera in steps until it lies
/// wholly inside the image.
fn nearest_fit(base: PatternSpec, scale: f64, camera: &Camera) -> Option<PatternSpec> {
    let (n_i, step) = match base.kind {
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
    // Steps of 2 cm for the default pattern, out to 6 m.
    let advance = 0.02 * scale;
    let steps = (6.0 / advance).ceil() as usize;
    (0..steps)
        .map(|k| PatternSpec {
            near_left: Point2::new(0.05 + advance * k as f64, half_width),
            ..base.clone()
        })
        .find(|spec| {
            along_outline(spec)
                .into_iter()
                .chain(spec.points())
                .all(inside)
        })
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

#[cfg(test)]
mod tests {
    use super::*;
    use floorscan_core::lens::Lens;
    use floorscan_core::mount::CameraMount;

    fn low_camera() -> Camera {
        // A Duckiebot-like wide lens 0.11 m above the floor, tilted 0.3 rad down.
        Camera {
            lens: Lens::PinholeRadial {
                fx: 296.0,
                fy: 300.0,
                cx: 321.3,
                cy: 241.7,
                k1: -0.235,
                k2: 0.036,
                p1: -0.0033,
                p2: -0.0012,
                k3: 0.0,
            },
            mount: CameraMount {
                height_m: 0.11,
                tilt_rad: 0.3,
                roll_rad: 0.0,
            },
            width: 640,
            height: 480,
            ..Camera::default()
        }
    }

    fn fits(spec: &PatternSpec, camera: &Camera) -> bool {
        spec.points().into_iter().chain(spec.outline()).all(|p| {
            ground_to_pixel(&camera.lens, &camera.mount, p).is_some_and(|px| {
                px[0] >= 0.0
                    && px[1] >= 0.0
                    && px[0] <= camera.width as f64 - 1.0
                    && px[1] <= camera.height as f64 - 1.0
            })
        })
    }

    #[test]
    fn row_step_matches_a_camera_looking_straight_down() {
        // Straight down from h, a pinhole images the floor at f / h px per metre everywhere.
        let camera = Camera {
            lens: Lens::Pinhole {
                fx: 200.0,
                fy: 200.0,
                cx: 159.5,
                cy: 119.5,
            },
            mount: CameraMount {
                height_m: 2.0,
                tilt_rad: std::f64::consts::FRAC_PI_2,
                roll_rad: 0.0,
            },
            ..Camera::default()
        };
        let mut spec = PatternSpec::new(PatternKind::Checkerboard, Point2::new(-0.3, 0.4));
        spec.inner_corners = [5, 4];
        let step = row_step_px(&spec, &camera).unwrap();
        assert!((step - 200.0 * 0.10 / 2.0).abs() < 1e-6, "{step}");
    }

    #[test]
    fn the_default_camera_keeps_the_default_board() {
        for (w, h) in [(160, 120), (320, 240), (640, 480)] {
            let camera = Camera::wide_angle(w, h);
            for kind in [PatternKind::Checkerboard, PatternKind::Lines] {
                let spec = default_pattern(kind, &camera).unwrap();
                let base = PatternSpec::new(kind, spec.near_left);
                assert_eq!(spec, base, "{w} x {h} {kind:?}");
                assert!(fits(&spec, &camera));
            }
            let board = default_pattern(PatternKind::Checkerboard, &camera).unwrap();
            assert!(legible(&board, &camera));
        }
    }

    #[test]
    fn a_low_camera_gets_a_smaller_legible_board() {
        let camera = low_camera();
        // The default board fits only far away, where its rows flatten.
        let base = nearest_fit(
            PatternSpec::new(PatternKind::Checkerboard, Point2::new(0.0, 0.0)),
            1.0,
            &camera,
        )
        .unwrap();
        assert!(!legible(&base, &camera));
        let spec = default_pattern(PatternKind::Checkerboard, &camera).unwrap();
        assert!(spec.square_m < 0.10, "{}", spec.square_m);
        assert!(fits(&spec, &camera));
        assert!(legible(&spec, &camera));
        // The largest legible board of the sizes tried: the next larger one is not legible.
        let k = PATTERN_SCALES
            .iter()
            .position(|s| (s * 0.10 - spec.square_m).abs() < 1e-9)
            .unwrap();
        let mut larger = PatternSpec::new(PatternKind::Checkerboard, Point2::new(0.0, 0.0));
        larger.square_m *= PATTERN_SCALES[k - 1];
        let larger = nearest_fit(larger, PATTERN_SCALES[k - 1], &camera);
        assert!(larger.is_none_or(|l| !legible(&l, &camera)));
    }
}
