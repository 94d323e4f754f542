//! Options of the appearance range sensor: one documented structure, validated when the ranger
//! is built. The `[appearance]` table of the TOML config file is exactly these fields.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};
use crate::floor_model::INTENSITY_BINS;
use crate::ground_table::GroundTable;
use crate::ranger_options::{ColumnSelection, ColumnStart, RangerOptions};

/// Which appearance statistics a pixel must match to look like floor.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum AppearanceFeatures {
    /// Colour only (intensity and two chroma axes).
    Colour,
    /// Colour and local texture (gradient magnitude).
    ColourAndTexture,
}

/// Options of [`crate::appearance::AppearanceRanger`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct AppearanceOptions {
    /// Sampled columns. Default: 64 evenly spaced (as the edge ranger).
    pub columns: ColumnSelection,
    /// Start of each column's scan. Default: 2 px bottom margin (as the edge ranger).
    pub start: ColumnStart,
    /// Farthest ground range scanned [m]; `None` (written `inf`): as far as the table has
    /// ground. Default 3 m.
    #[serde(with = "crate::ranger_options::range_limit")]
    #[cfg_attr(feature = "schema", schemars(with = "f64"))]
    pub max_range_m: Option<f64>,
    /// Height of the reference band of floor, just above each column's start row, as a share
    /// of the image height, in (0, 0.5]. Default 0.1 (the floor nearest the robot).
    pub reference_fraction: f64,
    /// Width of the reference band, centred on the image, as a share of the image width, in
    /// (0, 1]: the floor straight ahead of the robot (Ulrich & Nourbakhsh's reference area in
    /// front of the robot), so furniture and walls that reach the bottom corners of the image
    /// are not learned as floor and their columns can read `too_close`. Default 0.5
    /// (EVALUATION.md, "Real floors": the real floor set, clip-wise cross-validated, and the
    /// simulated suite).
    pub reference_width_fraction: f64,
    /// Statistics compared. Default: colour and texture.
    pub features: AppearanceFeatures,
    /// A pixel looks like floor when at least this share of the reference lies within one bin
    /// of its colour (and of its texture), in (0, 1). Default 0.003.
    pub min_floor_share: f64,
    /// How far in intensity a pixel may lie from reference pixels and still match them, in
    /// intensity bins of 16 grey levels (the chroma reach is one bin), in 1..=15. Default 1.
    pub intensity_reach_bins: usize,
    /// Half-width of the horizontal patch classified around each column [px]: a row of the
    /// column is not floor when most of its 2w + 1 pixels are not. Default 2.
    pub patch_half_width_px: usize,
    /// Rows in a run of non-floor rows that makes a boundary (the lowest row of the run is the
    /// boundary), >= 1. Default 3 (as the floor-mask truth).
    pub min_run_px: usize,
    /// Weight of the newest frame's reference in the model, in (0, 1]; 1 relearns every frame.
    /// Default 0.5.
    pub adaptation_rate: f64,
    /// Refresh from floor the robot has driven over: a boundary whose ground point the robot's
    /// origin later passes within this distance [m] was floor, and its pixels (the run that
    /// stopped the scan) are learned as floor where the frame taken there confirms them (its
    /// reference band looks like them); in [0, 2], 0 turns the refresh off. Used where the poses are known (`floorscan
    /// run`, `floorscan eval`, `floorscan drive`). Default 0.1 (well inside a small robot's
    /// footprint, so a boundary passed beside is not taken as driven over).
    pub driven_floor_radius_m: f64,
    /// Driven-over pixels within one bin of a colour (or texture) needed to take it as floor,
    /// in [1, 10000]. Default 8 (two boundaries' worth: one odometry slip past a real
    /// obstacle's base does not teach it).
    pub driven_floor_samples: f64,
    /// Half-life of the driven-over samples [frames], in [1, 1e6]. Default 600 (a minute at
    /// 10 frames/s: the floor of the rooms just driven through).
    pub driven_floor_half_life_frames: f64,
}

