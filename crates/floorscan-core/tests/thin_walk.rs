//! The thin grid walk against its definition written on the exact walk (itself checked against
//! exact rational arithmetic in tests/raycast.rs): the start cell, every cell the exact walk
//! enters by a step along the major axis, and the end cell.

use floorscan_core::raycast::*;
use floorscan_core::thin_walk::*;
use proptest::prelude::*;

mod common;

/// The definition, by filtering the exact walk's cells.
fn reference(a: FixedPoint, b: FixedPoint) -> Vec<CellIndex> {
    let exact: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
    let major_x = (b.x - a.x).abs() >= (b.y - a.y).abs();
    let major = |c: &CellIndex| if major_x { c.x } else { c.y };
    let last = exact.len() - 1;
    exact
        .iter()
        .enumerate()
        .filter(|&(i, c)| i == 0 || i == last || major(c) != major(&exact[i - 1]))
        .map(|(_, c)| *c)
        .collect()
}

fn check(a: FixedPoint, b: FixedPoint) {
    let cells: Vec<CellIndex> = thin_cells_on_segment(a, b).unwrap().collect();
    assert_eq!(cells, reference(a, b), "{a:?} -> {b:?}");
    // A Bresenham line's shape: 8-connected, one step per cell along the major axis, with
    // at most one extra step at the end.
    let (di, dj) = (
        (b.cell().x - a.cell().x).abs(),
        (b.cell().y - a.cell().y).abs(),
    );
    let n = cells.len() as i32;
    assert!(
        n == di.max(dj) + 1 || n == di.max(dj) + 2,
        "{n} cells for {di} x {dj}"
    );
    for w in cells.windows(2) {
        let (dx, dy) = ((w[1].x - w[0].x).abs(), (w[1].y - w[0].y).abs());
        assert!(
            dx <= 1 && dy <= 1 && dx + dy >= 1,
            "jump {:?} -> {:?}",
            w[0],
            w[1]
        );
    }
}

fn collect_in_boxes(a: FixedPoint, b: FixedPoint, tile: i32) -> Vec<CellIndex> {
    common::collect_in_boxes(ThinWalk::new(a, b).unwrap(), tile)
}

#[test]
fn hand_worked_walks() {
    let p = |x: f64, y: f64| FixedPoint::from_cells(x, y).unwrap();
    let walk = |a, b| {
        thin_cells_on_segment(a, b)
            .unwrap()
            .map(|c| (c.x, c.y))
            .collect::<Vec<_>>()
    };
    // A shallow line: the exact walk's (2, 0) -> (2, 1) -> (3, 1) becomes one diagonal step.
    assert_eq!(
        walk(p(0.5, 0.5), p(4.5, 1.5)),
        vec![(0, 0), (1, 0), (2, 0), (3, 1), (4, 1)]
    );
    // Steep, going down: y is the major axis.
    assert_eq!(
        walk(p(0.5, 4.5), p(1.5, 0.5)),
        vec![(0, 4), (0, 3), (0, 2), (1, 1), (1, 0)]
    );
    // The last crossing is a minor one: the end cell is one more step.
    assert_eq!(walk(p(0.5, 0.2), p(1.9, 1.1)), vec![(0, 0), (1, 0), (1, 1)]);
    assert_eq!(walk(p(0.5, 0.5), p(0.6, 0.5)), vec![(0, 0)]);
    assert_eq!(
        walk(p(0.5, 0.5), p(3.5, 0.5)),
        vec![(0, 0), (1, 0), (2, 0), (3, 0)]
    );
}

#[test]
fn corner_and_boundary_cases_match_the_definition() {
    let q = SUBCELL / 4;
    let pts: Vec<FixedPoint> = (-3..=3)
        .flat_map(|x| (-3..=3).map(move |y| FixedPoint::new(x * q * 3, y * q * 2)))
        .collect();
    for &a in &pts {
        for &b in &pts {
            check(a, b);
            for tile in [1, 2, 3] {
                assert_eq!(
                    collect_in_boxes(a, b, tile),
                    reference(a, b),
                    "{a:?} -> {b:?}"
                );
            }
        }
    }
}

#[test]
fn too_long_rays_are_refused() {
    let a = FixedPoint::new(0, 0);
    assert!(ThinWalk::new(a, FixedPoint::new(MAX_RAY_CELLS * SUBCELL, 0)).is_err());
    assert!(ThinWalk::new(a, FixedPoint::new(0, MAX_RAY_CELLS * SUBCELL - 1)).is_ok());
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn random_walks_match_the_definition(ax in -40_000i64..40_000, ay in -40_000i64..40_000,
                                         dx in -30_000i64..30_000, dy in -30_000i64..30_000) {
        check(FixedPoint::new(ax, ay), FixedPoint::new(ax + dx, ay + dy));
    }

    #[test]
    fn tiled_runs_visit_the_same_cells_in_order(ax in -40_000i64..40_000, ay in -40_000i64..40_000,
                                                dx in -60_000i64..60_000, dy in -60_000i64..60_000,
                                                tile in prop::sample::select(vec![1, 2, 3, 8, 64])) {
        let (a, b) = (FixedPoint::new(ax, ay), FixedPoint::new(ax + dx, ay + dy));
        prop_assert_eq!(collect_in_boxes(a, b, tile), reference(a, b));
    }

    #[test]
    fn grid_aligned_tiled_runs_match_the_definition(ax in -40i64..40, ay in -40i64..40, bx in -40i64..40, by in -40i64..40,
                                                    tile in prop::sample::select(vec![1, 2, 3, 8])) {
        // Quarter-cell lattice: corners on the line, diagonal steps.
        let q = SUBCELL / 4;
        let (a, b) = (FixedPoint::new(ax * q, ay * q), FixedPoint::new(bx * q, by * q));
        check(a, b);
        prop_assert_eq!(collect_in_boxes(a, b, tile), reference(a, b));
    }
}
