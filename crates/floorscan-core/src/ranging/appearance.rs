//! The appearance range sensor: the paper's "visual ranging that does not rely on the texture
//! assumption". A [`FloorModel`] of colour and texture is learned from a band of floor just
//! above each column's start row (in front of the robot) and blended over frames; each sampled
//! column is then scanned from the bottom, and the lowest row of the first run of
//! `min_run_px` rows that do not look like floor is the boundary, looked up in the ground
//! table like the edge ranger's (same statuses: boundary, no_boundary, too_close, invalid).
//!
//! A row of a column does not look like floor when most pixels of the horizontal patch around
//! the column (2w + 1 pixels) do not. Each reading carries a confidence in [0, 1]: the margin by
//! which the rows above the boundary are not floor times the margin by which those below are.
//! Buffers live in the ranger and its model: scanning a frame allocates nothing.

use crate::appearance_options::{AppearanceFeatures, AppearanceOptions};
use crate::colour_image::ColourView;
use crate::dark_rim::is_dark_rim;
use crate::error::{invalid_option, Error, Result};
use crate::floor_model::{colour_bin, texture_bin, FloorModel, COLOUR_BINS, TEXTURE_BINS};
use crate::ground_table::GroundTable;
use crate::image::Pixel;
use crate::pose::Point2;
use crate::ranger_options::ColumnStart;
use crate::scan::{ColumnOutcome, ColumnReading, Scan};

/// Reference pixels are sampled every this many columns and rows.
const REFERENCE_STRIDE: usize = 2;

/// Pixels kept per boundary for the driven-over refresh: the column's pixel in each of the
/// first (lowest) rows of the run that stopped its scan.
pub const BOUNDARY_SAMPLES: usize = 4;
/// A slot of [`AppearanceRanger::boundary_samples`] without a pixel.
pub const NO_SAMPLE: u32 = u32::MAX;

/// A pixel's bins packed in one sample: `colour * TEXTURE_BINS + texture`.
pub fn pack_sample(colour: usize, texture: usize) -> u32 {
    (colour * TEXTURE_BINS + texture) as u32
}

#[derive(Debug, Clone, Copy)]
struct Plan {
    column: u32,
    start_row: usize,
    /// The start row as configured; `start_row` moves to `first_ground_row` while the rows at
    /// this one are a lens's dark rim (`dark_rim`).
    nominal_start: usize,
    /// The column's lowest row with ground at or above the start row, `None` without ground.
    first_ground_row: Option<usize>,
    near: Option<Point2>,
    /// Highest row scanned; `None` when the column cannot be scanned (no ground at or above
    /// its start).
    top_row: Option<usize>,
    /// Patch columns, inclusive.
    patch: (usize, usize),
}

/// The appearance range sensor for one camera (image size fixed by its ground table).
#[derive(Debug, Clone)]
pub struct AppearanceRanger {
    table: GroundTable,
    options: AppearanceOptions,
    plans: Vec<Plan>,
    /// Per image column: the reference band's rows (top, bottom), inclusive; `None` where the
    /// column's start row has no ground.
    reference: Vec<Option<(usize, usize)>>,
    model: FloorModel,
    outcomes: Vec<ColumnOutcome>,
    confidence: Vec<f32>,
    /// Row-major scan buffers (dense columns): per-column state, and one image row's floor
    /// classification as a prefix count (width + 1).
    states: Vec<ColumnState>,
    row_prefix: Vec<u32>,
    /// As `row_prefix`, for the reference's floor alone (while driven-over floor is known).
    row_prefix_reference: Vec<u32>,
    /// Per column of the last scan: whether it crossed at least `min_run_px` rows that look
    /// like floor only through the driven-over floor.
    driven_columns: Vec<bool>,
    /// Per column of the last scan: the row [px] of the first border between the reference's
    /// floor and driven-over floor (NaN where none).
    driven_borders: Vec<f64>,
    /// Per column of the last scan: the pixels of the run that made its boundary (packed
    /// bins, [`NO_SAMPLE`] where none), for the driven-over refresh.
    samples: Vec<[u32; BOUNDARY_SAMPLES]>,
}

