//! A world: a 2-D floor plan with vertical structure. Everything the camera can see is one of
//! - the floor (z = 0), covered by floor coverings (a default one plus polygonal regions on top);
//! - solids: polygons extruded between a base and a top height (wall pieces, boxes, table legs,
//!   table tops, chair seats); a solid whose base is above the floor overhangs;
//! - the ceiling (z = `ceiling_m`).
//!
//! Worlds are built from world files ([`crate::world_file`]) or in code; [`World::new`] checks
//! them. Frames: world frame, REP 103 (x, y on the floor, z up), metres.

use floorscan_core::{Point2, Pose2};
use serde::{Deserialize, Serialize};

use crate::contact_shadow::ContactShadow;
use crate::error::{Error, Result};
use crate::geometry::{signed_area, Aabb};
use crate::texture::{Appearance, Covering};

/// A polygon extruded between `base_m` and `top_m`: an obstacle the robot cannot cross if its
/// base is below the robot's height.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Solid {
    /// Footprint, counter-clockwise, at least 3 vertices [m].
    pub polygon: Vec<Point2>,
    /// Height of the bottom face above the floor [m], >= 0 (0: it stands on the floor).
    pub base_m: f64,
    /// Height of the top face [m], > base_m.
    pub top_m: f64,
    /// Index into [`World::appearances`].
    pub appearance: usize,
    /// What it is, for people reading the truth ("wall", "box", "table", "chair").
    pub kind: String,
}

/// A floor region with its own covering; later regions lie on top of earlier ones.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FloorRegion {
    pub polygon: Vec<Point2>,
    /// Index into [`World::coverings`].
    pub covering: usize,
}

/// A ceiling light: illuminance on the floor below it is `power`, falling off as
/// (h^2 / (h^2 + d^2))^1.5 with horizontal distance d (a point source at height h).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Light {
    pub position: Point2,
    pub height_m: f64,
    pub power: f64,
}

/// Illumination of the world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Lighting {
    /// Illumination everywhere, from indirect light (same units as light power).
    pub ambient: f64,
    pub lights: Vec<Light>,
    /// Mean exposure, > 0: scales the whole image. At 1, a surface of albedo 0.9 under the
    /// world's median floor illumination reads 255 (as a camera's auto exposure would set it).
    pub exposure: f64,
    /// Standard deviation of the per-frame relative exposure change (log scale), >= 0.
    pub exposure_jitter: f64,
    /// Illumination of vertical faces relative to the floor below them.
    pub wall_factor: f64,
    /// Brightness (albedo times illumination) of the ceiling.
    pub ceiling_brightness: f64,
    /// The floor's darkening towards the foot of solids (off by default).
    #[serde(default)]
    pub contact_shadow: ContactShadow,
}

/// A validated world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct World {
    pub name: String,
    pub description: String,
    /// Height of the ceiling [m], > 0.
    pub ceiling_m: f64,
    /// Start pose of the robot base (world_from_robot).
    pub start: Pose2,
    /// Default waypoint tour of the robot [m], driven in order and repeated.
    pub tour: Vec<Point2>,
    pub solids: Vec<Solid>,
    pub regions: Vec<FloorRegion>,
    /// Covering of the floor outside every region (index into `coverings`).
    pub floor_covering: usize,
    pub coverings: Vec<Covering>,
    pub appearances: Vec<Appearance>,
    pub lighting: Lighting,
    /// The world file this world was read from, if any (kept for datasets' truth folder).
    #[serde(skip)]
    pub source: Option<String>,
}

fn bad(name: &str, reason: String) -> Error {
    Error::InvalidWorld {
        source_name: name.to_string(),
        reason,
    }
}

/// Farthest a world's geometry may lie from its origin [m]: the simulator's indexes and
/// rasters scale with the world's extent, so a wall to x = 1e12 is an error, not an allocation.
pub const MAX_WORLD_EXTENT_M: f64 = 2000.0;

/// Finite and within [`MAX_WORLD_EXTENT_M`] of the origin on both axes.
fn finite_point(p: Point2) -> bool {
    p.x.abs() <= MAX_WORLD_EXTENT_M && p.y.abs() <= MAX_WORLD_EXTENT_M
}

