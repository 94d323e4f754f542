//! Rays through a scene: the grid walk over each cell's face quads and caps to the first
//! surface (a solid's side or cap, the floor, the ceiling), the clear-path test, and the brute
//! force reference.

use super::*;

impl Scene {
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

    /// The first face of solid `k` along the ray: (t, surface), t infinite if none.
    pub(super) fn trace_solid(&self, o: [f64; 3], d: [f64; 3], k: usize) -> (f64, Surface) {
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
    pub(super) fn trace_after(&self, o: [f64; 3], d: [f64; 3], t0: f64) -> Hit {
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
