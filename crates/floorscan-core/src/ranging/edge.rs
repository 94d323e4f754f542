//! The paper's one-dimensional box edge filter (eq. 1-2) and its incremental form.
//!
//! A column is indexed by `k`, counting pixels *from the bottom of the image* (k = 0 is the
//! bottom row), because the filter walks up from the robot. With half-width d, the raw response
//!
//! ```text
//! S(k) = sum_{i=1..d} I(k+i) - sum_{i=1..d} I(k-i)        (= 2d R(k), eq. 1 with eq. 2)
//! ```
//!
//! is the sum of the d pixels above k minus the sum of the d pixels below it; the centre pixel
//! has weight 0. Moving up one row, the window above loses I(k+1) and gains I(k+d+1), the window
//! below loses I(k-d) and gains I(k):
//!
//! ```text
//! S(k+1) = S(k) + I(k+d+1) - I(k+1) - I(k) + I(k-d)
//! R(k+1) = R(k) + (1/2d) [ I(k+d+1) - I(k+1) - I(k) + I(k-d) ]
//! ```
//!
//! (The paper prints `R(n+1) = R(n) - (1/2d){I(n) - I(n+1) + I(n-d) + I(n+d+1)}`, whose signs
//! on I(n+1) and I(n-d) do not follow from eq. 1-2.) Integer sums are exact, so the incremental
//! and direct responses are equal at every row; the threshold test `|R| > T` becomes
//! `|S| > floor(2d T)`.

use serde::{Deserialize, Serialize};

/// How the boundary row is placed once the response first crosses the threshold.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum Refinement {
    /// The paper: the first row whose response exceeds the threshold. Its position depends on
    /// the edge's contrast (a strong edge crosses earlier on its ramp).
    FirstCrossing,
    /// The local maximum of |R| within the next d rows (the centre of a plateau of equal maxima).
    Peak,
    /// As `Peak`, then a parabola through the peak and its two neighbours, for a sub-pixel row.
    SubPixel,
    /// As `SubPixel`, then the sharpest one-pixel step of the edge's sign within d/2 rows of
    /// that peak (a parabola through the step differences for a sub-pixel row), or further up
    /// while the column keeps changing with that sign ([`ramp_above`], at most
    /// [`RAMP_ROWS_PER_HALF_WIDTH`] x d rows). The box filter's peak is the centre of mass of
    /// every change inside its 2d window: a thin strip above the base (a dark baseboard, a
    /// shadow line) pulls it towards the robot, and a contact shadow, darkening the floor
    /// ever faster towards the base, makes the filter cross where the shadow starts; the
    /// sharpest step is where the intensity changes, the obstacle's base.
    #[default]
    Step,
}

/// Raw response S(k) by the direct sum of eq. (1). Needs `d <= k` and `k + d < column.len()`.
pub fn direct_response(column: &[i32], k: usize, half_width: usize) -> i32 {
    let above: i32 = column[k + 1..=k + half_width].iter().sum();
    let below: i32 = column[k - half_width..k].iter().sum();
    above - below
}

/// S(k) of image column `u` by the direct sum, k counted from the bottom row.
pub fn direct_response_at<P: crate::image::Pixel>(
    image: &crate::image::ImageView<P>,
    u: usize,
    k: usize,
    half_width: usize,
) -> i32 {
    let bottom = image.height() - 1;
    let above: i32 = (1..=half_width)
        .map(|i| image.get(u, bottom - (k + i)).to_i32())
        .sum();
    let below: i32 = (1..=half_width)
        .map(|i| image.get(u, bottom - (k - i)).to_i32())
        .sum();
    above - below
}

/// S(k+1) from S(k) and the four pixels the window moves over.
#[inline(always)]
pub fn next_response(
    s_k: i32,
    i_k_minus_d: i32,
    i_k: i32,
    i_k_plus_1: i32,
    i_k_plus_d_plus_1: i32,
) -> i32 {
    s_k + i_k_plus_d_plus_1 - i_k_plus_1 - i_k + i_k_minus_d
}

/// The threshold on the raw sum: `|S| > threshold_sum` iff `|R| > threshold` (S integer).
pub fn threshold_to_sum(threshold: f64, half_width: usize) -> i32 {
    let t = (2.0 * half_width as f64 * threshold).floor();
    t.clamp(-1.0, i32::MAX as f64) as i32
}

/// The located peak of |S| after a crossing, in column coordinates (k from the bottom).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// Continuous position; a plateau of equal maxima gives its centre.
    pub k: f64,
}

