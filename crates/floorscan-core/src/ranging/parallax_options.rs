//! Options of the floor-parallax cue (`[parallax]` in the config file, [`crate::floor_parallax`]):
//! whether the edge ranger's boundaries are checked against the motion between two frames, and
//! how.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Most earlier frames a [`crate::floor_parallax::FloorParallax`] may keep (memory: this many
/// frames of 4 bytes a pixel).
pub const MAX_HISTORY_FRAMES: usize = 64;

/// Options of [`crate::floor_parallax::FloorParallax`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct ParallaxOptions {
    /// Check each boundary of the edge ranger against the motion since an earlier frame where
    /// poses are known (`run`, `node`, `eval`; a single image is ranged as before). Default
    /// false: an opt-in until real frames with motion judge it (EVALUATION.md).
    pub enabled: bool,
    /// Least camera travel [m] between the current frame and the earlier one it is compared
    /// with, finite and > 0: the newest kept frame at least this far back is used; where none
    /// is, `min_turn_baseline_m` decides (a robot standing: the boundaries stay as ranged).
    /// Default 0.15 (0.5 s at 0.3 m/s).
    pub min_baseline_m: f64,
    /// Where no kept frame is `min_baseline_m` back, the kept frame farthest from the current
    /// camera is used if it is at least this far [m]: a robot turning on the spot moves its
    /// camera (mounted ahead of the wheels' axis) along a circle, and a robot that sees walls
    /// everywhere in its first frames (the grout of a tiled floor) only turns, so without this
    /// the cue never starts. In (0, `min_baseline_m`]; equal to `min_baseline_m` turns it off.
    /// Default 0.05 (a camera 0.12 m ahead of the axis turning 0.42 rad).
    pub min_turn_baseline_m: f64,
    /// Earlier frames kept, 1 ..= 64. Default 10 (1 s at 10 Hz).
    pub history_frames: usize,
    /// Rows above a boundary compared between the two frames, as a share of the image height,
    /// in (0, 0.5]. Default 0.125 (30 rows of 240).
    pub rows_above_fraction: f64,
    /// Least standard deviation [grey levels] of those rows for a test: a patch without
    /// texture cannot tell floor from a standing surface, and its boundary stays. Finite and
    /// >= 0. Default 2.
    pub min_texture_grey: f64,
    /// Gaussian blur applied to both frames before they are compared [px], finite, in
    /// [0, 5]; 0 for none. Default 1.
    pub blur_sigma_px: f64,
    /// Floor within this range [m] of the camera refines the odometry's motion (Lucas-Kanade
    /// on the floor between the two frames) and gives the residual's noise; finite and > 0.
    /// Default 1.
    pub refine_range_m: f64,
    /// Least log-likelihood ratio of "the rows above are floor" over "they stand on a vertical
    /// surface at the boundary" for the boundary to be the floor's own, finite. Default 0.
    pub min_log_likelihood_ratio: f64,
    /// How far [px] the warp between the two frames may be off (the table's and the motion's
    /// errors): each pixel's residual variance is the noise's plus (its gradient x this)^2,
    /// so a strong edge running along the motion, which both explanations place alike up to
    /// such errors, weighs little. Finite and >= 0. Default 0.5.
    pub warp_error_px: f64,
    /// Least distance [px, root mean square over the rows] between the two explanations'
    /// positions of the rows in the earlier frame for a test: closer, the frames cannot tell
    /// them apart (a wall along the motion, a short baseline, a low or far obstacle) and the
    /// boundary stays. Finite and >= 0. Default 1.5.
    pub min_separation_px: f64,
    /// Most boundaries of one column found to be the floor's own in one frame, 1 ..= 100.
    /// Default 10.
    pub max_vetoes: usize,
    /// Neighbouring columns' boundaries within this distance [m] of a boundary give directions
    /// the surface standing there may have (the line through both, to each alone), tried with
    /// the surface facing the camera; finite and > 0.
    /// Default 0.25.
    pub base_line_gap_m: f64,
    /// A memory of the floor's own edges, in the world (odometry's frame): a boundary found to
    /// be the floor's own marks its ground cell; once a cell was marked in this many different
    /// frames, a later boundary there (or in the 8 cells around) is taken as the floor's at
    /// once where the motion cannot tell (no earlier frame far enough back, no texture); a
    /// boundary whose rows the motion shows standing clears its cell. 0 turns it off; 0 ..=
    /// 100. Default 0 (off): with 2 it takes a tiled floor from 86 to 51 % of columns wrong
    /// but carries the cue's mistakes on carpets forward (EVALUATION.md, "The floor-parallax
    /// cue").
    pub memory_min_frames: u32,
    /// Cell of that memory [m], in [0.01, 0.5]. Default 0.05.
    pub memory_cell_m: f64,
    /// Cells farther than this [m] from the camera are forgotten (odometry's drift makes old
    /// marks wrong), in (0, 20]. Default 3.
    pub memory_radius_m: f64,
    /// Where a vetoed boundary has no edge above it (the floor seen to the end of the
    /// column's range), the motion looks for a standing surface above it: rows tested every
    /// quarter of `rows_above_fraction`, the first whose rows above move as a surface standing
    /// there (log-likelihood ratio below minus `min_standing_log_likelihood_ratio`) is the
    /// boundary. Once the floor's own edges are vetoed, a wall or a baseboard fainter than the
    /// frame's threshold (set by the floor's texture) is no edge: without this the column
    /// reports floor where the wall stands. Default true.
    pub search_above_vetoed: bool,
    /// Evidence [nats] a row's test needs to place a boundary in that search, finite and >= 0.
    /// Default 2.
    pub min_standing_log_likelihood_ratio: f64,
}

