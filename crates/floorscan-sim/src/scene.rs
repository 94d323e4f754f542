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

/// Four side faces' end points, lane by lane (padding lanes NaN: never met).
#[derive(Debug, Clone, Copy)]
struct FaceQuad {
    ax: [f64; 4],
    ay: [f64; 4],
    bx: [f64; 4],
    by: [f64; 4],
}

impl FaceQuad {
    /// The first four of `faces` (NaN lanes after the last).
    fn of(faces: &[SideFace]) -> FaceQuad {
        let mut q = FaceQuad {
            ax: [f64::NAN; 4],
            ay: [f64::NAN; 4],
            bx: [f64::NAN; 4],
            by: [f64::NAN; 4],
        };
        for (lane, f) in faces.iter().take(4).enumerate() {
            (q.ax[lane], q.ay[lane]) = (f.a.x, f.a.y);
            (q.bx[lane], q.by[lane]) = (f.b.x, f.b.y);
        }
        q
    }

    /// [`ray_segment`] of the ground track o + t d with the four faces: a bit per lane
    /// whose face the track meets, and each lane's (t, s) (meaningful where met). Each
    /// lane does ray_segment's operations in its order (IEEE operations, no fused
    /// multiply-add), so the same bits.
    #[inline(always)]
    fn ray(&self, o: Point2, d: Point2) -> (u32, [f64; 4], [f64; 4]) {
        #[cfg(target_arch = "x86_64")]
        {
            // SSE2 is part of x86-64.
            self.ray_sse2(o, d)
        }
        #[cfg(not(target_arch = "x86_64"))]
        {
            self.ray_portable(o, d)
        }
    }

    /// [`Self::ray`] one lane at a time.
    #[cfg_attr(target_arch = "x86_64", allow(dead_code))]
    fn ray_portable(&self, o: Point2, d: Point2) -> (u32, [f64; 4], [f64; 4]) {
        let mut met = 0u32;
        let (mut ts, mut ss) = ([0.0; 4], [0.0; 4]);
        for lane in 0..4 {
            let (a, b) = (
                Point2::new(self.ax[lane], self.ay[lane]),
                Point2::new(self.bx[lane], self.by[lane]),
            );
            if let Some((t, s)) = ray_segment(o, d, a, b) {
                met |= 1 << lane;
                (ts[lane], ss[lane]) = (t, s);
            }
        }
        (met, ts, ss)
    }

    /// [`Self::ray`] in two SSE2 registers of two lanes.
    #[cfg(target_arch = "x86_64")]
    #[inline(always)]
    fn ray_sse2(&self, o: Point2, d: Point2) -> (u32, [f64; 4], [f64; 4]) {
        use std::arch::x86_64::*;
        // SAFETY (every block below): SSE2 is part of x86-64; the loads and stores are of
        // [f64; 4] arrays at offsets 0 and 2 (two f64 each, unaligned).
        unsafe {
            let (ox, oy) = (_mm_set1_pd(o.x), _mm_set1_pd(o.y));
            let (dx, dy) = (_mm_set1_pd(d.x), _mm_set1_pd(d.y));
            let sign = _mm_set1_pd(-0.0);
            let (zero, tiny) = (_mm_setzero_pd(), _mm_set1_pd(1e-300));
            let mut met = 0u32;
            let (mut ts, mut ss) = ([0.0f64; 4], [0.0f64; 4]);
            let mut parts = [(zero, zero, zero); 2];
            for (half, part) in parts.iter_mut().enumerate() {
                let at = |v: &[f64; 4]| _mm_loadu_pd(v.as_ptr().add(2 * half));
                let (ax, ay, bx, by) = (at(&self.ax), at(&self.ay), at(&self.bx), at(&self.by));
                let (ex, ey) = (_mm_sub_pd(bx, ax), _mm_sub_pd(by, ay));
                let denom = _mm_sub_pd(_mm_mul_pd(dx, ey), _mm_mul_pd(dy, ex));
                let (wx, wy) = (_mm_sub_pd(ax, ox), _mm_sub_pd(ay, oy));
                let tn = _mm_sub_pd(_mm_mul_pd(wx, ey), _mm_mul_pd(wy, ex));
                let sn = _mm_sub_pd(_mm_mul_pd(wx, dy), _mm_mul_pd(wy, dx));
                // Negated (the sign bit flipped) where denom < 0.
                let flip = _mm_and_pd(_mm_cmplt_pd(denom, zero), sign);
                let (tn, sn, dn) = (
                    _mm_xor_pd(tn, flip),
                    _mm_xor_pd(sn, flip),
                    _mm_xor_pd(denom, flip),
                );
                let ok = _mm_and_pd(
                    _mm_and_pd(_mm_cmpgt_pd(dn, tiny), _mm_cmpge_pd(tn, zero)),
                    _mm_and_pd(_mm_cmpge_pd(sn, zero), _mm_cmple_pd(sn, dn)),
                );
                met |= (_mm_movemask_pd(ok) as u32) << (2 * half);
                *part = (tn, sn, dn);
            }
            if met != 0 {
                let one = _mm_set1_pd(1.0);
                for (half, &(tn, sn, dn)) in parts.iter().enumerate() {
                    let inv = _mm_div_pd(one, dn);
                    _mm_storeu_pd(ts.as_mut_ptr().add(2 * half), _mm_mul_pd(tn, inv));
                    _mm_storeu_pd(ss.as_mut_ptr().add(2 * half), _mm_mul_pd(sn, inv));
                }
            }
            (met, ts, ss)
        }
    }
}