/// Finds the boundary position after the response first crossed the threshold at `k_cross`.
///
/// `response(k)` gives S(k) for any k in `k_min..=k_max` (the rows where the filter window lies
/// inside the column). The climb goes at most d rows up while |S| does not decrease.
pub fn refine_crossing(
    refinement: Refinement,
    k_cross: usize,
    half_width: usize,
    k_min: usize,
    k_max: usize,
    mut response: impl FnMut(usize) -> i32,
) -> Peak {
    if refinement == Refinement::FirstCrossing {
        return Peak { k: k_cross as f64 };
    }
    let s0 = response(k_cross);
    let sign = if s0 >= 0 { 1 } else { -1 };
    let mag = |s: i32| sign * s;
    let climb_limit = (k_cross + half_width).min(k_max);
    let mut k_top = k_cross;
    let mut best = mag(s0);
    let mut k_plateau_start = k_cross;
    while k_top < climb_limit {
        let next = mag(response(k_top + 1));
        if next < best {
            break;
        }
        if next > best {
            k_plateau_start = k_top + 1;
            best = next;
        }
        k_top += 1;
    }
    // Every row from k_plateau_start to k_top holds the maximum (the climb stops before a drop).
    let k_end = k_top;
    let centre = (k_plateau_start + k_end) as f64 / 2.0;
    if refinement == Refinement::Peak || k_end != k_plateau_start {
        return Peak { k: centre };
    }
    let k = k_plateau_start;
    if k <= k_min || k >= k_max {
        return Peak { k: centre };
    }
    let (a, b, c) = (
        mag(response(k - 1)) as f64,
        best as f64,
        mag(response(k + 1)) as f64,
    );
    let denom = a - 2.0 * b + c;
    if denom >= 0.0 {
        return Peak { k: centre };
    }
    let offset = (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
    Peak {
        k: k as f64 + offset,
    }
}

/// How far (in rows, per row of the box filter's half width d) the step refinement follows a
/// ramp above its window: a 4 cm contact shadow spans 8-16 rows of a 320 x 240 image at
/// 0.4-0.8 m, and d is 4 by default.
pub const RAMP_ROWS_PER_HALF_WIDTH: usize = 4;

/// Rows above the step window's top (`k_peak + radius`) along which the column keeps changing
/// with sign `sign`: a ramp, such as a contact shadow darkening the floor towards an
/// obstacle's base, whose sharpest step (the base) lies above the window. From the window's
/// last pixel pair up, while `sign * (I(j + 2) - I(j)) > 0` (pixels two rows apart, so that
/// one noisy pixel does not end it), at most `cap` rows, reading pixels up to `j_top`.
/// `pixel(j)` is I(j), k counted from the bottom. 0 where the column stops changing.
pub fn ramp_above(
    k_peak: f64,
    radius: f64,
    sign: i32,
    cap: usize,
    j_top: usize,
    mut pixel: impl FnMut(usize) -> i32,
) -> usize {
    let start = (k_peak + radius - 0.5).floor();
    if start.is_nan() || start < 0.0 {
        return 0;
    }
    let mut j = start as usize;
    let mut n = 0;
    while n < cap && j + 2 <= j_top && sign * (pixel(j + 2) - pixel(j)) > 0 {
        j += 1;
        n += 1;
    }
    n
}

/// The sharpest step of sign `sign` near the box filter's peak `k_peak`: over the pixel pairs
/// (j, j + 1) with `j_min <= j < j_max` whose edge line j + 0.5 lies from `radius` rows below
/// `k_peak` to `radius` + `above` rows above it, the largest `sign * (I(j + 1) - I(j))`,
/// placed by a parabola through its two neighbours. `pixel(j)` is I(j), k counted from the
/// bottom. `k_peak` when no step of that sign is there.
pub fn sharpest_step(
    k_peak: f64,
    sign: i32,
    radius: f64,
    above: usize,
    j_min: usize,
    j_max: usize,
    mut pixel: impl FnMut(usize) -> i32,
) -> f64 {
    let first = (k_peak - radius - 0.5).ceil().max(j_min as f64) as usize;
    let last = ((k_peak + radius - 0.5).floor() as usize + above).min(j_max.saturating_sub(1));
    if j_max == 0 || last < first {
        return k_peak;
    }
    let step = |j: usize, pixel: &mut dyn FnMut(usize) -> i32| sign * (pixel(j + 1) - pixel(j));
    let (mut best_j, mut best) = (first, i32::MIN);
    for j in first..=last {
        let g = step(j, &mut pixel);
        if g > best {
            (best_j, best) = (j, g);
        }
    }
    if best <= 0 {
        return k_peak;
    }
    let mut k = best_j as f64 + 0.5;
    // Neighbouring steps (inside the pixels that exist) for the parabola.
    if best_j > j_min && best_j + 1 < j_max {
        let (a, c) = (
            step(best_j - 1, &mut pixel) as f64,
            step(best_j + 1, &mut pixel) as f64,
        );
        let b = best as f64;
        let denom = a - 2.0 * b + c;
        if denom < 0.0 {
            k += (0.5 * (a - c) / denom).clamp(-0.5, 0.5);
        }
    }
    k
}

#[cfg(test)]
#[path = "edge_tests.rs"]
mod tests;
