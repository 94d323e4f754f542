//! One row step of the column loop, three ways: 32-bit running sums in plain Rust for any
//! pixel type ([`WideStep`]), 16-bit running sums through the lane kernels for 8-bit images
//! ([`LaneStep`]), and the byte-average prefilter for 8-bit images whose half-width is a
//! power of two ([`PrefilterStep`]). The loop that drives them, opening and closing the test
//! windows and resolving each crossing, is one ([`VisualRanger::run_columns`]).

use super::*;

/// The column loop's per-frame buffers, indexed like the ranger's plans (sized once).
#[derive(Debug, Clone, Default)]
pub(super) struct ColumnScratch {
    /// 32-bit running sums and their thresholds (i32::MAX: column not tested).
    sums: Vec<i32>,
    active_threshold: Vec<i32>,
    /// Each sampled pixel's offset in its image row, and the largest of them.
    offsets: Vec<usize>,
    max_offset: usize,
    /// The sampled pixels of the last 2d + 2 rows (row k in slot k mod (2d + 2)), so sparse
    /// columns are gathered once per row and updated from contiguous memory.
    ring: Vec<u16>,
    /// The 8-bit paths: 16-bit sums and thresholds (i16::MAX: not tested), the crossing masks
    /// of the last row step (one word per LANES columns), the byte ring (a power of two rows),
    /// and the prefilter's byte thresholds (255: not tested) and flags.
    sums16: Vec<i16>,
    active_threshold16: Vec<i16>,
    masks: Vec<u32>,
    ring8: Vec<u8>,
    thresholds8: Vec<u8>,
    flags: Vec<u8>,
}

impl ColumnScratch {
    /// Buffers for n columns at half-width d.
    pub(super) fn new(n: usize, d: usize) -> Self {
        let small_d = d <= MAX_HALF_WIDTH_I16;
        Self {
            sums: vec![0; n],
            active_threshold: vec![i32::MAX; n],
            offsets: vec![0; n],
            max_offset: 0,
            ring: vec![0; (2 * d + 2) * n],
            sums16: vec![0; if small_d { n } else { 0 }],
            active_threshold16: vec![i16::MAX; n],
            masks: vec![0; n.div_ceil(LANES)],
            ring8: vec![0; if small_d { ring8_rows(d) * n } else { 0 }],
            thresholds8: vec![u8::MAX; n],
            flags: vec![0; n],
        }
    }

    /// Sets the columns' offsets in an image row; returns whether the sampled columns are
    /// consecutive pixels of a contiguous row (plain slices, which vectorise).
    pub(super) fn set_offsets(
        &mut self,
        columns: impl Iterator<Item = usize>,
        stride: usize,
    ) -> bool {
        for (off, c) in self.offsets.iter_mut().zip(columns) {
            *off = c * stride;
        }
        self.max_offset = self.offsets.iter().copied().max().unwrap_or(0);
        stride == 1 && self.offsets.windows(2).all(|w| w[1] == w[0] + 1)
    }

