//! The frame's thresholds: each column's from the near floor's texture noise and brightness
//! (`noise_multiple`, `contrast`), never below the configured `threshold`.

use super::*;

impl VisualRanger {
    /// Sets each column's threshold for this frame from its near-floor band (when
    /// `noise_multiple` or `contrast` is > 0): max(threshold, noise_multiple x sigma of the
    /// frame, contrast x the column's mean brightness).
    pub(super) fn set_frame_threshold<P: Pixel>(&mut self, image: &ImageView<P>) {
        let (k_noise, contrast) = (self.options.noise_multiple, self.options.contrast);
        if k_noise <= 0.0 && contrast <= 0.0 {
            return;
        }
        let d = self.options.half_width_px;
        let band = near_band_rows(image.height(), d);
        // The noise is pooled over at most NOISE_COLUMNS evenly spread scannable columns.
        let stride = self.by_lo.len().div_ceil(NOISE_COLUMNS).max(1);
        // The rows (k) of the pixels each column's band windows read, lo - d ..= top + d, and
        // whether every scannable column shares them (the common case: one bottom margin,
        // ground higher than the band).
        let rows_of = move |(lo, hi): (usize, usize)| (lo - d, hi.min(lo + band - 1) + d);
        let mut shared = None;
        let mut all_shared = true;
        for window in self.plans.iter().filter_map(|p| p.window) {
            all_shared &= *shared.get_or_insert(rows_of(window)) == rows_of(window);
        }
        let n = match shared.filter(|_| all_shared) {
            Some(rows) => self.band_statistics_shared(image, rows, stride),
            None => self.band_statistics_by_column(image, rows_of, stride),
        };
        let noise_threshold =
            match robust_sigma_counted(&mut self.noise_samples[..n], &mut self.noise_histogram) {
                Some(sigma_s) => k_noise * sigma_s / (2 * d) as f64,
                None => 0.0,
            };
        let base = self.options.threshold.max(noise_threshold);
        self.frame_threshold = base;
        let mut lowest = i32::MAX;
        let mut memo = (i32::MIN, None);
        let mid_contrast = self.options.mid_contrast.min(contrast);
        self.band_active = false;
        for j in 0..self.plans.len() {
            let t = base.max(contrast * self.column_brightness[j]);
            let sum = threshold_to_sum(t, d);
            if self.plans[j].band.is_some() {
                let band_sum =
                    threshold_to_sum(base.max(mid_contrast * self.column_brightness[j]), d);
                self.band_threshold_sum[j] = band_sum;
                self.band_active |= band_sum < sum;
            }
            if memo.0 != sum {
                memo = (sum, lanes::prefilter_threshold(d, sum));
            }
            self.column_threshold_sum[j] = sum;
            self.column_prefilter[j] = memo.1.unwrap_or(u8::MAX);
            if self.plans[j].window.is_some() {
                lowest = lowest.min(sum);
            }
        }
        // The prefilter serves a frame only if it is conservative for every column.
        self.prefilter = lowest == i32::MAX || lanes::prefilter_threshold(d, lowest).is_some();
    }
    /// The band's noise samples (returns how many) and each column's band brightness, column
    /// by column: the scannable columns do not all share their band rows (one column's pixels
    /// read at a time).
    fn band_statistics_by_column<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        rows_of: impl Fn((usize, usize)) -> (usize, usize),
        stride: usize,
    ) -> usize {
        let (k_noise, contrast) = (self.options.noise_multiple, self.options.contrast);
        let d = self.options.half_width_px;
        let height = image.height();
        let mut n = 0;
        let mut scannable = 0;
        for (j, plan) in self.plans.iter().enumerate() {
            let Some(window) = plan.window else {
                self.column_brightness[j] = 0.0;
                continue;
            };
            scannable += 1;
            let noise = k_noise > 0.0 && (scannable - 1) % stride == 0;
            if !noise && contrast <= 0.0 {
                continue;
            }
            // The column's pixels under the band's windows, read once.
            let c = plan.column as usize;
            let (first, last) = rows_of(window);
            let pixels = &mut self.band_pixels[..last + 1 - first];
            for (i, p) in pixels.iter_mut().enumerate() {
                *p = image.get(c, height - 1 - (first + i)).to_i32();
            }
            if noise {
                // S(k) for k = lo ..= top: the windows of k = lo start at pixels[0]
                let mut s = direct_response(pixels, d, d);
                self.noise_samples[n] = s;
                n += 1;
                for i in d + 1..pixels.len() - d {
                    s = next_response(
                        s,
                        pixels[i - 1 - d],
                        pixels[i - 1],
                        pixels[i],
                        pixels[i + d],
                    );
                    self.noise_samples[n] = s;
                    n += 1;
                }
            }
            if contrast > 0.0 {
                self.column_brightness[j] = mean_of(pixels);
            }
        }
        n
    }

    /// The band's noise samples (returns how many) and each column's band brightness where
    /// every scannable column shares the band rows `(first, last)` (k), a row at a time across
    /// the columns: read from the image's rows where the columns are consecutive pixels, else
    /// gathered row by row into `band_rows` first (memory read in order). The samples are
    /// those of [`Self::band_statistics_by_column`] in another order (the noise's median and
    /// spread do not depend on it).
    fn band_statistics_shared<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        (first, last): (usize, usize),
        stride: usize,
    ) -> usize {
        let height = image.height();
        // the scannable columns' offsets, in plan order
        let mut m = 0;
        for (j, plan) in self.plans.iter().enumerate() {
            if plan.window.is_some() {
                self.band_offsets[m] = plan.column as usize * image.col_stride();
                m += 1;
            } else {
                self.column_brightness[j] = 0.0;
            }
        }
        let rows = last + 1 - first;
        let offsets = &self.band_offsets[..m];
        let image_row = |r: usize| image.row(height - 1 - (first + r));
        let stats = BandStatistics {
            d: self.options.half_width_px,
            stride,
            noise: self.options.noise_multiple > 0.0,
            brightness: self.options.contrast > 0.0,
        };
        let n = if image.col_stride() == 1 && offsets.windows(2).all(|w| w[1] == w[0] + 1) {
            let o = offsets[0];
            stats.run(
                |r| &image_row(r)[o..o + m],
                rows,
                &mut self.brightness_sums[..m],
                &mut self.band_responses,
                &mut self.noise_samples,
            )
        } else {
            let max_offset = offsets.iter().copied().max().unwrap_or(0);
            for r in 0..rows {
                let row = image_row(r);
                // Offsets come from columns checked against the image width when the ranger
                // was built (and the image size against the table's): one check of the largest.
                assert!(max_offset < row.len(), "column offset outside the row");
                for (dst, &o) in self.band_rows[r * m..(r + 1) * m].iter_mut().zip(offsets) {
                    // SAFETY: o <= max_offset < row.len() (asserted above).
                    *dst = unsafe { row.get_unchecked(o) }.to_i32() as u16;
                }
            }
            let band_rows = &self.band_rows;
            stats.run(
                |r| &band_rows[r * m..(r + 1) * m],
                rows,
                &mut self.brightness_sums[..m],
                &mut self.band_responses,
                &mut self.noise_samples,
            )
        };
        if stats.brightness {
            let mut t = 0;
            for (b, plan) in self.column_brightness.iter_mut().zip(&self.plans) {
                if plan.window.is_some() {
                    *b = f64::from(self.brightness_sums[t]) / rows as f64;
                    t += 1;
                }
            }
        }
        n
    }
}