/// One column's scan state: the current run of non-floor rows and the floor rows below it.
#[derive(Debug, Clone, Copy, Default)]
struct ColumnState {
    run: usize,
    run_start: usize,
    run_not_floor: f32,
    floor_rows: usize,
    floor_sum: f32,
    /// Floor rows that look like floor only through the driven-over floor.
    driven_rows: usize,
    /// The kind of the last floor row: 0 none yet, 1 the reference's floor, 2 floor only as
    /// driven-over floor.
    last_kind: u8,
    /// The first row where the floor changes between the two kinds (a rug's border).
    border: Option<usize>,
    /// The scan has ended: at a boundary (its lowest row and confidence) or without one.
    done: bool,
}

impl ColumnState {
    /// Takes row `v` with `floor` of its `patch_n` patch pixels looking like floor (`reference`
    /// of them to the reference alone); returns the run's lowest row and the reading's
    /// confidence once `min_run` rows are not floor.
    #[inline]
    fn step(
        &mut self,
        v: usize,
        (floor, reference): (usize, usize),
        patch_n: usize,
        min_run: usize,
    ) -> Option<(usize, f32)> {
        let share = floor as f32 / patch_n as f32;
        if 2 * floor < patch_n {
            if self.run == 0 {
                self.run_start = v;
                self.run_not_floor = 0.0;
            }
            self.run += 1;
            self.run_not_floor += 1.0 - share;
            if self.run >= min_run {
                let below = if self.floor_rows > 0 {
                    self.floor_sum / self.floor_rows as f32
                } else {
                    1.0
                };
                self.done = true;
                let confidence = margin(self.run_not_floor / self.run as f32) * margin(below);
                return Some((self.run_start, confidence));
            }
        } else {
            self.run = 0;
            self.floor_rows += 1;
            self.floor_sum += share;
            let kind = if 2 * reference < patch_n { 2 } else { 1 };
            self.driven_rows += usize::from(kind == 2);
            if self.last_kind != 0 && kind != self.last_kind && self.border.is_none() {
                self.border = Some(v);
            }
            self.last_kind = kind;
        }
        None
    }

    /// Confidence of a column that saw no boundary: the margin of its floor rows.
    fn no_boundary_confidence(&self) -> f32 {
        if self.floor_rows > 0 {
            margin(self.floor_sum / self.floor_rows as f32)
        } else {
            0.0
        }
    }
}

impl AppearanceRanger {
    pub fn new(table: GroundTable, options: AppearanceOptions) -> Result<Self> {
        options.validate()?;
        let (width, height) = (table.image_width(), table.image_height());
        let starts: Vec<usize> = match &options.start {
            ColumnStart::BottomMargin(m) => {
                if *m >= height {
                    return Err(invalid_option(
                        "bottom_margin",
                        format!("{m} rows leaves nothing of a {height}-row image"),
                    ));
                }
                vec![height - 1 - m; width]
            }
            ColumnStart::PerColumn(rows) => {
                if rows.len() != width {
                    return Err(invalid_option(
                        "start_rows",
                        format!(
                            "needs one start row per image column ({width}), got {}",
                            rows.len()
                        ),
                    ));
                }
                if let Some(bad) = rows.iter().find(|&&r| r as usize >= height) {
                    return Err(invalid_option(
                        "start_rows",
                        format!("start row {bad} is outside the image ({height} rows)"),
                    ));
                }
                rows.iter().map(|&r| r as usize).collect()
            }
        };
        let band = ((options.reference_fraction * height as f64).round() as usize).max(1);
        let span = reference_span(width, options.reference_width_fraction);
        let reference = (0..width)
            .map(|u| {
                let s = starts[u];
                table
                    .lookup(u as f64, s as f64)
                    .filter(|_| span.contains(&u))
                    .map(|_| ((s + 1).saturating_sub(band), s))
            })
            .collect();
        let w = options.patch_half_width_px;
        let plans: Vec<Plan> = options
            .column_indices(&table)?
            .into_iter()
            .map(|c| {
                let u = c as usize;
                let start_row = starts[u];
                let within = |p: Point2| options.max_range_m.is_none_or(|r| p.norm() <= r);
                // As the edge ranger: scanned from the start row, placed from the first row
                // with ground.
                let rows = table.column_ground_rows(u as f64, start_row, within);
                let near = rows.and_then(|(first, _)| table.lookup(u as f64, first as f64));
                let top_row = rows.map(|(_, top)| top);
                Plan {
                    column: c,
                    start_row,
                    nominal_start: start_row,
                    first_ground_row: rows.map(|(first, _)| first),
                    near,
                    top_row,
                    patch: (u.saturating_sub(w), (u + w).min(width - 1)),
                }
            })
            .collect();
        let n = plans.len();
        Ok(Self {
            table,
            options,
            plans,
            reference,
            model: FloorModel::default(),
            outcomes: vec![ColumnOutcome::Invalid { row: None }; n],
            confidence: vec![0.0; n],
            states: vec![ColumnState::default(); n],
            row_prefix: vec![0; width + 1],
            row_prefix_reference: vec![0; width + 1],
            driven_columns: vec![false; n],
            driven_borders: vec![f64::NAN; n],
            samples: vec![[NO_SAMPLE; BOUNDARY_SAMPLES]; n],
        })
    }

