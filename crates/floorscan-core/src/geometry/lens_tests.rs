//! Tests of the `lens` module.

use super::*;
use proptest::prelude::*;

fn lenses() -> Vec<Lens> {
    vec![
        Lens::Pinhole {
            fx: 300.0,
            fy: 310.0,
            cx: 160.0,
            cy: 120.0,
        },
        Lens::PinholeRadial {
            fx: 295.8,
            fy: 299.5,
            cx: 321.3,
            cy: 241.7,
            k1: -0.2354,
            k2: 0.0364,
            p1: -0.0033,
            p2: -0.0012,
            k3: 0.0,
        },
        Lens::Equidistant {
            f: 120.0,
            cx: 160.0,
            cy: 120.0,
        },
        Lens::KannalaBrandt {
            fx: 120.0,
            fy: 121.0,
            cx: 159.5,
            cy: 119.5,
            k1: -0.02,
            k2: 0.004,
            k3: -0.001,
            k4: 0.0001,
        },
    ]
}

#[test]
fn equidistant_radius_is_focal_times_angle() {
    let lens = Lens::Equidistant {
        f: 100.0,
        cx: 0.0,
        cy: 0.0,
    };
    let theta: f64 = 0.7;
    let p = lens.project([theta.sin(), 0.0, theta.cos()]).unwrap();
    assert!((p[0] - 70.0).abs() < 1e-9 && p[1].abs() < 1e-12);
}

#[test]
fn rays_behind_a_pinhole_do_not_project() {
    assert!(lenses()[0].project([0.0, 0.0, -1.0]).is_none());
}

#[test]
fn bad_focal_length_is_an_error() {
    assert!(Lens::Pinhole {
        fx: 0.0,
        fy: 1.0,
        cx: 0.0,
        cy: 0.0
    }
    .validate()
    .is_err());
    assert!(Lens::Equidistant {
        f: f64::NAN,
        cx: 0.0,
        cy: 0.0
    }
    .validate()
    .is_err());
}

proptest! {
    #[test]
    fn pixel_ray_pixel_round_trip(u in 0.0..320.0f64, v in 0.0..240.0f64, which in 0usize..4) {
        let lens = lenses()[which];
        if let Some(ray) = lens.unproject([u, v]) {
            let p = lens.project(ray).unwrap();
            prop_assert!((p[0] - u).abs() < 1e-6 && (p[1] - v).abs() < 1e-6, "{:?} -> {:?}", (u, v), p);
        } else {
            // The ideal pinhole inverts everywhere; the others may not, far from the centre
            // (fisheye beyond its field of view, plumb_bob where it folds over).
            prop_assert!(which != 0);
            let (_, _, cx, cy) = lens.intrinsics();
            prop_assert!((u - cx).hypot(v - cy) > 150.0);
        }
    }

    #[test]
    fn ray_pixel_ray_round_trip(x in -1.0..1.0f64, y in -1.0..1.0f64, which in 0usize..4) {
        let lens = lenses()[which];
        let ray = [x, y, 1.0];
        if let Some(p) = lens.project(ray) {
            if let Some(back) = lens.unproject(p) {
                let n = (x * x + y * y + 1.0).sqrt();
                for k in 0..3 { prop_assert!((back[k] - ray[k] / n).abs() < 1e-6); }
            }
        }
    }
}
