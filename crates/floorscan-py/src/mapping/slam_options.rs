//! Bindings of `floorscan_core::slam_options`: the defaults, check and schema of `SlamOptions`
//! (the config file's `[slam]`).

use floorscan_core::SlamOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    SlamOptions,
    default_slam_options,
    check_slam_options,
    slam_options_schema
);
