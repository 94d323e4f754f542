//! The search of a correlative scan matcher (Olson 2009; cartographer's real-time correlative
//! scan matcher): every pose of a window around a prior, scored by the mean of a likelihood
//! field at the scan's points, times a prior that keeps the pose near the prior where the scan
//! does not decide.
//!
//! Translations move whole field cells; yaws go in fixed steps. The likelihood field (values
//! in [0, 1], row major, row 0 = lowest y) is the caller's: [`crate::scan_matcher`] builds it from the
//! distance to the nearest stored hit.

use crate::error::{invalid_option, Error, Result};
use crate::pose::Pose2;

/// The search window and the prior.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchWindow {
    /// Translations tried: -steps..=steps cells in x and in y.
    pub xy_steps: u32,
    /// Yaws tried: -yaw_steps..=yaw_steps times `yaw_step_rad`.
    pub yaw_steps: u32,
    /// Yaw step [rad], > 0.
    pub yaw_step_rad: f64,
    /// Width of the translation prior [m], > 0: exp(-(|t| / prior_xy_m)^2).
    pub prior_xy_m: f64,
    /// Width of the rotation prior [rad], > 0: exp(-(dyaw / prior_yaw_rad)^2).
    pub prior_yaw_rad: f64,
}

/// The best pose of a search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SearchResult {
    /// The pose found (world_from_robot).
    pub pose: Pose2,
    /// Mean field value at the points there, in [0, 1].
    pub mean: f64,
    /// `mean` times the prior: what the search maximised.
    pub score: f64,
}

/// The largest window a search runs (candidates x points), a bound on the work an argument can
/// ask for.
pub const MAX_EVALUATIONS: u64 = 1 << 32;

/// The largest field plus a border of twice the translation window on each side [cells] a
/// search runs over (16 M): with [`MAX_EVALUATIONS`], bounds the window (and its sums) an
/// argument can ask for.
pub const MAX_PADDED_CELLS: u64 = 1 << 24;

/// A likelihood field: `width` x `height` values, its cell (0, 0)'s lower-left corner at
/// `origin_m` [m], cells `cell_m` [m] wide.
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    pub values: &'a [f32],
    pub width: usize,
    pub height: usize,
    pub origin_m: (f64, f64),
    pub cell_m: f64,
}

impl Field<'_> {
    /// Its values fill `width` x `height`, its cells have a finite positive size.
    pub fn validate(&self) -> Result<()> {
        if self.values.len() != self.width * self.height {
            return Err(Error::LengthMismatch(format!(
                "field {} x {} needs {} values, got {}",
                self.width,
                self.height,
                self.width * self.height,
                self.values.len()
            )));
        }
        if !(self.cell_m.is_finite() && self.cell_m > 0.0) {
            return Err(invalid_option("cell_m", "must be > 0"));
        }
        Ok(())
    }
}

