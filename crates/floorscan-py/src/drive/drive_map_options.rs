//! Bindings of `floorscan_core::drive_map_options`: the defaults, check and schema of
//! `DriveMapOptions` (the config file's `[drive]` table).

use floorscan_core::drive_map_options::DriveMapOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    DriveMapOptions,
    default_drive_map_options,
    check_drive_map_options,
    drive_map_options_schema
);
