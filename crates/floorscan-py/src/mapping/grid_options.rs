//! Bindings of `floorscan_core::grid_options`: the defaults, check and schema of `GridOptions`.

use floorscan_core::GridOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    GridOptions,
    default_grid_options,
    check_grid_options,
    grid_options_schema
);
