//! Column placement from the camera's geometry: columns close enough on the floor that an
//! obstacle of a given width at a given range cannot stand between two sampled columns (a
//! chair leg stepped over by evenly spaced columns is an obstacle the map never sees).
//!
//! For every image column, the ground point whose range is nearest the asked range is found
//! in the ground table (so the rule holds for any lens, with no pinhole assumption); walking
//! across the image, a column is taken whenever the next one's point would lie farther than
//! the obstacle's width from the last taken column's point. Where the nearest ground a column
//! sees lies beyond the asked range, the spacing is kept there (stricter: the same width
//! subtends a smaller angle farther away).

use crate::error::{invalid_option, Result};
use crate::ground_table::GroundTable;
use crate::pose::Point2;

/// Per image column: the ground point [m] whose range is nearest `range_m`, `None` where the
/// column has no ground.
fn points_at_range(table: &GroundTable, range_m: f64) -> Vec<Option<Point2>> {
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
            best.map(|(_, p)| p)
        })
        .collect()
}

/// The image columns (ascending) such that consecutive columns' ground points near
/// `range_m` [m] lie at most `obstacle_width_m` [m] apart, where the pixels allow (adjacent
/// pixel columns farther apart than that are both taken). Columns without ground are left
/// out. Errors: non-positive or non-finite arguments, or a table without ground.
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
    let points = points_at_range(table, range_m);
    let dist = |a: Point2, b: Point2| (a.x - b.x).hypot(a.y - b.y);
    let mut out: Vec<u32> = Vec::new();
    // The last column taken and the last one with ground (each column seen but not taken
    // lies within the width of the last one taken).
    let mut taken: Option<(usize, Point2)> = None;
    let mut seen: Option<(usize, Point2)> = None;
    for (u, p) in points.iter().enumerate() {
        let Some(p) = *p else { continue };
        let mut take = |c: usize, q: Point2, taken: &mut Option<(usize, Point2)>| {
            out.push(c as u32);
            *taken = Some((c, q));
        };
        match (taken, seen) {
            (None, _) => take(u, p, &mut taken),
            (Some((tu, tp)), Some((su, sp))) if dist(p, tp) > obstacle_width_m => {
                if su != tu {
                    take(su, sp, &mut taken);
                }
                // Adjacent columns (or the two sides of a gap without ground) farther apart
                // than the width: this one too.
                if dist(p, sp) > obstacle_width_m || su == tu {
                    take(u, p, &mut taken);
                }
            }
            _ => {}
        }
        seen = Some((u, p));
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

    /// Brute force: the largest gap between consecutive chosen columns' points near the
    /// range, over the pairs whose pixels are not adjacent (adjacent pixels cannot be split).
    fn worst_gap(table: &GroundTable, cols: &[u32], range_m: f64) -> f64 {
        let pts = points_at_range(table, range_m);
        cols.windows(2)
            .filter(|w| w[1] > w[0] + 1)
            .map(|w| {
                let (a, b) = (pts[w[0] as usize].unwrap(), pts[w[1] as usize].unwrap());
                (a.x - b.x).hypot(a.y - b.y)
            })
            .fold(0.0, f64::max)
    }

    #[test]
    fn no_obstacle_of_the_width_fits_between_columns() {
        let t = pinhole(640, 480, 300.0, 0.3, 0.5);
        for (width, range) in [(0.03, 1.0), (0.05, 2.0), (0.10, 1.0)] {
            let cols = spaced_columns(&t, width, range).unwrap();
            assert!(worst_gap(&t, &cols, range) <= width, "{width} at {range}");
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
