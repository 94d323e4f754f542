//! The cue's evidence at a boundary: the rows above it explained as floor and as a surface
//! standing at the boundary (their log-likelihood ratio), the base line the neighbouring
//! boundaries draw, and the search above a vetoed boundary with no edge.

use super::warp::{column_reads, READ_COLUMNS};
use super::*;

impl FloorParallax {
    /// Columns whose last vetoed boundary has no edge above it: the first row above it, in
    /// steps of a quarter of the test's rows, whose rows above move as a surface standing
    /// there becomes the boundary. Returns how many columns got one.
    pub(super) fn search_above_vetoed(
        &mut self,
        earlier: &[f32],
        motion: &Pose2,
        noise: f64,
        out: &mut Scan,
    ) -> usize {
        let rows = ((self.options.rows_above_fraction * self.height as f64).round()).max(4.0);
        let step = (rows / 4.0).round().max(1.0);
        let mut found = 0;
        for j in 0..out.readings.len() {
            let Some(vetoed_row) = self.last_vetoed[j] else {
                continue;
            };
            let ColumnOutcome::NoBoundary { top_row, .. } = out.readings[j].outcome else {
                continue;
            };
            let u = out.readings[j].column as f64;
            let mut row = vetoed_row - step;
            while row >= top_row.max(rows) {
                if let Some(point) = self.table.lookup(u, row) {
                    let llr =
                        self.log_likelihood_ratio(earlier, motion, noise, u, row, point, &[None]);
                    if llr < -self.options.min_standing_log_likelihood_ratio {
                        let footprint_m = self
                            .table
                            .lookup(u, row - 1.0)
                            .map_or(0.0, |above| (above.x - point.x).hypot(above.y - point.y));
                        out.readings[j].outcome = ColumnOutcome::Boundary {
                            row,
                            point,
                            footprint_m,
                        };
                        out.readings[j].confidence = (-llr / (1.0 - llr)) as f32;
                        found += 1;
                        break;
                    }
                }
                row -= step;
            }
        }
        found
    }

    /// log p(rows above | floor) - log p(rows above | standing at the boundary), Gaussian
    /// residuals of `noise`, for the standing surface that explains them best of those along
    /// `directions` on the floor (`None`: facing the camera); 0 where the rows cannot tell (no
    /// texture, not seen before). The search ends at the first direction that leaves the ratio
    /// below both `min_log_likelihood_ratio` and 0 (no veto, and the motion shows standing:
    /// the memory's cell is cleared); a direction that cannot tell does not end it.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn log_likelihood_ratio(
        &mut self,
        earlier: &[f32],
        motion: &Pose2,
        noise: f64,
        u: f64,
        row: f64,
        base: Point2,
        directions: &[Option<Point2>],
    ) -> f64 {
        let rows =
            ((self.options.rows_above_fraction * self.height as f64).round() as usize).max(4);
        if row < rows as f64 || u < 1.0 || u > (self.width - 2) as f64 {
            return 0.0;
        }
        column_reads(
            &self.current,
            self.width,
            self.height,
            u,
            row,
            rows,
            &mut self.reads,
        );
        let read = |i: usize, k: usize| self.reads[i * READ_COLUMNS + k];
        self.patch.clear();
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for i in 1..=rows {
            for (k, du) in [(1, -1.0), (2, 0.0), (3, 1.0)] {
                let (pu, pv) = (u + du, row - i as f64);
                let Some(g) = self.table.lookup(pu, pv) else {
                    return 0.0;
                };
                let c = read(i, k);
                sum += c as f64;
                sum2 += c as f64 * c as f64;
                let gradient = (
                    (read(i, k + 1) - read(i, k - 1)) / 2.0,
                    (read(i - 1, k) - read(i + 1, k)) / 2.0,
                );
                self.patch.push(PatchPixel {
                    pu,
                    pv,
                    ground: g,
                    current: c,
                    gradient,
                    floor: None,
                });
            }
        }
        let n = self.patch.len() as f64;
        if (sum2 / n - (sum / n).powi(2)).max(0.0).sqrt() < self.options.min_texture_grey {
            return 0.0;
        }
        // the surfaces every pixel's ray meets before its floor point; the others cannot tell
        // (0), and with none the floor's warp is not needed
        let mut usable = [None; 4];
        let mut count = 0;
        for &along in directions.iter().take(usable.len()) {
            let d = facing(base, along);
            if self
                .patch
                .iter()
                .all(|px| share(base, px.ground, d).is_some())
            {
                usable[count] = Some(d);
                count += 1;
            }
        }
        if count == 0 {
            return 0.0;
        }
        // each pixel's earlier position as floor, once
        let mut last = None;
        for px in &mut self.patch {
            let (pu, pv) = (px.pu, px.pv);
            px.floor = self
                .table
                .pixel_of(motion.transform_point(px.ground), chained(last, pu, pv))
                .map(|(fu, fv)| {
                    last = Some((pu, pv, fu, fv));
                    (fu, fv, bilinear(earlier, self.width, self.height, fu, fv))
                });
        }
        let mut best = if count < directions.len() {
            0.0
        } else {
            f64::INFINITY
        };
        for d in usable[..count].iter().flatten() {
            let llr = self.standing_log_likelihood_ratio(earlier, motion, noise, base, *d);
            best = best.min(if llr.is_finite() { llr } else { 0.0 });
            // settled: no veto, and evidence of standing (which clears the memory's cell)
            if best <= self.options.min_log_likelihood_ratio && best < 0.0 {
                break;
            }
        }
        best
    }

    /// The ratio of [`Self::log_likelihood_ratio`] for the surface standing along direction
    /// `d` through `base` (the patch and its floor positions made, every pixel's ray meeting
    /// the surface).
    fn standing_log_likelihood_ratio(
        &mut self,
        earlier: &[f32],
        motion: &Pose2,
        noise: f64,
        base: Point2,
        d: Point2,
    ) -> f64 {
        // each pixel's earlier position under the standing explanation, and its variance (the
        // noise, and what a warp `warp_error_px` off does to it: a strong edge along the
        // motion, which both explanations place alike up to their small errors, weighs little)
        self.samples.clear();
        let mut apart = 0.0f64;
        let mut last = None;
        for px in &self.patch {
            let (pu, pv, g) = (px.pu, px.pv, px.ground);
            let (Some(s), Some((fu, fv, floor_read))) = (share(base, g, d), px.floor) else {
                continue;
            };
            let p = motion.transform_point(Point2::new(s * g.x, s * g.y));
            let Some((su, sv)) = self
                .table
                .pixel_of(Point2::new(p.x / s, p.y / s), chained(last, pu, pv))
            else {
                continue;
            };
            last = Some((pu, pv, su, sv));
            apart += (fu - su).powi(2) + (fv - sv).powi(2);
            let (gu, gv) = px.gradient;
            let slip = gu.hypot(gv) as f64 * self.options.warp_error_px;
            self.samples.push([
                px.current,
                floor_read,
                bilinear(earlier, self.width, self.height, su, sv),
                (1.0 / (noise * noise + slip * slip)) as f32,
            ]);
        }
        let n = self.patch.len() as f64;
        let k = self.samples.len();
        if (k as f64) < MIN_PLACED_SHARE * n {
            return 0.0;
        }
        // explanations that put the rows nearly in the same place cannot be told apart
        if (apart / k as f64).sqrt() < self.options.min_separation_px {
            return 0.0;
        }
        let mean = |i: usize| self.samples.iter().map(|x| x[i] as f64).sum::<f64>() / k as f64;
        let (mc, mf, ms) = (mean(0), mean(1), mean(2));
        let (mut floor, mut standing) = (0.0, 0.0);
        for &[c, f, st, w] in &self.samples {
            let c = c as f64 - mc;
            floor += w as f64 * (c - (f as f64 - mf)).powi(2);
            standing += w as f64 * (c - (st as f64 - ms)).powi(2);
        }
        // as if every pixel of the patch had been placed
        (standing - floor) / 2.0 * n / k as f64
    }
}

