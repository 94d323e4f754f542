//! Contact shadows: the floor darkens towards the foot of everything that stands on it.
//!
//! A real floor is darker next to a cabinet, a box or a wall: the solid hides part of the sky
//! of indirect light from the floor beside it. To a camera the shadow is a soft darkening that
//! starts a few centimetres before the obstacle's base, so an edge filter that stops at the
//! first strong change stops at the shadow, not at the base (issue 13: ~5 rows early on a real
//! RGB-D recording of a cabinet at 640 x 480).
//!
//! Model: at horizontal distance d from the footprint of a solid standing on the floor
//! (`base_m` 0; a table's top casts none, its legs do), the floor's light is multiplied by
//! `1 - strength * g(d) * span / pi`, with `g(d) = (exp(-d / length_m) - exp(-REACH)) /
//! (1 - exp(-REACH))` for `d < REACH * length_m` and 0 beyond (the exponential, made to reach
//! 0 continuously) and span the angle the footprint covers seen from the point (pi beside a
//! wall's face, little beside a thin leg, which hides little of the light). The darkest
//! solid decides. Precomputed on a raster around the solids, looked up bilinearly;
//! off (`strength` 0, the default) it costs nothing.

use floorscan_core::Point2;
use serde::{Deserialize, Serialize};

use crate::geometry::Aabb;

/// The shadow ends at this many `length_m` from the footprint.
pub const REACH: f64 = 5.0;
/// Most raster cells (a bound on memory: 4 bytes each); a huge world gets a coarser raster.
pub const MAX_CELLS: usize = 8 << 20;
/// Most cell evaluations while building (a bound on the build time).
pub const MAX_EVALUATIONS: f64 = 2.0e8;
/// Solids whose base is at most this high [m] stand on the floor.
pub const STANDING_BASE_M: f64 = 1e-3;

/// `[lighting] contact_shadow = { strength = 0.5, length_m = 0.04 }` in a world file.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ContactShadow {
    /// How much darker the floor is right at a solid's foot, in [0, 1]: 0 none (the default),
    /// 0.5 half the light.
    pub strength: f64,
    /// The distance over which the darkening falls to 1/e of itself [m], in (0, 0.5].
    /// Default 0.04.
    pub length_m: f64,
}

impl Default for ContactShadow {
    fn default() -> Self {
        Self {
            strength: 0.0,
            length_m: 0.04,
        }
    }
}

impl ContactShadow {
    /// Checks the ranges; the message names the field.
    pub fn validate(&self) -> std::result::Result<(), String> {
        if !(0.0..=1.0).contains(&self.strength) {
            return Err(format!(
                "lighting.contact_shadow.strength: must be in [0, 1], got {}",
                self.strength
            ));
        }
        if !(self.length_m > 0.0 && self.length_m <= 0.5) {
            return Err(format!(
                "lighting.contact_shadow.length_m: must be in (0, 0.5], got {}",
                self.length_m
            ));
        }
        Ok(())
    }

    /// The light factor at floor point `p` outside the (convex) footprint `polygon` of a
    /// standing solid: `1 - strength g(d) span / pi`, d the distance to the footprint and span
    /// the angle the footprint covers seen from `p` (pi next to a wall's face, a few degrees
    /// from a thin leg: a thin solid hides little of the light). 1 - strength g(d) inside.
    pub fn factor_of(&self, p: Point2, polygon: &[Point2]) -> f64 {
        let n = polygon.len();
        let d = (0..n)
            .map(|i| segment_distance(p, polygon[i], polygon[(i + 1) % n]))
            .fold(f64::INFINITY, f64::min);
        if d >= REACH * self.length_m {
            return 1.0;
        }
        1.0 - (1.0 - self.factor(d)) * footprint_span(p, polygon) / std::f64::consts::PI
    }

    /// The light factor at distance `d_m` from a long face (a wall's): `1 - strength g(d)`.
    pub fn factor(&self, d_m: f64) -> f64 {
        let x = d_m.max(0.0) / self.length_m;
        if x >= REACH {
            return 1.0;
        }
        let tail = (-REACH).exp();
        1.0 - self.strength * ((-x).exp() - tail) / (1.0 - tail)
    }
}

