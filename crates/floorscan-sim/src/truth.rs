//! Ground truth of a view: the label of each pixel, and per image column the true obstacle
//! boundary and the appearance boundary, found exactly (bisection on the continuous row with the
//! lens model's own rays, not on the pixel grid).
//!
//! Rows are image rows (v = 0 at the top, pixel centres at integers). A boundary row is the
//! position of the edge line between the last floor pixel and the first obstacle pixel of the
//! column, counted from the bottom: a float between their centres.

use floorscan_core::{ColumnStatus, Point2, Pose2};
use serde::{Deserialize, Serialize};

use crate::camera::{CameraPlacement, CameraRays};
use crate::clearance::{sector_of, Clearance};
use crate::error::{check_range, Result};
use crate::scene::{Scene, Surface};

/// What a pixel centre sees. Codes are stable (they are written to label images).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[repr(u8)]
pub enum PixelLabel {
    /// No ray (outside a fisheye's image circle), or nothing in that direction.
    Nothing = 0,
    /// Floor covered by carpet.
    Carpet = 1,
    /// Floor with another covering (linoleum, tiles, a calibration pattern).
    OtherCovering = 2,
    /// A scrap of paper on the floor: looks like an obstacle, is not one.
    Paper = 3,
    /// A face of a solid: wall, box, furniture.
    Obstacle = 4,
    Ceiling = 5,
}

impl PixelLabel {
    pub const ALL: [PixelLabel; 6] = [
        PixelLabel::Nothing,
        PixelLabel::Carpet,
        PixelLabel::OtherCovering,
        PixelLabel::Paper,
        PixelLabel::Obstacle,
        PixelLabel::Ceiling,
    ];

    pub fn as_str(self) -> &'static str {
        match self {
            PixelLabel::Nothing => "nothing",
            PixelLabel::Carpet => "carpet",
            PixelLabel::OtherCovering => "other_covering",
            PixelLabel::Paper => "paper",
            PixelLabel::Obstacle => "obstacle",
            PixelLabel::Ceiling => "ceiling",
        }
    }
}

/// Options of the column truth.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TruthOptions {
    /// Farthest boundary reported [m], > 0: a column whose boundary is farther is `no_boundary`,
    /// as for a ranger whose ground table ends there. Default 10 (the default of
    /// `GroundTable.from_camera`).
    pub max_range_m: f64,
}

impl Default for TruthOptions {
    fn default() -> Self {
        Self { max_range_m: 10.0 }
    }
}

impl TruthOptions {
    pub fn validate(&self) -> Result<()> {
        check_range("max_range_m", self.max_range_m, 1e-6, 1e9)
    }
}

/// The truth of one image column.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ColumnTruth {
    /// Image column u [px].
    pub column: u32,
    /// `boundary`: floor up to an obstacle within range; `no_boundary`: the floor ends without
    /// an obstacle (at the horizon) or the obstacle is beyond `max_range_m`; `too_close`: the
    /// lowest pixel with a ray already sees an obstacle; `invalid`: the column has no ray, or
    /// its lowest ray does not see the floor or an obstacle.
    pub status: ColumnStatus,
    /// Boundary row [px, float] (edge line between the last floor pixel and the first
    /// obstacle pixel); NaN unless `boundary`.
    pub row: f64,
    /// The floor point at `row`, camera ground frame [m]: what an ideal visual range sensor
    /// reports. For an obstacle standing on the floor it is the foot of its face.
    pub point: Option<Point2>,
    /// `point` in the world frame [m].
    pub point_world: Option<Point2>,
    /// The obstacle surface point seen just above the boundary, world frame (x, y) [m], and
    /// its height `obstacle_z_m`. Equal to `point_world` (height 0) for faces standing on the
    /// floor; nearer than it for overhangs.
    pub obstacle_world: Option<Point2>,
    pub obstacle_z_m: f64,
    /// Appearance boundary row [px, float]: the edge line below the first pixel, from the
    /// bottom, that does not see the home covering (the floor covering under the camera); the
    /// lower edge of the lowest pixel (its row + 0.5) if that already differs; NaN if every
    /// pixel sees the home covering.
    pub appearance_row: f64,
    /// The floor point at `appearance_row` (camera ground frame) when the first differing
    /// pixel is floor with another covering (or paper); `None` otherwise.
    pub appearance_point: Option<Point2>,
}

