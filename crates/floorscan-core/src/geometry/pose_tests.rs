//! Tests of the `pose` module.

use super::*;
use proptest::prelude::*;

fn close(a: Pose2, b: Pose2) -> bool {
    (a.x - b.x).abs() < 1e-9
        && (a.y - b.y).abs() < 1e-9
        && normalize_angle(a.yaw - b.yaw).abs() < 1e-9
}

#[test]
fn quarter_turn_maps_x_axis_to_y_axis() {
    let p = Pose2::new(1.0, 2.0, std::f64::consts::FRAC_PI_2);
    let q = p.transform_point(Point2::new(1.0, 0.0));
    assert!((q.x - 1.0).abs() < 1e-12 && (q.y - 3.0).abs() < 1e-12);
}

#[test]
fn non_finite_pose_is_rejected() {
    assert!(Pose2::checked(f64::NAN, 0.0, 0.0).is_err());
    assert!(Pose2::checked(0.0, 0.0, f64::INFINITY).is_err());
}

proptest! {
    #[test]
    fn inverse_composes_to_identity(x in -10.0..10.0f64, y in -10.0..10.0f64, t in -4.0..4.0f64) {
        let p = Pose2::new(x, y, t);
        prop_assert!(close(p.compose(&p.inverse()), Pose2::IDENTITY));
        prop_assert!(close(p.inverse().compose(&p), Pose2::IDENTITY));
    }

    #[test]
    fn between_recovers_relative_motion(a in (-5.0..5.0f64, -5.0..5.0f64, -3.0..3.0f64),
                                        d in (-5.0..5.0f64, -5.0..5.0f64, -3.0..3.0f64)) {
        let pa = Pose2::new(a.0, a.1, a.2);
        let delta = Pose2::new(d.0, d.1, d.2);
        let pb = pa.compose(&delta);
        prop_assert!(close(pa.between(&pb), delta));
    }

    #[test]
    fn normalized_angle_is_in_range(a in -100.0..100.0f64) {
        let n = normalize_angle(a);
        prop_assert!(n > -std::f64::consts::PI - 1e-12 && n <= std::f64::consts::PI + 1e-12);
        prop_assert!(((a - n) / std::f64::consts::TAU - ((a - n) / std::f64::consts::TAU).round()).abs() < 1e-9);
    }
}
