//! Bindings of `floorscan_core::pose_graph_options`: the defaults, check and schema of
//! `PoseGraphOptions` (the config file's `[slam.graph]`).

use floorscan_core::PoseGraphOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    PoseGraphOptions,
    default_pose_graph_options,
    check_pose_graph_options,
    pose_graph_options_schema
);

/// `PoseGraphOptions::field_half_side_m` of a dict of its fields: the half-side [m] of a
/// search's likelihood field around the pose searched from.
#[pyfunction]
pub fn pose_graph_field_half_side_m(options: &Bound<'_, PyAny>) -> PyResult<f64> {
    crate::errors::guard(|| {
        let o: PoseGraphOptions = crate::options::from_py(options)?;
        Ok(o.field_half_side_m())
    })
}
