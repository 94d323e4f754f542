//! Bindings of `floorscan_core::scan_matcher_options`: the defaults, check and schema of
//! `ScanMatcherOptions`.

use floorscan_core::ScanMatcherOptions;
use pyo3::prelude::*;

use crate::options::options_functions;

options_functions!(
    ScanMatcherOptions,
    default_scan_matcher_options,
    check_scan_matcher_options,
    scan_matcher_options_schema
);