impl World {
    /// Checks the world and orients its polygons counter-clockwise.
    pub fn new(mut world: World) -> Result<World> {
        let name = world.name.clone();
        if !(world.ceiling_m > 0.0 && world.ceiling_m.is_finite()) {
            return Err(bad(
                &name,
                format!("ceiling_m: must be > 0, got {}", world.ceiling_m),
            ));
        }
        if !(world.start.is_finite() && finite_point(Point2::new(world.start.x, world.start.y))) {
            return Err(bad(
                &name,
                format!(
                    "start: pose must be finite and within {MAX_WORLD_EXTENT_M} m of the origin"
                ),
            ));
        }
        if let Some(i) = world.tour.iter().position(|p| !finite_point(*p)) {
            return Err(bad(
                &name,
                format!(
                    "tour[{i}]: must be finite and within {MAX_WORLD_EXTENT_M} m of the origin"
                ),
            ));
        }
        let n_app = world.appearances.len();
        for (i, s) in world.solids.iter_mut().enumerate() {
            check_polygon(&name, &format!("solids[{i}] ({})", s.kind), &mut s.polygon)?;
            if !(s.base_m >= 0.0 && s.top_m > s.base_m && s.top_m.is_finite()) {
                return Err(bad(
                    &name,
                    format!(
                        "solids[{i}] ({}): needs 0 <= base_m < top_m, got {} and {}",
                        s.kind, s.base_m, s.top_m
                    ),
                ));
            }
            if s.appearance >= n_app {
                return Err(bad(
                    &name,
                    format!("solids[{i}]: unknown appearance index {}", s.appearance),
                ));
            }
        }
        let n_cov = world.coverings.len();
        for (i, r) in world.regions.iter_mut().enumerate() {
            check_polygon(&name, &format!("regions[{i}]"), &mut r.polygon)?;
            if r.covering >= n_cov {
                return Err(bad(
                    &name,
                    format!("regions[{i}]: unknown covering index {}", r.covering),
                ));
            }
        }
        if world.floor_covering >= n_cov {
            return Err(bad(&name, "floor.covering: unknown covering".into()));
        }
        for c in &world.coverings {
            if !(c.albedo >= 0.0 && c.albedo <= 1.0) {
                return Err(bad(
                    &name,
                    format!(
                        "coverings.{}.brightness: must be in [0, 1], got {}",
                        c.name, c.albedo
                    ),
                ));
            }
        }
        for a in &world.appearances {
            if !(a.albedo >= 0.0 && a.albedo <= 1.0) {
                return Err(bad(
                    &name,
                    format!(
                        "appearances.{}.brightness: must be in [0, 1], got {}",
                        a.name, a.albedo
                    ),
                ));
            }
            if !(a.texture_m > 0.0 && a.texture_m.is_finite()) {
                return Err(bad(
                    &name,
                    format!("appearances.{}.texture_m: must be > 0", a.name),
                ));
            }
        }
        let l = &world.lighting;
        if !(l.ambient >= 0.0 && l.ambient.is_finite()) {
            return Err(bad(
                &name,
                format!("lighting.ambient: must be >= 0, got {}", l.ambient),
            ));
        }
        if !(l.exposure > 0.0 && l.exposure.is_finite()) {
            return Err(bad(
                &name,
                format!("lighting.exposure: must be > 0, got {}", l.exposure),
            ));
        }
        if !(l.exposure_jitter >= 0.0 && l.exposure_jitter <= 1.0) {
            return Err(bad(
                &name,
                format!(
                    "lighting.exposure_jitter: must be in [0, 1], got {}",
                    l.exposure_jitter
                ),
            ));
        }
        l.contact_shadow.validate().map_err(|m| bad(&name, m))?;
        for (i, light) in l.lights.iter().enumerate() {
            if !(finite_point(light.position)
                && light.height_m > 0.0
                && light.power >= 0.0
                && light.power.is_finite())
            {
                return Err(bad(
                    &name,
                    format!(
                        "lighting.lights[{i}]: needs a finite position (within {MAX_WORLD_EXTENT_M} m), height_m > 0, power >= 0"
                    ),
                ));
            }
        }
        Ok(world)
    }

    /// Bounding box of everything in the world [m] (solids, regions, start, tour).
    pub fn bounds(&self) -> Aabb {
        let mut b = Aabb::EMPTY.including(self.start.translation());
        for s in &self.solids {
            b = b.union(Aabb::of_points(&s.polygon));
        }
        for r in &self.regions {
            b = b.union(Aabb::of_points(&r.polygon));
        }
        for p in &self.tour {
            b = b.including(*p);
        }
        b
    }

    /// The covering index at a floor point (topmost region containing it, else the floor's).
    pub fn covering_at(&self, p: Point2) -> usize {
        self.regions
            .iter()
            .rev()
            .find(|r| crate::geometry::point_in_polygon(p, &r.polygon))
            .map_or(self.floor_covering, |r| r.covering)
    }
}

fn check_polygon(world: &str, what: &str, polygon: &mut [Point2]) -> Result<()> {
    if polygon.len() < 3 {
        return Err(bad(
            world,
            format!(
                "{what}: a polygon needs at least 3 points, got {}",
                polygon.len()
            ),
        ));
    }
    if let Some(i) = polygon.iter().position(|p| !finite_point(*p)) {
        return Err(bad(
            world,
            format!("{what}: point {i} is not finite or farther than {MAX_WORLD_EXTENT_M} m from the origin"),
        ));
    }
    let area = signed_area(polygon);
    if area.abs() < 1e-10 {
        return Err(bad(world, format!("{what}: polygon has zero area")));
    }
    if area < 0.0 {
        polygon.reverse();
    }
    Ok(())
}