    pub fn table(&self) -> &GroundTable {
        &self.table
    }
    pub fn options(&self) -> &AppearanceOptions {
        &self.options
    }
    pub fn model(&self) -> &FloorModel {
        &self.model
    }
    /// The sampled image columns, in output order.
    pub fn columns(&self) -> Vec<u32> {
        self.plans.iter().map(|p| p.column).collect()
    }

    /// Forgets the learned floor (e.g. on entering another building).
    pub fn reset_model(&mut self) {
        self.model.reset();
    }

    /// Per sampled column (output order) of the last scan: the packed bins
    /// ([`pack_sample`]) of the column's pixel in the lowest [`BOUNDARY_SAMPLES`] rows of the
    /// run of non-floor rows that made its boundary, [`NO_SAMPLE`] in the other slots and for
    /// readings other than a boundary.
    pub fn boundary_samples(&self) -> &[[u32; BOUNDARY_SAMPLES]] {
        &self.samples
    }

    /// Per sampled column (output order) of the last scan: whether its scan crossed at least
    /// `min_run_px` rows that look like floor only through the driven-over floor (a rug the
    /// robot drove across): there an edge where the floor's look changes is that floor's
    /// border, not an obstacle of the floor's colour (see `fusion`).
    pub fn driven_floor_columns(&self) -> &[bool] {
        &self.driven_columns
    }

    /// Per sampled column (output order) of the last scan: the image row [px] of the first
    /// border, scanning up, between the reference's floor and driven-over floor (a rug's
    /// near or far edge); NaN in columns without driven-over floor. The fused ranger keeps
    /// this ranger's "only floor" reading where the edge ranger's boundary lies on it.
    pub fn driven_floor_borders(&self) -> &[f64] {
        &self.driven_borders
    }

    /// Learns `samples` (from [`Self::boundary_samples`] of boundaries the robot has since
    /// driven through: they were floor) as floor from the next frame on, for as long as
    /// `driven_floor_half_life_frames` keeps them. Call it right after the scan of the frame
    /// taken where the robot drove through them: a sample is learned only if that frame's
    /// reference band (the floor just in front of the robot there) confirms it, i.e. the
    /// reference's own model takes its bins as floor now; a boundary the robot only seemed to
    /// drive through (odometry drift past a wall's base) shows other pixels there and teaches
    /// nothing. [`NO_SAMPLE`] entries are skipped; any other value that is not a packed sample
    /// is an error and nothing is learned. Returns the samples learned.
    pub fn learn_driven_floor(&mut self, samples: &[u32]) -> Result<usize> {
        let limit = (COLOUR_BINS * TEXTURE_BINS) as u32;
        if let Some(bad) = samples.iter().find(|&&s| s != NO_SAMPLE && s >= limit) {
            return Err(invalid_option(
                "samples",
                format!("{bad} is not a packed (colour, texture) sample (below {limit})"),
            ));
        }
        let reach = self.options.intensity_reach_bins;
        let mut n = 0;
        for &s in samples.iter().filter(|&&s| s != NO_SAMPLE) {
            let (colour, texture) = (s as usize / TEXTURE_BINS, s as usize % TEXTURE_BINS);
            if self.model.is_reference_floor(colour, Some(texture)) {
                self.model.add_driven(colour, texture, reach);
                n += 1;
            }
        }
        Ok(n)
    }

