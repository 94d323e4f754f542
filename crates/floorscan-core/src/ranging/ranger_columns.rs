//! The ranger's column loop: every sampled column advanced one image row per step with the
//! incremental box filter of eq. (1), the test windows opened and closed as rows pass, and
//! each crossing resolved where it happens. One loop for every image type; the row step
//! itself (plain Rust, the lane kernels, or the byte-average prefilter) is a
//! [`RowStep`](super::row_step::RowStep).

use super::row_step::{LaneStep, PrefilterStep, RowStep, WideStep};
use super::*;

impl VisualRanger {
    pub(super) fn run_columns<P: Pixel>(&mut self, image: &ImageView<P>) {
        let d = self.options.half_width_px;
        self.crossings.fill(usize::MAX);
        for (o, plan) in self.outcomes.iter_mut().zip(&self.plans) {
            *o = plan
                .window
                .is_none()
                .then_some(ColumnOutcome::Invalid { row: None });
        }
        if self.by_lo.is_empty() {
            return;
        }
        // The buffers leave the ranger while the loop runs (no allocation: a Vec's move).
        let mut scratch = std::mem::take(&mut self.scratch);
        let mut hits = std::mem::take(&mut self.hits);
        let columns = || self.plans.iter().map(|p| p.column as usize);
        let contiguous = scratch.set_offsets(columns(), image.col_stride());
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        match image.as_u8() {
            Some(bytes) if self.prefilter => {
                let step =
                    PrefilterStep::new(&mut scratch, bytes, d, contiguous, self.kernel, k_first);
                self.drive_columns(image, step, k_first, &mut hits);
            }
            Some(bytes) if d <= MAX_HALF_WIDTH_I16 => {
                let step = LaneStep::new(&mut scratch, bytes, d, contiguous, self.kernel, k_first);
                self.drive_columns(image, step, k_first, &mut hits);
            }
            _ => {
                let step = WideStep::new(&mut scratch, *image, d, contiguous, columns(), k_first);
                self.drive_columns(image, step, k_first, &mut hits);
            }
        }
        self.scratch = scratch;
        self.hits = hits;
    }

    /// Steps every column up from row `k_first` until each has crossed or its window has
    /// ended (no edge: free to its top row).
    fn drive_columns<P: Pixel, S: RowStep>(
        &mut self,
        image: &ImageView<P>,
        mut step: S,
        k_first: usize,
        hits: &mut Vec<(usize, i32)>,
    ) {
        let height = image.height();
        let d = self.options.half_width_px;
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut step, &mut events, k, height, &mut unresolved);
        let mut maybe_crossing = step.test();
        loop {
            if maybe_crossing {
                step.crossings(k, hits);
                for &(j, s) in hits.iter() {
                    self.confidence[j] = edge_confidence(s, self.column_threshold_sum[j]);
                    self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                    self.crossings[j] = k;
                    step.close(j);
                    unresolved -= 1;
                }
                hits.clear();
            }
            if unresolved == 0 {
                break;
            }
            // Past height - 1 - d no window fits in the image; no column tests a row there
            // either (every window ends at or below it), so the events of k + 1 close them all.
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut step, &mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            maybe_crossing = step.advance(k);
        }
    }

    /// Opens the test windows that start at k and closes those that ended below k (no edge:
    /// free up to the column's top row).
    fn apply_window_events(
        &mut self,
        step: &mut impl RowStep,
        cursor: &mut EventCursor,
        k: usize,
        height: usize,
        unresolved: &mut usize,
    ) {
        while cursor.lo < self.by_lo.len()
            && self.plans[self.by_lo[cursor.lo]].window.unwrap().0 <= k
        {
            let j = self.by_lo[cursor.lo];
            if self.outcomes[j].is_none() {
                step.open(j, self.column_threshold_sum[j], self.column_prefilter[j]);
            }
            cursor.lo += 1;
        }
        while cursor.hi < self.by_hi.len()
            && self.plans[self.by_hi[cursor.hi]].window.unwrap().1 < k
        {
            let j = self.by_hi[cursor.hi];
            cursor.hi += 1;
            if self.outcomes[j].is_none() {
                self.outcomes[j] = Some(self.no_boundary(j, height));
                step.close(j);
                *unresolved -= 1;
            }
        }
    }
}

/// Positions in the ranger's window-start and window-end orders.
#[derive(Default)]
struct EventCursor {
    lo: usize,
    hi: usize,
}
