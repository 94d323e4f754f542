//! Options of the visual range sensor: one documented structure, validated when the ranger is
//! built. The `[ranger]` table of the TOML config file is exactly these fields.

use serde::{Deserialize, Serialize};

use crate::edge::Refinement;
use crate::error::{invalid_option, Result};
use crate::ground_table::GroundTable;

/// Which image columns are sampled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum ColumnSelection {
    /// `n` columns evenly spaced across the image: the centres of n equal strips.
    Count(usize),
    /// These image columns, in this order.
    Explicit(Vec<u32>),
    /// Columns placed from the ground table so that no obstacle `obstacle_width_m` [m] wide
    /// at `range_m` [m] falls between two of them (`crate::column_spacing`): the count
    /// follows the camera and lens.
    Spacing {
        /// Narrowest obstacle that must be hit by a column [m], > 0 (a chair leg: 0.03).
        obstacle_width_m: f64,
        /// Range at which it must be hit [m], > 0.
        range_m: f64,
    },
}

/// Where each column's scan starts (the bottom of its region of interest).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum ColumnStart {
    /// Skip this many rows at the bottom of every column (a bumper, a dark border row).
    BottomMargin(usize),
    /// Start row v (counted from the top) of every image column, e.g. from a mask image; its
    /// length is the image width.
    PerColumn(Vec<u32>),
}

/// Options of [`crate::ranger::VisualRanger`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct RangerOptions {
    /// Half-width d of the box filter [px], >= 1. Default 4: wide enough to average carpet
    /// texture, narrow enough to resolve a boundary a few pixels from the bottom.
    pub half_width_px: usize,
    /// Least edge threshold on |R| of the paper's eq. (1)-(2), R = (sum of the d pixels above -
    /// sum of the d pixels below) / 2d, i.e. half the difference of the two window means, in the
    /// image's intensity units (0-255 for 8-bit images), finite and >= 0. Each frame's
    /// threshold is the largest of this, `noise_multiple` x the frame's noise and `contrast` x
    /// the floor's brightness; with both of those 0 it is the paper's fixed threshold (10 was
    /// the fixed default, chosen on the evaluation suite). Default 2: a noise-free, textureless
    /// frame still needs a step of more than 4 grey levels.
    pub threshold: f64,
    /// Threshold that follows each frame's noise: at least `noise_multiple` x sigma, sigma the
    /// robust standard deviation (1.4826 x median absolute deviation) of R over the near-floor
    /// band (the bottom 12 % of the image above each sampled column's start) of that frame, all
    /// sampled columns pooled; finite and >= 0, 0 for none. Default 4: Gaussian noise crosses 4
    /// sigma at 6e-5 of the rows (docs/visual-range-sensor.md gives the figures).
    pub noise_multiple: f64,
    /// Threshold relative to the floor's brightness (Weber contrast): each column's threshold
    /// is at least `contrast` x the mean brightness of its near-floor band in that frame, so an
    /// edge must change the brightness by more than 2 x `contrast` of the floor's (R is half
    /// the difference of the window means). Gain and exposure scale both sides alike; finite
    /// and >= 0, 0 for none. Default 0.12: the old fixed threshold 10 over the simulated
    /// carpets' grey level 72-99 in normal light (docs/visual-range-sensor.md).
    pub contrast: f64,
    /// A lower Weber contrast floor for the rows whose ground lies within `mid_range_m`,
    /// finite and >= 0: there the threshold is max(`threshold`, the noise term,
    /// min(`mid_contrast`, `contrast`) x the floor's brightness) (the band only lowers the
    /// floor). Default 0.06 (a 12 % step), used only where `mid_range_m` is set.
    pub mid_contrast: f64,
    /// [near, far] ground range [m] of the band where `mid_contrast` applies, 0 <= near <= far
    /// <= 100; an empty band (near = far) applies it nowhere. Default [0, 0]. The band suits
    /// the range where a missed obstacle is about to be met but the floor's texture is
    /// averaged out: nearer, the floor's grain is resolved into steps as strong as a low-contrast
    /// obstacle's base; farther, lighting and aliasing make more false edges, and what is far
    /// is seen again nearer (`floorscan drive` sets [0.6, 1.2] m at 0.06: EVALUATION.md).
    pub mid_range_m: Vec<f64>,
    /// How the boundary row is placed after the first crossing. Default: `step` (the sharpest
    /// one-pixel step near the filter's sub-pixel peak).
    pub refinement: Refinement,
    /// Sampled columns. Default: placed from the ground table so that no obstacle 3 cm wide
    /// (a chair leg) at 1 m stands between two columns (115 columns on a 320-pixel
    /// 136-degree camera; evenly spaced 64 stepped over 15 % of such legs in the simulator).
    pub columns: ColumnSelection,
    /// Start of each column's scan. Default: 2 px bottom margin (dead border rows are common).
    pub start: ColumnStart,
    /// Farthest ground range scanned [m]; `None` (written `inf`) scans up to the highest row
    /// with ground. Default 3 m: beyond it a typical 320x240 wide-angle camera images more
    /// than 10 cm of floor per pixel row (ROS costmaps default to 2.5-3 m for the same reason).
    #[serde(with = "range_limit")]
    #[cfg_attr(feature = "schema", schemars(with = "f64"))]
    pub max_range_m: Option<f64>,
    /// Widest line on the floor [m] whose two sides are not a boundary: where the column
    /// leaves the floor's brightness at an edge and comes back to it (within the edge's own
    /// threshold) no more than this far beyond on the ground (by the table; 2 rows more for
    /// the lens's blur), the edge is a grout line, a seam or a painted line, and the search
    /// goes on above it. Finite, 0 <= w <= 1; 0 turns it off. Default 0.
    pub floor_line_width_m: f64,
}

