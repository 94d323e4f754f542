//! The floor-parallax cue: is a boundary of the edge ranger the floor's own edge (a grout line,
//! a plank joint, a printed pattern) or an obstacle's base? Between the current frame and an
//! earlier one, the ground table and the motion predict where every floor pixel was seen
//! (the floor's homography, read through the table: no pinhole). The image rows above a
//! boundary are explained two ways:
//!
//! - **floor**: they moved as floor does;
//! - **standing**: they lie on a vertical surface through the boundary's ground point B, along
//!   the base line the neighbouring columns' boundaries draw (facing the camera where none lie
//!   near). A pixel whose ray meets the floor at G (camera ground frame, origin under the
//!   camera) meets that surface at s G; seen from the earlier camera its ray meets the floor at
//!   M(s G) / s, M the earlier camera ground frame from the current one. Neither explanation
//!   needs the camera's height.
//!
//! When the floor explains the rows' zero-mean intensities better (a log-likelihood ratio
//! above `min_log_likelihood_ratio` at the floor's own residual noise), the boundary is the
//! floor's and the column is scanned on above it ([`VisualRanger::continue_above`]). Rows
//! without texture, no earlier frame far enough back (standing, turning on the spot) or no pose
//! keep the edge ranger's reading. The odometry's motion is refined first by Lucas-Kanade on
//! the floor near the robot. Measured: EVALUATION.md, "The floor-parallax cue".

use crate::error::{Error, Result};
use crate::ground_table::GroundTable;
use crate::image::{ImageView, Pixel};
use crate::parallax_options::ParallaxOptions;
use crate::pose::{Point2, Pose2};
use crate::ranger::VisualRanger;
use crate::scan::{ColumnOutcome, Scan};

/// Most pixels of the near floor used to refine the motion (every s-th pixel in each
/// direction, s the least that keeps within this).
const MAX_BAND_PIXELS: usize = 4096;
/// Lucas-Kanade iterations, and the least gradient [grey levels/px] of a pixel that takes part.
const REFINE_ITERATIONS: usize = 5;
const REFINE_MIN_GRADIENT: f32 = 2.0;
/// Least share of a patch's pixels both explanations must place in the earlier frame.
const MIN_PLACED_SHARE: f64 = 0.7;
/// Floor of the residual noise [grey levels] (a synthetic frame without noise).
const MIN_NOISE_GREY: f64 = 0.5;

/// What one frame's check did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ParallaxReport {
    /// Camera travel [m] to the earlier frame compared with; 0 when none was.
    pub baseline_m: f64,
    /// Boundaries found to be the floor's own (each column scanned on above them).
    pub vetoes: usize,
    /// The floor's residual noise after the refined warp [grey levels]; 0 when not compared.
    pub noise_grey: f64,
    /// Of the vetoes, those the memory of the floor's edges made (no comparison needed).
    pub remembered: usize,
    /// Columns whose boundary the motion found above a vetoed one where no edge was
    /// (`search_above_vetoed`).
    pub found_above: usize,
}

/// One cell of the memory of the floor's own edges: in how many frames a boundary there was
/// found to be the floor's, and the last of them.
#[derive(Debug, Clone, Copy)]
struct Mark {
    frames: u32,
    last_frame: u64,
}

struct Frame {
    image: Vec<f32>,
    world_from_camera: Pose2,
}

/// The cue's state: the earlier frames (blurred, with their poses) and scratch buffers, sized
/// once for the table's image size.
pub struct FloorParallax {
    options: ParallaxOptions,
    table: GroundTable,
    width: usize,
    height: usize,
    /// Earlier frames, oldest first once full (a ring: `next` is the slot written next).
    frames: Vec<Frame>,
    next: usize,
    current: Vec<f32>,
    scratch: Vec<f32>,
    kernel: Vec<f32>,
    /// The near floor's pixels and ground points, and their last earlier-frame pixels.
    band: Vec<(f64, f64, Point2)>,
    band_guess: Vec<(f64, f64)>,
    residuals: Vec<f32>,
    restarts: Vec<(usize, f64)>,
    /// Each column's last vetoed row in the current frame.
    last_vetoed: Vec<Option<f64>>,
    dirty: Vec<bool>,
    patch: Vec<(f64, f64, Point2)>,
    samples: Vec<[f32; 4]>,
    /// The memory of the floor's own edges: world cells -> marks; frames seen with a pose.
    memory: std::collections::HashMap<(i64, i64), Mark>,
    frame_index: u64,
}

