//! Bindings of the mapping stage (`floorscan._native.mapping`): grids, the local map, evidence, log
//! odds, the inserter's and SLAM's options.

pub mod evidence;
pub mod grid;
pub mod grid_options;
pub mod grid_views;
pub mod inserter;
pub mod local_map;
pub mod log_odds;
pub mod pose_graph_options;
pub mod slam_options;
