//! Tests of the `ground_table_inverse` module.

use super::*;

/// A pinhole camera 0.3 m above the floor, pitched 30 degrees down, 160 x 120: the ground
/// point of each pixel in closed form.
fn pinhole() -> (GroundTable, impl Fn(f64, f64) -> Option<Point2>) {
    let (f, cx, cy, h, pitch) = (120.0, 79.5, 59.5, 0.3, 30f64.to_radians());
    let ground = move |u: f64, v: f64| {
        // camera ray (x forward, y left, z up) for pixel (u, v)
        let (xc, yc, zc) = (1.0, -(u - cx) / f, -(v - cy) / f);
        let (s, c) = pitch.sin_cos();
        let dx = c * xc + s * zc;
        let dz = -s * xc + c * zc;
        (dz < -1e-6).then(|| {
            let t = h / -dz;
            Point2::new(t * dx, t * yc)
        })
    };
    let table = GroundTable::from_fn(160, 120, 4, &ground).unwrap();
    (table, ground)
}

#[test]
fn pixel_of_inverts_the_table_to_a_fraction_of_a_pixel() {
    let (table, ground) = pinhole();
    let mut checked = 0;
    for v in (40..119).step_by(7) {
        for u in (2..157).step_by(9) {
            let (u, v) = (u as f64 + 0.37, v as f64 + 0.61);
            let Some(g) = table.lookup(u, v) else {
                continue;
            };
            // the table agrees with the closed form, and its inverse finds the pixel back
            let exact = ground(u, v).unwrap();
            assert!((g.x - exact.x).hypot(g.y - exact.y) < 0.01 * exact.norm().max(0.1));
            let (pu, pv) = table
                .pixel_of(g, (u + 6.0, v - 5.0))
                .unwrap_or_else(|| panic!("{u} {v} {g:?} not found"));
            assert!(
                (pu - u).abs() < 0.01 && (pv - v).abs() < 0.01,
                "{u} {v}: {pu} {pv}"
            );
            checked += 1;
        }
    }
    assert!(checked > 50);
    // a point behind the camera is not seen
    assert!(table
        .pixel_of(Point2::new(-1.0, 0.0), (80.0, 100.0))
        .is_none());
}
