//! Bindings of `floorscan_core::appearance_options`: the defaults, check and schema of
//! `AppearanceOptions`.

use floorscan_core::AppearanceOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    AppearanceOptions,
    default_appearance_options,
    check_appearance_options,
    appearance_options_schema
);
