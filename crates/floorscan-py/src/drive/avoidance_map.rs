//! Bindings of `floorscan_core::avoidance_map`: the drive's avoidance map updates, in place on
//! the numpy layers `floorscan.drive.AvoidanceMap` keeps.

use floorscan_core::avoidance_map::{self, AvoidanceMap, PlanLayers, VisualModel, VisualReadings};
use numpy::{
    PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyReadwriteArray2,
    PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::arrays::{pose, rows, slice1};
use crate::errors::{error, guard, IntoPyResult};

/// A mutable, C-contiguous 2-D layer as a flat slice and its (rows, columns).
fn layer<'a, T: numpy::Element>(
    a: &'a mut PyReadwriteArray2<'_, T>,
    name: &str,
) -> PyResult<(&'a mut [T], (usize, usize))> {
    let shape = (a.shape()[0], a.shape()[1]);
    let s = a.as_slice_mut().map_err(|_| {
        error(
            "LengthMismatchError",
            format!("`{name}` must be a C-contiguous array"),
        )
    })?;
    Ok((s, shape))
}

/// A second writable layer (the planner's), refused with a typed error when it is the same
/// array as a layer already taken (numpy's borrow flags tell).
fn own_layer<'py, T: numpy::Element>(
    a: &Bound<'py, PyArray2<T>>,
    name: &str,
) -> PyResult<PyReadwriteArray2<'py, T>> {
    a.try_readwrite().map_err(|_| {
        error(
            "LengthMismatchError",
            format!("`{name}` must be a layer of its own, not one already given"),
        )
    })
}

/// The avoidance map's insertion machinery for a `side` x `side` window of `cell_size_m`
/// [m] cells clamped to `clamp_nats` (min < 0 < max); its scratch layers are made once.
#[pyclass(name = "AvoidanceMap", module = "floorscan._native.drive")]
pub struct PyAvoidanceMap {
    inner: AvoidanceMap,
}

#[pymethods]
impl PyAvoidanceMap {
    #[new]
    fn new(side: usize, cell_size_m: f64, clamp_nats: (f64, f64)) -> PyResult<Self> {
        guard(|| {
            Ok(Self {
                inner: AvoidanceMap::new(side, cell_size_m, clamp_nats).py()?,
            })
        })
    }

    /// Adds one visual scan to `log_odds` ((side, side) float32, in place; its cell (0, 0) is
    /// world cell `origin_cells`) and to `confirmed` ((side, side) uint8, in place: the cells a
    /// hit from `confirm_range_m` or farther confirmed), and to the planner's layers
    /// `plan_log_odds` and `plan_confirmed`, whose confirmed obstacles alone clear by the
    /// model's `confirmed_clearing` (`log_odds` clear in full), and which take a hit nearer
    /// than the model's `persist_range_m` only when it persists (`plan_near_hits`, (side,
    /// side) uint8, in place: the cells the last insertion hit from that near), seen by the
    /// camera at
    /// `camera` (world_from_camera): per column the status codes, boundary points, near edges
    /// [m, camera ground frame], footprints and predicted errors [m] (NaN: none); `model` a
    /// `floorscan.drive.VisualSensorModel` (its fields are read by name).
    #[allow(clippy::too_many_arguments)]
    fn insert_visual(
        &mut self,
        py: Python<'_>,
        mut log_odds: PyReadwriteArray2<'_, f32>,
        mut confirmed: PyReadwriteArray2<'_, u8>,
        plan_log_odds: Bound<'_, PyArray2<f32>>,
        plan_confirmed: Bound<'_, PyArray2<u8>>,
        plan_near_hits: Bound<'_, PyArray2<u8>>,
        origin_cells: (i64, i64),
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
            let field = |name: &str| -> PyResult<f64> { model.getattr(name)?.extract::<f64>() };
            let model = VisualModel {
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
            };
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
            let (values, _) = layer(&mut log_odds, "log_odds")?;
            let (confirmed, _) = layer(&mut confirmed, "confirmed")?;
            let mut plan_log_odds = own_layer(&plan_log_odds, "plan_log_odds")?;
            let mut plan_confirmed = own_layer(&plan_confirmed, "plan_confirmed")?;
            let (plan_values, _) = layer(&mut plan_log_odds, "plan_log_odds")?;
            let (plan_confirmed, _) = layer(&mut plan_confirmed, "plan_confirmed")?;
            let mut plan_near_hits = own_layer(&plan_near_hits, "plan_near_hits")?;
            let (plan_near_hits, _) = layer(&mut plan_near_hits, "plan_near_hits")?;
            let camera = pose(camera);
            let inner = &mut self.inner;
            py.detach(|| {
                inner.insert_visual(
                    values,
                    confirmed,
                    Some(PlanLayers {
                        log_odds: plan_values,
                        confirmed: plan_confirmed,
                        near_hits: plan_near_hits,
                    }),
                    origin_cells,
                    camera,
                    &readings,
                    &model,
                )
            })
            .py()
        })
    }

    /// Adds an ideal 2-D laser scan to `log_odds` and to the planner's `plan_log_odds` (in
    /// place): the fan from the sensor at `sensor_cell` to the beam ends `end_cells` (N, 2)
    /// [fractional cells of the window] gets `miss_nats`, the end cells where `returned` (N,)
    /// bool get `hit_nats`.
    #[allow(clippy::too_many_arguments)]
    fn insert_laser(
        &mut self,
        py: Python<'_>,
        mut log_odds: PyReadwriteArray2<'_, f32>,
        plan_log_odds: Bound<'_, PyArray2<f32>>,
        sensor_cell: (f64, f64),
        end_cells: PyReadonlyArray2<'_, f64>,
        returned: PyReadonlyArray1<'_, bool>,
        hit_nats: f32,
        miss_nats: f32,
    ) -> PyResult<()> {
        guard(|| {
            let (flat, n) = rows(&end_cells, 2, "end_cells")?;
            let ends: Vec<[f64; 2]> = (0..n).map(|k| [flat[2 * k], flat[2 * k + 1]]).collect();
            let returned = returned.as_slice().map_err(|_| {
                error(
                    "LengthMismatchError",
                    "`returned` must be a contiguous 1-D bool array".into(),
                )
            })?;
            let (values, _) = layer(&mut log_odds, "log_odds")?;
            let mut plan_log_odds = own_layer(&plan_log_odds, "plan_log_odds")?;
            let (plan_values, _) = layer(&mut plan_log_odds, "plan_log_odds")?;
            let inner = &mut self.inner;
            let sensor = [sensor_cell.0, sensor_cell.1];
            py.detach(|| {
                inner.insert_laser(
                    values,
                    Some(plan_values),
                    sensor,
                    &ends,
                    returned,
                    hit_nats,
                    miss_nats,
                )
            })
            .py()
        })
    }
}

/// Forgetting: every value of `values` (float32, in place) times `factor`.
#[pyfunction]
pub fn decay(py: Python<'_>, mut values: PyReadwriteArray2<'_, f32>, factor: f32) -> PyResult<()> {
    guard(|| {
        let (v, _) = layer(&mut values, "values")?;
        py.detach(|| avoidance_map::decay(v, factor));
        Ok(())
    })
}
