//! Bindings of the driving stage (`floorscan._native.drive`): the avoidance map, the planner's
//! navigation function and dynamic window, the scan matcher's search, hit map and match
//! information.

pub mod avoidance_map;
pub mod avoidance_map_options;
pub mod costmap_options;
pub mod drive_map_options;
pub mod drive_run_options;
pub mod dwa_options;
pub mod dynamic_window;
pub mod hit_map;
pub mod match_information;
pub mod navigation;
pub mod scan_matcher;
pub mod scan_matcher_options;
pub mod visual_sensor_model;
