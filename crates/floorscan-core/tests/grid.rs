//! Tiled grid storage: geometry, tiles on demand, clamping, fixed bounds, rectangles.

use floorscan_core::grid::*;
use floorscan_core::grid_options::Bounds;
use floorscan_core::grid_options::GridOptions;
use floorscan_core::log_odds::LogOdds;
use floorscan_core::raycast::CellIndex;
use floorscan_core::{Error, Occupancy, Point2};

#[test]
fn cells_follow_the_origin_and_size() {
    let g = Grid::new(GridOptions {
        cell_size_m: 0.5,
        origin_m: Point2::new(-1.0, 2.0),
        ..Default::default()
    })
    .unwrap();
    assert_eq!(
        g.cell_of(Point2::new(-1.0, 2.0)),
        Some(CellIndex::new(0, 0))
    );
    assert_eq!(
        g.cell_of(Point2::new(-1.01, 1.99)),
        Some(CellIndex::new(-1, -1))
    );
    assert_eq!(g.cell_of(Point2::new(0.2, 3.4)), Some(CellIndex::new(2, 2)));
    assert_eq!(g.cell_center(CellIndex::new(2, 2)), Point2::new(0.25, 3.25));
    assert_eq!(g.cell_of(Point2::new(f64::NAN, 0.0)), None);
}

#[test]
fn growing_grid_allocates_tiles_on_demand_and_keeps_values() {
    let mut g = Grid::new(GridOptions::default()).unwrap();
    assert_eq!(g.allocated_tiles(), 0);
    assert_eq!(g.get(CellIndex::new(5, 5)), LogOdds(0));
    g.set(CellIndex::new(5, 5), LogOdds(100)).unwrap();
    g.set(CellIndex::new(-700, 900), LogOdds(-100)).unwrap();
    g.set(CellIndex::new(3000, -20), LogOdds(7)).unwrap();
    assert_eq!(g.allocated_tiles(), 3);
    assert_eq!(g.get(CellIndex::new(5, 5)), LogOdds(100));
    assert_eq!(g.get(CellIndex::new(-700, 900)), LogOdds(-100));
    assert_eq!(g.get(CellIndex::new(3000, -20)), LogOdds(7));
    assert_eq!(g.get(CellIndex::new(6, 5)), LogOdds(0));
    assert_eq!(
        g.known_rect(),
        Some(CellRect {
            min: CellIndex::new(-700, -20),
            max: CellIndex::new(3001, 901)
        })
    );
    assert!(g.memory_bytes() >= 3 * TILE_CELLS * 2);
}

#[test]
fn values_are_clamped_on_write() {
    let mut g = Grid::new(GridOptions::default()).unwrap();
    g.set(CellIndex::new(0, 0), LogOdds(30_000)).unwrap();
    g.set(CellIndex::new(1, 0), LogOdds(-30_000)).unwrap();
    assert_eq!(g.get(CellIndex::new(0, 0)), LogOdds(3500));
    assert_eq!(g.get(CellIndex::new(1, 0)), LogOdds(-2000));
    assert_eq!(g.occupancy(CellIndex::new(0, 0)), Occupancy::Occupied);
    assert_eq!(g.occupancy(CellIndex::new(1, 0)), Occupancy::Free);
    assert_eq!(g.occupancy(CellIndex::new(2, 0)), Occupancy::Unknown);
}

#[test]
fn fixed_bounds_cover_the_overlapping_cells_only() {
    let b = Bounds {
        min: Point2::new(-0.1, 0.0),
        max: Point2::new(0.3, 0.2),
    };
    let mut g = Grid::new(GridOptions {
        cell_size_m: 0.1,
        bounds_m: Some(b),
        ..Default::default()
    })
    .unwrap();
    let r = g.fixed_cells().unwrap();
    assert_eq!(
        (r.min, r.max),
        (CellIndex::new(-1, 0), CellIndex::new(3, 2))
    );
    assert!(g.set(CellIndex::new(2, 1), LogOdds(5)).is_ok());
    assert!(matches!(
        g.set(CellIndex::new(3, 1), LogOdds(5)),
        Err(Error::OutOfBounds(_))
    ));
    assert_eq!(g.extent(), r);
}

#[test]
fn rect_round_trip_across_tiles() {
    let mut g = Grid::new(GridOptions::default()).unwrap();
    let rect = CellRect {
        min: CellIndex::new(-70, 60),
        max: CellIndex::new(75, 140),
    };
    let values: Vec<i16> = (0..rect.width() * rect.height())
        .map(|i| ((i * 37) % 4001) as i16 - 2000)
        .collect();
    g.write_rect(rect, &values).unwrap();
    let mut back = Vec::new();
    g.read_rect(rect, &mut back);
    assert_eq!(back, values);
    // A cell by hand: row 3, column 5 of the rectangle.
    assert_eq!(
        g.get(CellIndex::new(-65, 63)).0,
        values[3 * rect.width() + 5]
    );
    assert!(g.write_rect(rect, &values[1..]).is_err());
}

#[test]
fn absurd_extents_are_refused_without_change() {
    let mut g = Grid::new(GridOptions::default()).unwrap();
    g.set(CellIndex::new(0, 0), LogOdds(1)).unwrap();
    let far = CellIndex::new(500_000_000, 500_000_000);
    assert!(matches!(g.set(far, LogOdds(1)), Err(Error::OutOfBounds(_))));
    assert_eq!(g.get(CellIndex::new(0, 0)), LogOdds(1));
    assert_eq!(g.allocated_tiles(), 1);
}