    /// Learns from this frame's reference band, then scans it into a new [`Scan`].
    pub fn scan<P: Pixel>(&mut self, image: &ColourView<P>, timestamp_s: f64) -> Result<Scan> {
        let mut scan = Scan::default();
        self.scan_into(image, timestamp_s, &mut scan)?;
        Ok(scan)
    }

    /// Learns from this frame's reference band, then scans it into `out` (its buffer reused).
    pub fn scan_into<P: Pixel>(
        &mut self,
        image: &ColourView<P>,
        timestamp_s: f64,
        out: &mut Scan,
    ) -> Result<()> {
        self.check_size(image)?;
        self.follow_dark_rim(image);
        self.learn(image);
        if self.row_major_pays(image.width()) {
            self.scan_rows(image);
        } else {
            for j in 0..self.plans.len() {
                let (outcome, confidence, state) = self.scan_column(image, j);
                self.outcomes[j] = outcome;
                self.confidence[j] = confidence;
                self.states[j] = state;
            }
        }
        let min_run = self.options.min_run_px;
        for ((d, b), s) in self
            .driven_columns
            .iter_mut()
            .zip(self.driven_borders.iter_mut())
            .zip(&self.states)
        {
            *d = s.driven_rows >= min_run;
            // the border lies between the row found and the one below it
            *b = match s.border {
                Some(v) if *d => v as f64 + 0.5,
                _ => f64::NAN,
            };
        }
        out.timestamp_s = timestamp_s;
        out.readings.clear();
        out.readings
            .extend(self.plans.iter().enumerate().map(|(j, p)| ColumnReading {
                column: p.column,
                start_row: p.start_row as f64,
                near: p.near,
                outcome: self.outcomes[j],
                confidence: self.confidence[j],
            }));
        self.record_boundary_samples(image);
        Ok(())
    }

    /// Fills `samples` from this frame's boundaries (see [`Self::boundary_samples`]).
    fn record_boundary_samples<P: Pixel>(&mut self, image: &ColourView<P>) {
        let rows = self.options.min_run_px.min(BOUNDARY_SAMPLES);
        for j in 0..self.plans.len() {
            let slots = &mut self.samples[j];
            *slots = [NO_SAMPLE; BOUNDARY_SAMPLES];
            let ColumnOutcome::Boundary { row, .. } = self.outcomes[j] else {
                continue;
            };
            let (u, v0) = (self.plans[j].column as usize, row.floor() as usize);
            for (k, slot) in slots.iter_mut().take(rows).enumerate() {
                let Some(v) = v0.checked_sub(k) else { break };
                let px = RowPixels::new(image, v, AppearanceFeatures::ColourAndTexture);
                if let (colour, Some(texture)) = px.bins(u) {
                    *slot = pack_sample(colour, texture);
                }
            }
        }
    }

    /// Starts each column whose start row has no ground at its first row with ground while
    /// this frame shows a lens's dark rim there (`dark_rim`; the brightest channel), and at
    /// its configured start row otherwise.
    fn follow_dark_rim<P: Pixel>(&mut self, image: &ColourView<P>) {
        for plan in &mut self.plans {
            let Some(first) = plan.first_ground_row.filter(|&f| f < plan.nominal_start) else {
                continue;
            };
            let c = plan.column as usize;
            let brightest =
                |v: usize| (0..3).fold(0, |m, k| m.max(image.channel(k).get(c, v).to_i32()));
            let rim = is_dark_rim(plan.nominal_start, brightest(first), P::MAX, brightest);
            plan.start_row = if rim { first } else { plan.nominal_start };
        }
    }

