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
    direct_response_at, next_response, ramp_above, refine_crossing, sharpest_step,
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

/// A sampled column's fixed geometry, worked out once from the table and the options.
#[derive(Debug, Clone, Copy)]
struct ColumnPlan {
    column: u32,
    /// Start row v (from the top).
    start_row: usize,
    /// The start row as configured; `start_row` moves to `first_ground_row` while the rows at
    /// this one are a lens's dark rim (`dark_rim`).
    nominal_start: usize,
    /// The ground point of the column's lowest row with ground, at or above the start row.
    near: Option<Point2>,
    /// That row (v), `None` without ground.
    first_ground_row: Option<usize>,
    /// Rows (k, counted from the bottom) where a crossing is tested: `lo..=hi`, from the start
    /// row up to the last row with ground. `None` when the column cannot be scanned (no ground
    /// at or above its start, or too few rows for the filter).
    window: Option<(usize, usize)>,
    /// The rows of `window` whose ground lies within the options' `mid_range_m` (the band of
    /// the lower contrast floor), `None` when there are none.
    band: Option<(usize, usize)>,
}

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
    // Per-frame scratch, indexed like `plans`.
    sums: Vec<i32>,
    active_threshold: Vec<i32>,
    offsets: Vec<usize>,
    /// The sampled pixels of the last 2d + 2 rows (row k in slot k mod (2d + 2)), so sparse
    /// columns are gathered once per row and updated from contiguous memory.
    ring: Vec<u16>,
    /// Largest entry of `offsets` for the current frame.
    max_offset: usize,
    /// The 8-bit path's buffers: 16-bit sums and thresholds (i16::MAX: not tested), the crossing
    /// masks of the last row step (one word per LANES columns), and the byte ring.
    kernel: Kernel,
    sums16: Vec<i16>,
    active_threshold16: Vec<i16>,
    masks: Vec<u32>,
    ring8: Vec<u8>,
    /// Whether this frame's scan uses the prefilter, each column's prefilter byte threshold
    /// for the frame (see [`lanes::prefilter_threshold`]), and the active per-column byte
    /// thresholds (255: column not tested) and flags.
    prefilter: bool,
    column_prefilter: Vec<u8>,
    thresholds8: Vec<u8>,
    flags: Vec<u8>,
    outcomes: Vec<Option<ColumnOutcome>>,
    /// Per column: the confidence of its outcome (see [`edge_confidence`]).
    confidence: Vec<f32>,
    /// The near-floor band's responses of one frame (see [`crate::noise_threshold`]), sized
    /// once; and the threshold the last frame was scanned with.
    noise_samples: Vec<i32>,
    /// Scratch histogram of the noise samples (sized once, [`MAX_HISTOGRAM_SPAN`] counts).
    noise_histogram: Vec<u32>,
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
        let small_d = d <= MAX_HALF_WIDTH_I16;
        let mut ranger = Self {
            column_threshold_sum: vec![threshold_sum; n],
            offsets: vec![0; n],
            ring: vec![0; (2 * d + 2) * n],
            max_offset: 0,
            kernel: Kernel::detect(),
            sums16: vec![0; if small_d { n } else { 0 }],
            active_threshold16: vec![i16::MAX; n],
            masks: vec![0; n.div_ceil(LANES)],
            ring8: vec![0; if small_d { ring8_rows(d) * n } else { 0 }],
            prefilter: prefilter.is_some(),
            column_prefilter: vec![prefilter.unwrap_or(u8::MAX); n],
            thresholds8: vec![u8::MAX; n],
            flags: vec![0; n],
            sums: vec![0; n],
            active_threshold: vec![i32::MAX; n],
            outcomes: vec![None; n],
            confidence: vec![1.0; n],
            footprints_m,
            noise_samples: Vec::new(),
            noise_histogram: vec![0; MAX_HISTOGRAM_SPAN],
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

    /// Sets each column's threshold for this frame from its near-floor band (when
    /// `noise_multiple` or `contrast` is > 0): max(threshold, noise_multiple x sigma of the
    /// frame, contrast x the column's mean brightness).
    fn set_frame_threshold<P: Pixel>(&mut self, image: &ImageView<P>) {
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
        let d = self.options.half_width_px;
        let height = image.height();
        for &(j, row) in restarts {
            let Some(plan) = self.plans.get(j).copied() else {
                continue;
            };
            let Some((lo, hi)) = plan.window else {
                continue;
            };
            if !(row.is_finite() && (0.0..height as f64).contains(&row)) {
                continue;
            }
            let c = plan.column as usize;
            let threshold = self.column_threshold_sum[j];
            let response = |k| direct_response_at(image, c, k, d);
            // leave the vetoed edge's own crossing, then find the next one whose refined row
            // lies above it (a line's far side, within the filter's reach, refines back onto
            // the same step)
            let mut k = (((height - 1) as f64 - row).round() as usize).max(lo + 1);
            let outcome = loop {
                while k <= hi && response(k).abs() > threshold {
                    k += 1;
                }
                let Some(k_cross) = (k..=hi).find(|&k| response(k).abs() > threshold) else {
                    break self.no_boundary(j, height);
                };
                let outcome = self.resolve_with(j, k_cross, height, response, |k| {
                    image.get(c, height - 1 - k).to_i32()
                });
                match outcome {
                    ColumnOutcome::Boundary { row: r, .. } if r > row - 1.0 => k = k_cross + 1,
                    _ => {
                        self.crossings[j] = k_cross;
                        self.confidence[j] = edge_confidence(response(k_cross), threshold);
                        break outcome;
                    }
                }
            };
            self.outcomes[j] = Some(outcome);
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

    fn run_columns<P: Pixel>(&mut self, image: &ImageView<P>) {
        let height = image.height();
        let d = self.options.half_width_px;
        let row_of = |k: usize| height - 1 - k;
        self.crossings.fill(usize::MAX);
        for (o, plan) in self.outcomes.iter_mut().zip(&self.plans) {
            *o = plan
                .window
                .is_none()
                .then_some(ColumnOutcome::Invalid { row: None });
        }
        if self.by_lo.is_empty() {
            return;
        }
        for (off, plan) in self.offsets.iter_mut().zip(&self.plans) {
            *off = plan.column as usize * image.col_stride();
        }
        self.max_offset = self.offsets.iter().copied().max().unwrap_or(0);
        // Consecutive image columns in a contiguous row: plain slices, which vectorise.
        let contiguous =
            image.col_stride() == 1 && self.offsets.windows(2).all(|w| w[1] == w[0] + 1);
        if let Some(bytes) = image.as_u8() {
            if self.prefilter {
                self.run_columns_prefiltered(&bytes, contiguous);
                return;
            }
            if d <= MAX_HALF_WIDTH_I16 {
                self.run_columns_u8(&bytes, contiguous);
                return;
            }
        }
        let ring_rows = 2 * d + 2;
        self.active_threshold.fill(i32::MAX);
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        for (j, plan) in self.plans.iter().enumerate() {
            self.sums[j] = direct_response_at(image, plan.column as usize, k_first, d);
        }
        if !contiguous {
            for k in k_first - d..=k_first + d {
                self.gather_row(image, k, ring_rows);
            }
        }
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut events, k, height, &mut unresolved);
        let mut any_crossing = self
            .sums
            .iter()
            .zip(&self.active_threshold)
            .fold(false, |any, (s, t)| any | (s.abs() > *t));
        loop {
            if any_crossing {
                for j in 0..self.plans.len() {
                    if self.sums[j].abs() > self.active_threshold[j] {
                        self.confidence[j] =
                            edge_confidence(self.sums[j], self.column_threshold_sum[j]);
                        self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                        self.crossings[j] = k;
                        self.active_threshold[j] = i32::MAX;
                        unresolved -= 1;
                    }
                }
            }
            if unresolved == 0 {
                break;
            }
            // Past height - 1 - d no window fits in the image; no column tests a row there
            // either (every window ends at or below it), so the events of k + 1 close them all.
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            // Advance every running sum from k - 1 to k and test it, in one pass.
            any_crossing = if contiguous {
                let (o, n) = (self.offsets[0], self.offsets.len());
                let row = |k: usize| &image.row(row_of(k))[o..o + n];
                advance_contiguous(
                    &mut self.sums,
                    &self.active_threshold,
                    [row(k - 1 - d), row(k - 1), row(k), row(k + d)],
                )
            } else {
                self.gather_row(image, k + d, ring_rows);
                let n = self.plans.len();
                let slot = |k: usize| &self.ring[(k % ring_rows) * n..(k % ring_rows + 1) * n];
                advance_contiguous(
                    &mut self.sums,
                    &self.active_threshold,
                    [slot(k - 1 - d), slot(k - 1), slot(k), slot(k + d)],
                )
            };
        }
    }

    /// `run_columns` for 8-bit images: 16-bit sums advanced by the lane kernels, which mark
    /// the columns that crossed.
    fn run_columns_u8(&mut self, image: &ImageView<u8>, contiguous: bool) {
        let height = image.height();
        let d = self.options.half_width_px;
        let n = self.plans.len();
        let row_of = |k: usize| height - 1 - k;
        let ring_rows = ring8_rows(d);
        self.active_threshold.fill(i32::MAX);
        self.active_threshold16.fill(i16::MAX);
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        // First sums S(k_first) of every column, row-major: the d rows above minus the d below.
        self.sums16.fill(0);
        if contiguous {
            let o = self.offsets[0];
            for i in 1..=d {
                lanes::accumulate_row(&mut self.sums16, &image.row(row_of(k_first + i))[o..], true);
                lanes::accumulate_row(
                    &mut self.sums16,
                    &image.row(row_of(k_first - i))[o..],
                    false,
                );
            }
        } else {
            for k in k_first - d..=k_first + d {
                self.gather_row8(image, k, ring_rows);
            }
            let slot = |k: usize| (k & (ring_rows - 1)) * n;
            for i in 1..=d {
                let (up, down) = (slot(k_first + i), slot(k_first - i));
                lanes::accumulate_row(&mut self.sums16, &self.ring8[up..up + n], true);
                lanes::accumulate_row(&mut self.sums16, &self.ring8[down..down + n], false);
            }
        }
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut events, k, height, &mut unresolved);
        let mut any_crossing =
            lanes::test_sums(&self.sums16, &self.active_threshold16, &mut self.masks);
        loop {
            if any_crossing {
                for chunk in 0..self.masks.len() {
                    let mut m = self.masks[chunk];
                    while m != 0 {
                        let lane = m.trailing_zeros() as usize / 2;
                        m &= !lanes::lane_bits(lane);
                        let j = chunk * LANES + lane;
                        let s = i32::from(self.sums16[j]);
                        self.confidence[j] = edge_confidence(s, self.column_threshold_sum[j]);
                        self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                        self.crossings[j] = k;
                        self.active_threshold[j] = i32::MAX;
                        self.active_threshold16[j] = i16::MAX;
                        unresolved -= 1;
                    }
                }
            }
            if unresolved == 0 {
                break;
            }
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            any_crossing = if contiguous {
                let o = self.offsets[0];
                let row = |k: usize| &image.row(row_of(k))[o..o + n];
                lanes::advance_u8(
                    self.kernel,
                    &mut self.sums16,
                    &self.active_threshold16,
                    [row(k - 1 - d), row(k - 1), row(k), row(k + d)],
                    &mut self.masks,
                )
            } else {
                self.gather_row8(image, k + d, ring_rows);
                let slot = |k: usize| {
                    &self.ring8[(k & (ring_rows - 1)) * n..((k & (ring_rows - 1)) + 1) * n]
                };
                lanes::advance_u8(
                    self.kernel,
                    &mut self.sums16,
                    &self.active_threshold16,
                    [slot(k - 1 - d), slot(k - 1), slot(k), slot(k + d)],
                    &mut self.masks,
                )
            };
        }
    }

    /// `run_columns` for 8-bit images where the prefilter applies (d a power of two): each row
    /// step flags, from byte averages, the columns that may cross; only those get the exact
    /// sum of eq. (1), from the 2d rows around the pixel.
    fn run_columns_prefiltered(&mut self, image: &ImageView<u8>, contiguous: bool) {
        let height = image.height();
        let d = self.options.half_width_px;
        let n = self.plans.len();
        let ring_rows = ring8_rows(d);
        self.active_threshold.fill(i32::MAX);
        self.active_threshold16.fill(i16::MAX);
        self.thresholds8.fill(u8::MAX);
        let k_first = self.plans[self.by_lo[0]].window.unwrap().0;
        if !contiguous {
            for k in k_first - d..=k_first + d {
                self.gather_row8(image, k, ring_rows);
            }
        }
        let o = self.offsets[0];
        let mut unresolved = self.by_lo.len();
        let mut events = EventCursor::default();
        let mut k = k_first;
        self.apply_window_events(&mut events, k, height, &mut unresolved);
        loop {
            let mut rows: [&[u8]; 2 * lanes::MAX_PREFILTER_HALF_WIDTH + 1] =
                [&[]; 2 * lanes::MAX_PREFILTER_HALF_WIDTH + 1];
            // Rows k - d ..= k + d (from the image, or from the ring of gathered columns).
            for (i, r) in rows[..2 * d + 1].iter_mut().enumerate() {
                let kk = k + i - d;
                *r = if contiguous {
                    &image.row(height - 1 - kk)[o..o + n]
                } else {
                    let slot = kk & (ring_rows - 1);
                    &self.ring8[slot * n..(slot + 1) * n]
                };
            }
            let rows = &rows[..2 * d + 1];
            if lanes::prefilter_u8(self.kernel, rows, &self.thresholds8, &mut self.flags) {
                let words = n / 8;
                for w in 0..=words {
                    let word = if w < words {
                        u64::from_le_bytes(self.flags[8 * w..8 * w + 8].try_into().unwrap())
                    } else {
                        self.flags[8 * w..]
                            .iter()
                            .rev()
                            .fold(0u64, |acc, &f| (acc << 8) | f as u64)
                    };
                    let mut word = word;
                    while word != 0 {
                        let j = 8 * w + word.trailing_zeros() as usize / 8;
                        word &= !(0xFFu64 << (8 * (j - 8 * w)));
                        let s: i32 = (1..=d)
                            .map(|t| rows[d + t][j] as i32 - rows[d - t][j] as i32)
                            .sum();
                        let threshold = self.column_threshold_sum[j];
                        if s.abs() > threshold {
                            self.confidence[j] = edge_confidence(s, threshold);
                            self.outcomes[j] = Some(self.resolve_crossing(image, j, k));
                            self.crossings[j] = k;
                            self.active_threshold[j] = i32::MAX;
                            self.active_threshold16[j] = i16::MAX;
                            self.thresholds8[j] = u8::MAX;
                            unresolved -= 1;
                        }
                    }
                }
            }
            if unresolved == 0 {
                break;
            }
            let can_advance = k + d + 1 < height;
            k += 1;
            self.apply_window_events(&mut events, k, height, &mut unresolved);
            if unresolved == 0 || !can_advance {
                break;
            }
            if !contiguous {
                self.gather_row8(image, k + d, ring_rows);
            }
        }
    }

    /// Copies the sampled pixels of 8-bit row k (from the bottom) into its byte-ring slot.
    fn gather_row8(&mut self, image: &ImageView<u8>, k: usize, ring_rows: usize) {
        let n = self.plans.len();
        let start = (k & (ring_rows - 1)) * n;
        let row = image.row(image.height() - 1 - k);
        // As in `gather_row`: one check of the largest offset covers every pixel.
        assert!(self.max_offset < row.len(), "column offset outside the row");
        for (dst, &o) in self.ring8[start..start + n].iter_mut().zip(&self.offsets) {
            // SAFETY: o <= max_offset < row.len() (asserted above).
            *dst = unsafe { *row.get_unchecked(o) };
        }
    }

    /// Copies the sampled pixels of row k (from the bottom) into its ring slot.
    fn gather_row<P: Pixel>(&mut self, image: &ImageView<P>, k: usize, ring_rows: usize) {
        let n = self.plans.len();
        let start = (k % ring_rows) * n;
        let row = image.row(image.height() - 1 - k);
        // Offsets come from columns checked against the image width when the ranger was built
        // (and the image size against the table's), so every offset is inside the row; one
        // check of the largest replaces a bounds check per pixel.
        assert!(self.max_offset < row.len(), "column offset outside the row");
        for (dst, &o) in self.ring[start..start + n].iter_mut().zip(&self.offsets) {
            // SAFETY: o <= max_offset < row.len() (asserted above).
            *dst = unsafe { row.get_unchecked(o) }.to_i32() as u16;
        }
    }

    /// Opens the test windows that start at k and closes those that ended below k (no edge:
    /// free up to the column's top row).
    fn apply_window_events(
        &mut self,
        cursor: &mut EventCursor,
        k: usize,
        height: usize,
        unresolved: &mut usize,
    ) {
        while cursor.lo < self.by_lo.len()
            && self.plans[self.by_lo[cursor.lo]].window.unwrap().0 <= k
        {
            let j = self.by_lo[cursor.lo];
            if self.outcomes[j].is_none() {
                let threshold = self.column_threshold_sum[j];
                self.active_threshold[j] = threshold;
                // Inside the 8-bit path |S| <= 255 d < i16::MAX, so a clamped threshold tests
                // the same.
                self.active_threshold16[j] = threshold.clamp(-1, i16::MAX as i32) as i16;
                self.thresholds8[j] = self.column_prefilter[j];
            }
            cursor.lo += 1;
        }
        while cursor.hi < self.by_hi.len()
            && self.plans[self.by_hi[cursor.hi]].window.unwrap().1 < k
        {
            let j = self.by_hi[cursor.hi];
            cursor.hi += 1;
            if self.outcomes[j].is_none() {
                self.outcomes[j] = Some(self.no_boundary(j, height));
                self.active_threshold[j] = i32::MAX;
                self.active_threshold16[j] = i16::MAX;
                self.thresholds8[j] = u8::MAX;
                *unresolved -= 1;
            }
        }
    }

    fn no_boundary(&self, j: usize, height: usize) -> ColumnOutcome {
        let plan = &self.plans[j];
        let top_row = (height - 1 - plan.window.unwrap().1) as f64;
        match self.table.lookup(plan.column as f64, top_row) {
            Some(farthest) => ColumnOutcome::NoBoundary { top_row, farthest },
            None => ColumnOutcome::Invalid { row: None },
        }
    }

    /// Resolves the crossing of column j at row k_cross. The refinement's responses come from
    /// prefix sums of the few pixels around the crossing, read once (exact integers: the
    /// direct sums of eq. (1)).
    fn resolve_crossing<P: Pixel>(
        &self,
        image: &ImageView<P>,
        j: usize,
        k_cross: usize,
    ) -> ColumnOutcome {
        let plan = &self.plans[j];
        let (lo, _) = plan.window.unwrap();
        let d = self.options.half_width_px;
        let height = image.height();
        let c = plan.column as usize;
        if k_cross == lo || self.options.refinement == crate::edge::Refinement::FirstCrossing {
            return self.resolve_with(j, k_cross, height, |_| 0, |_| 0);
        }
        // The refinement asks for S(k) with k in k_cross - 1 ..= min(k_cross + d + 1, k_max),
        // and the step refinement for pixels inside those windows and up a ramp above them
        // (`ramp_top`); those read the pixels base ..= top (k_cross > lo >= d, so base >= 0).
        let base = k_cross - 1 - d;
        let top = ramp_top(k_cross, d, height);
        const SEGMENT: usize = 64;
        if top - base + 2 > SEGMENT {
            return self.resolve_with(
                j,
                k_cross,
                height,
                |k| direct_response_at(image, c, k, d),
                |k| image.get(c, height - 1 - k).to_i32(),
            );
        }
        let mut prefix = [0i32; SEGMENT];
        let mut total = 0;
        for (t, k) in (base..=top).enumerate() {
            total += image.get(c, height - 1 - k).to_i32();
            prefix[t + 1] = total;
        }
        let p = |k: usize| prefix[k - base];
        self.resolve_with(
            j,
            k_cross,
            height,
            |k| (p(k + d + 1) - p(k + 1)) - (p(k) - p(k - d)),
            |k| p(k + 1) - p(k),
        )
    }

    /// The outcome of column j whose response first crossed at k_cross, `response(k)` giving
    /// S(k) and `pixel(k)` the column's pixel k (from the bottom) for the refinement.
    fn resolve_with(
        &self,
        j: usize,
        k_cross: usize,
        height: usize,
        mut response: impl FnMut(usize) -> i32,
        mut pixel: impl FnMut(usize) -> i32,
    ) -> ColumnOutcome {
        let plan = &self.plans[j];
        let (lo, hi) = plan.window.unwrap();
        if k_cross == lo {
            return ColumnOutcome::TooClose;
        }
        let d = self.options.half_width_px;
        let c = plan.column as usize;
        // Pixels exist for windows centred up to height - 1 - d; the refinement may look past
        // the column's top limit by up to d rows to find the peak.
        let k_max = height - 1 - d;
        let k = match self.options.refinement {
            Refinement::Step => {
                let sign = if response(k_cross) >= 0 { 1 } else { -1 };
                let peak = refine_crossing(Refinement::SubPixel, k_cross, d, lo, k_max, response);
                let (radius, top) = (d as f64 / 2.0, ramp_top(k_cross, d, height));
                let cap = RAMP_ROWS_PER_HALF_WIDTH * d;
                let above = ramp_above(peak.k, radius, sign, cap, top, &mut pixel);
                sharpest_step(peak.k, sign, radius, above, k_cross - 1 - d, top, pixel)
            }
            r => refine_crossing(r, k_cross, d, lo, k_max, response).k,
        };
        // A refined edge above the column's last scanned row lies past its ground (the table's
        // or the range limit's): beyond what the column can place, so free up to that row.
        if k > hi as f64 {
            return self.no_boundary(j, height);
        }
        let row = (height - 1) as f64 - k;
        match self.table.lookup(c as f64, row) {
            Some(point) => {
                // Floor covered by one pixel row at the boundary: the reading's range resolution.
                let v = (row.round().max(0.0) as usize).min(height - 1);
                let footprint_m = self.footprints_m[j * height + v] as f64;
                ColumnOutcome::Boundary {
                    row,
                    point,
                    footprint_m,
                }
            }
            None => ColumnOutcome::Invalid { row: Some(row) },
        }
    }
}

