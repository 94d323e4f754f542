//! Tests of [`super`] (avoidance_map.rs).

use super::*;

fn model() -> VisualModel {
    VisualModel {
        free_a: -3.2,
        free_b: 0.55,
        hit_a: 2.0,
        hit_b: -0.45,
        too_close_logit: 1.0,
        margin_sigmas: 2.0,
        default_error_m: 0.01,
        fusion_weight: 0.7,
        no_boundary_clearing: 1.0,
        confirmed_nats: 1.5,
        confirm_range_m: 0.0,
        confirmed_clearing: 1.0,
        persist_range_m: 0.0,
    }
}

/// A straight wall 1.5 m ahead of a camera at the window's centre, seen by 41 columns.
type Columns = (Vec<u8>, Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>);

fn wall(n: usize) -> Columns {
    let status = vec![BOUNDARY; n];
    let mut x = Vec::new();
    let mut y = Vec::new();
    let mut nx = Vec::new();
    let mut ny = Vec::new();
    for k in 0..n {
        let a = -0.6 + 1.2 * k as f64 / (n - 1) as f64;
        x.push(1.5);
        y.push(1.5 * a.tan());
        nx.push(0.3);
        ny.push(0.3 * a.tan());
    }
    (status, x, y, nx, ny)
}

#[test]
fn a_wall_ahead_is_occupied_and_the_floor_before_it_free() {
    let side = 100;
    let mut map = AvoidanceUpdates::new(side, 0.05, (-2.0, 3.5)).unwrap();
    let mut l = vec![0.0f32; side * side];
    let mut c = vec![0u8; side * side];
    let (status, x, y, nx, ny) = wall(41);
    let fp = vec![0.01; 41];
    let err = vec![f64::NAN; 41];
    let r = VisualReadings {
        status: &status,
        x_m: &x,
        y_m: &y,
        near_x_m: &nx,
        near_y_m: &ny,
        footprint_m: &fp,
        error_m: &err,
    };
    // camera at (2.5, 2.5) m: cell (50, 50)
    let cam = Pose2::new(2.5, 2.5, 0.0);
    let mut insert = |l: &mut [f32], c: &mut [u8]| {
        map.insert_visual(l, c, None, (0, 0), cam, &r, &model())
            .unwrap()
    };
    insert(&mut l, &mut c);
    let at = |l: &[f32], x: f64, y: f64| l[(y / 0.05) as usize * side + (x / 0.05) as usize];
    assert!(at(&l, 2.5 + 1.5, 2.5) > 0.5, "{}", at(&l, 4.0, 2.5));
    assert!(at(&l, 2.5 + 1.0, 2.5) < -0.5);
    assert!(at(&l, 2.5 + 0.5, 2.5 + 0.1) < -0.5);
    assert_eq!(at(&l, 2.5 - 0.5, 2.5), 0.0); // behind the camera
    assert_eq!(at(&l, 2.5 + 2.0, 2.5), 0.0); // behind the wall
    assert_eq!(
        c[(2.5f64 / 0.05) as usize * side + (4.0f64 / 0.05) as usize],
        1
    ); // 1.5 m
       // the scratch layers are reset: a second insertion adds the same evidence again
    let once = l.clone();
    insert(&mut l, &mut c);
    for (a, b) in l.iter().zip(&once) {
        assert!((a - (2.0 * b).clamp(-2.0, 3.5)).abs() < 1e-5);
    }
}

/// Readings of `status` codes at points (x, y) with near edges (nx, ny), footprints `fp`
/// and predicted errors `err`.
fn readings<'a>(
    status: &'a [u8],
    (x, y): (&'a [f64], &'a [f64]),
    (nx, ny): (&'a [f64], &'a [f64]),
    (fp, err): (&'a [f64], &'a [f64]),
) -> VisualReadings<'a> {
    VisualReadings {
        status,
        x_m: x,
        y_m: y,
        near_x_m: nx,
        near_y_m: ny,
        footprint_m: fp,
        error_m: err,
    }
}

