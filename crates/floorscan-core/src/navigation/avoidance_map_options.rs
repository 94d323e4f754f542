//! Options of the drive's avoidance map (`floorscan.drive.AvoidanceMap`, the updates in
//! [`crate::avoidance_map`]): its window, clamps, forgetting, bumper layer, class thresholds and
//! the calibration of its output probabilities.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};
use crate::grid_options::GridOptions;

/// Options of the avoidance map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct AvoidanceMapOptions {
    /// Side of the window [m], in [1, 100]. Default 8 (room for a plan around an obstacle
    /// ahead of the paper's 3 m camera range in every direction).
    pub size_m: f64,
    /// [m/cell], in [0.01, 0.5]. Default 0.05 (the ROS navigation stack's local costmap
    /// resolution).
    pub cell_size_m: f64,
    /// (min, max) log odds, min < 0 < max. Default (-2.0, 3.5), the local map's clamps
    /// (OctoMap's 0.12 / 0.97): a cell seen free a few times still turns occupied within two
    /// frames when an obstacle appears (wider clamps made the closed loop hesitate).
    pub clamp_nats: (f64, f64),
    /// Evidence halves every this many seconds without new readings, > 0, or none (never).
    /// Default 3 s: long enough to remember an obstacle that left the camera's view while
    /// the robot turns past it, short enough that a moved obstacle fades within a corridor.
    pub half_life_s: Option<f64>,
    /// The bumper layer's marks halve every this many seconds, > 0, or none (never); a mark
    /// is an obstacle until it has halved. Default 300 s: what the bumper felt is often what
    /// the camera cannot see (a face the colour of the floor), so the mark must outlast the
    /// robot's tries around it (a 30 s memory let the robot bump the same unseen box 11
    /// times in the lab world).
    pub bump_half_life_s: Option<f64>,
    /// A bump marks a straight face this far [m] to either side of the touched bearing, in
    /// [0, 1]. Default 0.15 (a 0.3 m face; `bench/drive_bumper.py` measures the choice).
    pub bump_face_half_length_m: f64,
    /// Class threshold on the probability: occupied at or above it, in (0.5, 1). Default: the
    /// occupancy grid's (`GridOptions`, map_server's).
    pub occupied_threshold: f64,
    /// Class threshold: free at or below it, in (0, 0.5). Default: the occupancy grid's.
    pub free_threshold: f64,
    /// With `probability_knots` unset, the map's probability of a cell is logistic(scale x
    /// log_odds + offset), a Platt calibration of the fused evidence (successive frames are
    /// correlated, so summed evidence overstates certainty); 0 < scale <= 10. Default 0.807,
    /// fitted by `bench/drive_sensor_model.py` on the corridor and room; (1, 0) reads the log
    /// odds as they are (the laser robot).
    pub probability_scale: f64,
    /// See `probability_scale`; |offset| <= 10. Default -1.111.
    pub probability_offset: f64,
    /// Instead of the Platt curve, a monotone calibration: 2-1000 knots (log_odds,
    /// probability), log odds increasing, probabilities non-decreasing in [0, 1], interpolated
    /// linearly (constant beyond the ends); unset uses the Platt curve. Default ((-1.9392,
    /// 0.0583), (3.0816, 0.7633)), fitted by isotonic regression (`bench/drive_sensor_model.py`,
    /// row `default_isotonic`) on the corridor and room; on six held-out worlds pooled, every
    /// decile's observed frequency lies within 5 points of the prediction up to its 95 %
    /// interval (EVALUATION.md, "Sensor model and reliability").
    pub probability_knots: Option<Vec<(f64, f64)>>,
}

impl Default for AvoidanceMapOptions {
    fn default() -> Self {
        let grid = GridOptions::default();
        Self {
            size_m: 8.0,
            cell_size_m: 0.05,
            clamp_nats: (-2.0, 3.5),
            half_life_s: Some(3.0),
            bump_half_life_s: Some(300.0),
            bump_face_half_length_m: 0.15,
            occupied_threshold: grid.occupied_threshold,
            free_threshold: grid.free_threshold,
            probability_scale: 0.807,
            probability_offset: -1.111,
            probability_knots: Some(vec![(-1.9392, 0.0583), (3.0816, 0.7633)]),
        }
    }
}

impl AvoidanceMapOptions {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        if !(1.0..=100.0).contains(&self.size_m) {
            return Err(invalid_option(
                "size_m",
                format!("must be in [1, 100], got {}", self.size_m),
            ));
        }
        if !(0.01..=0.5).contains(&self.cell_size_m) {
            return Err(invalid_option(
                "cell_size_m",
                format!("must be in [0.01, 0.5], got {}", self.cell_size_m),
            ));
        }
        let (lo, hi) = self.clamp_nats;
        if !(lo < 0.0 && 0.0 < hi && lo.is_finite() && hi.is_finite()) {
            return Err(invalid_option(
                "clamp_nats",
                format!("need min < 0 < max, got ({lo}, {hi})"),
            ));
        }
        for (name, v) in [
            ("half_life_s", self.half_life_s),
            ("bump_half_life_s", self.bump_half_life_s),
        ] {
            if let Some(v) = v {
                if v.is_nan() || v <= 0.0 {
                    return Err(invalid_option(name, format!("must be > 0, got {v}")));
                }
            }
        }
        if !(0.0..=1.0).contains(&self.bump_face_half_length_m) {
            return Err(invalid_option(
                "bump_face_half_length_m",
                format!("must be in [0, 1], got {}", self.bump_face_half_length_m),
            ));
        }
        if !(self.probability_scale > 0.0 && self.probability_scale <= 10.0) {
            return Err(invalid_option(
                "probability_scale",
                format!("must be in (0, 10], got {}", self.probability_scale),
            ));
        }
        if self.probability_offset.is_nan() || self.probability_offset.abs() > 10.0 {
            return Err(invalid_option(
                "probability_offset",
                format!("must be in [-10, 10], got {}", self.probability_offset),
            ));
        }
        if let Some(k) = &self.probability_knots {
            let finite = k.iter().all(|(x, p)| x.is_finite() && p.is_finite());
            let increasing = k.windows(2).all(|w| w[1].0 > w[0].0);
            let monotone = k.windows(2).all(|w| w[1].1 >= w[0].1);
            let in_unit = k.iter().all(|(_, p)| (0.0..=1.0).contains(p));
            if !((2..=1000).contains(&k.len()) && finite && increasing && monotone && in_unit) {
                return Err(invalid_option(
                    "probability_knots",
                    "need 2-1000 (log_odds, probability) pairs, log odds increasing, \
                     probabilities non-decreasing in [0, 1]",
                ));
            }
        }
        if !(0.0 < self.free_threshold
            && self.free_threshold < 0.5
            && 0.5 < self.occupied_threshold
            && self.occupied_threshold < 1.0)
        {
            return Err(invalid_option(
                "free_threshold",
                format!(
                    "need 0 < free_threshold < 0.5 < occupied_threshold < 1, got {} and {}",
                    self.free_threshold, self.occupied_threshold
                ),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "avoidance_map_options_tests.rs"]
mod tests;