/// A run of a grid cell's items: up to four side faces in a row (`ids`; the quad's lanes
/// beyond them NaN, never met), or the cap of a solid.
#[derive(Debug, Clone, Copy)]
enum CellRun {
    Faces { quad: FaceQuad, ids: [u32; 4] },
    Cap(u32),
}

/// Each grid cell's items as runs, in the cell's order (faces grouped four by four between
/// caps).
#[derive(Debug, Clone)]
struct CellRuns {
    offsets: Vec<u32>,
    runs: Vec<CellRun>,
}

impl CellRuns {
    fn build(cells: &CellLists, sides: &[SideFace], cell_count: usize) -> CellRuns {
        let mut offsets = Vec::with_capacity(cell_count + 1);
        let mut runs = Vec::new();
        offsets.push(0);
        for cell in 0..cell_count {
            let mut faces: Vec<u32> = Vec::with_capacity(4);
            let flush = |faces: &mut Vec<u32>, runs: &mut Vec<CellRun>| {
                if !faces.is_empty() {
                    let group: Vec<SideFace> = faces.iter().map(|&id| sides[id as usize]).collect();
                    let mut ids = [u32::MAX; 4];
                    ids[..faces.len()].copy_from_slice(faces);
                    runs.push(CellRun::Faces {
                        quad: FaceQuad::of(&group),
                        ids,
                    });
                    faces.clear();
                }
            };
            for &item in cells.get(cell) {
                if item & CAP_BIT == 0 {
                    faces.push(item);
                    if faces.len() == 4 {
                        flush(&mut faces, &mut runs);
                    }
                } else {
                    flush(&mut faces, &mut runs);
                    runs.push(CellRun::Cap(item & !CAP_BIT));
                }
            }
            flush(&mut faces, &mut runs);
            offsets.push(runs.len() as u32);
        }
        CellRuns { offsets, runs }
    }

    #[inline]
    fn get(&self, cell: usize) -> &[CellRun] {
        &self.runs[self.offsets[cell] as usize..self.offsets[cell + 1] as usize]
    }
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