    /// Copies the sampled pixels of row k (from the bottom) into its ring slot.
    fn gather_row<P: Pixel>(&mut self, image: &ImageView<P>, k: usize, ring_rows: usize) {
        let n = self.offsets.len();
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

    /// Copies the sampled pixels of 8-bit row k (from the bottom) into its byte-ring slot.
    fn gather_row8(&mut self, image: &ImageView<u8>, k: usize, ring_rows: usize) {
        let n = self.offsets.len();
        let start = (k & (ring_rows - 1)) * n;
        let row = image.row(image.height() - 1 - k);
        // As in `gather_row`: one check of the largest offset covers every pixel.
        assert!(self.max_offset < row.len(), "column offset outside the row");
        for (dst, &o) in self.ring8[start..start + n].iter_mut().zip(&self.offsets) {
            // SAFETY: o <= max_offset < row.len() (asserted above).
            *dst = unsafe { *row.get_unchecked(o) };
        }
    }
}

/// One way of stepping every sampled column up one image row and testing it.
pub(super) trait RowStep {
    /// Column j's test window opens: `threshold` on |S| (the raw sum of eq. (1)), `prefilter`
    /// its byte threshold for the prefilter.
    fn open(&mut self, j: usize, threshold: i32, prefilter: u8);
    /// Column j is no longer tested (resolved, or its window has ended).
    fn close(&mut self, j: usize);
    /// Tests the current row in full; returns whether any column may cross there.
    fn test(&mut self) -> bool;
    /// Advances every column from row k - 1 to row k and tests it; returns whether any column
    /// may cross at k.
    fn advance(&mut self, k: usize) -> bool;
    /// After a `test` or `advance` that returned true: appends (j, S(k)) for every tested
    /// column whose |S(k)| exceeds its threshold at row k.
    fn crossings(&mut self, k: usize, hits: &mut Vec<(usize, i32)>);
}

/// 32-bit running sums in plain Rust, for any pixel type.
pub(super) struct WideStep<'s, 'i, P: Pixel> {
    s: &'s mut ColumnScratch,
    image: ImageView<'i, P>,
    d: usize,
    contiguous: bool,
}

impl<'s, 'i, P: Pixel> WideStep<'s, 'i, P> {
    /// Ready at row `k_first` (the lowest window start): every column's S(k_first).
    pub(super) fn new(
        s: &'s mut ColumnScratch,
        image: ImageView<'i, P>,
        d: usize,
        contiguous: bool,
        columns: impl Iterator<Item = usize>,
        k_first: usize,
    ) -> Self {
        s.active_threshold.fill(i32::MAX);
        for (sum, c) in s.sums.iter_mut().zip(columns) {
            *sum = direct_response_at(&image, c, k_first, d);
        }
        let step = Self {
            s,
            image,
            d,
            contiguous,
        };
        if !contiguous {
            for k in k_first - d..=k_first + d {
                step.s.gather_row(&step.image, k, 2 * d + 2);
            }
        }
        step
    }
}

impl<P: Pixel> RowStep for WideStep<'_, '_, P> {
    fn open(&mut self, j: usize, threshold: i32, _prefilter: u8) {
        self.s.active_threshold[j] = threshold;
    }

    fn close(&mut self, j: usize) {
        self.s.active_threshold[j] = i32::MAX;
    }

    fn test(&mut self) -> bool {
        let s = &*self.s;
        s.sums
            .iter()
            .zip(&s.active_threshold)
            .fold(false, |any, (v, t)| any | (v.abs() > *t))
    }

    fn advance(&mut self, k: usize) -> bool {
        let d = self.d;
        let height = self.image.height();
        if self.contiguous {
            let (o, n) = (self.s.offsets[0], self.s.offsets.len());
            let image = self.image;
            let row = |k: usize| &image.row(height - 1 - k)[o..o + n];
            advance_contiguous(
                &mut self.s.sums,
                &self.s.active_threshold,
                [row(k - 1 - d), row(k - 1), row(k), row(k + d)],
            )
        } else {
            let ring_rows = 2 * d + 2;
            self.s.gather_row(&self.image, k + d, ring_rows);
            let ColumnScratch {
                sums,
                active_threshold,
                ring,
                offsets,
                ..
            } = &mut *self.s;
            let n = offsets.len();
            let slot = |k: usize| &ring[(k % ring_rows) * n..(k % ring_rows + 1) * n];
            advance_contiguous(
                sums,
                active_threshold,
                [slot(k - 1 - d), slot(k - 1), slot(k), slot(k + d)],
            )
        }
    }

