//! Bindings of `floorscan_core::avoidance_map_options`: the defaults, check and schema of `AvoidanceMapOptions`.

use floorscan_core::avoidance_map_options::AvoidanceMapOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    AvoidanceMapOptions,
    default_avoidance_map_options,
    check_avoidance_map_options,
    avoidance_map_options_schema
);