/// The wall of [`wall`] mapped from 1.5 m (once: one reading, below `confirmed_nats`;
/// twice: confirmed), then seen again by columns that find no boundary (their farthest
/// point 3 m out): a confirmed wall's cells take `clearing` x the free evidence, an
/// unconfirmed one's all of it; seen again by columns that find the floor end farther on,
/// a confirmed wall's cells take `confirmed_clearing` x the free evidence (as do those
/// beside no-boundary columns when `clearing` is 1: then no quadrilateral is weak), an
/// unconfirmed one's all of it; unknown cells before the wall take it in full.
#[test]
fn columns_without_a_boundary_clear_a_confirmed_obstacle_only_by_their_share() {
    let side = 100;
    let n = 41;
    let (status, x, y, nx, ny) = wall(n);
    let fp = vec![0.01; n];
    let err = vec![f64::NAN; n];
    let first = readings(&status, (&x, &y), (&nx, &ny), (&fp, &err));
    let new_map = || {
        let map = AvoidanceUpdates::new(side, 0.05, (-2.0, 3.5)).unwrap();
        (map, vec![0.0f32; side * side], vec![0u8; side * side])
    };
    let cell = |x: f64, y: f64| (y / 0.05) as usize * side + (x / 0.05) as usize;
    let wall_cell = cell(4.0, 2.5);
    // an unknown cell before the wall, out of the first view (behind its near edge)
    let unknown = cell(2.6, 2.5);
    // the same columns' points 3 m out, seen from a camera 0.5 m back (x + 0.5), so the
    // wall, now 2 m ahead, lies inside the new view
    let x2: Vec<f64> = x.iter().map(|a| 2.0 * a + 0.5).collect();
    let y2: Vec<f64> = y.iter().map(|b| 2.0 * b).collect();
    let cam = Pose2::new(2.0, 2.5, 0.0);
    // the free evidence a fully clearing quadrilateral gives at a cell, from that camera
    let free_at = |c: usize| {
        let (i, j) = (c % side, c / side);
        let r = ((i as f64 + 0.5 - 2.0 / 0.05).hypot(j as f64 + 0.5 - 50.0) * 0.05) as f32;
        0.7f32 * (-3.2f32 + 0.55f32 * r)
    };
    // the wall is 1.5 m away: a confirm range beyond that leaves it unconfirmed
    for (clearing, confirm_range_m, confirmed_clearing) in [
        (0.0, 0.0, 1.0),
        (0.25, 0.0, 1.0),
        (1.0, 0.0, 1.0),
        (0.0, 2.0, 1.0),
        (0.0, 0.0, 0.25),
        (1.0, 0.0, 0.25),
        (0.0, 2.0, 0.25),
    ] {
        let m = VisualModel {
            no_boundary_clearing: clearing,
            confirm_range_m,
            confirmed_clearing,
            ..model()
        };
        for (st, times) in [(NO_BOUNDARY, 1), (NO_BOUNDARY, 2), (BOUNDARY, 2)] {
            let (mut map, mut l, mut c) = new_map();
            for _ in 0..times {
                let cam = Pose2::new(2.5, 2.5, 0.0);
                map.insert_visual(&mut l, &mut c, None, (0, 0), cam, &first, &m)
                    .unwrap();
            }
            let before = l[wall_cell];
            assert!(before > 0.5, "{before}");
            assert_eq!(c[wall_cell] == 1, confirm_range_m <= 1.5);
            let confirmed = f64::from(before) > m.confirmed_nats && confirm_range_m <= 1.5;
            assert_eq!(confirmed, times == 2 && confirm_range_m <= 1.5, "{before}");
            assert_eq!(l[unknown], 0.0);
            let s2 = vec![st; n];
            let r = readings(&s2, (&x2, &y2), (&nx, &ny), (&fp, &err));
            map.insert_visual(&mut l, &mut c, None, (0, 0), cam, &r, &m)
                .unwrap();
            // the far boundary's own hits lie 4 m out: the wall's cell is floor seen, in
            // full unless confirmed; then by no-boundary columns by their share, by the
            // others (every column when `clearing` is 1) by the confirmed one
            let share = if !confirmed {
                1.0
            } else if st == BOUNDARY || clearing == 1.0 {
                confirmed_clearing as f32
            } else {
                clearing as f32
            };
            let expect = (before + share * free_at(wall_cell)).clamp(-2.0, 3.5);
            let got = l[wall_cell];
            assert!(
                (got - expect).abs() < 1e-5,
                "{clearing} {st}: {got} {expect}"
            );
            // unknown floor takes the free evidence in full either way
            let u = free_at(unknown).clamp(-2.0, 3.5);
            assert!((l[unknown] - u).abs() < 1e-5, "{} {u}", l[unknown]);
        }
    }
    for bad in [
        VisualModel {
            no_boundary_clearing: 1.5,
            ..model()
        },
        VisualModel {
            confirmed_nats: f64::NAN,
            ..model()
        },
        VisualModel {
            confirmed_nats: -1.0,
            ..model()
        },
        VisualModel {
            confirm_range_m: f64::NAN,
            ..model()
        },
        VisualModel {
            confirmed_clearing: 0.0,
            ..model()
        },
        VisualModel {
            confirmed_clearing: f64::NAN,
            ..model()
        },
        VisualModel {
            persist_range_m: -0.1,
            ..model()
        },
        VisualModel {
            persist_range_m: f64::INFINITY,
            ..model()
        },
    ] {
        let (mut map, mut l, mut c) = new_map();
        let cam = Pose2::new(2.5, 2.5, 0.0);
        assert!(map
            .insert_visual(&mut l, &mut c, None, (0, 0), cam, &first, &bad)
            .is_err());
        assert!(l.iter().all(|&v| v == 0.0));
    }
}

