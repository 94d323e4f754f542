//! The edge threshold that follows each frame's own noise and light (beyond the paper, issue
//! 13): the paper's region nearest the robot is floor, so the box filter's response there is
//! what the floor's texture and the camera's noise look like to the filter in this frame. Its
//! robust spread sets the threshold: `max(threshold, noise_multiple x sigma)`.
//!
//! sigma is 1.4826 x the median absolute deviation (the standard deviation for Gaussian noise;
//! half the samples may be an edge or an obstacle without moving it much) of the raw response
//! S over the near-floor band of every sampled column, divided by 2d (R = S / 2d). Gain scales
//! the texture, the edges and sigma alike, so dim and bright frames of one scene get the same
//! edges at the same multiple.

/// Rows of the near-floor band, as a fraction of the image height, counted up from each
/// column's first tested row; at least 4d + 1 rows, so that one edge in the band (a bumper, a
/// wall at the robot's feet), which moves the response over 2d rows, stays a minority of it. 12 % is the band of the label-free
/// threshold that `floorscan tune` reports (chosen there on the simulated carpet corridor):
/// at the simulated camera's tilt, the floor within about 0.5 m of the robot.
pub const NEAR_BAND_FRACTION: f64 = 0.12;

/// Most columns the noise is pooled over: with more sampled columns, every s-th scannable one
/// (s = ceil(scannable / 64)), so dense scans cost no more than the default 64 columns here
/// (64 x ~30 rows is ~2000 samples: the median absolute deviation within a few percent).
pub const NOISE_COLUMNS: usize = 64;

/// Rows of the near-floor band for an image `height` rows high and half-width `d`.
pub fn near_band_rows(height: usize, d: usize) -> usize {
    ((NEAR_BAND_FRACTION * height as f64).round() as usize).max(4 * d + 1)
}

/// 1.4826 x the median absolute deviation of `values` (reordered in place, no allocation);
/// `None` for no values.
pub fn robust_sigma(values: &mut [i32]) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mid = values.len() / 2;
    let median = *values.select_nth_unstable(mid).1;
    for v in values.iter_mut() {
        *v = (*v - median).abs();
    }
    let mad = *values.select_nth_unstable(mid).1;
    Some(1.4826 * mad as f64)
}

/// Largest span of sample values [`robust_sigma_counted`] counts in its histogram; wider
/// spans (16-bit images with strong edges in the band) fall back to [`robust_sigma`].
pub const MAX_HISTOGRAM_SPAN: usize = 1 << 14;

/// [`robust_sigma`] by counting: the median and the median absolute deviation read off a
/// histogram of the values (`histogram`, at least [`MAX_HISTOGRAM_SPAN`] long, is scratch
/// space; only the span the values cover is cleared). The same result as [`robust_sigma`],
/// in time linear in the values and their span rather than two selections.
pub fn robust_sigma_counted(values: &mut [i32], histogram: &mut [u32]) -> Option<f64> {
    let (&lo, &hi) = (values.iter().min()?, values.iter().max()?);
    let span = (hi as i64 - lo as i64 + 1) as usize;
    if span > MAX_HISTOGRAM_SPAN || span > histogram.len() {
        return robust_sigma(values);
    }
    let h = &mut histogram[..span];
    h.fill(0);
    for &v in values.iter() {
        h[(v - lo) as usize] += 1;
    }
    // the (n / 2)-th smallest value, 0-based, as select_nth_unstable(n / 2) picks it
    let mid = values.len() / 2;
    let mut seen = 0usize;
    let mut m = 0usize;
    for (k, &c) in h.iter().enumerate() {
        seen += c as usize;
        if seen > mid {
            m = k;
            break;
        }
    }
    // the smallest r with more than `mid` values within r of the median
    let mut within = h[m] as usize;
    let mut r = 0usize;
    while within <= mid {
        r += 1;
        if m >= r {
            within += h[m - r] as usize;
        }
        if m + r < span {
            within += h[m + r] as usize;
        }
    }
    Some(1.4826 * r as f64)
}

#[cfg(test)]
#[path = "noise_threshold_tests.rs"]
mod tests;
