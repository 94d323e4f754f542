//! A differential-drive robot following waypoints (or velocity commands), sampled at the camera's
//! frame rate, with its true pose and its wheel odometry.

use floorscan_core::pose::normalize_angle;
use floorscan_core::{Point2, Pose2};
use serde::{Deserialize, Serialize};

use crate::error::{check_range, invalid_option, Result};
use crate::odometry::{integrate, Odometry, OdometryNoise};

/// Options of the robot.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RobotOptions {
    /// Cruise speed [m/s], in (0, 3]. Default 0.3 (the paper's top speed).
    pub speed_mps: f64,
    /// Largest turn rate [rad/s], in (0, 10]. Default 0.8.
    pub turn_rate_radps: f64,
    /// Camera frame rate [Hz], in (0, 1000]. Default 10.
    pub frame_rate_hz: f64,
    /// Distance between the wheels [m], in (0, 5]. Default 0.3.
    pub wheelbase_m: f64,
    /// A waypoint counts as reached within this distance [m], in (0, 5]. Default 0.05.
    pub waypoint_tolerance_m: f64,
    /// Control and integration steps per second [Hz], in [frame rate, 10000]. Default 100.
    pub control_rate_hz: f64,
}

impl Default for RobotOptions {
    fn default() -> Self {
        Self {
            speed_mps: 0.3,
            turn_rate_radps: 0.8,
            frame_rate_hz: 10.0,
            wheelbase_m: 0.3,
            waypoint_tolerance_m: 0.05,
            control_rate_hz: 100.0,
        }
    }
}

impl RobotOptions {
    pub fn validate(&self) -> Result<()> {
        check_range("speed_mps", self.speed_mps, 1e-6, 3.0)?;
        check_range("turn_rate_radps", self.turn_rate_radps, 1e-6, 10.0)?;
        check_range("frame_rate_hz", self.frame_rate_hz, 1e-6, 1000.0)?;
        check_range("wheelbase_m", self.wheelbase_m, 1e-6, 5.0)?;
        check_range("waypoint_tolerance_m", self.waypoint_tolerance_m, 1e-6, 5.0)?;
        check_range(
            "control_rate_hz",
            self.control_rate_hz,
            self.frame_rate_hz,
            10_000.0,
        )
    }
}

/// One velocity command: drive at `v_mps` [m/s] and `omega_radps` [rad/s] for `duration_s` [s].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct VelocityCommand {
    pub duration_s: f64,
    pub v_mps: f64,
    pub omega_radps: f64,
}

/// How the robot moves.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Motion {
    /// Drive to each point in turn (world frame [m]); start over at the first after the last
    /// when `repeat`, else stop there.
    Waypoints { points: Vec<Point2>, repeat: bool },
    /// Velocity commands in order; the robot stops after the last.
    Commands(Vec<VelocityCommand>),
}

/// Robot poses sampled at the frames.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Trajectory {
    /// Frame times [s], starting at 0.
    pub times_s: Vec<f64>,
    /// True world_from_robot at each frame.
    pub truth: Vec<Pose2>,
    /// Odometry pose at each frame (odom frame, which starts at the true start pose).
    pub odometry: Vec<Pose2>,
}

/// Body velocity (v, omega) that steers from `pose` towards `target`.
fn steer(pose: Pose2, target: Point2, opts: &RobotOptions) -> (f64, f64) {
    let bearing = (target.y - pose.y).atan2(target.x - pose.x);
    let err = normalize_angle(bearing - pose.yaw);
    let omega = (2.5 * err).clamp(-opts.turn_rate_radps, opts.turn_rate_radps);
    // Turn on the spot when far off course; slow down in curves.
    let v = if err.abs() > 0.6 {
        0.0
    } else {
        opts.speed_mps * err.cos().powi(4)
    };
    let dist = (target.x - pose.x).hypot(target.y - pose.y);
    (v.min(dist * opts.control_rate_hz), omega)
}

