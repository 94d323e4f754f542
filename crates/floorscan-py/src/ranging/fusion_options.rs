//! Bindings of `floorscan_core::fusion_options`: the defaults, check and schema of
//! `FusionOptions` (the fused ranger's keys of the config file's `[appearance]`).

use floorscan_core::FusionOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    FusionOptions,
    default_fusion_options,
    check_fusion_options,
    fusion_options_schema
);
