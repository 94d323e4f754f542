//! Options of the fused range sensor ([`crate::fusion`]): when an edge places the appearance
//! ranger's boundary, and when a frame's floor breaks the texture assumption. In the config
//! file they are keys of `[appearance]` (`snap_rows`, `snap_fraction`, `texture_share`).

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Options of the edge and appearance rangers' fusion.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct FusionOptions {
    /// Largest distance [image rows] at which the edge reading replaces the appearance
    /// boundary, finite and >= 0. Default 3.
    pub snap_rows: f64,
    /// The same distance as a share of the image height, in [0, 1]; the larger of the two
    /// applies. Default 0.08: on the simulated carpets the appearance boundary lies a median
    /// 7-18 rows of 240 above a right edge (a grey skirting board looks like the grey carpet),
    /// on tiles and planks a median 62-93 rows above a wrong one (`bench/fusion_gaps.py`).
    pub snap_fraction: f64,
    /// In [0, 1]: a frame in which more than this share of the edge ranger's boundaries lie
    /// farther than the snap distance below an appearance boundary breaks the texture
    /// assumption (grout, joints, a printed pattern), and its columns where the appearance
    /// ranger saw only floor stay floor; 1 never. Default 0.15, chosen on 20 s of each
    /// simulated world (on the carpets at most 3 % of a frame's edge boundaries lie that far
    /// below, on tiles a median 37 %; `bench/fusion_gaps.py`, EVALUATION.md).
    pub texture_share: f64,
}

impl Default for FusionOptions {
    fn default() -> Self {
        Self {
            snap_rows: 3.0,
            snap_fraction: 0.08,
            texture_share: 0.15,
        }
    }
}

impl FusionOptions {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        if !(self.snap_rows.is_finite() && self.snap_rows >= 0.0) {
            return Err(invalid_option(
                "snap_rows",
                format!("must be finite and >= 0, got {}", self.snap_rows),
            ));
        }
        for (name, v) in [
            ("snap_fraction", self.snap_fraction),
            ("texture_share", self.texture_share),
        ] {
            if !(0.0..=1.0).contains(&v) {
                return Err(invalid_option(name, format!("must be in [0, 1], got {v}")));
            }
        }
        Ok(())
    }

    /// The snap distance [rows] in an image `image_height` rows tall: the larger of
    /// `snap_rows` and `snap_fraction` of the height.
    pub fn snap_distance_rows(&self, image_height: usize) -> f64 {
        self.snap_rows.max(self.snap_fraction * image_height as f64)
    }
}

#[cfg(test)]
#[path = "fusion_options_tests.rs"]
mod tests;
