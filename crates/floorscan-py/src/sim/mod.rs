//! Bindings of `floorscan_sim` (the Python module `floorscan._native.sim`), one file per
//! simulator module with a Python face: worlds, cameras, truth, rendering, robot trajectories,
//! whole runs and the calibration scene. Options arrive as JSON in the simulator's serde form,
//! built by the Python wrappers in `floorscan.sim`. Heavy calls release the GIL. This file:
//! the shared conversions.

use std::sync::Arc;

use floorscan_core::mount::ground_to_pixel;
use floorscan_core::{Point2, Pose2};
use floorscan_sim::builtin::{builtin_names, builtin_world};
use floorscan_sim::calibration::{
    calibration_world, default_pattern, robot_pose, PatternKind, PatternSpec,
};
use floorscan_sim::occupancy::{occupancy_raster, OccupancyOptions};
use floorscan_sim::odometry::OdometryNoise;
use floorscan_sim::render::{render_into, RenderBuffers};
use floorscan_sim::robot::{drive, Motion, RobotOptions};
use floorscan_sim::run::{render_run, RunOutputs};
use floorscan_sim::truth::{
    frame_truth, write_columns_csv, FrameTruth, TruthOptions, COLUMNS_CSV_HEADER,
};
use floorscan_sim::world_file::parse_world;
use floorscan_sim::{Camera, CameraRays, Scene};
use numpy::{PyArray1, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::{error, to_pyerr};
use crate::ground_table::PyGroundTable;

/// Converts a simulator error into its Python exception.
pub(crate) fn sim_err(e: floorscan_sim::Error) -> PyErr {
    match e {
        floorscan_sim::Error::InvalidWorld { .. } => error("WorldError", e.to_string()),
        floorscan_sim::Error::Core(c) => to_pyerr(c),
    }
}

pub(crate) trait IntoSimResult<T> {
    fn sim(self) -> PyResult<T>;
}

impl<T> IntoSimResult<T> for floorscan_sim::Result<T> {
    fn sim(self) -> PyResult<T> {
        self.map_err(sim_err)
    }
}

pub(crate) type Xy<'py> = (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>);
pub(crate) type Rendered<'py> = (Bound<'py, PyAny>, Bound<'py, PyAny>, Option<PyTruth>, f64);
pub(crate) type RenderedRun<'py> = (
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Option<PyTruth>,
    Bound<'py, PyAny>,
);

/// A value's JSON text; a failure is an InternalError, never an empty string.
pub(crate) fn to_json<T: serde::Serialize>(value: &T) -> PyResult<String> {
    serde_json::to_string(value).map_err(|e| {
        error(
            "InternalError",
            format!("internal error (a bug; please report it): cannot write JSON: {e}"),
        )
    })
}

pub(crate) fn parse_json<T: serde::de::DeserializeOwned>(what: &str, text: &str) -> PyResult<T> {
    serde_json::from_str(text).map_err(|e| error("OptionError", format!("invalid {what}: {e}")))
}

pub(crate) fn pose_of(x: f64, y: f64, yaw: f64) -> PyResult<Pose2> {
    Pose2::checked(x, y, yaw).map_err(to_pyerr)
}

pub(crate) fn image_array<'py>(
    py: Python<'py>,
    data: Vec<u8>,
    shape: &[usize],
) -> PyResult<Bound<'py, PyAny>> {
    Ok(PyArray1::from_vec(py, data)
        .reshape(shape.to_vec())?
        .into_any())
}

pub mod calibration;
pub mod camera;
pub mod render;
pub mod robot;
pub mod run;
pub mod truth;
pub mod world;

pub use camera::PyCamera;
pub use truth::PyTruth;
pub use world::PyWorld;