/// The best pose for `points` (robot frame [m]) in `window` around `prior`; points off the
/// field score 0.
pub fn search(
    field: &Field<'_>,
    points: &[[f64; 2]],
    prior: Pose2,
    window: &SearchWindow,
) -> Result<SearchResult> {
    field.validate()?;
    for (name, v) in [
        ("yaw_step_rad", window.yaw_step_rad),
        ("prior_xy_m", window.prior_xy_m),
        ("prior_yaw_rad", window.prior_yaw_rad),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(invalid_option(name, format!("must be > 0, got {v}")));
        }
    }
    let side = 2 * window.xy_steps as u64 + 1;
    let work = side
        .saturating_mul(side)
        .saturating_mul(2 * window.yaw_steps as u64 + 1)
        .saturating_mul(points.len() as u64);
    if work > MAX_EVALUATIONS {
        return Err(invalid_option(
            "window",
            format!("{work} evaluations > {MAX_EVALUATIONS}"),
        ));
    }
    let border = 4 * window.xy_steps as u64;
    let padded = (field.width as u64)
        .saturating_add(border)
        .saturating_mul((field.height as u64).saturating_add(border));
    if padded > MAX_PADDED_CELLS {
        return Err(invalid_option(
            "window",
            format!("field and window need {padded} cells > {MAX_PADDED_CELLS}"),
        ));
    }
    if !(prior.x.is_finite() && prior.y.is_finite() && prior.yaw.is_finite()) {
        return Err(Error::InvalidGeometry("prior pose not finite".into()));
    }
    let mut best = SearchResult {
        pose: prior,
        mean: 0.0,
        score: -1.0,
    };
    if points.is_empty() {
        best.score = 0.0;
        return Ok(best);
    }
    let s = window.xy_steps as i64;
    let side = (2 * s + 1) as usize;
    let (w, h) = (field.width as i64, field.height as i64);
    // the sums of every shift of one yaw, filled point by point (each shift's sum still adds
    // the points in their order, so the sums are those of a loop over shifts); a shift that
    // moves a point off the field reads 0 there, a point that no shift brings onto the
    // field is left out of the sums (not of the mean)
    let mut sums = vec![0.0f64; side * side];
    // the translation prior of every shift, the same for every yaw
    let mut xy_prior = Vec::with_capacity(side * side);
    for ty in -s..=s {
        for tx in -s..=s {
            let t = ((tx * tx + ty * ty) as f64).sqrt() * field.cell_m;
            xy_prior.push((-(t / window.prior_xy_m).powi(2)).exp());
        }
    }
    // per point of one yaw: its cell, and whether every shift's chunk reads inside the field
    let mut cells: Vec<(i64, i64, bool)> = Vec::with_capacity(points.len());
    let inv_n = 1.0 / points.len() as f64;
    for ky in -(window.yaw_steps as i64)..=(window.yaw_steps as i64) {
        let dyaw = ky as f64 * window.yaw_step_rad;
        let yaw = prior.yaw + dyaw;
        let (sn, cs) = yaw.sin_cos();
        cells.clear();
        for p in points {
            let wx = prior.x + cs * p[0] - sn * p[1];
            let wy = prior.y + sn * p[0] + cs * p[1];
            let fi = floor((wx - field.origin_m.0) / field.cell_m);
            let fj = floor((wy - field.origin_m.1) / field.cell_m);
            let reach = |f: f64, n: i64| f >= -(s as f64) && f < (n + s) as f64;
            if reach(fi, w) && reach(fj, h) {
                let (i, j) = (fi as i64, fj as i64);
                let inside = i - s >= 0 && j - s >= 0 && i + s + CHUNK as i64 <= w && j + s < h;
                cells.push((i, j, inside));
            }
        }
        window_sums(field, &cells, s, &mut sums);
        let yaw_prior = (-(dyaw / window.prior_yaw_rad).powi(2)).exp();
        for ty in -s..=s {
            for tx in -s..=s {
                let k = (ty + s) as usize * side + (tx + s) as usize;
                let mean = sums[k] * inv_n;
                let score = mean * xy_prior[k] * yaw_prior;
                if score > best.score {
                    best = SearchResult {
                        pose: Pose2::new(
                            prior.x + tx as f64 * field.cell_m,
                            prior.y + ty as f64 * field.cell_m,
                            yaw,
                        ),
                        mean,
                        score,
                    };
                }
            }
        }
    }
    Ok(best)
}

/// `x.floor()` without a call into libm (the baseline x86-64 target has no rounding
/// instruction): the same value for every finite `x` below 2^52 in magnitude, `floor` beyond.
#[inline]
fn floor(x: f64) -> f64 {
    if x.abs() < 4.0e15 {
        let t = x as i64 as f64;
        if t > x {
            t - 1.0
        } else {
            t
        }
    } else {
        x.floor()
    }
}

/// Shifts summed at once per point (kept in registers).
const CHUNK: usize = 16;

/// The sums of the field at every shift of the window (rows of `2 s + 1` shifts, row major) for
/// the points in `cells` (their cells; `inside`: every chunk of shifts reads inside the field),
/// each sum adding the points in their order; a shift that moves a point off the field reads
/// 0 there (and adds it).
///
/// AVX2 (chosen at run time where the CPU has it) adds four sums per instruction instead of
/// two; the additions, and so the sums, are the same.
fn window_sums(field: &Field<'_>, cells: &[(i64, i64, bool)], s: i64, sums: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the CPU has AVX2 (checked just above)
        unsafe { window_sums_avx2(field, cells, s, sums) };
        return;
    }
    window_sums_body(field, cells, s, sums);
}

/// [`window_sums`] compiled for AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn window_sums_avx2(
    field: &Field<'_>,
    cells: &[(i64, i64, bool)],
    s: i64,
    sums: &mut [f64],
) {
    window_sums_body(field, cells, s, sums);
}

#[inline(always)]
fn window_sums_body(field: &Field<'_>, cells: &[(i64, i64, bool)], s: i64, sums: &mut [f64]) {
    let side = (2 * s + 1) as usize;
    let (w, h) = (field.width as i64, field.height as i64);
    for row in 0..side {
        let dj = row as i64 - s;
        for col0 in (0..side).step_by(CHUNK) {
            let di0 = col0 as i64 - s;
            let mut acc = [0.0f64; CHUNK];
            for &(i, j, inside) in cells {
                let at = (j + dj) * w + i + di0;
                let values: [f32; CHUNK] = if inside {
                    field.values[at as usize..at as usize + CHUNK]
                        .try_into()
                        .unwrap_or([0.0; CHUNK])
                } else {
                    // off the field reads 0 (as the zero border the search once padded with)
                    let jj = j + dj;
                    std::array::from_fn(|k| {
                        let ii = i + di0 + k as i64;
                        if jj >= 0 && jj < h && ii >= 0 && ii < w {
                            field.values[(jj * w + ii) as usize]
                        } else {
                            0.0
                        }
                    })
                };
                for (a, v) in acc.iter_mut().zip(values) {
                    *a += v as f64;
                }
            }
            let len = CHUNK.min(side - col0);
            sums[row * side + col0..row * side + col0 + len].copy_from_slice(&acc[..len]);
        }
    }
}

