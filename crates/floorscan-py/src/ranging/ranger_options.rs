//! Bindings of `floorscan_core::ranger_options`: the defaults, check and schema of
//! `RangerOptions`.

use floorscan_core::RangerOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    RangerOptions,
    default_ranger_options,
    check_ranger_options,
    ranger_options_schema
);