impl FloorParallax {
    pub fn new(table: GroundTable, options: ParallaxOptions) -> Result<Self> {
        options.validate()?;
        let (width, height) = (table.image_width(), table.image_height());
        let near = |u: usize, v: usize| {
            table
                .lookup(u as f64, v as f64)
                .filter(|g| g.norm() <= options.refine_range_m)
        };
        let all = (0..height)
            .flat_map(|v| (0..width).map(move |u| (u, v)))
            .filter(|&(u, v)| near(u, v).is_some())
            .count();
        let stride = ((all as f64 / MAX_BAND_PIXELS as f64).sqrt().ceil() as usize).max(1);
        let mut band = Vec::with_capacity(MAX_BAND_PIXELS);
        for v in (0..height).step_by(stride) {
            for u in (0..width).step_by(stride) {
                if let Some(g) = near(u, v) {
                    band.push((u as f64, v as f64, g));
                }
            }
        }
        let band_guess = band.iter().map(|&(u, v, _)| (u, v)).collect();
        Ok(Self {
            kernel: gaussian_kernel(options.blur_sigma_px),
            frames: Vec::with_capacity(options.history_frames),
            next: 0,
            current: vec![0.0; width * height],
            scratch: vec![0.0; width * height],
            residuals: Vec::with_capacity(band.len()),
            band_guess,
            band,
            restarts: Vec::new(),
            last_vetoed: Vec::new(),
            dirty: Vec::new(),
            patch: Vec::new(),
            samples: Vec::new(),
            memory: std::collections::HashMap::new(),
            frame_index: 0,
            options,
            table,
            width,
            height,
        })
    }

    pub fn options(&self) -> &ParallaxOptions {
        &self.options
    }

    /// Forgets the earlier frames (a jump in the poses, another recording).
    pub fn reset(&mut self) {
        self.frames.clear();
        self.next = 0;
        self.memory.clear();
    }

    fn cell_of(&self, world: Point2) -> (i64, i64) {
        let c = self.options.memory_cell_m;
        ((world.x / c).floor() as i64, (world.y / c).floor() as i64)
    }

    /// Whether the memory holds the floor's own edge at `world`: its cell, or one of the 8
    /// around, was marked in `memory_min_frames` different frames. (Counting different frames
    /// over the 9 cells together let single-frame mistakes add up: 35 % of the columns within
    /// 1 m wrong on a held-out carpet world, against 15 % this way.)
    fn remembered(&self, world: Point2) -> bool {
        let need = self.options.memory_min_frames;
        if need == 0 {
            return false;
        }
        let (i, j) = self.cell_of(world);
        (-1..=1).any(|di| {
            (-1..=1).any(|dj| {
                self.memory
                    .get(&(i + di, j + dj))
                    .is_some_and(|m| m.frames >= need)
            })
        })
    }

    fn mark(&mut self, world: Point2) {
        if self.options.memory_min_frames == 0 {
            return;
        }
        let frame = self.frame_index;
        let cell = self.cell_of(world);
        let m = self.memory.entry(cell).or_insert(Mark {
            frames: 0,
            last_frame: u64::MAX,
        });
        if m.last_frame != frame {
            m.frames = m.frames.saturating_add(1);
            m.last_frame = frame;
        }
    }

    /// Forgets the cells beyond `memory_radius_m` of the camera at `pose`.
    fn forget_far(&mut self, pose: &Pose2) {
        let r = self.options.memory_radius_m;
        let c = self.options.memory_cell_m;
        let o = pose.transform_point(Point2::new(0.0, 0.0));
        self.memory.retain(|&(i, j), _| {
            let (x, y) = ((i as f64 + 0.5) * c, (j as f64 + 0.5) * c);
            (x - o.x).hypot(y - o.y) <= r
        });
    }