/// The truth of one frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrameTruth {
    /// world_from_robot.
    pub pose: Pose2,
    /// world_from_camera (camera ground frame).
    pub world_from_camera: Pose2,
    pub columns: Vec<ColumnTruth>,
}

/// What a ray sees, coarsely.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Class {
    Floor(usize),
    Obstacle,
    Other,
}

struct Column<'a> {
    scene: &'a Scene,
    rays: &'a CameraRays,
    place: CameraPlacement,
    clear: &'a Clearance,
    u: u32,
}

impl Column<'_> {
    fn ray_at(&self, v: f64) -> Option<[f64; 3]> {
        let (w, h) = (self.rays.camera.width, self.rays.camera.height);
        let fv = v.round();
        let d = if fv == v && v >= 0.0 && (v as usize) < h {
            self.rays.dirs[v as usize * w + self.u as usize]
        } else {
            self.rays
                .camera
                .ray(self.u as f64, v)
                .unwrap_or([f64::NAN; 3])
        };
        (!d[0].is_nan()).then_some(d)
    }

    /// Class and hit of the exact ray through (u, v).
    fn classify(&self, v: f64) -> Option<(Class, crate::scene::Hit, [f64; 3])> {
        let d = self.ray_at(v)?;
        let dw = self.place.to_world(d);
        let (w, h) = (self.rays.camera.width, self.rays.camera.height);
        // Pixel centres have their azimuth precomputed; other rows compute it.
        let (azimuth, horizontal) = if v.fract() == 0.0 && v >= 0.0 && (v as usize) < h {
            let k = v as usize * w + self.u as usize;
            (
                self.rays.azimuth[k] + self.place.world_from_camera.yaw,
                self.rays.horizontal[k],
            )
        } else {
            (dw[1].atan2(dw[0]), (dw[0] * dw[0] + dw[1] * dw[1]).sqrt())
        };
        let sector = self.clear.sector(sector_of(azimuth));
        let hit = self
            .scene
            .trace_clear(self.place.origin, dw, sector, horizontal);
        let class = match hit.surface {
            Surface::Floor => Class::Floor(
                self.scene
                    .covering_at(Point2::new(hit.point[0], hit.point[1])),
            ),
            s if s.is_obstacle() => Class::Obstacle,
            _ => Class::Other,
        };
        Some((class, hit, d))
    }

    /// Bisects the edge between row `inside` (where `keep` holds) and row `outside` (above it).
    fn bisect(
        &self,
        mut inside: f64,
        mut outside: f64,
        keep: impl Fn(Class) -> bool,
    ) -> (f64, f64) {
        for _ in 0..30 {
            let mid = 0.5 * (inside + outside);
            match self.classify(mid) {
                Some((c, _, _)) if keep(c) => inside = mid,
                _ => outside = mid,
            }
        }
        (inside, outside)
    }

    fn ground_point(&self, d: [f64; 3]) -> Point2 {
        let t = self.rays.camera.mount.height_m / -d[2];
        Point2::new(t * d[0], t * d[1])
    }
}

/// The truth of one view (robot at `world_from_robot`).
pub fn frame_truth(
    scene: &Scene,
    rays: &CameraRays,
    world_from_robot: Pose2,
    options: &TruthOptions,
) -> FrameTruth {
    let place = CameraPlacement::new(rays, world_from_robot);
    let home = scene.covering_at(place.world_from_camera.translation());
    let clear = Clearance::new(
        &scene.world.solids,
        &scene.solid_bounds,
        place.world_from_camera.translation(),
    );
    let columns = (0..rays.camera.width as u32)
        .map(|u| {
            column_truth(
                &Column {
                    scene,
                    rays,
                    place,
                    clear: &clear,
                    u,
                },
                home,
                options,
            )
        })
        .collect();
    FrameTruth {
        pose: world_from_robot,
        world_from_camera: place.world_from_camera,
        columns,
    }
}

