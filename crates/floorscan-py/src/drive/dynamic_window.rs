//! Bindings of `floorscan_core::dynamic_window`: the dynamic window's roll-outs and scores
//! over numpy rasters.

use floorscan_core::dynamic_window::{best_sample, Raster, WindowScoring};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::{error, guard, to_pyerr};

fn slice2<'a, T: numpy::Element>(
    a: &'a PyReadonlyArray2<'_, T>,
    name: &str,
) -> PyResult<(&'a [T], usize, usize)> {
    let shape = a.shape().to_vec();
    let s = a.as_slice().map_err(|_| {
        error(
            "LengthMismatchError",
            format!("`{name}` must be C-contiguous"),
        )
    })?;
    Ok((s, shape[1], shape[0]))
}

fn slice1<'a, T: numpy::Element>(a: &'a PyReadonlyArray1<'_, T>, name: &str) -> PyResult<&'a [T]> {
    a.as_slice().map_err(|_| {
        error(
            "LengthMismatchError",
            format!("`{name}` must be contiguous"),
        )
    })
}

/// The index `k = iw * len(vs) + iv` of the dynamic window's chosen sample of `vs` (float64
/// [m/s]) x `omegas` (float64 [rad/s]) rolled out from `pose` (x, y, yaw) at `times_s`
/// (float64 [s]), or None when no sample is admissible (`floorscan_core::dynamic_window`).
/// `cost` (H, W) uint8 and `unknown` (H, W) bool share `origin_m` and `cell_m`; `nav` (h, w)
/// float64 [m] has its own `nav_origin_m` and `nav_cell_m`; `scoring` is (path_distance_bias,
/// goal_distance_bias, occdist_scale, forward_point_distance_m, blind_radius_m); costs from
/// `inscribed` up are not admissible.
#[pyfunction]
#[pyo3(signature = (pose, vs, omegas, times_s, cost, origin_m, cell_m, unknown, nav, nav_origin_m, nav_cell_m, goal, scoring, inscribed))]
#[allow(clippy::too_many_arguments)]
pub fn best_velocity_sample(
    py: Python<'_>,
    pose: [f64; 3],
    vs: PyReadonlyArray1<'_, f64>,
    omegas: PyReadonlyArray1<'_, f64>,
    times_s: PyReadonlyArray1<'_, f64>,
    cost: PyReadonlyArray2<'_, u8>,
    origin_m: [f64; 2],
    cell_m: f64,
    unknown: Option<PyReadonlyArray2<'_, bool>>,
    nav: PyReadonlyArray2<'_, f64>,
    nav_origin_m: [f64; 2],
    nav_cell_m: f64,
    goal: [f64; 2],
    scoring: [f64; 5],
    inscribed: u8,
) -> PyResult<Option<usize>> {
    guard(|| {
        let (c, w, h) = slice2(&cost, "cost")?;
        let cost = Raster::new(c, w, h, origin_m, cell_m).map_err(to_pyerr)?;
        let unknown = match &unknown {
            Some(u) => {
                let (d, uw, uh) = slice2(u, "unknown")?;
                if (uw, uh) != (w, h) {
                    return Err(error(
                        "LengthMismatchError",
                        "`unknown` must have the shape of `cost`".into(),
                    ));
                }
                Some(Raster::new(d, w, h, origin_m, cell_m).map_err(to_pyerr)?)
            }
            None => None,
        };
        let (n, nw, nh) = slice2(&nav, "nav")?;
        let nav = Raster::new(n, nw, nh, nav_origin_m, nav_cell_m).map_err(to_pyerr)?;
        let [path_distance_bias, goal_distance_bias, occdist_scale, forward_point_distance_m, blind_radius_m] =
            scoring;
        let scoring = WindowScoring {
            path_distance_bias,
            goal_distance_bias,
            occdist_scale,
            forward_point_distance_m,
            blind_radius_m,
            inscribed,
        };
        let (vs, omegas, times) = (
            slice1(&vs, "vs")?,
            slice1(&omegas, "omegas")?,
            slice1(&times_s, "times_s")?,
        );
        py.detach(|| {
            best_sample(
                pose,
                vs,
                omegas,
                times,
                &cost,
                unknown.as_ref(),
                &nav,
                goal,
                cell_m,
                &scoring,
            )
        })
        .map_err(to_pyerr)
    })
}
