//! Shared argument conversions of the bindings: poses, numpy slices and rows, laser layouts,
//! sonar readings, update statistics.

use floorscan_core::{BeamAngles, LaserScan, Pose2, SonarReading, UpdateStats};
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::errors::error;

pub type Stats = (u64, u64, u64);

pub fn stats(s: UpdateStats) -> Stats {
    (s.rays, s.cells_traversed, s.cells_hit)
}

pub fn pose(p: [f64; 3]) -> Pose2 {
    Pose2::new(p[0], p[1], p[2])
}

/// A contiguous 1-D view, or a clear error naming the argument.
pub fn slice1<'a>(a: &'a PyReadonlyArray1<'_, f64>, name: &str) -> PyResult<&'a [f64]> {
    a.as_slice().map_err(|_| {
        error(
            "LengthMismatchError",
            format!("`{name}` must be a contiguous 1-D float64 array"),
        )
    })
}

/// An (N, k) contiguous float64 array as a flat slice and N.
pub fn rows<'a>(
    a: &'a PyReadonlyArray2<'_, f64>,
    k: usize,
    name: &str,
) -> PyResult<(&'a [f64], usize)> {
    let shape = a.shape();
    if shape[1] != k {
        return Err(error(
            "LengthMismatchError",
            format!(
                "`{name}` must have shape (N, {k}), got ({}, {})",
                shape[0], shape[1]
            ),
        ));
    }
    let s = a.as_slice().map_err(|_| {
        error(
            "LengthMismatchError",
            format!("`{name}` must be a contiguous float64 array"),
        )
    })?;
    Ok((s, shape[0]))
}

/// The laser layout: explicit angles, or a uniform fan.
pub fn laser_layout<'a>(
    ranges: &'a [f64],
    angles: Option<&'a [f64]>,
    angle_min: f64,
    angle_increment: f64,
    range_min: f64,
    range_max: f64,
) -> LaserScan<'a> {
    let angles = match angles {
        Some(a) => BeamAngles::Explicit(a),
        None => BeamAngles::Uniform {
            min_rad: angle_min,
            increment_rad: angle_increment,
        },
    };
    LaserScan {
        ranges_m: ranges,
        angles,
        range_min_m: range_min,
        range_max_m: range_max,
    }
}

/// Sonar readings and their mounts from arrays.
pub fn sonar_readings(
    ranges: &[f64],
    mounts: &[f64],
    beam_width: f64,
    range_max: f64,
) -> PyResult<(Vec<SonarReading>, Vec<Pose2>)> {
    if mounts.len() != 3 * ranges.len() {
        return Err(error(
            "LengthMismatchError",
            format!(
                "{} sonar ranges but {} mounts",
                ranges.len(),
                mounts.len() / 3
            ),
        ));
    }
    let readings = ranges
        .iter()
        .map(|&r| SonarReading {
            range_m: r,
            beam_width_rad: beam_width,
            range_max_m: range_max,
        })
        .collect();
    let poses = mounts
        .chunks(3)
        .map(|m| Pose2::new(m[0], m[1], m[2]))
        .collect();
    Ok((readings, poses))
}
