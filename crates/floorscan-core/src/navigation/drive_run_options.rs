//! Options of a closed-loop drive in the simulator (`floorscan drive`, Python's
//! `floorscan.drive.DriveOptions`): how long and how fast, which range sensor, how waypoints
//! count as reached, the ideal laser's shape. The components' own options (avoidance map,
//! costmap, dynamic window, scan matcher, sensor model) are their own types.

use serde::{Deserialize, Serialize};

use crate::error::{invalid_option, Result};
use crate::ranger_options::RangerOptions;

/// The range sensor the simulated robot drives with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum DriveSensor {
    /// The product: the camera, its ranger and ground table.
    Camera,
    /// The anchor: an ideal 2-D laser.
    Laser,
}

/// The camera's ground table in a drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum DriveTable {
    /// Calibrated from the simulated pattern of dark lines, as `floorscan demo` does.
    Calibrated,
    /// The camera's perfect table.
    Exact,
}

/// The range sensor's kind in a drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub enum DriveRanger {
    Edge,
    Appearance,
    Fused,
}

/// Options of one closed-loop drive.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct DriveRunOptions {
    /// Top speed [m/s], in (0, 3]. Default 0.3 (the paper's top speed).
    pub speed_m_s: f64,
    /// Longest run [s], in (0, 1e5]. Default 600; the run ends earlier when the tour is done
    /// once.
    pub seconds: f64,
    /// Seed of the odometry noise and the image noise. Default 0.
    pub seed: u64,
    /// The range sensor: the camera (the product) or an ideal laser (the anchor). Default
    /// camera.
    pub sensor: DriveSensor,
    /// The camera's ground table: calibrated from the simulated pattern, or exact. Default
    /// calibrated.
    pub table: DriveTable,
    /// Ranger columns, in 2 ..= 4096. Default 160 (every second column of a 320-wide image: a
    /// 2.5 cm chair leg at 1 m spans at least one).
    pub columns: u32,
    /// The range sensor's kind (a configuration given to the drive supplies the rangers'
    /// options, this their kind). Default edge, the configuration's default too: on the
    /// carpet worlds the closed loop drives better with the paper's ranger (EVALUATION.md).
    pub ranger: DriveRanger,
    /// The edge ranger's lower contrast floor in the band `mid_range_m` (`RangerOptions`'
    /// field of the same name and rules), set for the drive unless the configuration sets a
    /// band of its own. Default the ranger's (0.06).
    pub mid_contrast: f64,
    /// That band's [near, far] ground range [m] (`RangerOptions`' rules); none leaves the
    /// ranger's options as they are. Default [0.6, 1.2]: where an obstacle is about to be met
    /// (the dynamic window looks 0.5 m ahead at 0.3 m/s) but the floor's texture is averaged
    /// out (EVALUATION.md, "A face the colour of the floor").
    pub mid_range_m: Option<Vec<f64>>,
    /// A waypoint counts as reached (by the robot, from its pose estimate) within this
    /// distance [m], > 0. Default 0.15.
    pub goal_tolerance_m: f64,
    /// The robot gives a waypoint up after this [s] plus three times its straight-line
    /// travel time, > 0. Default 20.
    pub waypoint_timeout_s: f64,
    /// The ideal laser's field of view [rad], in (0, 2 pi]. Default 3 pi / 2 (270 degrees).
    pub laser_fov_rad: f64,
    /// The ideal laser's range [m], in (0, 100]. Default 4 (a Hokuyo UTM-30LX-like scanner
    /// cut to the camera's range).
    pub laser_range_m: f64,
    /// The ideal laser's beams, in 1 ..= 10000. Default 271.
    pub laser_beams: u32,
    /// Frames between navigation-function updates, in 1 ..= 1000. Default 5.
    pub replan_every: u32,
    /// Keep camera images and map views for a GIF every this many frames (0: none). Default
    /// 5.
    pub keep_frames: u32,
    /// After a bump ahead or beside (not behind), the robot reverses this far [m] at 0.1 m/s,
    /// in [0, 1]. Default 0.12: out of the inscribed radius of the face it marked, where the
    /// dynamic window works again (`bench/drive_bumper.py`).
    pub bump_backup_m: f64,
    /// Estimate the robot's pose in the world frame by matching each scan against its own
    /// persistent map (the correction carries the waypoints into the odometry frame the
    /// avoidance map and the planner work in). Default true; false drives on odometry alone.
    pub scan_matching: bool,
}

impl Default for DriveRunOptions {
    fn default() -> Self {
        Self {
            speed_m_s: 0.3,
            seconds: 600.0,
            seed: 0,
            sensor: DriveSensor::Camera,
            table: DriveTable::Calibrated,
            columns: 160,
            ranger: DriveRanger::Edge,
            mid_contrast: RangerOptions::default().mid_contrast,
            mid_range_m: Some(vec![0.6, 1.2]),
            goal_tolerance_m: 0.15,
            waypoint_timeout_s: 20.0,
            laser_fov_rad: 1.5 * std::f64::consts::PI,
            laser_range_m: 4.0,
            laser_beams: 271,
            replan_every: 5,
            keep_frames: 5,
            bump_backup_m: 0.12,
            scan_matching: true,
        }
    }
}

impl DriveRunOptions {
    /// Every field's rule (an error names the field).
    pub fn validate(&self) -> Result<()> {
        // (name, value, low, high, low open)
        let ranges: [(&'static str, f64, f64, f64, bool); 6] = [
            ("speed_m_s", self.speed_m_s, 0.0, 3.0, true),
            ("seconds", self.seconds, 0.0, 1e5, true),
            (
                "laser_fov_rad",
                self.laser_fov_rad,
                0.0,
                std::f64::consts::TAU,
                true,
            ),
            ("laser_range_m", self.laser_range_m, 0.0, 100.0, true),
            ("bump_backup_m", self.bump_backup_m, 0.0, 1.0, false),
            ("goal_tolerance_m", self.goal_tolerance_m, 0.0, 100.0, true),
        ];
        for (name, v, lo, hi, open) in ranges {
            let above = if open { v > lo } else { v >= lo };
            if !(v.is_finite() && above && v <= hi) {
                let left = if open { "(" } else { "[" };
                return Err(invalid_option(
                    name,
                    format!("must be in {left}{lo}, {hi}], got {v}"),
                ));
            }
        }
        let t = self.waypoint_timeout_s;
        if !(t.is_finite() && t > 0.0) {
            return Err(invalid_option(
                "waypoint_timeout_s",
                format!("must be finite and > 0, got {t}"),
            ));
        }
        for (name, v, lo, hi) in [
            ("columns", self.columns, 2, 4096),
            ("laser_beams", self.laser_beams, 1, 10000),
            ("replan_every", self.replan_every, 1, 1000),
        ] {
            if !(lo..=hi).contains(&v) {
                return Err(invalid_option(
                    name,
                    format!("must be in {lo}..={hi}, got {v}"),
                ));
            }
        }
        // the band is the ranger's: its rules are RangerOptions'
        let mut band = RangerOptions {
            mid_contrast: self.mid_contrast,
            ..RangerOptions::default()
        };
        if let Some(range) = &self.mid_range_m {
            band.mid_range_m = range.clone();
        }
        band.validate()
    }
}

#[cfg(test)]
#[path = "drive_run_options_tests.rs"]
mod tests;
