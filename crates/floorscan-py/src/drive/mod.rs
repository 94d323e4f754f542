//! Bindings of the driving stage (`floorscan._native.drive`): the avoidance map, the planner's
//! navigation function and dynamic window.

pub mod avoidance_map;
pub mod avoidance_map_options;
pub mod costmap_options;
pub mod drive_map_options;
pub mod drive_run_options;
pub mod dwa_options;
pub mod dynamic_window;
pub mod navigation;
pub mod visual_sensor_model;
