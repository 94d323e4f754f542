//! The visual range sensor (paper III.B): scan sampled columns from the bottom with the
//! incremental box filter, take the first edge above the threshold, refine it, and look its
//! ground point up in the calibration table.
//!
//! All sampled columns advance together, one image row per step, so memory is read row-major;
//! the per-column state is a running sum. The loop ends as soon as every column is resolved.
//! Buffers live in the ranger, so scanning a frame allocates nothing.
//!
//! For 8-bit images the sums are 16-bit and a row step runs through the lane kernels of
//! [`crate::lanes`] (AVX2 where the CPU has it, chosen at run time), which also mark the
//! columns that crossed, so a row with crossings costs a look at those columns only. 16-bit
//! images use 32-bit sums in plain Rust. Both give the readings of the direct filter of eq. (1)
//! (the tests check every column of random images against it, for every kernel).

use crate::dark_rim::is_dark_rim;
use crate::edge::{
    direct_response, direct_response_at, next_response, ramp_above, refine_crossing, sharpest_step,
    threshold_to_sum, Refinement, RAMP_ROWS_PER_HALF_WIDTH,
};
use crate::error::{Error, Result};
use crate::ground_table::GroundTable;
use crate::image::{ImageView, Pixel};
use crate::lanes::{self, Kernel, LANES, MAX_HALF_WIDTH_I16};
use crate::noise_threshold::{
    near_band_rows, robust_sigma_counted, MAX_HISTOGRAM_SPAN, NOISE_COLUMNS,
};
use crate::pose::Point2;
use crate::ranger_options::{ColumnStart, RangerOptions};
use crate::scan::{ColumnOutcome, ColumnReading, Scan};

/// The visual range sensor for one camera (image size fixed by its ground table).
#[derive(Debug, Clone)]
pub struct VisualRanger {
    table: GroundTable,
    options: RangerOptions,
    /// Each column's threshold on the raw sum for the current frame (the options' one, or the
    /// frame's own with `noise_multiple` / `contrast`).
    column_threshold_sum: Vec<i32>,
    plans: Vec<ColumnPlan>,
    /// Indices (into `plans`) of scannable columns, sorted by window start and by window end.
    by_lo: Vec<usize>,
    by_hi: Vec<usize>,
    /// The column loop's buffers (see [`row_step::ColumnScratch`]), and its crossings of one
    /// row (column, sum; capacity one a column).
    scratch: ColumnScratch,
    hits: Vec<(usize, i32)>,
    /// The lane kernels' instruction set; whether this frame's scan uses the prefilter, and
    /// each column's prefilter byte threshold for the frame (see
    /// [`lanes::prefilter_threshold`]).
    kernel: Kernel,
    prefilter: bool,
    column_prefilter: Vec<u8>,
    outcomes: Vec<Option<ColumnOutcome>>,
    /// Per column: the confidence of its outcome (see [`edge_confidence`]).
    confidence: Vec<f32>,
    /// The near-floor band's responses of one frame (see [`crate::noise_threshold`]), sized
    /// once; and the threshold the last frame was scanned with.
    noise_samples: Vec<i32>,
    /// Scratch histogram of the noise samples (sized once, [`MAX_HISTOGRAM_SPAN`] counts).
    noise_histogram: Vec<u32>,
    /// One column's pixels under the near-floor band's windows (sized once: the band's rows
    /// and 2d more).
    band_pixels: Vec<i32>,
    /// The band's rows of every scannable column, row-major (row r of the band, then the
    /// columns in plan order), when they share their band rows (sized once); those columns'
    /// pixel offsets in a row, and the running responses of the noise columns.
    band_rows: Vec<u16>,
    band_offsets: Vec<usize>,
    band_responses: Vec<i32>,
    /// Each column's sum over the band's rows, when every column shares them (sized once).
    brightness_sums: Vec<i32>,
    column_brightness: Vec<f64>,
    frame_threshold: f64,
    /// Each column's threshold on the raw sum inside its `mid_range_m` band for the current
    /// frame, and whether any column has a band with a lower threshold this frame.
    band_threshold_sum: Vec<i32>,
    band_active: bool,
    /// Per column, the row k of this frame's first crossing (`usize::MAX`: none).
    crossings: Vec<usize>,
    /// Floor length [m] one pixel row covers, per sampled column (outer) and image row (inner),
    /// worked out once: a boundary's footprint then costs no table lookup.
    footprints_m: Vec<f32>,
}

