//! Bindings of `floorscan_sim::{robot, odometry}`: driving the robot, odometry noise.

use super::*;

/// Drives the robot: (times (N,), truth (N, 3), odometry (N, 3)).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn sim_drive<'py>(
    py: Python<'py>,
    x: f64,
    y: f64,
    yaw: f64,
    motion_json: &str,
    robot_json: &str,
    noise_json: &str,
    duration_s: f64,
    seed: u64,
) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>, Bound<'py, PyAny>)> {
    crate::errors::guard(|| {
        let start = pose_of(x, y, yaw)?;
        let motion: Motion = parse_json("motion", motion_json)?;
        let robot: RobotOptions = parse_json("robot options", robot_json)?;
        let noise: OdometryNoise = parse_json("odometry noise", noise_json)?;
        let tr = py
            .detach(|| drive(start, &motion, &robot, &noise, duration_s, seed))
            .sim()?;
        let n = tr.times_s.len();
        let flat = |p: &[Pose2]| {
            p.iter()
                .flat_map(|p| [p.x, p.y, p.yaw])
                .collect::<Vec<f64>>()
        };
        Ok((
            PyArray1::from_vec(py, tr.times_s).into_any(),
            PyArray1::from_vec(py, flat(&tr.truth))
                .reshape([n, 3])?
                .into_any(),
            PyArray1::from_vec(py, flat(&tr.odometry))
                .reshape([n, 3])?
                .into_any(),
        ))
    })
}

/// Validates robot options (JSON, the simulator's serde form).
#[pyfunction]
pub fn validate_robot_options(options_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        parse_json::<RobotOptions>("robot options", options_json)?
            .validate()
            .sim()
    })
}

/// Validates odometry noise (JSON, the simulator's serde form).
#[pyfunction]
pub fn validate_odometry_noise(options_json: &str) -> PyResult<()> {
    crate::errors::guard(|| {
        parse_json::<OdometryNoise>("odometry noise", options_json)?
            .validate()
            .sim()
    })
}
