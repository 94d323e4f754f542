//! A world prepared for rendering: solids broken into faces, a 2-D grid index of faces and floor
//! regions, and the floor's illumination. [`Scene::trace`] finds the first surface along a ray.

use floorscan_core::Point2;

use crate::cell_memo::CellMemo;
use crate::clearance::{SectorClear, NO_SOLID};
use crate::contact_shadow::{ShadowMap, STANDING_BASE_M};
use crate::geometry::{point_in_polygon, ray_segment, Aabb};
use crate::grid_index::{segment_cells, segment_meets_box, CellLists, CellWalk, GridShape};
use crate::lightmap::LightMap;
use crate::rng::fast_floor;
use crate::rng::splitmix64;
use crate::texture::PreparedCovering;
use crate::world::World;

/// A vertical face: the side of a solid between `z0` and `z1` along segment a-b.
#[derive(Debug, Clone, Copy)]
pub struct SideFace {
    pub a: Point2,
    pub b: Point2,
    pub z0: f64,
    pub z1: f64,
    pub solid: u32,
    pub length: f64,
    /// Texture seed of this face.
    pub seed: u64,
    /// How much of the main light this face catches: faces turned differently are lit
    /// differently (a fixed main light direction), see [`SideFace::turn_towards_light`].
    pub turn: f32,
}

impl SideFace {
    /// The shading factor of a face from `a` to `b` of length `length`: 0.88 + 0.12 times its
    /// outward normal along the main light's direction (0.6, 0.8).
    pub fn turn_towards_light(a: Point2, b: Point2, length: f64) -> f32 {
        let (nx, ny) = ((b.y - a.y) / length, -(b.x - a.x) / length);
        0.88 + 0.12 * (0.6 * nx + 0.8 * ny) as f32
    }
}

/// What a ray hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surface {
    /// Nothing (left the world without meeting floor, ceiling or solid).
    Nothing,
    Floor,
    Ceiling,
    /// Side face `face`, at offset `s` [m] along it.
    Side {
        face: u32,
        s: f64,
    },
    /// Top (`up`) or bottom face of a solid.
    Cap {
        solid: u32,
        up: bool,
    },
}

impl Surface {
    /// Whether this surface belongs to an obstacle (a solid).
    pub fn is_obstacle(&self) -> bool {
        matches!(self, Surface::Side { .. } | Surface::Cap { .. })
    }
}

/// The first surface along a ray: its parameter `t` [m, for a unit direction] and 3-D point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f64,
    pub surface: Surface,
    pub point: [f64; 3],
}

impl Hit {
    /// The hit at ray parameter `t` of `o + t d` on `surface`; nothing when `t` is infinite.
    fn at(o: [f64; 3], d: [f64; 3], t: f64, surface: Surface) -> Hit {
        if !t.is_finite() {
            return Hit {
                t: f64::INFINITY,
                surface: Surface::Nothing,
                point: [f64::NAN; 3],
            };
        }
        Hit {
            t,
            surface,
            point: [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]],
        }
    }
}

/// Grid cell size of the scene index [m].
pub const SCENE_CELL_M: f64 = 0.5;

/// A world prepared for ray casting.
#[derive(Debug, Clone)]
pub struct Scene {
    pub world: World,
    pub sides: Vec<SideFace>,
    pub shape: GridShape,
    /// Each grid cell's side faces and caps, as runs for the grid walk (faces four at a time).
    cell_runs: CellRuns,
    /// The items of each cell one by one (the tests' reference for `cell_runs`).
    #[cfg(test)]
    faces: CellLists,
    regions: CellLists,
    /// Per cell: the covering of the whole cell when one region (or none) decides it, else -1.
    cell_covering: Vec<i32>,
    pub light: LightMap,
    /// The floor's contact shadows (None: off, the default).
    pub shadow: Option<ShadowMap>,
    /// Bounds of each solid's footprint.
    pub solid_bounds: Vec<Aabb>,
    /// Side faces of each solid (indices into `sides`).
    solid_sides: Vec<std::ops::Range<u32>>,
    /// The side faces' end points in groups of four (each solid's faces in its own groups,
    /// the last one padded with NaN), for meeting a ray with four faces at once.
    face_quads: Vec<FaceQuad>,
    /// Each solid's groups (indices into `face_quads`).
    solid_quads: Vec<std::ops::Range<u32>>,
    /// 1 / the grid's cell size [1/m].
    inv_cell_m: f64,
    /// The grid's (nx, ny) as floats (a conversion per lookup otherwise).
    extent: (f64, f64),
    /// The world's coverings, prepared for shading (same indices).
    pub coverings: Vec<PreparedCovering>,
}

