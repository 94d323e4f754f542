//! Options of the drive's dynamic-window planner (`floorscan.drive.dwa`, as ROS's
//! dwa_local_planner runs it). Defaults are dwa_local_planner's unless said otherwise.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};

/// Options of the dynamic window.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct DwaOptions {
    /// Top speed [m/s], in (0, 3] (the drive's `--speed`). Default 0.3.
    pub max_speed_m_s: f64,
    /// Top turn rate [rad/s], > 0. Default 1.0 (`max_vel_theta`).
    pub max_turn_rad_s: f64,
    /// [m/s^2], > 0. Default 2.5.
    pub acc_lim_x: f64,
    /// [rad/s^2], > 0. Default 3.2.
    pub acc_lim_theta: f64,
    /// Roll-out horizon [s], > 0. Default 1.7.
    pub sim_time_s: f64,
    /// Step along the roll-out [m], > 0. Default 0.025.
    pub sim_granularity_m: f64,
    /// Speed samples, >= 1. Default 5 (dwa_local_planner's 3 gives too coarse a choice of
    /// speed at 10 Hz control).
    pub vx_samples: u32,
    /// Turn-rate samples, >= 1. Default 21 (20, made odd so omega = 0 is a sample).
    pub vth_samples: u32,
    /// Weight of the navigation function at the forward point, > 0. Default 32.
    pub path_distance_bias: f64,
    /// Weight of the navigation function at the roll-out's end, > 0. Default 24.
    pub goal_distance_bias: f64,
    /// Weight of the largest cost along the path, > 0. Default 0.01.
    pub occdist_scale: f64,
    /// The forward point's distance ahead of the rolled-out end pose [m], > 0. Default 0.325.
    pub forward_point_distance_m: f64,
    /// Beyond this distance [m] from the robot a roll-out may not enter a cell the map has no
    /// evidence for: a camera sees a 136-degree wedge, so an arc into unseen floor may hide an
    /// obstacle beside the robot; the robot turns to look first. Within it (the footprint and
    /// the floor just ahead the camera cannot see) unknown cells are allowed; > 0. Default
    /// 0.35 (0.18 m radius plus the strip before the camera's nearest visible floor).
    pub blind_radius_m: f64,
}

impl Default for DwaOptions {
    fn default() -> Self {
        Self {
            max_speed_m_s: 0.3,
            max_turn_rad_s: 1.0,
            acc_lim_x: 2.5,
            acc_lim_theta: 3.2,
            sim_time_s: 1.7,
            sim_granularity_m: 0.025,
            vx_samples: 5,
            vth_samples: 21,
            path_distance_bias: 32.0,
            goal_distance_bias: 24.0,
            occdist_scale: 0.01,
            forward_point_distance_m: 0.325,
            blind_radius_m: 0.35,
        }
    }
}

impl DwaOptions {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        for (name, v) in [
            ("max_speed_m_s", self.max_speed_m_s),
            ("max_turn_rad_s", self.max_turn_rad_s),
            ("acc_lim_x", self.acc_lim_x),
            ("acc_lim_theta", self.acc_lim_theta),
            ("sim_time_s", self.sim_time_s),
            ("sim_granularity_m", self.sim_granularity_m),
            ("path_distance_bias", self.path_distance_bias),
            ("goal_distance_bias", self.goal_distance_bias),
            ("occdist_scale", self.occdist_scale),
            ("forward_point_distance_m", self.forward_point_distance_m),
            ("blind_radius_m", self.blind_radius_m),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(invalid_option(
                    name,
                    format!("must be a number > 0, got {v}"),
                ));
            }
        }
        for (name, v) in [
            ("vx_samples", self.vx_samples),
            ("vth_samples", self.vth_samples),
        ] {
            if !(1..=1000).contains(&v) {
                return Err(invalid_option(
                    name,
                    format!("must be in 1 ..= 1000, got {v}"),
                ));
            }
        }
        if self.max_speed_m_s > 3.0 {
            return Err(invalid_option(
                "max_speed_m_s",
                format!("must be <= 3, got {}", self.max_speed_m_s),
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "dwa_options_tests.rs"]
mod tests;
