//! The floor warp between two frames: the odometry's motion refined by Lucas-Kanade on the
//! near floor, the floor's residual noise after it, and the image helpers they read through
//! (Gaussian blur, bilinear reads, gradients, a 3 x 3 solve).

use super::*;

impl FloorParallax {
    /// Lucas-Kanade on the near floor: a left correction of `motion` (earlier from current)
    /// that aligns the two frames' floor.
    pub(super) fn refine_motion(&mut self, earlier: &[f32], motion: Pose2) -> Pose2 {
        let mut m = motion;
        // the floor's texture moves with it: a pixel flat in this frame is flat there, and
        // takes no part (the band's pixels that do, found once for the iterations)
        self.textured.clear();
        for (i, &(u, v, _)) in self.band.iter().enumerate() {
            let (cu, cv) = gradient(&self.current, self.width, self.height, u, v);
            // (the blurred frame is finite: the complement of the old `< min` test)
            if cu.hypot(cv) >= REFINE_MIN_GRADIENT {
                self.textured.push(i);
            }
        }
        for _ in 0..REFINE_ITERATIONS {
            let (mut a, mut b, mut n) = ([[0.0f64; 3]; 3], [0.0f64; 3], 0usize);
            for &i in &self.textured {
                let (u, v, g) = self.band[i];
                let gp = m.transform_point(g);
                let Some((pu, pv)) = self.table.pixel_of(gp, self.band_guess[i]) else {
                    continue;
                };
                self.band_guess[i] = (pu, pv);
                let Some((_, [ja, jb, jc, jd])) = self.table.jacobian(pu, pv) else {
                    continue;
                };
                let det = ja * jd - jb * jc;
                let (gx, gy) = gradient(earlier, self.width, self.height, pu, pv);
                if det.abs() < 1e-15 || gx.hypot(gy) < REFINE_MIN_GRADIENT {
                    continue;
                }
                let (gx, gy) = (gx as f64, gy as f64);
                let dix = (gx * jd - gy * jc) / det;
                let diy = (-gx * jb + gy * ja) / det;
                let jrow = [dix, diy, -dix * gp.y + diy * gp.x];
                let r = self.current[v as usize * self.width + u as usize] as f64
                    - bilinear(earlier, self.width, self.height, pu, pv) as f64;
                let w = 1.0 / (r.abs() / 10.0).max(1.0);
                for p in 0..3 {
                    b[p] += w * jrow[p] * r;
                    for q in 0..3 {
                        a[p][q] += w * jrow[p] * jrow[q];
                    }
                }
                n += 1;
            }
            if n < 50 {
                return motion;
            }
            let Some(delta) = solve3(a, b) else {
                return m;
            };
            m = Pose2::new(delta[0], delta[1], delta[2]).compose(&m);
            if delta.iter().all(|d| d.abs() < 1e-4) {
                break;
            }
        }
        m
    }

    /// Robust sigma (1.4826 x the median absolute deviation) of the near floor's residual
    /// after the warp [grey levels].
    pub(super) fn floor_noise(&mut self, earlier: &[f32], motion: &Pose2) -> f64 {
        self.residuals.clear();
        for (i, &(u, v, g)) in self.band.iter().enumerate() {
            if let Some((pu, pv)) = self
                .table
                .pixel_of(motion.transform_point(g), self.band_guess[i])
            {
                self.residuals.push(
                    self.current[v as usize * self.width + u as usize]
                        - bilinear(earlier, self.width, self.height, pu, pv),
                );
            }
        }
        let n = self.residuals.len();
        if n == 0 {
            return 0.0;
        }
        let median = |xs: &mut Vec<f32>| {
            let mid = xs.len() / 2;
            *xs.select_nth_unstable_by(mid, |a, b| a.total_cmp(b)).1
        };
        let m = median(&mut self.residuals);
        for r in self.residuals.iter_mut() {
            *r = (*r - m).abs();
        }
        1.4826 * median(&mut self.residuals) as f64
    }
}

/// Gaussian kernel of `sigma` px (radius 3 sigma), normalised; `[1]` for sigma 0.
pub(super) fn gaussian_kernel(sigma: f64) -> Vec<f32> {
    if sigma <= 0.0 {
        return vec![1.0];
    }
    let r = (3.0 * sigma).ceil() as i64;
    let k: Vec<f64> = (-r..=r)
        .map(|i| (-(i * i) as f64 / (2.0 * sigma * sigma)).exp())
        .collect();
    let total: f64 = k.iter().sum();
    k.iter().map(|x| (x / total) as f32).collect()
}

