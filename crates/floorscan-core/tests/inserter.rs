//! The update rules against hand-worked expectations on tiny grids (1 m cells so the geometry
//! can be checked by eye), and against a straightforward reference implementation of the
//! once-per-scan rule on random scans.

use std::collections::{HashMap, HashSet};

use floorscan_core::grid::{CellRect, Grid};
use floorscan_core::grid_options::{Bounds, GridOptions, RayWalk};
use floorscan_core::inserter::{Inserter, InserterOptions, TooClosePolicy};
use floorscan_core::laser::{BeamAngles, LaserScan};
use floorscan_core::log_odds::Evidence;
use floorscan_core::ray_update::Ray;
use floorscan_core::raycast::{cells_on_segment, CellIndex, FixedPoint};
use floorscan_core::sonar::SonarReading;
use floorscan_core::{ColumnOutcome, ColumnReading, Error, Point2, Pose2, Scan};

const HIT: i16 = 850;
const MISS: i16 = -400;

fn unit_grid() -> Grid {
    Grid::new(GridOptions {
        cell_size_m: 1.0,
        ..Default::default()
    })
    .unwrap()
}

fn inserter() -> Inserter {
    Inserter::new(InserterOptions::default()).unwrap()
}

/// Row `y` of the grid from x = 0 to `n - 1`.
fn row(g: &Grid, y: i32, n: i32) -> Vec<i16> {
    (0..n).map(|x| g.get(CellIndex::new(x, y)).0).collect()
}

fn reading(near: Option<(f64, f64)>, outcome: ColumnOutcome) -> ColumnReading {
    ColumnReading {
        column: 0,
        start_row: 100.0,
        near: near.map(|(x, y)| Point2::new(x, y)),
        outcome,
        confidence: 1.0,
    }
}

fn boundary(near: (f64, f64), x: f64, y: f64) -> ColumnReading {
    reading(
        Some(near),
        ColumnOutcome::Boundary {
            row: 50.0,
            point: Point2::new(x, y),
            footprint_m: 0.0,
        },
    )
}

fn scan(readings: Vec<ColumnReading>) -> Scan {
    Scan {
        timestamp_s: 0.0,
        readings,
    }
}

const ROBOT: Pose2 = Pose2::new(0.5, 0.5, 0.0);

#[test]
fn boundary_cell_incremented_cells_between_decremented_beyond_untouched() {
    let mut g = unit_grid();
    let s = scan(vec![boundary((2.0, 0.0), 4.0, 0.0)]);
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    // Robot in cell 0; the camera sees from 2.5 m (cell 2) to the boundary at 4.5 m (cell 4).
    //                     0  1  2     3     4    5  6
    assert_eq!(row(&g, 0, 7), vec![0, 0, MISS, MISS, HIT, 0, 0]);
    assert_eq!(row(&g, 1, 7), vec![0; 7]);
}

#[test]
fn without_a_near_point_free_space_starts_at_the_camera() {
    let mut g = unit_grid();
    let s = scan(vec![reading(
        None,
        ColumnOutcome::Boundary {
            row: 50.0,
            point: Point2::new(3.0, 0.0),
            footprint_m: 0.0,
        },
    )]);
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 5), vec![MISS, MISS, MISS, HIT, 0]);
}

#[test]
fn the_floor_just_before_an_uncertain_boundary_is_left_unobserved() {
    // Boundary at x = 5.5 with a footprint of 1.2 cells: with a margin of one pixel row, free
    // space ends at x = 4.3 (cell 4), cell 5 gets the hit, nothing in between.
    let one_row = || {
        Inserter::new(InserterOptions {
            boundary_margin_rows: 1.0,
            ..Default::default()
        })
        .unwrap()
    };
    let mut g = unit_grid();
    let s = scan(vec![reading(
        Some((0.5, 0.5)),
        ColumnOutcome::Boundary {
            row: 50.0,
            point: Point2::new(5.5, 0.5),
            footprint_m: 1.2,
        },
    )]);
    one_row()
        .insert_scan(&mut g, &s, &Pose2::IDENTITY, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 7), vec![MISS, MISS, MISS, MISS, MISS, HIT, 0]);
    // A footprint of 2.6 cells leaves cells 3 and 4 unobserved: free space ends at x = 2.9.
    let mut g = unit_grid();
    let s = scan(vec![reading(
        Some((0.5, 0.5)),
        ColumnOutcome::Boundary {
            row: 50.0,
            point: Point2::new(5.5, 0.5),
            footprint_m: 2.6,
        },
    )]);
    one_row()
        .insert_scan(&mut g, &s, &Pose2::IDENTITY, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 7), vec![MISS, MISS, MISS, 0, 0, HIT, 0]);
}

