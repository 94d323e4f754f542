//! The drive's calibrated inverse sensor model for visual scans (`floorscan.drive.
//! VisualSensorModel`): how much evidence one column reading adds to a cell of the avoidance
//! map ([`crate::avoidance_map`]), from what is known about the reading.
//!
//! For a `boundary` reading at range r [m] with footprint f (the floor one pixel row covers
//! there) and the table's predicted error e, the boundary's position is uncertain by
//! sigma = sqrt(e^2 + (f / 2)^2 + (cell / 2)^2). Floor from the near edge of view to
//! `margin_sigmas` x sigma before the boundary is free with logit P(occupied) = free_a +
//! free_b r; the cells within max(sigma, cell / 2) of the boundary are occupied with logit
//! hit_a + hit_b r; `too_close` near edges with `too_close_logit`; each times
//! `fusion_weight`. Where the defaults come from: `floorscan.drive.sensor_fit` fits the four
//! logits on simulator truth (`bench/drive_sensor_model.py`: free -2.97 - 0.07 r, hit 2.0 -
//! 0.99 r); driven in closed loop those made the robot hesitate, so the defaults are hand-set
//! values chosen before the fit and checked in the closed loop, the map's probabilities made
//! to mean what they say by the avoidance map's output calibration (EVALUATION.md,
//! "Sensor model and reliability").

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// The calibrated inverse sensor model (logits are natural-log odds of the cell being
/// occupied).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct VisualModel {
    /// logit P(occupied | seen free at range r) = free_a + free_b r [1]. Default -3.2.
    pub free_a: f64,
    /// [1/m], see `free_a`. Default 0.55.
    pub free_b: f64,
    /// logit P(occupied | boundary cell at range r) = hit_a + hit_b r [1]. Default 2.0.
    pub hit_a: f64,
    /// [1/m], see `hit_a`. Default -0.45.
    pub hit_b: f64,
    /// logit P(occupied) at the near edge of a `too_close` column. Default 1.0 (the fitted
    /// share of too-close near edges that touch an obstacle).
    pub too_close_logit: f64,
    /// Floor left unobserved before a boundary, in sigmas, in [0, 10]. Default 2 (95 % of the
    /// boundary's position errors lie within 2 sigma).
    pub margin_sigmas: f64,
    /// The error e [m] where the table predicts none, > 0. Default 0.01 (the calibration's
    /// typical error bar inside the pattern, docs/calibration.md).
    pub default_error_m: f64,
    /// Evidence multiplier per frame, in (0, 1]. Default 0.7; the correlation of successive
    /// frames is corrected once more on the map's output (the avoidance map's probability
    /// calibration).
    pub fusion_weight: f64,
    /// The share, in [0, 1], of its free evidence that the floor beside a `no_boundary`
    /// column adds to a cell the map believes occupied (log odds above `confirmed_nats`,
    /// confirmed by a hit from `confirm_range_m` or farther); floor between two boundary
    /// columns clears in full. Default 0: a column that finds no edge over an obstacle
    /// mapped from farther away (a face the colour of the floor) does not clear it, as a ROS
    /// costmap does not clear through a laser's no-return beams (on four held-out worlds, 64
    /// runs: 1 gave 3 collisions at 0.3 m/s, 0 none; EVALUATION.md, "A column without a
    /// boundary does not clear a mapped obstacle"). 1: the model as it was.
    pub no_boundary_clearing: f64,
    /// Log odds (>= 0) above which a cell counts as believed occupied for
    /// `no_boundary_clearing`. Default 0 (more likely occupied than not; 1.5 gave back time
    /// but not safety).
    pub confirmed_nats: f64,
    /// Least range [m] (>= 0) of a boundary whose hit makes its cells believed obstacles for
    /// `no_boundary_clearing`; a cell only ever hit from nearer (a fleck of a light carpet,
    /// 0.1-0.3 m from the camera where the floor's grain is magnified) is cleared in full.
    /// Default 0.3 (EVALUATION.md, "Flecks of a light carpet"; 0.5 let two contacts through).
    /// 0: every hit confirms.
    pub confirm_range_m: f64,
    /// The share, in (0, 1], of its free evidence that floor between two boundary columns
    /// adds, in the planner's layer, to a cell believed occupied and confirmed; the map's own
    /// log odds clear in full. Default 0.25: OctoMap's ratio of miss to hit evidence carried
    /// over to this model's evidence at 1 m, rounded down (a saturated obstacle's cell clears
    /// over about eight frames of floor seen beyond it; EVALUATION.md, "A thin leg clears over
    /// several frames"). 1: the planner's layer equals the map's.
    pub confirmed_clearing: f64,
    /// Range [m] (>= 0, camera frame) within which a hit enters the planner's layers only
    /// when it persists (the previous insertion hit its cell or a neighbour from as near, or
    /// the planner already believes one of them occupied); the map's own log odds take every
    /// hit. Default 0: every hit enters at once. 0.5 cut the time against the laser robot from
    /// 1.47x to 1.30x over ten held-out worlds on pale grainy carpets but raised contacts
    /// (EVALUATION.md, "Near hits that do not persist"): an opt-in, not a default.
    pub persist_range_m: f64,
}

