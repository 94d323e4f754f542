//! Tests of [`super`] (avoidance_map_layers.rs): scrolling against a cell-by-cell shift in
//! world cells, forgetting by its half-life, a bump's face against its geometry, the views
//! against their formulas.

use super::*;

fn small() -> AvoidanceMapOptions {
    AvoidanceMapOptions {
        size_m: 2.0,
        cell_size_m: 0.1,
        ..Default::default()
    }
}

#[test]
fn scrolling_keeps_each_value_at_its_world_cell() {
    let mut m = AvoidanceMap::new(small(), (0.0, 0.0)).unwrap();
    let n = m.side();
    assert_eq!(n, 20);
    assert_eq!(m.origin_cells(), (-10, -10));
    // a value per cell that names its world cell
    let world = |i: i64, j: i64| (i * 1000 + j) as f32;
    let (x0, y0) = m.origin_cells();
    for j in 0..n {
        for i in 0..n {
            m.log_odds[j * n + i] = world(x0 + i as i64, y0 + j as i64);
            m.confirmed[j * n + i] = ((i + j) % 2) as u8;
        }
    }
    // within a quarter window of the centre: no scroll
    m.recenter(0.45, -0.45).unwrap();
    assert_eq!(m.origin_cells(), (-10, -10));
    m.recenter(0.73, -1.21).unwrap(); // cells (7, -13) - 10
    let (x1, y1) = m.origin_cells();
    assert_eq!((x1, y1), (-3, -23));
    for j in 0..n {
        for i in 0..n {
            let (wi, wj) = (x1 + i as i64, y1 + j as i64);
            let inside_before =
                (x0..x0 + n as i64).contains(&wi) && (y0..y0 + n as i64).contains(&wj);
            let want = if inside_before { world(wi, wj) } else { 0.0 };
            assert_eq!(m.log_odds[j * n + i], want, "({i}, {j})");
            let flag = if inside_before {
                ((wi - x0 + wj - y0) % 2) as u8
            } else {
                0
            };
            assert_eq!(m.confirmed[j * n + i], flag);
        }
    }
    // far away: all unknown
    m.recenter(50.0, 50.0).unwrap();
    assert!(m.log_odds.iter().all(|&v| v == 0.0));
    // farther than any cell index (saturates): scrolls, no overflow
    m.log_odds[0] = 1.0;
    m.recenter(-1e300, 1e300).unwrap();
    assert_eq!(m.origin_cells(), (i64::MIN, i64::MAX - 10));
    assert!(m.log_odds.iter().all(|&v| v == 0.0));
    m.log_odds[0] = 1.0;
    m.recenter(1e300, -1e300).unwrap();
    assert!(m.log_odds.iter().all(|&v| v == 0.0));
    assert!(m.recenter(f64::NAN, 0.0).is_err());
}

#[test]
fn evidence_halves_in_a_half_life() {
    let mut m = AvoidanceMap::new(small(), (0.0, 0.0)).unwrap();
    m.log_odds[3] = 2.0;
    m.plan_log_odds[3] = -1.0;
    m.bumps[3] = 1.0;
    let hl = m.options().half_life_s.unwrap();
    m.decay(hl);
    assert!((m.log_odds[3] - 1.0).abs() < 1e-6 && (m.plan_log_odds[3] + 0.5).abs() < 1e-6);
    let bump_hl = m.options().bump_half_life_s.unwrap();
    assert!((m.bumps[3] as f64 - 0.5f64.powf(hl / bump_hl)).abs() < 1e-6);
    m.decay(-1.0);
    m.decay(f64::NAN);
    assert!((m.log_odds[3] - 1.0).abs() < 1e-6);
}

