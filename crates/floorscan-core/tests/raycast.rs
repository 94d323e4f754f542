//! The exact grid walk against a brute-force reference in exact rational arithmetic.

use floorscan_core::raycast::*;
use proptest::prelude::*;
use std::collections::BTreeSet;

mod common;

/// A rational bound `num / den` (den > 0) on the segment parameter t, open or closed.
#[derive(Clone, Copy)]
struct Bound {
    num: i128,
    den: i128,
    closed: bool,
}

fn cmp(a: Bound, b: Bound) -> std::cmp::Ordering {
    (a.num * b.den).cmp(&(b.num * a.den))
}

/// Brute force: does the closed segment meet the half-open cell [i, i+1) x [j, j+1)?
/// Intersects the parameter intervals of both axes with [0, 1], exactly.
fn segment_meets_cell(a: FixedPoint, b: FixedPoint, c: CellIndex) -> bool {
    let mut lo = Bound {
        num: 0,
        den: 1,
        closed: true,
    };
    let mut hi = Bound {
        num: 1,
        den: 1,
        closed: true,
    };
    for (p0, p1, i) in [(a.x, b.x, c.x), (a.y, b.y, c.y)] {
        let (p0, d) = (p0 as i128, (p1 - p0) as i128);
        let (lo_line, hi_line) = (
            i as i128 * SUBCELL as i128,
            (i as i128 + 1) * SUBCELL as i128,
        );
        if d == 0 {
            if !(lo_line <= p0 && p0 < hi_line) {
                return false;
            }
            continue;
        }
        // p0 + t d in [lo_line, hi_line): solve for t.
        let (t_lo_line, t_hi_line) = ((lo_line - p0, d), (hi_line - p0, d));
        let norm = |(n, d): (i128, i128)| if d < 0 { (-n, -d) } else { (n, d) };
        let (l, h) = (norm(t_lo_line), norm(t_hi_line));
        let (enter, leave) = if d > 0 {
            (
                Bound {
                    num: l.0,
                    den: l.1,
                    closed: true,
                },
                Bound {
                    num: h.0,
                    den: h.1,
                    closed: false,
                },
            )
        } else {
            (
                Bound {
                    num: h.0,
                    den: h.1,
                    closed: false,
                },
                Bound {
                    num: l.0,
                    den: l.1,
                    closed: true,
                },
            )
        };
        match cmp(enter, lo) {
            std::cmp::Ordering::Greater => lo = enter,
            std::cmp::Ordering::Equal => lo.closed &= enter.closed,
            _ => {}
        }
        match cmp(leave, hi) {
            std::cmp::Ordering::Less => hi = leave,
            std::cmp::Ordering::Equal => hi.closed &= leave.closed,
            _ => {}
        }
    }
    match cmp(lo, hi) {
        std::cmp::Ordering::Less => true,
        std::cmp::Ordering::Equal => lo.closed && hi.closed,
        std::cmp::Ordering::Greater => false,
    }
}

fn brute_force(a: FixedPoint, b: FixedPoint) -> BTreeSet<CellIndex> {
    let (c0, c1) = (a.cell(), b.cell());
    let mut out = BTreeSet::new();
    for x in c0.x.min(c1.x) - 1..=c0.x.max(c1.x) + 1 {
        for y in c0.y.min(c1.y) - 1..=c0.y.max(c1.y) + 1 {
            if segment_meets_cell(a, b, CellIndex::new(x, y)) {
                out.insert(CellIndex::new(x, y));
            }
        }
    }
    out
}

fn check_walk(a: FixedPoint, b: FixedPoint) {
    let cells: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
    assert_eq!(cells.first(), Some(&a.cell()));
    assert_eq!(cells.last(), Some(&b.cell()));
    for w in cells.windows(2) {
        let (dx, dy) = ((w[1].x - w[0].x).abs(), (w[1].y - w[0].y).abs());
        assert!(
            dx <= 1 && dy <= 1 && dx + dy >= 1,
            "jump {:?} -> {:?}",
            w[0],
            w[1]
        );
    }
    let set: BTreeSet<CellIndex> = cells.iter().copied().collect();
    assert_eq!(
        set.len(),
        cells.len(),
        "a cell visited twice on {a:?} -> {b:?}"
    );
    assert_eq!(set, brute_force(a, b), "{a:?} -> {b:?}");
}

