//! The local map against a global map built from the same data: equal over the window for
//! every cell that never left it, whatever the moves.

use std::collections::HashMap;

use floorscan_core::grid::{CellRect, Grid};
use floorscan_core::grid_options::GridOptions;
use floorscan_core::inserter::{Inserter, InserterOptions};
use floorscan_core::laser::{BeamAngles, LaserScan};
use floorscan_core::local_map::{LocalMap, LocalMapOptions};
use floorscan_core::raycast::CellIndex;
use floorscan_core::{ColumnOutcome, ColumnReading, Error, Point2, Pose2, Scan};

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A local map with the default options at the origin.
fn default_local() -> LocalMap {
    LocalMap::new(
        LocalMapOptions::default(),
        InserterOptions::default(),
        Pose2::IDENTITY,
    )
    .unwrap()
}

fn visual_scan(rng: &mut Rng) -> Scan {
    let readings = (0..32)
        .map(|i| {
            let a = -0.7 + 1.4 * i as f64 / 31.0;
            let (s, c) = a.sin_cos();
            let r = 0.4 + 2.5 * rng.next();
            let outcome = if rng.next() < 0.8 {
                ColumnOutcome::Boundary {
                    row: 100.0,
                    point: Point2::new(r * c, r * s),
                    footprint_m: 0.0,
                }
            } else {
                ColumnOutcome::NoBoundary {
                    top_row: 10.0,
                    farthest: Point2::new(r * c, r * s),
                }
            };
            ColumnReading {
                column: i,
                start_row: 470.0,
                near: Some(Point2::new(0.35 * c, 0.35 * s)),
                outcome,
                confidence: 1.0,
            }
        })
        .collect();
    Scan {
        timestamp_s: 0.0,
        readings,
    }
}

/// Drives `steps` random increments (each within `step_m` and 0.3 rad), inserting a visual
/// scan and a laser scan at every pose into both maps; returns, per cell of the final window,
/// whether it stayed inside the window the whole time.
fn drive(
    local: &mut LocalMap,
    global: &mut Grid,
    rng: &mut Rng,
    steps: usize,
    step_m: f64,
    by_increments: bool,
) -> HashMap<CellIndex, bool> {
    // The global map gets the local map's visual evidence (its own option).
    let mut inserter = Inserter::new(InserterOptions {
        visual: local.options().visual,
        ..Default::default()
    })
    .unwrap();
    let mount = Pose2::new(0.12, 0.0, 0.0);
    let mut pose = local.pose();
    let mut always_inside: HashMap<CellIndex, bool> = HashMap::new();
    let w = local.window();
    for y in w.min.y..w.max.y {
        for x in w.min.x..w.max.x {
            always_inside.insert(CellIndex::new(x, y), true);
        }
    }
    let mut scrolls = 0;
    for _ in 0..steps {
        let delta = Pose2::new(
            step_m * (rng.next() - 0.3),
            step_m * (rng.next() - 0.5),
            0.3 * (rng.next() - 0.5),
        );
        pose = pose.compose(&delta);
        let before = local.window();
        if by_increments {
            local.move_by(&delta).unwrap();
        } else {
            local.move_to(&pose).unwrap();
        }
        assert_eq!(local.pose(), pose);
        if local.window() != before {
            scrolls += 1;
        }
        let w = local.window();
        for (c, inside) in always_inside.iter_mut() {
            *inside &= w.contains(*c);
        }
        for y in w.min.y..w.max.y {
            for x in w.min.x..w.max.x {
                always_inside.entry(CellIndex::new(x, y)).or_insert(false);
            }
        }
        let scan = visual_scan(rng);
        local.insert_scan(&scan, &mount).unwrap();
        inserter.insert_scan(global, &scan, &pose, &mount).unwrap();
        let ranges: Vec<f64> = (0..90).map(|_| 0.3 + 3.0 * rng.next()).collect();
        let laser = LaserScan {
            ranges_m: &ranges,
            angles: BeamAngles::Uniform {
                min_rad: -3.1,
                increment_rad: 0.069,
            },
            range_min_m: 0.1,
            range_max_m: 2.5,
        };
        local.insert_laser(&laser, &Pose2::IDENTITY).unwrap();
        inserter
            .insert_laser(global, &laser, &pose, &Pose2::IDENTITY)
            .unwrap();
    }
    assert!(
        scrolls > steps / 4,
        "the window should have scrolled often, got {scrolls} scrolls"
    );
    always_inside
}