/// The highest pixel (from the bottom) the step refinement of a crossing at `k_cross` reads:
/// the box filter's windows around the crossing, then a ramp of up to
/// `RAMP_ROWS_PER_HALF_WIDTH` x d rows above them (`edge::ramp_above`), within the image.
pub(crate) fn ramp_top(k_cross: usize, d: usize, height: usize) -> usize {
    let k_max = height - 1 - d;
    ((k_cross + d + 1).min(k_max) + d + RAMP_ROWS_PER_HALF_WIDTH * d + 2).min(height - 1)
}

/// Rows of the byte ring: at least the 2d + 2 a row step reads, a power of two (slot = k & mask).
fn ring8_rows(d: usize) -> usize {
    (2 * d + 2).next_power_of_two()
}

/// Confidence of an edge whose raw response `s` crossed `threshold_sum`: 1 - t / |S|, 0 at the
/// threshold, towards 1 for edges far above it.
fn edge_confidence(s: i32, threshold_sum: i32) -> f32 {
    let m = s.unsigned_abs() as f32;
    if m <= 0.0 {
        0.0
    } else {
        (1.0 - threshold_sum.max(0) as f32 / m).clamp(0.0, 1.0)
    }
}

/// Positions in the ranger's window-start and window-end orders.
#[derive(Default)]
struct EventCursor {
    lo: usize,
    hi: usize,
}

