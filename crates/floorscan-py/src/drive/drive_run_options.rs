//! Bindings of `floorscan_core::drive_run_options`: the defaults, check and schema of
//! `DriveRunOptions`.

use floorscan_core::drive_run_options::DriveRunOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    DriveRunOptions,
    default_drive_run_options,
    check_drive_run_options,
    drive_run_options_schema
);
