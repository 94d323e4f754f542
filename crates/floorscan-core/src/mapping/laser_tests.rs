//! Tests of the `laser` module.

use super::*;

fn scan(ranges: &[f64]) -> LaserScan<'_> {
    LaserScan {
        ranges_m: ranges,
        angles: BeamAngles::Uniform {
            min_rad: 0.0,
            increment_rad: std::f64::consts::FRAC_PI_2,
        },
        range_min_m: 0.1,
        range_max_m: 5.0,
    }
}

#[test]
fn ranges_follow_rep_117() {
    let ranges = [2.0, f64::INFINITY, 0.05, f64::NEG_INFINITY, 7.0];
    let mut rays = Vec::new();
    scan(&ranges)
        .rays(&Pose2::new(1.0, 1.0, 0.0), &mut rays)
        .unwrap();
    // Beam 0: hit at (3, 1); beam 1 (90 deg): no return, cleared to 5 m; beams 2-3 too
    // close: ignored; beam 4 (360 deg) beyond range_max: cleared to 5 m.
    assert_eq!(rays.len(), 3);
    assert!(
        rays[0].hit && (rays[0].to.x - 3.0).abs() < 1e-12 && (rays[0].to.y - 1.0).abs() < 1e-12
    );
    assert!(
        !rays[1].hit && (rays[1].to.y - 6.0).abs() < 1e-12 && (rays[1].to.x - 1.0).abs() < 1e-12
    );
    assert!(!rays[2].hit && (rays[2].to.x - 6.0).abs() < 1e-9);
    assert!(rays.iter().all(|r| r.from == Point2::new(1.0, 1.0)));
}

#[test]
fn bad_input_is_named() {
    let mut rays = Vec::new();
    let e = scan(&[1.0, f64::NAN])
        .rays(&Pose2::IDENTITY, &mut rays)
        .unwrap_err();
    assert!(e.to_string().contains("beam 1"));
    let ranges = [1.0, 2.0];
    let bad = LaserScan {
        angles: BeamAngles::Explicit(&[0.0]),
        ..scan(&ranges)
    };
    assert!(matches!(bad.check(), Err(Error::LengthMismatch(_))));
    let bad = LaserScan {
        range_max_m: 0.05,
        ..scan(&ranges)
    };
    assert!(bad.check().unwrap_err().to_string().contains("range_max_m"));
    assert!(rays.is_empty());
}