/// The light factor of contact shadows over the floor, on a raster.
#[derive(Debug, Clone)]
pub struct ShadowMap {
    origin: Point2,
    inv_cell: f64,
    nx: usize,
    ny: usize,
    values: Vec<f32>,
}

impl ShadowMap {
    /// The contact shadows `cs` of the solids standing on the floor, given by their
    /// footprints `standing` (convex polygons [m]; [`STANDING_BASE_M`]: which solids
    /// stand), or None when they are off or nothing stands.
    pub fn new(cs: ContactShadow, standing: &[&[Point2]]) -> Option<ShadowMap> {
        if cs.strength == 0.0 || standing.is_empty() {
            return None;
        }
        let reach = REACH * cs.length_m;
        let mut bounds = Aabb::EMPTY;
        for poly in standing {
            bounds = bounds.union(Aabb::of_points(poly));
        }
        let (w, h) = (
            bounds.max.x - bounds.min.x + 2.0 * reach,
            bounds.max.y - bounds.min.y + 2.0 * reach,
        );
        // A third of the shadow's length per cell, no finer than 5 mm; coarser while the
        // raster or the evaluations (per cell of a solid's grown bounds, a pass over its
        // vertices) would exceed their bounds.
        let work: f64 = standing
            .iter()
            .map(|p| {
                let bb = Aabb::of_points(p);
                (bb.max.x - bb.min.x + 2.0 * reach)
                    * (bb.max.y - bb.min.y + 2.0 * reach)
                    * p.len() as f64
            })
            .sum();
        let mut cell = (cs.length_m / 3.0).max(0.005);
        while (w / cell + 2.0) * (h / cell + 2.0) > MAX_CELLS as f64
            || work / (cell * cell) > MAX_EVALUATIONS
        {
            cell *= 2.0;
        }
        let nx = (w / cell).ceil() as usize + 2;
        let ny = (h / cell).ceil() as usize + 2;
        let origin = Point2::new(bounds.min.x - reach - cell, bounds.min.y - reach - cell);
        // per solid, its shadow over its bounds grown by the reach; the darkest decides
        let mut values = vec![1.0f32; nx * ny];
        for poly in standing {
            let bb = Aabb::of_points(poly);
            let i0 = (((bb.min.x - reach - origin.x) / cell).floor().max(0.0)) as usize;
            let i1 = (((bb.max.x + reach - origin.x) / cell).ceil() as usize).min(nx - 1);
            let j0 = (((bb.min.y - reach - origin.y) / cell).floor().max(0.0)) as usize;
            let j1 = (((bb.max.y + reach - origin.y) / cell).ceil() as usize).min(ny - 1);
            for j in j0..=j1 {
                let y = origin.y + j as f64 * cell;
                for i in i0..=i1 {
                    let p = Point2::new(origin.x + i as f64 * cell, y);
                    let f = cs.factor_of(p, poly) as f32;
                    let k = j * nx + i;
                    if f < values[k] {
                        values[k] = f;
                    }
                }
            }
        }
        Some(ShadowMap {
            origin,
            inv_cell: 1.0 / cell,
            nx,
            ny,
            values,
        })
    }

    /// The light factor at floor point `p` (bilinear between raster nodes; 1 off the raster).
    #[inline]
    pub fn at(&self, p: Point2) -> f32 {
        let gx = (p.x - self.origin.x) * self.inv_cell;
        let gy = (p.y - self.origin.y) * self.inv_cell;
        if !(gx >= 0.0 && gy >= 0.0 && gx < (self.nx - 1) as f64 && gy < (self.ny - 1) as f64) {
            return 1.0;
        }
        let (i, j) = (gx as usize, gy as usize);
        let (fx, fy) = ((gx - i as f64) as f32, (gy - j as f64) as f32);
        let k = j * self.nx + i;
        let (t0, t1) = (self.values[k], self.values[k + 1]);
        let (b0, b1) = (self.values[k + self.nx], self.values[k + self.nx + 1]);
        let top = t0 + (t1 - t0) * fx;
        let bottom = b0 + (b1 - b0) * fx;
        top + (bottom - top) * fy
    }
}

