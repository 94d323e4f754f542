//! Bindings of `floorscan_core::avoidance_map`: the drive's avoidance map, its layers owned in
//! Rust (`floorscan.drive.AvoidanceMap` wraps it; the layers reach Python as copies).

use floorscan_core::avoidance_map::{AvoidanceMap, VisualModel, VisualReadings};
use floorscan_core::avoidance_map_options::AvoidanceMapOptions;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::arrays::{pose, slice1};
use crate::errors::{error, guard, IntoPyResult};
use crate::options::from_py;

/// A layer (side, side) as a numpy copy.
fn to_numpy<'py, T: numpy::Element + Copy>(
    py: Python<'py>,
    values: &[T],
    side: usize,
) -> PyResult<Bound<'py, PyArray2<T>>> {
    PyArray1::from_slice(py, values).reshape([side, side])
}

/// `value` (side, side), C-contiguous, copied into `layer`.
fn set_layer<T: numpy::Element + Copy>(
    layer: &mut [T],
    value: &PyReadonlyArray2<'_, T>,
    name: &str,
) -> PyResult<()> {
    let s = value
        .as_slice()
        .ok()
        .filter(|s| s.len() == layer.len())
        .ok_or_else(|| {
            error(
                "LengthMismatchError",
                format!("`{name}` must be a C-contiguous array of the window's shape"),
            )
        })?;
    layer.copy_from_slice(s);
    Ok(())
}

/// The model's fields read by name from a `floorscan.drive.VisualSensorModel`.
fn visual_model(model: &Bound<'_, PyAny>) -> PyResult<VisualModel> {
    let field = |name: &str| -> PyResult<f64> { model.getattr(name)?.extract::<f64>() };
    Ok(VisualModel {
        free_a: field("free_a")?,
        free_b: field("free_b")?,
        hit_a: field("hit_a")?,
        hit_b: field("hit_b")?,
        too_close_logit: field("too_close_logit")?,
        margin_sigmas: field("margin_sigmas")?,
        default_error_m: field("default_error_m")?,
        fusion_weight: field("fusion_weight")?,
        no_boundary_clearing: field("no_boundary_clearing")?,
        confirmed_nats: field("confirmed_nats")?,
        confirm_range_m: field("confirm_range_m")?,
        confirmed_clearing: field("confirmed_clearing")?,
        persist_range_m: field("persist_range_m")?,
    })
}

/// The avoidance map of `options` (a dict of `AvoidanceMapOptions`' fields) whose window is
/// centred near `center` [m, odometry frame].
#[pyclass(name = "AvoidanceMap", module = "floorscan._native.drive")]
pub struct PyAvoidanceMap {
    inner: AvoidanceMap,
}

#[pymethods]
impl PyAvoidanceMap {
    #[new]
    fn new(options: &Bound<'_, PyAny>, center: (f64, f64)) -> PyResult<Self> {
        guard(|| {
            let o: AvoidanceMapOptions = from_py(options)?;
            Ok(Self {
                inner: AvoidanceMap::new(o, center).py()?,
            })
        })
    }