#[test]
fn hand_worked_walks() {
    let p = |x: f64, y: f64| FixedPoint::from_cells(x, y).unwrap();
    let walk = |a, b| {
        cells_on_segment(a, b)
            .unwrap()
            .map(|c| (c.x, c.y))
            .collect::<Vec<_>>()
    };
    assert_eq!(
        walk(p(0.5, 0.5), p(3.5, 0.5)),
        vec![(0, 0), (1, 0), (2, 0), (3, 0)]
    );
    assert_eq!(
        walk(p(3.5, 0.5), p(0.5, 0.5)),
        vec![(3, 0), (2, 0), (1, 0), (0, 0)]
    );
    // Through the corner (1, 1) going up-right: the corner belongs to cell (1, 1).
    assert_eq!(walk(p(0.5, 0.5), p(1.5, 1.5)), vec![(0, 0), (1, 1)]);
    // Going down-left through the same corner: the corner point is in (1, 1), which the
    // walk starts in, then both coordinates drop below 1 at once.
    assert_eq!(walk(p(1.5, 1.5), p(0.5, 0.5)), vec![(1, 1), (0, 0)]);
    // Going down-right through corner (1, 1): x reaches 1 (cell x = 1) before y drops below.
    assert_eq!(walk(p(0.5, 1.5), p(1.5, 0.5)), vec![(0, 1), (1, 1), (1, 0)]);
    // A shallow line.
    assert_eq!(
        walk(p(0.5, 0.5), p(4.5, 1.5)),
        vec![(0, 0), (1, 0), (2, 0), (2, 1), (3, 1), (4, 1)]
    );
    // Along a cell boundary: the line y = 1 belongs to row 1.
    assert_eq!(walk(p(0.5, 1.0), p(2.5, 1.0)), vec![(0, 1), (1, 1), (2, 1)]);
    assert_eq!(walk(p(-0.5, -0.5), p(-0.5, -0.5)), vec![(-1, -1)]);
}

#[test]
fn corner_and_boundary_cases_match_brute_force() {
    // Every segment between lattice-aligned points of a small neighbourhood, including
    // quarter-cell positions: all corner and boundary coincidences.
    let q = SUBCELL / 4;
    let pts: Vec<FixedPoint> = (-3..=3)
        .flat_map(|x| (-3..=3).map(move |y| FixedPoint::new(x * q * 3, y * q * 2)))
        .collect();
    for &a in &pts {
        for &b in &pts {
            check_walk(a, b);
        }
    }
}

#[test]
fn fixed_point_rounds_to_the_nearest_unit() {
    let u = 1.0 / SUBCELL as f64;
    for (v, want) in [
        (0.0, 0),
        (0.49 * u, 0),
        (0.5 * u, 1),
        (-0.5 * u, 0),
        (-0.51 * u, -1),
        (-3.7, -3789),
        (2.25, 2304),
    ] {
        assert_eq!(FixedPoint::from_cells(v, 0.0).unwrap().x, want, "{v}");
    }
    assert_eq!(
        FixedPoint::from_cells(-0.001, 0.0).unwrap().cell(),
        CellIndex::new(-1, 0)
    );
    assert!(FixedPoint::from_cells(f64::NAN, 0.0).is_none());
    assert!(FixedPoint::from_cells(0.0, 2e9).is_none());
}

#[test]
fn too_long_rays_are_refused() {
    let a = FixedPoint::new(0, 0);
    assert!(GridWalk::new(a, FixedPoint::new(MAX_RAY_CELLS * SUBCELL, 0)).is_err());
    assert!(GridWalk::new(a, FixedPoint::new(0, MAX_RAY_CELLS * SUBCELL - 1)).is_ok());
}

fn collect_in_boxes(a: FixedPoint, b: FixedPoint, tile: i32) -> Vec<CellIndex> {
    common::collect_in_boxes(GridWalk::new(a, b).unwrap(), tile)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(3000))]

    #[test]
    fn random_walks_match_brute_force(ax in -40_000i64..40_000, ay in -40_000i64..40_000,
                                      dx in -30_000i64..30_000, dy in -30_000i64..30_000) {
        check_walk(FixedPoint::new(ax, ay), FixedPoint::new(ax + dx, ay + dy));
    }

    #[test]
    fn tiled_runs_visit_the_same_cells_in_order(ax in -40_000i64..40_000, ay in -40_000i64..40_000,
                                                dx in -60_000i64..60_000, dy in -60_000i64..60_000,
                                                tile in prop::sample::select(vec![1, 2, 3, 8, 64])) {
        let (a, b) = (FixedPoint::new(ax, ay), FixedPoint::new(ax + dx, ay + dy));
        let simple: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
        prop_assert_eq!(collect_in_boxes(a, b, tile), simple);
    }

    #[test]
    fn grid_aligned_tiled_runs_match_the_simple_walk(ax in -40i64..40, ay in -40i64..40, bx in -40i64..40, by in -40i64..40,
                                                      tile in prop::sample::select(vec![1, 2, 3, 8])) {
        // Quarter-cell lattice: corners on the line, diagonal steps, the exact loop.
        let q = SUBCELL / 4;
        let (a, b) = (FixedPoint::new(ax * q, ay * q), FixedPoint::new(bx * q, by * q));
        let simple: Vec<CellIndex> = cells_on_segment(a, b).unwrap().collect();
        prop_assert_eq!(collect_in_boxes(a, b, tile), simple);
    }

    #[test]
    fn grid_aligned_walks_match_brute_force(ax in -12i64..12, ay in -12i64..12, bx in -12i64..12, by in -12i64..12) {
        // Coordinates on a half-cell lattice: many exact corner passages.
        let h = SUBCELL / 2;
        check_walk(FixedPoint::new(ax * h, ay * h), FixedPoint::new(bx * h, by * h));
    }
}
