//! Bindings of `floorscan_core::navigation`: the planner's navigation function over numpy grids.

use numpy::{
    PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::{error, guard, to_pyerr};

/// Geodesic cost-to-goal (H, W) float64 [m, weighted] over an 8-connected grid: `blocked`
/// (H, W) bool cells are never entered, a step costs its length (`step_m` or sqrt 2 times it)
/// times the mean `weight` (H, W) float64 of its two cells; `seed_cells` (K,) int64 row-major
/// cell indices start at `seed_costs` (K,) float64. `inf` where nothing reaches.
#[pyfunction]
pub fn geodesic_distances<'py>(
    py: Python<'py>,
    blocked: PyReadonlyArray2<'py, bool>,
    weight: PyReadonlyArray2<'py, f64>,
    seed_cells: PyReadonlyArray1<'py, i64>,
    seed_costs: PyReadonlyArray1<'py, f64>,
    step_m: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    guard(|| {
        let shape = blocked.shape().to_vec();
        if weight.shape() != shape.as_slice() || seed_cells.len() != seed_costs.len() {
            return Err(error(
                "LengthMismatchError",
                "`weight` must have the shape of `blocked`, `seed_costs` the length of \
                 `seed_cells`"
                    .into(),
            ));
        }
        let contiguous = |ok: bool| {
            if ok {
                Ok(())
            } else {
                Err(error(
                    "LengthMismatchError",
                    "arrays must be C-contiguous".into(),
                ))
            }
        };
        contiguous(blocked.is_c_contiguous() && weight.is_c_contiguous())?;
        let (h, w) = (shape[0], shape[1]);
        let b = blocked
            .as_slice()
            .map_err(|_| error("LengthMismatchError", "blocked".into()))?;
        let wt = weight
            .as_slice()
            .map_err(|_| error("LengthMismatchError", "weight".into()))?;
        let cells = seed_cells.as_array();
        let costs = seed_costs.as_array();
        let mut seeds = Vec::with_capacity(cells.len());
        for (&c, &d) in cells.iter().zip(costs.iter()) {
            if c < 0 {
                return Err(error("InvalidGeometryError", format!("seed cell {c} < 0")));
            }
            seeds.push((c as usize, d));
        }
        let out = py
            .detach(|| floorscan_core::navigation::geodesic_distances(w, h, b, wt, &seeds, step_m))
            .map_err(to_pyerr)?;
        PyArray1::from_vec(py, out).reshape([h, w])
    })
}

/// The navigation function's coarse grid from a costmap `cost` (H, W) uint8 in blocks of
/// `factor` x `factor` cells: (blocked (h, w) bool: every cell of the block costs
/// `blocked_from` or more; weight (h, w) float64: 1 + min(mean cost, blocked_from) / 64, plus
/// `unknown_cost` times the block's share of cells not `known` (H, W) bool when given).
#[pyfunction]
#[pyo3(signature = (cost, factor, blocked_from, unknown_cost, known=None))]
#[allow(clippy::type_complexity)]
pub fn coarse_grid<'py>(
    py: Python<'py>,
    cost: PyReadonlyArray2<'py, u8>,
    factor: usize,
    blocked_from: u8,
    unknown_cost: f64,
    known: Option<PyReadonlyArray2<'py, bool>>,
) -> PyResult<(Bound<'py, PyArray2<bool>>, Bound<'py, PyArray2<f64>>)> {
    guard(|| {
        let shape = cost.shape().to_vec();
        let c = cost
            .as_slice()
            .map_err(|_| error("LengthMismatchError", "`cost` must be C-contiguous".into()))?;
        let k = match &known {
            Some(k) if k.shape() != shape.as_slice() => {
                return Err(error(
                    "LengthMismatchError",
                    "`known` must have the shape of `cost`".into(),
                ))
            }
            Some(k) => Some(k.as_slice().map_err(|_| {
                error("LengthMismatchError", "`known` must be C-contiguous".into())
            })?),
            None => None,
        };
        let (mut blocked, mut weight) = (Vec::new(), Vec::new());
        let (w, h) = py
            .detach(|| {
                floorscan_core::navigation::coarse_grid(
                    c,
                    shape[1],
                    shape[0],
                    k,
                    factor,
                    blocked_from,
                    unknown_cost,
                    &mut blocked,
                    &mut weight,
                )
            })
            .map_err(to_pyerr)?;
        Ok((
            PyArray1::from_vec(py, blocked).reshape([h, w])?,
            PyArray1::from_vec(py, weight).reshape([h, w])?,
        ))
    })
}
