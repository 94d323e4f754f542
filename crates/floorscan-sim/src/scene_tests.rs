//! Tests of [`super`] (scene.rs).

use super::*;
use crate::builtin::builtin_world;
use crate::rng::Rng;

#[test]
fn face_quads_meet_rays_as_ray_segment_bit_for_bit() {
    // Random faces and rays, with rays through end points, along a face, from a point on
    // it, parallel to it, and quads padded with NaN lanes; the SSE2 lanes (x86-64) and
    // the portable loop against ray_segment, face by face.
    let mut rng = Rng::new(12);
    let p = |rng: &mut Rng| Point2::new(8.0 * rng.uniform() - 4.0, 8.0 * rng.uniform() - 4.0);
    let face = |a: Point2, b: Point2| SideFace {
        a,
        b,
        z0: 0.0,
        z1: 1.0,
        solid: 0,
        length: 1.0,
        seed: 0,
        turn: 1.0,
    };
    let mut checked = [0usize; 2];
    for i in 0..20_000 {
        let n = 1 + i % 4;
        let faces: Vec<SideFace> = (0..n).map(|_| face(p(&mut rng), p(&mut rng))).collect();
        let o = p(&mut rng);
        let target = match i % 5 {
            0 => faces[0].a,
            1 => faces[0].b,
            _ => p(&mut rng),
        };
        let mut d = Point2::new(target.x - o.x, target.y - o.y);
        if i % 7 == 0 {
            // Parallel to the first face.
            d = Point2::new(faces[0].b.x - faces[0].a.x, faces[0].b.y - faces[0].a.y);
        }
        let o = if i % 11 == 0 { faces[0].a } else { o };
        let quad = FaceQuad::of(&faces);
        #[cfg(target_arch = "x86_64")]
        let results = vec![quad.ray_portable(o, d), quad.ray_sse2(o, d)];
        #[cfg(not(target_arch = "x86_64"))]
        let results = vec![quad.ray_portable(o, d)];
        for (met, ts, ss) in results {
            for lane in 0..4 {
                let want = faces.get(lane).and_then(|f| ray_segment(o, d, f.a, f.b));
                match want {
                    Some((t, s)) => {
                        assert!(met & 1 << lane != 0, "{i} lane {lane}");
                        assert_eq!(
                            (ts[lane].to_bits(), ss[lane].to_bits()),
                            (t.to_bits(), s.to_bits())
                        );
                        checked[0] += 1;
                    }
                    None => {
                        assert!(met & 1 << lane == 0, "{i} lane {lane}");
                        checked[1] += 1;
                    }
                }
            }
        }
    }
    assert!(checked[0] > 5_000 && checked[1] > 5_000, "{checked:?}");
}

/// The grid walk testing the cell's items one by one (the code before the runs).
fn trace_items(scene: &Scene, o: [f64; 3], d: [f64; 3]) -> Hit {
    let (t_limit, limit_surface) = scene.limit(o, d);
    let o2 = Point2::new(o[0], o[1]);
    let d2 = Point2::new(d[0], d[1]);
    let (mut best_t, mut best) = (t_limit, limit_surface);
    let mut walk = CellWalk::starting_at(&scene.shape, o2, d2, 0.0);
    while let Some((cell, t_exit)) = walk.next_cell() {
        for &item in scene.faces.get(cell) {
            if item & CAP_BIT == 0 {
                let f = &scene.sides[item as usize];
                if let Some((t, s)) = ray_segment(o2, d2, f.a, f.b) {
                    let z = o[2] + t * d[2];
                    if t < best_t && z >= f.z0 && z <= f.z1 {
                        best_t = t;
                        best = Surface::Side {
                            face: item,
                            s: s * f.length,
                        };
                    }
                }
            } else {
                let k = (item & !CAP_BIT) as usize;
                let s = &scene.world.solids[k];
                let (z, up) = if o[2] > s.top_m && d[2] < 0.0 {
                    (s.top_m, true)
                } else if o[2] < s.base_m && s.base_m > 0.0 && d[2] > 0.0 {
                    (s.base_m, false)
                } else {
                    continue;
                };
                let t = (z - o[2]) / d[2];
                let p = Point2::new(o[0] + t * d[0], o[1] + t * d[1]);
                if t < best_t
                    && scene.solid_bounds[k].contains(p)
                    && point_in_polygon(p, &s.polygon)
                {
                    best_t = t;
                    best = Surface::Cap {
                        solid: k as u32,
                        up,
                    };
                }
            }
        }
        if best_t <= t_exit {
            break;
        }
    }
    Hit::at(o, d, best_t, best)
}

