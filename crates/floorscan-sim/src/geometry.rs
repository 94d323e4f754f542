//! Small 2-D geometry helpers on [`Point2`]: polygons (point inclusion, bounding boxes) and the
//! intersection of a ray's ground track with a segment.

use floorscan_core::Point2;

/// An axis-aligned box [m].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Point2,
    pub max: Point2,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb {
        min: Point2 {
            x: f64::INFINITY,
            y: f64::INFINITY,
        },
        max: Point2 {
            x: f64::NEG_INFINITY,
            y: f64::NEG_INFINITY,
        },
    };

    pub fn of_points(points: &[Point2]) -> Aabb {
        points.iter().fold(Aabb::EMPTY, |b, p| b.including(*p))
    }

    pub fn including(self, p: Point2) -> Aabb {
        Aabb {
            min: Point2::new(self.min.x.min(p.x), self.min.y.min(p.y)),
            max: Point2::new(self.max.x.max(p.x), self.max.y.max(p.y)),
        }
    }

    pub fn union(self, o: Aabb) -> Aabb {
        self.including(o.min).including(o.max)
    }

    pub fn contains(&self, p: Point2) -> bool {
        p.x >= self.min.x && p.x <= self.max.x && p.y >= self.min.y && p.y <= self.max.y
    }

    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y)
    }
}

/// Whether `p` lies inside the polygon (even-odd rule; points on an edge may go either way).
pub fn point_in_polygon(p: Point2, polygon: &[Point2]) -> bool {
    let mut inside = false;
    let n = polygon.len();
    let mut j = n - 1;
    for i in 0..n {
        let (a, b) = (polygon[i], polygon[j]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y);
            if p.x < x {
                inside = !inside;
            }
        }
        j = i;
    }
    inside
}

/// Signed area of a polygon [m^2] (positive when counter-clockwise).
pub fn signed_area(polygon: &[Point2]) -> f64 {
    let n = polygon.len();
    (0..n)
        .map(|i| {
            let (a, b) = (polygon[i], polygon[(i + 1) % n]);
            a.x * b.y - b.x * a.y
        })
        .sum::<f64>()
        * 0.5
}

/// Where the ground track `o + t d` (t >= 0) crosses the segment a-b: `(t, s)` with s in [0, 1]
/// the position along the segment. `None` if parallel or missed.
#[inline]
pub fn ray_segment(o: Point2, d: Point2, a: Point2, b: Point2) -> Option<(f64, f64)> {
    let e = Point2::new(b.x - a.x, b.y - a.y);
    let denom = d.x * e.y - d.y * e.x;
    let w = Point2::new(a.x - o.x, a.y - o.y);
    let tn = w.x * e.y - w.y * e.x;
    let sn = w.x * d.y - w.y * d.x;
    // Range checks on the numerators (sign-adjusted), so misses cost no division.
    let (tn, sn, den) = if denom < 0.0 {
        (-tn, -sn, -denom)
    } else {
        (tn, sn, denom)
    };
    if !(den > 1e-300 && tn >= 0.0 && sn >= 0.0 && sn <= den) {
        return None;
    }
    let inv = 1.0 / den;
    Some((tn * inv, sn * inv))
}

/// A rectangle of `size` (along its x, along its y) centred at `center`, rotated by `yaw`,
/// counter-clockwise.
pub fn rotated_rect(center: Point2, size: [f64; 2], yaw: f64) -> Vec<Point2> {
    let (s, c) = yaw.sin_cos();
    let (hx, hy) = (size[0] / 2.0, size[1] / 2.0);
    [(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)]
        .iter()
        .map(|&(x, y)| Point2::new(center.x + c * x - s * y, center.y + s * x + c * y))
        .collect()
}

/// A regular polygon approximating a circle (counter-clockwise).
pub fn circle_polygon(center: Point2, radius: f64, sides: usize) -> Vec<Point2> {
    (0..sides)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / sides as f64;
            Point2::new(center.x + radius * a.cos(), center.y + radius * a.sin())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn square_contains_its_centre_not_outside_points() {
        let sq = rotated_rect(Point2::new(1.0, 1.0), [2.0, 2.0], 0.3);
        assert!(point_in_polygon(Point2::new(1.0, 1.0), &sq));
        assert!(!point_in_polygon(Point2::new(3.0, 1.0), &sq));
        assert!((signed_area(&sq) - 4.0).abs() < 1e-12);
    }

    #[test]
    fn ray_meets_segment_at_the_analytic_distance() {
        let (t, s) = ray_segment(
            Point2::new(0.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(2.0, -1.0),
            Point2::new(2.0, 3.0),
        )
        .unwrap();
        assert!((t - 2.0).abs() < 1e-12 && (s - 0.25).abs() < 1e-12);
        // Behind the origin, or past the segment's ends: no hit.
        assert!(ray_segment(
            Point2::new(3.0, 0.0),
            Point2::new(1.0, 0.0),
            Point2::new(2.0, -1.0),
            Point2::new(2.0, 1.0)
        )
        .is_none());
        assert!(ray_segment(
            Point2::new(0.0, 2.0),
            Point2::new(1.0, 0.0),
            Point2::new(2.0, -1.0),
            Point2::new(2.0, 1.0)
        )
        .is_none());
    }
}
