//! Tests of the `queries` module.

use super::*;
use crate::grid_options::GridOptions;
use crate::log_odds::LogOdds;

fn brute_force(g: &Grid, occupied: &[CellIndex], p: Point2) -> f64 {
    let s = g.cell_size_m();
    occupied
        .iter()
        .map(|c| {
            let (x0, y0) = (s * f64::from(c.x), s * f64::from(c.y));
            let dx = (x0 - p.x).max(p.x - (x0 + s)).max(0.0);
            let dy = (y0 - p.y).max(p.y - (y0 + s)).max(0.0);
            dx.hypot(dy)
        })
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn distance_matches_brute_force() {
    let mut g = Grid::new(GridOptions {
        cell_size_m: 0.1,
        ..Default::default()
    })
    .unwrap();
    let mut state = 12345u64;
    let mut next = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 33) as f64 / (1u64 << 31) as f64
    };
    let mut occupied = Vec::new();
    for _ in 0..40 {
        let c = CellIndex::new((next() * 100.0) as i32 - 50, (next() * 100.0) as i32 - 50);
        g.set(c, LogOdds(3000)).unwrap();
        occupied.push(c);
        // Free and weakly occupied cells are not obstacles.
        g.set(CellIndex::new(c.x + 1, c.y), LogOdds(-2000)).unwrap();
        g.set(CellIndex::new(c.x, c.y + 1), LogOdds(100)).unwrap();
    }
    occupied.retain(|c| g.get(*c).0 == 3000);
    for _ in 0..300 {
        let p = Point2::new(next() * 12.0 - 6.0, next() * 12.0 - 6.0);
        let want = brute_force(&g, &occupied, p);
        let got = g.distance_to_occupied(p, 3.0).unwrap();
        if want <= 3.0 {
            assert!(
                (got.unwrap() - want).abs() < 1e-12,
                "{p:?}: {got:?} vs {want}"
            );
        } else {
            assert_eq!(got, None);
        }
    }
    assert_eq!(
        g.distance_to_occupied(g.cell_center(occupied[0]), 1.0)
            .unwrap(),
        Some(0.0)
    );
}

#[test]
fn occupancy_and_bad_queries() {
    let mut g = Grid::new(GridOptions {
        cell_size_m: 1.0,
        ..Default::default()
    })
    .unwrap();
    g.set(CellIndex::new(0, 0), LogOdds(-1500)).unwrap();
    assert_eq!(
        g.occupancy_at(Point2::new(0.5, 0.5)).unwrap(),
        Occupancy::Free
    );
    assert_eq!(
        g.occupancy_at(Point2::new(5.5, 0.5)).unwrap(),
        Occupancy::Unknown
    );
    assert!(g.occupancy_at(Point2::new(f64::NAN, 0.5)).is_err());
    assert!(g
        .distance_to_occupied(Point2::new(0.0, 0.0), f64::NAN)
        .is_err());
    assert_eq!(
        g.distance_to_occupied(Point2::new(0.0, 0.0), 10.0).unwrap(),
        None
    );
}
