//! Bindings of `floorscan_core::inserter`: the defaults, check and schema of
//! `InserterOptions` (the inserter itself lives inside the grid and local map bindings).

use floorscan_core::InserterOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    InserterOptions,
    default_inserter_options,
    check_inserter_options,
    inserter_options_schema
);
