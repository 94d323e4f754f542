//! Per-view free space around the camera, in azimuth sectors: for each sector (wedge) the
//! distance within which no solid's footprint reaches into it. A ray whose floor or ceiling hit
//! lies nearer than its sector's clearance cannot be blocked by a solid, so it needs no walk
//! through the grid. This is exact (the clearance is a lower bound), and it is what makes
//! rendering fast: most pixels see open floor.

use floorscan_core::Point2;

use crate::geometry::point_in_polygon;
use crate::scene::Scene;

/// Number of azimuth sectors (0.18 degrees each).
pub const SECTORS: usize = 2048;

/// Clearance per azimuth sector around one camera position.
#[derive(Debug, Clone)]
pub struct Clearance {
    /// Horizontal distance [m] within which each sector is free of solids (0: unknown).
    pub free_m: Vec<f64>,
}

const SECTOR_RAD: f64 = std::f64::consts::TAU / SECTORS as f64;

/// The sector of an azimuth [rad] (any value).
#[inline]
pub fn sector_of(azimuth: f64) -> usize {
    let k = crate::rng::fast_floor(azimuth / SECTOR_RAD).rem_euclid(SECTORS as i64);
    k as usize
}

impl Clearance {
    /// Clearance around the point `o` (world frame).
    pub fn new(scene: &Scene, o: Point2) -> Clearance {
        let mut free = vec![f64::INFINITY; SECTORS];
        for (k, s) in scene.world.solids.iter().enumerate() {
            let b = scene.solid_bounds[k];
            if b.contains(o) && point_in_polygon(o, &s.polygon) {
                // The camera is above or below this solid (under a table): no shortcut.
                return Clearance {
                    free_m: vec![0.0; SECTORS],
                };
            }
            let n = s.polygon.len();
            for e in 0..n {
                let a = s.polygon[e];
                let c = s.polygon[(e + 1) % n];
                shade_segment(
                    &mut free,
                    Point2::new(a.x - o.x, a.y - o.y),
                    Point2::new(c.x - o.x, c.y - o.y),
                );
            }
        }
        Clearance { free_m: free }
    }
}

impl Clearance {
    /// The clearance of every azimuth within `spread_rad` of `azimuth` [rad] (the smallest of
    /// their sectors'): for rays known only to lie near an azimuth.
    pub fn free_within(&self, azimuth: f64, spread_rad: f64) -> f64 {
        let k0 = crate::rng::fast_floor((azimuth - spread_rad) / SECTOR_RAD);
        let k1 =
            crate::rng::fast_floor((azimuth + spread_rad) / SECTOR_RAD).min(k0 + SECTORS as i64);
        (k0..=k1)
            .map(|k| self.free_m[k.rem_euclid(SECTORS as i64) as usize])
            .fold(f64::INFINITY, f64::min)
    }
}

/// Lowers the clearance of every sector the segment a-b (relative to the camera) reaches into
/// to the segment's nearest distance within that sector.
fn shade_segment(free: &mut [f64], a: Point2, b: Point2) {
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
        free.iter_mut().for_each(|f| *f = 0.0);
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
    // Parameter where the segment's line meets the ray of azimuth phi.
    let s_at = |phi: f64| {
        let u = Point2::new(phi.cos(), phi.sin());
        let den = u.x * e.y - u.y * e.x;
        if den.abs() < 1e-300 {
            f64::NAN
        } else {
            -(u.x * a.y - u.y * a.x) / den
        }
    };
    let mut s_lo = s_at(k0 as f64 * SECTOR_RAD);
    for k in k0..=k1 {
        let s_hi = s_at((k + 1) as f64 * SECTOR_RAD);
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
        let slot = &mut free[k.rem_euclid(SECTORS as i64) as usize];
        if d < *slot {
            *slot = d;
        }
        s_lo = s_hi;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::builtin::builtin_world;
    use crate::rng::Rng;

    #[test]
    fn clearance_is_a_lower_bound_of_the_first_solid_along_any_ray() {
        for name in ["corridor", "room", "lab"] {
            let scene = Scene::new(builtin_world(name).unwrap());
            let mut rng = Rng::new(3);
            let o = scene.world.start.translation();
            let c = Clearance::new(&scene, o);
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
}
