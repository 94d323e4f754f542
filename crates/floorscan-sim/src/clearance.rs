//! Per-view free space around the camera, in azimuth sectors: for each sector (wedge) the
//! distance within which no solid's footprint reaches into it. A ray whose floor or ceiling hit
//! lies nearer than its sector's clearance cannot be blocked by a solid, so it needs no walk
//! through the grid. This is exact (the clearance is a lower bound), and it is what makes
//! rendering fast: most pixels see open floor.
//!
//! Each sector also remembers which solid is nearest and how far the nearest *other* solid is:
//! a ray that meets the nearest solid before that distance has met its first surface, found by
//! testing that solid's faces alone.

use floorscan_core::Point2;

use crate::geometry::{point_in_polygon, Aabb};
use crate::world::Solid;

/// Number of azimuth sectors (0.18 degrees each).
pub const SECTORS: usize = 2048;

/// Clearance per azimuth sector around one camera position.
#[derive(Debug, Clone)]
pub struct Clearance {
    /// Horizontal distance [m] within which each sector is free of solids (0: unknown).
    pub free_m: Vec<f64>,
    /// The solid nearest in each sector ([`NO_SOLID`] if none or unknown).
    pub nearest: Vec<u32>,
    /// Horizontal distance [m] within which each sector holds no solid but `nearest`.
    pub second_m: Vec<f64>,
}

/// No solid in the sector (or no shortcut possible).
pub const NO_SOLID: u32 = u32::MAX;

/// What a ray's sector says about it.
#[derive(Debug, Clone, Copy)]
pub struct SectorClear {
    pub free_m: f64,
    pub nearest: u32,
    pub second_m: f64,
}

const SECTOR_RAD: f64 = std::f64::consts::TAU / SECTORS as f64;

/// The sector of an azimuth [rad] (any value).
#[inline]
pub fn sector_of(azimuth: f64) -> usize {
    let k = crate::rng::fast_floor(azimuth / SECTOR_RAD).rem_euclid(SECTORS as i64);
    k as usize
}

impl Clearance {
    /// Clearance around the point `o` (world frame) among `solids` (with their bounding
    /// boxes, `bounds[k]` of `solids[k]`).
    pub fn new(solids: &[Solid], bounds: &[Aabb], o: Point2) -> Clearance {
        let mut c = Clearance {
            free_m: vec![f64::INFINITY; SECTORS],
            nearest: vec![NO_SOLID; SECTORS],
            second_m: vec![f64::INFINITY; SECTORS],
        };
        for (k, (s, &b)) in solids.iter().zip(bounds).enumerate() {
            if b.contains(o) && point_in_polygon(o, &s.polygon) {
                // The camera is above or below this solid (under a table): no shortcut.
                return Clearance {
                    free_m: vec![0.0; SECTORS],
                    nearest: vec![NO_SOLID; SECTORS],
                    second_m: vec![0.0; SECTORS],
                };
            }
            let n = s.polygon.len();
            for e in 0..n {
                let a = s.polygon[e];
                let b = s.polygon[(e + 1) % n];
                c.shade_segment(
                    k as u32,
                    Point2::new(a.x - o.x, a.y - o.y),
                    Point2::new(b.x - o.x, b.y - o.y),
                );
            }
        }
        c
    }

    /// The clearance of sector `k`.
    #[inline]
    pub fn sector(&self, k: usize) -> SectorClear {
        SectorClear {
            free_m: self.free_m[k],
            nearest: self.nearest[k],
            second_m: self.second_m[k],
        }
    }

    /// Records that `solid` reaches into sector `k` at distance `d`.
    #[inline]
    fn record(&mut self, k: usize, solid: u32, d: f64) {
        if d < self.free_m[k] {
            if self.nearest[k] != solid {
                self.second_m[k] = self.free_m[k];
                self.nearest[k] = solid;
            }
            self.free_m[k] = d;
        } else if self.nearest[k] != solid && d < self.second_m[k] {
            self.second_m[k] = d;
        }
    }
}