impl Default for AppearanceOptions {
    fn default() -> Self {
        let edge = RangerOptions::default();
        Self {
            columns: edge.columns,
            start: edge.start,
            max_range_m: edge.max_range_m,
            reference_fraction: 0.1,
            reference_width_fraction: 0.5,
            features: AppearanceFeatures::ColourAndTexture,
            min_floor_share: 0.003,
            intensity_reach_bins: 1,
            patch_half_width_px: 2,
            min_run_px: 3,
            adaptation_rate: 0.5,
            driven_floor_radius_m: 0.1,
            driven_floor_samples: 8.0,
            driven_floor_half_life_frames: 600.0,
        }
    }
}

/// Largest patch half-width and run accepted [px] (far beyond any image's useful values).
pub const MAX_PATCH_PX: usize = 256;

impl AppearanceOptions {
    /// Checks every field that does not depend on the image size.
    pub fn validate(&self) -> Result<()> {
        let share = |name: &'static str, v: f64, hi_inclusive: bool| {
            let ok = v.is_finite() && v > 0.0 && if hi_inclusive { v <= 1.0 } else { v < 1.0 };
            if ok {
                Ok(())
            } else {
                Err(invalid_option(
                    name,
                    format!(
                        "must be in (0, 1{}, got {v}",
                        if hi_inclusive { "]" } else { ")" }
                    ),
                ))
            }
        };
        if !(self.reference_fraction.is_finite()
            && self.reference_fraction > 0.0
            && self.reference_fraction <= 0.5)
        {
            return Err(invalid_option(
                "reference_fraction",
                format!("must be in (0, 0.5], got {}", self.reference_fraction),
            ));
        }
        share(
            "reference_width_fraction",
            self.reference_width_fraction,
            true,
        )?;
        share("min_floor_share", self.min_floor_share, false)?;
        share("adaptation_rate", self.adaptation_rate, true)?;
        let within = |name: &'static str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(invalid_option(
                    name,
                    format!("must be in [{lo}, {hi}], got {v}"),
                ))
            }
        };
        within(
            "driven_floor_radius_m",
            self.driven_floor_radius_m,
            0.0,
            2.0,
        )?;
        within("driven_floor_samples", self.driven_floor_samples, 1.0, 1e4)?;
        within(
            "driven_floor_half_life_frames",
            self.driven_floor_half_life_frames,
            1.0,
            1e6,
        )?;
        if !(1..INTENSITY_BINS).contains(&self.intensity_reach_bins) {
            return Err(invalid_option(
                "intensity_reach_bins",
                format!(
                    "must be in 1..={}, got {}",
                    INTENSITY_BINS - 1,
                    self.intensity_reach_bins
                ),
            ));
        }
        if self.patch_half_width_px > MAX_PATCH_PX {
            return Err(invalid_option(
                "patch_half_width_px",
                format!(
                    "must be at most {MAX_PATCH_PX}, got {}",
                    self.patch_half_width_px
                ),
            ));
        }
        if self.min_run_px < 1 || self.min_run_px > MAX_PATCH_PX {
            return Err(invalid_option(
                "min_run_px",
                format!("must be in 1..={MAX_PATCH_PX}, got {}", self.min_run_px),
            ));
        }
        // Columns and range limit: the edge ranger's rules.
        RangerOptions {
            columns: self.columns.clone(),
            max_range_m: self.max_range_m,
            ..Default::default()
        }
        .validate()
    }

    /// The sampled image columns for the camera of `table` (the edge ranger's rule).
    pub fn column_indices(&self, table: &GroundTable) -> Result<Vec<u32>> {
        RangerOptions {
            columns: self.columns.clone(),
            ..Default::default()
        }
        .column_indices(table)
    }
}

#[cfg(test)]
#[path = "appearance_options_tests.rs"]
mod tests;