impl VisualRanger {
    pub fn new(table: GroundTable, options: RangerOptions) -> Result<Self> {
        options.validate()?;
        let (width, height) = (table.image_width(), table.image_height());
        let d = options.half_width_px;
        if 2 * d + 2 > height {
            return Err(crate::error::invalid_option(
                "half_width",
                format!(
                    "{d} px needs an image at least {} rows high, the table's has {height}",
                    2 * d + 2
                ),
            ));
        }
        let columns = options.column_indices(&table)?;
        let starts: Vec<usize> = match &options.start {
            ColumnStart::BottomMargin(m) => {
                if *m >= height {
                    return Err(crate::error::invalid_option(
                        "bottom_margin",
                        format!("{m} rows leaves nothing of a {height}-row image"),
                    ));
                }
                vec![height - 1 - m; width]
            }
            ColumnStart::PerColumn(rows) => {
                if rows.len() != width {
                    return Err(crate::error::invalid_option(
                        "start_rows",
                        format!(
                            "needs one start row per image column ({width}), got {}",
                            rows.len()
                        ),
                    ));
                }
                if let Some(bad) = rows.iter().find(|&&r| r as usize >= height) {
                    return Err(crate::error::invalid_option(
                        "start_rows",
                        format!("start row {bad} is outside the image ({height} rows)"),
                    ));
                }
                rows.iter().map(|&r| r as usize).collect()
            }
        };
        let plans: Vec<ColumnPlan> = columns
            .iter()
            .map(|&c| plan_column(&table, &options, c, starts[c as usize]))
            .collect();
        let footprints_m = plans
            .iter()
            .flat_map(|p| {
                let table = &table;
                (0..height).map(move |v| row_footprint_m(table, p.column, v as f64) as f32)
            })
            .collect();
        let n = plans.len();
        let threshold_sum = threshold_to_sum(options.threshold, d);
        let prefilter = lanes::prefilter_threshold(d, threshold_sum);
        let mut ranger = Self {
            column_threshold_sum: vec![threshold_sum; n],
            scratch: ColumnScratch::new(n, d),
            hits: Vec::with_capacity(n),
            kernel: Kernel::detect(),
            prefilter: prefilter.is_some(),
            column_prefilter: vec![prefilter.unwrap_or(u8::MAX); n],
            outcomes: vec![None; n],
            confidence: vec![1.0; n],
            footprints_m,
            noise_samples: Vec::new(),
            noise_histogram: vec![0; MAX_HISTOGRAM_SPAN],
            band_pixels: vec![0; near_band_rows(height, d) + 2 * d + 1],
            band_rows: vec![0; (near_band_rows(height, d) + 2 * d + 1) * n],
            band_offsets: vec![0; n],
            band_responses: vec![0; n],
            brightness_sums: vec![0; n],
            column_brightness: vec![0.0; n],
            frame_threshold: options.threshold,
            band_threshold_sum: vec![threshold_sum; n],
            band_active: false,
            crossings: vec![usize::MAX; n],
            table,
            options,
            plans,
            by_lo: Vec::new(),
            by_hi: Vec::new(),
        };
        ranger.index_plans();
        Ok(ranger)
    }

    /// The scannable columns sorted by window start and end, and the noise samples' buffer,
    /// from the plans (at construction, and again when a plan's start row moves).
    fn index_plans(&mut self) {
        let plans = &self.plans;
        // Into the buffers already held (no allocation once they have grown: a plan's move
        // only ever shrinks its window).
        let scannable = (0..plans.len()).filter(|&j| plans[j].window.is_some());
        self.by_lo.clear();
        self.by_lo.extend(scannable.clone());
        self.by_lo
            .sort_unstable_by_key(|&j| plans[j].window.unwrap().0);
        self.by_hi.clear();
        self.by_hi.extend(scannable);
        self.by_hi
            .sort_unstable_by_key(|&j| plans[j].window.unwrap().1);
        let band = near_band_rows(self.table.image_height(), self.options.half_width_px);
        let band_samples: usize = plans
            .iter()
            .filter_map(|p| p.window)
            .map(|(lo, hi)| (hi - lo + 1).min(band))
            .sum();
        let samples = if self.options.noise_multiple > 0.0 {
            band_samples
        } else {
            0
        };
        self.noise_samples.resize(samples, 0);
    }