impl Default for ParallaxOptions {
    fn default() -> Self {
        Self {
            enabled: false,
            min_baseline_m: 0.15,
            min_turn_baseline_m: 0.05,
            history_frames: 10,
            rows_above_fraction: 0.125,
            min_texture_grey: 2.0,
            blur_sigma_px: 1.0,
            refine_range_m: 1.0,
            min_log_likelihood_ratio: 0.0,
            warp_error_px: 0.5,
            min_separation_px: 1.5,
            max_vetoes: 10,
            base_line_gap_m: 0.25,
            memory_min_frames: 0,
            memory_cell_m: 0.05,
            memory_radius_m: 3.0,
            search_above_vetoed: true,
            min_standing_log_likelihood_ratio: 2.0,
        }
    }
}

impl ParallaxOptions {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        let positive = |name: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(())
            } else {
                Err(invalid_option(
                    name,
                    format!("must be finite and > 0, got {v}"),
                ))
            }
        };
        positive("min_baseline_m", self.min_baseline_m)?;
        let turn = self.min_turn_baseline_m;
        if !(turn > 0.0 && turn <= self.min_baseline_m) {
            return Err(invalid_option(
                "min_turn_baseline_m",
                format!(
                    "must be in (0, min_baseline_m = {}], got {turn}",
                    self.min_baseline_m
                ),
            ));
        }
        positive("refine_range_m", self.refine_range_m)?;
        positive("base_line_gap_m", self.base_line_gap_m)?;
        let standing = self.min_standing_log_likelihood_ratio;
        if !(standing.is_finite() && standing >= 0.0) {
            return Err(invalid_option(
                "min_standing_log_likelihood_ratio",
                format!("must be finite and >= 0, got {standing}"),
            ));
        }
        if !(1..=MAX_HISTORY_FRAMES).contains(&self.history_frames) {
            return Err(invalid_option(
                "history_frames",
                format!(
                    "must be in 1 ..= {MAX_HISTORY_FRAMES}, got {}",
                    self.history_frames
                ),
            ));
        }
        if !(self.rows_above_fraction > 0.0 && self.rows_above_fraction <= 0.5) {
            return Err(invalid_option(
                "rows_above_fraction",
                format!("must be in (0, 0.5], got {}", self.rows_above_fraction),
            ));
        }
        if !(self.min_texture_grey.is_finite() && self.min_texture_grey >= 0.0) {
            return Err(invalid_option(
                "min_texture_grey",
                format!("must be finite and >= 0, got {}", self.min_texture_grey),
            ));
        }
        if !(0.0..=5.0).contains(&self.blur_sigma_px) {
            return Err(invalid_option(
                "blur_sigma_px",
                format!("must be in [0, 5], got {}", self.blur_sigma_px),
            ));
        }
        if !self.min_log_likelihood_ratio.is_finite() {
            return Err(invalid_option(
                "min_log_likelihood_ratio",
                format!("must be finite, got {}", self.min_log_likelihood_ratio),
            ));
        }
        if !(self.warp_error_px.is_finite() && self.warp_error_px >= 0.0) {
            return Err(invalid_option(
                "warp_error_px",
                format!("must be finite and >= 0, got {}", self.warp_error_px),
            ));
        }
        if !(self.min_separation_px.is_finite() && self.min_separation_px >= 0.0) {
            return Err(invalid_option(
                "min_separation_px",
                format!("must be finite and >= 0, got {}", self.min_separation_px),
            ));
        }
        if self.memory_min_frames > 100 {
            return Err(invalid_option(
                "memory_min_frames",
                format!("must be in 0 ..= 100, got {}", self.memory_min_frames),
            ));
        }
        if !(self.memory_cell_m.is_finite() && (0.01..=0.5).contains(&self.memory_cell_m)) {
            return Err(invalid_option(
                "memory_cell_m",
                format!("must be in [0.01, 0.5], got {}", self.memory_cell_m),
            ));
        }
        if !(self.memory_radius_m > 0.0 && self.memory_radius_m <= 20.0) {
            return Err(invalid_option(
                "memory_radius_m",
                format!("must be in (0, 20], got {}", self.memory_radius_m),
            ));
        }
        if !(1..=100).contains(&self.max_vetoes) {
            return Err(invalid_option(
                "max_vetoes",
                format!("must be in 1 ..= 100, got {}", self.max_vetoes),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "parallax_options_tests.rs"]
mod tests;