impl Scene {
    pub fn new(world: World) -> Scene {
        let b = world.bounds();
        let pad = 1.0;
        let bounds = Aabb {
            min: Point2::new(b.min.x - pad, b.min.y - pad),
            max: Point2::new(b.max.x + pad, b.max.y + pad),
        };
        let shape = GridShape::covering(bounds, SCENE_CELL_M, 1 << 20);
        let mut sides = Vec::new();
        let mut face_pairs = Vec::new();
        let mut solid_bounds = Vec::new();
        let mut solid_sides = Vec::with_capacity(world.solids.len());
        for (k, s) in world.solids.iter().enumerate() {
            let first = sides.len() as u32;
            let n = s.polygon.len();
            for e in 0..n {
                let (a, b) = (s.polygon[e], s.polygon[(e + 1) % n]);
                let length = (b.x - a.x).hypot(b.y - a.y);
                if length < 1e-12 {
                    continue;
                }
                let id = sides.len() as u32;
                for (i, j) in segment_cells(&shape, a, b) {
                    face_pairs.push((j * shape.nx + i, id));
                }
                sides.push(SideFace {
                    a,
                    b,
                    z0: s.base_m,
                    z1: s.top_m,
                    solid: k as u32,
                    length,
                    seed: splitmix64((k as u64) << 16 | e as u64),
                    turn: SideFace::turn_towards_light(a, b, length),
                });
            }
            solid_sides.push(first..sides.len() as u32);
            let bb = Aabb::of_points(&s.polygon);
            solid_bounds.push(bb);
            // Caps that no camera below the ceiling can see (floor-standing solids reaching the
            // ceiling: walls) are left out of the index.
            if s.base_m > 0.0 || s.top_m < world.ceiling_m {
                for (i, j) in shape.cells_overlapping(bb) {
                    face_pairs.push((j * shape.nx + i, k as u32 | CAP_BIT));
                }
            }
        }
        let mut region_pairs = Vec::new();
        for (k, r) in world.regions.iter().enumerate() {
            for (i, j) in shape.cells_overlapping(Aabb::of_points(&r.polygon)) {
                region_pairs.push((j * shape.nx + i, k as u32));
            }
        }
        // Light the floor well beyond the world (far floor seen through doorways).
        let lit = Aabb {
            min: Point2::new(bounds.min.x - 4.0, bounds.min.y - 4.0),
            max: Point2::new(bounds.max.x + 4.0, bounds.max.y + 4.0),
        };
        let light = LightMap::new(&world.lighting, lit, b);
        let standing: Vec<&[Point2]> = (world.solids.iter())
            .filter(|s| s.base_m <= STANDING_BASE_M)
            .map(|s| s.polygon.as_slice())
            .collect();
        let shadow = ShadowMap::new(world.lighting.contact_shadow, &standing);
        let regions = CellLists::build(shape.cell_count(), &region_pairs);
        let cell_covering = (0..shape.cell_count())
            .map(|cell| uniform_covering(&world, &shape, &regions, cell))
            .collect();
        let mut face_quads = Vec::new();
        let solid_quads = solid_sides
            .iter()
            .map(|r| {
                let first = face_quads.len() as u32;
                for chunk in sides[r.start as usize..r.end as usize].chunks(4) {
                    face_quads.push(FaceQuad::of(chunk));
                }
                first..face_quads.len() as u32
            })
            .collect();
        let faces = CellLists::build(shape.cell_count(), &face_pairs);
        let cell_runs = CellRuns::build(&faces, &sides, shape.cell_count());
        Scene {
            cell_runs,
            #[cfg(test)]
            faces,
            face_quads,
            solid_quads,
            regions,
            cell_covering,
            sides,
            shape,
            light,
            shadow,
            solid_bounds,
            coverings: world.coverings.iter().map(|c| c.prepare()).collect(),
            inv_cell_m: 1.0 / shape.cell_m,
            extent: (shape.nx as f64, shape.ny as f64),
            solid_sides,
            world,
        }
    }

    /// The contact shadows' light factor at a floor point (1 where there are none).
    #[inline(always)]
    pub fn shadow_at(&self, p: Point2) -> f32 {
        match &self.shadow {
            None => 1.0,
            Some(s) => s.at(p),
        }
    }

    /// The floor covering (index into `world.coverings`) at a floor point.
    pub fn covering_at(&self, p: Point2) -> usize {
        self.covering_cached(p, &mut CellMemo::default())
    }

    /// [`Self::covering_at`], remembering the last cell of one covering in `memo`.
    #[inline(always)]
    pub fn covering_cached(&self, p: Point2, memo: &mut CellMemo<usize>) -> usize {
        let gx = (p.x - self.shape.origin.x) * self.inv_cell_m;
        let gy = (p.y - self.shape.origin.y) * self.inv_cell_m;
        match memo.get(gx, gy) {
            Some(c) => c,
            None => self.covering_enter(p, gx, gy, memo),
        }
    }