#[test]
fn camera_mount_and_robot_pose_place_the_points() {
    let mut g = unit_grid();
    // Robot at (5.5, 5.5) facing +y; camera 1 m ahead of the robot, looking to the robot's
    // left (world -x). A boundary 2 m ahead of the camera is at world (3.5, 6.5).
    let world_from_robot = Pose2::new(5.5, 5.5, std::f64::consts::FRAC_PI_2);
    let robot_from_camera = Pose2::new(1.0, 0.0, std::f64::consts::FRAC_PI_2);
    let s = scan(vec![boundary((1.0, 0.0), 2.0, 0.0)]);
    inserter()
        .insert_scan(&mut g, &s, &world_from_robot, &robot_from_camera)
        .unwrap();
    assert_eq!(row(&g, 6, 7), vec![0, 0, 0, HIT, MISS, 0, 0]);
    assert_eq!(
        g.get(CellIndex::new(5, 6)).0,
        0,
        "the camera's own cell is not in view"
    );
}

#[test]
fn no_boundary_clears_up_to_and_including_the_farthest_point() {
    let mut g = unit_grid();
    let s = scan(vec![reading(
        Some((1.0, 0.0)),
        ColumnOutcome::NoBoundary {
            top_row: 10.0,
            farthest: Point2::new(3.0, 0.0),
        },
    )]);
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 6), vec![0, MISS, MISS, MISS, 0, 0]);
}

#[test]
fn too_close_marks_the_near_edge_unless_ignored_and_invalid_does_nothing() {
    let s = scan(vec![
        reading(Some((2.0, 0.0)), ColumnOutcome::TooClose),
        reading(Some((2.0, 1.0)), ColumnOutcome::Invalid { row: None }),
    ]);
    let mut g = unit_grid();
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 4), vec![0, 0, HIT, 0]);
    assert_eq!(row(&g, 1, 4), vec![0; 4]);

    let mut g = unit_grid();
    let mut ins = Inserter::new(InserterOptions {
        too_close: TooClosePolicy::Ignore,
        ..Default::default()
    })
    .unwrap();
    ins.insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(g.allocated_tiles(), 0);
}

#[test]
fn each_cell_is_updated_once_per_scan() {
    let mut g = unit_grid();
    // Three columns along nearly the same line: cells 2 and 3 are crossed three times and the
    // boundary cell 4 is hit three times, but each changes once.
    let s = scan(vec![
        boundary((2.0, 0.0), 4.0, 0.0),
        boundary((2.1, 0.1), 4.2, 0.1),
        boundary((2.0, 0.2), 4.4, 0.3),
    ]);
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 6), vec![0, 0, MISS, MISS, HIT, 0]);
    // A second scan is a new scan: everything changes once more.
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 6), vec![0, 0, 2 * MISS, 2 * MISS, 2 * HIT, 0]);
}

#[test]
fn occupied_wins_over_free_in_the_same_scan() {
    let mut g = unit_grid();
    // Column A sees a boundary in cell 2; column B looks through cell 2 to a boundary in
    // cell 5. Cell 2 is occupied once, not occupied and free.
    let s = scan(vec![
        boundary((1.0, 0.0), 2.0, 0.0),
        boundary((1.0, 0.0), 5.0, 0.0),
    ]);
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g, 0, 7), vec![0, MISS, HIT, MISS, MISS, HIT, 0]);
    // The order of the columns does not matter.
    let mut g2 = unit_grid();
    let s2 = scan(vec![
        boundary((1.0, 0.0), 5.0, 0.0),
        boundary((1.0, 0.0), 2.0, 0.0),
    ]);
    inserter()
        .insert_scan(&mut g2, &s2, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(row(&g2, 0, 7), row(&g, 0, 7));
}