impl Default for RangerOptions {
    fn default() -> Self {
        Self {
            half_width_px: 4,
            threshold: 2.0,
            noise_multiple: 4.0,
            contrast: 0.12,
            mid_contrast: 0.06,
            mid_range_m: vec![0.0, 0.0],
            refinement: Refinement::Step,
            columns: ColumnSelection::Spacing {
                obstacle_width_m: 0.03,
                range_m: 1.0,
            },
            start: ColumnStart::BottomMargin(2),
            max_range_m: Some(3.0),
            floor_line_width_m: 0.0,
        }
    }
}

/// A range limit in its serde form: a number [m], `inf` for none (TOML, JSON-free dicts and
/// keyword arguments have no null).
pub mod range_limit {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(v.unwrap_or(f64::INFINITY))
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
        let v = Option::<f64>::deserialize(d)?;
        Ok(v.filter(|r| *r != f64::INFINITY))
    }
}

/// Longest half-width accepted: keeps the raw sums of 16-bit pixels inside i32.
pub const MAX_HALF_WIDTH_PX: usize = 4096;

impl RangerOptions {
    /// Checks every field that does not depend on the image size.
    pub fn validate(&self) -> Result<()> {
        if self.half_width_px < 1 || self.half_width_px > MAX_HALF_WIDTH_PX {
            return Err(invalid_option(
                "half_width_px",
                format!(
                    "must be in 1..={MAX_HALF_WIDTH_PX}, got {}",
                    self.half_width_px
                ),
            ));
        }
        if !(self.threshold.is_finite() && self.threshold >= 0.0) {
            return Err(invalid_option(
                "threshold",
                format!("must be finite and >= 0, got {}", self.threshold),
            ));
        }
        if !(self.noise_multiple.is_finite() && self.noise_multiple >= 0.0) {
            return Err(invalid_option(
                "noise_multiple",
                format!("must be finite and >= 0, got {}", self.noise_multiple),
            ));
        }
        if !(self.contrast.is_finite() && self.contrast >= 0.0) {
            return Err(invalid_option(
                "contrast",
                format!("must be finite and >= 0, got {}", self.contrast),
            ));
        }
        if !(self.mid_contrast.is_finite() && self.mid_contrast >= 0.0) {
            return Err(invalid_option(
                "mid_contrast",
                format!("must be finite and >= 0, got {}", self.mid_contrast),
            ));
        }
        let ok = match self.mid_range_m[..] {
            [near, far] => {
                near.is_finite() && far.is_finite() && 0.0 <= near && near <= far && far <= 100.0
            }
            _ => false,
        };
        if !ok {
            return Err(invalid_option(
                "mid_range_m",
                format!(
                    "needs [near, far] with 0 <= near <= far <= 100 [m], got {:?}",
                    self.mid_range_m
                ),
            ));
        }
        match &self.columns {
            ColumnSelection::Count(0) => {
                return Err(invalid_option("columns", "count must be at least 1"))
            }
            ColumnSelection::Explicit(c) if c.is_empty() => {
                return Err(invalid_option("columns", "the column list is empty"))
            }
            ColumnSelection::Spacing {
                obstacle_width_m: w,
                range_m: r,
            } if !(w.is_finite() && *w > 0.0 && r.is_finite() && *r > 0.0) => {
                return Err(invalid_option(
                    "columns",
                    format!("obstacle_width_m and range_m must be finite and > 0, got {w} and {r}"),
                ))
            }
            _ => {}
        }
        if !(self.floor_line_width_m.is_finite() && (0.0..=1.0).contains(&self.floor_line_width_m))
        {
            return Err(invalid_option(
                "floor_line_width_m",
                format!("must be in [0, 1] m, got {}", self.floor_line_width_m),
            ));
        }
        if let Some(r) = self.max_range_m {
            if !(r > 0.0 && r.is_finite()) {
                return Err(invalid_option(
                    "max_range_m",
                    format!("must be finite and > 0, got {r}"),
                ));
            }
        }
        Ok(())
    }

    /// The sampled image columns for the camera of `table` (its image width; its ground for
    /// [`ColumnSelection::Spacing`]).
    pub fn column_indices(&self, table: &GroundTable) -> Result<Vec<u32>> {
        let width = table.image_width();
        match &self.columns {
            ColumnSelection::Count(n) => {
                if *n > width {
                    return Err(invalid_option(
                        "columns",
                        format!("asked for {n} columns of an image {width} pixels wide"),
                    ));
                }
                Ok((0..*n)
                    .map(|j| (((j as f64 + 0.5) * width as f64 / *n as f64) - 0.5).round() as u32)
                    .collect())
            }
            ColumnSelection::Explicit(cols) => {
                if let Some(bad) = cols.iter().find(|&&c| c as usize >= width) {
                    return Err(invalid_option(
                        "columns",
                        format!("column {bad} is outside the image (width {width})"),
                    ));
                }
                Ok(cols.clone())
            }
            ColumnSelection::Spacing {
                obstacle_width_m,
                range_m,
            } => crate::column_spacing::spaced_columns(table, *obstacle_width_m, *range_m),
        }
    }
}

#[cfg(test)]
#[path = "ranger_options_tests.rs"]
mod tests;
