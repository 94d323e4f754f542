//! A world prepared for rendering: solids broken into faces, a 2-D grid index of faces and floor
//! regions, and the floor's illumination. [`Scene::trace`] finds the first surface along a ray.

use floorscan_core::Point2;

use crate::geometry::{point_in_polygon, ray_segment, Aabb};
use crate::grid_index::{segment_cells, CellLists, CellWalk, GridShape};
use crate::lightmap::LightMap;
use crate::rng::splitmix64;
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
}

/// What a ray hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Surface {
    /// Nothing (left the world without meeting floor, ceiling or solid).
    Nothing,
    Floor,
    Ceiling,
    /// Side face `face`, at offset `s` [m] along it.
    Side { face: u32, s: f64 },
    /// Top (`up`) or bottom face of a solid.
    Cap { solid: u32, up: bool },
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

/// Grid items: side faces are stored as their index, caps with this bit set.
const CAP_BIT: u32 = 1 << 31;

/// Grid cell size of the scene index [m].
pub const SCENE_CELL_M: f64 = 0.5;

/// A world prepared for ray casting.
#[derive(Debug, Clone)]
pub struct Scene {
    pub world: World,
    pub sides: Vec<SideFace>,
    pub shape: GridShape,
    faces: CellLists,
    regions: CellLists,
    pub light: LightMap,
    /// Bounds of each solid's footprint.
    pub solid_bounds: Vec<Aabb>,
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
        for (k, s) in world.solids.iter().enumerate() {
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
                });
            }
            let bb = Aabb::of_points(&s.polygon);
            solid_bounds.push(bb);
            for (i, j) in shape.cells_overlapping(bb) {
                face_pairs.push((j * shape.nx + i, k as u32 | CAP_BIT));
            }
        }
        let mut region_pairs = Vec::new();
        for (k, r) in world.regions.iter().enumerate() {
            for (i, j) in shape.cells_overlapping(Aabb::of_points(&r.polygon)) {
                region_pairs.push((j * shape.nx + i, k as u32));
            }
        }
        let light = LightMap::new(&world.lighting, shape.bounds());
        Scene {
            faces: CellLists::build(shape.cell_count(), &face_pairs),
            regions: CellLists::build(shape.cell_count(), &region_pairs),
            sides,
            shape,
            light,
            solid_bounds,
            world,
        }
    }

    /// The floor covering (index into `world.coverings`) at a floor point.
    pub fn covering_at(&self, p: Point2) -> usize {
        if let Some((i, j)) = self.shape.cell_of(p) {
            for &r in self.regions.get(j * self.shape.nx + i).iter().rev() {
                let region = &self.world.regions[r as usize];
                if point_in_polygon(p, &region.polygon) {
                    return region.covering;
                }
            }
        }
        self.world.floor_covering
    }

    /// The first surface along the ray from `o` in direction `d` (unit length; world frame).
    pub fn trace(&self, o: [f64; 3], d: [f64; 3]) -> Hit {
        let ceiling = self.world.ceiling_m;
        // The floor or the ceiling ends every ray that does not hit a solid first.
        let (t_limit, limit_surface) = if d[2] < -1e-12 && o[2] > 0.0 {
            (o[2] / -d[2], Surface::Floor)
        } else if d[2] > 1e-12 && o[2] < ceiling {
            ((ceiling - o[2]) / d[2], Surface::Ceiling)
        } else {
            (f64::INFINITY, Surface::Nothing)
        };
        let o2 = Point2::new(o[0], o[1]);
        let d2 = Point2::new(d[0], d[1]);
        let mut best_t = t_limit;
        let mut best = limit_surface;
        let mut walk = CellWalk::new(&self.shape, o2, d2);
        while let Some((cell, t_exit)) = walk.next_cell() {
            for &item in self.faces.get(cell) {
                if item & CAP_BIT == 0 {
                    let f = &self.sides[item as usize];
                    if let Some((t, s)) = ray_segment(o2, d2, f.a, f.b) {
                        if t < best_t {
                            let z = o[2] + t * d[2];
                            if z >= f.z0 && z <= f.z1 {
                                best_t = t;
                                best = Surface::Side { face: item, s: s * f.length };
                            }
                        }
                    }
                } else {
                    let k = (item & !CAP_BIT) as usize;
                    let s = &self.world.solids[k];
                    // A top face is seen from above, a bottom face (overhangs) from below.
                    let (z, up) = if o[2] > s.top_m && d[2] < 0.0 {
                        (s.top_m, true)
                    } else if o[2] < s.base_m && s.base_m > 0.0 && d[2] > 0.0 {
                        (s.base_m, false)
                    } else {
                        continue;
                    };
                    let t = (z - o[2]) / d[2];
                    if t < best_t {
                        let p = Point2::new(o[0] + t * d[0], o[1] + t * d[1]);
                        if self.solid_bounds[k].contains(p) && point_in_polygon(p, &s.polygon) {
                            best_t = t;
                            best = Surface::Cap { solid: k as u32, up };
                        }
                    }
                }
            }
            if best_t <= t_exit {
                break;
            }
        }
        if !best_t.is_finite() {
            return Hit { t: f64::INFINITY, surface: Surface::Nothing, point: [f64::NAN; 3] };
        }
        Hit {
            t: best_t,
            surface: best,
            point: [o[0] + best_t * d[0], o[1] + best_t * d[1], o[2] + best_t * d[2]],
        }
    }

    /// The same as [`Self::trace`] without the grid: every face tested (reference for tests).
    pub fn trace_brute_force(&self, o: [f64; 3], d: [f64; 3]) -> Hit {
        let ceiling = self.world.ceiling_m;
        let (mut best_t, mut best) = if d[2] < -1e-12 && o[2] > 0.0 {
            (o[2] / -d[2], Surface::Floor)
        } else if d[2] > 1e-12 && o[2] < ceiling {
            ((ceiling - o[2]) / d[2], Surface::Ceiling)
        } else {
            (f64::INFINITY, Surface::Nothing)
        };
        let o2 = Point2::new(o[0], o[1]);
        let d2 = Point2::new(d[0], d[1]);
        for (id, f) in self.sides.iter().enumerate() {
            if let Some((t, s)) = ray_segment(o2, d2, f.a, f.b) {
                let z = o[2] + t * d[2];
                if t < best_t && z >= f.z0 && z <= f.z1 {
                    best_t = t;
                    best = Surface::Side { face: id as u32, s: s * f.length };
                }
            }
        }
        for (k, s) in self.world.solids.iter().enumerate() {
            for (z, up) in [(s.top_m, true), (s.base_m, false)] {
                let visible = if up { o[2] > z && d[2] < 0.0 } else { z > 0.0 && o[2] < z && d[2] > 0.0 };
                if !visible {
                    continue;
                }
                let t = (z - o[2]) / d[2];
                let p = Point2::new(o[0] + t * d[0], o[1] + t * d[1]);
                if t < best_t && point_in_polygon(p, &s.polygon) {
                    best_t = t;
                    best = Surface::Cap { solid: k as u32, up };
                }
            }
        }
        if !best_t.is_finite() {
            return Hit { t: f64::INFINITY, surface: Surface::Nothing, point: [f64::NAN; 3] };
        }
        Hit { t: best_t, surface: best, point: [o[0] + best_t * d[0], o[1] + best_t * d[1], o[2] + best_t * d[2]] }
    }
}
