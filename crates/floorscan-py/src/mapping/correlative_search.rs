//! Bindings of `floorscan_core::correlative_search`: the correlative search over a numpy likelihood
//! field.

use floorscan_core::correlative_search::{refine, search, Field, SearchWindow};
use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::arrays::{pose, rows};
use crate::errors::{error, guard, to_pyerr};

/// A numpy likelihood field (H, W) float32 as a [`Field`], and `points` (N, 2) float64.
pub(crate) fn field_and_points<'a>(
    field: &'a PyReadonlyArray2<'_, f32>,
    origin_m: (f64, f64),
    cell_m: f64,
    points: &PyReadonlyArray2<'_, f64>,
) -> PyResult<(Field<'a>, Vec<[f64; 2]>)> {
    let shape = field.shape().to_vec();
    let values = field
        .as_slice()
        .map_err(|_| error("LengthMismatchError", "`field` must be C-contiguous".into()))?;
    let (flat, n) = rows(points, 2, "points")?;
    let pts: Vec<[f64; 2]> = (0..n).map(|k| [flat[2 * k], flat[2 * k + 1]]).collect();
    let f = Field {
        values,
        width: shape[1],
        height: shape[0],
        origin_m,
        cell_m,
    };
    Ok((f, pts))
}

/// The best pose (x, y, yaw), its mean field value and its score for `points` (N, 2) float64
/// [m, robot frame] around `prior` (world_from_robot): translations of -xy_steps..=xy_steps
/// cells of `field` (H, W) float32 (values in [0, 1], row 0 = lowest y, cell (0, 0)'s corner
/// at `origin_m`, cells `cell_m` wide), yaws of -yaw_steps..=yaw_steps times `yaw_step_rad`;
/// score = mean field value x exp(-(|t| / prior_xy_m)^2 - (dyaw / prior_yaw_rad)^2); then
/// refined below a cell on the field read bilinearly (`floorscan_core::correlative_search::refine`).
#[pyfunction]
#[allow(clippy::too_many_arguments)]
pub fn correlative_search(
    py: Python<'_>,
    field: PyReadonlyArray2<'_, f32>,
    origin_m: (f64, f64),
    cell_m: f64,
    points: PyReadonlyArray2<'_, f64>,
    prior: [f64; 3],
    xy_steps: u32,
    yaw_steps: u32,
    yaw_step_rad: f64,
    prior_xy_m: f64,
    prior_yaw_rad: f64,
) -> PyResult<((f64, f64, f64), f64, f64)> {
    guard(|| {
        let (f, pts) = field_and_points(&field, origin_m, cell_m, &points)?;
        let window = SearchWindow {
            xy_steps,
            yaw_steps,
            yaw_step_rad,
            prior_xy_m,
            prior_yaw_rad,
        };
        let prior = pose(prior);
        let r = py
            .detach(|| {
                search(&f, &pts, prior, &window).map(|r| refine(&f, &pts, r.pose, prior, &window))
            })
            .map_err(to_pyerr)?;
        Ok(((r.pose.x, r.pose.y, r.pose.yaw), r.mean, r.score))
    })
}
