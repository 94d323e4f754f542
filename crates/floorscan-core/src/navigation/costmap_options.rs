//! Options of the drive's costmap (`floorscan.drive.costmap`: ROS costmap_2d's inflation layer
//! and a navfn-like navigation function over it).

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Options of the costmap and the navigation function.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct CostmapOptions {
    /// The circular footprint's radius [m], > 0. Default 0.18 (a TurtleBot 2 / Kobuki base,
    /// 0.354 m across).
    pub robot_radius_m: f64,
    /// Added to the radius for the inscribed cost [m], in [0, 1). Default 0.07: one 5 cm cell
    /// of discretisation plus the camera map's few-centimetre placement error near obstacles
    /// (costmap_2d's `footprint_padding` is 0.01 for a laser).
    pub footprint_padding_m: f64,
    /// Inflation radius [m], >= `robot_radius_m`. Default 0.55 (costmap_2d's default).
    pub inflation_radius_m: f64,
    /// Cost decay beyond the inscribed radius [1/m], > 0. Default 10 (costmap_2d's default).
    pub cost_scaling_factor: f64,
    /// Cell of the navigation function [m], a multiple of the map's cell, > 0. Default 0.1.
    pub plan_cell_m: f64,
    /// When the map blocks the goal's cell, the plan leads to the nearest free cell within
    /// this distance of it [m], > 0. Default 0.6.
    pub goal_seed_radius_m: f64,
    /// Extra cost per metre of planning through cells without evidence, in units of a metre
    /// of known floor, > 0. Default 2 (an unseen route must be three times shorter to win).
    pub unknown_cost: f64,
}

impl Default for CostmapOptions {
    fn default() -> Self {
        Self {
            robot_radius_m: 0.18,
            footprint_padding_m: 0.07,
            inflation_radius_m: 0.55,
            cost_scaling_factor: 10.0,
            plan_cell_m: 0.1,
            goal_seed_radius_m: 0.6,
            unknown_cost: 2.0,
        }
    }
}

impl CostmapOptions {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("robot_radius_m", self.robot_radius_m),
            ("inflation_radius_m", self.inflation_radius_m),
            ("cost_scaling_factor", self.cost_scaling_factor),
            ("plan_cell_m", self.plan_cell_m),
            ("goal_seed_radius_m", self.goal_seed_radius_m),
            ("unknown_cost", self.unknown_cost),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid_option(
                    name,
                    format!("must be a number > 0, got {v}"),
                ));
            }
        }
        let p = self.footprint_padding_m;
        if !(p.is_finite() && (0.0..1.0).contains(&p)) {
            return Err(invalid_option(
                "footprint_padding_m",
                format!("must be in [0, 1), got {p}"),
            ));
        }
        if self.inflation_radius_m < self.robot_radius_m {
            return Err(invalid_option(
                "inflation_radius_m",
                format!(
                    "must be >= robot_radius_m ({}), got {}",
                    self.robot_radius_m, self.inflation_radius_m
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "costmap_options_tests.rs"]
mod tests;