    fn crossings(&mut self, _k: usize, hits: &mut Vec<(usize, i32)>) {
        let s = &*self.s;
        hits.extend(
            (0..s.sums.len())
                .filter(|&j| s.sums[j].abs() > s.active_threshold[j])
                .map(|j| (j, s.sums[j])),
        );
    }
}

/// 16-bit running sums advanced by the lane kernels, which mark the columns that crossed.
pub(super) struct LaneStep<'s, 'i> {
    s: &'s mut ColumnScratch,
    image: ImageView<'i, u8>,
    d: usize,
    contiguous: bool,
    kernel: Kernel,
}

impl<'s, 'i> LaneStep<'s, 'i> {
    /// Ready at row `k_first`: every column's S(k_first), row-major (the d rows above minus
    /// the d below).
    pub(super) fn new(
        s: &'s mut ColumnScratch,
        image: ImageView<'i, u8>,
        d: usize,
        contiguous: bool,
        kernel: Kernel,
        k_first: usize,
    ) -> Self {
        let height = image.height();
        let row_of = |k: usize| height - 1 - k;
        let ring_rows = ring8_rows(d);
        let n = s.offsets.len();
        s.active_threshold16.fill(i16::MAX);
        s.sums16.fill(0);
        if contiguous {
            let o = s.offsets[0];
            for i in 1..=d {
                lanes::accumulate_row(&mut s.sums16, &image.row(row_of(k_first + i))[o..], true);
                lanes::accumulate_row(&mut s.sums16, &image.row(row_of(k_first - i))[o..], false);
            }
        } else {
            for k in k_first - d..=k_first + d {
                s.gather_row8(&image, k, ring_rows);
            }
            let slot = |k: usize| (k & (ring_rows - 1)) * n;
            for i in 1..=d {
                let (up, down) = (slot(k_first + i), slot(k_first - i));
                lanes::accumulate_row(&mut s.sums16, &s.ring8[up..up + n], true);
                lanes::accumulate_row(&mut s.sums16, &s.ring8[down..down + n], false);
            }
        }
        Self {
            s,
            image,
            d,
            contiguous,
            kernel,
        }
    }
}

impl RowStep for LaneStep<'_, '_> {
    fn open(&mut self, j: usize, threshold: i32, _prefilter: u8) {
        // Inside the 8-bit path |S| <= 255 d < i16::MAX, so a clamped threshold tests the same.
        self.s.active_threshold16[j] = threshold.clamp(-1, i16::MAX as i32) as i16;
    }

    fn close(&mut self, j: usize) {
        self.s.active_threshold16[j] = i16::MAX;
    }

    fn test(&mut self) -> bool {
        let s = &mut *self.s;
        lanes::test_sums(&s.sums16, &s.active_threshold16, &mut s.masks)
    }

    fn advance(&mut self, k: usize) -> bool {
        let d = self.d;
        let n = self.s.offsets.len();
        if self.contiguous {
            let o = self.s.offsets[0];
            let (image, height) = (self.image, self.image.height());
            let row = |k: usize| &image.row(height - 1 - k)[o..o + n];
            let s = &mut *self.s;
            lanes::advance_u8(
                self.kernel,
                &mut s.sums16,
                &s.active_threshold16,
                [row(k - 1 - d), row(k - 1), row(k), row(k + d)],
                &mut s.masks,
            )
        } else {
            let ring_rows = ring8_rows(d);
            self.s.gather_row8(&self.image, k + d, ring_rows);
            let ColumnScratch {
                sums16,
                active_threshold16,
                ring8,
                masks,
                ..
            } = &mut *self.s;
            let slot =
                |k: usize| &ring8[(k & (ring_rows - 1)) * n..((k & (ring_rows - 1)) + 1) * n];
            lanes::advance_u8(
                self.kernel,
                sums16,
                active_threshold16,
                [slot(k - 1 - d), slot(k - 1), slot(k), slot(k + d)],
                masks,
            )
        }
    }