    /// Whether pixel (u, v) looks like floor to the current model.
    pub fn looks_like_floor<P: Pixel>(&self, image: &ColourView<P>, u: usize, v: usize) -> bool {
        RowPixels::new(image, v, self.options.features).is_floor(&self.model, u)
    }

    fn check_size<P: Pixel>(&self, image: &ColourView<P>) -> Result<()> {
        let (width, height) = (self.table.image_width(), self.table.image_height());
        if image.width() != width || image.height() != height {
            return Err(Error::InvalidImage(format!(
                "image is {} x {} (w x h) but the calibration table is for {width} x {height}",
                image.width(),
                image.height()
            )));
        }
        Ok(())
    }
}

/// The image columns of the reference band: `fraction` of the width, centred, at least one
/// column.
fn reference_span(width: usize, fraction: f64) -> std::ops::Range<usize> {
    let n = ((fraction * width as f64).round() as usize).clamp(1, width);
    let lo = (width - n) / 2;
    lo..lo + n
}

/// A share s in [0.5, 1] as a margin in [0, 1]: 2s - 1.
fn margin(share: f32) -> f32 {
    (2.0 * share - 1.0).clamp(0.0, 1.0)
}

/// One image row's pixels, read from the channels' row slices: each pixel's colour bin and
/// texture bin, the texture being |G(u+1, v) - G(u-1, v)| + 2 |G(u, v+1) - G(u, v)| of the green
/// channel (8-bit scale, clamped at the borders). The vertical difference looks only
/// downwards, so the floor row just below an obstacle keeps its floor texture and the boundary
/// stays on the obstacle's base.
struct RowPixels<'a, P: Pixel> {
    red: &'a [P],
    green: &'a [P],
    blue: &'a [P],
    green_below: &'a [P],
    strides: [usize; 3],
    last: usize,
    texture: bool,
}

impl<'a, P: Pixel> RowPixels<'a, P> {
    #[inline(always)]
    fn new(image: &ColourView<'a, P>, v: usize, features: AppearanceFeatures) -> Self {
        let (r, g, b) = (image.channel(0), image.channel(1), image.channel(2));
        Self {
            red: r.row(v),
            green: g.row(v),
            blue: b.row(v),
            green_below: g.row((v + 1).min(image.height() - 1)),
            strides: [r.col_stride(), g.col_stride(), b.col_stride()],
            last: image.width() - 1,
            texture: matches!(features, AppearanceFeatures::ColourAndTexture),
        }
    }

    /// (colour bin, texture bin when texture is used) of pixel u.
    #[inline(always)]
    fn bins(&self, u: usize) -> (usize, Option<usize>) {
        let shift = if P::MAX > 255 { 8 } else { 0 };
        let at = |row: &[P], stride: usize, u: usize| row[u * stride].to_i32() >> shift;
        let [rs, gs, bs] = self.strides;
        let g0 = at(self.green, gs, u);
        let colour = colour_bin([at(self.red, rs, u), g0, at(self.blue, bs, u)]);
        let texture = self.texture.then(|| {
            let (ul, ur) = (u.saturating_sub(1), (u + 1).min(self.last));
            let across = at(self.green, gs, ur) - at(self.green, gs, ul);
            texture_bin(across.abs() + 2 * (at(self.green_below, gs, u) - g0).abs())
        });
        (colour, texture)
    }

    #[inline(always)]
    fn is_floor(&self, model: &FloorModel, u: usize) -> bool {
        let (colour, texture) = self.bins(u);
        model.is_floor(colour, texture)
    }
}

#[path = "appearance_scan.rs"]
mod scanning;

#[cfg(test)]
#[path = "appearance_tests.rs"]
mod tests;
