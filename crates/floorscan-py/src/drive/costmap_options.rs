//! Bindings of `floorscan_core::costmap_options`: the defaults, check and schema of `CostmapOptions`.

use floorscan_core::costmap_options::CostmapOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    CostmapOptions,
    default_costmap_options,
    check_costmap_options,
    costmap_options_schema
);
