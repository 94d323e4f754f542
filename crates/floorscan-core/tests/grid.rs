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

#[test]
fn a_cell_past_max_cells_is_an_error_and_the_directory_stays_small() {
    // Issue 12: one pose 1000 km away must be an error, not an allocation.
    let mut g = Grid::new(GridOptions::default()).unwrap();
    g.set(CellIndex::new(0, 0), LogOdds(1)).unwrap();
    let far = g.cell_of(Point2::new(1.0e6, 0.0)).unwrap();
    assert!(matches!(g.set(far, LogOdds(1)), Err(Error::OutOfBounds(_))));
    let far = g.cell_of(Point2::new(1.0e5, 0.0)).unwrap();
    assert!(matches!(g.set(far, LogOdds(1)), Err(Error::OutOfBounds(_))));
    assert!(g.memory_bytes() < 1 << 20, "{} bytes", g.memory_bytes());
    // Within max_cells (default 2^25 = 2048 tiles of 128^2): 200 m x 200 m at 4 cm is fine.
    g.set(g.cell_of(Point2::new(200.0, 200.0)).unwrap(), LogOdds(1))
        .unwrap();
    let r = g.known_rect().unwrap();
    assert!((r.width() as u64) * (r.height() as u64) <= g.options().max_cells);
    // A smaller limit refuses sooner; a larger one accepts.
    let mut small = Grid::new(GridOptions {
        max_cells: 4 * TILE_CELLS as u64,
        ..Default::default()
    })
    .unwrap();
    small.set(CellIndex::new(0, 0), LogOdds(1)).unwrap();
    small.set(CellIndex::new(255, 255), LogOdds(1)).unwrap();
    assert!(small.set(CellIndex::new(300, 0), LogOdds(1)).is_err());
}

#[test]
fn fixed_bounds_past_max_cells_are_an_option_error() {
    // OccupancyGrid(bounds_m=((0,0),(1e4,1e4))): 250 000^2 cells.
    let bounds = Some(Bounds {
        min: Point2::new(0.0, 0.0),
        max: Point2::new(1.0e4, 1.0e4),
    });
    let e = Grid::new(GridOptions {
        bounds_m: bounds,
        ..Default::default()
    })
    .unwrap_err();
    assert!(
        matches!(
            e,
            Error::InvalidOption {
                name: "bounds_m",
                ..
            }
        ),
        "{e}"
    );
    let ok = Grid::new(GridOptions {
        bounds_m: bounds,
        cell_size_m: 2.0,
        ..Default::default()
    });
    assert!(ok.is_ok());
}

#[test]
fn checked_rect_refuses_overflow_and_huge_rectangles() {
    let g = Grid::new(GridOptions::default()).unwrap();
    let r = g.checked_rect(-3, 4, 10, 20).unwrap();
    assert_eq!(
        (r.min, r.max),
        (CellIndex::new(-3, 4), CellIndex::new(7, 24))
    );
    // raw(extent) with a 10^6 x 10^6 extent.
    assert!(matches!(
        g.checked_rect(0, 0, 1_000_000, 1_000_000),
        Err(Error::OutOfBounds(_))
    ));
    // write_raw at x_cell 2^31 - 1: the end would wrap.
    assert!(g.checked_rect(i64::from(i32::MAX), 0, 1, 1).is_err());
    assert!(g.checked_rect(i64::MIN, 0, 1, 1).is_err());
    assert!(g.checked_rect(0, 0, u64::MAX, 1).is_err());
}