fn column_truth(col: &Column, home: usize, options: &TruthOptions) -> ColumnTruth {
    let h = col.rays.camera.height;
    let mut t = ColumnTruth {
        column: col.u,
        status: ColumnStatus::Invalid,
        row: f64::NAN,
        point: None,
        point_world: None,
        obstacle_world: None,
        obstacle_z_m: f64::NAN,
        appearance_row: f64::NAN,
        appearance_point: None,
    };
    // Rows from the bottom, starting at the lowest pixel with a ray.
    let Some(start) = (0..h).rev().find(|&v| col.ray_at(v as f64).is_some()) else {
        return t;
    };
    let mut status = None;
    let mut appearance_done = false;
    let mut last_floor: Option<usize> = None;
    for v in (0..=start).rev() {
        let Some((class, _, _)) = col.classify(v as f64) else {
            break;
        };
        if !appearance_done && class != Class::Floor(home) {
            appearance_done = true;
            // Every pixel below this one saw the home covering.
            match last_floor {
                Some(below) => {
                    let (inside, out) =
                        col.bisect(below as f64, v as f64, |c| c == Class::Floor(home));
                    t.appearance_row = 0.5 * (inside + out);
                    if let Some((Class::Floor(_), _, d)) = col.classify(out) {
                        t.appearance_point = Some(col.ground_point(d));
                    }
                }
                None => t.appearance_row = v as f64 + 0.5,
            }
        }
        match class {
            Class::Floor(_) => last_floor = Some(v),
            Class::Obstacle => {
                status = Some(match last_floor {
                    None => ColumnStatus::TooClose,
                    Some(below) => {
                        let (inside, outside) =
                            col.bisect(below as f64, v as f64, |c| matches!(c, Class::Floor(_)));
                        let floor_d = col.ray_at(inside).expect("bisection stays between rays");
                        let p = col.ground_point(floor_d);
                        if p.norm() > options.max_range_m {
                            ColumnStatus::NoBoundary
                        } else {
                            t.row = 0.5 * (inside + outside);
                            t.point = Some(p);
                            t.point_world = Some(col.place.world_from_camera.transform_point(p));
                            if let Some((_, hit, _)) = col.classify(outside) {
                                t.obstacle_world = Some(Point2::new(hit.point[0], hit.point[1]));
                                t.obstacle_z_m = hit.point[2].max(0.0);
                            }
                            ColumnStatus::Boundary
                        }
                    }
                });
            }
            Class::Other => {
                status = Some(if last_floor.is_some() {
                    ColumnStatus::NoBoundary
                } else {
                    ColumnStatus::Invalid
                });
            }
        }
        // A settled status means a pixel that is not floor, so the appearance is settled too.
        if status.is_some() {
            break;
        }
    }
    t.status = status.unwrap_or(if last_floor.is_some() {
        ColumnStatus::NoBoundary
    } else {
        ColumnStatus::Invalid
    });
    t
}

/// Header of the truth columns CSV (`truth/columns.csv` of a dataset, one line per frame and
/// image column; docs/dataset-format.md).
pub const COLUMNS_CSV_HEADER: &str = "timestamp,frame,column,status,row,x,y,world_x,world_y,obstacle_x,obstacle_y,obstacle_z,appearance_row,appearance_x,appearance_y";

/// Appends the truth CSV lines (no header) of frames with their timestamps [s]. Missing values
/// are written as `nan`.
pub fn write_columns_csv(frames: &[FrameTruth], timestamps_s: &[f64], out: &mut String) {
    use std::fmt::Write;
    let f = |v: f64| {
        if v.is_nan() {
            "nan".to_string()
        } else {
            format!("{v:.6}")
        }
    };
    let xy =
        |p: Option<Point2>| p.map_or(("nan".to_string(), "nan".to_string()), |p| (f(p.x), f(p.y)));
    for (k, (frame, t)) in frames.iter().zip(timestamps_s).enumerate() {
        for c in &frame.columns {
            let (x, y) = xy(c.point);
            let (wx, wy) = xy(c.point_world);
            let (ox, oy) = xy(c.obstacle_world);
            let (ax, ay) = xy(c.appearance_point);
            let _ = writeln!(
                out,
                "{t:.6},{k},{},{},{},{x},{y},{wx},{wy},{ox},{oy},{},{},{ax},{ay}",
                c.column,
                c.status.as_str(),
                f(c.row),
                f(c.obstacle_z_m),
                f(c.appearance_row),
            );
        }
    }
}

#[cfg(test)]
#[path = "truth_tests.rs"]
mod tests;