/// What [`VisualRanger::band_statistics_shared`] works out over the band's rows, each row a
/// slice of the scannable columns' pixels.
struct BandStatistics {
    d: usize,
    /// The noise columns: every stride-th scannable one.
    stride: usize,
    noise: bool,
    brightness: bool,
}

impl BandStatistics {
    /// Sums each column's pixels into `sums` (with `brightness`) and writes the noise columns'
    /// responses S(k) at every row of the band into `samples` (with `noise`; returns how
    /// many), advancing them in `responses` a row at a time.
    fn run<'a, Q: Pixel + 'a>(
        &self,
        row: impl Fn(usize) -> &'a [Q],
        rows: usize,
        sums: &mut [i32],
        responses: &mut [i32],
        samples: &mut [i32],
    ) -> usize {
        let d = self.d;
        if self.brightness {
            sums.fill(0);
            for r in 0..rows {
                for (sum, p) in sums.iter_mut().zip(row(r)) {
                    *sum += p.to_i32();
                }
            }
        }
        if !self.noise {
            return 0;
        }
        let stride = self.stride;
        let s = &mut responses[..sums.len().div_ceil(stride)];
        for (i, sum) in s.iter_mut().enumerate() {
            let t = i * stride;
            *sum = (1..=d)
                .map(|q| row(d + q)[t].to_i32() - row(d - q)[t].to_i32())
                .sum();
        }
        let mut n = 0;
        for r in d..rows - d {
            if r > d {
                let (a, b, c, e) = (row(r - 1 - d), row(r - 1), row(r), row(r + d));
                if stride == 1 {
                    advance_rows(s, [a, b, c, e]);
                } else {
                    for (i, sum) in s.iter_mut().enumerate() {
                        let t = i * stride;
                        *sum += e[t].to_i32() - c[t].to_i32() - b[t].to_i32() + a[t].to_i32();
                    }
                }
            }
            samples[n..n + s.len()].copy_from_slice(s);
            n += s.len();
        }
        n
    }
}

/// `S += e - c - b + a` element by element (equal-length slices and an index loop, which
/// vectorise).
fn advance_rows<Q: Pixel>(s: &mut [i32], [a, b, c, e]: [&[Q]; 4]) {
    let n = s.len();
    let (a, b, c, e) = (&a[..n], &b[..n], &c[..n], &e[..n]);
    for i in 0..n {
        s[i] += e[i].to_i32() - c[i].to_i32() - b[i].to_i32() + a[i].to_i32();
    }
}

/// The mean of a column's pixels.
fn mean_of(pixels: &[i32]) -> f64 {
    let sum: i64 = pixels.iter().map(|&p| i64::from(p)).sum();
    sum as f64 / pixels.len() as f64
}
