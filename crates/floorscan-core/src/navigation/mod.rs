//! Driving on the maps: the avoidance map's updates (its floor quadrilaterals filled by
//! polygon_fill), the planner's navigation function and the dynamic window.

pub mod avoidance_map;
pub mod avoidance_map_options;
pub mod costmap_options;
pub mod drive_map_options;
pub mod drive_run_options;
pub mod dwa_options;
pub mod dynamic_window;
pub mod navigation_function;
pub mod polygon_fill;
pub mod visual_sensor_model;

pub use navigation_function::{coarse_grid, geodesic_distances, MAX_CELLS};
