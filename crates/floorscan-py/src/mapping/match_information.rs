//! Bindings of `floorscan_core::match_information`: a scan match's information matrix over a
//! numpy likelihood field.

use floorscan_core::match_information::match_information as information;
use numpy::{PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray2};
use pyo3::prelude::*;

use crate::errors::{guard, to_pyerr};

/// The information matrix (3, 3) float64 of `points` (N, 2) float64 [m, robot frame] matched at
/// `pose` (world_from_robot): minus the Hessian of the sum of `field` (H, W) float32 (row 0 =
/// lowest y, cell (0, 0)'s corner at `origin_m`, cells `cell_m` wide) read bilinearly at the
/// points over (x, y, yaw), by central differences of a cell and of `yaw_step_rad`, its
/// negative eigenvalues cut to 0; a point whose four cells leave the field reads 0
/// (`floorscan_core::match_information`).
#[pyfunction]
pub fn match_information<'py>(
    py: Python<'py>,
    field: PyReadonlyArray2<'_, f32>,
    origin_m: (f64, f64),
    cell_m: f64,
    points: PyReadonlyArray2<'_, f64>,
    pose: [f64; 3],
    yaw_step_rad: f64,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    guard(|| {
        let (f, pts) =
            crate::correlative_search::field_and_points(&field, origin_m, cell_m, &points)?;
        let m = py
            .detach(|| information(&f, &pts, crate::arrays::pose(pose), yaw_step_rad))
            .map_err(to_pyerr)?;
        PyArray1::from_vec(py, m.concat()).reshape([3, 3])
    })
}
