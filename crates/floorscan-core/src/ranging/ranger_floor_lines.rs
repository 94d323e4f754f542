//! Lines on the floor (`RangerOptions::floor_line_width_m`): an edge where the column leaves
//! the floor's brightness and comes back to it within the ground width of a grout line, a
//! seam or a painted line is the floor's own, and the column's search goes on above it. The
//! paper's filter takes the first edge from the bottom, so on a tiled floor every column
//! ends at the nearest grout line; a line's width on the ground, unlike an obstacle's face,
//! is known from the table at every row (a face rises, a line lies flat and is foreshortened).

use super::*;

/// Most lines one column may pass before its search stops (its outcome stays the last edge).
const MAX_LINES_PER_COLUMN: usize = 64;

/// Rows added to a line's width on the ground for the lens's blur and the edge's refinement.
const BLUR_ROWS: usize = 2;

impl VisualRanger {
    /// Passes the floor lines of every boundary column of the frame just scanned.
    pub(super) fn skip_floor_lines<P: Pixel>(&mut self, image: &ImageView<P>) {
        if self.options.floor_line_width_m <= 0.0 {
            return;
        }
        for j in 0..self.plans.len() {
            self.skip_column_floor_lines(image, j);
        }
    }

    /// Passes the floor lines of column j's outcome, one after another.
    pub(super) fn skip_column_floor_lines<P: Pixel>(&mut self, image: &ImageView<P>, j: usize) {
        if self.options.floor_line_width_m <= 0.0 {
            return;
        }
        let height = image.height();
        for _ in 0..MAX_LINES_PER_COLUMN {
            let Some(ColumnOutcome::Boundary { row, .. }) = self.outcomes[j] else {
                return;
            };
            let Some(far_side) = self.floor_line_far_side(image, j, row) else {
                return;
            };
            // on from the line's far side: the next edge above it, or floor to the top
            let outcome = self.search_above(image, j, (height - 1 - far_side) as f64);
            self.outcomes[j] = Some(outcome);
        }
    }

    /// The first pixel k (from the bottom) past the line that the boundary at row `row` of
    /// column j belongs to, when that boundary is a side of a line on the floor: the 2d pixels
    /// from k up are back within the edge's threshold of d pixels below the edge (each d of
    /// them), the pixels
    /// between them (the line, which holds the edge) differ from those below by more than
    /// that, and they span no more than the line's greatest width on the ground at the edge
    /// (plus the blur). The refined edge may be either side of a thin line: the filter's
    /// first crossing can be the line's lower or upper side. `None` otherwise.
    fn floor_line_far_side<P: Pixel>(
        &self,
        image: &ImageView<P>,
        j: usize,
        row: f64,
    ) -> Option<usize> {
        let plan = &self.plans[j];
        let (lo, _) = plan.window?;
        let height = image.height();
        let d = self.options.half_width_px;
        let c = plan.column as usize;
        let pixel = |k: usize| image.get(c, height - 1 - k).to_i32();
        // the refined edge lies between pixels k_e - 0.5 and k_e + 0.5
        let k_edge = (height - 1) as f64 - row;
        if !k_edge.is_finite() || k_edge < 0.5 {
            return None;
        }
        let below_edge = (k_edge - 0.5).floor() as usize; // the pixel just below the edge
        let v = (row.round().max(0.0) as usize).min(height - 1);
        let footprint_m = f64::from(self.footprints_m[j * height + v]);
        if footprint_m <= 0.0 {
            return None;
        }
        let width_rows = (self.options.floor_line_width_m / footprint_m).ceil();
        let max_rows = (width_rows.min(height as f64) as usize).saturating_add(BLUR_ROWS);
        // "back to the floor": two windows of d pixels whose sums differ by no more than the
        // threshold, the filter's own test of no edge between them
        let tolerance = self.column_threshold_sum[j].max(1);
        let window = |first: usize| -> i32 { (first..first + d).map(pixel).sum() };
        // the floor below: windows ending at most the line's width under the edge, never
        // below the column's first tested row's lower window (k_floor - d + 1 >= lo - d)
        let lowest_top = (lo.max(d) - 1).max(below_edge.saturating_sub(max_rows));
        let mut best: Option<usize> = None;
        for floor_top in (lowest_top..=below_edge).rev() {
            let below = window(floor_top + 1 - d);
            let mut extreme = 0;
            // the line: floor_top + 1 ..= k - 1, at most max_rows pixels, holding the edge
            let last = (floor_top + 1 + max_rows).min(height.saturating_sub(2 * d));
            for k in floor_top + 1..=last {
                if (k as f64) > k_edge && best.is_none_or(|b| k < b) {
                    // two windows, so that a dark line's rows and a bright face's above it do
                    // not average to the floor's brightness in one
                    let back = (window(k) - below).abs() <= tolerance
                        && (window(k + d) - below).abs() <= tolerance;
                    if back && extreme > tolerance {
                        best = Some(k);
                        break;
                    }
                }
                // how far the line's own pixels depart from the floor (in sums of d pixels)
                extreme = extreme.max((pixel(k) * d as i32 - below).abs());
            }
        }
        best
    }

    /// The outcome of column j searched on from row `row` (v): from the first row above it
    /// where the response has fallen back under the threshold, the next crossing whose
    /// refined row lies above `row` (a line's far side, within the filter's reach, refines
    /// back onto the same step), at the frame's thresholds; floor to the top without one.
    /// Sets the column's crossing and confidence.
    pub(super) fn search_above<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        j: usize,
        row: f64,
    ) -> ColumnOutcome {
        let d = self.options.half_width_px;
        let height = image.height();
        let plan = self.plans[j];
        let Some((lo, hi)) = plan.window else {
            return ColumnOutcome::Invalid { row: None };
        };
        let c = plan.column as usize;
        let threshold = self.column_threshold_sum[j];
        let response = |k| direct_response_at(image, c, k, d);
        let mut k = (((height - 1) as f64 - row).round() as usize).max(lo + 1);
        loop {
            while k <= hi && response(k).abs() > threshold {
                k += 1;
            }
            let Some(k_cross) = (k..=hi).find(|&k| response(k).abs() > threshold) else {
                return self.no_boundary(j, height);
            };
            let outcome = self.resolve_with(j, k_cross, height, response, |k| {
                image.get(c, height - 1 - k).to_i32()
            });
            match outcome {
                ColumnOutcome::Boundary { row: r, .. } if r > row - 1.0 => k = k_cross + 1,
                _ => {
                    self.crossings[j] = k_cross;
                    self.confidence[j] = edge_confidence(response(k_cross), threshold);
                    return outcome;
                }
            }
        }
    }
}

#[cfg(test)]
#[path = "ranger_floor_lines_tests.rs"]
mod tests;
