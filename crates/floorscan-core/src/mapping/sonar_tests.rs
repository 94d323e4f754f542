//! Tests of the `sonar` module.

use super::*;

#[test]
fn rays_fan_over_the_beam_at_the_range() {
    let s = SonarReading {
        range_m: 2.0,
        beam_width_rad: 0.4,
        range_max_m: 5.0,
    };
    let mut rays = Vec::new();
    s.rays(
        &Pose2::new(1.0, 0.0, std::f64::consts::FRAC_PI_2),
        0.04,
        &mut rays,
    )
    .unwrap();
    // Arc of 0.8 m at 2 cm spacing: 40 intervals.
    assert_eq!(rays.len(), 41);
    for r in &rays {
        assert!(r.hit);
        assert!(((r.to.x - 1.0).hypot(r.to.y) - 2.0).abs() < 1e-12);
        let bearing = r.to.y.atan2(r.to.x - 1.0);
        assert!((bearing - std::f64::consts::FRAC_PI_2).abs() <= 0.2 + 1e-12);
    }
}

#[test]
fn no_echo_clears_to_max_range() {
    let s = SonarReading {
        range_m: f64::INFINITY,
        beam_width_rad: 0.4,
        range_max_m: 3.0,
    };
    let mut rays = Vec::new();
    s.rays(&Pose2::IDENTITY, 0.04, &mut rays).unwrap();
    assert!(rays
        .iter()
        .all(|r| !r.hit && (r.to.x.hypot(r.to.y) - 3.0).abs() < 1e-12));
}

#[test]
fn bad_readings_are_refused() {
    let ok = SonarReading {
        range_m: 1.0,
        beam_width_rad: 0.4,
        range_max_m: 3.0,
    };
    assert!(SonarReading {
        range_m: f64::NAN,
        ..ok
    }
    .check()
    .is_err());
    assert!(SonarReading {
        range_m: -1.0,
        ..ok
    }
    .check()
    .is_err());
    assert!(SonarReading {
        beam_width_rad: 0.0,
        ..ok
    }
    .check()
    .is_err());
    assert!(SonarReading {
        range_max_m: f64::INFINITY,
        ..ok
    }
    .check()
    .is_err());
    let mut rays = Vec::new();
    SonarReading {
        range_m: f64::NEG_INFINITY,
        ..ok
    }
    .rays(&Pose2::IDENTITY, 0.04, &mut rays)
    .unwrap();
    assert!(rays.is_empty());
}