#[test]
fn discs_cover_the_cells_whose_centres_are_within_the_radius() {
    let side = 20;
    let mut hit = vec![f32::NAN; side * side];
    let mut rows = RowSpan::EMPTY;
    let mut confirms = vec![false; side * side];
    let mut unheld = vec![false; side * side];
    stamp_disc(
        (&mut hit, &mut confirms, &mut unheld),
        side,
        7.3,
        9.8,
        2.4,
        (1.0, true, true),
        &mut rows,
    );
    for j in 0..side {
        for i in 0..side {
            let d = ((i as f64 + 0.5 - 7.3).powi(2) + (j as f64 + 0.5 - 9.8).powi(2)).sqrt();
            assert_eq!(hit[j * side + i] == 1.0, d <= 2.4, "{i} {j}");
            assert_eq!(confirms[j * side + i], d <= 2.4);
            assert_eq!(unheld[j * side + i], d <= 2.4);
        }
    }
    assert!(rows.lo == 7 && rows.hi == 12);
    // a huge disc far outside stays within the grid's loops
    stamp_disc(
        (&mut hit, &mut confirms, &mut unheld),
        side,
        -1e300,
        5.0,
        1e200,
        (2.0, false, false),
        &mut rows,
    );
}

#[test]
fn bad_arguments_are_errors() {
    assert!(AvoidanceUpdates::new(0, 0.05, (-2.0, 3.5)).is_err());
    assert!(AvoidanceUpdates::new(MAX_SIDE + 1, 0.05, (-2.0, 3.5)).is_err());
    assert!(AvoidanceUpdates::new(10, 0.0, (-2.0, 3.5)).is_err());
    assert!(AvoidanceUpdates::new(10, 0.05, (1.0, 3.5)).is_err());
    assert!(AvoidanceUpdates::new(10, 0.05, (-2.0, f64::NAN)).is_err());
    let mut map = AvoidanceUpdates::new(10, 0.05, (-2.0, 3.5)).unwrap();
    let mut l = vec![0.0f32; 99];
    let mut c = vec![0u8; 100];
    let r = VisualReadings {
        status: &[],
        x_m: &[],
        y_m: &[],
        near_x_m: &[],
        near_y_m: &[],
        footprint_m: &[],
        error_m: &[],
    };
    assert!(map
        .insert_visual(&mut l, &mut c, None, (0, 0), Pose2::IDENTITY, &r, &model())
        .is_err());
    let mut l = vec![0.0f32; 100];
    let mut short_c = vec![0u8; 99];
    assert!(map
        .insert_visual(
            &mut l,
            &mut short_c,
            None,
            (0, 0),
            Pose2::IDENTITY,
            &r,
            &model()
        )
        .is_err());
    assert!(map
        .insert_visual(
            &mut l,
            &mut c,
            None,
            (0, 0),
            Pose2::new(f64::NAN, 0.0, 0.0),
            &r,
            &model()
        )
        .is_err());
    let short = VisualReadings { status: &[0], ..r };
    assert!(map
        .insert_visual(
            &mut l,
            &mut c,
            None,
            (0, 0),
            Pose2::IDENTITY,
            &short,
            &model()
        )
        .is_err());
    let (mut pl, mut pc, mut pn) = (vec![0.0f32; 99], vec![0u8; 100], vec![0u8; 100]);
    assert!(map
        .insert_visual(
            &mut l,
            &mut c,
            Some(PlanLayers {
                log_odds: &mut pl,
                confirmed: &mut pc,
                near_hits: &mut pn,
            }),
            (0, 0),
            Pose2::IDENTITY,
            &r,
            &model()
        )
        .is_err());
    assert!(map
        .insert_laser(
            &mut l,
            Some(&mut pl),
            [0.0, 0.0],
            &[[1.0, 1.0]],
            &[true],
            1.0,
            -1.0
        )
        .is_err());
}