/// The surface's direction on the floor: `along`, or facing the camera (across the ray to
/// `base`).
fn facing(base: Point2, along: Option<Point2>) -> Point2 {
    along.unwrap_or(Point2::new(-base.y, base.x))
}

/// The share s of the ray to floor point `g` at which it meets the vertical surface through
/// `base` along `d` (in front of the floor point, not too near the camera), else `None`.
fn share(base: Point2, g: Point2, d: Point2) -> Option<f64> {
    let cross = |p: Point2| p.x * d.y - p.y * d.x;
    let s = cross(base) / cross(g);
    (s.is_finite() && s > 0.05 && s <= 1.0 + 1e-9).then_some(s)
}

/// Where a Newton search for a pixel's earlier position starts: where the previous pixel's
/// ended (`last`: its pixel and what it found), moved as the pixel moved; else the pixel.
fn chained(last: Option<(f64, f64, f64, f64)>, pu: f64, pv: f64) -> (f64, f64) {
    match last {
        Some((lu, lv, eu, ev)) => (eu + pu - lu, ev + pv - lv),
        None => (pu, pv),
    }
}

/// The directions a surface standing at reading j's boundary may have on the floor, the most
/// likely first: the base line its neighbours' boundary points within `gap_m` of its own draw
/// (through both where both lie near), the line to each of them alone (at a corner the two
/// faces meet; on a straight base, three estimates of its direction), and facing the camera
/// (`None`, the only one where none lie near). Returns the directions and how many of the four
/// slots hold one.
pub(super) fn base_directions(
    scan: &Scan,
    j: usize,
    here: Point2,
    gap_m: f64,
) -> ([Option<Point2>; 4], usize) {
    let near = |i: usize| match scan.readings.get(i).map(|r| r.outcome) {
        Some(ColumnOutcome::Boundary { point, .. })
            if (point.x - here.x).hypot(point.y - here.y) < gap_m =>
        {
            Some(point)
        }
        _ => None,
    };
    let unit = |d: Point2| {
        let n = d.norm();
        (n > 1e-9).then(|| Point2::new(d.x / n, d.y / n))
    };
    let before = j.checked_sub(1).and_then(near);
    let after = near(j + 1);
    let through = match (before, after) {
        (Some(a), Some(b)) => unit(Point2::new(b.x - a.x, b.y - a.y)),
        _ => None,
    };
    let to_before = before.and_then(|a| unit(Point2::new(here.x - a.x, here.y - a.y)));
    let to_after = after.and_then(|b| unit(Point2::new(b.x - here.x, b.y - here.y)));
    let mut out = [None; 4];
    let mut count = 0;
    for d in [through, to_before, to_after].into_iter().flatten() {
        out[count] = Some(d);
        count += 1;
    }
    (out, count + 1)
}