    /// Moves the start of each column whose start row has no ground to its first row with
    /// ground while this frame shows a dark rim there (`dark_rim`), and back when it does not;
    /// re-indexes the plans when one moved (no allocation otherwise).
    fn follow_dark_rim<P: Pixel>(&mut self, image: &ImageView<P>) {
        let mut moved = false;
        for j in 0..self.plans.len() {
            let plan = self.plans[j];
            let nominal = plan.nominal_start;
            let Some(first) = plan.first_ground_row.filter(|&f| f < nominal) else {
                continue;
            };
            let c = plan.column as usize;
            let floor = image.get(c, first).to_i32();
            let rim = is_dark_rim(nominal, floor, P::MAX, |v| image.get(c, v).to_i32());
            let start = if rim { first } else { nominal };
            if start != plan.start_row {
                self.plans[j] = ColumnPlan {
                    nominal_start: nominal,
                    ..plan_column(&self.table, &self.options, plan.column, start)
                };
                moved = true;
            }
        }
        if moved {
            self.index_plans();
        }
    }

    pub fn table(&self) -> &GroundTable {
        &self.table
    }
    pub fn options(&self) -> &RangerOptions {
        &self.options
    }
    /// The sampled image columns, in output order.
    pub fn columns(&self) -> Vec<u32> {
        self.plans.iter().map(|p| p.column).collect()
    }

    /// The threshold on |R| the last frame was scanned with: `threshold`, or with
    /// `noise_multiple` > 0 the frame's own (see [`crate::noise_threshold`]).
    pub fn frame_threshold(&self) -> f64 {
        self.frame_threshold
    }

    /// The lane kernel 8-bit images are scanned with (the fastest this CPU has, by default).
    pub fn kernel(&self) -> Kernel {
        self.kernel
    }

    /// Scans 8-bit images with this kernel (for tests and benchmarks; every kernel gives the
    /// same readings). An error if the CPU lacks it.
    pub fn set_kernel(&mut self, kernel: Kernel) -> Result<()> {
        if !kernel.is_supported() {
            return Err(crate::error::invalid_option(
                "kernel",
                format!("this CPU does not run the {} kernel", kernel.name()),
            ));
        }
        self.kernel = kernel;
        Ok(())
    }

    /// Scans one frame into a new [`Scan`].
    pub fn scan<P: Pixel>(&mut self, image: &ImageView<P>, timestamp_s: f64) -> Result<Scan> {
        let mut scan = Scan::default();
        self.scan_into(image, timestamp_s, &mut scan)?;
        Ok(scan)
    }

