//! floorscan's native Python module (`floorscan._native`). Thin: numpy in and out, the GIL
//! released on heavy calls, every core error mapped to its Python class. The public, documented
//! API is the Python package `floorscan`, which wraps these classes.
//!
//! One submodule per stage of the Python package (`floorscan._native.ranging`, `.mapping`,
//! `.drive`, `.formats`, `.sim`), registered in `sys.modules` so that
//! `from floorscan._native.sim import SimWorld` works; one binding file per core module with a Python face. The type stubs
//! (`python/floorscan/_native/*.pyi`) are generated from these declarations
//! (`make stubs`, crates/floorscan-stubgen) and checked for drift by `make test`.

use pyo3::prelude::*;

mod arrays;
mod drive;
mod errors;
mod formats;
mod image;
mod mapping;
mod options;
mod ranging;
mod sim;

// Each binding file also at the crate root (`crate::ranger`), as before the files were grouped
// by the package's submodules.
use drive::{
    avoidance_map, avoidance_map_options, costmap_options, drive_map_options, drive_run_options,
    dwa_options, dynamic_window, navigation, visual_sensor_model,
};
use formats::{gif, png, read_ahead};
use mapping::{
    correlative_search, evidence, grid, grid_options, grid_views, inserter, local_map, log_odds,
    match_information, pose_graph_options, scan_matcher, scan_matcher_options, slam_options,
};
use ranging::{
    appearance, appearance_options, floor_parallax, fusion_options, ground_table, parallax_options,
    ranger, ranger_options, scan,
};

/// Panics inside [`errors::guard`], for the test that a panic reaches Python as
/// `floorscan.errors.InternalError` (never `PanicException`).
#[pyfunction]
pub fn _panic_for_tests() -> PyResult<()> {
    errors::guard(|| panic!("deliberate panic for the FFI guard test"))
}

/// Makes a submodule importable by its full name (`floorscan._native.NAME`).
fn register_submodule(m: &Bound<'_, PyModule>, name: &str) -> PyResult<()> {
    let full = format!("floorscan._native.{name}");
    m.setattr("__name__", &full)?;
    m.py()
        .import("sys")?
        .getattr("modules")?
        .set_item(full, m)?;
    Ok(())
}

#[pymodule]
mod _native {
    use super::*;

    #[pymodule_export]
    use super::_panic_for_tests;

    /// The package version (the crates').
    #[pymodule_export]
    #[allow(non_upper_case_globals)]
    const __version__: &str = env!("CARGO_PKG_VERSION");

    /// Ranging: ground tables, the edge and appearance rangers, scans.
    #[pymodule]
    mod ranging {
        use super::*;

        #[pymodule_export]
        use crate::appearance::{fuse, PyAppearanceRanger};
        #[pymodule_export]
        use crate::appearance_options::{
            appearance_options_schema, check_appearance_options, default_appearance_options,
        };
        #[pymodule_export]
        use crate::floor_parallax::PyFloorParallax;
        #[pymodule_export]
        use crate::fusion_options::{
            check_fusion_options, default_fusion_options, fusion_options_schema,
        };
        #[pymodule_export]
        use crate::ground_table::PyGroundTable;
        #[pymodule_export]
        use crate::parallax_options::{
            check_parallax_options, default_parallax_options, parallax_options_schema,
        };
        #[pymodule_export]
        use crate::ranger::PyVisualRanger;
        #[pymodule_export]
        use crate::ranger_options::{
            check_ranger_options, default_ranger_options, ranger_options_schema,
        };
        #[pymodule_export]
        use crate::scan::{column_statuses, PyScan};

        /// The scans CSV header (`floorscan_core::scan::SCAN_CSV_HEADER`).
        #[pymodule_export]
        const SCAN_CSV_HEADER: &str = floorscan_core::scan::SCAN_CSV_HEADER;

