//! Resolving a column's crossing into its reading: the refined row of the edge (the step
//! refinement reads the pixels around the crossing once), its ground point and confidence; or
//! floor up to the column's top row where no edge crossed.

use super::*;

impl VisualRanger {
    pub(super) fn no_boundary(&self, j: usize, height: usize) -> ColumnOutcome {
        let plan = &self.plans[j];
        let top_row = (height - 1 - plan.window.unwrap().1) as f64;
        match self.table.lookup(plan.column as f64, top_row) {
            Some(farthest) => ColumnOutcome::NoBoundary { top_row, farthest },
            None => ColumnOutcome::Invalid { row: None },
        }
    }

    /// Resolves the crossing of column j at row k_cross. The refinement's responses come from
    /// prefix sums of the few pixels around the crossing, read once (exact integers: the
    /// direct sums of eq. (1)).
    pub(super) fn resolve_crossing<P: Pixel>(
        &self,
        image: &ImageView<P>,
        j: usize,
        k_cross: usize,
    ) -> ColumnOutcome {
        let plan = &self.plans[j];
        let (lo, _) = plan.window.unwrap();
        let d = self.options.half_width_px;
        let height = image.height();
        let c = plan.column as usize;
        if k_cross == lo || self.options.refinement == crate::edge::Refinement::FirstCrossing {
            return self.resolve_with(j, k_cross, height, |_| 0, |_| 0);
        }
        // The refinement asks for S(k) with k in k_cross - 1 ..= min(k_cross + d + 1, k_max),
        // and the step refinement for pixels inside those windows and up a ramp above them
        // (`ramp_top`); those read the pixels base ..= top (k_cross > lo >= d, so base >= 0).
        let base = k_cross - 1 - d;
        let top = ramp_top(k_cross, d, height);
        const SEGMENT: usize = 64;
        if top - base + 2 > SEGMENT {
            return self.resolve_with(
                j,
                k_cross,
                height,
                |k| direct_response_at(image, c, k, d),
                |k| image.get(c, height - 1 - k).to_i32(),
            );
        }
        let mut prefix = [0i32; SEGMENT];
        let mut total = 0;
        for (t, k) in (base..=top).enumerate() {
            total += image.get(c, height - 1 - k).to_i32();
            prefix[t + 1] = total;
        }
        let p = |k: usize| prefix[k - base];
        self.resolve_with(
            j,
            k_cross,
            height,
            |k| (p(k + d + 1) - p(k + 1)) - (p(k) - p(k - d)),
            |k| p(k + 1) - p(k),
        )
    }

    /// The outcome of column j whose response first crossed at k_cross, `response(k)` giving
    /// S(k) and `pixel(k)` the column's pixel k (from the bottom) for the refinement.
    pub(super) fn resolve_with(
        &self,
        j: usize,
        k_cross: usize,
        height: usize,
        mut response: impl FnMut(usize) -> i32,
        mut pixel: impl FnMut(usize) -> i32,
    ) -> ColumnOutcome {
        let plan = &self.plans[j];
        let (lo, hi) = plan.window.unwrap();
        if k_cross == lo {
            return ColumnOutcome::TooClose;
        }
        let d = self.options.half_width_px;
        let c = plan.column as usize;
        // Pixels exist for windows centred up to height - 1 - d; the refinement may look past
        // the column's top limit by up to d rows to find the peak.
        let k_max = height - 1 - d;
        let k = match self.options.refinement {
            Refinement::Step => {
                let sign = if response(k_cross) >= 0 { 1 } else { -1 };
                let peak = refine_crossing(Refinement::SubPixel, k_cross, d, lo, k_max, response);
                let (radius, top) = (d as f64 / 2.0, ramp_top(k_cross, d, height));
                let cap = RAMP_ROWS_PER_HALF_WIDTH * d;
                let above = ramp_above(peak.k, radius, sign, cap, top, &mut pixel);
                sharpest_step(peak.k, sign, radius, above, k_cross - 1 - d, top, pixel)
            }
            r => refine_crossing(r, k_cross, d, lo, k_max, response).k,
        };
        // A refined edge above the column's last scanned row lies past its ground (the table's
        // or the range limit's): beyond what the column can place, so free up to that row.
        if k > hi as f64 {
            return self.no_boundary(j, height);
        }
        let row = (height - 1) as f64 - k;
        match self.table.lookup(c as f64, row) {
            Some(point) => {
                // Floor covered by one pixel row at the boundary: the reading's range resolution.
                let v = (row.round().max(0.0) as usize).min(height - 1);
                let footprint_m = self.footprints_m[j * height + v] as f64;
                ColumnOutcome::Boundary {
                    row,
                    point,
                    footprint_m,
                }
            }
            None => ColumnOutcome::Invalid { row: Some(row) },
        }
    }
}

/// The highest pixel (from the bottom) the step refinement of a crossing at `k_cross` reads:
/// the box filter's windows around the crossing, then a ramp of up to
/// `RAMP_ROWS_PER_HALF_WIDTH` x d rows above them (`edge::ramp_above`), within the image.
fn ramp_top(k_cross: usize, d: usize, height: usize) -> usize {
    let k_max = height - 1 - d;
    ((k_cross + d + 1).min(k_max) + d + RAMP_ROWS_PER_HALF_WIDTH * d + 2).min(height - 1)
}

/// Confidence of an edge whose raw response `s` crossed `threshold_sum`: 1 - t / |S|, 0 at the
/// threshold, towards 1 for edges far above it.
pub(super) fn edge_confidence(s: i32, threshold_sum: i32) -> f32 {
    let m = s.unsigned_abs() as f32;
    if m <= 0.0 {
        0.0
    } else {
        (1.0 - threshold_sum.max(0) as f32 / m).clamp(0.0, 1.0)
    }
}