/// The field read bilinearly between cell centres at world point (x, y) [m]; 0 off the field.
fn bilinear(field: &Field<'_>, x: f64, y: f64) -> f64 {
    let fx = (x - field.origin_m.0) / field.cell_m - 0.5;
    let fy = (y - field.origin_m.1) / field.cell_m - 0.5;
    if !(fx.is_finite() && fy.is_finite()) || fx.abs() > 1e12 || fy.abs() > 1e12 {
        return 0.0;
    }
    let (i0, j0) = (floor(fx) as i64, floor(fy) as i64);
    let (ax, ay) = (fx - i0 as f64, fy - j0 as f64);
    let at = |i: i64, j: i64| -> f64 {
        if i >= 0 && j >= 0 && i < field.width as i64 && j < field.height as i64 {
            field.values[j as usize * field.width + i as usize] as f64
        } else {
            0.0
        }
    };
    (1.0 - ax) * (1.0 - ay) * at(i0, j0)
        + ax * (1.0 - ay) * at(i0 + 1, j0)
        + (1.0 - ax) * ay * at(i0, j0 + 1)
        + ax * ay * at(i0 + 1, j0 + 1)
}

/// (score, mean) of `points` at `pose`, the field read bilinearly, the prior as in [`search`].
fn smooth_score(
    field: &Field<'_>,
    points: &[[f64; 2]],
    pose: Pose2,
    prior: Pose2,
    window: &SearchWindow,
) -> (f64, f64) {
    let (sn, cs) = pose.yaw.sin_cos();
    let sum: f64 = points
        .iter()
        .map(|p| {
            bilinear(
                field,
                pose.x + cs * p[0] - sn * p[1],
                pose.y + sn * p[0] + cs * p[1],
            )
        })
        .sum();
    let mean = sum / points.len().max(1) as f64;
    let t = (pose.x - prior.x).hypot(pose.y - prior.y);
    let dyaw = pose.yaw - prior.yaw;
    let score =
        mean * (-(t / window.prior_xy_m).powi(2) - (dyaw / window.prior_yaw_rad).powi(2)).exp();
    (score, mean)
}

/// Sub-cell refinement of a search's pose (the search moves whole cells and yaw steps, so a
/// correction under half a cell is never made): the field read bilinearly, per axis the vertex
/// of the parabola through the score at -h, 0, +h, kept when it scores higher; h from half a
/// cell (half a yaw step) down, halved for each of three rounds.
pub fn refine(
    field: &Field<'_>,
    points: &[[f64; 2]],
    found: Pose2,
    prior: Pose2,
    window: &SearchWindow,
) -> SearchResult {
    let (mut best, mut mean) = smooth_score(field, points, found, prior, window);
    let mut pose = [found.x, found.y, found.yaw];
    let (mut hx, mut hyaw) = (0.5 * field.cell_m, 0.5 * window.yaw_step_rad);
    let at = |p: [f64; 3]| Pose2 {
        x: p[0],
        y: p[1],
        yaw: p[2],
    };
    for _ in 0..3 {
        for (axis, h) in [(0, hx), (1, hx), (2, hyaw)] {
            let (mut lo, mut hi) = (pose, pose);
            lo[axis] -= h;
            hi[axis] += h;
            let (a, _) = smooth_score(field, points, at(lo), prior, window);
            let (b, _) = smooth_score(field, points, at(hi), prior, window);
            let den = a - 2.0 * best + b;
            if den >= 0.0 || !den.is_finite() {
                continue;
            }
            let mut trial = pose;
            trial[axis] += (0.5 * (a - b) / den).clamp(-1.0, 1.0) * h;
            let (sc, m) = smooth_score(field, points, at(trial), prior, window);
            if sc > best {
                pose = trial;
                best = sc;
                mean = m;
            }
        }
        hx *= 0.5;
        hyaw *= 0.5;
    }
    SearchResult {
        pose: at(pose),
        mean,
        score: best,
    }
}

#[cfg(test)]
#[path = "correlative_search_tests.rs"]
mod tests;