#[test]
fn values_stay_within_the_clamp_bounds() {
    let mut g = unit_grid();
    let s = scan(vec![boundary((1.0, 0.0), 3.0, 0.0)]);
    let mut ins = inserter();
    for _ in 0..20 {
        ins.insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
            .unwrap();
    }
    // 20 hits of 0.85 would be 17 nats; the clamp stops at 3.5. 20 misses stop at -2.0.
    assert_eq!(row(&g, 0, 5), vec![0, -2000, -2000, 3500, 0]);
    // With the clamp, a changed world shows after a few scans: the boundary moves away.
    let moved = scan(vec![boundary((1.0, 0.0), 4.0, 0.0)]);
    for _ in 0..13 {
        ins.insert_scan(&mut g, &moved, &ROBOT, &Pose2::IDENTITY)
            .unwrap();
    }
    assert_eq!(g.get(CellIndex::new(3, 0)).0, 3500 - 13 * 400);
    assert!(
        g.get(CellIndex::new(3, 0)).probability() < 0.196,
        "the old obstacle is free again"
    );
}

#[test]
fn laser_hits_mark_and_max_range_readings_only_clear() {
    let mut g = unit_grid();
    let ranges = [3.0, 10.0, f64::INFINITY];
    let laser = LaserScan {
        ranges_m: &ranges,
        angles: BeamAngles::Explicit(&[0.0, std::f64::consts::FRAC_PI_2, std::f64::consts::PI]),
        range_min_m: 0.1,
        range_max_m: 3.0 + 1e-9,
    };
    let robot = Pose2::new(4.5, 4.5, 0.0);
    inserter()
        .insert_laser(&mut g, &laser, &robot, &Pose2::IDENTITY)
        .unwrap();
    assert_eq!(
        row(&g, 4, 9),
        vec![0, MISS, MISS, MISS, MISS, MISS, MISS, HIT, 0]
    );
    // Upward beam: beyond range_max, cleared up to it (cells 5, 6 and 7), not marked.
    let up: Vec<i16> = (4..10).map(|y| g.get(CellIndex::new(4, y)).0).collect();
    assert_eq!(up, vec![MISS, MISS, MISS, MISS, 0, 0]);
}

#[test]
fn sonar_marks_the_arc_and_frees_the_cone() {
    let mut g = Grid::new(GridOptions {
        cell_size_m: 0.1,
        ..Default::default()
    })
    .unwrap();
    let reading = SonarReading {
        range_m: 2.0,
        beam_width_rad: 0.5,
        range_max_m: 5.0,
    };
    let sonar_pose = Pose2::new(0.05, 0.05, 0.0);
    inserter()
        .insert_sonar(&mut g, &[reading], &Pose2::IDENTITY, &[sonar_pose])
        .unwrap();
    for y in -12..=12 {
        for x in -3..=25 {
            let c = CellIndex::new(x, y);
            let p = g.cell_center(c);
            let (dx, dy) = (p.x - 0.05, p.y - 0.05);
            let (r, bearing) = (dx.hypot(dy), dy.atan2(dx));
            let v = g.get(c).0;
            if bearing.abs() > 0.25 + 0.1 / r.max(0.1) + 0.05 || r > 2.0 + 0.15 {
                assert_eq!(v, 0, "cell {c:?} outside the cone must be untouched");
            } else if bearing.abs() < 0.2 && r < 1.8 && r > 0.15 {
                assert_eq!(v, -200, "cell {c:?} inside the cone must be free");
            } else if bearing.abs() < 0.2 && (r - 2.0).abs() < 0.03 {
                assert_eq!(v, 400, "cell {c:?} on the arc must be occupied");
            }
        }
    }
}