fn compare(
    local: &LocalMap,
    global: &Grid,
    always_inside: &HashMap<CellIndex, bool>,
) -> (usize, usize) {
    let w = local.window();
    let (mut compared, mut known) = (0, 0);
    for y in w.min.y..w.max.y {
        for x in w.min.x..w.max.x {
            let c = CellIndex::new(x, y);
            if always_inside[&c] {
                assert_eq!(local.grid().get(c), global.get(c), "cell {c:?}");
                compared += 1;
                known += usize::from(global.get(c).0 != 0);
            }
        }
    }
    (compared, known)
}

#[test]
fn local_map_equals_global_map_over_the_window_with_absolute_poses() {
    let mut rng = Rng(0x1234_5678_9ABC_DEF1);
    let start = Pose2::new(1.3, -0.7, 0.4);
    let mut local = LocalMap::new(
        LocalMapOptions::default(),
        InserterOptions::default(),
        start,
    )
    .unwrap();
    let mut global = Grid::new(GridOptions::default()).unwrap();
    let inside = drive(&mut local, &mut global, &mut rng, 150, 0.06, false);
    let (compared, known) = compare(&local, &global, &inside);
    assert!(
        compared > 2000 && known > 1000,
        "compared {compared} cells, {known} known"
    );
}

#[test]
fn local_map_equals_global_map_over_the_window_with_increments() {
    let mut rng = Rng(0x0F0F_1234_ABCD_5555);
    let mut local = default_local();
    let mut global = Grid::new(GridOptions::default()).unwrap();
    let inside = drive(&mut local, &mut global, &mut rng, 150, 0.06, true);
    let (compared, known) = compare(&local, &global, &inside);
    assert!(
        compared > 2000 && known > 1000,
        "compared {compared} cells, {known} known"
    );
}

#[test]
fn cells_that_scroll_out_are_forgotten_and_come_back_unknown() {
    let mut local = default_local();
    let ranges = [1.0];
    let laser = LaserScan {
        ranges_m: &ranges,
        angles: BeamAngles::Uniform {
            min_rad: 0.0,
            increment_rad: 0.0,
        },
        range_min_m: 0.1,
        range_max_m: 3.0,
    };
    local.insert_laser(&laser, &Pose2::IDENTITY).unwrap();
    let hit = local.grid().cell_of(Point2::new(1.0, 0.0)).unwrap();
    assert!(local.grid().get(hit).0 > 0);
    local.move_by(&Pose2::new(10.0, 0.0, 0.0)).unwrap();
    assert!(!local.window().contains(hit));
    local.move_by(&Pose2::new(-10.0, 0.0, 0.0)).unwrap();
    assert!(local.window().contains(hit));
    assert_eq!(local.grid().get(hit).0, 0);
    assert_eq!(local.grid().known_rect(), None);
}

#[test]
fn window_is_centred_on_the_robot_and_keeps_the_sub_cell_remainder() {
    let mut local = default_local();
    let w = local.window();
    assert_eq!((w.width(), w.height()), (96, 96));
    assert_eq!(w.min, CellIndex::new(-48, -48));
    // 1000 moves of 1.5 cm: the window follows by whole cells, the pose keeps the rest.
    for _ in 0..1000 {
        local.move_by(&Pose2::new(0.015, 0.0, 0.0)).unwrap();
    }
    assert!((local.pose().x - 15.0).abs() < 1e-9);
    let centre = local.grid().cell_of(local.pose().translation()).unwrap();
    assert_eq!(centre, CellIndex::new(375, 0));
    assert_eq!(local.window().min, CellIndex::new(375 - 48, -48));
}

