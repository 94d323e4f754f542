//! Tests of the `mount` module.

use super::*;

const MOUNT: CameraMount = CameraMount {
    height_m: 0.5,
    tilt_rad: 0.5,
    roll_rad: 0.0,
};

#[test]
fn principal_ray_hits_the_floor_at_height_over_tan_tilt() {
    let p = MOUNT.ray_to_ground([0.0, 0.0, 1.0]).unwrap();
    assert!((p.x - 0.5 / 0.5f64.tan()).abs() < 1e-12 && p.y.abs() < 1e-12);
}

#[test]
fn image_right_is_ground_right() {
    // A ray to the right of the optical axis lands at negative y (REP 103: y is left).
    let p = MOUNT.ray_to_ground([0.2, 0.0, 1.0]).unwrap();
    assert!(p.y < 0.0);
    // Lower in the image is nearer.
    let near = MOUNT.ray_to_ground([0.0, 0.2, 1.0]).unwrap();
    assert!(near.x < 0.5 / 0.5f64.tan());
}

#[test]
fn rays_at_or_above_the_horizon_have_no_ground() {
    let level = CameraMount {
        tilt_rad: 0.0,
        ..MOUNT
    };
    assert!(level.ray_to_ground([0.0, 0.0, 1.0]).is_none());
    assert!(level.ray_to_ground([0.0, -0.1, 1.0]).is_none());
}

#[test]
fn ground_and_optical_rotations_are_inverse() {
    let m = CameraMount {
        height_m: 0.3,
        tilt_rad: 0.7,
        roll_rad: 0.1,
    };
    let r = [0.3, -0.2, 0.9];
    let back = m.optical_from_ground(m.ground_from_optical(r));
    for k in 0..3 {
        assert!((back[k] - r[k]).abs() < 1e-12);
    }
}

#[test]
fn table_from_camera_matches_pixel_to_ground_and_round_trips() {
    let lens = Lens::KannalaBrandt {
        fx: 110.0,
        fy: 110.0,
        cx: 159.5,
        cy: 119.5,
        k1: -0.01,
        k2: 0.002,
        k3: 0.0,
        k4: 0.0,
    };
    let t = ground_table_from_camera(&lens, &MOUNT, 320, 240, 4, 10.0).unwrap();
    let mut checked = 0;
    for v in (120..240).step_by(7) {
        for u in (0..320).step_by(11) {
            let exact = pixel_to_ground(&lens, &MOUNT, u as f64, v as f64, 10.0);
            if let (Some(e), Some(p)) = (exact, t.lookup(u as f64, v as f64)) {
                // Interpolation error on a 4 px grid is small near the robot.
                if e.norm() < 2.0 {
                    assert!(
                        (e.x - p.x).hypot(e.y - p.y) < 0.01,
                        "({u},{v}): {e:?} vs {p:?}"
                    );
                    let px = ground_to_pixel(&lens, &MOUNT, e).unwrap();
                    assert!((px[0] - u as f64).abs() < 1e-6 && (px[1] - v as f64).abs() < 1e-6);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 100);
    // Top rows look above the horizon.
    assert!(t.lookup(160.0, 0.0).is_none());
}

#[test]
fn invalid_mounts_are_errors() {
    assert!(CameraMount {
        height_m: 0.0,
        ..MOUNT
    }
    .validate()
    .is_err());
    assert!(CameraMount {
        tilt_rad: f64::NAN,
        ..MOUNT
    }
    .validate()
    .is_err());
}