#[test]
fn fixed_bounds_clip_rays_and_refuse_poses_outside() {
    let bounds = Bounds {
        min: Point2::new(0.0, 0.0),
        max: Point2::new(4.0, 2.0),
    };
    let mut g = Grid::new(GridOptions {
        cell_size_m: 1.0,
        bounds_m: Some(bounds),
        ..Default::default()
    })
    .unwrap();
    let s = scan(vec![boundary((1.0, 0.0), 6.0, 0.0)]);
    inserter()
        .insert_scan(&mut g, &s, &ROBOT, &Pose2::IDENTITY)
        .unwrap();
    // The boundary lies outside: the ray is cleared up to the edge, nothing is marked.
    assert_eq!(row(&g, 0, 4), vec![0, MISS, MISS, MISS]);
    let before: Vec<i16> = row(&g, 0, 4);
    let e = inserter()
        .insert_scan(&mut g, &s, &Pose2::new(4.5, 0.5, 0.0), &Pose2::IDENTITY)
        .unwrap_err();
    assert!(matches!(e, Error::OutOfBounds(_)), "{e}");
    assert_eq!(row(&g, 0, 4), before);
}

#[test]
fn bad_input_leaves_the_map_unchanged() {
    let mut g = unit_grid();
    let mut ins = inserter();
    let good = boundary((1.0, 0.0), 3.0, 0.0);
    let bad = boundary((1.0, 0.0), f64::NAN, 0.0);
    assert!(matches!(
        ins.insert_scan(&mut g, &scan(vec![good, bad]), &ROBOT, &Pose2::IDENTITY),
        Err(Error::InvalidGeometry(_))
    ));
    assert!(matches!(
        ins.insert_scan(
            &mut g,
            &scan(vec![good]),
            &Pose2::new(f64::NAN, 0.0, 0.0),
            &Pose2::IDENTITY
        ),
        Err(Error::InvalidGeometry(_))
    ));
    assert!(matches!(
        ins.insert_scan(
            &mut g,
            &scan(vec![good]),
            &ROBOT,
            &Pose2::new(0.0, 0.0, f64::INFINITY)
        ),
        Err(Error::InvalidGeometry(_))
    ));
    let ranges = [1.0, 2.0, 3.0];
    let layout = LaserScan {
        ranges_m: &[0.0; 2],
        angles: BeamAngles::Uniform {
            min_rad: 0.0,
            increment_rad: 0.1,
        },
        range_min_m: 0.0,
        range_max_m: 10.0,
    };
    let e = ins
        .insert_lasers(&mut g, &layout, &ranges, &[ROBOT, ROBOT], &Pose2::IDENTITY)
        .unwrap_err();
    assert!(matches!(e, Error::LengthMismatch(_)));
    let ranges = [1.0, 2.0, 3.0, f64::NAN];
    let e = ins
        .insert_lasers(&mut g, &layout, &ranges, &[ROBOT, ROBOT], &Pose2::IDENTITY)
        .unwrap_err();
    assert!(e.to_string().contains("scan 1"), "{e}");
    let reading = SonarReading {
        range_m: 1.0,
        beam_width_rad: 0.3,
        range_max_m: 4.0,
    };
    assert!(matches!(
        ins.insert_sonar(&mut g, &[reading, reading], &ROBOT, &[Pose2::IDENTITY]),
        Err(Error::LengthMismatch(_))
    ));
    assert_eq!(g.allocated_tiles(), 0);
    assert_eq!(g.known_rect(), None);
}

/// The thin walk's cells by its definition: the exact walk's start and end cells and every
/// cell it enters by a step along the ray's major axis.
fn thin_reference(a: FixedPoint, b: FixedPoint) -> Vec<CellIndex> {
    let exact: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
    let major_x = (b.x - a.x).abs() >= (b.y - a.y).abs();
    let major = |c: &CellIndex| if major_x { c.x } else { c.y };
    let last = exact.len() - 1;
    (0..exact.len())
        .filter(|&i| i == 0 || i == last || major(&exact[i]) != major(&exact[i - 1]))
        .map(|i| exact[i])
        .collect()
}

