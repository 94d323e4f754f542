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