#[test]
fn cell_runs_walk_as_the_items_one_by_one_bit_for_bit() {
    for name in crate::builtin::builtin_names() {
        let scene = Scene::new(builtin_world(name).unwrap());
        // The runs hold each cell's items in order.
        for cell in 0..scene.shape.cell_count() {
            let items: Vec<u32> = scene
                .cell_runs
                .get(cell)
                .iter()
                .flat_map(|run| match *run {
                    CellRun::Faces { ids, .. } => {
                        ids.into_iter().filter(|&id| id != u32::MAX).collect()
                    }
                    CellRun::Cap(k) => vec![k | CAP_BIT],
                })
                .collect();
            assert_eq!(items, scene.faces.get(cell), "{name} cell {cell}");
        }
        // Random rays (from the camera heights, looking anywhere): the same hit, bits.
        let b = scene.world.bounds();
        let mut rng = Rng::new(8);
        for _ in 0..4000 {
            let o = [
                b.min.x + rng.uniform() * (b.max.x - b.min.x),
                b.min.y + rng.uniform() * (b.max.y - b.min.y),
                0.05 + rng.uniform() * 1.5,
            ];
            let (az, el) = (
                rng.uniform() * std::f64::consts::TAU,
                (rng.uniform() - 0.5) * 3.0,
            );
            let d = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
            let (got, want) = (scene.trace(o, d), trace_items(&scene, o, d));
            assert_eq!(got.t.to_bits(), want.t.to_bits(), "{name} {o:?} {d:?}");
            assert_eq!(got.surface, want.surface, "{name} {o:?} {d:?}");
        }
    }
}

#[test]
fn grid_trace_agrees_with_brute_force_in_every_builtin_world() {
    for name in crate::builtin::builtin_names() {
        let scene = Scene::new(builtin_world(name).unwrap());
        let b = scene.world.bounds();
        let mut rng = Rng::new(42);
        for _ in 0..4000 {
            let o = [
                b.min.x + rng.uniform() * (b.max.x - b.min.x),
                b.min.y + rng.uniform() * (b.max.y - b.min.y),
                0.05 + rng.uniform() * 1.5,
            ];
            let (az, el) = (
                rng.uniform() * std::f64::consts::TAU,
                (rng.uniform() - 0.5) * 3.0,
            );
            let d = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
            let (fast, slow) = (scene.trace(o, d), scene.trace_brute_force(o, d));
            assert!(
                (fast.t - slow.t).abs() < 1e-9 || (fast.t.is_infinite() && slow.t.is_infinite()),
                "{name}: {o:?} {d:?}: {fast:?} vs {slow:?}"
            );
            assert_eq!(
                fast.surface.is_obstacle(),
                slow.surface.is_obstacle(),
                "{name}: {fast:?} vs {slow:?}"
            );
        }
    }
}

#[test]
fn floor_regions_are_found_through_the_grid() {
    let scene = Scene::new(builtin_world("lab").unwrap());
    let mut rng = Rng::new(1);
    let b = scene.world.bounds();
    for _ in 0..5000 {
        let p = Point2::new(
            b.min.x + rng.uniform() * (b.max.x - b.min.x),
            b.min.y + rng.uniform() * (b.max.y - b.min.y),
        );
        assert_eq!(scene.covering_at(p), scene.world.covering_at(p));
    }
}