/// The once-per-scan rule written plainly: hit cells of the scan get one hit each; every
/// other cell on any ray (by the grid's walk) gets one miss.
/// Returns the cells the rays' walks visit, repeats included.
fn reference_update(values: &mut HashMap<CellIndex, i32>, g: &Grid, rays: &[Ray]) -> u64 {
    let fp = |p: Point2| {
        let (u, v) = g.to_cells(p);
        FixedPoint::from_cells(u, v).unwrap()
    };
    let hits: HashSet<CellIndex> = rays
        .iter()
        .filter(|r| r.hit)
        .map(|r| fp(r.to).cell())
        .collect();
    let mut free = HashSet::new();
    let mut walked = 0;
    for r in rays {
        let cells: Vec<CellIndex> = match g.options().ray_walk {
            RayWalk::Exact => cells_on_segment(fp(r.from), fp(r.to)).unwrap().collect(),
            RayWalk::Thin => thin_reference(fp(r.from), fp(r.to)),
        };
        walked += cells.len() as u64;
        free.extend(cells.into_iter().filter(|c| !hits.contains(c)));
    }
    for c in hits {
        let v = values.entry(c).or_default();
        *v = (*v + i32::from(HIT)).min(3500);
    }
    for c in free {
        let v = values.entry(c).or_default();
        *v = (*v + i32::from(MISS)).max(-2000);
    }
    walked
}

#[test]
fn random_scans_match_the_reference_rule_across_tiles() {
    random_scans_match_the_reference_rule(RayWalk::Exact);
}

#[test]
fn random_scans_match_the_reference_rule_with_the_thin_walk() {
    random_scans_match_the_reference_rule(RayWalk::Thin);
}

fn random_scans_match_the_reference_rule(ray_walk: RayWalk) {
    // A small deterministic generator (no dependency on rand).
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut g = Grid::new(GridOptions {
        ray_walk,
        ..Default::default()
    })
    .unwrap();
    let mut ins = inserter();
    let mut expected: HashMap<CellIndex, i32> = HashMap::new();
    let (mut traversed, mut expected_traversed) = (0, 0);
    for _ in 0..40 {
        let origin = Point2::new(next() * 8.0 - 4.0, next() * 8.0 - 4.0);
        let rays: Vec<Ray> = (0..48)
            .map(|_| {
                let (a, r) = (next() * std::f64::consts::TAU, next() * 6.0);
                let near = 0.3 * next();
                Ray {
                    from: Point2::new(origin.x + near * a.cos(), origin.y + near * a.sin()),
                    to: Point2::new(origin.x + r * a.cos(), origin.y + r * a.sin()),
                    hit: next() < 0.7,
                }
            })
            .collect();
        traversed += ins
            .insert_rays(
                &mut g,
                &rays,
                Evidence {
                    hit_nats: 0.85,
                    miss_nats: -0.4,
                },
            )
            .unwrap()
            .cells_traversed;
        expected_traversed += reference_update(&mut expected, &g, &rays);
    }
    assert_eq!(traversed, expected_traversed, "cells walked");
    let rect = g.known_rect().unwrap();
    let mut values = Vec::new();
    g.read_rect(rect, &mut values);
    let mut compared = 0;
    for (i, &v) in values.iter().enumerate() {
        let c = CellIndex::new(
            rect.min.x + (i % rect.width()) as i32,
            rect.min.y + (i / rect.width()) as i32,
        );
        assert_eq!(
            i32::from(v),
            expected.get(&c).copied().unwrap_or(0),
            "cell {c:?}"
        );
        compared += usize::from(v != 0);
    }
    assert!(
        compared > 10_000,
        "the scans should cover many cells, got {compared}"
    );
    assert!(
        g.allocated_tiles() > 4,
        "the scans should span several tiles"
    );
    let _ = CellRect {
        min: rect.min,
        max: rect.max,
    };
}
