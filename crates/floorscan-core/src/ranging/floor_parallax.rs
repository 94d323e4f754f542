//! The floor-parallax cue: is a boundary of the edge ranger the floor's own edge (a grout line,
//! a plank joint, a printed pattern) or an obstacle's base? Between the current frame and an
//! earlier one, the ground table and the motion predict where every floor pixel was seen
//! (the floor's homography, read through the table: no pinhole). The image rows above a
//! boundary are explained two ways:
//!
//! - **floor**: they moved as floor does;
//! - **standing**: they lie on a vertical surface through the boundary's ground point B: along
//!   the base line the neighbouring columns' boundaries draw (through both, to each alone: a
//!   corner), and facing the camera. A pixel whose ray meets the floor at G (camera ground frame, origin under the
//!   camera) meets that surface at s G; seen from the earlier camera its ray meets the floor at
//!   M(s G) / s, M the earlier camera ground frame from the current one. Neither explanation
//!   needs the camera's height.
//!
//! When the floor explains the rows' zero-mean intensities better than every such surface (a
//! log-likelihood ratio above `min_log_likelihood_ratio` at the floor's own residual noise),
//! the boundary is the floor's and the column is scanned on above it
//! ([`VisualRanger::continue_above`]). Rows without texture, no earlier frame far enough back
//! (standing; a camera turning about its own centre) or no pose keep the edge ranger's reading. The odometry's motion is refined first by Lucas-Kanade on
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

/// A pixel of a tested patch: where it is, its ground point, the current frame's reading
/// there and its central differences.
struct PatchPixel {
    pu: f64,
    pv: f64,
    ground: Point2,
    current: f32,
    gradient: (f32, f32),
    /// Where the floor explanation puts it in the earlier frame, and the reading there.
    floor: Option<(f64, f64, f32)>,
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
    /// The band's pixels whose gradient in the current frame lets them take part in the
    /// refinement (indices into `band`).
    textured: Vec<usize>,
    residuals: Vec<f32>,
    restarts: Vec<(usize, f64)>,
    /// Each column's last vetoed row in the current frame.
    last_vetoed: Vec<Option<f64>>,
    dirty: Vec<bool>,
    patch: Vec<PatchPixel>,
    /// The current frame around a tested patch (its rows and one beyond each end, five columns).
    reads: Vec<f32>,
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
            textured: Vec::with_capacity(band.len()),
            band_guess,
            band,
            restarts: Vec::new(),
            last_vetoed: Vec::new(),
            dirty: Vec::new(),
            patch: Vec::new(),
            reads: Vec::new(),
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
                            let u = out.readings[j].column as f64;
                            // floor must beat every surface that could stand there: along the
                            // line the neighbours draw, along either neighbour's side alone (a
                            // corner), facing the camera
                            let (directions, count) =
                                base_directions(out, j, point, self.options.base_line_gap_m);
                            self.log_likelihood_ratio(
                                &earlier,
                                &motion,
                                noise,
                                u,
                                row,
                                point,
                                &directions[..count],
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

    /// The newest kept frame at least `min_baseline_m` of camera travel back; where none is
    /// (turning on the spot, starting, creeping), the kept frame farthest from the camera if
    /// it is at least `min_turn_baseline_m` away.
    fn earlier_frame(&self, pose: &Pose2) -> Option<usize> {
        let n = self.frames.len();
        let travel = |i: usize| {
            self.frames[i]
                .world_from_camera
                .between(pose)
                .translation()
                .norm()
        };
        (1..=n)
            .map(|back| (self.next + n - back) % n)
            .find(|&i| travel(i) >= self.options.min_baseline_m)
            .or_else(|| {
                (0..n)
                    .map(|i| (i, travel(i)))
                    .filter(|&(_, d)| d >= self.options.min_turn_baseline_m)
                    .max_by(|a, b| a.1.total_cmp(&b.1))
                    .map(|(i, _)| i)
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
}

#[path = "floor_parallax_warp.rs"]
mod warp;
use warp::{bilinear, blur_into, gaussian_kernel};
#[path = "floor_parallax_evidence.rs"]
mod evidence;
use evidence::base_directions;

#[cfg(test)]
#[path = "floor_parallax_tests.rs"]
mod tests;
