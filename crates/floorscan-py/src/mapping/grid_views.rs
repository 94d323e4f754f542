//! Read-only views shared by the global grid and the local map (the Python
//! `floorscan.mapping.grid_views`): raw values, extent, classes, distances, limits.

use floorscan_core::{Grid, Point2};
use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::prelude::*;

use crate::errors::{error, IntoPyResult};

/// Read-only views shared by the global grid and the local map.
pub fn values<'py>(
    py: Python<'py>,
    grid: &Grid,
    min_x: i64,
    min_y: i64,
    width: u64,
    height: u64,
) -> PyResult<Bound<'py, PyArray2<i16>>> {
    let rect = grid.checked_rect(min_x, min_y, width, height).py()?;
    let mut out = Vec::new();
    py.detach(|| grid.read_rect(rect, &mut out));
    PyArray1::from_vec(py, out).reshape([rect.height(), rect.width()])
}

pub fn extent(grid: &Grid) -> (i32, i32, usize, usize) {
    let r = grid.extent();
    (r.min.x, r.min.y, r.width(), r.height())
}

pub fn occupancy_codes<'py>(
    py: Python<'py>,
    grid: &Grid,
    xs: &[f64],
    ys: &[f64],
) -> PyResult<Bound<'py, PyArray1<u8>>> {
    if xs.len() != ys.len() {
        return Err(error(
            "LengthMismatchError",
            format!("{} x but {} y coordinates", xs.len(), ys.len()),
        ));
    }
    let codes: Vec<u8> = xs
        .iter()
        .zip(ys)
        .map(|(&x, &y)| grid.occupancy_at(Point2::new(x, y)).map(|o| o.code()))
        .collect::<floorscan_core::Result<_>>()
        .py()?;
    Ok(PyArray1::from_vec(py, codes))
}

pub fn distances<'py>(
    py: Python<'py>,
    grid: &Grid,
    xs: &[f64],
    ys: &[f64],
    max_m: f64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    if xs.len() != ys.len() {
        return Err(error(
            "LengthMismatchError",
            format!("{} x but {} y coordinates", xs.len(), ys.len()),
        ));
    }
    let d: Vec<f64> = py
        .detach(|| {
            xs.iter()
                .zip(ys)
                .map(|(&x, &y)| {
                    grid.distance_to_occupied(Point2::new(x, y), max_m)
                        .map(|d| d.unwrap_or(f64::INFINITY))
                })
                .collect::<floorscan_core::Result<_>>()
        })
        .py()?;
    Ok(PyArray1::from_vec(py, d))
}

pub fn limits(grid: &Grid) -> (i16, i16, i16, i16) {
    let l = grid.limits();
    (l.clamp_min, l.clamp_max, l.occupied_at, l.free_at)
}