    /// Ranges `image` with `ranger` into `out`, then checks its boundaries against the
    /// earlier frames where `world_from_camera` (the camera ground frame's pose, from odometry)
    /// is given; keeps the frame for later ones. `ranger` must use this cue's table.
    pub fn scan_into<P: Pixel>(
        &mut self,
        ranger: &mut VisualRanger,
        image: &ImageView<P>,
        timestamp_s: f64,
        world_from_camera: Option<Pose2>,
        out: &mut Scan,
    ) -> Result<ParallaxReport> {
        if ranger.table() != &self.table {
            return Err(Error::InvalidTable(
                "the ranger and the parallax cue use different ground tables".into(),
            ));
        }
        ranger.scan_into(image, timestamp_s, out)?;
        let Some(pose) = world_from_camera else {
            return Ok(ParallaxReport::default());
        };
        if !pose.is_finite() {
            return Err(Error::InvalidGeometry(format!(
                "world_from_camera must be finite, got {pose:?}"
            )));
        }
        blur_into(image, &self.kernel, &mut self.scratch, &mut self.current);
        self.frame_index += 1;
        self.forget_far(&pose);
        let mut report = ParallaxReport::default();
        let earlier_index = self.earlier_frame(&pose);
        if earlier_index.is_some() || !self.memory.is_empty() {
            let earlier = earlier_index
                .map(|i| std::mem::take(&mut self.frames[i].image))
                .unwrap_or_default();
            let rough = earlier_index
                .map(|i| self.frames[i].world_from_camera.between(&pose))
                .unwrap_or(Pose2::new(0.0, 0.0, 0.0));
            let (motion, noise) = if earlier_index.is_some() {
                let motion = self.refine_motion(&earlier, rough);
                let noise = self.floor_noise(&earlier, &motion).max(MIN_NOISE_GREY);
                (motion, noise)
            } else {
                (rough, 0.0)
            };
            report = ParallaxReport {
                baseline_m: if earlier_index.is_some() {
                    rough.translation().norm()
                } else {
                    0.0
                },
                vetoes: 0,
                noise_grey: noise,
                remembered: 0,
                found_above: 0,
            };
            // a column's test reads its own boundary and its neighbours': it is tested again
            // only when one of those moved
            self.dirty.clear();
            self.dirty.resize(out.readings.len(), true);
            self.last_vetoed.clear();
            self.last_vetoed.resize(out.readings.len(), None);
            for _ in 0..self.options.max_vetoes {
                self.restarts.clear();
                for j in 0..out.readings.len() {
                    if !self.dirty[j] {
                        continue;
                    }
                    if let ColumnOutcome::Boundary { row, point, .. } = out.readings[j].outcome {
                        let world = pose.transform_point(point);
                        // the motion decides where it can; the memory where it cannot (no
                        // earlier frame, no texture above, the two explanations too close)
                        let llr = if earlier_index.is_some() {
                            let along = base_direction(out, j, point, self.options.base_line_gap_m);
                            let u = out.readings[j].column as f64;
                            self.log_likelihood_ratio(
                                &earlier, &motion, noise, u, row, point, along,
                            )
                        } else {
                            0.0
                        };
                        if llr > self.options.min_log_likelihood_ratio {
                            self.restarts.push((j, row));
                            self.mark(world);
                        } else if llr < 0.0 {
                            // any evidence of standing outweighs the memory, and clears it
                            let cell = self.cell_of(world);
                            self.memory.remove(&cell);
                        } else if self.remembered(world) {
                            self.restarts.push((j, row));
                            report.remembered += 1;
                        }
                    }
                }
                if self.restarts.is_empty() {
                    break;
                }
                report.vetoes += self.restarts.len();
                for &(j, row) in &self.restarts {
                    self.last_vetoed[j] = Some(row);
                }
                ranger.continue_above(image, &self.restarts, out)?;
                self.dirty.fill(false);
                for &(j, _) in &self.restarts {
                    for k in j.saturating_sub(1)..=(j + 1).min(self.dirty.len() - 1) {
                        self.dirty[k] = true;
                    }
                }
            }
            if self.options.search_above_vetoed && earlier_index.is_some() {
                report.found_above = self.search_above_vetoed(&earlier, &motion, noise, out);
            }
            if let Some(i) = earlier_index {
                self.frames[i].image = earlier;
            }
        }
        self.keep(pose);
        Ok(report)
    }