/// The angle [rad, 0..=pi] the convex `polygon` covers seen from `p` (pi from inside or on
/// its boundary): the spread of its vertices' bearings about the bearing of their mean.
fn footprint_span(p: Point2, polygon: &[Point2]) -> f64 {
    let n = polygon.len() as f64;
    let (cx, cy) = polygon
        .iter()
        .fold((0.0, 0.0), |(x, y), v| (x + v.x / n, y + v.y / n));
    let (ux, uy) = (cx - p.x, cy - p.y);
    if ux.hypot(uy) < 1e-12 {
        return std::f64::consts::PI;
    }
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for v in polygon {
        let (vx, vy) = (v.x - p.x, v.y - p.y);
        let a = (ux * vy - uy * vx).atan2(ux * vx + uy * vy);
        lo = lo.min(a);
        hi = hi.max(a);
    }
    (hi - lo).min(std::f64::consts::PI)
}

/// Distance from `p` to the segment `a`-`b` [m].
fn segment_distance(p: Point2, a: Point2, b: Point2) -> f64 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.x - (a.x + t * dx)).hypot(p.y - (a.y + t * dy))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_factor_falls_from_one_minus_strength_at_the_foot_to_one_at_the_reach() {
        let cs = ContactShadow {
            strength: 0.5,
            length_m: 0.04,
        };
        assert!((cs.factor(0.0) - 0.5).abs() < 1e-12);
        assert_eq!(cs.factor(REACH * 0.04), 1.0);
        assert_eq!(cs.factor(1.0), 1.0);
        // monotone, and the exponential's shape in between
        let mut last = 0.0;
        for k in 0..=100 {
            let f = cs.factor(k as f64 * 0.002);
            assert!(f >= last);
            last = f;
        }
        let tail = (-REACH).exp();
        let expected = 1.0 - 0.5 * ((-1.0f64).exp() - tail) / (1.0 - tail);
        assert!((cs.factor(0.04) - expected).abs() < 1e-12);
    }

    #[test]
    fn out_of_range_options_are_refused_by_name() {
        for (s, l) in [
            (-0.1, 0.04),
            (1.5, 0.04),
            (0.5, 0.0),
            (0.5, 0.6),
            (f64::NAN, 0.04),
        ] {
            let e = ContactShadow {
                strength: s,
                length_m: l,
            }
            .validate()
            .unwrap_err();
            assert!(e.contains("lighting.contact_shadow"), "{e}");
        }
    }

    #[test]
    fn a_thin_leg_darkens_less_than_a_long_face_at_the_same_distance() {
        let cs = ContactShadow {
            strength: 0.5,
            length_m: 0.04,
        };
        let square = |x0: f64, x1: f64, y0: f64, y1: f64| {
            vec![
                Point2::new(x0, y0),
                Point2::new(x1, y0),
                Point2::new(x1, y1),
                Point2::new(x0, y1),
            ]
        };
        let wall = square(0.0, 0.1, -5.0, 5.0);
        let leg = square(0.0, 0.025, 0.0, 0.025);
        let p = Point2::new(-0.02, 0.0125);
        // beside a 10 m face the span is within a few thousandths of pi: the long-face factor
        assert!((cs.factor_of(p, &wall) - cs.factor(0.02)).abs() < 1e-3);
        // beside a 2.5 cm leg, 2 cm away: span 2 atan(1.25 / 2) = 64 degrees
        let span = 2.0 * (0.0125f64 / 0.02).atan();
        let want = 1.0 - (1.0 - cs.factor(0.02)) * span / std::f64::consts::PI;
        assert!((cs.factor_of(p, &leg) - want).abs() < 1e-12);
        assert!(cs.factor_of(p, &leg) > cs.factor_of(p, &wall) + 0.05);
        assert_eq!(cs.factor_of(Point2::new(-0.5, 0.0), &leg), 1.0);
    }

    #[test]
    fn segment_distance_matches_geometry() {
        let (a, b) = (Point2::new(0.0, 0.0), Point2::new(2.0, 0.0));
        assert!((segment_distance(Point2::new(1.0, 0.3), a, b) - 0.3).abs() < 1e-12);
        assert!((segment_distance(Point2::new(3.0, 0.0), a, b) - 1.0).abs() < 1e-12);
        assert!((segment_distance(Point2::new(-0.3, 0.4), a, b) - 0.5).abs() < 1e-12);
    }
}
