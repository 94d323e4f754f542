//! The map builder: log-odds maths, grids and their queries, the mergeable evidence layer, the
//! exact and thin ray walks, updates from visual scans, lasers and sonars, the robot-centred local
//! map, and the correlative scan matcher that corrects poses before scans are inserted.

pub mod branchless;
pub mod correlative_search;
pub mod evidence;
pub mod grid;
pub mod grid_options;
pub mod hit_map;
pub mod inserter;
pub mod laser;
pub mod local_map;
pub mod log_odds;
pub mod match_filter;
pub mod match_information;
pub mod pose_graph_options;
pub mod queries;
pub mod ray_update;
pub mod raycast;
pub mod scan_matcher;
pub mod scan_matcher_options;
pub mod slam_options;
pub mod sonar;
pub mod thin_walk;
