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