        /// Also loads NumPy's C API while the package is imported (the first submodule):
        /// rust-numpy would load it on the first array made, running Python code there, and
        /// panic if a signal's exception (a Ctrl-C, a SIGTERM) interrupted that code. Here the
        /// exception propagates as the import's.
        #[pymodule_init]
        fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
            m.py().import("numpy")?;
            errors::guard(|| {
                numpy::PyArray1::<u8>::zeros(m.py(), 0, false);
                Ok(())
            })?;
            register_submodule(m, "ranging")
        }
    }

    /// Mapping: the global grid, the local map, evidence merges, log-odds, the correlative scan
    /// matcher (its search, its match's information) and SLAM's options.
    #[pymodule]
    mod mapping {
        use super::*;

        #[pymodule_export]
        use crate::correlative_search::correlative_search;
        #[pymodule_export]
        use crate::evidence::merge_evidence;
        #[pymodule_export]
        use crate::grid::PyOccupancyGrid;
        #[pymodule_export]
        use crate::grid_options::{check_grid_options, default_grid_options, grid_options_schema};
        #[pymodule_export]
        use crate::inserter::{
            check_inserter_options, default_inserter_options, inserter_options_schema,
        };
        #[pymodule_export]
        use crate::local_map::{
            check_local_map_options, default_local_map_options, local_map_options_schema,
            PyLocalMap,
        };
        #[pymodule_export]
        use crate::log_odds::{
            occupancy_classes, probabilities_from_units, units_from_probabilities,
        };
        #[pymodule_export]
        use crate::match_information::match_information;
        #[pymodule_export]
        use crate::pose_graph_options::{
            check_pose_graph_options, default_pose_graph_options, pose_graph_field_half_side_m,
            pose_graph_options_schema,
        };
        #[pymodule_export]
        use crate::scan_matcher::PyScanMatcher;
        #[pymodule_export]
        use crate::scan_matcher_options::{
            check_scan_matcher_options, default_scan_matcher_options, scan_matcher_options_schema,
        };
        #[pymodule_export]
        use crate::slam_options::{check_slam_options, default_slam_options, slam_options_schema};

        /// How far [m] the pose graph's rolling submap field may be used from where it was built
        /// (`floorscan_core::pose_graph_options::FIELD_REUSE_M`).
        #[pymodule_export]
        const FIELD_REUSE_M: f64 = floorscan_core::pose_graph_options::FIELD_REUSE_M;

        /// Stored log-odds units per nat (`floorscan_core::log_odds::UNITS_PER_NAT`).
        #[pymodule_export]
        const UNITS_PER_NAT: f64 = floorscan_core::log_odds::UNITS_PER_NAT;

        /// Largest stored log-odds magnitude (`floorscan_core::log_odds::MAX_ABS_UNITS`).
        #[pymodule_export]
        const MAX_ABS_UNITS: i16 = floorscan_core::log_odds::MAX_ABS_UNITS;

        #[pymodule_init]
        fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
            register_submodule(m, "mapping")
        }
    }

    /// Driving: the avoidance map, the planner's navigation function and dynamic window, the
    /// drive's options.
    #[pymodule]
    mod drive {
        use super::*;

        #[pymodule_export]
        use crate::avoidance_map::PyAvoidanceMap;
        #[pymodule_export]
        use crate::avoidance_map_options::{
            avoidance_map_options_schema, check_avoidance_map_options,
            default_avoidance_map_options,
        };
        #[pymodule_export]
        use crate::costmap_options::{
            check_costmap_options, costmap_options_schema, default_costmap_options,
        };
        #[pymodule_export]
        use crate::drive_map_options::{
            check_drive_map_options, default_drive_map_options, drive_map_options_schema,
        };
        #[pymodule_export]
        use crate::drive_run_options::{
            check_drive_run_options, default_drive_run_options, drive_run_options_schema,
        };
        #[pymodule_export]
        use crate::dwa_options::{check_dwa_options, default_dwa_options, dwa_options_schema};
        #[pymodule_export]
        use crate::visual_sensor_model::{
            check_visual_sensor_model, default_visual_sensor_model, visual_sensor_model_schema,
        };

        #[pymodule_export]
        use crate::dynamic_window::best_velocity_sample;
        #[pymodule_export]
        use crate::navigation::{coarse_grid, geodesic_distances};

        #[pymodule_init]
        fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
            register_submodule(m, "drive")
        }
    }

    /// Formats: image files in Rust, the GIL released: PNG decoding (and reading ahead), the
    /// overlay's GIF stream.
    #[pymodule]
    mod formats {
        use super::*;

        #[pymodule_export]
        use crate::gif::PyGifStream;
        #[pymodule_export]
        use crate::png::{max_png_file_bytes, png_to_array, png_to_grey};
        #[pymodule_export]
        use crate::read_ahead::PyPngReadAhead;

        #[pymodule_init]
        fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
            register_submodule(m, "formats")
        }
    }

    /// The simulator: worlds, cameras, rendering with truth, robot runs, calibration scenes.
    #[pymodule]
    mod sim {
        use super::*;

        #[pymodule_export]
        use crate::sim::calibration::{
            sim_default_pattern, sim_pattern_points, sim_render_calibration, validate_pattern,
        };
        #[pymodule_export]
        use crate::sim::camera::{validate_camera, validate_imaging, PyCamera};
        #[pymodule_export]
        use crate::sim::render::sim_render;
        #[pymodule_export]
        use crate::sim::robot::{sim_drive, validate_odometry_noise, validate_robot_options};
        #[pymodule_export]
        use crate::sim::run::sim_render_run;
        #[pymodule_export]
        use crate::sim::truth::PyTruth;
        #[pymodule_export]
        use crate::sim::world::{validate_occupancy_options, PyWorld};

        #[pymodule_init]
        fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
            register_submodule(m, "sim")
        }
    }
}
