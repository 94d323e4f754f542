//! Bindings of the mapping stage (`floorscan._native.mapping`): grids, the local map, evidence, log
//! odds, the inserter's and SLAM's options, the correlative scan matcher (its search, its match's
//! information matrix, its options).

pub mod correlative_search;
pub mod evidence;
pub mod grid;
pub mod grid_options;
pub mod grid_views;
pub mod inserter;
pub mod local_map;
pub mod log_odds;
pub mod match_information;
pub mod pose_graph_options;
pub mod scan_matcher;
pub mod scan_matcher_options;
pub mod slam_options;
