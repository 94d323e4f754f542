//! The ranger's column loop: every sampled column advanced one image row per step with the
//! incremental box filter of eq. (1), for 16-bit images in plain Rust and for 8-bit images
//! through the lane kernels of [`crate::lanes`] (with the byte-average prefilter where the
//! half-width is a power of two); the test windows opened and closed as rows pass, and each
//! crossing resolved where it happens.

use super::*;

impl VisualRanger {
    pub(super) fn run_columns<P: Pixel>(&mut self, image: &ImageView<P>) {
        let height = image.height();
        let d = self.options.half_width_px;
        let row_of = |k: usize| height - 1 - k;
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
        for (off, plan) in self.offsets.iter_mut().zip(&self.plans) {
            *off = plan.column as usize * image.col_stride();
        }
        self.max_offset = self.offsets.iter().copied().max().unwrap_or(0);
        // Consecutive image columns in a contiguous row: plain slices, which vectorise.
        let contiguous =
            image.col_stride() == 1 && self.offsets.windows(2).all(|w| w[1] == w[0] + 1);
        if let Some(bytes) = image.as_u8() {
            if self.prefilter {
                self.run_columns_prefiltered(&bytes, contiguous);
                return;
            }
            if d <= MAX_HALF_WIDTH_I16 {
                self.run_columns_u8(&bytes, contiguous);
                return;
            }
        }
        let ring_rows = 2 * d + 2;
        self.active_threshold.fill(i32::MAX);
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        for (j, plan) in self.plans.iter().enumerate() {
            self.sums[j] = direct_response_at(image, plan.column as usize, k_first, d);
        }
        if !contiguous {
            for k in k_first - d..=k_first + d {
                self.gather_row(image, k, ring_rows);
            }
        }
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut events, k, height, &mut unresolved);
        let mut any_crossing = self
            .sums
            .iter()
            .zip(&self.active_threshold)
            .fold(false, |any, (s, t)| any | (s.abs() > *t));
        loop {
            if any_crossing {
                for j in 0..self.plans.len() {
                    if self.sums[j].abs() > self.active_threshold[j] {
                        self.confidence[j] =
                            edge_confidence(self.sums[j], self.column_threshold_sum[j]);
                        self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                        self.crossings[j] = k;
                        self.active_threshold[j] = i32::MAX;
                        unresolved -= 1;
                    }
                }
            }
            if unresolved == 0 {
                break;
            }
            // Past height - 1 - d no window fits in the image; no column tests a row there
            // either (every window ends at or below it), so the events of k + 1 close them all.
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            // Advance every running sum from k - 1 to k and test it, in one pass.
            any_crossing = if contiguous {
                let (o, n) = (self.offsets[0], self.offsets.len());
                let row = |k: usize| &image.row(row_of(k))[o..o + n];
                advance_contiguous(
                    &mut self.sums,
                    &self.active_threshold,
                    [row(k - 1 - d), row(k - 1), row(k), row(k + d)],
                )
            } else {
                self.gather_row(image, k + d, ring_rows);
                let n = self.plans.len();
                let slot = |k: usize| &self.ring[(k % ring_rows) * n..(k % ring_rows + 1) * n];
                advance_contiguous(
                    &mut self.sums,
                    &self.active_threshold,
                    [slot(k - 1 - d), slot(k - 1), slot(k), slot(k + d)],
                )
            };
        }
    }

    /// `run_columns` for 8-bit images: 16-bit sums advanced by the lane kernels, which mark
    /// the columns that crossed.
    pub(super) fn run_columns_u8(&mut self, image: &ImageView<u8>, contiguous: bool) {
        let height = image.height();
        let d = self.options.half_width_px;
        let n = self.plans.len();
        let row_of = |k: usize| height - 1 - k;
        let ring_rows = ring8_rows(d);
        self.active_threshold.fill(i32::MAX);
        self.active_threshold16.fill(i16::MAX);
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        // First sums S(k_first) of every column, row-major: the d rows above minus the d below.
        self.sums16.fill(0);
        if contiguous {
            let o = self.offsets[0];
            for i in 1..=d {
                lanes::accumulate_row(&mut self.sums16, &image.row(row_of(k_first + i))[o..], true);
                lanes::accumulate_row(
                    &mut self.sums16,
                    &image.row(row_of(k_first - i))[o..],
                    false,
                );
            }
        } else {
            for k in k_first - d..=k_first + d {
                self.gather_row8(image, k, ring_rows);
            }
            let slot = |k: usize| (k & (ring_rows - 1)) * n;
            for i in 1..=d {
                let (up, down) = (slot(k_first + i), slot(k_first - i));
                lanes::accumulate_row(&mut self.sums16, &self.ring8[up..up + n], true);
                lanes::accumulate_row(&mut self.sums16, &self.ring8[down..down + n], false);
            }
        }
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut events, k, height, &mut unresolved);
        let mut any_crossing =
            lanes::test_sums(&self.sums16, &self.active_threshold16, &mut self.masks);
        loop {
            if any_crossing {
                for chunk in 0..self.masks.len() {
                    let mut m = self.masks[chunk];
                    while m != 0 {
                        let lane = m.trailing_zeros() as usize / 2;
                        m &= !lanes::lane_bits(lane);
                        let j = chunk * LANES + lane;
                        let s = i32::from(self.sums16[j]);
                        self.confidence[j] = edge_confidence(s, self.column_threshold_sum[j]);
                        self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                        self.crossings[j] = k;
                        self.active_threshold[j] = i32::MAX;
                        self.active_threshold16[j] = i16::MAX;
                        unresolved -= 1;
                    }
                }
            }
            if unresolved == 0 {
                break;
            }
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            any_crossing = if contiguous {
                let o = self.offsets[0];
                let row = |k: usize| &image.row(row_of(k))[o..o + n];
                lanes::advance_u8(
                    self.kernel,
                    &mut self.sums16,
                    &self.active_threshold16,
                    [row(k - 1 - d), row(k - 1), row(k), row(k + d)],
                    &mut self.masks,
                )
            } else {
                self.gather_row8(image, k + d, ring_rows);
                let slot = |k: usize| {
                    &self.ring8[(k & (ring_rows - 1)) * n..((k & (ring_rows - 1)) + 1) * n]
                };
                lanes::advance_u8(
                    self.kernel,
                    &mut self.sums16,
                    &self.active_threshold16,
                    [slot(k - 1 - d), slot(k - 1), slot(k), slot(k + d)],
                    &mut self.masks,
                )
            };
        }
    }

    /// `run_columns` for 8-bit images where the prefilter applies (d a power of two): each row
    /// step flags, from byte averages, the columns that may cross; only those get the exact
    /// sum of eq. (1), from the 2d rows around the pixel.
    pub(super) fn run_columns_prefiltered(&mut self, image: &ImageView<u8>, contiguous: bool) {
        let height = image.height();
        let d = self.options.half_width_px;
        let n = self.plans.len();
        let ring_rows = ring8_rows(d);
        self.active_threshold.fill(i32::MAX);
        self.active_threshold16.fill(i16::MAX);
        self.thresholds8.fill(u8::MAX);
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        if !contiguous {
            for k in k_first - d..=k_first + d {
                self.gather_row8(image, k, ring_rows);
            }
        }
        let o = self.offsets[0];
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut events, k, height, &mut unresolved);
        loop {
            let mut rows: [&[u8]; 2 * lanes::MAX_PREFILTER_HALF_WIDTH + 1] =
                [&[]; 2 * lanes::MAX_PREFILTER_HALF_WIDTH + 1];
            // Rows k - d ..= k + d (from the image, or from the ring of gathered columns).
            for (i, r) in rows[..2 * d + 1].iter_mut().enumerate() {
                let kk = k + i - d;
                *r = if contiguous {
                    &image.row(height - 1 - kk)[o..o + n]
                } else {
                    let slot = kk & (ring_rows - 1);
                    &self.ring8[slot * n..(slot + 1) * n]
                };
            }
            let rows = &rows[..2 * d + 1];
            if lanes::prefilter_u8(self.kernel, rows, &self.thresholds8, &mut self.flags) {
                let words = n / 8;
                for w in 0..=words {
                    let word = if w < words {
                        u64::from_le_bytes(self.flags[8 * w..8 * w + 8].try_into().unwrap())
                    } else {
                        self.flags[8 * w..]
                            .iter()
                            .rev()
                            .fold(0u64, |acc, &f| (acc << 8) | f as u64)
                    };
                    let mut word = word;
                    while word != 0 {
                        let j = 8 * w + word.trailing_zeros() as usize / 8;
                        word &= !(0xFFu64 << (8 * (j - 8 * w)));
                        let s: i32 = (1..=d)
                            .map(|t| rows[d + t][j] as i32 - rows[d - t][j] as i32)
                            .sum();
                        let threshold = self.column_threshold_sum[j];
                        if s.abs() > threshold {
                            self.confidence[j] = edge_confidence(s, threshold);
                            self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                            self.crossings[j] = k;
                            self.active_threshold[j] = i32::MAX;
                            self.active_threshold16[j] = i16::MAX;
                            self.thresholds8[j] = u8::MAX;
                            unresolved -= 1;
                        }
                    }
                }
            }
            if unresolved == 0 {
                break;
            }
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            if !contiguous {
                self.gather_row8(image, k + d, ring_rows);
            }
        }
    }

    /// Copies the sampled pixels of 8-bit row k (from the bottom) into its byte-ring slot.
    pub(super) fn gather_row8(&mut self, image: &ImageView<u8>, k: usize, ring_rows: usize) {
        let n = self.plans.len();
        let start = (k & (ring_rows - 1)) * n;
        let row = image.row(image.height() - 1 - k);
        // As in `gather_row`: one check of the largest offset covers every pixel.
        assert!(self.max_offset < row.len(), "column offset outside the row");
        for (dst, &o) in self.ring8[start..start + n].iter_mut().zip(&self.offsets) {
            // SAFETY: o <= max_offset < row.len() (asserted above).
            *dst = unsafe { *row.get_unchecked(o) };
        }
    }

    /// Copies the sampled pixels of row k (from the bottom) into its ring slot.
    pub(super) fn gather_row<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        k: usize,
        ring_rows: usize,
    ) {
        let n = self.plans.len();
        let start = (k % ring_rows) * n;
        let row = image.row(image.height() - 1 - k);
        // Offsets come from columns checked against the image width when the ranger was built
        // (and the image size against the table's), so every offset is inside the row; one
        // check of the largest replaces a bounds check per pixel.
        assert!(self.max_offset < row.len(), "column offset outside the row");
        for (dst, &o) in self.ring[start..start + n].iter_mut().zip(&self.offsets) {
            // SAFETY: o <= max_offset < row.len() (asserted above).
            *dst = unsafe { row.get_unchecked(o) }.to_i32() as u16;
        }
    }

    /// Opens the test windows that start at k and closes those that ended below k (no edge:
    /// free up to the column's top row).
    pub(super) fn apply_window_events(
        &mut self,
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
                let threshold = self.column_threshold_sum[j];
                self.active_threshold[j] = threshold;
                // Inside the 8-bit path |S| <= 255 d < i16::MAX, so a clamped threshold tests
                // the same.
                self.active_threshold16[j] = threshold.clamp(-1, i16::MAX as i32) as i16;
                self.thresholds8[j] = self.column_prefilter[j];
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
                self.active_threshold[j] = i32::MAX;
                self.active_threshold16[j] = i16::MAX;
                self.thresholds8[j] = u8::MAX;
                *unresolved -= 1;
            }
        }
    }
}

/// Positions in the ranger's window-start and window-end orders.
#[derive(Default)]
pub(super) struct EventCursor {
    pub(super) lo: usize,
    pub(super) hi: usize,
}

/// `S(k) = S(k-1) + I(k+d) - I(k) - I(k-1) + I(k-1-d)` for every column whose pixels are the
/// consecutive elements of the four rows `[k-1-d, k-1, k, k+d]`; returns whether any column's
/// new |S| exceeds its active threshold.
#[inline]
pub(super) fn advance_contiguous<P: Pixel>(
    sums: &mut [i32],
    thresholds: &[i32],
    rows: [&[P]; 4],
) -> bool {
    // Equal-length slices and an index loop: the form LLVM vectorises reliably.
    let n = sums.len();
    let (t, a, b, c, e) = (
        &thresholds[..n],
        &rows[0][..n],
        &rows[1][..n],
        &rows[2][..n],
        &rows[3][..n],
    );
    let mut hits = 0i32;
    for i in 0..n {
        let v = sums[i] + e[i].to_i32() - c[i].to_i32() - b[i].to_i32() + a[i].to_i32();
        sums[i] = v;
        hits |= (v.abs() > t[i]) as i32;
    }
    hits != 0
}