impl Clearance {
    /// The clearance of every azimuth within `spread_rad` of `azimuth` [rad] (the smallest of
    /// their sectors'): for rays known only to lie near an azimuth.
    pub fn within(&self, azimuth: f64, spread_rad: f64) -> SectorClear {
        let k0 = crate::rng::fast_floor((azimuth - spread_rad) / SECTOR_RAD);
        let k1 =
            crate::rng::fast_floor((azimuth + spread_rad) / SECTOR_RAD).min(k0 + SECTORS as i64);
        let first = self.sector(k0.rem_euclid(SECTORS as i64) as usize);
        (k0 + 1..=k1).fold(first, |acc, k| {
            let s = self.sector(k.rem_euclid(SECTORS as i64) as usize);
            // One nearest solid for the whole range, or none.
            let (nearest, second_m) = if s.nearest == acc.nearest {
                (acc.nearest, acc.second_m.min(s.second_m))
            } else {
                (NO_SOLID, 0.0)
            };
            SectorClear {
                free_m: acc.free_m.min(s.free_m),
                nearest,
                second_m,
            }
        })
    }
}

/// Unit vector along sector boundary k (any integer; boundaries repeat every SECTORS).
fn boundary(k: i64) -> Point2 {
    static TABLE: std::sync::OnceLock<Vec<Point2>> = std::sync::OnceLock::new();
    let table = TABLE.get_or_init(|| {
        (0..SECTORS)
            .map(|k| {
                let phi = k as f64 * SECTOR_RAD;
                Point2::new(phi.cos(), phi.sin())
            })
            .collect()
    });
    table[k.rem_euclid(SECTORS as i64) as usize]
}