    /// [`Self::trace`] for a ray whose ground track is free of solids for `free_m` [m]
    /// (its sector's [`crate::clearance::Clearance`]); `horizontal` is the length of the
    /// horizontal part of `d`. Rays ending on the floor or ceiling within that distance skip
    /// the grid walk; the result is the same.
    #[inline]
    pub fn trace_clear(
        &self,
        o: [f64; 3],
        d: [f64; 3],
        sector: SectorClear,
        horizontal: f64,
    ) -> Hit {
        self.trace_clear_from(o, d, sector, horizontal, self.limit(o, d))
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

    /// The first face of solid `k` along the ray: (t, surface), t infinite if none.
    fn trace_solid(&self, o: [f64; 3], d: [f64; 3], k: usize) -> (f64, Surface) {
        let o2 = Point2::new(o[0], o[1]);
        let d2 = Point2::new(d[0], d[1]);
        let mut best = (f64::INFINITY, Surface::Nothing);
        // The faces four at a time (ray_segment in lanes), then each face that the ray meets
        // in their order, as one face at a time would.
        let mut id = self.solid_sides[k].start;
        for quad in
            &self.face_quads[self.solid_quads[k].start as usize..self.solid_quads[k].end as usize]
        {
            let (met, ts, ss) = quad.ray(o2, d2);
            for lane in 0..4 {
                if met & 1 << lane != 0 {
                    let f = &self.sides[id as usize + lane];
                    let t = ts[lane];
                    let z = o[2] + t * d[2];
                    if t < best.0 && z >= f.z0 && z <= f.z1 {
                        best = (
                            t,
                            Surface::Side {
                                face: id + lane as u32,
                                s: ss[lane] * f.length,
                            },
                        );
                    }
                }
            }
            id += 4;
        }
        let s = &self.world.solids[k];
        let (z, up) = if o[2] > s.top_m && d[2] < 0.0 {
            (s.top_m, true)
        } else if o[2] < s.base_m && s.base_m > 0.0 && d[2] > 0.0 {
            (s.base_m, false)
        } else {
            return best;
        };
        let t = (z - o[2]) / d[2];
        if t < best.0 {
            let p = Point2::new(o[0] + t * d[0], o[1] + t * d[1]);
            if point_in_polygon(p, &s.polygon) {
                best = (
                    t,
                    Surface::Cap {
                        solid: k as u32,
                        up,
                    },
                );
            }
        }
        best
    }

    /// The first surface along the ray from `o` in direction `d` (unit length; world frame).
    pub fn trace(&self, o: [f64; 3], d: [f64; 3]) -> Hit {
        self.trace_after(o, d, 0.0)
    }

    /// [`Self::trace`] for a ray known to meet no solid before `t0`.
    fn trace_after(&self, o: [f64; 3], d: [f64; 3], t0: f64) -> Hit {
        // The floor or the ceiling ends every ray that does not hit a solid first.
        let (t_limit, limit_surface) = self.limit(o, d);
        let o2 = Point2::new(o[0], o[1]);
        let d2 = Point2::new(d[0], d[1]);
        let mut best_t = t_limit;
        let mut best = limit_surface;
        let mut walk = CellWalk::starting_at(&self.shape, o2, d2, t0);
        while let Some((cell, t_exit)) = walk.next_cell() {
            // The cell's items in their order: side faces four at a time (lanes), caps.
            for run in self.cell_runs.get(cell) {
                match *run {
                    CellRun::Faces { ref quad, ids } => {
                        let (met, ts, ss) = quad.ray(o2, d2);
                        if met == 0 {
                            continue;
                        }
                        for lane in 0..4 {
                            let t = ts[lane];
                            if met & 1 << lane != 0 && t < best_t {
                                let f = &self.sides[ids[lane] as usize];
                                let z = o[2] + t * d[2];
                                if z >= f.z0 && z <= f.z1 {
                                    best_t = t;
                                    best = Surface::Side {
                                        face: ids[lane],
                                        s: ss[lane] * f.length,
                                    };
                                }
                            }
                        }
                    }
                    CellRun::Cap(k) => {
                        let k = k as usize;
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
                                best = Surface::Cap {
                                    solid: k as u32,
                                    up,
                                };
                            }
                        }
                    }
                }
            }
            if best_t <= t_exit {
                break;
            }
        }
        Hit::at(o, d, best_t, best)
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
                    best = Surface::Side {
                        face: id as u32,
                        s: s * f.length,
                    };
                }
            }
        }
        for (k, s) in self.world.solids.iter().enumerate() {
            for (z, up) in [(s.top_m, true), (s.base_m, false)] {
                let visible = if up {
                    o[2] > z && d[2] < 0.0
                } else {
                    z > 0.0 && o[2] < z && d[2] > 0.0
                };
                if !visible {
                    continue;
                }
                let t = (z - o[2]) / d[2];
                let p = Point2::new(o[0] + t * d[0], o[1] + t * d[1]);
                if t < best_t && point_in_polygon(p, &s.polygon) {
                    best_t = t;
                    best = Surface::Cap {
                        solid: k as u32,
                        up,
                    };
                }
            }
        }
        Hit::at(o, d, best_t, best)
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

#[cfg(test)]
#[path = "scene_tests.rs"]
mod tests;
