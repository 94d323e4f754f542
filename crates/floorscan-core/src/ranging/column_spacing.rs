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
mod tests {
    use super::*;

    /// A pinhole camera h above the floor, pitched down by `pitch` [rad], focal `f` [px].
    fn pinhole(w: usize, h: usize, f: f64, height_m: f64, pitch: f64) -> GroundTable {
        let (cu, cv) = (w as f64 / 2.0, h as f64 / 2.0);
        GroundTable::from_fn(w, h, 4, |u, v| {
            // ray in the camera: forward 1, left -(u - cu) / f, down (v - cv) / f
            let (fx, ly, dz) = (1.0, -(u - cu) / f, (v - cv) / f);
            let (s, c) = pitch.sin_cos();
            let forward = c * fx - s * -dz;
            let down = s * fx + c * dz;
            (down > 1e-9).then(|| {
                let t = height_m / down;
                Point2::new(t * forward, t * ly)
            })
        })
        .unwrap()
    }

    /// Brute force: the largest bearing difference between consecutive chosen columns' points
    /// nearest the range (every pixel row looked up), over the pairs whose pixels are not
    /// adjacent (adjacent pixels cannot be split).
    fn worst_gap_rad(table: &GroundTable, cols: &[u32], range_m: f64) -> f64 {
        let bearing = |u: u32| {
            (0..table.image_height())
                .filter_map(|v| table.lookup(u as f64, v as f64))
                .min_by(|a, b| {
                    (a.norm() - range_m)
                        .abs()
                        .total_cmp(&(b.norm() - range_m).abs())
                })
                .map(|p| p.y.atan2(p.x))
                .unwrap()
        };
        cols.windows(2)
            .filter(|w| w[1] > w[0] + 1)
            .map(|w| (bearing(w[1]) - bearing(w[0])).abs())
            .fold(0.0, f64::max)
    }

    #[test]
    fn no_obstacle_of_the_width_fits_between_columns() {
        let t = pinhole(640, 480, 300.0, 0.3, 0.5);
        for (width, range) in [(0.03, 1.0), (0.05, 2.0), (0.10, 1.0)] {
            let cols = spaced_columns(&t, width, range).unwrap();
            let reach = subtended_rad(width, range);
            assert!(
                worst_gap_rad(&t, &cols, range) <= reach,
                "{width} at {range}"
            );
            // at the range itself, the chord between neighbouring bearings is the width
            assert!((2.0 * range * (reach / 2.0).sin() - width).abs() < 1e-12);
            assert!(cols.windows(2).all(|w| w[0] < w[1]));
            assert_eq!(cols[0], 0);
            assert_eq!(*cols.last().unwrap(), 639);
            // analytic count: at 1 m the floor spans range / f per pixel near the centre, so
            // about width / (range / f) pixels per column; the columns are no denser than
            // twice that (greedy takes the farthest column within reach)
            let px_per_col = width / (range / 300.0);
            let least = (640.0 / px_per_col / 1.5) as usize;
            assert!(
                cols.len() >= least && cols.len() <= 2 * 640 / px_per_col.max(1.0) as usize + 2,
                "{} columns for {px_per_col} px per column",
                cols.len()
            );
        }
        // Wider obstacles need fewer columns.
        let a = spaced_columns(&t, 0.03, 1.0).unwrap().len();
        let b = spaced_columns(&t, 0.10, 1.0).unwrap().len();
        assert!(b < a);
    }

    #[test]
    fn a_table_short_of_the_range_keeps_the_ranges_angular_spacing() {
        // A calibration that covers the floor only to 0.6 m: the columns' bearings still lie
        // within the angle a 3 cm obstacle subtends at 1 m (a floor distance of 3 cm at 0.6 m
        // would allow 1.7 times that).
        let full = pinhole(640, 480, 300.0, 0.3, 0.5);
        let short = GroundTable::from_fn(640, 480, 4, |u, v| {
            full.lookup(u, v).filter(|p| p.norm() <= 0.6)
        })
        .unwrap();
        let b = spaced_columns(&short, 0.03, 1.0).unwrap();
        assert!(worst_gap_rad(&short, &b, 1.0) <= subtended_rad(0.03, 1.0));
        assert!(b.len() > spaced_columns(&short, 0.03 / 0.6, 1.0).unwrap().len());
    }

    #[test]
    fn too_fine_a_spacing_takes_every_column() {
        let t = pinhole(64, 48, 30.0, 0.3, 0.5);
        let cols = spaced_columns(&t, 0.001, 1.0).unwrap();
        assert_eq!(cols, (0..64).collect::<Vec<u32>>());
    }

    #[test]
    fn bad_arguments_and_groundless_tables_are_errors() {
        let t = pinhole(64, 48, 30.0, 0.3, 0.5);
        assert!(spaced_columns(&t, 0.0, 1.0).is_err());
        assert!(spaced_columns(&t, 0.03, f64::INFINITY).is_err());
        let none = GroundTable::from_fn(64, 48, 4, |_, _| None).unwrap();
        assert!(spaced_columns(&none, 0.03, 1.0).is_err());
    }
}