impl Clearance {
    /// Lowers the clearance of every sector the segment a-b (relative to the camera) of `solid`
    /// reaches into to the segment's nearest distance within that sector.
    fn shade_segment(&mut self, solid: u32, a: Point2, b: Point2) {
        let e = Point2::new(b.x - a.x, b.y - a.y);
        let len2 = e.x * e.x + e.y * e.y;
        if len2 <= 0.0 {
            return;
        }
        // Squared distance to the origin along the segment is a quadratic in s in [0, 1].
        let dist2 = |s: f64| {
            let p = Point2::new(a.x + s * e.x, a.y + s * e.y);
            p.x * p.x + p.y * p.y
        };
        let s_foot = (-(a.x * e.x + a.y * e.y) / len2).clamp(0.0, 1.0);
        let nearest = dist2(s_foot).sqrt();
        if nearest < 1e-9 {
            // The segment passes through the camera: nothing is clear.
            self.free_m.iter_mut().for_each(|f| *f = 0.0);
            self.nearest.iter_mut().for_each(|n| *n = NO_SOLID);
            self.second_m.iter_mut().for_each(|f| *f = 0.0);
            return;
        }
        let (za, zb) = (a.y.atan2(a.x), b.y.atan2(b.x));
        // The segment spans the shorter way between its endpoints' azimuths (it does not contain
        // the origin).
        let mut span = zb - za;
        if span > std::f64::consts::PI {
            span -= std::f64::consts::TAU;
        } else if span < -std::f64::consts::PI {
            span += std::f64::consts::TAU;
        }
        let (start, end) = if span >= 0.0 {
            (za, za + span)
        } else {
            (za + span, za)
        };
        let k0 = crate::rng::fast_floor(start / SECTOR_RAD);
        let k1 = crate::rng::fast_floor(end / SECTOR_RAD);
        // Parameter where the segment's line meets the ray of sector boundary k.
        let s_at = |k: i64| {
            let u = boundary(k);
            let den = u.x * e.y - u.y * e.x;
            if den.abs() < 1e-300 {
                f64::NAN
            } else {
                -(u.x * a.y - u.y * a.x) / den
            }
        };
        let mut s_lo = s_at(k0);
        for k in k0..=k1 {
            let s_hi = s_at(k + 1);
            // The piece of the segment inside this wedge: between the two boundary crossings,
            // clamped to the segment (its ends lie in the first and last wedges).
            let (mut lo, mut hi) = if s_lo.is_nan() || s_hi.is_nan() {
                (0.0, 1.0)
            } else {
                (s_lo.min(s_hi), s_lo.max(s_hi))
            };
            lo = lo.clamp(0.0, 1.0);
            hi = hi.clamp(0.0, 1.0);
            if k0 == k1 {
                (lo, hi) = (0.0, 1.0);
            } else if k == k0 || k == k1 {
                // Wedges holding an endpoint: include it.
                let s_end = if (k == k0) == (span >= 0.0) { 0.0 } else { 1.0 };
                lo = lo.min(s_end);
                hi = hi.max(s_end);
            }
            let d = if (lo..=hi).contains(&s_foot) {
                nearest
            } else {
                dist2(lo).min(dist2(hi)).sqrt()
            };
            // A hair less, so rounding can never make a blocked ray look clear.
            let d = d * (1.0 - 1e-9) - 1e-9;
            self.record(k.rem_euclid(SECTORS as i64) as usize, solid, d);
            s_lo = s_hi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::builtin_world;
    use crate::rng::Rng;
    use crate::scene::Scene;

    #[test]
    fn clearance_is_a_lower_bound_of_the_first_solid_along_any_ray() {
        for name in ["corridor", "room", "lab"] {
            let scene = Scene::new(builtin_world(name).unwrap());
            let mut rng = Rng::new(3);
            let o = scene.world.start.translation();
            let c = Clearance::new(&scene.world.solids, &scene.solid_bounds, o);
            for _ in 0..20_000 {
                let az = rng.uniform() * std::f64::consts::TAU;
                let d = [az.cos(), az.sin(), 0.0];
                // A horizontal ray at a low height meets the first solid standing on the floor.
                let hit = scene.trace_brute_force([o.x, o.y, 0.01], d);
                if hit.surface.is_obstacle() {
                    assert!(
                        hit.t >= c.free_m[sector_of(az)],
                        "{name}: az {az}: hit {} < {}",
                        hit.t,
                        c.free_m[sector_of(az)]
                    );
                }
            }
            // And it is useful: most sectors are clear for at least 0.3 m.
            let clear = c.free_m.iter().filter(|&&f| f > 0.3).count();
            assert!(clear > SECTORS / 2, "{name}: {clear}");
        }
    }

    #[test]
    fn shortcut_traces_agree_with_brute_force() {
        for name in crate::builtin::builtin_names() {
            let scene = Scene::new(builtin_world(name).unwrap());
            let mut rng = Rng::new(9);
            let b = scene.world.bounds();
            for _ in 0..40 {
                let o = Point2::new(
                    b.min.x + rng.uniform() * (b.max.x - b.min.x),
                    b.min.y + rng.uniform() * (b.max.y - b.min.y),
                );
                let c = Clearance::new(&scene.world.solids, &scene.solid_bounds, o);
                let z = 0.1 + rng.uniform() * 1.2;
                for _ in 0..300 {
                    let az = rng.uniform() * std::f64::consts::TAU;
                    let el = (rng.uniform() - 0.5) * 2.5;
                    let d = [el.cos() * az.cos(), el.cos() * az.sin(), el.sin()];
                    let origin = [o.x, o.y, z];
                    let fast = scene.trace_clear(origin, d, c.sector(sector_of(az)), el.cos());
                    let slow = scene.trace_brute_force(origin, d);
                    let same_t = (fast.t - slow.t).abs() < 1e-9
                        || (fast.t.is_infinite() && slow.t.is_infinite());
                    assert!(
                        same_t && fast.surface == slow.surface,
                        "{name}: {origin:?} {d:?}: {fast:?} vs {slow:?}"
                    );
                }
            }
        }
    }
}