#[test]
fn robot_view_is_the_window_seen_from_the_robot() {
    // Robot facing +y (world); an obstacle 1 m ahead of it is at world (0, 1). In the robot
    // view (x forward = columns, y left = rows), it is 1 m ahead on the centre row.
    // The robot stands on a lattice corner, so the view's cell centres are the map's.
    let mut local = LocalMap::new(
        LocalMapOptions::default(),
        InserterOptions::default(),
        Pose2::new(0.0, 0.0, std::f64::consts::FRAC_PI_2),
    )
    .unwrap();
    let ranges = [1.0];
    let laser = LaserScan {
        ranges_m: &ranges,
        angles: BeamAngles::Uniform {
            min_rad: 0.0,
            increment_rad: 0.0,
        },
        range_min_m: 0.1,
        range_max_m: 3.0,
    };
    local.insert_laser(&laser, &Pose2::IDENTITY).unwrap();
    let mut view = Vec::new();
    local.robot_view(96, 96, &mut view);
    // The beam runs along world x in [0, 0.04): robot y (left) = -world x, so row 47, whose
    // centre is at robot y = -0.02 m. The hit cell spans robot x in [1.00, 1.04): column 73.
    let positive: Vec<(usize, usize)> = (0..view.len())
        .filter(|&k| view[k] > 0)
        .map(|k| (k / 96, k % 96))
        .collect();
    assert_eq!(positive, vec![(47, 73)]);
    let free: Vec<(usize, usize)> = (0..view.len())
        .filter(|&k| view[k] < 0)
        .map(|k| (k / 96, k % 96))
        .collect();
    assert_eq!(
        free,
        (48..73).map(|c| (47, c)).collect::<Vec<_>>(),
        "free from the robot to the hit"
    );
}

#[test]
fn bad_moves_and_options_are_refused() {
    let mut local = default_local();
    assert!(matches!(
        local.move_by(&Pose2::new(f64::NAN, 0.0, 0.0)),
        Err(Error::InvalidGeometry(_))
    ));
    assert_eq!(local.pose(), Pose2::IDENTITY);
    let bad = LocalMapOptions {
        size_m: 0.01,
        ..Default::default()
    };
    assert!(LocalMap::new(bad, InserterOptions::default(), Pose2::IDENTITY).is_err());
    let g = GridOptions {
        bounds_m: Some(floorscan_core::grid_options::Bounds {
            min: Point2::new(0.0, 0.0),
            max: Point2::new(1.0, 1.0),
        }),
        ..Default::default()
    };
    assert!(LocalMap::new(
        LocalMapOptions {
            grid: g,
            ..Default::default()
        },
        InserterOptions::default(),
        Pose2::IDENTITY
    )
    .is_err());
    let _ = CellRect {
        min: CellIndex::default(),
        max: CellIndex::default(),
    };
}

#[test]
fn the_local_map_settles_in_two_frames_with_its_own_visual_evidence() {
    // The same view twice: every cell the view clears is free after the second frame (two
    // misses of -0.75 nats pass the free threshold's -1.41), every boundary cell occupied
    // after the first; the global map's default evidence (-0.4) needs four frames.
    let scan = visual_scan(&mut Rng(0x5EED_0000_0000_0001));
    let mount = Pose2::new(0.12, 0.0, 0.0);
    let mut local = default_local();
    let mut global = Grid::new(GridOptions::default()).unwrap();
    let mut inserter = Inserter::new(InserterOptions::default()).unwrap();
    let limits = local.grid().limits();
    let classes = |g: &Grid, w: CellRect| {
        let (mut free, mut occupied, mut known) = (0, 0, 0);
        for y in w.min.y..w.max.y {
            for x in w.min.x..w.max.x {
                let v = g.get(CellIndex::new(x, y)).0;
                known += usize::from(v != 0);
                free += usize::from(v != 0 && v <= limits.free_at);
                occupied += usize::from(v >= limits.occupied_at);
            }
        }
        (free, occupied, known)
    };
    let w = local.window();
    for frame in 1..=4 {
        local.insert_scan(&scan, &mount).unwrap();
        inserter
            .insert_scan(&mut global, &scan, &Pose2::IDENTITY, &mount)
            .unwrap();
        let (free, occupied, known) = classes(local.grid(), w);
        let (g_free, g_occupied, g_known) = classes(&global, w);
        assert!(
            known > 200 && occupied > 10,
            "{known} known, {occupied} occupied"
        );
        assert_eq!(free + occupied == known, frame >= 2, "local, frame {frame}");
        assert_eq!(
            g_free + g_occupied == g_known,
            frame >= 4,
            "global, frame {frame}"
        );
    }
}
