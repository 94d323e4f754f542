//! Each sampled column's fixed geometry, worked out once from the ground table and the
//! options: where its scan starts (the bottom margin, or the nearest ground), the rows where
//! a crossing is tested, and the band of the lower contrast floor.

use super::*;

/// A sampled column's fixed geometry, worked out once from the table and the options.
#[derive(Debug, Clone, Copy)]
pub(super) struct ColumnPlan {
    pub(super) column: u32,
    /// Start row v (from the top).
    pub(super) start_row: usize,
    /// The start row as configured; `start_row` moves to `first_ground_row` while the rows at
    /// this one are a lens's dark rim (`dark_rim`).
    pub(super) nominal_start: usize,
    /// The ground point of the column's lowest row with ground, at or above the start row.
    pub(super) near: Option<Point2>,
    /// That row (v), `None` without ground.
    pub(super) first_ground_row: Option<usize>,
    /// Rows (k, counted from the bottom) where a crossing is tested: `lo..=hi`, from the start
    /// row up to the last row with ground. `None` when the column cannot be scanned (no ground
    /// at or above its start, or too few rows for the filter).
    pub(super) window: Option<(usize, usize)>,
    /// The rows of `window` whose ground lies within the options' `mid_range_m` (the band of
    /// the lower contrast floor), `None` when there are none.
    pub(super) band: Option<(usize, usize)>,
}

/// Floor length [m] that pixel row v of column u covers (between the row's upper and lower
/// edges); 0 where either edge has no ground.
pub(super) fn row_footprint_m(table: &GroundTable, column: u32, v: f64) -> f64 {
    match (
        table.lookup(column as f64, v - 0.5),
        table.lookup(column as f64, v + 0.5),
    ) {
        (Some(a), Some(b)) => (a.x - b.x).hypot(a.y - b.y),
        _ => 0.0,
    }
}

/// Works out where a column's scan starts and how far up it may go.
pub(super) fn plan_column(
    table: &GroundTable,
    options: &RangerOptions,
    column: u32,
    start_row: usize,
) -> ColumnPlan {
    let height = table.image_height();
    let d = options.half_width_px;
    let u = column as f64;
    let within_range = |p: Point2| options.max_range_m.is_none_or(|r| p.norm() <= r);
    // The column's near edge of view is its lowest row, from the start up, with ground. Rows
    // below it (an image corner the table does not trust: a fisheye's sides near the robot)
    // are still scanned, as the paper's ranger takes the bottom rows for floor, but an edge
    // there cannot be placed (invalid). One in the first window is too close: the obstacle
    // then covers the column up to its first row with ground, so it stands on that row's ray
    // at or before `near`, where the map marks it (as for any too-close column).
    let rows = table.column_ground_rows(u, start_row, within_range);
    let near = rows.and_then(|(first, _)| table.lookup(u, first as f64));
    let mut window = None;
    let mut band = None;
    if let Some((_, top)) = rows {
        let k_start = height - 1 - start_row;
        let lo = k_start + d;
        let hi = (height - 1 - top).min(height - 1 - d);
        if lo <= hi {
            window = Some((lo, hi));
            let (near_m, far_m) = (options.mid_range_m[0], options.mid_range_m[1]);
            if near_m < far_m {
                let in_band = |k: usize| {
                    table
                        .lookup(u, (height - 1 - k) as f64)
                        .is_some_and(|p| (near_m..=far_m).contains(&p.norm()))
                };
                let first = (lo..=hi).find(|&k| in_band(k));
                band = first.map(|b_lo| {
                    let b_hi = (b_lo..=hi)
                        .take_while(|&k| in_band(k))
                        .last()
                        .unwrap_or(b_lo);
                    (b_lo, b_hi)
                });
            }
        }
    }
    ColumnPlan {
        column,
        start_row,
        nominal_start: start_row,
        near,
        first_ground_row: rows.map(|(first, _)| first),
        window,
        band,
    }
}
