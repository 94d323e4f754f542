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
        let height = image.height();
        let band = near_band_rows(height, d);
        // The noise is pooled over at most NOISE_COLUMNS evenly spread scannable columns.
        let stride = self.by_lo.len().div_ceil(NOISE_COLUMNS).max(1);
        let mut n = 0;
        let mut scannable = 0;
        // The rows (k) of the pixels each column's band windows read, lo - d ..= top + d, and
        // whether every scannable column shares them (the common case: one bottom margin,
        // ground higher than the band).
        let rows_of = |(lo, hi): (usize, usize)| (lo - d, hi.min(lo + band - 1) + d);
        let mut shared = None;
        let mut all_shared = true;
        for (j, plan) in self.plans.iter().enumerate() {
            let Some(window) = plan.window else {
                self.column_brightness[j] = 0.0;
                continue;
            };
            let rows = rows_of(window);
            all_shared &= *shared.get_or_insert(rows) == rows;
            scannable += 1;
            let noise = k_noise > 0.0 && (scannable - 1) % stride == 0;
            let per_column_brightness = contrast > 0.0 && !all_shared;
            if !noise && !per_column_brightness {
                continue;
            }
            // The column's pixels under the band's windows, read once.
            let c = plan.column as usize;
            let (first, last) = rows;
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
            if per_column_brightness {
                self.column_brightness[j] = mean_of(pixels);
            }
        }
        if contrast > 0.0 {
            match shared.filter(|_| all_shared) {
                Some(rows) => self.shared_band_brightness(image, rows),
                // columns met before their rows differed from the first's
                None => self.band_brightness_by_column(image, rows_of),
            }
        }
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
    /// Each scannable column's mean brightness over the shared band rows `(first, last)` (k),
    /// summed row by row over the row's slice where the sampled columns are consecutive
    /// pixels (all columns: the sums vectorise), column by column otherwise.
    fn shared_band_brightness<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        (first, last): (usize, usize),
    ) {
        let n = self.plans.len();
        let c0 = self.plans[0].column as usize;
        let consecutive = image.col_stride() == 1
            && self
                .plans
                .iter()
                .enumerate()
                .all(|(j, p)| p.column as usize == c0 + j);
        if !consecutive {
            let rows = (first, last);
            self.band_brightness_by_column(image, |_| rows);
            return;
        }
        let height = image.height();
        let sums = &mut self.brightness_sums;
        sums.fill(0);
        for k in first..=last {
            let row = &image.row(height - 1 - k)[c0..c0 + n];
            for (sum, p) in sums.iter_mut().zip(row) {
                *sum += p.to_i32();
            }
        }
        let count = (last + 1 - first) as f64;
        for ((b, plan), &sum) in self
            .column_brightness
            .iter_mut()
            .zip(&self.plans)
            .zip(sums.iter())
        {
            *b = if plan.window.is_some() {
                f64::from(sum) / count
            } else {
                0.0
            };
        }
    }

    /// Each scannable column's mean brightness over its own band rows, column by column.
    fn band_brightness_by_column<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        rows_of: impl Fn((usize, usize)) -> (usize, usize),
    ) {
        let height = image.height();
        for (j, plan) in self.plans.iter().enumerate() {
            let Some(window) = plan.window else {
                continue;
            };
            let (first, last) = rows_of(window);
            let c = plan.column as usize;
            let pixels = &mut self.band_pixels[..last + 1 - first];
            for (i, p) in pixels.iter_mut().enumerate() {
                *p = image.get(c, height - 1 - (first + i)).to_i32();
            }
            self.column_brightness[j] = mean_of(pixels);
        }
    }
}

/// The mean of a column's pixels.
fn mean_of(pixels: &[i32]) -> f64 {
    let sum: i64 = pixels.iter().map(|&p| i64::from(p)).sum();
    sum as f64 / pixels.len() as f64
}