impl Default for VisualModel {
    fn default() -> Self {
        Self {
            free_a: -3.2,
            free_b: 0.55,
            hit_a: 2.0,
            hit_b: -0.45,
            too_close_logit: 1.0,
            margin_sigmas: 2.0,
            default_error_m: 0.01,
            fusion_weight: 0.7,
            no_boundary_clearing: 0.0,
            confirmed_nats: 0.0,
            confirm_range_m: 0.3,
            confirmed_clearing: 0.25,
            persist_range_m: 0.0,
        }
    }
}

impl VisualModel {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        let fields = [
            ("free_a", self.free_a),
            ("free_b", self.free_b),
            ("hit_a", self.hit_a),
            ("hit_b", self.hit_b),
            ("too_close_logit", self.too_close_logit),
            ("margin_sigmas", self.margin_sigmas),
            ("default_error_m", self.default_error_m),
            ("fusion_weight", self.fusion_weight),
            ("no_boundary_clearing", self.no_boundary_clearing),
            ("confirmed_nats", self.confirmed_nats),
            ("confirm_range_m", self.confirm_range_m),
            ("confirmed_clearing", self.confirmed_clearing),
            ("persist_range_m", self.persist_range_m),
        ];
        for (name, v) in fields {
            if !v.is_finite() {
                return Err(invalid_option(
                    name,
                    format!("must be a finite number, got {v}"),
                ));
            }
        }
        let rule = |ok: bool, name: &'static str, what: &str, v: f64| {
            if ok {
                Ok(())
            } else {
                Err(invalid_option(name, format!("must be {what}, got {v}")))
            }
        };
        let m = self;
        rule(
            (0.0..=10.0).contains(&m.margin_sigmas),
            "margin_sigmas",
            "in [0, 10]",
            m.margin_sigmas,
        )?;
        rule(
            m.default_error_m > 0.0,
            "default_error_m",
            "> 0",
            m.default_error_m,
        )?;
        rule(
            (0.0..=1.0).contains(&m.no_boundary_clearing),
            "no_boundary_clearing",
            "in [0, 1]",
            m.no_boundary_clearing,
        )?;
        rule(
            m.confirmed_nats >= 0.0,
            "confirmed_nats",
            ">= 0",
            m.confirmed_nats,
        )?;
        rule(
            m.confirm_range_m >= 0.0,
            "confirm_range_m",
            ">= 0",
            m.confirm_range_m,
        )?;
        rule(
            m.persist_range_m >= 0.0,
            "persist_range_m",
            ">= 0",
            m.persist_range_m,
        )?;
        rule(
            m.confirmed_clearing > 0.0 && m.confirmed_clearing <= 1.0,
            "confirmed_clearing",
            "in (0, 1]",
            m.confirmed_clearing,
        )?;
        rule(
            m.fusion_weight > 0.0 && m.fusion_weight <= 1.0,
            "fusion_weight",
            "in (0, 1]",
            m.fusion_weight,
        )
    }
}

#[cfg(test)]
#[path = "visual_sensor_model_tests.rs"]
mod tests;
