//! Bindings of `floorscan_core::dwa_options`: the defaults, check and schema of `DwaOptions`.

use floorscan_core::dwa_options::DwaOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    DwaOptions,
    default_dwa_options,
    check_dwa_options,
    dwa_options_schema
);
