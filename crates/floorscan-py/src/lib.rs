//! floorscan's native Python module (`floorscan._native`). Thin: numpy in and out, the GIL
//! released on heavy calls, every core error mapped to its Python class. The public, documented
//! API is the Python package `floorscan`, which wraps these classes.

use pyo3::prelude::*;

mod appearance;
mod errors;
mod evidence;
mod grid;
mod ground_table;
mod image;
mod local_map;
mod log_odds;
mod options;
mod ranger;
mod scan;
mod sim;

/// Panics inside [`errors::guard`], for the test that a panic reaches Python as
/// `floorscan.errors.InternalError` (never `PanicException`).
#[pyfunction]
fn _panic_for_tests() -> PyResult<()> {
    errors::guard(|| panic!("deliberate panic for the FFI guard test"))
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_function(wrap_pyfunction!(_panic_for_tests, m)?)?;
    m.add_class::<ground_table::PyGroundTable>()?;
    m.add_class::<ranger::PyVisualRanger>()?;
    m.add_class::<appearance::PyAppearanceRanger>()?;
    m.add_function(wrap_pyfunction!(appearance::fuse, m)?)?;
    m.add_function(wrap_pyfunction!(ranger::default_ranger_options, m)?)?;
    m.add_function(wrap_pyfunction!(ranger::check_ranger_options, m)?)?;
    m.add_function(wrap_pyfunction!(ranger::ranger_options_schema, m)?)?;
    m.add_function(wrap_pyfunction!(appearance::default_appearance_options, m)?)?;
    m.add_function(wrap_pyfunction!(appearance::check_appearance_options, m)?)?;
    m.add_function(wrap_pyfunction!(appearance::appearance_options_schema, m)?)?;
    m.add_function(wrap_pyfunction!(grid::default_grid_options, m)?)?;
    m.add_function(wrap_pyfunction!(grid::check_grid_options, m)?)?;
    m.add_function(wrap_pyfunction!(grid::grid_options_schema, m)?)?;
    m.add_function(wrap_pyfunction!(grid::default_inserter_options, m)?)?;
    m.add_function(wrap_pyfunction!(grid::check_inserter_options, m)?)?;
    m.add_function(wrap_pyfunction!(grid::inserter_options_schema, m)?)?;
    m.add_function(wrap_pyfunction!(local_map::default_local_map_options, m)?)?;
    m.add_function(wrap_pyfunction!(local_map::check_local_map_options, m)?)?;
    m.add_function(wrap_pyfunction!(local_map::local_map_options_schema, m)?)?;
    m.add_class::<scan::PyScan>()?;
    m.add_class::<grid::PyOccupancyGrid>()?;
    m.add_class::<local_map::PyLocalMap>()?;
    m.add_function(wrap_pyfunction!(scan::column_statuses, m)?)?;
    m.add("SCAN_CSV_HEADER", floorscan_core::scan::SCAN_CSV_HEADER)?;
    log_odds::register(m)?;
    sim::register(m)?;
    evidence::register(m)?;
    Ok(())
}
