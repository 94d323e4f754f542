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
        for (j, plan) in self.plans.iter().enumerate() {
            let Some((lo, hi)) = plan.window else {
                continue;
            };
            scannable += 1;
            let c = plan.column as usize;
            let px = |k: usize| image.get(c, height - 1 - k).to_i32();
            let top = hi.min(lo + band - 1);
            if k_noise > 0.0 && (scannable - 1) % stride == 0 {
                let mut s = direct_response_at(image, c, lo, d);
                for k in lo..=top {
                    if k > lo {
                        s = next_response(s, px(k - 1 - d), px(k - 1), px(k), px(k + d));
                    }
                    self.noise_samples[n] = s;
                    n += 1;
                }
            }
            // The column's mean brightness over the pixels the band's windows read.
            let mean = if contrast > 0.0 {
                let sum: i64 = (lo - d..=top + d).map(|k| px(k) as i64).sum();
                sum as f64 / (top + 2 * d + 1 - lo) as f64
            } else {
                0.0
            };
            self.column_brightness[j] = mean;
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
}