    /// Columns whose last vetoed boundary has no edge above it: the first row above it, in
    /// steps of a quarter of the test's rows, whose rows above move as a surface standing
    /// there becomes the boundary. Returns how many columns got one.
    fn search_above_vetoed(
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
                        self.log_likelihood_ratio(earlier, motion, noise, u, row, point, None);
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

    /// The newest kept frame at least `min_baseline_m` of camera travel back.
    fn earlier_frame(&self, pose: &Pose2) -> Option<usize> {
        let n = self.frames.len();
        (1..=n).map(|back| (self.next + n - back) % n).find(|&i| {
            self.frames[i]
                .world_from_camera
                .between(pose)
                .translation()
                .norm()
                >= self.options.min_baseline_m
        })
    }

    fn keep(&mut self, pose: Pose2) {
        if self.frames.len() < self.options.history_frames {
            self.frames.push(Frame {
                image: vec![0.0; self.width * self.height],
                world_from_camera: pose,
            });
            let last = self.frames.len() - 1;
            std::mem::swap(&mut self.frames[last].image, &mut self.current);
            self.next = self.frames.len() % self.options.history_frames;
        } else {
            let slot = &mut self.frames[self.next];
            std::mem::swap(&mut slot.image, &mut self.current);
            slot.world_from_camera = pose;
            self.next = (self.next + 1) % self.options.history_frames;
        }
    }

    /// Lucas-Kanade on the near floor: a left correction of `motion` (earlier from current)
    /// that aligns the two frames' floor.
    fn refine_motion(&mut self, earlier: &[f32], motion: Pose2) -> Pose2 {
        let mut m = motion;
        for _ in 0..REFINE_ITERATIONS {
            let (mut a, mut b, mut n) = ([[0.0f64; 3]; 3], [0.0f64; 3], 0usize);
            for (i, &(u, v, g)) in self.band.iter().enumerate() {
                // the floor's texture moves with it: a pixel flat in this frame is flat there
                let (cu, cv) = gradient(&self.current, self.width, self.height, u, v);
                if cu.hypot(cv) < REFINE_MIN_GRADIENT {
                    continue;
                }
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
    fn floor_noise(&mut self, earlier: &[f32], motion: &Pose2) -> f64 {
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

    /// log p(rows above | floor) - log p(rows above | standing at the boundary), Gaussian
    /// residuals of `noise`; 0 where the rows cannot tell (no texture, not seen before).
    #[allow(clippy::too_many_arguments)]
    fn log_likelihood_ratio(
        &mut self,
        earlier: &[f32],
        motion: &Pose2,
        noise: f64,
        u: f64,
        row: f64,
        base: Point2,
        along: Option<Point2>,
    ) -> f64 {
        let rows =
            ((self.options.rows_above_fraction * self.height as f64).round() as usize).max(4);
        if row < rows as f64 || u < 1.0 || u > (self.width - 2) as f64 {
            return 0.0;
        }
        // the surface's direction on the floor, and the share s of each ray's floor point G at
        // which the ray meets it
        let d = along.unwrap_or(Point2::new(-base.y, base.x));
        let cross = |p: Point2| p.x * d.y - p.y * d.x;
        self.patch.clear();
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for i in 1..=rows {
            for du in [-1.0, 0.0, 1.0] {
                let (pu, pv) = (u + du, row - i as f64);
                let Some(g) = self.table.lookup(pu, pv) else {
                    return 0.0;
                };
                let c = bilinear(&self.current, self.width, self.height, pu, pv) as f64;
                sum += c;
                sum2 += c * c;
                self.patch.push((pu, pv, g));
            }
        }
        let n = self.patch.len() as f64;
        if (sum2 / n - (sum / n).powi(2)).max(0.0).sqrt() < self.options.min_texture_grey {
            return 0.0;
        }
        // each pixel's earlier position under both explanations, its variance (the noise, and
        // what a warp `warp_error_px` off does to it: a strong edge along the motion, which both
        // explanations place alike up to their small errors, weighs little)
        self.samples.clear();
        let mut apart = 0.0f64;
        let (mut last_floor, mut last_standing) = (None, None);
        for &(pu, pv, g) in &self.patch {
            let s = cross(base) / cross(g);
            if !(s.is_finite() && s > 0.05 && s <= 1.0 + 1e-9) {
                return 0.0;
            }
            let p = motion.transform_point(Point2::new(s * g.x, s * g.y));
            // the search starts where the previous pixel's ended, moved as the pixel moved
            let guess = |at: Option<(f64, f64, f64, f64)>| match at {
                Some((lu, lv, eu, ev)) => (eu + pu - lu, ev + pv - lv),
                None => (pu, pv),
            };
            let floor = self
                .table
                .pixel_of(motion.transform_point(g), guess(last_floor));
            let standing = self
                .table
                .pixel_of(Point2::new(p.x / s, p.y / s), guess(last_standing));
            let (Some((fu, fv)), Some((su, sv))) = (floor, standing) else {
                continue;
            };
            last_floor = Some((pu, pv, fu, fv));
            last_standing = Some((pu, pv, su, sv));
            apart += (fu - su).powi(2) + (fv - sv).powi(2);
            let (gu, gv) = gradient(&self.current, self.width, self.height, pu, pv);
            let slip = gu.hypot(gv) as f64 * self.options.warp_error_px;
            self.samples.push([
                bilinear(&self.current, self.width, self.height, pu, pv),
                bilinear(earlier, self.width, self.height, fu, fv),
                bilinear(earlier, self.width, self.height, su, sv),
                (1.0 / (noise * noise + slip * slip)) as f32,
            ]);
        }
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

/// The base line's direction at reading j from its neighbours' boundary points within `gap_m`
/// of its own (`None` where none lie near).
fn base_direction(scan: &Scan, j: usize, here: Point2, gap_m: f64) -> Option<Point2> {
    let near = |i: usize| match scan.readings.get(i).map(|r| r.outcome) {
        Some(ColumnOutcome::Boundary { point, .. })
            if (point.x - here.x).hypot(point.y - here.y) < gap_m =>
        {
            Some(point)
        }
        _ => None,
    };
    let before = j.checked_sub(1).and_then(near);
    let after = near(j + 1);
    let d = match (before, after) {
        (Some(a), Some(b)) => Point2::new(b.x - a.x, b.y - a.y),
        (Some(a), None) => Point2::new(here.x - a.x, here.y - a.y),
        (None, Some(b)) => Point2::new(b.x - here.x, b.y - here.y),
        (None, None) => return None,
    };
    let n = d.norm();
    (n > 1e-9).then(|| Point2::new(d.x / n, d.y / n))
}

/// Gaussian kernel of `sigma` px (radius 3 sigma), normalised; `[1]` for sigma 0.
fn gaussian_kernel(sigma: f64) -> Vec<f32> {
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

/// Separable blur of `image` into `out` (edges clamped), through `scratch`.
fn blur_into<P: Pixel>(image: &ImageView<P>, kernel: &[f32], scratch: &mut [f32], out: &mut [f32]) {
    let (w, h) = (image.width(), image.height());
    let r = (kernel.len() / 2) as i64;
    for v in 0..h {
        for u in 0..w {
            let mut acc = 0.0;
            for (t, &k) in kernel.iter().enumerate() {
                let uu = (u as i64 + t as i64 - r).clamp(0, w as i64 - 1) as usize;
                acc += k * image.get(uu, v).to_i32() as f32;
            }
            scratch[v * w + u] = acc;
        }
    }
    for v in 0..h {
        for u in 0..w {
            let mut acc = 0.0;
            for (t, &k) in kernel.iter().enumerate() {
                let vv = (v as i64 + t as i64 - r).clamp(0, h as i64 - 1) as usize;
                acc += k * scratch[vv * w + u];
            }
            out[v * w + u] = acc;
        }
    }
}

/// Bilinear sample of a (w, h) image at (u, v), clamped to the image.
fn bilinear(img: &[f32], w: usize, h: usize, u: f64, v: f64) -> f32 {
    let u = u.clamp(0.0, (w - 1) as f64 - 1e-6);
    let v = v.clamp(0.0, (h - 1) as f64 - 1e-6);
    let (u0, v0) = (u.floor() as usize, v.floor() as usize);
    let (fu, fv) = ((u - u0 as f64) as f32, (v - v0 as f64) as f32);
    let (u1, v1) = ((u0 + 1).min(w - 1), (v0 + 1).min(h - 1));
    let p = |uu: usize, vv: usize| img[vv * w + uu];
    p(u0, v0) * (1.0 - fu) * (1.0 - fv)
        + p(u1, v0) * fu * (1.0 - fv)
        + p(u0, v1) * (1.0 - fu) * fv
        + p(u1, v1) * fu * fv
}

/// Central-difference gradient (d/du, d/dv) of the image at (u, v).
fn gradient(img: &[f32], w: usize, h: usize, u: f64, v: f64) -> (f32, f32) {
    (
        (bilinear(img, w, h, u + 1.0, v) - bilinear(img, w, h, u - 1.0, v)) / 2.0,
        (bilinear(img, w, h, u, v + 1.0) - bilinear(img, w, h, u, v - 1.0)) / 2.0,
    )
}

/// Solves the 3 x 3 system a x = b (Cramer's rule); `None` when it is singular.
fn solve3(a: [[f64; 3]; 3], b: [f64; 3]) -> Option<[f64; 3]> {
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

#[cfg(test)]
#[path = "floor_parallax_tests.rs"]
mod tests;