/// A near hit enters the planner's layers only when it persists: a face 0.4 m ahead
/// (within `persist_range_m` 0.5) seen once is an obstacle in the map's own layer and
/// stays below the planner's threshold (0.6 nats) in the planner's; seen again from the
/// same place it is an obstacle there too; one seen each frame at another place (a fleck
/// that comes and goes) never is; a face beyond the range enters at once; a cell with
/// free evidence takes the hit in full when that stays below the threshold; a near hit on
/// a cell the planner counts an obstacle enters at once; with the range 0 the two layers
/// are equal.
#[test]
fn near_hits_enter_the_planners_layers_when_they_persist() {
    let side = 100;
    let n = 9;
    let face = |ahead: f64, left: f64| {
        let status = vec![BOUNDARY; n];
        let ys: Vec<f64> = (0..n).map(|k| left + 0.01 * k as f64).collect();
        let x = vec![ahead; n];
        let nx = vec![0.25; n];
        (status, x, ys.clone(), nx, ys)
    };
    let fp = vec![0.005; n];
    let err = vec![0.005; n];
    let held = VisualModel {
        persist_range_m: 0.5,
        ..model()
    };
    let cam = Pose2::new(2.5, 2.5, 0.0);
    let cell_of = |ahead: f64, left: f64| {
        ((2.5 + left + 0.04) / 0.05) as usize * side + ((2.5 + ahead) / 0.05) as usize
    };
    struct Run {
        map: AvoidanceUpdates,
        l: Vec<f32>,
        c: Vec<u8>,
        pl: Vec<f32>,
        pc: Vec<u8>,
        pn: Vec<u8>,
    }
    let new_run = || Run {
        map: AvoidanceUpdates::new(side, 0.05, (-2.0, 3.5)).unwrap(),
        l: vec![0.0; side * side],
        c: vec![0; side * side],
        pl: vec![0.0; side * side],
        pc: vec![0; side * side],
        pn: vec![0; side * side],
    };
    let insert = |run: &mut Run, ahead: f64, left: f64, m: &VisualModel| {
        let (status, x, y, nx, ny) = face(ahead, left);
        let r = readings(&status, (&x, &y), (&nx, &ny), (&fp, &err));
        run.map
            .insert_visual(
                &mut run.l,
                &mut run.c,
                Some(PlanLayers {
                    log_odds: &mut run.pl,
                    confirmed: &mut run.pc,
                    near_hits: &mut run.pn,
                }),
                (0, 0),
                cam,
                &r,
                m,
            )
            .unwrap();
    };
    // seen once, then again from the same place
    let mut run = new_run();
    let k = cell_of(0.4, 0.0);
    insert(&mut run, 0.4, 0.0, &held);
    assert!(
        run.l[k] > 0.5,
        "the map's own layer takes the hit: {}",
        run.l[k]
    );
    assert_eq!(run.pl[k], 0.0, "the planner's layer does not yet take it");
    assert_eq!(run.pc[k], 0, "nor does it confirm the cell");
    assert_eq!(
        run.pn[k], 1,
        "the near hit is remembered for the next insertion"
    );
    insert(&mut run, 0.4, 0.0, &held);
    assert!(run.pl[k] > 1.0, "persisting, it enters: {}", run.pl[k]);
    // a fleck at another place each frame (0.3 m apart, all within 0.5 m) never enters
    let mut run = new_run();
    for f in 0..3 {
        insert(&mut run, 0.3, -0.3 + 0.3 * f as f64, &held);
    }
    assert!(
        run.pl.iter().all(|&v| v <= 0.0),
        "a fleck that moves entered"
    );
    assert!(run.l.iter().any(|&v| v > 0.5));
    // beyond the range: at once
    let mut run = new_run();
    insert(&mut run, 1.0, 0.0, &held);
    assert!(run.pl[cell_of(1.0, 0.0)] > 0.5);
    // a cell with free evidence keeps it against a near hit that does not persist
    let mut run = new_run();
    run.pl[k] = -1.5;
    insert(&mut run, 0.4, 0.0, &held);
    assert_eq!(run.pl[k], -1.5);
    // a cell the planner believes occupied takes a near hit at once
    let mut run = new_run();
    run.pl[k] = 1.0;
    insert(&mut run, 0.4, 0.0, &held);
    assert!(run.pl[k] > 1.5, "{}", run.pl[k]);
    // range 0: the planner's layers equal the map's own (confirmed_clearing 1)
    let mut run = new_run();
    for f in 0..3 {
        insert(&mut run, 0.4, -0.3 + 0.3 * f as f64, &model());
    }
    assert_eq!((&run.l, &run.c), (&run.pl, &run.pc));
    assert!(run.pn.iter().all(|&v| v == 0));
}