/// Separable blur of `image` into `out` (edges clamped), through `scratch`. Each sum adds the
/// kernel's taps in order (a tap at a time over a whole row, so the additions vectorise and
/// the sums are those of a pixel-by-pixel loop).
pub(super) fn blur_into<P: Pixel>(
    image: &ImageView<P>,
    kernel: &[f32],
    scratch: &mut [f32],
    out: &mut [f32],
) {
    let (w, h) = (image.width(), image.height());
    let r = (kernel.len() / 2) as i64;
    for v in 0..h {
        // the row as floats, in `out`'s row (rewritten by the second pass)
        let row = &mut out[v * w..(v + 1) * w];
        for (u, x) in row.iter_mut().enumerate() {
            *x = image.get(u, v).to_i32() as f32;
        }
        let acc = &mut scratch[v * w..(v + 1) * w];
        acc.fill(0.0);
        for (t, &k) in kernel.iter().enumerate() {
            let d = t as i64 - r;
            // u + d clamped to the row: the first `lo` pixels read its first, the last ones
            // from `hi` on its last
            let lo = (-d).clamp(0, w as i64) as usize;
            let hi = (w as i64 - d).clamp(lo as i64, w as i64) as usize;
            for a in &mut acc[..lo] {
                *a += k * row[0];
            }
            if hi > lo {
                let src = (lo as i64 + d) as usize;
                for (a, &x) in acc[lo..hi].iter_mut().zip(&row[src..src + (hi - lo)]) {
                    *a += k * x;
                }
            }
            for a in &mut acc[hi..] {
                *a += k * row[w - 1];
            }
        }
    }
    for v in 0..h {
        let acc = &mut out[v * w..(v + 1) * w];
        acc.fill(0.0);
        for (t, &k) in kernel.iter().enumerate() {
            let vv = (v as i64 + t as i64 - r).clamp(0, h as i64 - 1) as usize;
            for (a, &x) in acc.iter_mut().zip(&scratch[vv * w..(vv + 1) * w]) {
                *a += k * x;
            }
        }
    }
}

/// Bilinear sample of a (w, h) image at (u, v), clamped to the image.
pub(super) fn bilinear(img: &[f32], w: usize, h: usize, u: f64, v: f64) -> f32 {
    let u = u.clamp(0.0, (w - 1) as f64 - 1e-6);
    let v = v.clamp(0.0, (h - 1) as f64 - 1e-6);
    // u, v >= 0 (or NaN, which both cast to 0): truncation is floor, without a call into
    // libm (the baseline x86-64 target has no rounding instruction)
    let (u0, v0) = (u as usize, v as usize);
    let (fu, fv) = ((u - u0 as f64) as f32, (v - v0 as f64) as f32);
    let (u1, v1) = ((u0 + 1).min(w - 1), (v0 + 1).min(h - 1));
    let p = |uu: usize, vv: usize| img[vv * w + uu];
    p(u0, v0) * (1.0 - fu) * (1.0 - fv)
        + p(u1, v0) * fu * (1.0 - fv)
        + p(u0, v1) * (1.0 - fu) * fv
        + p(u1, v1) * fu * fv
}

/// Columns read around a tested column by [`column_reads`].
pub(super) const READ_COLUMNS: usize = 5;

/// The image around a patch of `rows` rows above `row` in column `u` (an integer), read once
/// for the patch's readings and their central differences: `out[i * READ_COLUMNS + k]` is
/// [`bilinear`] at (u + k - 2, row - i) for i in 0..=rows + 1 (the patch's rows, and one beyond
/// each end) and k in 0..5. A patch pixel (u + du, row - i) reads `out[i * 5 + 2 + du]`, and its
/// [`gradient`] the reads either side: the same coordinates, so the same floats (row - i + 1 is
/// row - (i - 1) exactly).
pub(super) fn column_reads(
    img: &[f32],
    w: usize,
    h: usize,
    u: f64,
    row: f64,
    rows: usize,
    out: &mut Vec<f32>,
) {
    out.clear();
    for i in 0..=rows + 1 {
        let pv = row - i as f64;
        for k in 0..READ_COLUMNS {
            out.push(bilinear(img, w, h, u + k as f64 - 2.0, pv));
        }
    }
}

/// Central-difference gradient (d/du, d/dv) of the image at (u, v).
pub(super) fn gradient(img: &[f32], w: usize, h: usize, u: f64, v: f64) -> (f32, f32) {
    (
        (bilinear(img, w, h, u + 1.0, v) - bilinear(img, w, h, u - 1.0, v)) / 2.0,
        (bilinear(img, w, h, u, v + 1.0) - bilinear(img, w, h, u, v - 1.0)) / 2.0,
    )
}

/// Solves the 3 x 3 system a x = b (Cramer's rule); `None` when it is singular.
pub(super) fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let d = det(a);
    let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
    if !(d.is_finite() && d.abs() > 1e-12 * scale.powi(3)) {
        return None;
    }
    let mut x = [0.0; 3];
    for (c, xc) in x.iter_mut().enumerate() {
        let mut m = a;
        for r in 0..3 {
            m[r][c] = b[r];
        }
        *xc = det(m) / d;
    }
    Some(x)
}
