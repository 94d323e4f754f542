//! Bindings of `floorscan_core::parallax_options`: the defaults, check and schema of
//! `ParallaxOptions` (the config file's `[parallax]`).

use floorscan_core::ParallaxOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    ParallaxOptions,
    default_parallax_options,
    check_parallax_options,
    parallax_options_schema
);