/// `S(k) = S(k-1) + I(k+d) - I(k) - I(k-1) + I(k-1-d)` for every column whose pixels are the
/// consecutive elements of the four rows `[k-1-d, k-1, k, k+d]`; returns whether any column's
/// new |S| exceeds its active threshold.
#[inline]
fn advance_contiguous<P: Pixel>(sums: &mut [i32], thresholds: &[i32], rows: [&[P]; 4]) -> bool {
    // Equal-length slices and an index loop: the form LLVM vectorises reliably.
    let n = sums.len();
    let (t, a, b, c, e) = (
        &thresholds[..n],
        &rows[0][..n],
        &rows[1][..n],
        &rows[2][..n],
        &rows[3][..n],
    );
    let mut hits = 0i32;
    for i in 0..n {
        let v = sums[i] + e[i].to_i32() - c[i].to_i32() - b[i].to_i32() + a[i].to_i32();
        sums[i] = v;
        hits |= (v.abs() > t[i]) as i32;
    }
    hits != 0
}

/// Floor length [m] that pixel row v of column u covers (between the row's upper and lower
/// edges); 0 where either edge has no ground.
fn row_footprint_m(table: &GroundTable, column: u32, v: f64) -> f64 {
    match (
        table.lookup(column as f64, v - 0.5),
        table.lookup(column as f64, v + 0.5),
    ) {
        (Some(a), Some(b)) => (a.x - b.x).hypot(a.y - b.y),
        _ => 0.0,
    }
}