    /// [`Self::covering_cached`] outside the remembered cell (out of line: the rarer path).
    #[inline(never)]
    fn covering_enter(&self, p: Point2, gx: f64, gy: f64, memo: &mut CellMemo<usize>) -> usize {
        if gx >= 0.0 && gy >= 0.0 && gx < self.extent.0 && gy < self.extent.1 {
            // In range (checked above): the fast floor is exact.
            let (ix, iy) = (fast_floor(gx), fast_floor(gy));
            let cell = iy as usize * self.shape.nx + ix as usize;
            if let Ok(c) = usize::try_from(self.cell_covering[cell]) {
                memo.set(ix, iy, c);
                return c;
            }
            for &r in self.regions.get(cell).iter().rev() {
                let region = &self.world.regions[r as usize];
                if point_in_polygon(p, &region.polygon) {
                    return region.covering;
                }
            }
        }
        self.world.floor_covering
    }

    /// Where the ray meets the floor or the ceiling (t, surface), if it does.
    #[inline]
    pub(crate) fn limit(&self, o: [f64; 3], d: [f64; 3]) -> (f64, Surface) {
        let ceiling = self.world.ceiling_m;
        if d[2] < -1e-12 && o[2] > 0.0 {
            (o[2] / -d[2], Surface::Floor)
        } else if d[2] > 1e-12 && o[2] < ceiling {
            ((ceiling - o[2]) / d[2], Surface::Ceiling)
        } else {
            (f64::INFINITY, Surface::Nothing)
        }
    }

    /// [`Self::trace_clear`] given the ray's [`Self::limit`] (the floor's, known per pixel).
    #[inline]
    pub(crate) fn trace_clear_from(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        sector: SectorClear,
        horizontal: f64,
        (t, surface): (f64, Surface),
    ) -> Hit {
        let free_m = sector.free_m;
        let at = |t: f64, surface| Hit {
            t,
            surface,
            point: [o[0] + t * d[0], o[1] + t * d[1], o[2] + t * d[2]],
        };
        if t.is_finite() && t * horizontal < free_m {
            return at(t, surface);
        }
        // Only the nearest solid reaches nearer than `second_m`: if the ray meets it (or the
        // floor or ceiling) within that distance, that is the first surface.
        if sector.nearest != NO_SOLID {
            let (ts, surface_s) = self.trace_solid(o, d, sector.nearest as usize);
            let (t, surface) = if ts < t {
                (ts, surface_s)
            } else {
                (t, surface)
            };
            if t.is_finite() && t * horizontal <= sector.second_m {
                return at(t, surface);
            }
        }
        // Nothing to meet before the clearance: start the grid walk there.
        let t0 = if horizontal > 1e-12 && free_m.is_finite() {
            (free_m / horizontal).max(0.0)
        } else {
            0.0
        };
        self.trace_after(o, d, t0)
    }
}

/// The covering of a whole grid cell if the topmost region overlapping it covers it entirely
/// (or no region overlaps it), else -1.
fn uniform_covering(world: &World, shape: &GridShape, regions: &CellLists, cell: usize) -> i32 {
    let list = regions.get(cell);
    let Some(&top) = list.last() else {
        return world.floor_covering as i32;
    };
    let region = &world.regions[top as usize];
    let c = shape.cell_m;
    let (i, j) = (cell % shape.nx, cell / shape.nx);
    let lo = Point2::new(shape.origin.x + i as f64 * c, shape.origin.y + j as f64 * c);
    let corners = [
        lo,
        Point2::new(lo.x + c, lo.y),
        Point2::new(lo.x + c, lo.y + c),
        Point2::new(lo.x, lo.y + c),
    ];
    let pad = 1e-9 * c;
    let cell_box = Aabb {
        min: Point2::new(lo.x - pad, lo.y - pad),
        max: Point2::new(lo.x + c + pad, lo.y + c + pad),
    };
    let n = region.polygon.len();
    let edges_cross =
        (0..n).any(|e| segment_meets_box(region.polygon[e], region.polygon[(e + 1) % n], cell_box));
    if !edges_cross
        && corners
            .iter()
            .all(|p| point_in_polygon(*p, &region.polygon))
    {
        region.covering as i32
    } else {
        -1
    }
}

#[path = "scene_faces.rs"]
mod faces;
use faces::{CellRun, CellRuns, FaceQuad, CAP_BIT};

#[path = "scene_trace.rs"]
mod trace_rays;

#[cfg(test)]
#[path = "scene_tests.rs"]
mod tests;