/// With the planner's layers, the map's own layers evolve as a single map with
/// `confirmed_clearing` 1, the planner's as a single map with the model's share: the wall
/// of [`wall`] mapped twice from 1.5 m, then seen with the floor's end 3 m out, frame
/// after frame (its cells cleared fast in one, slowly in the other), then a laser scan.
#[test]
fn the_planners_layers_clear_confirmed_obstacles_by_their_share_alone() {
    let side = 100;
    let n = 41;
    let (status, x, y, nx, ny) = wall(n);
    let fp = vec![0.01; n];
    let err = vec![f64::NAN; n];
    let first = readings(&status, (&x, &y), (&nx, &ny), (&fp, &err));
    let x2: Vec<f64> = x.iter().map(|a| 2.0 * a + 0.5).collect();
    let y2: Vec<f64> = y.iter().map(|b| 2.0 * b).collect();
    let later = readings(&status, (&x2, &y2), (&nx, &ny), (&fp, &err));
    let slow = VisualModel {
        confirmed_nats: 0.0,
        no_boundary_clearing: 0.0,
        confirmed_clearing: 0.25,
        ..model()
    };
    let fast = VisualModel {
        confirmed_clearing: 1.0,
        ..slow
    };
    let layers = || (vec![0.0f32; side * side], vec![0u8; side * side]);
    let mut both = AvoidanceUpdates::new(side, 0.05, (-2.0, 3.5)).unwrap();
    let mut single = both.clone();
    let ((mut l, mut c), (mut pl, mut pc)) = (layers(), layers());
    let mut pn = vec![0u8; side * side];
    let ((mut fl, mut fc), (mut sl, mut sc)) = (layers(), layers());
    let wall_cell = (2.5 / 0.05) as usize * side + (4.0 / 0.05) as usize;
    let mut differed = false;
    for (k, r) in [&first, &first, &later, &later, &later, &later]
        .iter()
        .enumerate()
    {
        let cam = Pose2::new(if k < 2 { 2.5 } else { 2.0 }, 2.5, 0.0);
        both.insert_visual(
            &mut l,
            &mut c,
            Some(PlanLayers {
                log_odds: &mut pl,
                confirmed: &mut pc,
                near_hits: &mut pn,
            }),
            (0, 0),
            cam,
            r,
            &slow,
        )
        .unwrap();
        single
            .insert_visual(&mut fl, &mut fc, None, (0, 0), cam, r, &fast)
            .unwrap();
        single
            .insert_visual(&mut sl, &mut sc, None, (0, 0), cam, r, &slow)
            .unwrap();
        assert_eq!((&l, &c), (&fl, &fc), "frame {k}");
        assert_eq!((&pl, &pc), (&sl, &sc), "frame {k}");
        differed |= pl[wall_cell] > l[wall_cell] + 0.1;
    }
    assert!(
        differed,
        "the wall's cell never cleared more slowly in the planner's layer"
    );
    let ends = [[60.0, 50.0], [60.0, 55.0], [f64::NAN, 0.0]];
    let ret = [true, true, false];
    both.insert_laser(&mut l, Some(&mut pl), [40.0, 50.0], &ends, &ret, 2.2, -2.0)
        .unwrap();
    single
        .insert_laser(&mut fl, None, [40.0, 50.0], &ends, &ret, 2.2, -2.0)
        .unwrap();
    single
        .insert_laser(&mut sl, None, [40.0, 50.0], &ends, &ret, 2.2, -2.0)
        .unwrap();
    assert_eq!((&l, &pl), (&fl, &sl));
}