    fn crossings(&mut self, _k: usize, hits: &mut Vec<(usize, i32)>) {
        let s = &*self.s;
        for (chunk, &mask) in s.masks.iter().enumerate() {
            let mut m = mask;
            while m != 0 {
                let lane = m.trailing_zeros() as usize / 2;
                m &= !lanes::lane_bits(lane);
                let j = chunk * LANES + lane;
                hits.push((j, i32::from(s.sums16[j])));
            }
        }
    }
}

/// For 8-bit images where the prefilter applies (d a power of two): each row flags, from byte
/// averages, the columns that may cross; only those get the exact sum of eq. (1), from the 2d
/// rows around the pixel.
pub(super) struct PrefilterStep<'s, 'i> {
    s: &'s mut ColumnScratch,
    image: ImageView<'i, u8>,
    d: usize,
    contiguous: bool,
    kernel: Kernel,
}

impl<'s, 'i> PrefilterStep<'s, 'i> {
    /// Ready at row `k_first`: its 2d + 1 rows gathered where the columns are sparse.
    pub(super) fn new(
        s: &'s mut ColumnScratch,
        image: ImageView<'i, u8>,
        d: usize,
        contiguous: bool,
        kernel: Kernel,
        k_first: usize,
    ) -> Self {
        s.active_threshold.fill(i32::MAX);
        s.thresholds8.fill(u8::MAX);
        if !contiguous {
            for k in k_first - d..=k_first + d {
                s.gather_row8(&image, k, ring8_rows(d));
            }
        }
        Self {
            s,
            image,
            d,
            contiguous,
            kernel,
        }
    }
}

impl RowStep for PrefilterStep<'_, '_> {
    fn open(&mut self, j: usize, threshold: i32, prefilter: u8) {
        self.s.active_threshold[j] = threshold;
        self.s.thresholds8[j] = prefilter;
    }

    fn close(&mut self, j: usize) {
        self.s.active_threshold[j] = i32::MAX;
        self.s.thresholds8[j] = u8::MAX;
    }

    fn test(&mut self) -> bool {
        true
    }

    fn advance(&mut self, k: usize) -> bool {
        if !self.contiguous {
            self.s
                .gather_row8(&self.image, k + self.d, ring8_rows(self.d));
        }
        true
    }

    fn crossings(&mut self, k: usize, hits: &mut Vec<(usize, i32)>) {
        let d = self.d;
        let height = self.image.height();
        let ring_rows = ring8_rows(d);
        let s = &mut *self.s;
        let n = s.offsets.len();
        let o = s.offsets[0];
        let mut rows: [&[u8]; 2 * lanes::MAX_PREFILTER_HALF_WIDTH + 1] =
            [&[]; 2 * lanes::MAX_PREFILTER_HALF_WIDTH + 1];
        // Rows k - d ..= k + d (from the image, or from the ring of gathered columns).
        for (i, r) in rows[..2 * d + 1].iter_mut().enumerate() {
            let kk = k + i - d;
            *r = if self.contiguous {
                &self.image.row(height - 1 - kk)[o..o + n]
            } else {
                let slot = kk & (ring_rows - 1);
                &s.ring8[slot * n..(slot + 1) * n]
            };
        }
        let rows = &rows[..2 * d + 1];
        if !lanes::prefilter_u8(self.kernel, rows, &s.thresholds8, &mut s.flags) {
            return;
        }
        let words = n / 8;
        for w in 0..=words {
            let mut word = if w < words {
                u64::from_le_bytes(s.flags[8 * w..8 * w + 8].try_into().unwrap())
            } else {
                s.flags[8 * w..]
                    .iter()
                    .rev()
                    .fold(0u64, |acc, &f| (acc << 8) | f as u64)
            };
            while word != 0 {
                let j = 8 * w + word.trailing_zeros() as usize / 8;
                word &= !(0xFFu64 << (8 * (j - 8 * w)));
                let sum: i32 = (1..=d)
                    .map(|t| rows[d + t][j] as i32 - rows[d - t][j] as i32)
                    .sum();
                if sum.abs() > s.active_threshold[j] {
                    hits.push((j, sum));
                }
            }
        }
    }
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

/// Rows of the byte ring: at least the 2d + 2 a row step reads, a power of two (slot = k & mask).
pub(super) fn ring8_rows(d: usize) -> usize {
    (2 * d + 2).next_power_of_two()
}
