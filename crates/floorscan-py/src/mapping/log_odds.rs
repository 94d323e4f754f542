//! Bindings of `floorscan_core::log_odds`: the stored unit of a cell (1/1000 nat) and the
//! conversions between probability and log-odds, over numpy arrays.

use floorscan_core::log_odds::{
    log_odds_from_probability, probability_from_log_odds, MAX_ABS_UNITS, UNITS_PER_NAT,
};
use floorscan_core::Occupancy;
use numpy::{PyArray1, PyArrayDyn, PyArrayMethods, PyReadonlyArrayDyn};
use pyo3::prelude::*;

/// Probabilities of stored log-odds values (any shape, int16 or int32 [1/1000 nat]) as
/// float64: `1 / (1 + exp(-units / 1000))`.
#[pyfunction]
pub fn probabilities_from_units<'py>(
    py: Python<'py>,
    units: PyReadonlyArrayDyn<'py, i32>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    crate::errors::guard(|| {
        let a = units.as_array();
        let shape = a.shape().to_vec();
        let out: Vec<f64> = py.detach(|| {
            a.iter()
                .map(|&u| probability_from_log_odds(u as f64 / UNITS_PER_NAT))
                .collect()
        });
        PyArray1::from_vec(py, out).reshape(shape)
    })
}

/// Stored log-odds units (int16, rounded, within +-`MAX_ABS_UNITS` and then `[lo, hi]`) of
/// probabilities (any shape, float64 in [0, 1]; 0 and 1 go to the bounds, NaN to 0).
#[pyfunction]
pub fn units_from_probabilities<'py>(
    py: Python<'py>,
    probabilities: PyReadonlyArrayDyn<'py, f64>,
    lo: i16,
    hi: i16,
) -> PyResult<Bound<'py, PyArrayDyn<i16>>> {
    crate::errors::guard(|| {
        let a = probabilities.as_array();
        let shape = a.shape().to_vec();
        let (lo, hi) = (lo.max(-MAX_ABS_UNITS), hi.min(MAX_ABS_UNITS).max(lo));
        let out: Vec<i16> = py.detach(|| {
            a.iter()
                .map(|&p| {
                    let u = (log_odds_from_probability(p) * UNITS_PER_NAT).round();
                    if u.is_nan() {
                        0
                    } else {
                        u.clamp(lo as f64, hi as f64) as i16
                    }
                })
                .collect()
        });
        PyArray1::from_vec(py, out).reshape(shape)
    })
}

/// Every occupancy class as (name, code), in code order (`floorscan.Occupancy` is built from
/// it).
#[pyfunction]
pub fn occupancy_classes() -> Vec<(&'static str, u8)> {
    Occupancy::ALL
        .iter()
        .map(|o| (o.as_str(), o.code()))
        .collect()
}
