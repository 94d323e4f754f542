//! Tests of [`super`] (texture.rs).

use super::*;

fn carpet() -> Covering {
    Covering {
        name: "carpet".into(),
        class: CoveringClass::Carpet,
        albedo: 0.4,
        pattern: FloorPattern::Carpet {
            contrast: 0.06,
            grain_m: 0.004,
            mottle: 0.03,
            mottle_m: 0.5,
        },
        seed: 11,
    }
}

fn std_along(c: &Covering, footprint: f64) -> f64 {
    let v: Vec<f64> = (0..4000)
        .map(|i| {
            c.albedo_at(
                Point2::new(i as f64 * 0.0137, 0.3 + i as f64 * 0.0071),
                footprint,
            ) as f64
        })
        .collect();
    let m = v.iter().sum::<f64>() / v.len() as f64;
    (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
}

#[test]
fn carpet_is_low_contrast_and_smoother_far_away() {
    let c = carpet();
    let near = std_along(&c, 0.002);
    let far = std_along(&c, 0.04);
    assert!(near / 0.4 < 0.15, "relative std {}", near / 0.4);
    assert!(far < near * 0.6, "near {near} far {far}");
}

fn covering(pattern: FloorPattern) -> Covering {
    Covering {
        name: "floor".into(),
        class: CoveringClass::Other,
        albedo: 0.5,
        pattern,
        seed: 11,
    }
}

#[test]
fn wood_joints_are_dark_planks_vary_and_rows_are_staggered() {
    let c = covering(FloorPattern::Wood {
        plank_m: 0.1,
        length_m: 1.0,
        grain: 0.0,
        variation: 0.2,
        joint_m: 0.004,
        joint_albedo: 0.1,
    });
    let fp = 0.0005;
    // On the long joint between two rows (y = 0.1) the floor is the joint's albedo.
    assert!((c.albedo_at(Point2::new(0.37, 0.1), fp) - 0.1).abs() < 1e-3);
    // Across one plank (no grain) the tone is constant; planks differ from each other.
    let tone = |x: f64, y: f64| c.albedo_at(Point2::new(x, y), fp);
    assert!((tone(0.30, 0.03) - tone(0.30, 0.07)).abs() < 1e-6);
    let tones: Vec<f32> = (0..12).map(|r| tone(0.3, 0.05 + 0.1 * r as f64)).collect();
    let spread = tones.iter().cloned().fold(f32::MIN, f32::max)
        - tones.iter().cloned().fold(f32::MAX, f32::min);
    assert!(spread > 0.05, "{tones:?}");
    // Butt joints: along a row, exactly one dark joint per plank length, and not at the
    // same x in every row.
    let joints = |y: f64| -> Vec<f64> {
        (0..4000)
            .map(|i| i as f64 * 0.001)
            .filter(|&x| tone(x, y) < 0.2)
            .collect()
    };
    let (a, b) = (joints(0.05), joints(0.15));
    assert!(!a.is_empty() && !b.is_empty());
    let first = |v: &[f64]| v[0];
    assert!(
        (first(&a) - first(&b)).abs() > 0.01,
        "rows not staggered: {a:?} {b:?}"
    );
    let runs = a.windows(2).filter(|w| w[1] - w[0] > 0.01).count() + 1;
    assert!(
        (3..=5).contains(&runs),
        "{runs} joints in 4 m of 1 m planks"
    );
}

#[test]
fn patterned_carpet_has_two_tones_of_the_given_contrast() {
    let c = covering(FloorPattern::PatternedCarpet {
        contrast: 0.0,
        grain_m: 0.004,
        mottle: 0.0,
        mottle_m: 0.5,
        pattern_m: 0.3,
        pattern_contrast: 0.25,
    });
    let fp = 0.0005;
    // Diamond centres: (u, v) = (0.5, 0.5) and (1.5, 0.5) in pattern units.
    let at = |u: f64, v: f64| {
        let (x, y) = ((u + v) * 0.15, (u - v) * 0.15);
        c.albedo_at(Point2::new(x, y), fp)
    };
    let (light, dark) = (at(0.5, 0.5), at(1.5, 0.5));
    assert!(
        (light.max(dark) - 0.5 * 1.25).abs() < 1e-4,
        "{light} {dark}"
    );
    assert!(
        (light.min(dark) - 0.5 * 0.75).abs() < 1e-4,
        "{light} {dark}"
    );
    // Far away (a footprint wider than the diamonds' edges blend) the tones average out.
    let far = c.albedo_at(Point2::new(0.0, 0.0), 0.3);
    assert!((far - 0.5).abs() < 0.07, "{far}");
}

#[test]
fn grout_lines_are_dark_and_tile_centres_are_not() {
    let t = Covering {
        name: "tiles".into(),
        class: CoveringClass::Other,
        albedo: 0.7,
        pattern: FloorPattern::Tiles {
            tile_m: 0.3,
            grout_m: 0.01,
            grout_albedo: 0.2,
            variation: 0.0,
        },
        seed: 1,
    };
    assert!((t.albedo_at(Point2::new(0.3, 0.15), 0.001) - 0.2).abs() < 1e-6);
    assert!(t.albedo_at(Point2::new(0.15, 0.15), 0.001) > 0.6);
}

#[test]
fn checkerboard_squares_alternate_around_an_inner_corner() {
    let b = Covering {
        name: "board".into(),
        class: CoveringClass::Other,
        albedo: 0.9,
        pattern: FloorPattern::Checkerboard {
            origin: Point2::new(1.0, 0.0),
            across: Point2::new(0.0, -1.0),
            away: Point2::new(1.0, 0.0),
            square_m: 0.1,
            corners: [3, 2],
            dark_albedo: 0.05,
            margin_m: 0.05,
        },
        seed: 0,
    };
    let at = |x: f64, y: f64| b.albedo_at(Point2::new(x, y), 1e-4);
    // Diagonal squares around the corner at (1, 0) share a colour, neighbours differ.
    assert_eq!(at(1.05, -0.05), at(0.95, 0.05));
    assert_ne!(at(1.05, -0.05), at(1.05, 0.05));
    // The margin is white.
    assert!((at(0.88, 0.0) - 0.9).abs() < 1e-6);
}