/// Works out where a column's scan starts and how far up it may go.
fn plan_column(
    table: &GroundTable,
    options: &RangerOptions,
    column: u32,
    start_row: usize,
) -> ColumnPlan {
    let height = table.image_height();
    let d = options.half_width_px;
    let u = column as f64;
    let within_range = |p: Point2| options.max_range_m.is_none_or(|r| p.norm() <= r);
    // The column's near edge of view is its lowest row, from the start up, with ground. Rows
    // below it (an image corner the table does not trust: a fisheye's sides near the robot)
    // are still scanned, as the paper's ranger takes the bottom rows for floor, but an edge
    // there cannot be placed (invalid). One in the first window is too close: the obstacle
    // then covers the column up to its first row with ground, so it stands on that row's ray
    // at or before `near`, where the map marks it (as for any too-close column).
    let rows = table.column_ground_rows(u, start_row, within_range);
    let near = rows.and_then(|(first, _)| table.lookup(u, first as f64));
    let mut window = None;
    let mut band = None;
    if let Some((_, top)) = rows {
        let k_start = height - 1 - start_row;
        let lo = k_start + d;
        let hi = (height - 1 - top).min(height - 1 - d);
        if lo <= hi {
            window = Some((lo, hi));
            let (near_m, far_m) = (options.mid_range_m[0], options.mid_range_m[1]);
            if near_m < far_m {
                let in_band = |k: usize| {
                    table
                        .lookup(u, (height - 1 - k) as f64)
                        .is_some_and(|p| (near_m..=far_m).contains(&p.norm()))
                };
                let first = (lo..=hi).find(|&k| in_band(k));
                band = first.map(|b_lo| {
                    let b_hi = (b_lo..=hi)
                        .take_while(|&k| in_band(k))
                        .last()
                        .unwrap_or(b_lo);
                    (b_lo, b_hi)
                });
            }
        }
    }
    ColumnPlan {
        column,
        start_row,
        nominal_start: start_row,
        near,
        first_ground_row: rows.map(|(first, _)| first),
        window,
        band,
    }
}

#[cfg(test)]
#[path = "ranger_tests.rs"]
mod tests;