    /// The map's log odds (side, side) float32, row 0 = lowest y (a copy).
    #[getter]
    fn get_log_odds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        to_numpy(py, &self.inner.log_odds, self.inner.side())
    }

    #[setter]
    fn set_log_odds(&mut self, value: PyReadonlyArray2<'_, f32>) -> PyResult<()> {
        guard(|| set_layer(&mut self.inner.log_odds, &value, "log_odds"))
    }

    /// The bumper's marks (side, side) float32 (a copy).
    #[getter]
    fn get_bumps<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        to_numpy(py, &self.inner.bumps, self.inner.side())
    }

    #[setter]
    fn set_bumps(&mut self, value: PyReadonlyArray2<'_, f32>) -> PyResult<()> {
        guard(|| set_layer(&mut self.inner.bumps, &value, "bumps"))
    }

    /// 1 where a hit from `confirm_range_m` or farther confirmed the cell (a copy).
    #[getter]
    fn get_confirmed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u8>>> {
        to_numpy(py, &self.inner.confirmed, self.inner.side())
    }

    #[setter]
    fn set_confirmed(&mut self, value: PyReadonlyArray2<'_, u8>) -> PyResult<()> {
        guard(|| set_layer(&mut self.inner.confirmed, &value, "confirmed"))
    }

    /// The planner's log odds (a copy).
    #[getter]
    fn get_plan_log_odds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        to_numpy(py, &self.inner.plan_log_odds, self.inner.side())
    }

    #[setter]
    fn set_plan_log_odds(&mut self, value: PyReadonlyArray2<'_, f32>) -> PyResult<()> {
        guard(|| set_layer(&mut self.inner.plan_log_odds, &value, "plan_log_odds"))
    }

    /// The planner's confirmed obstacles (a copy).
    #[getter]
    fn get_plan_confirmed<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u8>>> {
        to_numpy(py, &self.inner.plan_confirmed, self.inner.side())
    }

    #[setter]
    fn set_plan_confirmed(&mut self, value: PyReadonlyArray2<'_, u8>) -> PyResult<()> {
        guard(|| set_layer(&mut self.inner.plan_confirmed, &value, "plan_confirmed"))
    }

    /// The cells the last visual insertion hit from nearer than `persist_range_m` (a copy).
    #[getter]
    fn get_plan_near_hits<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u8>>> {
        to_numpy(py, &self.inner.plan_near_hits, self.inner.side())
    }

    #[setter]
    fn set_plan_near_hits(&mut self, value: PyReadonlyArray2<'_, u8>) -> PyResult<()> {
        guard(|| set_layer(&mut self.inner.plan_near_hits, &value, "plan_near_hits"))
    }

    /// Cells on a side of the window.
    #[getter]
    fn side(&self) -> usize {
        self.inner.side()
    }

    /// The world cell of the window's cell (0, 0).
    #[getter]
    fn origin_cells(&self) -> (i64, i64) {
        self.inner.origin_cells()
    }

    /// Scrolls by whole cells so (x, y) [m] lies within a quarter window of the centre.
    fn recenter(&mut self, x: f64, y: f64) -> PyResult<()> {
        guard(|| self.inner.recenter(x, y).py())
    }

    /// Forgets `dt_s` [s] of evidence and bumps (their half-lives).
    fn decay(&mut self, dt_s: f64) {
        self.inner.decay(dt_s)
    }

    /// Adds one visual scan seen by the camera at `camera` (world_from_camera, odometry
    /// frame): per column the status codes, boundary points, near edges [m, camera ground
    /// frame], footprints and predicted errors [m] (NaN: none); `model` a
    /// `floorscan.drive.VisualSensorModel` (its fields are read by name).
    #[allow(clippy::too_many_arguments)]
    fn insert_visual(
        &mut self,
        py: Python<'_>,
        camera: [f64; 3],
        status: PyReadonlyArray1<'_, u8>,
        x: PyReadonlyArray1<'_, f64>,
        y: PyReadonlyArray1<'_, f64>,
        near_x: PyReadonlyArray1<'_, f64>,
        near_y: PyReadonlyArray1<'_, f64>,
        footprints: PyReadonlyArray1<'_, f64>,
        errors: PyReadonlyArray1<'_, f64>,
        model: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        guard(|| {
            let model = visual_model(model)?;
            let status = status.as_slice().map_err(|_| {
                error(
                    "LengthMismatchError",
                    "`status` must be a contiguous 1-D uint8 array".into(),
                )
            })?;
            let readings = VisualReadings {
                status,
                x_m: slice1(&x, "x")?,
                y_m: slice1(&y, "y")?,
                near_x_m: slice1(&near_x, "near_x")?,
                near_y_m: slice1(&near_y, "near_y")?,
                footprint_m: slice1(&footprints, "footprints")?,
                error_m: slice1(&errors, "errors")?,
            };
            let camera = pose(camera);
            let inner = &mut self.inner;
            py.detach(|| inner.insert_visual(camera, &readings, &model))
                .py()
        })
    }

    /// An ideal 2-D laser scan from `pose` (world_from_robot): `ranges` [m] (REP 117) at
    /// `angles` [rad, robot frame], free to each return or `range_max_m`, `hit_nats` at the
    /// return, `miss_nats` along the beam (None: the ideal laser's 2.2 / -2.0).
    #[pyo3(signature = (pose, ranges, angles, range_max_m, hit_nats=None, miss_nats=None))]
    #[allow(clippy::too_many_arguments)]
    fn insert_laser(
        &mut self,
        py: Python<'_>,
        pose: [f64; 3],
        ranges: PyReadonlyArray1<'_, f64>,
        angles: PyReadonlyArray1<'_, f64>,
        range_max_m: f64,
        hit_nats: Option<f32>,
        miss_nats: Option<f32>,
    ) -> PyResult<()> {
        guard(|| {
            let r = slice1(&ranges, "ranges")?;
            let a = slice1(&angles, "angles")?;
            let nats = match (hit_nats, miss_nats) {
                (None, None) => None,
                (h, m) => Some((
                    h.unwrap_or(floorscan_core::avoidance_map::LASER_HIT_NATS),
                    m.unwrap_or(floorscan_core::avoidance_map::LASER_MISS_NATS),
                )),
            };
            let p = self::pose(pose);
            let inner = &mut self.inner;
            py.detach(|| inner.insert_laser(p, r, a, range_max_m, nats))
                .py()
        })
    }

    /// A bumper contact at `distance_m` along `bearing_rad` (robot frame) from `pose`.
    fn mark_bump(&mut self, pose: [f64; 3], bearing_rad: f64, distance_m: f64) -> PyResult<()> {
        guard(|| {
            self.inner
                .mark_bump(self::pose(pose), bearing_rad, distance_m)
                .py()
        })
    }

    /// Calibrated occupancy probabilities (side, side) float64; 0.5 without evidence.
    fn probabilities<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let mut out = Vec::new();
        self.inner.probabilities(&mut out);
        to_numpy(py, &out, self.inner.side())
    }

    /// The planner's classes (side, side) uint8: 0 free, 1 unknown, 2 occupied.
    fn occupancy_classes<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<u8>>> {
        let n = self.inner.side();
        let c: Vec<u8> = (0..n * n).map(|k| self.inner.occupancy_class(k)).collect();
        to_numpy(py, &c, n)
    }

    /// Cells the planner has evidence for (side, side) bool.
    fn known<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<bool>>> {
        let n = self.inner.side();
        let c: Vec<bool> = (0..n * n).map(|k| self.inner.known(k)).collect();
        to_numpy(py, &c, n)
    }

    /// The planner's obstacles (side, side) bool (its evidence or the bumper's marks).
    fn occupied<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<bool>>> {
        let n = self.inner.side();
        let c: Vec<bool> = (0..n * n).map(|k| self.inner.occupied(k)).collect();
        to_numpy(py, &c, n)
    }
}
