//! Column placement from the camera's geometry: columns close enough on the floor that an
//! obstacle of a given width at a given range cannot stand between two sampled columns (a
//! chair leg stepped over by evenly spaced columns is an obstacle the map never sees).
//!
//! For every image column, the bearing of the ground point whose range is nearest the asked
//! range is read from the ground table (so the rule holds for any lens, with no pinhole
//! assumption); walking across the image, a column is taken whenever the next one's bearing
//! would differ from the last taken column's by more than the angle the obstacle subtends at
//! that range, 2 asin(width / 2 range). Bearings, not floor distances: a table that stops short
//! of the range (a calibration that covers only the near floor) still gets the spacing the
//! range needs.

use crate::error::{invalid_option, Result};
use crate::ground_table::GroundTable;
use crate::pose::Point2;

/// Per image column: the bearing [rad] of the ground point whose range is nearest `range_m`,
/// `None` where the column has no ground.
fn bearings_at_range(table: &GroundTable, range_m: f64) -> Vec<Option<f64>> {
    let (w, h) = (table.image_width(), table.image_height());
    (0..w)
        .map(|u| {
            let mut best: Option<(f64, Point2)> = None;
            for v in (0..h).rev() {
                if let Some(p) = table.lookup(u as f64, v as f64) {
                    let d = (p.norm() - range_m).abs();
                    if best.is_none_or(|(bd, _)| d < bd) {
                        best = Some((d, p));
                    }
                }
            }
            best.map(|(_, p)| p.y.atan2(p.x))
        })
        .collect()
}

/// The angle [rad] an obstacle `width_m` wide subtends at `range_m`.
pub fn subtended_rad(width_m: f64, range_m: f64) -> f64 {
    2.0 * (width_m / (2.0 * range_m)).min(1.0).asin()
}

/// The image columns (ascending) such that consecutive columns' bearings differ by at most
/// [`subtended_rad`]`(obstacle_width_m, range_m)`, where the pixels allow (adjacent pixel
/// columns farther apart than that are both taken). Columns without ground are left out.
/// Errors: non-positive or non-finite arguments, or a table without ground.
pub fn spaced_columns(
    table: &GroundTable,
    obstacle_width_m: f64,
    range_m: f64,
) -> Result<Vec<u32>> {
    if !(obstacle_width_m.is_finite() && obstacle_width_m > 0.0) {
        return Err(invalid_option(
            "columns.obstacle_width_m",
            format!("must be finite and > 0, got {obstacle_width_m}"),
        ));
    }
    if !(range_m.is_finite() && range_m > 0.0) {
        return Err(invalid_option(
            "columns.range_m",
            format!("must be finite and > 0, got {range_m}"),
        ));
    }
    let reach = subtended_rad(obstacle_width_m, range_m);
    let mut out: Vec<u32> = Vec::new();
    // The last column taken and the last one with ground (each column seen but not taken
    // lies within reach of the last one taken).
    let mut taken: Option<(usize, f64)> = None;
    let mut seen: Option<(usize, f64)> = None;
    for (u, b) in bearings_at_range(table, range_m).into_iter().enumerate() {
        let Some(b) = b else { continue };
        match (taken, seen) {
            (None, _) => {
                out.push(u as u32);
                taken = Some((u, b));
            }
            (Some((tu, tb)), Some((su, sb))) if (b - tb).abs() > reach => {
                if su != tu {
                    out.push(su as u32);
                }
                // Adjacent columns (or the two sides of a gap without ground) farther apart
                // than the reach: this one too.
                if (b - sb).abs() > reach || su == tu {
                    out.push(u as u32);
                    taken = Some((u, b));
                } else {
                    taken = Some((su, sb));
                }
            }
            _ => {}
        }
        seen = Some((u, b));
    }
    if let (Some((su, _)), Some((tu, _))) = (seen, taken) {
        if su != tu {
            out.push(su as u32);
        }
    }
    if out.is_empty() {
        return Err(invalid_option(
            "columns",
            "the ground table has no ground to place columns on",
        ));
    }
    Ok(out)
}

#[cfg(test)]
#[path = "column_spacing_tests.rs"]
mod tests;