#[test]
fn a_bump_marks_the_face_square_to_its_bearing() {
    let mut m = AvoidanceMap::new(small(), (0.0, 0.0)).unwrap();
    // robot at the origin facing +x, contact dead ahead at 0.35 m: a face x = 0.35, |y| <= h
    m.mark_bump(Pose2::new(0.0, 0.0, 0.0), 0.0, 0.35).unwrap();
    let n = m.side();
    let h = m.options().bump_face_half_length_m;
    let (x0, y0) = m.origin_cells();
    let mut marked = 0;
    for j in 0..n {
        for i in 0..n {
            if m.bumps[j * n + i] == 0.0 {
                continue;
            }
            marked += 1;
            let (cx, cy) = ((x0 + i as i64) as f64 * 0.1, (y0 + j as i64) as f64 * 0.1);
            assert!(cx <= 0.35 && 0.35 < cx + 0.1, "column of ({i}, {j})");
            assert!(cy + 0.1 > -h - 1e-9 && cy < h + 1e-9, "row of ({i}, {j})");
            assert!(m.occupied(j * n + i) && m.occupancy_class(j * n + i) == 2);
        }
    }
    // cells of y in [-0.2, 0.2): four, the face's ends on cell borders at +-0.15 -> -0.2..0.2
    assert_eq!(marked, 4);
}

#[test]
fn probabilities_follow_the_calibration_and_classes_the_raw_evidence() {
    let platt = AvoidanceMapOptions {
        probability_knots: None,
        probability_scale: 0.5,
        probability_offset: -1.0,
        ..small()
    };
    let mut m = AvoidanceMap::new(platt, (0.0, 0.0)).unwrap();
    m.log_odds[..3].copy_from_slice(&[4.0, 1.0, 0.01]);
    m.plan_log_odds[..3].copy_from_slice(&[4.0, 1.0, -1.5]);
    let mut p = Vec::new();
    m.probabilities(&mut p);
    assert!((p[0] - 1.0 / (1.0 + (-(0.5 * 4.0 - 1.0f64)).exp())).abs() < 1e-12);
    assert_eq!(p[2], 0.5); // no evidence
    assert_eq!(p[10], 0.5);
    let classes: Vec<u8> = (0..4).map(|k| m.occupancy_class(k)).collect();
    // logit(0.65) = 0.62, logit(0.196) = -1.41
    assert_eq!(classes, vec![2, 2, 0, 1]);
    let knots = AvoidanceMapOptions {
        probability_knots: Some(vec![(-2.0, 0.02), (0.0, 0.3), (2.0, 0.9)]),
        ..small()
    };
    let mut m = AvoidanceMap::new(knots, (0.0, 0.0)).unwrap();
    m.log_odds[..5].copy_from_slice(&[-3.0, -1.0, 1.0, 3.0, 2.0]);
    m.probabilities(&mut p);
    for (got, want) in p[..5].iter().zip([0.02, 0.16, 0.6, 0.9, 0.9]) {
        assert!((got - want).abs() < 1e-12, "{got} {want}");
    }
}

#[test]
fn a_laser_scan_frees_its_beams_and_marks_its_returns() {
    let mut m = AvoidanceMap::new(small(), (0.0, 0.0)).unwrap();
    let angles = [-0.1, 0.0, 0.1];
    m.insert_laser(
        Pose2::new(0.0, 0.0, 0.0),
        &[0.55, 0.55, f64::INFINITY],
        &angles,
        0.8,
        None,
    )
    .unwrap();
    let n = m.side();
    let (x0, y0) = m.origin_cells();
    let cell = |x: f64, y: f64| {
        ((y / 0.1).floor() as i64 - y0) as usize * n + ((x / 0.1).floor() as i64 - x0) as usize
    };
    assert_eq!(m.log_odds[cell(0.55, 0.0)], LASER_HIT_NATS);
    assert_eq!(m.plan_log_odds[cell(0.55, 0.0)], LASER_HIT_NATS);
    assert_eq!(m.log_odds[cell(0.25, 0.0)], LASER_MISS_NATS);
    assert!(m
        .insert_laser(Pose2::IDENTITY, &[1.0], &[], 1.0, None)
        .is_err());
}