/// Drives from `start` for `duration_s` [s] and samples the true and odometry poses at every
/// frame (frame k at time k / frame_rate_hz, k = 0 .. duration * rate, inclusive of 0).
pub fn drive(
    start: Pose2,
    motion: &Motion,
    options: &RobotOptions,
    noise: &OdometryNoise,
    duration_s: f64,
    seed: u64,
) -> Result<Trajectory> {
    options.validate()?;
    check_range("duration_s", duration_s, 0.0, 1.0e6)?;
    if !start.is_finite() {
        return Err(invalid_option("start", "start pose must be finite"));
    }
    match motion {
        Motion::Waypoints { points, .. } => {
            if let Some(i) = points
                .iter()
                .position(|p| !(p.x.is_finite() && p.y.is_finite()))
            {
                return Err(invalid_option(
                    "waypoints",
                    format!("waypoint {i} is not finite"),
                ));
            }
        }
        Motion::Commands(cmds) => {
            if let Some(i) = cmds.iter().position(|c| {
                !(c.duration_s >= 0.0
                    && c.duration_s.is_finite()
                    && c.v_mps.is_finite()
                    && c.omega_radps.is_finite())
            }) {
                return Err(invalid_option(
                    "commands",
                    format!("command {i} must be finite with duration >= 0"),
                ));
            }
        }
    }
    let frames = (duration_s * options.frame_rate_hz + 1e-9).floor() as usize + 1;
    let substeps = (options.control_rate_hz / options.frame_rate_hz)
        .round()
        .max(1.0) as usize;
    let dt = 1.0 / (options.frame_rate_hz * substeps as f64);
    let b = options.wheelbase_m;
    let mut odo = Odometry::new(*noise, b, start, seed)?;
    let mut pose = start;
    let mut target = 0usize;
    let (mut cmd_index, mut cmd_elapsed) = (0usize, 0.0);
    let mut out = Trajectory {
        times_s: Vec::with_capacity(frames),
        truth: Vec::with_capacity(frames),
        odometry: Vec::with_capacity(frames),
    };
    for k in 0..frames {
        out.times_s.push(k as f64 / options.frame_rate_hz);
        out.truth.push(pose);
        out.odometry.push(odo.pose);
        if k + 1 == frames {
            break;
        }
        for _ in 0..substeps {
            let (v, omega) = match motion {
                Motion::Waypoints { points, repeat } => {
                    // Skip the waypoints already reached; a repeating tour whose every
                    // waypoint lies within the tolerance of the robot stands still (once
                    // round the tour without a target ends the search, never a busy loop).
                    let mut reached = 0usize;
                    loop {
                        if points.is_empty()
                            || (target >= points.len() && !repeat)
                            || reached >= points.len()
                        {
                            break (0.0, 0.0);
                        }
                        let p = points[target % points.len()];
                        if (p.x - pose.x).hypot(p.y - pose.y) <= options.waypoint_tolerance_m {
                            target = if *repeat {
                                (target + 1) % points.len()
                            } else {
                                target + 1
                            };
                            reached += 1;
                            continue;
                        }
                        break steer(pose, p, options);
                    }
                }
                Motion::Commands(cmds) => {
                    while cmd_index < cmds.len()
                        && cmd_elapsed >= cmds[cmd_index].duration_s - 1e-12
                    {
                        cmd_index += 1;
                        cmd_elapsed = 0.0;
                    }
                    cmd_elapsed += dt;
                    cmds.get(cmd_index)
                        .map_or((0.0, 0.0), |c| (c.v_mps, c.omega_radps))
                }
            };
            let left = (v - 0.5 * omega * b) * dt;
            let right = (v + 0.5 * omega * b) * dt;
            pose = integrate(pose, left, right, b);
            odo.step(left, right);
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn waypoints_are_reached_at_the_cruise_speed() {
        let opts = RobotOptions::default();
        let motion = Motion::Waypoints {
            points: vec![Point2::new(3.0, 0.0), Point2::new(3.0, 2.0)],
            repeat: false,
        };
        let tr = drive(
            Pose2::IDENTITY,
            &motion,
            &opts,
            &OdometryNoise::none(),
            30.0,
            0,
        )
        .unwrap();
        assert_eq!(tr.times_s.len(), 301);
        // 3 m straight at 0.3 m/s: at 5 s the robot is at 1.5 m.
        assert!((tr.truth[50].x - 1.5).abs() < 0.02, "{:?}", tr.truth[50]);
        let end = tr.truth.last().unwrap();
        assert!(
            (end.x - 3.0).abs() < 0.1 && (end.y - 2.0).abs() < 0.06,
            "{end:?}"
        );
        assert_eq!(tr.truth, tr.odometry);
    }

    #[test]
    fn velocity_commands_drive_an_arc() {
        let opts = RobotOptions::default();
        let motion = Motion::Commands(vec![VelocityCommand {
            duration_s: 10.0,
            v_mps: 0.2,
            omega_radps: 0.1,
        }]);
        let tr = drive(
            Pose2::IDENTITY,
            &motion,
            &opts,
            &OdometryNoise::none(),
            12.0,
            0,
        )
        .unwrap();
        // A circle of radius 2 m: after 10 s the heading is 1 rad, then the robot stops.
        let p = tr.truth[100];
        assert!((p.yaw - 1.0).abs() < 1e-9);
        assert!(
            (p.x - 2.0 * 1f64.sin()).abs() < 1e-9 && (p.y - 2.0 * (1.0 - 1f64.cos())).abs() < 1e-9
        );
        assert_eq!(tr.truth[120], p);
    }

    #[test]
    fn a_repeating_tour_of_waypoints_at_the_start_stands_still_and_returns() {
        // Issue 12: `floorscan sim` with such a tour spun at 100 % CPU forever.
        for n in [1, 2, 5] {
            let motion = Motion::Waypoints {
                points: vec![Point2::new(0.0, 0.0); n],
                repeat: true,
            };
            let tr = drive(
                Pose2::IDENTITY,
                &motion,
                &RobotOptions::default(),
                &OdometryNoise::none(),
                2.0,
                0,
            )
            .unwrap();
            assert!(tr.truth.iter().all(|p| *p == Pose2::IDENTITY));
        }
    }

    #[test]
    fn bad_options_are_errors() {
        let opts = RobotOptions {
            speed_mps: -1.0,
            ..RobotOptions::default()
        };
        let m = Motion::Commands(vec![]);
        assert!(drive(Pose2::IDENTITY, &m, &opts, &OdometryNoise::none(), 1.0, 0).is_err());
        assert!(drive(
            Pose2::IDENTITY,
            &m,
            &RobotOptions::default(),
            &OdometryNoise::none(),
            f64::NAN,
            0
        )
        .is_err());
    }
}