    /// Scans one frame into `out`, reusing its buffer (no allocation once it has grown).
    pub fn scan_into<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        timestamp_s: f64,
        out: &mut Scan,
    ) -> Result<()> {
        self.check_size(image)?;
        self.follow_dark_rim(image);
        self.set_frame_threshold(image);
        self.run_columns(image);
        self.scan_band(image);
        self.skip_floor_lines(image);
        self.fill_scan(timestamp_s, out);
        Ok(())
    }

    /// The same scan computed column by column with the direct sum of eq. (1) at every row
    /// (2d pixel reads per row instead of 4). A reference for tests and benchmarks.
    pub fn scan_direct_into<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        timestamp_s: f64,
        out: &mut Scan,
    ) -> Result<()> {
        self.check_size(image)?;
        self.follow_dark_rim(image);
        self.set_frame_threshold(image);
        let d = self.options.half_width_px;
        self.crossings.fill(usize::MAX);
        for j in 0..self.plans.len() {
            let plan = self.plans[j];
            self.outcomes[j] = Some(match plan.window {
                None => ColumnOutcome::Invalid { row: None },
                Some((lo, hi)) => {
                    let c = plan.column as usize;
                    let response = |k| direct_response_at(image, c, k, d);
                    let pixel = |k: usize| image.get(c, image.height() - 1 - k).to_i32();
                    let threshold = self.column_threshold_sum[j];
                    match (lo..=hi).find(|&k| response(k).abs() > threshold) {
                        None => self.no_boundary(j, image.height()),
                        Some(k) => {
                            self.crossings[j] = k;
                            self.confidence[j] = edge_confidence(response(k), threshold);
                            self.resolve_with(j, k, image.height(), response, pixel)
                        }
                    }
                }
            });
        }
        self.scan_band(image);
        self.skip_floor_lines(image);
        self.fill_scan(timestamp_s, out);
        Ok(())
    }

    /// Scans on, above a row, columns of the frame last scanned whose first boundary another
    /// cue found to be the floor's own (`crate::floor_parallax`): each `(j, row)` (j a
    /// reading's index, `row` its boundary row v) continues the search from the first row
    /// above `row` where the response has fallen back under the threshold, at that frame's
    /// thresholds; the column's new outcome replaces the old one and `out` is filled again.
    /// `image` must be the frame last scanned.
    pub fn continue_above<P: Pixel>(
        &mut self,
        image: &ImageView<P>,
        restarts: &[(usize, f64)],
        out: &mut Scan,
    ) -> Result<()> {
        self.check_size(image)?;
        let height = image.height() as f64;
        for &(j, row) in restarts {
            if j >= self.plans.len() || !(row.is_finite() && (0.0..height).contains(&row)) {
                continue;
            }
            if self.plans[j].window.is_none() {
                continue;
            }
            let outcome = self.search_above(image, j, row);
            self.outcomes[j] = Some(outcome);
            self.skip_column_floor_lines(image, j);
        }
        self.fill_scan(out.timestamp_s, out);
        Ok(())
    }

    /// The `mid_range_m` band's second look: in each column whose first crossing (at the
    /// frame's threshold) is not nearer than its band, the band's rows below that crossing
    /// are tested against the band's lower threshold; the first that crosses becomes the
    /// column's crossing. The same outcome as testing every row against its own threshold
    /// from the bottom up (the band's threshold is never the higher one).
    fn scan_band<P: Pixel>(&mut self, image: &ImageView<P>) {
        if !self.band_active {
            return;
        }
        let d = self.options.half_width_px;
        let height = image.height();
        for j in 0..self.plans.len() {
            let Some((band_lo, band_hi)) = self.plans[j].band else {
                continue;
            };
            let threshold = self.band_threshold_sum[j];
            if threshold >= self.column_threshold_sum[j] {
                continue;
            }
            // The band's rows below the first crossing: none when it lies at or before the band.
            let k_main = self.crossings[j];
            if k_main <= band_lo {
                continue;
            }
            let last = band_hi.min(k_main - 1);
            let c = self.plans[j].column as usize;
            let px = |k: usize| image.get(c, height - 1 - k).to_i32();
            // S(k) by the recurrence from the band's first row (four reads a row)
            let mut s = direct_response_at(image, c, band_lo, d);
            let mut crossing = None;
            for k in band_lo..=last {
                if k > band_lo {
                    s = next_response(s, px(k - 1 - d), px(k - 1), px(k), px(k + d));
                }
                if s.abs() > threshold {
                    crossing = Some((k, s));
                    break;
                }
            }
            if let Some((k, s)) = crossing {
                self.crossings[j] = k;
                self.confidence[j] = edge_confidence(s, threshold);
                self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
            }
        }
    }

    fn check_size<P: Pixel>(&self, image: &ImageView<P>) -> Result<()> {
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

    fn fill_scan(&self, timestamp_s: f64, out: &mut Scan) {
        out.timestamp_s = timestamp_s;
        out.readings.clear();
        out.readings.extend(
            self.plans
                .iter()
                .zip(&self.outcomes)
                .zip(&self.confidence)
                .map(|((plan, outcome), &confidence)| ColumnReading {
                    column: plan.column,
                    start_row: plan.start_row as f64,
                    near: plan.near,
                    outcome: outcome.unwrap_or(ColumnOutcome::Invalid { row: None }),
                    confidence: match outcome {
                        Some(ColumnOutcome::Boundary { .. } | ColumnOutcome::TooClose) => {
                            confidence
                        }
                        Some(ColumnOutcome::NoBoundary { .. }) => 1.0,
                        _ => 0.0,
                    },
                }),
        );
    }
}

#[path = "ranger_columns.rs"]
mod columns;
#[path = "ranger_floor_lines.rs"]
mod floor_lines;
#[path = "ranger_plan.rs"]
mod plan;
#[path = "ranger_resolve.rs"]
mod resolve;
#[path = "ranger_row_step.rs"]
mod row_step;
use plan::{plan_column, row_footprint_m, ColumnPlan};
use row_step::ColumnScratch;
#[path = "ranger_threshold.rs"]
mod threshold;
use resolve::edge_confidence;

#[cfg(test)]
#[path = "ranger_tests.rs"]
mod tests;
